//! `cargo bench -p geopid-lie`: each operation through the generic `lie` code
//! beside the same formula written by hand on the library's own types, for
//! the four (backend, scalar) pairs (ids `<op>/<pair>/<generic|hand>`),
//! and beside the backend's own types for rotations and rigid motions
//! (ids `vs-native/<op>/<pair> <repr>/<generic|native>`, each over a batch
//! of [`BATCH`] inputs; criterion's throughput says so and the tables
//! divide by it).
//! `cargo xtask bench-table` turns the criterion results into median
//! tables with the ratios; `cargo xtask bench` runs the `vs-native` group
//! and prints its table.

use criterion::{Criterion, criterion_group, criterion_main};
use lie::{Rotation, So3Mat};
use std::hint::black_box;

/// Hand-written glam versions of the formulas (same branches and cut-offs
/// as the generic code, so the ratio measures the abstraction alone).
macro_rules! glam_hand {
    ($m:ident, $s:ty, $v:ty, $mat:ty, $cut_exp:expr, $cut_jac:expr, $cut_log:expr) => {
        mod $m {
            pub fn exp(phi: $v) -> $mat {
                let th = phi.length();
                let (a, b, c) = if th < $cut_exp {
                    let t2 = th * th;
                    let b = 0.5 - t2 * (1.0 / 24.0 - t2 / 720.0);
                    (1.0 - t2 * (1.0 / 6.0 - t2 / 120.0), b, 1.0 - t2 * b)
                } else {
                    let (sh, ch) = (0.5 * th).sin_cos();
                    (
                        2.0 * sh * ch / th,
                        2.0 * sh * sh / (th * th),
                        1.0 - 2.0 * sh * sh,
                    )
                };
                rodrigues(c, a, b, phi)
            }
            fn rodrigues(a0: $s, a1: $s, a2: $s, p: $v) -> $mat {
                let (x, y, z) = (p.x, p.y, p.z);
                <$mat>::from_cols(
                    <$v>::new(a0 + a2 * x * x, a2 * x * y + a1 * z, a2 * x * z - a1 * y),
                    <$v>::new(a2 * x * y - a1 * z, a0 + a2 * y * y, a2 * y * z + a1 * x),
                    <$v>::new(a2 * x * z + a1 * y, a2 * y * z - a1 * x, a0 + a2 * z * z),
                )
            }
            pub fn left_jacobian(phi: $v) -> $mat {
                let th = phi.length();
                let t2 = th * th;
                let (a, b) = if th < $cut_exp {
                    (
                        1.0 - t2 * (1.0 / 6.0 - t2 / 120.0),
                        0.5 - t2 * (1.0 / 24.0 - t2 / 720.0),
                    )
                } else {
                    let (sh, ch) = (0.5 * th).sin_cos();
                    (2.0 * sh * ch / th, 2.0 * sh * sh / t2)
                };
                let c = if th < $cut_jac {
                    let k: [$s; 7] = [
                        1.0 / 6.0,
                        -1.0 / 120.0,
                        1.0 / 5040.0,
                        -1.0 / 362880.0,
                        1.0 / 39916800.0,
                        -1.0 / 6227020800.0,
                        1.0 / 1307674368000.0,
                    ];
                    let mut acc = k[6];
                    for i in (0..6).rev() {
                        acc = acc * t2 + k[i];
                    }
                    acc
                } else {
                    (th - th.sin()) / (t2 * th)
                };
                rodrigues(a, b, c, phi)
            }
            pub fn log(m: $mat) -> $v {
                let (m00, m11, m22) = (m.x_axis.x, m.y_axis.y, m.z_axis.z);
                let (m01, m02, m10) = (m.y_axis.x, m.z_axis.x, m.x_axis.y);
                let (m12, m20, m21) = (m.z_axis.y, m.x_axis.z, m.y_axis.z);
                let tr = m00 + m11 + m22;
                let [mut w, mut x, mut y, mut z] = if tr >= m00 && tr >= m11 && tr >= m22 {
                    let w = 0.5 * (1.0 + tr).sqrt();
                    let k = 0.25 / w;
                    [w, (m21 - m12) * k, (m02 - m20) * k, (m10 - m01) * k]
                } else if m00 >= m11 && m00 >= m22 {
                    let x = 0.5 * (1.0 + m00 - m11 - m22).sqrt();
                    let k = 0.25 / x;
                    [(m21 - m12) * k, x, (m01 + m10) * k, (m02 + m20) * k]
                } else if m11 >= m22 {
                    let y = 0.5 * (1.0 - m00 + m11 - m22).sqrt();
                    let k = 0.25 / y;
                    [(m02 - m20) * k, (m01 + m10) * k, y, (m12 + m21) * k]
                } else {
                    let z = 0.5 * (1.0 - m00 - m11 + m22).sqrt();
                    let k = 0.25 / z;
                    [(m10 - m01) * k, (m02 + m20) * k, (m12 + m21) * k, z]
                };
                if w < 0.0 {
                    (w, x, y, z) = (-w, -x, -y, -z);
                }
                let n2 = x * x + y * y + z * z;
                let n = n2.sqrt();
                let k = if n < $cut_log {
                    2.0 / w - (2.0 / 3.0) * n2 / (w * w * w)
                } else {
                    2.0 * n.atan2(w) / n
                };
                <$v>::new(x * k, y * k, z * k)
            }
        }
    };
}
glam_hand!(glam32, f32, glam::Vec3, glam::Mat3, 1e-2, 1.5, 1e-4);
glam_hand!(glam64, f64, glam::DVec3, glam::DMat3, 1e-3, 0.5, 1e-8);

