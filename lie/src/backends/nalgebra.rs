//! The nalgebra backend: `Vector3<T>`, `Matrix3<T>` and `UnitQuaternion<T>`.

use crate::SimdBackend;
use crate::backend::inherent_primitives;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// The primitives whose nalgebra calls need no more of the scalar than
/// arithmetic (the quaternion product and rotation need nalgebra's
/// `SimdRealField`, which the dual scalar does not implement).
macro_rules! nalgebra_primitives {
    ($s:ty) => {
        #[inline(always)]
        fn vec3(x: $s, y: $s, z: $s) -> Vector3<$s> {
            Vector3::new(x, y, z)
        }
        #[inline(always)]
        fn vec3_to_array(v: Vector3<$s>) -> [$s; 3] {
            [v.x, v.y, v.z]
        }
        #[inline(always)]
        fn dot(a: Vector3<$s>, b: Vector3<$s>) -> $s {
            a.dot(&b)
        }
        #[inline(always)]
        fn cross(a: Vector3<$s>, b: Vector3<$s>) -> Vector3<$s> {
            a.cross(&b)
        }
        #[inline(always)]
        fn mat3_from_cols(c0: Vector3<$s>, c1: Vector3<$s>, c2: Vector3<$s>) -> Matrix3<$s> {
            Matrix3::from_columns(&[c0, c1, c2])
        }
        #[inline(always)]
        fn mat3_cols(m: Matrix3<$s>) -> [Vector3<$s>; 3] {
            [
                m.fixed_view::<3, 1>(0, 0).into_owned(),
                m.fixed_view::<3, 1>(0, 1).into_owned(),
                m.fixed_view::<3, 1>(0, 2).into_owned(),
            ]
        }
        #[inline(always)]
        fn mat3_transpose(m: Matrix3<$s>) -> Matrix3<$s> {
            m.transpose()
        }
        #[inline(always)]
        fn quat_from_wxyz(w: $s, x: $s, y: $s, z: $s) -> UnitQuaternion<$s> {
            UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z))
        }
    };
}

/// The matrix products written out for the dual scalar, in nalgebra's own
/// order (so the real parts are its operators' results bit for bit):
/// nalgebra's operators go through its generic BLAS loops, which the
/// optimiser inlines for `f32`/`f64` but leaves out of line for a scalar as
/// wide as a dual number, with three products per term instead of one (the
/// `α = 1` and `β` factors of `gemv`), which a gradient pays on every
/// product.
#[cfg(feature = "dual")]
macro_rules! explicit_products {
    ($s:ty) => {
        /// `(c₀·v, c₁·v, c₂·v)` with each dot product summed as nalgebra's
        /// `dot` sums three terms, `(a₀b₀ + a₁b₁) + a₂b₂`.
        #[inline(always)]
        fn mat3_tr_mul_vec(m: Matrix3<$s>, v: Vector3<$s>) -> Vector3<$s> {
            let d = |j: usize| m[(0, j)] * v.x + m[(1, j)] * v.y + m[(2, j)] * v.z;
            Vector3::new(d(0), d(1), d(2))
        }
        /// `c₀v₀ + c₁v₁ + c₂v₂`, row by row, in the order of nalgebra's
        /// `gemv` (one column after the other; the sum of two terms does
        /// not depend on their order).
        #[inline(always)]
        fn mat3_mul_vec(m: Matrix3<$s>, v: Vector3<$s>) -> Vector3<$s> {
            let r = |i: usize| m[(i, 0)] * v.x + m[(i, 1)] * v.y + m[(i, 2)] * v.z;
            Vector3::new(r(0), r(1), r(2))
        }
        /// [`SimdBackend::mat3_mul_vec`] on each column of `b`, as
        /// nalgebra's `gemm` does for a fixed-size product.
        #[inline(always)]
        fn mat3_mul(a: Matrix3<$s>, b: Matrix3<$s>) -> Matrix3<$s> {
            let col = |j: usize| {
                let r = |i: usize| {
                    a[(i, 0)] * b[(0, j)] + a[(i, 1)] * b[(1, j)] + a[(i, 2)] * b[(2, j)]
                };
                Vector3::new(r(0), r(1), r(2))
            };
            Matrix3::from_columns(&[col(0), col(1), col(2)])
        }
    };
}

