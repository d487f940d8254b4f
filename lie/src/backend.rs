//! The backend abstraction: the handful of primitive vector, matrix and
//! quaternion operations that every Lie formula in this crate is built from.
//!
//! A backend is a zero-sized marker type ([`NalgebraF32`](crate::NalgebraF32),
//! [`GlamF64`](crate::GlamF64), …) naming a (linear-algebra library, scalar)
//! pair. Its associated types *are* that library's own types — `glam::DVec3`,
//! `nalgebra::Matrix3<f32>` — so values cross the API boundary without any
//! conversion, and each primitive is a one-line call to the library. The
//! arithmetic operators come straight from the library through the bounds on
//! the associated types; only what has no common operator (dot, cross,
//! columns, quaternion product and rotation) is a trait function.

use crate::{Real, SimdReal};
use core::fmt::Debug;
use core::ops::{Add, Mul, Neg, Sub};

/// A (linear-algebra library, scalar) pair. See the module docs.
///
/// A formula written once over `B` compiles to each library's own types:
///
/// ```
/// use lie::{Backend, GlamF32, NalgebraF64, Real, S, V3};
///
/// /// The component of `v` normal to the unit vector `n`.
/// fn normal_part<B: Backend>(v: V3<B>, n: V3<B>) -> V3<B> {
///     v - n * B::dot(v, n)
/// }
/// let g: glam::Vec3 = normal_part::<GlamF32>(glam::Vec3::new(1.0, 2.0, 3.0), glam::Vec3::Z);
/// assert_eq!(g, glam::Vec3::new(1.0, 2.0, 0.0));
/// let n = normal_part::<NalgebraF64>(NalgebraF64::vec3(1.0, 2.0, 3.0), NalgebraF64::vec3(1.0, 0.0, 0.0));
/// assert_eq!(NalgebraF64::vec3_to_array(n), [0.0, 2.0, 3.0]);
/// let _: S<GlamF32> = Real::lit(1.5); // the scalar is f32 here
/// ```
pub trait Backend: SimdBackend<Scalar: Real> {}

/// Every [`SimdBackend`] whose scalar is one real number is a [`Backend`]:
/// the single-lane case is a bound, not a second trait.
impl<B: SimdBackend> Backend for B where B::Scalar: Real {}

