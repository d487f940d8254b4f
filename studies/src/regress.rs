//! The regression suite: every built-in scene against expectations
//! computed independently of the code under test — a tighter
//! integrator (Dormand–Prince at tol 1e-12), closed forms (the no-integral
//! steady state, Ψ of a known rotation, the disturbance-learning fixed
//! point), an algebraic equilibrium solve, and conservation laws. Each row
//! carries its tolerance and the reason for it.

#![allow(clippy::needless_range_loop)] // index notation mirrors the component formulas

use crate::metrics::norm;
use crate::metrics::{Difference, at, max_difference, max_ex_after, max_psi_after, nan_max};
use scenarios::{RunOptions, RunOutput, SimError};
use scenes::Error;
use scenes::reference::rotation_f64;
use scenes::{Scene, builtin};

/// One figure of a scene against its expectation.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// The scene (and variant) it is about.
    pub scene: String,
    /// What is measured.
    pub metric: String,
    /// The measured value.
    pub value: f64,
    /// The expectation (two-sided checks).
    pub expected: f64,
    /// The tolerance, or the bound of a one-sided check.
    pub tol: f64,
    /// `true`: |value − expected| ≤ tol; `false`: value ≤ tol (a bound).
    pub two_sided: bool,
    /// Why the tolerance is that size.
    pub why: &'static str,
}

/// Why a suite (this one, [`crate::stress`]) could not measure something.
#[derive(Debug)]
pub enum SuiteError {
    /// A scene did not run.
    Run {
        /// The scene.
        scene: String,
        /// Its error.
        source: Error,
    },
    /// A sample the check reads was not recorded.
    Missing {
        /// The scene.
        scene: String,
        /// What was missing.
        what: &'static str,
    },
    /// A file the suite writes could not be written.
    Output(logs::OutputError),
    /// A file the suite wrote could not be read back.
    Read {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

impl std::fmt::Display for SuiteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SuiteError::Run { scene, source } => write!(f, "{scene}: {source}"),
            SuiteError::Missing { scene, what } => write!(f, "{scene}: {what}"),
            SuiteError::Output(e) => write!(f, "{e}"),
            SuiteError::Read { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for SuiteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SuiteError::Run { source, .. } => Some(source),
            SuiteError::Missing { .. } => None,
            SuiteError::Output(e) => Some(e),
            SuiteError::Read { source, .. } => Some(source.as_ref()),
        }
    }
}

impl Check {
    /// Whether it holds.
    pub fn ok(&self) -> bool {
        if self.two_sided {
            (self.value - self.expected).abs() <= self.tol
        } else {
            self.value <= self.tol
        }
    }
}

/// The checks so far, and what sees each scene's main run.
struct Table<'a>(Vec<Check>, &'a mut dyn FnMut(&Scene, &RunOutput));

impl Table<'_> {
    fn close(
        &mut self,
        scene: &str,
        metric: &str,
        value: f64,
        expected: f64,
        tol: f64,
        why: &'static str,
    ) {
        self.0.push(Check {
            scene: scene.into(),
            metric: metric.into(),
            value,
            expected,
            tol,
            two_sided: true,
            why,
        });
    }
    fn below(&mut self, scene: &str, metric: &str, value: f64, bound: f64, why: &'static str) {
        self.0.push(Check {
            scene: scene.into(),
            metric: metric.into(),
            value,
            expected: 0.0,
            tol: bound,
            two_sided: false,
            why,
        });
    }
}

fn run(scene: &Scene) -> Result<RunOutput, SuiteError> {
    scenes::run(scene, RunOptions::default()).map_err(|source| SuiteError::Run {
        scene: scene.name.clone(),
        source,
    })
}

fn missing(scene: &Scene, what: &'static str) -> SuiteError {
    SuiteError::Missing {
        scene: scene.name.clone(),
        what,
    }
}

fn dopri(scene: &Scene) -> Result<RunOutput, SuiteError> {
    let mut s = scene.clone();
    s.integrator.kind = "dopri".into();
    s.integrator.tol = 1e-12;
    s.integrator.dt = s.record.sample;
    run(&s)
}

