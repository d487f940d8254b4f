//! Reference generators with their analytic derivatives.

use std::cell::RefCell;
use std::rc::Rc;

use controllers::{AttitudeReference, PositionReference, PositionSource};
use lie::{Backend, Real, S, So3Mat, V3};
use missions::Trajectory;

use crate::scene::{AttitudeRef, PositionRef};

type M = [[f64; 3]; 3];

fn rot(axis: usize, a: f64) -> M {
    let (s, c) = a.sin_cos();
    match axis {
        0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

fn mul(a: M, b: M) -> M {
    // Written out: this runs four times per integrator step.
    let r = |i: usize, j: usize| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    [
        [r(0, 0), r(0, 1), r(0, 2)],
        [r(1, 0), r(1, 1), r(1, 2)],
        [r(2, 0), r(2, 1), r(2, 2)],
    ]
}

/// `mᵀ v`.
fn tmul(m: M, v: [f64; 3]) -> [f64; 3] {
    let c = |j: usize| m[0][j] * v[0] + m[1][j] * v[1] + m[2][j] * v[2];
    [c(0), c(1), c(2)]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn axpy(a: f64, x: [f64; 3], y: [f64; 3]) -> [f64; 3] {
    [a * x[0] + y[0], a * x[1] + y[1], a * x[2] + y[2]]
}

#[doc(hidden)]
pub fn v<B: Backend>(a: [f64; 3]) -> V3<B> {
    B::vec3(S::<B>::lit(a[0]), S::<B>::lit(a[1]), S::<B>::lit(a[2]))
}

#[doc(hidden)]
pub fn m<B: Backend>(a: M) -> So3Mat<B> {
    let l = S::<B>::lit;
    So3Mat::from_matrix_unchecked(B::mat3_from_cols(
        B::vec3(l(a[0][0]), l(a[1][0]), l(a[2][0])),
        B::vec3(l(a[0][1]), l(a[1][1]), l(a[2][1])),
        B::vec3(l(a[0][2]), l(a[1][2]), l(a[2][2])),
    ))
}

/// `(R_d, Ω_d, Ω̇_d)` at time `t`, computed in f64.
pub fn attitude_f64(r: &AttitudeRef, t: f64) -> (M, [f64; 3], [f64; 3]) {
    use std::f64::consts::PI;
    match r {
        AttitudeRef::PaperFlip {} => {
            // R_d = Rz(πt) Ry(4πt); Ω_d = π Ry(4πt)ᵀe3 + 4π e2,
            // Ω̇_d = −4π² e2 × Ry(4πt)ᵀe3.
            let ry = rot(1, 4.0 * PI * t);
            let rd = mul(rot(2, PI * t), ry);
            let e3b = tmul(ry, [0.0, 0.0, 1.0]);
            let w = axpy(PI, e3b, [0.0, 4.0 * PI, 0.0]);
            let wd = cross([0.0, -4.0 * PI * PI, 0.0], e3b);
            (rd, w, wd)
        }
        AttitudeRef::EulerExperiment {
            amplitude,
            frequency,
        } => {
            // R_d = Ry(θ) Rx(φ); Ω_d = φ̇ e1 + θ̇ Rx(φ)ᵀe2,
            // Ω̇_d = φ̈ e1 + θ̈ Rxᵀe2 − θ̇ φ̇ e1 × Rxᵀe2.
            let (a, w) = (*amplitude, *frequency);
            let (s, c) = (w * t).sin_cos();
            let (phi, phid, phidd) = (a * s, a * w * c, -a * w * w * s);
            let (th, thd, thdd) = (a * c, -a * w * s, -a * w * w * c);
            let rx = rot(0, phi);
            let e2r = tmul(rx, [0.0, 1.0, 0.0]);
            let om = axpy(thd, e2r, [phid, 0.0, 0.0]);
            let e1xe2r = cross([1.0, 0.0, 0.0], e2r);
            let omd = axpy(-thd * phid, e1xe2r, axpy(thdd, e2r, [phidd, 0.0, 0.0]));
            (mul(rot(1, th), rx), om, omd)
        }
        AttitudeRef::Hold { rotation } => (rotation_f64(*rotation), [0.0; 3], [0.0; 3]),
    }
}

/// The attitude reference in backend types.
pub fn attitude<B: Backend>(r: &AttitudeRef, t: S<B>) -> AttitudeReference<B, So3Mat<B>> {
    let (rd, w, wd) = attitude_f64(r, t.to_f64_lossless());
    AttitudeReference {
        rd: m::<B>(rd),
        omega_d: v::<B>(w),
        omega_d_dot: v::<B>(wd),
    }
}

/// A planned trajectory and the time it starts, s.
pub type Planned = Rc<(Trajectory, f64)>;

thread_local! {
    /// The planned references this thread evaluated last, with their
    /// trajectories: planning solves a linear system or reads a file, too
    /// much to repeat per evaluation.
    static PLANNED: RefCell<Vec<(PositionRef, Planned)>> =
        const { RefCell::new(Vec::new()) };
}

/// The trajectory and start time of a planned reference (`minsnap`,
/// `trajectory-file`), planned once per thread; `None` for the curves.
///
/// # Panics
/// If [`PositionRef::plan`] refuses `p`: a scene's references are
/// validated when it is read, and every run validates again.
pub fn planned(p: &PositionRef) -> Option<Planned> {
    if !matches!(
        p,
        PositionRef::MinSnap { .. } | PositionRef::TrajectoryFile { .. }
    ) {
        return None;
    }
    PLANNED.with(|cache| {
        let mut cache = cache.borrow_mut();
        if let Some((_, t)) = cache.iter().find(|(q, _)| q == p) {
            return Some(t.clone());
        }
        let t = match p.plan() {
            Ok(Some(t)) => Rc::new(t),
            Ok(None) => unreachable!("a minsnap or trajectory-file reference plans"),
            Err(e) => panic!("position reference not validated: {e}"),
        };
        if cache.len() >= 8 {
            cache.remove(0);
        }
        cache.push((p.clone(), t.clone()));
        Some(t)
    })
}

/// `(x_d, ẋ_d, ẍ_d, x_d⁽³⁾, x_d⁽⁴⁾, b1d)` at time `t`, in f64.
///
/// # Panics
/// For a planned reference that does not validate (see [`planned`]).
pub fn position_f64(p: &PositionRef, t: f64) -> ([[f64; 3]; 5], [f64; 3]) {
    match p {
        PositionRef::MinSnap { .. } | PositionRef::TrajectoryFile { .. } => planned_f64(p, t),
        PositionRef::Hold { x, b1d } => {
            let n = (b1d[0] * b1d[0] + b1d[1] * b1d[1] + b1d[2] * b1d[2]).sqrt();
            (
                [*x, [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]],
                b1d.map(|c| c / n),
            )
        }
        PositionRef::FigureEight {
            center,
            a,
            b,
            omega,
        } => {
            let w = *omega;
            let (s1, c1) = (w * t).sin_cos();
            let (s2, c2) = (2.0 * w * t).sin_cos();
            let w2 = 2.0 * w;
            let d = [
                [center[0] + a * s1, center[1] + b * s2, center[2]],
                [a * w * c1, b * w2 * c2, 0.0],
                [-a * w * w * s1, -b * w2 * w2 * s2, 0.0],
                [-a * w.powi(3) * c1, -b * w2.powi(3) * c2, 0.0],
                [a * w.powi(4) * s1, b * w2.powi(4) * s2, 0.0],
            ];
            (d, [1.0, 0.0, 0.0])
        }
        PositionRef::Sinusoids {
            center,
            amplitude,
            omega,
            phase,
        } => {
            let mut d = [[0.0; 3]; 5];
            for i in 0..3 {
                let (a, w) = (amplitude[i], omega[i]);
                let (s, c) = (w * t + phase[i]).sin_cos();
                d[0][i] = center[i] + a * s;
                d[1][i] = a * w * c;
                d[2][i] = -a * w * w * s;
                d[3][i] = -a * w.powi(3) * c;
                d[4][i] = a * w.powi(4) * s;
            }
            (d, [1.0, 0.0, 0.0])
        }
        PositionRef::Circle {
            center,
            radius,
            omega,
        } => {
            let (r, w) = (*radius, *omega);
            let (s, c) = (w * t).sin_cos();
            let d = [
                [center[0] + r * c, center[1] + r * s, center[2]],
                [-r * w * s, r * w * c, 0.0],
                [-r * w * w * c, -r * w * w * s, 0.0],
                [r * w.powi(3) * s, -r * w.powi(3) * c, 0.0],
                [r * w.powi(4) * c, r * w.powi(4) * s, 0.0],
            ];
            (d, [1.0, 0.0, 0.0])
        }
    }
}

/// [`position_f64`] of a planned reference, out of the curves' way.
#[cold]
#[inline(never)]
fn planned_f64(p: &PositionRef, t: f64) -> ([[f64; 3]; 5], [f64; 3]) {
    let plan = planned(p).expect("a planned reference");
    let f = plan.0.flat(t - plan.1);
    let (s, c) = f.yaw[0].sin_cos();
    (f.x, [c, s, 0.0])
}

/// [`position`] of a planned reference, out of the curves' way.
#[cold]
#[inline(never)]
fn planned_position<B: Backend>(p: &PositionRef, t: S<B>) -> PositionReference<B> {
    let plan = planned(p).expect("a planned reference");
    plan.0.position(t - S::<B>::lit(plan.1))
}

/// The position reference in backend types (a planned one with the
/// heading's derivatives from its yaw).
#[inline]
pub fn position<B: Backend>(p: &PositionRef, t: S<B>) -> PositionReference<B> {
    if matches!(
        p,
        PositionRef::MinSnap { .. } | PositionRef::TrajectoryFile { .. }
    ) {
        return planned_position(p, t);
    }
    curve::<B>(p, t)
}

/// [`position`] of an analytic curve (a planned reference is evaluated
/// through [`position_f64`], without its heading's derivatives).
#[doc(hidden)]
#[inline]
pub fn curve<B: Backend>(p: &PositionRef, t: S<B>) -> PositionReference<B> {
    let (d, b1) = position_f64(p, t.to_f64_lossless());
    let mut r = PositionReference::<B>::hold(v::<B>(d[0]), v::<B>(b1));
    r.v = v::<B>(d[1]);
    r.a = v::<B>(d[2]);
    r.jerk = v::<B>(d[3]);
    r.snap = v::<B>(d[4]);
    r
}

/// The rotation with rotation vector `phi`, rows, in f64 (`lie`'s exp on
/// nalgebra-f64).
pub fn rotation_f64(phi: [f64; 3]) -> M {
    use lie::{NalgebraF64, Rotation};
    let r = So3Mat::<NalgebraF64>::exp(NalgebraF64::vec3(phi[0], phi[1], phi[2])).matrix();
    lie::ops::elems::<NalgebraF64>(r)
}

/// How far a position reference's derivatives are from central differences
/// of the one below them, over `n` times evenly spread in `[t0, t1]`:
/// `[ẋ_d, ẍ_d, x_d⁽³⁾, x_d⁽⁴⁾, ḃ1d, b̈1d]`, each the largest
/// `|analytic − difference|` divided by (1 + the largest |analytic|). A
/// user's trajectory with consistent derivatives gives ~1e-7 or less (the
/// differences' own error at step 1e-4 on a smooth path); a wrong sign or
/// factor gives O(1). Evaluated on nalgebra-f64.
pub fn derivative_mismatch<P: controllers::PositionSource<lie::NalgebraF64>>(
    source: &P,
    t0: f64,
    t1: f64,
    n: usize,
) -> [f64; 6] {
    use lie::NalgebraF64 as N;
    let h = 1e-4;
    let arr = |v: lie::V3<N>| N::vec3_to_array(v);
    let mut worst = [0.0f64; 6];
    let mut scale = [0.0f64; 6];
    for k in 0..n.max(1) {
        let t = t0 + (t1 - t0) * k as f64 / (n.max(2) - 1) as f64;
        let (a, b, c) = (
            source.position(t - h),
            source.position(t),
            source.position(t + h),
        );
        let pairs = [
            (arr(a.x), arr(c.x), arr(b.v)),
            (arr(a.v), arr(c.v), arr(b.a)),
            (arr(a.a), arr(c.a), arr(b.jerk)),
            (arr(a.jerk), arr(c.jerk), arr(b.snap)),
            (arr(a.b1d), arr(c.b1d), arr(b.b1d_dot)),
            (arr(a.b1d_dot), arr(c.b1d_dot), arr(b.b1d_ddot)),
        ];
        for (i, (lo, hi, d)) in pairs.iter().enumerate() {
            for j in 0..3 {
                let fd = (hi[j] - lo[j]) / (2.0 * h);
                worst[i] = worst[i].max((fd - d[j]).abs());
                scale[i] = scale[i].max(d[j].abs());
            }
        }
    }
    [0, 1, 2, 3, 4, 5].map(|i| worst[i] / (1.0 + scale[i]))
}