/// Inherent forwarders of a backend type's primitives, so that
/// `GlamF32::vec3(…)` reads with only `Backend` imported (the primitives
/// are [`SimdBackend`]'s; generic code reaches them through the bound).
macro_rules! inherent_primitives {
    ($name:ident) => {
        inherent_primitives!([] $name);
    };
    ([$($gen:tt)*] $name:ty) => {
        impl<$($gen)*> $name {
            /// Short name, as [`SimdBackend::NAME`](crate::SimdBackend::NAME).
            pub const NAME: &'static str = <$name as $crate::SimdBackend>::NAME;
            /// [`SimdBackend::vec3`](crate::SimdBackend::vec3).
            #[inline(always)]
            pub fn vec3(
                x: $crate::S<$name>,
                y: $crate::S<$name>,
                z: $crate::S<$name>,
            ) -> $crate::V3<$name> {
                <$name as $crate::SimdBackend>::vec3(x, y, z)
            }
            /// [`SimdBackend::vec3_to_array`](crate::SimdBackend::vec3_to_array).
            #[inline(always)]
            pub fn vec3_to_array(v: $crate::V3<$name>) -> [$crate::S<$name>; 3] {
                <$name as $crate::SimdBackend>::vec3_to_array(v)
            }
            /// [`SimdBackend::dot`](crate::SimdBackend::dot).
            #[inline(always)]
            pub fn dot(a: $crate::V3<$name>, b: $crate::V3<$name>) -> $crate::S<$name> {
                <$name as $crate::SimdBackend>::dot(a, b)
            }
            /// [`SimdBackend::cross`](crate::SimdBackend::cross).
            #[inline(always)]
            pub fn cross(a: $crate::V3<$name>, b: $crate::V3<$name>) -> $crate::V3<$name> {
                <$name as $crate::SimdBackend>::cross(a, b)
            }
            /// [`SimdBackend::mat3_from_cols`](crate::SimdBackend::mat3_from_cols).
            #[inline(always)]
            pub fn mat3_from_cols(
                c0: $crate::V3<$name>,
                c1: $crate::V3<$name>,
                c2: $crate::V3<$name>,
            ) -> $crate::M3<$name> {
                <$name as $crate::SimdBackend>::mat3_from_cols(c0, c1, c2)
            }
            /// [`SimdBackend::mat3_cols`](crate::SimdBackend::mat3_cols).
            #[inline(always)]
            pub fn mat3_cols(m: $crate::M3<$name>) -> [$crate::V3<$name>; 3] {
                <$name as $crate::SimdBackend>::mat3_cols(m)
            }
            /// [`SimdBackend::mat3_transpose`](crate::SimdBackend::mat3_transpose).
            #[inline(always)]
            pub fn mat3_transpose(m: $crate::M3<$name>) -> $crate::M3<$name> {
                <$name as $crate::SimdBackend>::mat3_transpose(m)
            }
            /// [`SimdBackend::mat3_tr_mul_vec`](crate::SimdBackend::mat3_tr_mul_vec).
            #[inline(always)]
            pub fn mat3_tr_mul_vec(
                m: $crate::M3<$name>,
                v: $crate::V3<$name>,
            ) -> $crate::V3<$name> {
                <$name as $crate::SimdBackend>::mat3_tr_mul_vec(m, v)
            }
            /// [`SimdBackend::mat3_mul_vec`](crate::SimdBackend::mat3_mul_vec).
            #[inline(always)]
            pub fn mat3_mul_vec(m: $crate::M3<$name>, v: $crate::V3<$name>) -> $crate::V3<$name> {
                <$name as $crate::SimdBackend>::mat3_mul_vec(m, v)
            }
            /// [`SimdBackend::mat3_mul`](crate::SimdBackend::mat3_mul).
            #[inline(always)]
            pub fn mat3_mul(a: $crate::M3<$name>, b: $crate::M3<$name>) -> $crate::M3<$name> {
                <$name as $crate::SimdBackend>::mat3_mul(a, b)
            }
            /// [`SimdBackend::quat_from_wxyz`](crate::SimdBackend::quat_from_wxyz).
            #[inline(always)]
            pub fn quat_from_wxyz(
                w: $crate::S<$name>,
                x: $crate::S<$name>,
                y: $crate::S<$name>,
                z: $crate::S<$name>,
            ) -> <$name as $crate::SimdBackend>::Quat {
                <$name as $crate::SimdBackend>::quat_from_wxyz(w, x, y, z)
            }
            /// [`SimdBackend::quat_to_wxyz`](crate::SimdBackend::quat_to_wxyz).
            #[inline(always)]
            pub fn quat_to_wxyz(q: <$name as $crate::SimdBackend>::Quat) -> [$crate::S<$name>; 4] {
                <$name as $crate::SimdBackend>::quat_to_wxyz(q)
            }
            /// [`SimdBackend::quat_mul`](crate::SimdBackend::quat_mul).
            #[inline(always)]
            pub fn quat_mul(
                a: <$name as $crate::SimdBackend>::Quat,
                b: <$name as $crate::SimdBackend>::Quat,
            ) -> <$name as $crate::SimdBackend>::Quat {
                <$name as $crate::SimdBackend>::quat_mul(a, b)
            }
            /// [`SimdBackend::quat_conj`](crate::SimdBackend::quat_conj).
            #[inline(always)]
            pub fn quat_conj(
                q: <$name as $crate::SimdBackend>::Quat,
            ) -> <$name as $crate::SimdBackend>::Quat {
                <$name as $crate::SimdBackend>::quat_conj(q)
            }
            /// [`SimdBackend::quat_rotate`](crate::SimdBackend::quat_rotate).
            #[inline(always)]
            pub fn quat_rotate(
                q: <$name as $crate::SimdBackend>::Quat,
                v: $crate::V3<$name>,
            ) -> $crate::V3<$name> {
                <$name as $crate::SimdBackend>::quat_rotate(q, v)
            }
        }
    };
}
pub(crate) use inherent_primitives;