macro_rules! nalgebra_backend {
    ($(#[$doc:meta])* $name:ident, $trait:ident, $s:ty, $label:literal) => {
        $(#[$doc])*
        #[derive(Copy, Clone, Default, Debug, PartialEq, Eq, Hash)]
        pub struct $name;

        inherent_primitives!($name);

        impl $trait for $name {
            type Scalar = $s;
            type Vec3 = Vector3<$s>;
            type Mat3 = Matrix3<$s>;
            type Quat = UnitQuaternion<$s>;
            const NAME: &'static str = $label;

            nalgebra_primitives!($s);
            #[inline(always)]
            fn mat3_tr_mul_vec(m: Matrix3<$s>, v: Vector3<$s>) -> Vector3<$s> {
                m.tr_mul(&v)
            }
            #[inline(always)]
            fn quat_to_wxyz(q: UnitQuaternion<$s>) -> [$s; 4] {
                [q.w, q.i, q.j, q.k]
            }
            #[inline(always)]
            fn quat_mul(a: UnitQuaternion<$s>, b: UnitQuaternion<$s>) -> UnitQuaternion<$s> {
                a * b
            }
            #[inline(always)]
            fn quat_conj(q: UnitQuaternion<$s>) -> UnitQuaternion<$s> {
                q.conjugate()
            }
            #[inline(always)]
            fn quat_rotate(q: UnitQuaternion<$s>, v: Vector3<$s>) -> Vector3<$s> {
                q * v
            }
        }
    };
}

nalgebra_backend!(
    /// nalgebra with `f32`: `Vector3<f32>`, `Matrix3<f32>`, `UnitQuaternion<f32>`.
    NalgebraF32, SimdBackend, f32, "nalgebra-f32"
);
nalgebra_backend!(
    /// nalgebra with `f64`: `Vector3<f64>`, `Matrix3<f64>`, `UnitQuaternion<f64>`.
    NalgebraF64, SimdBackend, f64, "nalgebra-f64"
);
#[cfg(feature = "simd")]
nalgebra_backend!(
    /// nalgebra on four `f64` lanes (feature `simd`): a `Vector3<WideF64x4>`
    /// is four 3-vectors, one per lane.
    NalgebraF64x4, SimdBackend, simba::simd::WideF64x4, "nalgebra-f64x4"
);
#[cfg(feature = "simd")]
nalgebra_backend!(
    /// nalgebra on eight `f32` lanes (feature `simd`): a `Vector3<WideF32x8>`
    /// is eight 3-vectors, one per lane.
    NalgebraF32x8, SimdBackend, simba::simd::WideF32x8, "nalgebra-f32x8"
);

#[cfg(feature = "dual")]
pub use dual::NalgebraDual;

#[cfg(feature = "dual")]
mod dual {
    use crate::{Dual, SimdBackend};
    use nalgebra::{Matrix3, Quaternion, Unit, UnitQuaternion, Vector3};

    /// nalgebra with the forward-mode dual scalar [`Dual<N>`] (feature
    /// `dual`): `Vector3<Dual<N>>`, `Matrix3<Dual<N>>`,
    /// `UnitQuaternion<Dual<N>>`. Every formula of the workspace written over
    /// a backend runs on it and carries `N` derivatives along; the real parts
    /// equal [`NalgebraF64`](crate::NalgebraF64)'s results bit for bit (the
    /// quaternion product and rotation below are nalgebra's own formulas,
    /// term for term, written out because nalgebra's operators ask for
    /// `SimdRealField`).
    #[derive(Copy, Clone, Default, Debug, PartialEq, Eq, Hash)]
    pub struct NalgebraDual<const N: usize>;

    crate::backend::inherent_primitives!([const N: usize] NalgebraDual<N>);

    impl<const N: usize> SimdBackend for NalgebraDual<N> {
        type Scalar = Dual<N>;
        type Vec3 = Vector3<Dual<N>>;
        type Mat3 = Matrix3<Dual<N>>;
        type Quat = UnitQuaternion<Dual<N>>;
        const NAME: &'static str = "nalgebra-dual";

        nalgebra_primitives!(Dual<N>);
        explicit_products!(Dual<N>);

        #[inline(always)]
        fn quat_to_wxyz(q: UnitQuaternion<Dual<N>>) -> [Dual<N>; 4] {
            let c = q.as_ref().coords;
            [c[3], c[0], c[1], c[2]]
        }
        #[inline(always)]
        fn quat_mul(
            a: UnitQuaternion<Dual<N>>,
            b: UnitQuaternion<Dual<N>>,
        ) -> UnitQuaternion<Dual<N>> {
            // nalgebra's `Quaternion × Quaternion`, with coords [i, j, k, w].
            let (a, b) = (a.as_ref().coords, b.as_ref().coords);
            Unit::new_unchecked(Quaternion::new(
                a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
                a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
                a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
                a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
            ))
        }
        #[inline(always)]
        fn quat_conj(q: UnitQuaternion<Dual<N>>) -> UnitQuaternion<Dual<N>> {
            let c = q.as_ref().coords;
            Unit::new_unchecked(Quaternion::new(c[3], -c[0], -c[1], -c[2]))
        }
        #[inline(always)]
        fn quat_rotate(q: UnitQuaternion<Dual<N>>, v: Vector3<Dual<N>>) -> Vector3<Dual<N>> {
            // nalgebra's `UnitQuaternion × Vector3`: v + 2w (q_v × v) + q_v × (2 q_v × v).
            let c = q.as_ref().coords;
            let qv = Vector3::new(c[0], c[1], c[2]);
            let t = qv.cross(&v) * Dual::constant(2.0);
            let cross = qv.cross(&t);
            t * c[3] + cross + v
        }
    }
}