/// Hand-written nalgebra versions of the same formulas.
macro_rules! na_hand {
    ($m:ident, $s:ty, $cut_exp:expr, $cut_jac:expr, $cut_log:expr) => {
        mod $m {
            use nalgebra::{Matrix3, Vector3};
            pub fn exp(phi: Vector3<$s>) -> Matrix3<$s> {
                let th = phi.norm();
                let (a, b, c) = if th < $cut_exp {
                    let t2 = th * th;
                    let b = 0.5 - t2 * (1.0 / 24.0 - t2 / 720.0);
                    (1.0 - t2 * (1.0 / 6.0 - t2 / 120.0), b, 1.0 - t2 * b)
                } else {
                    let (sh, ch) = (0.5 * th).sin_cos();
                    (
                        2.0 * sh * ch / th,
                        2.0 * sh * sh / (th * th),
                        1.0 - 2.0 * sh * sh,
                    )
                };
                rodrigues(c, a, b, phi)
            }
            fn rodrigues(a0: $s, a1: $s, a2: $s, p: Vector3<$s>) -> Matrix3<$s> {
                let (x, y, z) = (p.x, p.y, p.z);
                Matrix3::new(
                    a0 + a2 * x * x,
                    a2 * x * y - a1 * z,
                    a2 * x * z + a1 * y,
                    a2 * x * y + a1 * z,
                    a0 + a2 * y * y,
                    a2 * y * z - a1 * x,
                    a2 * x * z - a1 * y,
                    a2 * y * z + a1 * x,
                    a0 + a2 * z * z,
                )
            }
            pub fn left_jacobian(phi: Vector3<$s>) -> Matrix3<$s> {
                let th = phi.norm();
                let t2 = th * th;
                let (a, b) = if th < $cut_exp {
                    (
                        1.0 - t2 * (1.0 / 6.0 - t2 / 120.0),
                        0.5 - t2 * (1.0 / 24.0 - t2 / 720.0),
                    )
                } else {
                    let (sh, ch) = (0.5 * th).sin_cos();
                    (2.0 * sh * ch / th, 2.0 * sh * sh / t2)
                };
                let c = if th < $cut_jac {
                    let k: [$s; 7] = [
                        1.0 / 6.0,
                        -1.0 / 120.0,
                        1.0 / 5040.0,
                        -1.0 / 362880.0,
                        1.0 / 39916800.0,
                        -1.0 / 6227020800.0,
                        1.0 / 1307674368000.0,
                    ];
                    let mut acc = k[6];
                    for i in (0..6).rev() {
                        acc = acc * t2 + k[i];
                    }
                    acc
                } else {
                    (th - th.sin()) / (t2 * th)
                };
                rodrigues(a, b, c, phi)
            }
            pub fn log(m: Matrix3<$s>) -> Vector3<$s> {
                let tr = m[(0, 0)] + m[(1, 1)] + m[(2, 2)];
                let (m00, m11, m22) = (m[(0, 0)], m[(1, 1)], m[(2, 2)]);
                let [mut w, mut x, mut y, mut z] = if tr >= m00 && tr >= m11 && tr >= m22 {
                    let w = 0.5 * (1.0 + tr).sqrt();
                    let k = 0.25 / w;
                    [
                        w,
                        (m[(2, 1)] - m[(1, 2)]) * k,
                        (m[(0, 2)] - m[(2, 0)]) * k,
                        (m[(1, 0)] - m[(0, 1)]) * k,
                    ]
                } else if m00 >= m11 && m00 >= m22 {
                    let x = 0.5 * (1.0 + m00 - m11 - m22).sqrt();
                    let k = 0.25 / x;
                    [
                        (m[(2, 1)] - m[(1, 2)]) * k,
                        x,
                        (m[(0, 1)] + m[(1, 0)]) * k,
                        (m[(0, 2)] + m[(2, 0)]) * k,
                    ]
                } else if m11 >= m22 {
                    let y = 0.5 * (1.0 - m00 + m11 - m22).sqrt();
                    let k = 0.25 / y;
                    [
                        (m[(0, 2)] - m[(2, 0)]) * k,
                        (m[(0, 1)] + m[(1, 0)]) * k,
                        y,
                        (m[(1, 2)] + m[(2, 1)]) * k,
                    ]
                } else {
                    let z = 0.5 * (1.0 - m00 - m11 + m22).sqrt();
                    let k = 0.25 / z;
                    [
                        (m[(1, 0)] - m[(0, 1)]) * k,
                        (m[(0, 2)] + m[(2, 0)]) * k,
                        (m[(1, 2)] + m[(2, 1)]) * k,
                        z,
                    ]
                };
                if w < 0.0 {
                    (w, x, y, z) = (-w, -x, -y, -z);
                }
                let n2 = x * x + y * y + z * z;
                let n = n2.sqrt();
                let k = if n < $cut_log {
                    2.0 / w - (2.0 / 3.0) * n2 / (w * w * w)
                } else {
                    2.0 * n.atan2(w) / n
                };
                Vector3::new(x * k, y * k, z * k)
            }
        }
    };
}
na_hand!(na32, f32, 1e-2, 1.5, 1e-4);
na_hand!(na64, f64, 1e-3, 0.5, 1e-8);

