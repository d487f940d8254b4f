//! SO(3) in the rotation-matrix representation, and the representation-free
//! parts of SO(3): hat/vee and the left/right Jacobians of the exponential.
//!
//! Conventions: `hat(x) y = x × y`; `exp(φ^)` is the rotation by `|φ|` about
//! `φ/|φ|`; the left Jacobian satisfies `exp(φ + δ) ≈ exp(J_l(φ) δ) exp(φ)`
//! and the right one `exp(φ + δ) ≈ exp(φ) exp(J_r(φ) δ)`, with
//! `J_r(φ) = J_l(−φ)`.

use crate::backend::ops;
use crate::{
    AttitudeErrors, Backend, LieError, M3, Real, Rotation, S, SimdBackend, SimdMask, SimdReal, V3,
    convert, series,
};
use num_traits::{One, Zero};

/// `hat(x)`, the skew matrix with `hat(x) y = x × y`.
#[inline]
pub fn hat<B: SimdBackend>(x: V3<B>) -> M3<B> {
    let [a, b, c] = B::vec3_to_array(x);
    let z = S::<B>::zero();
    B::mat3_from_cols(B::vec3(z, c, -b), B::vec3(-c, z, a), B::vec3(b, -a, z))
}

/// `vee(m)`, the inverse of [`hat`]. It reads the skew-symmetric part
/// `½(m − mᵀ)`, so it is exact for skew input and the least-squares answer
/// otherwise.
#[inline]
pub fn vee<B: SimdBackend>(m: M3<B>) -> V3<B> {
    let e = ops::elems::<B>(m);
    let h = S::<B>::simd_lit(0.5);
    B::vec3(
        h * (e[2][1] - e[1][2]),
        h * (e[0][2] - e[2][0]),
        h * (e[1][0] - e[0][1]),
    )
}

/// `a0 I + a1 φ^ + a2 φ φᵀ`, built element-wise: every SO(3) series
/// (exp, both Jacobians and their inverses) has this shape once `φ^²` is
/// written as `φ φᵀ − θ² I`.
#[inline(always)]
pub(crate) fn rodrigues<B: SimdBackend>(a0: S<B>, a1: S<B>, a2: S<B>, phi: V3<B>) -> M3<B> {
    let [x, y, z] = B::vec3_to_array(phi);
    let (xy, xz, yz) = (a2 * x * y, a2 * x * z, a2 * y * z);
    let (sx, sy, sz) = (a1 * x, a1 * y, a1 * z);
    B::mat3_from_cols(
        B::vec3(a0 + a2 * x * x, xy + sz, xz - sy),
        B::vec3(xy - sz, a0 + a2 * y * y, yz + sx),
        B::vec3(xz + sy, yz - sx, a0 + a2 * z * z),
    )
}

/// The left Jacobian `J_l(φ) = I + B φ^ + C φ^²` (series near zero).
#[inline]
pub fn left_jacobian<B: SimdBackend>(phi: V3<B>) -> M3<B> {
    let theta = ops::norm::<B>(phi);
    let (a, b, _) = series::exp_coeffs(theta);
    rodrigues::<B>(a, b, series::c_coeff(theta), phi)
}

/// The right Jacobian `J_r(φ) = J_l(−φ)`.
#[inline]
pub fn right_jacobian<B: SimdBackend>(phi: V3<B>) -> M3<B> {
    let theta = ops::norm::<B>(phi);
    let (a, b, _) = series::exp_coeffs(theta);
    rodrigues::<B>(a, -b, series::c_coeff(theta), phi)
}

/// `J_l⁻¹(φ) = I − ½ φ^ + D φ^²`; finite for `|φ| < 2π`.
#[inline]
pub fn left_jacobian_inv<B: SimdBackend>(phi: V3<B>) -> M3<B> {
    let theta = ops::norm::<B>(phi);
    let d = series::d_coeff(theta);
    rodrigues::<B>(
        S::<B>::one() - d * theta * theta,
        S::<B>::simd_lit(-0.5),
        d,
        phi,
    )
}