/// A (linear-algebra library, scalar) pair whose scalar may be SIMD lanes
/// ([`SimdReal`]): the primitives of [`Backend`] without its requirement
/// that the scalar be one real number. The formulas that never stop on an
/// error (exp, log, the Jacobians, compose, act) are written over this
/// trait, their branches as lane-wise selects, so one formula serves the
/// scalar backends and the lane backends (`NalgebraF64x4`,
/// `NalgebraF32x8`, feature `simd`) alike. [`Backend`] is this trait with
/// the scalar one real number (a bound, not a second trait): code for
/// `f32`/`f64` only writes `B: Backend`.
pub trait SimdBackend: Copy + Clone + Default + Debug + PartialEq + Send + Sync + 'static {
    /// The scalar: `f32`, `f64`, or lanes of them.
    type Scalar: SimdReal;
    /// The library's 3-vector.
    type Vec3: Copy
        + Debug
        + PartialEq
        + Send
        + Sync
        + Add<Output = Self::Vec3>
        + Sub<Output = Self::Vec3>
        + Neg<Output = Self::Vec3>
        + Mul<Self::Scalar, Output = Self::Vec3>;
    /// The library's 3×3 matrix.
    type Mat3: Copy
        + Debug
        + PartialEq
        + Send
        + Sync
        + Add<Output = Self::Mat3>
        + Sub<Output = Self::Mat3>
        + Mul<Self::Mat3, Output = Self::Mat3>
        + Mul<Self::Vec3, Output = Self::Vec3>
        + Mul<Self::Scalar, Output = Self::Mat3>;
    /// The library's quaternion (assumed unit wherever it is used here).
    type Quat: Copy + Debug + PartialEq + Send + Sync;

    /// Short name used in reports and test names, e.g. `"glam-f32"`.
    const NAME: &'static str;

    /// Builds a vector from components.
    fn vec3(x: Self::Scalar, y: Self::Scalar, z: Self::Scalar) -> Self::Vec3;
    /// Components of a vector.
    fn vec3_to_array(v: Self::Vec3) -> [Self::Scalar; 3];
    /// Dot product.
    fn dot(a: Self::Vec3, b: Self::Vec3) -> Self::Scalar;
    /// Cross product.
    fn cross(a: Self::Vec3, b: Self::Vec3) -> Self::Vec3;
    /// Builds a matrix from its three columns.
    fn mat3_from_cols(c0: Self::Vec3, c1: Self::Vec3, c2: Self::Vec3) -> Self::Mat3;
    /// The three columns of a matrix.
    fn mat3_cols(m: Self::Mat3) -> [Self::Vec3; 3];
    /// Transpose.
    fn mat3_transpose(m: Self::Mat3) -> Self::Mat3;
    /// The transpose times a vector, `mᵀ v`, without forming `mᵀ`.
    fn mat3_tr_mul_vec(m: Self::Mat3, v: Self::Vec3) -> Self::Vec3;
    /// The product `m v`: the matrix type's own `*`, except on the dual
    /// backend, which writes the three column combinations out in
    /// nalgebra's own order (the same result bit for bit): nalgebra's
    /// operator goes through its generic BLAS loop, which the optimiser
    /// inlines for `f32`/`f64` but leaves out of line for a scalar as wide
    /// as the dual number, with three products per term instead of one (its
    /// `α = 1` and `β` factors). Hot paths call this rather than `*`.
    #[inline(always)]
    fn mat3_mul_vec(m: Self::Mat3, v: Self::Vec3) -> Self::Vec3 {
        m * v
    }
    /// The product `a b` ([`SimdBackend::mat3_mul_vec`] column by column on
    /// the dual backend, for the same reason).
    #[inline(always)]
    fn mat3_mul(a: Self::Mat3, b: Self::Mat3) -> Self::Mat3 {
        a * b
    }
    /// Builds a quaternion `w + x i + y j + z k`.
    fn quat_from_wxyz(
        w: Self::Scalar,
        x: Self::Scalar,
        y: Self::Scalar,
        z: Self::Scalar,
    ) -> Self::Quat;
    /// Components `[w, x, y, z]`.
    fn quat_to_wxyz(q: Self::Quat) -> [Self::Scalar; 4];
    /// Hamilton product `a ⊗ b`.
    fn quat_mul(a: Self::Quat, b: Self::Quat) -> Self::Quat;
    /// Conjugate (the inverse of a unit quaternion).
    fn quat_conj(q: Self::Quat) -> Self::Quat;
    /// Rotates a vector by a unit quaternion, `q v q*`.
    fn quat_rotate(q: Self::Quat, v: Self::Vec3) -> Self::Vec3;
}

/// Scalar alias for a backend.
pub type S<B> = <B as SimdBackend>::Scalar;
/// Vector alias for a backend.
pub type V3<B> = <B as SimdBackend>::Vec3;
/// Matrix alias for a backend.
pub type M3<B> = <B as SimdBackend>::Mat3;

/// Derived helpers written once on top of the [`Backend`] primitives, public
/// so that downstream crates (dynamics, integrators) share one definition
/// instead of re-deriving zero vectors, norms and 3×3 inverses per crate.
pub mod ops {
    use super::*;
    use num_traits::{One, Zero};