macro_rules! bench_pair {
    ($c:expr, $backend:ty, $hand:ident, $v:expr, $w:expr) => {{
        type B = $backend;
        let name = <B as lie::SimdBackend>::NAME;
        let phi = $v;
        let v = $w;
        let r = So3Mat::<B>::exp(phi);
        let r2 = So3Mat::<B>::exp(v);
        let (m, m2) = (r.matrix(), r2.matrix());
        let mut g = $c.benchmark_group("exp");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| So3Mat::<B>::exp(black_box(phi)))
        });
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| $hand::exp(black_box(phi)))
        });
        g.finish();
        let mut g = $c.benchmark_group("log");
        g.bench_function(format!("{name}/generic"), |b| b.iter(|| black_box(r).log()));
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| $hand::log(black_box(m)))
        });
        g.finish();
        let mut g = $c.benchmark_group("compose");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| black_box(r) * black_box(r2))
        });
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| black_box(m) * black_box(m2))
        });
        g.finish();
        let mut g = $c.benchmark_group("act");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| black_box(r).act(black_box(v)))
        });
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| black_box(m) * black_box(v))
        });
        g.finish();
        // The group operations of `LieGroup` (called through the trait:
        // `Rotation` shares some names); the hand twins are the same
        // formulas on the backend's own matrices.
        type G = So3Mat<B>;
        let mut g = $c.benchmark_group("rplus");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| <G as lie::LieGroup<B>>::rplus(black_box(r), black_box(phi)))
        });
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| black_box(m) * $hand::exp(black_box(phi)))
        });
        g.finish();
        let mut g = $c.benchmark_group("rminus");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| <G as lie::LieGroup<B>>::rminus(black_box(r2), black_box(r)))
        });
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| $hand::log(black_box(m).transpose() * black_box(m2)))
        });
        g.finish();
        let mut g = $c.benchmark_group("rplus_jac");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| <G as lie::LieGroup<B>>::rplus_jac(black_box(r), black_box(phi)))
        });
        g.finish();
        let mut g = $c.benchmark_group("rminus_jac");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| <G as lie::LieGroup<B>>::rminus_jac(black_box(r2), black_box(r)))
        });
        g.finish();
        let mut g = $c.benchmark_group("left_jacobian");
        g.bench_function(format!("{name}/generic"), |b| {
            b.iter(|| lie::left_jacobian::<B>(black_box(phi)))
        });
        g.bench_function(format!("{name}/hand"), |b| {
            b.iter(|| $hand::left_jacobian(black_box(phi)))
        });
        g.finish();
    }};
}