fn mat_mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// Static equilibrium of the position loop without integral terms under
/// Δ_x, Δ_R, solved algebraically (Newton on x, finite-difference
/// Jacobian): at rest, k_R e_R = Δ_R gives R = R_c exp(asin|δ| δ̂), δ =
/// Δ_R/k_R, and the force balance m g e3 − f R e3 + Δ_x = 0 with
/// f = −A·R e3, A = −k_x x − m g e3, R_c from b3c = −A/|A| and b1d.
fn no_integral_equilibrium(scene: &Scene, b1d: [f64; 3]) -> [f64; 3] {
    let (m, g) = (scene.vehicle.mass, scene.vehicle.gravity);
    let d = scene.disturbance.clone().expect("scene has disturbances");
    let kr = scene.gains.k_r;
    let delta = d.moment.map(|c| c / kr);
    let th = norm(delta).asin();
    let e = rotation_f64(delta.map(|c| c / norm(delta) * th));
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let residual = |x: [f64; 3]| {
        let a = [
            -scene.gains.k_x * x[0],
            -scene.gains.k_x * x[1],
            -scene.gains.k_x * x[2] - m * g,
        ];
        let na = norm(a);
        let b3 = a.map(|c| -c / na);
        let b2u = cross(b3, b1d);
        let b2 = b2u.map(|c| c / norm(b2u));
        let b1 = cross(b2, b3);
        let rc = [
            [b1[0], b2[0], b3[0]],
            [b1[1], b2[1], b3[1]],
            [b1[2], b2[2], b3[2]],
        ];
        let r = mat_mul(rc, e);
        let re3 = [r[0][2], r[1][2], r[2][2]];
        let f = -(a[0] * re3[0] + a[1] * re3[1] + a[2] * re3[2]);
        [0, 1, 2].map(|k| if k == 2 { m * g } else { 0.0 } - f * re3[k] + d.force[k])
    };
    let mut x = d.force.map(|c| c / scene.gains.k_x);
    for _ in 0..50 {
        let r0 = residual(x);
        if norm(r0) < 1e-14 {
            break;
        }
        let h = 1e-7;
        let mut jac = [[0.0; 3]; 3];
        for j in 0..3 {
            let mut xp = x;
            xp[j] += h;
            let rp = residual(xp);
            for i in 0..3 {
                jac[i][j] = (rp[i] - r0[i]) / h;
            }
        }
        // Cramer's rule for the 3×3 Newton step.
        let det = |m: [[f64; 3]; 3]| {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        };
        let dj = det(jac);
        for k in 0..3 {
            let mut mk = jac;
            for i in 0..3 {
                mk[i][k] = r0[i];
            }
            x[k] -= det(mk) / dj;
        }
    }
    x
}

