//! The glam backends: `Vec3`/`Mat3`/`Quat` for f32, `DVec3`/`DMat3`/`DQuat`
//! for f64, and `Vec3A`/`Mat3A`/`Quat` for f32 in SIMD registers
//! ([`GlamF32A`]). The plain f32 types are the ones most users of glam pass
//! around; the 16-byte aligned ones are what glam's own `Affine3A` is built
//! on, four lanes wide with the fourth unused, and faster for matrix
//! products and actions.

use crate::SimdBackend;
use crate::backend::inherent_primitives;

macro_rules! glam_backend {
    ($(#[$doc:meta])* $name:ident, $s:ty, $v:ty, $m:ty, $q:ty, $label:literal) => {
        $(#[$doc])*
        #[derive(Copy, Clone, Default, Debug, PartialEq, Eq, Hash)]
        pub struct $name;

        inherent_primitives!($name);

        impl SimdBackend for $name {
            type Scalar = $s;
            type Vec3 = $v;
            type Mat3 = $m;
            type Quat = $q;
            const NAME: &'static str = $label;

            #[inline(always)]
            fn vec3(x: $s, y: $s, z: $s) -> $v {
                <$v>::new(x, y, z)
            }
            #[inline(always)]
            fn vec3_to_array(v: $v) -> [$s; 3] {
                v.to_array()
            }
            #[inline(always)]
            fn dot(a: $v, b: $v) -> $s {
                a.dot(b)
            }
            #[inline(always)]
            fn cross(a: $v, b: $v) -> $v {
                a.cross(b)
            }
            #[inline(always)]
            fn mat3_from_cols(c0: $v, c1: $v, c2: $v) -> $m {
                <$m>::from_cols(c0, c1, c2)
            }
            #[inline(always)]
            fn mat3_cols(m: $m) -> [$v; 3] {
                [m.x_axis, m.y_axis, m.z_axis]
            }
            #[inline(always)]
            fn mat3_transpose(m: $m) -> $m {
                m.transpose()
            }
            #[inline(always)]
            fn mat3_tr_mul_vec(m: $m, v: $v) -> $v {
                <$v>::new(m.x_axis.dot(v), m.y_axis.dot(v), m.z_axis.dot(v))
            }
            #[inline(always)]
            fn quat_from_wxyz(w: $s, x: $s, y: $s, z: $s) -> $q {
                <$q>::from_xyzw(x, y, z, w)
            }
            #[inline(always)]
            fn quat_to_wxyz(q: $q) -> [$s; 4] {
                [q.w, q.x, q.y, q.z]
            }
            #[inline(always)]
            fn quat_mul(a: $q, b: $q) -> $q {
                a * b
            }
            #[inline(always)]
            fn quat_conj(q: $q) -> $q {
                q.conjugate()
            }
            #[inline(always)]
            fn quat_rotate(q: $q, v: $v) -> $v {
                q * v
            }
        }
    };
}

glam_backend!(
    /// glam with `f32`: `glam::Vec3`, `glam::Mat3`, `glam::Quat`.
    GlamF32, f32, glam::Vec3, glam::Mat3, glam::Quat, "glam-f32"
);
glam_backend!(
    /// glam with `f64`: `glam::DVec3`, `glam::DMat3`, `glam::DQuat`.
    GlamF64, f64, glam::DVec3, glam::DMat3, glam::DQuat, "glam-f64"
);
glam_backend!(
    /// glam with `f32` in SIMD registers: `glam::Vec3A`, `glam::Mat3A`,
    /// `glam::Quat` (16 bytes a vector, the layout of glam's `Affine3A`).
    GlamF32A, f32, glam::Vec3A, glam::Mat3A, glam::Quat, "glam-f32a"
);