fn benches(c: &mut Criterion) {
    // A generic-angle input (θ ≈ 1.1, the closed-form branches) for every op.
    bench_pair!(
        c,
        lie::GlamF32,
        glam32,
        glam::Vec3::new(0.3, -0.7, 0.8),
        glam::Vec3::new(1.0, 2.0, 3.0)
    );
    bench_pair!(
        c,
        lie::GlamF64,
        glam64,
        glam::DVec3::new(0.3, -0.7, 0.8),
        glam::DVec3::new(1.0, 2.0, 3.0)
    );
    bench_pair!(
        c,
        lie::NalgebraF32,
        na32,
        nalgebra::Vector3::new(0.3f32, -0.7, 0.8),
        nalgebra::Vector3::new(1.0f32, 2.0, 3.0)
    );
    bench_pair!(
        c,
        lie::NalgebraF64,
        na64,
        nalgebra::Vector3::new(0.3f64, -0.7, 0.8),
        nalgebra::Vector3::new(1.0f64, 2.0, 3.0)
    );
}

/// Inputs per timed iteration of the `vs-native` group. A loop that feeds
/// one black-boxed value to the same call 10⁸ times measured the
/// surroundings more than the call here: the same inlined
/// `So3Quat::exp` took 6 ns in one such loop and 22 ns in another, and
/// nalgebra's own `Rotation3` log 8 ns or 24 ns from one build to the
/// next. Over an array of different inputs, results written to an array
/// as a loop over data does, the times are stable to a few per cent.
const BATCH: usize = 64;

/// `BATCH` rotation vectors `comb(a_k, b_k) = a_k φ + b_k ψ` (`(a_k, b_k)` on a circle of
/// radius 0.9): angles from about 0.1 to 1.6 rad about axes in the plane
/// of φ and ψ, the moderate angles of increments and residuals.
fn spread<V>(comb: impl Fn(f64, f64) -> V) -> Vec<V> {
    (0..BATCH)
        .map(|k| {
            let t = k as f64 * 0.37;
            comb(0.9 * t.cos(), 0.9 * t.sin())
        })
        .collect()
}

/// Times `f` over every input of a batch, its results kept in an array.
fn over<I: Copy, O: Clone>(b: &mut criterion::Bencher<'_>, inputs: &[I], f: impl Fn(I) -> O) {
    let mut out = vec![f(inputs[0]); inputs.len()];
    b.iter(|| {
        for (o, x) in out.iter_mut().zip(black_box(inputs)) {
            *o = f(*x);
        }
        black_box(&mut out);
    })
}