fn paper_flip(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::paper_flip();
    let n = s.name.clone();
    let def = run(&s)?;
    (t.1)(&s, &def);
    let reference = dopri(&s)?;
    let mut fine = s.clone();
    fine.integrator.dt = 1e-4;
    let fine = run(&fine)?;
    let Difference {
        x: dx,
        v: dv,
        r: dr,
        compared: cnt,
    } = max_difference(&fine.samples, &reference.samples);
    const WHY_FINE: &str = "with the sat′ events located (and the branch forced on each side) both are smooth per piece; measured Δx 1.0e-12, Δv 3.8e-12, ΔR 1.4e-12, bound ~50×; stepping across the jumps instead leaves 3e-7";
    t.below(
        &n,
        &format!("rk4 h=1e-4 vs dopri 1e-12: max|Δx| ({cnt} samples)"),
        dx,
        5e-11,
        WHY_FINE,
    );
    t.below(
        &n,
        "rk4 h=1e-4 vs dopri 1e-12: max|Δv|",
        dv,
        2e-10,
        WHY_FINE,
    );
    t.below(
        &n,
        "rk4 h=1e-4 vs dopri 1e-12: max|ΔR|",
        dr,
        1e-10,
        WHY_FINE,
    );
    let mut blind = s.clone();
    blind.integrator.dt = 1e-4;
    blind.integrator.locate_events = false;
    let blind = run(&blind)?;
    let Difference { r: dr_blind, .. } = max_difference(&blind.samples, &reference.samples);
    t.close(&n, &format!("log10 max|ΔR| without event location (max|ΔR| = {dr_blind:.1e})"), dr_blind.log10().round(), -6.0, 1.0, "stepping across the sat′ jump at h = 1e-4 limits the agreement to ~1e-5…1e-6 (order of magnitude checked)");
    let Difference { x: dx, r: dr, .. } = max_difference(&def.samples, &reference.samples);
    const WHY_DEF: &str = "default step 5e-4: rk4 error (5e-4/1e-4)⁴ = 625× the fine run's; measured Δx 1.8e-10, ΔR 1.3e-10, bound ~60×";
    t.below(
        &n,
        "default rk4 h=5e-4 vs dopri: max|Δx|",
        dx,
        1e-8,
        WHY_DEF,
    );
    t.below(
        &n,
        "default rk4 h=5e-4 vs dopri: max|ΔR|",
        dr,
        1e-8,
        WHY_DEF,
    );
    for tt in [1.0, 2.0, 4.0] {
        let (a, b) = (at(&def.samples, tt), at(&reference.samples, tt));
        let (a, b) = (
            a.ok_or_else(|| missing(&s, "a sample at 1, 2 or 4 s"))?,
            b.ok_or_else(|| missing(&s, "a reference sample at 1, 2 or 4 s"))?,
        );
        t.close(
            &n,
            &format!("Ψ({tt}) vs dopri"),
            a.psi,
            b.psi,
            1e-9,
            "|ΔΨ| ≤ ‖ΔR‖ and the default run is within 1.3e-10 in R (measured |ΔΨ| ≤ 1.3e-11)",
        );
        t.close(
            &n,
            &format!("‖e_x‖({tt}) vs dopri"),
            a.ex,
            b.ex,
            1e-8,
            "|Δ‖e_x‖| ≤ |Δx| (1.8e-10; measured ≤ 1.7e-10)",
        );
    }
    t.close(
        &n,
        "switch time",
        def.switches.first().map_or(f64::NAN, |s| s.t),
        0.4,
        0.0,
        "the run lands exactly on the switch at 0.4 s (a time switch is a checkpoint)",
    );
    t.close(
        &n,
        "switches",
        def.switches.len() as f64,
        1.0,
        0.0,
        "one attitude→position switch",
    );
    let at_switch = at(&def.samples, 0.4).ok_or_else(|| missing(&s, "a sample at 0.4 s"))?;
    t.close(
        &n,
        "‖e_i‖ at the switch",
        norm(at_switch.e_pos),
        0.0,
        0.0,
        "e_i starts at zero on entering position mode (PositionMode::enter)",
    );
    t.below(
        &n,
        "located sat′ events (count, ≥ 1 expected)",
        -(def.events as f64),
        -1.0,
        "e_i crosses ±σ after the flip; the run must have located it",
    );
    Ok(())
}

/// Sampled control (zero-order hold) against continuous control on the
/// flip: the hold delays the command by half a period on average, so the
/// deviation is first order in the period — halving it halves the gap.
fn sampled(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let base = builtin::paper_flip();
    let n = format!("{} (sampled)", base.name);
    let cont = run(&base)?;
    let gap = |rate: f64| -> Result<f64, SuiteError> {
        let mut s = base.clone();
        s.control.timing = scenes::scene::Timing::Sampled;
        s.control.rate = rate;
        let out = run(&s)?;
        let Difference { x: dx, r: dr, .. } = max_difference(&out.samples, &cont.samples);
        Ok(dx.max(dr))
    };
    let (g1, g2) = (gap(1000.0)?, gap(2000.0)?);
    t.close(&n, &format!("gap(1 kHz)/gap(2 kHz) (gaps {g1:.2e}, {g2:.2e})"), g1 / g2, 2.0, 2e-3, "ZOH is a first-order perturbation of the continuous loop; the O(T²) remainder measured 3.2e-5, bound ~60× (a second-order gap would give 4)");
    Ok(())
}