/// `J_r⁻¹(φ) = I + ½ φ^ + D φ^²`; the `dexp⁻¹` of Runge–Kutta–Munthe-Kaas
/// methods in the right-trivialised form `u̇ = J_r⁻¹(u) Ω`.
#[inline]
pub fn right_jacobian_inv<B: SimdBackend>(phi: V3<B>) -> M3<B> {
    let theta = ops::norm::<B>(phi);
    let d = series::d_coeff(theta);
    rodrigues::<B>(
        S::<B>::one() - d * theta * theta,
        S::<B>::simd_lit(0.5),
        d,
        phi,
    )
}

pub use crate::convert::orthogonality_error;

/// A rotation stored as a 3×3 rotation matrix of the backend's own type.
///
/// The matrix is public through [`So3Mat::matrix`] and built without checks
/// by [`So3Mat::from_matrix_unchecked`], so data moves in and out of a
/// user's glam or nalgebra code for free; [`So3Mat::project`] is the checked
/// way in.
#[derive(Copy, Clone, Debug, PartialEq)]
#[repr(transparent)]
pub struct So3Mat<B: SimdBackend>(pub(crate) M3<B>);

impl<B: SimdBackend> So3Mat<B> {
    /// Wraps a matrix the caller knows to be a rotation.
    #[inline]
    pub fn from_matrix_unchecked(m: M3<B>) -> Self {
        Self(m)
    }
}

impl<B: Backend> So3Mat<B> {
    /// The nearest rotation to `m` in the Frobenius norm: the orthogonal
    /// factor of the polar decomposition `m = U P`.
    ///
    /// Computed by Higham's scaled Newton iteration `X ← ½(γX + X⁻ᵀ/γ)`, with
    /// `X⁻ᵀ` from cross products of the columns; it converges quadratically
    /// (two or three iterations for a matrix that drifted from orthogonality
    /// by integration) and needs no SVD, so it is `no_std` and allocation
    /// free. Fails on non-finite input, when `det m ≤ 0`, where the nearest
    /// orthogonal matrix is a reflection, not a rotation, and when the
    /// iteration has not settled after 30 steps.
    pub fn project(m: M3<B>) -> Result<Self, LieError> {
        if !ops::is_finite_mat::<B>(m) {
            return Err(LieError::NonFinite {
                what: "matrix to project onto SO(3)",
            });
        }
        let half = S::<B>::lit(0.5);
        let tol = S::<B>::epsilon() * S::<B>::lit(8.0);
        let mut x = m;
        let mut step = S::<B>::infinity();
        for _ in 0..30 {
            let [c0, c1, c2] = B::mat3_cols(x);
            let cof = B::mat3_from_cols(B::cross(c1, c2), B::cross(c2, c0), B::cross(c0, c1));
            let det = B::dot(c0, B::cross(c1, c2));
            // NaN-safe: a NaN determinant fails here too.
            if det.partial_cmp(&S::<B>::zero()) != Some(core::cmp::Ordering::Greater) {
                return Err(LieError::NotProjectable {
                    det: det.to_f64_lossless(),
                });
            }
            let inv_t = cof * (S::<B>::one() / det);
            let gamma = (ops::frob_norm::<B>(inv_t) / ops::frob_norm::<B>(x)).sqrt();
            let next = (x * gamma + inv_t * (S::<B>::one() / gamma)) * half;
            step = ops::frob_norm::<B>(next - x);
            x = next;
            if step <= tol {
                return Ok(Self(x));
            }
        }
        Err(LieError::NotConverged {
            step: step.to_f64_lossless(),
        })
    }

    /// One Newton–Schulz step `R(3I − RᵀR)/2`: the cheap re-orthonormalisation
    /// for a matrix within ~1e-3 of SO(3) (it squares the error), e.g. every
    /// few hundred steps of a Lie-group integrator in f32.
    #[inline]
    pub fn renormalized(self) -> Self {
        let three = ops::identity::<B>() * S::<B>::lit(3.0);
        Self(self.0 * (three - B::mat3_transpose(self.0) * self.0) * S::<B>::lit(0.5))
    }

    /// The rotation by `angle` about the unit vector `axis`.
    #[inline]
    pub fn from_axis_angle(axis: V3<B>, angle: S<B>) -> Self {
        Self::exp(axis * angle)
    }
}

/// The all-NaN matrix a failed projection gives, so the failure shows at
/// the next finiteness check instead of passing as a rotation.
fn nan_matrix<B: SimdBackend>() -> M3<B> {
    let nan = S::<B>::simd_lit(f64::NAN);
    ops::diag::<B>(nan, nan, nan) * nan
}