/// Each operation through `lie` beside the backend's own type for it
/// (nalgebra's `Rotation3` and `UnitQuaternion`, glam's `Quat`), where
/// the backend has the operation, over a batch of [`BATCH`] inputs: ids
/// `vs-native/<op>/<pair> <repr>/<generic|native>`.
macro_rules! bench_native {
    ($c:expr, $backend:ty, $repr:ident, $native:ty, $new:expr, $log:expr, $inv:expr, $v:expr, $w:expr) => {{
        type B = $backend;
        type G = lie::$repr<B>;
        type V = lie::V3<B>;
        let name = format!("{} {}", <B as lie::SimdBackend>::NAME, stringify!($repr));
        // The backend's calls stay closures (not `fn` pointers) so that
        // they inline as the `lie` side does.
        let new = |v: V| -> $native { $new(v) };
        let log = |n: $native| -> V { $log(n) };
        let inv = |n: $native| -> $native { $inv(n) };
        let lit = <lie::S<B> as lie::Real>::lit;
        let (v0, w0): (V, V) = ($v, $w);
        let phis = spread(|a, b| v0 * lit(a) + w0 * lit(b));
        let ws = spread(|a, b| w0 * lit(a) + v0 * lit(b));
        let gs: Vec<(G, G, V)> = phis
            .iter()
            .zip(&ws)
            .map(|(p, w)| (G::exp(*p), G::exp(*w), *w))
            .collect();
        let ns: Vec<($native, $native, V)> = phis
            .iter()
            .zip(&ws)
            .map(|(p, w)| (new(*p), new(*w), *w))
            .collect();
        let mut g = $c.benchmark_group("vs-native");
        g.throughput(criterion::Throughput::Elements(BATCH as u64));
        g.bench_function(format!("exp/{name}/generic"), |b| {
            over(b, &phis, |p| G::exp(p))
        });
        g.bench_function(format!("exp/{name}/native"), |b| over(b, &phis, |p| new(p)));
        g.bench_function(format!("log/{name}/generic"), |b| {
            over(b, &gs, |(r, _, _)| r.log())
        });
        g.bench_function(format!("log/{name}/native"), |b| {
            over(b, &ns, |(n, _, _)| log(n))
        });
        g.bench_function(format!("compose/{name}/generic"), |b| {
            over(b, &gs, |(r, r2, _)| r.compose(r2))
        });
        g.bench_function(format!("compose/{name}/native"), |b| {
            over(b, &ns, |(n, n2, _)| n * n2)
        });
        g.bench_function(format!("rplus/{name}/generic"), |b| {
            over(b, &gs, |(r, _, w)| <G as lie::LieGroup<B>>::rplus(r, w))
        });
        g.bench_function(format!("rplus/{name}/native"), |b| {
            over(b, &ns, |(n, _, w)| n * new(w))
        });
        g.bench_function(format!("rminus/{name}/generic"), |b| {
            over(b, &gs, |(r, r2, _)| <G as lie::LieGroup<B>>::rminus(r2, r))
        });
        g.bench_function(format!("rminus/{name}/native"), |b| {
            over(b, &ns, |(n, n2, _)| log(inv(n) * n2))
        });
        g.bench_function(format!("rplus_jac/{name}/generic"), |b| {
            over(b, &gs, |(r, _, w)| <G as lie::LieGroup<B>>::rplus_jac(r, w))
        });
        g.bench_function(format!("rminus_jac/{name}/generic"), |b| {
            over(b, &gs, |(r, r2, _)| {
                <G as lie::LieGroup<B>>::rminus_jac(r2, r)
            })
        });
        g.finish();
    }};
}