fn no_integral(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::paper_flip_no_integral();
    let n = s.name.clone();
    let def = run(&s)?;
    (t.1)(&s, &def);
    let reference = dopri(&s)?;
    let Difference { x: dx, r: dr, .. } = max_difference(&def.samples, &reference.samples);
    let why = "default rk4 h = 5e-4 against dopri 1e-12, events located in both; same budget as paper-flip (measured Δx 1.9e-10, ΔR 1.4e-10)";
    t.below(&n, "rk4 vs dopri: max|Δx|", dx, 1e-8, why);
    t.below(&n, "rk4 vs dopri: max|ΔR|", dr, 1e-8, why);
    // The closed-form steady state needs an unbiased Ω_c model. With Δ_x ≠ 0
    // and no integral, the nominal model predicts −Δ_x/m at rest, so the
    // paper's scene settles elsewhere; remove Δ_x (keep
    // Δ_R) and the static balance must hold exactly.
    let mut v = s.clone();
    v.name = format!("{n} (Δ_x = 0)");
    v.duration = 20.0;
    v.record.sample = 0.01;
    if let Some(d) = v.disturbance.as_mut() {
        d.force = [0.0; 3];
    }
    let out = run(&v)?;
    let last = &out.last;
    let d = v.disturbance.clone().unwrap();
    let k = norm(d.moment) / v.gains.k_r;
    let psi_ss = 1.0 - (1.0 - k * k).sqrt();
    let why = "closed form / static balance; the slowest PD pole (≈ −2.8 s⁻¹) leaves e^(−2.8·16) ≈ 1e-19 of the transient at 20 s; measured |ΔΨ| 4e-12, |Δx| 9.5e-11 (the default step's error), bounds 50×";
    t.close(
        &v.name,
        "Ψ(20 s) vs 1 − √(1 − ‖Δ_R‖²/k_R²)",
        last.psi,
        psi_ss,
        2e-10,
        why,
    );
    let x_eq = no_integral_equilibrium(&v, [0.0, 1.0, 0.0]);
    let dx = norm([
        last.x[0] - x_eq[0],
        last.x[1] - x_eq[1],
        last.x[2] - x_eq[2],
    ]);
    t.below(
        &v.name,
        "|x(20 s) − x_eq| (algebraic equilibrium)",
        dx,
        5e-9,
        why,
    );
    Ok(())
}

/// Slowest root of the linearised attitude PID per axis,
/// `J s³ + k_Ω s² + (k_R + k_I) s + k_I c2 = 0`, by Newton from the
/// small-J approximation `−k_I c2/(k_R + k_I)`.
fn slow_attitude_root(j: f64, g: &scenes::scene::GainsSpec) -> f64 {
    let (a, b, c, d) = (j, g.k_omega, g.k_r + g.k_att_i, g.k_att_i * g.c2);
    let mut s = -d / c;
    for _ in 0..50 {
        let f = ((a * s + b) * s + c) * s + d;
        let df = (3.0 * a * s + 2.0 * b) * s + c;
        s -= f / df;
    }
    s
}

fn attitude_experiment(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::paper_attitude_experiment();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let psi0 = 1.0 - (std::f64::consts::PI / 9.0).cos();
    t.close(
        &n,
        "Ψ(0) vs 1 − cos(π/9)",
        out.samples[0].psi,
        psi0,
        1e-15,
        "R(0) = I, R_d(0) = R_y(π/9): closed form, rounding only",
    );
    let reference = dopri(&s)?;
    let Difference { r: dr, .. } = max_difference(&out.samples, &reference.samples);
    t.below(
        &n,
        "rk4 h=1e-3 vs dopri 1e-12: max|ΔR|",
        dr,
        1e-8,
        "smooth reference, rk4 O(h⁴): measured 1.1e-10, bound ~90×",
    );
    t.below(
        &n,
        "translation integrated (‖x‖ max)",
        out.samples.iter().map(|s| norm(s.x)).fold(0.0, nan_max),
        0.0,
        "pinned vehicle: x stays exactly 0",
    );
    Ok(())
}