impl<B: SimdBackend> So3Mat<B> {
    /// [`So3Mat::project`] in every lane: the polar factor by the same
    /// scaled Newton iteration, each lane stopping where the scalar
    /// iteration stops for that lane's matrix (a lane that has converged
    /// keeps its iterate while the others go on), so each lane's result is
    /// the scalar one to the bit. Returns the rotations and the mask of
    /// lanes that succeeded; a lane that fails for one of `project`'s
    /// reasons (non-finite input, `det ≤ 0`, no convergence in 30 steps)
    /// is all NaN. The scalar `project` keeps its own code because it
    /// reports which reason, with the number.
    pub fn project_lanes(m: M3<B>) -> (Self, <S<B> as SimdReal>::Mask) {
        type Mask<B> = <S<B> as SimdReal>::Mask;
        let elem = |x: f64| <<S<B> as SimdReal>::Element as Real>::lit(x);
        let half = S::<B>::simd_lit(0.5);
        let tol = S::<B>::simd_splat(<<S<B> as SimdReal>::Element as Real>::epsilon() * elem(8.0));
        let mut failed: Mask<B> = !ops::finite_mat::<B>(m);
        let mut done = Mask::<B>::splat(false);
        let mut x = m;
        for _ in 0..30 {
            let [c0, c1, c2] = B::mat3_cols(x);
            let cof = B::mat3_from_cols(B::cross(c1, c2), B::cross(c2, c0), B::cross(c0, c1));
            let det = B::dot(c0, B::cross(c1, c2));
            // NaN-safe, as in `project`: a NaN determinant fails too.
            let running = !(done | failed);
            failed = failed | (running & !det.simd_gt(S::<B>::zero()));
            let running = !(done | failed);
            if !running.any() {
                break;
            }
            let inv_t = cof * (S::<B>::one() / det);
            let gamma = (ops::frob_norm::<B>(inv_t) / ops::frob_norm::<B>(x)).simd_sqrt();
            let next = (x * gamma + inv_t * (S::<B>::one() / gamma)) * half;
            let step = ops::frob_norm::<B>(next - x);
            x = ops::select_mat::<B>(running, next, x);
            done = done | (running & step.simd_le(tol));
        }
        (Self(ops::select_mat::<B>(done, x, nan_matrix::<B>())), done)
    }
}

/// The group operations (also [`LieGroup`](crate::LieGroup)'s, which calls these): inherent,
/// so that a concrete rotation needs no trait in scope and never meets two
/// traits' methods of the same name. On lane backends too (`simd`).
impl<B: SimdBackend> So3Mat<B> {
    /// The identity rotation.
    #[inline]
    pub fn identity() -> Self {
        Self(ops::identity::<B>())
    }
    /// The rotation matrix: [`Rotation::matrix`] under a name of its own,
    /// for lane backends, which have no [`Rotation`].
    #[inline]
    pub fn as_matrix(self) -> M3<B> {
        self.0
    }
    /// `self ∘ rhs` (apply `rhs` first).
    #[inline]
    pub fn compose(self, rhs: Self) -> Self {
        Self(B::mat3_mul(self.0, rhs.0))
    }
    /// The inverse rotation.
    #[inline]
    pub fn inverse(self) -> Self {
        Self(B::mat3_transpose(self.0))
    }
    /// `R v`.
    #[inline]
    pub fn act(self, v: V3<B>) -> V3<B> {
        B::mat3_mul_vec(self.0, v)
    }
    /// `exp(φ^) = cos θ I + (sin θ/θ) φ^ + ((1 − cos θ)/θ²) φ φᵀ` (Rodrigues).
    #[inline]
    pub fn exp(phi: V3<B>) -> Self {
        let (a, b, c) = series::exp_coeffs(ops::norm::<B>(phi));
        Self(rodrigues::<B>(c, a, b, phi))
    }
    /// From the skew part up to 2π/3, else through Shepperd's quaternion of
    /// the largest pivot ([`log_matrix`](crate::log_matrix)): accurate to
    /// rounding at every angle, including exactly π, where
    /// `acos((tr R − 1)/2)` alone loses half its digits and the skew part
    /// has none left for the axis.
    #[inline]
    pub fn log(self) -> V3<B> {
        convert::log_matrix::<B>(self.0)
    }
}