/// SE(3) through `lie` beside nalgebra's `IsometryMatrix3`/`Isometry3` and
/// glam's `Affine3A`/`DAffine3` where the backend has a type for it (they
/// compose and act; neither has exp or log, so those rows have no
/// baseline), over a batch of [`BATCH`] inputs. Ids
/// `vs-native/<op>/<pair> Se3<repr>/<generic|native>`.
macro_rules! bench_se3 {
    ($c:expr, $backend:ty, $repr:ident, $native:ty, $to_native:expr, $act:expr, $v:expr, $w:expr) => {{
        type B = $backend;
        type G = lie::Se3<B, lie::$repr<B>>;
        type V = lie::V3<B>;
        let name = format!(
            "{} Se3<{}>",
            <B as lie::SimdBackend>::NAME,
            stringify!($repr)
        );
        let to_native: fn(G) -> $native = $to_native;
        let act = $act;
        let lit = <lie::S<B> as lie::Real>::lit;
        let (v0, w0): (V, V) = ($v, $w);
        let vs = spread(|a, b| v0 * lit(a) + w0 * lit(b));
        let ws = spread(|a, b| w0 * lit(a) + v0 * lit(b));
        // (ξ, ξ₂, X = Exp ξ, Y = Exp ξ₂, a point).
        let gs: Vec<_> = vs
            .iter()
            .zip(&ws)
            .map(|(v, w)| {
                let (xi, xi2) = (lie::Twist::<B>::new(*w, *v), lie::Twist::<B>::new(*v, *w));
                (xi, xi2, G::exp(xi), G::exp(xi2), *v)
            })
            .collect();
        let ns: Vec<($native, $native, V)> = gs
            .iter()
            .map(|g| (to_native(g.2), to_native(g.3), g.4))
            .collect();
        let mut g = $c.benchmark_group("vs-native");
        g.throughput(criterion::Throughput::Elements(BATCH as u64));
        g.bench_function(format!("exp/{name}/generic"), |b| {
            over(b, &gs, |x| G::exp(x.0))
        });
        g.bench_function(format!("log/{name}/generic"), |b| {
            over(b, &gs, |x| x.2.log())
        });
        g.bench_function(format!("compose/{name}/generic"), |b| {
            over(b, &gs, |x| x.2.compose(x.3))
        });
        g.bench_function(format!("compose/{name}/native"), |b| {
            over(b, &ns, |(n, n2, _)| n * n2)
        });
        g.bench_function(format!("act/{name}/generic"), |b| {
            over(b, &gs, |x| x.2.act(x.4))
        });
        g.bench_function(format!("act/{name}/native"), |b| {
            over(b, &ns, |(n, _, p)| act(n, p))
        });
        g.bench_function(format!("rplus/{name}/generic"), |b| {
            over(b, &gs, |x| <G as lie::LieGroup<B>>::rplus(x.2, x.1))
        });
        g.bench_function(format!("rminus/{name}/generic"), |b| {
            over(b, &gs, |x| <G as lie::LieGroup<B>>::rminus(x.3, x.2))
        });
        g.bench_function(format!("rplus_jac/{name}/generic"), |b| {
            over(b, &gs, |x| <G as lie::LieGroup<B>>::rplus_jac(x.2, x.1))
        });
        g.bench_function(format!("rminus_jac/{name}/generic"), |b| {
            over(b, &gs, |x| <G as lie::LieGroup<B>>::rminus_jac(x.3, x.2))
        });
        g.finish();
    }};
}

fn se3_natives(c: &mut Criterion) {
    use nalgebra::{Isometry3, IsometryMatrix3, Point3, Translation3, Vector3};
    let (v64, w64) = (
        Vector3::new(0.3f64, -0.7, 0.8),
        Vector3::new(0.3f64, 0.6, 0.9),
    );
    let (v32, w32) = (
        Vector3::new(0.3f32, -0.7, 0.8),
        Vector3::new(0.3f32, 0.6, 0.9),
    );
    bench_se3!(
        c,
        lie::NalgebraF64,
        So3Mat,
        IsometryMatrix3<f64>,
        |x| IsometryMatrix3::from_parts(
            Translation3::from(x.translation),
            nalgebra::Rotation3::from_matrix_unchecked(x.rotation.matrix())
        ),
        |n: IsometryMatrix3<f64>, p: Vector3<f64>| n * Point3::from(p),
        v64,
        w64
    );
    bench_se3!(
        c,
        lie::NalgebraF64,
        So3Quat,
        Isometry3<f64>,
        |x| Isometry3::from_parts(Translation3::from(x.translation), x.rotation.quaternion()),
        |n: Isometry3<f64>, p: Vector3<f64>| n * Point3::from(p),
        v64,
        w64
    );
    bench_se3!(
        c,
        lie::NalgebraF32,
        So3Mat,
        IsometryMatrix3<f32>,
        |x| IsometryMatrix3::from_parts(
            Translation3::from(x.translation),
            nalgebra::Rotation3::from_matrix_unchecked(x.rotation.matrix())
        ),
        |n: IsometryMatrix3<f32>, p: Vector3<f32>| n * Point3::from(p),
        v32,
        w32
    );
    bench_se3!(
        c,
        lie::NalgebraF32,
        So3Quat,
        Isometry3<f32>,
        |x| Isometry3::from_parts(Translation3::from(x.translation), x.rotation.quaternion()),
        |n: Isometry3<f32>, p: Vector3<f32>| n * Point3::from(p),
        v32,
        w32
    );
    bench_se3!(
        c,
        lie::GlamF64,
        So3Mat,
        glam::DAffine3,
        |x| glam::DAffine3::from_mat3_translation(x.rotation.matrix(), x.translation),
        |n: glam::DAffine3, p: glam::DVec3| n.transform_point3(p),
        glam::DVec3::new(0.3, -0.7, 0.8),
        glam::DVec3::new(0.3, 0.6, 0.9)
    );
    // `Affine3A` is `Mat3A` + `Vec3A`: the SIMD backend's layout, so it is
    // beside `GlamF32A`; glam has no f32 affine type on `Mat3`/`Vec3`.
    bench_se3!(
        c,
        lie::GlamF32A,
        So3Mat,
        glam::Affine3A,
        |x| glam::Affine3A {
            matrix3: x.rotation.matrix(),
            translation: x.translation,
        },
        |n: glam::Affine3A, p: glam::Vec3A| n.transform_point3a(p),
        glam::Vec3A::new(0.3, -0.7, 0.8),
        glam::Vec3A::new(0.3, 0.6, 0.9)
    );
}