/// On the stand, exact compensation of the gravity moment turns the loop
/// into the pinned vehicle's with the pivot inertia J + m l² diag(1, 1, 0)
/// (computed here, independently of `AttitudeStand`).
fn attitude_stand(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::paper_attitude_stand();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let mut pinned = builtin::paper_attitude_experiment();
    let (m, l) = (s.vehicle.mass, s.vehicle.stand_height);
    pinned.vehicle.inertia = [
        s.vehicle.inertia[0] + m * l * l,
        s.vehicle.inertia[1] + m * l * l,
        s.vehicle.inertia[2],
    ];
    let twin = run(&pinned)?;
    let Difference { r: dr, .. } = max_difference(&out.samples, &twin.samples);
    t.below(&n, "compensated stand vs pinned body with pivot inertia: max|ΔR|", dr, 3e-14, "−M_g + M_g cancels to rounding; the remaining loop is the pinned one (parallel-axis inertia); measured 2.8e-16, bound ~100×");
    let mut bare = s.clone();
    bare.control.compensate_configuration_moment = false;
    let bare = run(&bare)?;
    let ratio = max_psi_after(&out.samples, 5.0) / max_psi_after(&bare.samples, 5.0);
    t.below(&n, "max Ψ(5–10 s) compensated / uncompensated", ratio, 0.5, "why the paper adds the term: uncompensated, the gravity moment (m g l sin tilt ≈ 0.13 N m at 20°) rivals Δ_R and the integral needs τ = 14.6 s to learn it");
    Ok(())
}

fn large_attitude(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::large_attitude_error();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let psi0 = 1.0 - 170f64.to_radians().cos();
    t.close(
        &n,
        "Ψ(0) vs 1 − cos 170°",
        out.samples[0].psi,
        psi0,
        1e-14,
        "closed form",
    );
    let first_below_1 = out
        .samples
        .iter()
        .find(|s| s.psi < 1.0)
        .map_or(f64::INFINITY, |s| s.t);
    t.below(&n, "first t with Ψ < 1 (s)", first_below_1, 3.0, "Prop. 3: from Ψ(0) < 2 the error decays; the PD poles (≈ −13 s⁻¹) bring Ψ under 1 within about a second");
    // After the fast PD modes die out only the integral mode remains, so Ψ
    // (quadratic in the error) decays like e^(2λt) with λ the slowest root
    // of the linearised loop (the rotation axis lies in the b1–b2 plane,
    // J1 = J2).
    let lam = slow_attitude_root(s.vehicle.inertia[0], &s.gains);
    let (p10, p20) = (
        at(&out.samples, 10.0)
            .ok_or_else(|| missing(&s, "a sample at 10 s"))?
            .psi,
        at(&out.samples, 20.0)
            .ok_or_else(|| missing(&s, "a sample at 20 s"))?
            .psi,
    );
    t.close(
        &n,
        "Ψ(20)/Ψ(10) vs e^(2λ·10), λ slowest linear root",
        p20 / p10,
        (2.0 * lam * 10.0).exp(),
        0.03 * (2.0 * lam * 10.0).exp(),
        "linearisation; 3 % covers the O(θ²) nonlinearity at Ψ ≈ 1e-2 (θ ≈ 0.15 rad)",
    );
    Ok(())
}