    /// The zero vector.
    #[inline(always)]
    pub fn zero<B: SimdBackend>() -> V3<B> {
        let z = S::<B>::zero();
        B::vec3(z, z, z)
    }
    /// Element-wise product `(a₁b₁, a₂b₂, a₃b₃)`: a diagonal matrix (per-axis
    /// gains, a principal-axes inertia) times a vector in three products.
    #[inline(always)]
    pub fn cmul<B: SimdBackend>(a: V3<B>, b: V3<B>) -> V3<B> {
        let (a, b) = (B::vec3_to_array(a), B::vec3_to_array(b));
        B::vec3(a[0] * b[0], a[1] * b[1], a[2] * b[2])
    }
    /// Euclidean norm.
    #[inline(always)]
    pub fn norm<B: SimdBackend>(v: V3<B>) -> S<B> {
        B::dot(v, v).simd_sqrt()
    }
    /// The 3×3 identity.
    #[inline(always)]
    pub fn identity<B: SimdBackend>() -> M3<B> {
        diag::<B>(S::<B>::one(), S::<B>::one(), S::<B>::one())
    }
    /// Diagonal matrix `diag(a, b, c)`.
    #[inline(always)]
    pub fn diag<B: SimdBackend>(a: S<B>, b: S<B>, c: S<B>) -> M3<B> {
        let z = S::<B>::zero();
        B::mat3_from_cols(B::vec3(a, z, z), B::vec3(z, b, z), B::vec3(z, z, c))
    }
    /// The diagonal of `m` when every off-diagonal element is zero (in
    /// every lane, for a lane backend): then
    /// `m v` is the element-wise product of the diagonal and `v`, with the
    /// same values for finite `v` (the terms it skips are exact zeros).
    #[inline(always)]
    pub fn diagonal<B: SimdBackend>(m: M3<B>) -> Option<V3<B>> {
        let e = elems::<B>(m);
        let off = [e[0][1], e[0][2], e[1][0], e[1][2], e[2][0], e[2][1]];
        S::<B>::simd_all_zero(off).then(|| B::vec3(e[0][0], e[1][1], e[2][2]))
    }
    /// Elements, indexed `[row][col]`.
    #[inline(always)]
    pub fn elems<B: SimdBackend>(m: M3<B>) -> [[S<B>; 3]; 3] {
        let [c0, c1, c2] = B::mat3_cols(m);
        let (a, b, c) = (
            B::vec3_to_array(c0),
            B::vec3_to_array(c1),
            B::vec3_to_array(c2),
        );
        [[a[0], b[0], c[0]], [a[1], b[1], c[1]], [a[2], b[2], c[2]]]
    }
    /// Builds from elements indexed `[row][col]`.
    #[inline(always)]
    pub fn from_elems<B: SimdBackend>(e: [[S<B>; 3]; 3]) -> M3<B> {
        B::mat3_from_cols(
            B::vec3(e[0][0], e[1][0], e[2][0]),
            B::vec3(e[0][1], e[1][1], e[2][1]),
            B::vec3(e[0][2], e[1][2], e[2][2]),
        )
    }
    /// Frobenius inner product `tr(aᵀ b)`.
    #[inline(always)]
    pub fn frob_dot<B: SimdBackend>(a: M3<B>, b: M3<B>) -> S<B> {
        let [a0, a1, a2] = B::mat3_cols(a);
        let [b0, b1, b2] = B::mat3_cols(b);
        B::dot(a0, b0) + B::dot(a1, b1) + B::dot(a2, b2)
    }
    /// Frobenius norm.
    #[inline(always)]
    pub fn frob_norm<B: SimdBackend>(a: M3<B>) -> S<B> {
        frob_dot::<B>(a, a).simd_sqrt()
    }
    /// `a` in the lanes where `mask` is set, `b` elsewhere (for one lane:
    /// `if mask { a } else { b }`).
    #[inline(always)]
    pub fn select_vec<B: SimdBackend>(mask: <S<B> as SimdReal>::Mask, a: V3<B>, b: V3<B>) -> V3<B> {
        let (a, b) = (B::vec3_to_array(a), B::vec3_to_array(b));
        let s = |k: usize| S::<B>::simd_select(mask, a[k], b[k]);
        B::vec3(s(0), s(1), s(2))
    }
    /// [`select_vec`] for matrices.
    #[inline(always)]
    pub fn select_mat<B: SimdBackend>(mask: <S<B> as SimdReal>::Mask, a: M3<B>, b: M3<B>) -> M3<B> {
        let (a, b) = (B::mat3_cols(a), B::mat3_cols(b));
        let s = |k: usize| select_vec::<B>(mask, a[k], b[k]);
        B::mat3_from_cols(s(0), s(1), s(2))
    }
    /// `v`'s values with `w`'s derivatives
    /// ([`SimdReal::with_derivatives_of`] per component; `v` itself unless
    /// the scalar carries derivatives).
    #[inline(always)]
    pub fn with_derivatives_of<B: SimdBackend>(v: V3<B>, w: V3<B>) -> V3<B> {
        let (a, b) = (B::vec3_to_array(v), B::vec3_to_array(w));
        let d = |k: usize| a[k].with_derivatives_of(b[k]);
        B::vec3(d(0), d(1), d(2))
    }
    /// Lane-wise: every component of `v` finite.
    #[inline(always)]
    pub fn finite_vec<B: SimdBackend>(v: V3<B>) -> <S<B> as SimdReal>::Mask {
        let a = B::vec3_to_array(v);
        a[0].simd_is_finite() & a[1].simd_is_finite() & a[2].simd_is_finite()
    }
    /// The lanes of `m` with no entry NaN or ±∞ ([`is_finite_mat`] on
    /// lanes).
    #[inline(always)]
    pub fn finite_mat<B: SimdBackend>(m: M3<B>) -> <S<B> as SimdReal>::Mask {
        let [c0, c1, c2] = B::mat3_cols(m);
        finite_vec::<B>(c0) & finite_vec::<B>(c1) & finite_vec::<B>(c2)
    }
    /// True when no component is NaN or ±∞.
    #[inline(always)]
    pub fn is_finite_vec<B: Backend>(v: V3<B>) -> bool {
        let a = B::vec3_to_array(v);
        // `&`, not `&&`: three compares combined without branches (the
        // checks run on every load evaluation of a simulation).
        a[0].is_finite() & a[1].is_finite() & a[2].is_finite()
    }
    /// True when no element is NaN or ±∞.
    #[inline(always)]
    pub fn is_finite_mat<B: Backend>(m: M3<B>) -> bool {
        let [c0, c1, c2] = B::mat3_cols(m);
        is_finite_vec::<B>(c0) & is_finite_vec::<B>(c1) & is_finite_vec::<B>(c2)
    }
    /// Determinant.
    #[inline(always)]
    pub fn det<B: SimdBackend>(m: M3<B>) -> S<B> {
        let [c0, c1, c2] = B::mat3_cols(m);
        B::dot(c0, B::cross(c1, c2))
    }
    /// [`inverse`] in every lane, with the mask of lanes where it exists
    /// (determinant non-zero and finite); the other lanes hold whatever the
    /// division by their determinant gave.
    #[inline(always)]
    pub fn inverse_lanes<B: SimdBackend>(m: M3<B>) -> (M3<B>, <S<B> as SimdReal>::Mask) {
        let [c0, c1, c2] = B::mat3_cols(m);
        let d = B::dot(c0, B::cross(c1, c2));
        let ok = !d.simd_eq(S::<B>::zero()) & d.simd_is_finite();
        let cof = B::mat3_from_cols(B::cross(c1, c2), B::cross(c2, c0), B::cross(c0, c1));
        (B::mat3_transpose(cof) * (S::<B>::one() / d), ok)
    }
    /// Inverse by cofactors, `None` when the determinant is zero or not
    /// finite. Cofactors (cross products of columns) keep it branch-free and
    /// exact enough for the well-conditioned 3×3 systems met here (inertia
    /// matrices, Newton Jacobians); it is not a substitute for a pivoted
    /// solve on ill-conditioned matrices.
    #[inline(always)]
    pub fn inverse<B: Backend>(m: M3<B>) -> Option<M3<B>> {
        let [c0, c1, c2] = B::mat3_cols(m);
        let d = B::dot(c0, B::cross(c1, c2));
        if d == S::<B>::zero() || !d.is_finite() {
            return None;
        }
        // Rows of the inverse are the cross products of the columns over det.
        let cof = B::mat3_from_cols(B::cross(c1, c2), B::cross(c2, c0), B::cross(c0, c1));
        Some(B::mat3_transpose(cof) * (S::<B>::one() / d))
    }
    /// A vector's components as f64 (exact for f32 and f64; a dual
    /// number's value part), for output and comparison.
    #[inline]
    pub fn vec3_f64<B: Backend>(v: V3<B>) -> [f64; 3] {
        B::vec3_to_array(v).map(|c| c.to_f64_lossless())
    }
    /// A matrix's elements as f64, indexed `[row][col]` (as [`vec3_f64`]).
    #[inline]
    pub fn mat3_f64<B: Backend>(m: M3<B>) -> [[f64; 3]; 3] {
        elems::<B>(m).map(|r| r.map(|c| c.to_f64_lossless()))
    }
}