/// [`AttitudeErrors`]' operations, also inherent so that a concrete
/// rotation needs no trait in scope for them.
impl<B: SimdBackend> So3Mat<B> {
    /// `Rᵀ v`, without forming the inverse.
    #[inline]
    pub fn inverse_act(self, v: V3<B>) -> V3<B> {
        B::mat3_tr_mul_vec(self.0, v)
    }
    /// `(e_R, Ψ)` against the identity ([`AttitudeErrors::errors_to_identity`]).
    #[inline]
    pub fn errors_to_identity(self) -> (V3<B>, S<B>) {
        // Ψ against I as in `Rotation::psi`: ¼ ‖R − I‖², never negative.
        let d = self.0 - ops::identity::<B>();
        (
            vee::<B>(self.0),
            S::<B>::simd_lit(0.25) * ops::frob_dot::<B>(d, d),
        )
    }
}

impl<B: SimdBackend> AttitudeErrors<B> for So3Mat<B> {
    #[inline]
    fn error_rotation(self, rd: Self) -> Self {
        rd.inverse().compose(self)
    }
    #[inline]
    fn inverse_act(self, v: V3<B>) -> V3<B> {
        So3Mat::inverse_act(self, v)
    }
    #[inline]
    fn errors_to_identity(self) -> (V3<B>, S<B>) {
        So3Mat::errors_to_identity(self)
    }
    #[inline]
    fn from_frame(b1: V3<B>, b2: V3<B>, b3: V3<B>) -> Self {
        Self(B::mat3_from_cols(b1, b2, b3))
    }
    #[inline]
    fn body_axes(self) -> [V3<B>; 3] {
        B::mat3_cols(self.0)
    }
}

impl<B: Backend> Rotation<B> for So3Mat<B> {
    const REPR: &'static str = "matrix";

    #[inline]
    fn matrix(self) -> M3<B> {
        self.0
    }
    #[inline]
    fn from_matrix(m: M3<B>) -> Self {
        Self(m)
    }
    #[inline]
    fn quaternion(self) -> B::Quat {
        let [w, x, y, z] = convert::shepperd::<B>(self.0);
        let n = S::<B>::one() / (w * w + x * x + y * y + z * z).sqrt();
        B::quat_from_wxyz(w * n, x * n, y * n, z * n)
    }
    #[inline]
    fn from_quaternion(q: B::Quat) -> Self {
        Self(convert::to_matrix::<B>(q))
    }
    /// `½ tr(I − Rdᵀ R)` as `¼ ‖R − Rd‖²_F` (equal for rotations, since
    /// `‖R − Rd‖² = 6 − 2 tr(RdᵀR)`): a sum of squares, so never negative
    /// and accurate to rounding relative to Ψ itself near 0, where
    /// `½(3 − tr)` cancels to a few ε of absolute error of either sign.
    /// Off SO(3) the two forms differ by the drift, which
    /// [`Rotation::orthogonality_error`] reports.
    #[inline]
    fn psi(self, rd: Self) -> S<B> {
        let d = self.0 - rd.0;
        S::<B>::lit(0.25) * ops::frob_dot::<B>(d, d)
    }
    #[inline]
    fn e_r(self, rd: Self) -> V3<B> {
        vee::<B>(B::mat3_mul(B::mat3_transpose(rd.0), self.0))
    }
    #[inline]
    fn orthogonality_error(self) -> S<B> {
        orthogonality_error::<B>(self.0)
    }
    #[inline]
    fn body_axis(self, k: usize) -> V3<B> {
        B::mat3_cols(self.0)[k]
    }
    /// The polar projection ([`So3Mat::project`]); where it fails
    /// (non-finite entries, `det ≤ 0`, no convergence) the result is all
    /// NaN, so the failure shows at the next finiteness check instead of
    /// passing as a rotation. Call `project` to handle the error.
    #[inline]
    fn normalized(self) -> Self {
        Self::project(self.0).unwrap_or_else(|_| Self(nan_matrix::<B>()))
    }
}

impl<B: SimdBackend> core::ops::Mul for So3Mat<B> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        self.compose(rhs)
    }
}