/// The Ψ-triggered switch is located to rounding and independently of the
/// stepper: rk4 and dopri 1e-12 switch at the same instant, with Ψ at the
/// threshold.
fn tumble(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::tumble_recovery();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let reference = dopri(&s)?;
    let (ta, tb) = (
        out.switches.first().map_or(f64::NAN, |w| w.t),
        reference.switches.first().map_or(f64::NAN, |w| w.t),
    );
    t.close(
        &n,
        "Ψ switch time, rk4 h=5e-4 vs dopri 1e-12",
        ta,
        tb,
        1e-8,
        "same located crossing up to the integrators' difference (~1e-10 in the state, Ψ̇ = O(1))",
    );
    let Difference { x: dx, r: dr, .. } = max_difference(&out.samples, &reference.samples);
    t.below(
        &n,
        "rk4 vs dopri: max(|Δx|, |ΔR|) after the switch",
        dx.max(dr),
        1e-8,
        "as paper-flip: events and switches located in both (measured 1.7e-10, bound ~60×)",
    );
    let mut clamped = s.clone();
    clamped.gains.clamp_integral = true;
    let clamped = run(&clamped)?;
    t.below(&n, "‖e_x‖(10 s) with clamped anti-windup / without", clamped.last.ex / out.last.ex, 0.5, "clamping stops e_i winding up during the fall, so the return is faster (qualitative; measured ratio in the value)");
    t.below(&n, "‖e_x‖ at 10 s (m)", out.last.ex, 0.3, "no closed form: the vehicle falls while upside down and e_i winds up (no anti-windup in the paper's law), so the return is slow; measured 0.22 m, a regression guard");
    Ok(())
}

fn free_body(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::free_rigid_body();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let energy = |x: &scenarios::Sample| {
        0.5 * (0..3)
            .map(|k| s.vehicle.inertia[k] * x.omega[k] * x.omega[k])
            .sum::<f64>()
    };
    let e0 = energy(&out.samples[0]);
    let drift = out
        .samples
        .iter()
        .map(|x| ((energy(x) - e0) / e0).abs())
        .fold(0.0, nan_max);
    t.below(
        &n,
        "lgvi max |ΔE/E| over 100 s (10⁴ steps)",
        drift,
        1e-12,
        "Moser–Veselov conserves E exactly; rounding floor measured 2e-14 per 1e5 steps",
    );
    let exact = dynamics::free_body::ExactFreeBody::new(
        s.vehicle.inertia,
        s.initial.omega,
        rotation_f64(s.initial.rotation),
    )
    .map_err(|e| SuiteError::Run {
        scene: s.name.clone(),
        source: Error::Run(SimError::Vehicle(e)),
    })?;
    let reference = dopri(&s)?;
    let l = &reference.last;
    let r_ex = exact.attitude(s.duration);
    let w_ex = exact.omega(s.duration);
    let mut err: f64 = 0.0;
    for i in 0..3 {
        err = err.max((l.omega[i] - w_ex[i]).abs());
        for j in 0..3 {
            err = err.max((l.r[i][j] - r_ex[i][j]).abs());
        }
    }
    t.below(&n, "dopri 1e-12 vs exact solution at 100 s", err, 1e-9, "global error of a tol-1e-12 run grows ~linearly: 1.2e-11 at 10 s measured, ×10 time ×~8 margin");
    Ok(())
}

fn hover(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::hover_disturbed();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let d = s.disturbance.clone().unwrap();
    let l = &out.last;
    let rel = |a: [f64; 3], b: [f64; 3]| norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]) / norm(b);
    let why = "fixed point k_i e_i = Δ_x, k_I e_I = Δ_R (controllers tests); the slowest mode (τ = 14.6 s, gain report) leaves at most e^(−150/14.6) ≈ 3.4e-5 of the initial error at 150 s, ×3 margin";
    t.below(
        &n,
        "‖e_i − Δ_x/k_i‖/‖Δ_x/k_i‖ at 150 s",
        rel(l.e_pos, d.force.map(|c| c / s.gains.k_i)),
        5e-7,
        "fixed point k_i e_i = Δ_x; the position integral settles with the position loop (τ = 2.7 s) and the slow attitude mode hardly reaches it: measured 6.9e-9, bound ~70×",
    );
    t.below(
        &n,
        "‖e_I − Δ_R/k_I‖/‖Δ_R/k_I‖ at 150 s",
        rel(l.e_att, d.moment.map(|c| c / s.gains.k_att_i)),
        1e-4,
        why,
    );
    t.below(
        &n,
        "‖e_x‖ at 150 s (m)",
        l.ex,
        5e-13,
        "with the Nominal model's disturbance estimate the position loop has no bias; measured 8.1e-15, bound ~60× (a lost estimate leaves 1e-2 m)",
    );
    Ok(())
}

