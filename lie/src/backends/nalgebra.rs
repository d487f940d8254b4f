//! The nalgebra backend: `Vector3<T>`, `Matrix3<T>` and `UnitQuaternion<T>`.

use crate::SimdBackend;
use crate::backend::inherent_primitives;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

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
            fn mat3_tr_mul_vec(m: Matrix3<$s>, v: Vector3<$s>) -> Vector3<$s> {
                m.tr_mul(&v)
            }
            #[inline(always)]
            fn quat_from_wxyz(w: $s, x: $s, y: $s, z: $s) -> UnitQuaternion<$s> {
                UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z))
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