fn natives(c: &mut Criterion) {
    use nalgebra::{Rotation3, UnitQuaternion, Vector3};
    let (v64, w64) = (
        Vector3::new(0.3f64, -0.7, 0.8),
        Vector3::new(1.0f64, 2.0, 3.0) * 0.3,
    );
    let (v32, w32) = (
        Vector3::new(0.3f32, -0.7, 0.8),
        Vector3::new(1.0f32, 2.0, 3.0) * 0.3,
    );
    bench_native!(
        c,
        lie::NalgebraF64,
        So3Mat,
        Rotation3<f64>,
        Rotation3::new,
        |r: Rotation3<f64>| r.scaled_axis(),
        |r: Rotation3<f64>| r.inverse(),
        v64,
        w64
    );
    bench_native!(
        c,
        lie::NalgebraF64,
        So3Quat,
        UnitQuaternion<f64>,
        UnitQuaternion::new,
        |q: UnitQuaternion<f64>| q.scaled_axis(),
        |q: UnitQuaternion<f64>| q.inverse(),
        v64,
        w64
    );
    bench_native!(
        c,
        lie::NalgebraF32,
        So3Mat,
        Rotation3<f32>,
        Rotation3::new,
        |r: Rotation3<f32>| r.scaled_axis(),
        |r: Rotation3<f32>| r.inverse(),
        v32,
        w32
    );
    bench_native!(
        c,
        lie::NalgebraF32,
        So3Quat,
        UnitQuaternion<f32>,
        UnitQuaternion::new,
        |q: UnitQuaternion<f32>| q.scaled_axis(),
        |q: UnitQuaternion<f32>| q.inverse(),
        v32,
        w32
    );
    let (g64, h64) = (
        glam::DVec3::new(0.3, -0.7, 0.8),
        glam::DVec3::new(0.3, 0.6, 0.9),
    );
    let (g32, h32) = (
        glam::Vec3::new(0.3, -0.7, 0.8),
        glam::Vec3::new(0.3, 0.6, 0.9),
    );
    bench_native!(
        c,
        lie::GlamF64,
        So3Quat,
        glam::DQuat,
        glam::DQuat::from_scaled_axis,
        |q: glam::DQuat| q.to_scaled_axis(),
        |q: glam::DQuat| q.inverse(),
        g64,
        h64
    );
    bench_native!(
        c,
        lie::GlamF32,
        So3Quat,
        glam::Quat,
        glam::Quat::from_scaled_axis,
        |q: glam::Quat| q.to_scaled_axis(),
        |q: glam::Quat| q.inverse(),
        g32,
        h32
    );
    let (a32, b32) = (
        glam::Vec3A::new(0.3, -0.7, 0.8),
        glam::Vec3A::new(0.3, 0.6, 0.9),
    );
    bench_native!(
        c,
        lie::GlamF32A,
        So3Quat,
        glam::Quat,
        |v: glam::Vec3A| glam::Quat::from_scaled_axis(v.into()),
        |q: glam::Quat| glam::Vec3A::from(q.to_scaled_axis()),
        |q: glam::Quat| q.inverse(),
        a32,
        b32
    );
}

criterion_group!(lie_benches, benches, natives, se3_natives);
criterion_main!(lie_benches);