fn figure_eight(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::figure_eight();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let reference = dopri(&s)?;
    let Difference {
        x: dx,
        v: dv,
        r: dr,
        ..
    } = max_difference(&out.samples, &reference.samples);
    let why = "rk4 at 1e-3 vs dopri 1e-12 with located events: measured Δx 4.1e-10, Δv 9.0e-10, ΔR 4.2e-10, bounds ~70×";
    t.below(&n, "rk4 vs dopri: max|Δx|", dx, 3e-8, why);
    t.below(&n, "rk4 vs dopri: max|Δv|", dv, 6e-8, why);
    t.below(&n, "rk4 vs dopri: max|ΔR|", dr, 3e-8, why);
    t.below(&n, "max ‖e_x‖ over 15–20 s (m)", max_ex_after(&out.samples, 15.0), 5e-3, "no closed form for the tracking error of a moving reference; measured 8.8e-4 m, bound ×5 to catch a regression of the feed-forward (exact Ω_c, Ω̇_c) without tripping on integrator changes");
    Ok(())
}

/// The wind scenes: the Dryden field is a function of seed and time, so
/// two steppers see the same gusts and must agree; and the integral terms
/// must pay in a mean wind.
fn wind(t: &mut Table<'_>) -> Result<(), SuiteError> {
    let s = builtin::gusty_hover();
    let n = s.name.clone();
    let out = run(&s)?;
    (t.1)(&s, &out);
    let reference = dopri(&s)?;
    let Difference { x: dx, r: dr, .. } = max_difference(&out.samples, &reference.samples);
    t.below(&n, "rk4 h=1e-3 vs dopri 1e-12: max(|Δx|, |ΔR|)", dx.max(dr), 1e-7, "both steppers sample the same continuous gust field (noise on a fixed 5 ms grid, filters solved exactly between); a field that depended on the steps would differ by the gusts' size, 1e-2 m");
    let s = builtin::figure_eight_wind();
    let n = s.name.clone();
    let on = run(&s)?;
    (t.1)(&s, &on);
    let mut off = s.clone();
    off.gains.k_i = 0.0;
    off.gains.k_att_i = 0.0;
    let off = run(&off)?;
    let rms = |o: &RunOutput| {
        let tail: Vec<f64> = o
            .samples
            .iter()
            .filter(|x| x.t >= 2.0)
            .map(|x| x.ex)
            .collect();
        (tail.iter().map(|e| e * e).sum::<f64>() / tail.len().max(1) as f64).sqrt()
    };
    t.below(&n, "RMS ‖e_x‖ after 2 s, with integral terms / without", rms(&on) / rms(&off), 0.7, "in a 3 m/s mean wind the integral terms learn the mean drag that the PD terms leave as an offset (measured 0.49; qualitative, no closed form)");
    Ok(())
}

/// Every check (`quick`: all scenes but the two long ones, what CI runs);
/// `on_run` sees each scene's main run (to log it, say).
pub fn checks(
    quick: bool,
    on_run: &mut dyn FnMut(&Scene, &RunOutput),
) -> Result<Vec<Check>, SuiteError> {
    let mut t = Table(Vec::new(), on_run);
    paper_flip(&mut t)?;
    sampled(&mut t)?;
    no_integral(&mut t)?;
    attitude_experiment(&mut t)?;
    attitude_stand(&mut t)?;
    large_attitude(&mut t)?;
    tumble(&mut t)?;
    free_body(&mut t)?;
    wind(&mut t)?;
    if !quick {
        hover(&mut t)?;
        figure_eight(&mut t)?;
    }
    Ok(t.0)
}
