//! The conditions of Propositions 2 and 3 for a scene's gains, with the
//! bounds taken from the scene ([`scene_bounds`], [`report`]), and a search
//! for gains that provably meet them ([`synthesize`]).
//!
//! # Bounds from the scene
//! Sampled every `min(T/20000, 1 ms)` over the scene's duration `T`:
//! - `B1 = max_t ‖−m g e3 + m ẍ_d(t)‖` over the position-mode segments
//!   (eqn:B; `m g` when there are none). The paper asks for `B1 >` this
//!   supremum; the report uses the supremum itself, so a condition holding
//!   by a positive margin also holds for a `B1` just above it.
//! - `B2 = ‖2J − tr(J) I‖₂ · max_t ‖Ω_d(t)‖` (eqn:B_2), with `Ω_d` the
//!   attitude reference's angular velocity in attitude-mode segments and,
//!   in position-mode segments, `Ω_c` along the nominal trajectory (the
//!   state on the reference: `x = x_d`, `v = ẋ_d`, `R = R_c`, `e_i = 0`,
//!   where the controller's `Ω_c` is exact).
//! - `δ_x = ‖Δ_x‖∞` of the scene's disturbance (0 without one).
//! - `ψ1` and `e_xmax`
//!   bound the initial errors the guarantee covers; they are choices, not
//!   properties of the scene.
//!
//! # Synthesis
//! Scalar gains `(k_x, k_v, k_i, k_R, k_Ω, k_I, c1, c2, σ)` (the scene
//! format's), searched in log space by Nelder–Mead with restarts. Every
//! condition is scored by its margin relative to its bound (so that
//! conditions in different units compare); the score of a gain set is the
//! worst of the four. Phase 1 maximises the score with the scene's peak
//! rotor thrust (simulated with those gains) held under the limit (by
//! default the peak of the scene with its own gains). If the best score is positive,
//! phase 2 minimises the slowest linearised time constant keeping the score
//! positive and the peak under the limit. If it is not, no gains were found
//! that meet every condition within the limit: the report names the
//! binding condition and the best margin, and the same search without the
//! thrust limit shows what meeting them would take.

use controllers::{
    AccelerationModel, AttitudeGains, GainBounds, GainReport, PositionGains, RigidBodyParams,
    VehicleState, check_gains, position_control,
};
use lie::{NalgebraF64 as B, So3Mat};
use scenes::Error;

use crate::metrics::norm;
use scenarios::{RunOptions, RunOutput, SimError};
use scenes::Scene;
use scenes::scene::{GainsSpec, ModeKind};

/// The bounds of the conditions, derived from a scene.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SceneBounds {
    /// What the checker takes.
    pub bounds: GainBounds,
    /// `max_t ‖Ω_d‖` (rad/s).
    pub max_omega_d: f64,
    /// `‖2J − tr(J) I‖₂` (kg m²).
    pub j_norm: f64,
    /// Sample times used.
    pub samples: usize,
}

/// What a run of `scene` gives its controller, so that the conditions are
/// checked on the numbers that fly.
fn params(scene: &Scene) -> Result<RigidBodyParams<B>, Error> {
    let v = scenes::build_vehicle::<B>(scene)?;
    Ok(scenes::controller_params(
        scene,
        v.as_ref(),
        scenes::Seeds::NONE,
    ))
}

fn gains_of(g: &GainsSpec) -> (PositionGains<B>, AttitudeGains<B>) {
    let (pg, ag, _) = scenes::controller_gains::<B>(g, scenes::Seeds::NONE);
    (pg, ag)
}

/// B1, B2, δ_x of `scene` (module docs).
pub fn scene_bounds(scene: &Scene, psi1: f64, ex_max: f64) -> Result<SceneBounds, Error> {
    let p = params(scene)?;
    let (pg, ag) = gains_of(&scene.gains);
    let (m, g) = (scene.vehicle.mass, scene.vehicle.gravity);
    let j = lie::ops::elems::<B>(p.inertia);
    let tr = j[0][0] + j[1][1] + j[2][2];
    if (0..3).any(|i| (0..3).any(|k| i != k && j[i][k] != 0.0)) {
        return Err(Error::Scene(scenes::SceneError::at_key(
            "vehicle.inertia",
            "the inertia is not diagonal; B2 needs its principal form".into(),
        )));
    }
    let j_norm = (0..3)
        .map(|i| (2.0 * j[i][i] - tr).abs())
        .fold(0.0, f64::max);
    // Step min(T/20000, 1 ms): n intervals, n + 1 samples.
    let n = 1 + ((scene.duration / 1e-3).ceil() as usize).max(20_000);
    let (mut b1, mut w_max) = (0.0f64, 0.0f64);
    let mut any_position = false;
    // Which segment is active at t: time switches only (a Ψ-triggered
    // switch's time depends on the flight; every segment is then sampled
    // over the whole duration, which can only make the bounds larger).
    let seg_at = |t: f64| -> Vec<usize> {
        if scene
            .plan
            .iter()
            .any(|s| s.until_psi.is_some() || s.until_clearance.is_some())
        {
            return (0..scene.plan.len()).collect();
        }
        let k = scene
            .plan
            .iter()
            .position(|s| s.until.is_none_or(|u| t < u))
            .unwrap_or(scene.plan.len().saturating_sub(1));
        vec![k]
    };
    for i in 0..n {
        let t = scene.duration * i as f64 / (n - 1) as f64;
        for k in seg_at(t) {
            let Some(seg) = scene.plan.get(k) else {
                continue;
            };
            match seg.mode {
                ModeKind::Attitude => {
                    if let Some(a) = &seg.attitude {
                        let (_, w, _) = scenes::reference::attitude_f64(a, t);
                        w_max = w_max.max(norm(w));
                    }
                }
                ModeKind::TakeOff | ModeKind::Hover | ModeKind::Land => {
                    any_position = true;
                    // A vertical move's acceleration does not depend on
                    // where it starts: its profile sampled from t = 0
                    // covers every start.
                    if let Some(vert) = seg.vertical::<B>() {
                        let a = vert.offset(t)[2];
                        b1 = b1.max((m * a - m * g).abs());
                    }
                }
                ModeKind::MotorsOff => {}
                ModeKind::Position => {
                    any_position = true;
                    let Some(pr) = &seg.position else { continue };
                    let r = scenes::reference::position::<B>(pr, t);
                    let a = B::vec3_to_array(r.a);
                    b1 = b1.max(norm([m * a[0], m * a[1], m * a[2] - m * g]));
                    // Ω_c on the nominal trajectory: R_c does not depend on
                    // R, so the first call gives R_c, the second the exact
                    // Ω_c with R = R_c.
                    let command = |r_now: So3Mat<B>| {
                        let st = VehicleState {
                            x: r.x,
                            v: r.v,
                            r: r_now,
                            omega: B::vec3(0.0, 0.0, 0.0),
                        };
                        let z = B::vec3(0.0, 0.0, 0.0);
                        let input = controllers::PositionInput {
                            state: &st,
                            e_i_pos: z,
                            e_i_att: z,
                            reference: &r,
                            model: AccelerationModel::Nominal,
                        };
                        position_control(&p, &pg, &ag, &input)
                            .map_err(|source| SimError::Control { t, source })
                    };
                    let first = command(So3Mat::<B>::identity())?;
                    let out = command(first.rc)?;
                    w_max = w_max.max(norm(B::vec3_to_array(out.omega_c)));
                }
            }
        }
    }
    if !any_position {
        b1 = m * g;
    }
    let delta_x = scene
        .disturbance
        .as_ref()
        .map_or(0.0, |d| d.force.iter().fold(0.0f64, |a, c| a.max(c.abs())));
    Ok(SceneBounds {
        bounds: GainBounds {
            b1,
            b2: j_norm * w_max,
            delta_x,
            psi1,
            e_x_max: ex_max,
        },
        max_omega_d: w_max,
        j_norm,
        samples: n,
    })
}

/// The checker on `scene`'s vehicle with gains `g`.
pub fn report(scene: &Scene, g: &GainsSpec, b: &GainBounds) -> Result<GainReport, Error> {
    let (pg, ag) = gains_of(g);
    Ok(check_gains(&params(scene)?, &pg, &ag, b))
}

// ---------------------------------------------------------------- synthesis

/// The log margin the search aims for (5 %: a certified set with room to
/// spare, not one on the boundary).
pub const MARGIN: f64 = 0.05;

/// The gains searched, in the order of the search vector.
pub const NAMES: [&str; 9] = [
    "k_x", "k_v", "k_i", "k_r", "k_omega", "k_att_i", "c1", "c2", "sigma",
];

fn to_vec(g: &GainsSpec) -> [f64; 9] {
    [
        g.k_x, g.k_v, g.k_i, g.k_r, g.k_omega, g.k_att_i, g.c1, g.c2, g.sigma,
    ]
    .map(|x| x.max(1e-6).ln())
}

fn from_vec(base: &GainsSpec, p: &[f64; 9]) -> GainsSpec {
    let e = p.map(f64::exp);
    GainsSpec {
        k_x: e[0],
        k_v: e[1],
        k_i: e[2],
        k_r: e[3],
        k_omega: e[4],
        k_att_i: e[5],
        c1: e[6],
        c2: e[7],
        sigma: e[8],
        ..base.clone()
    }
}

/// The scene flown with `g`: peak rotor thrust and the run (None when it
/// diverges). The step shrinks with the attitude gains so that RK4 stays
/// stable (|λ| h ≲ 1 for the fastest linear mode, k_Ω/λm(J)).
pub fn fly(scene: &Scene, g: &GainsSpec) -> Option<(f64, RunOutput)> {
    let mut s = scene.clone();
    s.gains = g.clone();
    let jmin = s
        .vehicle
        .inertia
        .iter()
        .fold(f64::INFINITY, |a, &b| a.min(b));
    let fast = g.k_omega / jmin + g.k_v / s.vehicle.mass + (g.k_r / jmin).sqrt();
    s.integrator.dt = s.integrator.dt.min(0.5 / fast);
    // Gains that need a step below 1 µs (10⁶ steps a second of flight)
    // are far beyond any actuator anyway; they are not flown.
    if s.integrator.dt < 1e-6 {
        return None;
    }
    let out = scenes::run(&s, RunOptions::default()).ok()?;
    out.last.psi.is_finite().then_some((out.max_rotor, out))
}

/// Minimises `f` from `x0` by Nelder–Mead (standard coefficients), with a
/// restart from the best point when the simplex collapses; at most `budget`
/// evaluations.
pub fn nelder_mead(
    f: &mut dyn FnMut(&[f64; 9]) -> f64,
    x0: [f64; 9],
    budget: usize,
) -> ([f64; 9], f64) {
    let mut evals = 0usize;
    let mut best = (x0, f64::INFINITY);
    let mut start = x0;
    let mut scale = 0.5;
    while evals < budget {
        let mut simplex: Vec<([f64; 9], f64)> = Vec::with_capacity(10);
        for k in 0..10 {
            let mut x = start;
            if k > 0 {
                x[k - 1] += scale;
            }
            let v = f(&x);
            evals += 1;
            simplex.push((x, v));
        }
        loop {
            simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
            if simplex[0].1 < best.1 {
                best = simplex[0];
            }
            let spread = simplex[9].1 - simplex[0].1;
            let size = (1..10)
                .map(|k| {
                    (0..9)
                        .map(|i| (simplex[k].0[i] - simplex[0].0[i]).abs())
                        .fold(0.0, f64::max)
                })
                .fold(0.0, f64::max);
            if evals >= budget || (spread.abs() < 1e-10 && size < 1e-6) || size < 1e-7 {
                break;
            }
            let mut c = [0.0; 9];
            for (x, _) in &simplex[..9] {
                for i in 0..9 {
                    c[i] += x[i] / 9.0;
                }
            }
            let w = simplex[9];
            let pt = |t: f64| {
                let mut y = [0.0; 9];
                for i in 0..9 {
                    y[i] = c[i] + t * (w.0[i] - c[i]);
                }
                y
            };
            let xr = pt(-1.0);
            let fr = f(&xr);
            evals += 1;
            if fr < simplex[0].1 {
                let xe = pt(-2.0);
                let fe = f(&xe);
                evals += 1;
                simplex[9] = if fe < fr { (xe, fe) } else { (xr, fr) };
            } else if fr < simplex[8].1 {
                simplex[9] = (xr, fr);
            } else {
                let (xc, fc) = if fr < w.1 {
                    let x = pt(-0.5);
                    (x, f(&x))
                } else {
                    let x = pt(0.5);
                    (x, f(&x))
                };
                evals += 1;
                if fc < w.1.min(fr) {
                    simplex[9] = (xc, fc);
                } else {
                    let b = simplex[0].0;
                    for s in simplex.iter_mut().skip(1) {
                        for (si, bi) in s.0.iter_mut().zip(&b) {
                            *si = bi + 0.5 * (*si - bi);
                        }
                        s.1 = f(&s.0);
                        evals += 1;
                    }
                }
            }
        }
        start = best.0;
        scale *= 0.5;
        if scale < 1e-3 {
            scale = 0.5;
        }
    }
    best
}

/// The condition labels in the order of [`GainReport::log_margins`].
pub const CONDITIONS: [&str; 4] = ["(eqn:c2)", "(eqn:kisigma)", "(eqn:c1b)", "(eqn:kRkWb)"];

/// What [`synthesize`] found.
#[derive(Clone, Debug)]
pub struct Synthesis {
    /// The gains it settled on (certified when [`Synthesis::certified`]).
    pub gains: GainsSpec,
    /// Their report.
    pub report: GainReport,
    /// Every condition holds with them, and they fly the scene under the
    /// thrust limit.
    pub certified: bool,
    /// The rotor thrust limit used, N.
    pub thrust_limit: f64,
    /// Index in [`CONDITIONS`] of the binding condition of phase 1's
    /// best, and its worst log margin.
    pub binding: usize,
    /// Phase 1's best worst log margin (positive: certified).
    pub best_log_margin: f64,
    /// λm(W1) of phase 1's best.
    pub lambda_min_w1: f64,
    /// Peak rotor thrust of phase 1's best, N (`None`: it did not fly).
    pub phase1_peak: Option<f64>,
    /// Without a thrust limit: the certified gains nearest to the scene's
    /// (in log space), their worst log margin and peak rotor thrust.
    pub free: (GainsSpec, f64, Option<f64>),
    /// The scene flown with its own gains: peak rotor thrust and the run.
    pub own: (f64, RunOutput),
    /// The scene flown with the synthesized gains (`None`: it diverged).
    pub flown: Option<(f64, RunOutput)>,
}

/// Searches for gains that meet every condition of Propositions 2 and 3
/// on `scene` with bounds `sb`, keeping the scene's peak rotor thrust
/// under `thrust_limit` (default: the peak with the scene's own gains),
/// with `evaluations` objective evaluations in each phase (the module docs
/// give the phases).
pub fn synthesize(
    scene: &Scene,
    sb: &SceneBounds,
    thrust_limit: Option<f64>,
    evaluations: usize,
) -> Result<Synthesis, Error> {
    let paper = scene.gains.clone();
    let (paper_peak, paper_run) = fly(scene, &paper).ok_or_else(|| SimError::Setting {
        field: "gains",
        message: "the scene does not fly with its own gains".into(),
    })?;
    let limit = thrust_limit.unwrap_or(paper_peak);
    if !(limit.is_finite() && limit > 0.0) {
        return Err(Error::Run(SimError::Setting {
            field: "thrust_limit",
            message: format!("{limit}: must be finite and > 0"),
        }));
    }
    let b = sb.bounds;
    let check = |p: &[f64; 9]| report(scene, &from_vec(&paper, p), &b);
    // Phase 0, for the record: the certified gains nearest (in log space)
    // to the scene's, with no thrust limit, and what they would need.
    let p0 = to_vec(&paper);
    let dist = |p: &[f64; 9]| p.iter().zip(&p0).map(|(a, b)| (a - b).powi(2)).sum::<f64>();
    let mut f0 = |p: &[f64; 9]| {
        check(p).map_or(1e9, |r| {
            100.0 * (MARGIN - r.worst_log_margin().0).max(0.0) + 1e-3 * dist(p)
        })
    };
    let (x0, _) = nelder_mead(&mut f0, p0, evaluations);
    let free = from_vec(&paper, &x0);
    let free_score = report(scene, &free, &b)?.worst_log_margin().0;
    let free_peak = if free_score > 0.0 {
        fly(scene, &free).map(|(p, _)| p)
    } else {
        None
    };
    // Phase 1: the worst margin under the thrust limit.
    let penalty = |peak: Option<f64>| peak.map_or(1e3, |p| 10.0 * (p / limit - 1.0).max(0.0));
    let mut f1 = |p: &[f64; 9]| {
        let Ok(r) = check(p) else { return 1e9 };
        let s = r.worst_log_margin().0.min(MARGIN);
        -s + penalty(fly(scene, &from_vec(&paper, p)).map(|x| x.0))
    };
    // Seeded from the scene's gains: the thrust limit keeps the answer near
    // realistic gains, far from phase 0's.
    let (x1, _) = nelder_mead(&mut f1, to_vec(&paper), evaluations);
    let g1 = from_vec(&paper, &x1);
    let r1 = report(scene, &g1, &b)?;
    let (s1, binding) = r1.worst_log_margin();
    let peak1 = fly(scene, &g1).map(|x| x.0);
    let feasible = s1 > 0.0 && peak1.is_some_and(|p| p <= limit);
    let (g, r) = if feasible {
        // Phase 2: fastest slowest decay, staying certified and under the limit.
        let mut f2 = |p: &[f64; 9]| {
            let Ok(r) = check(p) else { return 1e9 };
            let s = r.worst_log_margin().0;
            if s <= 0.0 {
                return 1e3 + 1e3 * -s;
            }
            let tc = r.attitude_time_constant.max(r.position_time_constant);
            tc + 100.0 * penalty(fly(scene, &from_vec(&paper, p)).map(|x| x.0))
        };
        let (x2, _) = nelder_mead(&mut f2, x1, evaluations);
        let g2 = from_vec(&paper, &x2);
        let r2 = report(scene, &g2, &b)?;
        let ok2 = r2.all_hold() && fly(scene, &g2).is_some_and(|(p, _)| p <= limit);
        if ok2 { (g2, r2) } else { (g1, r1) }
    } else {
        (g1, r1)
    };
    let flown = fly(scene, &g);
    Ok(Synthesis {
        certified: r.all_hold() && feasible,
        gains: g,
        report: r,
        thrust_limit: limit,
        binding,
        best_log_margin: s1,
        lambda_min_w1: r1.lambda_min_w1,
        phase1_peak: peak1,
        free: (free, free_score, free_peak),
        own: (paper_peak, paper_run),
        flown,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The report for paper-flip's gains against a hand calculation of the
    /// bounds and conditions (closed forms written out here, not the
    /// checker's code).
    #[test]
    fn paper_flip_report_matches_a_hand_calculation() {
        let scene = scenes::builtin::paper_flip();
        let sb = scene_bounds(&scene, 0.05, 1.0).unwrap();
        let (m, g) = (0.755, 9.81);
        // x_d is held, so ẍ_d = 0 and B1 = ‖−m g e3‖ = m g.
        assert!((sb.bounds.b1 - m * g).abs() < 1e-12, "{}", sb.bounds.b1);
        // J = diag(0.43, 0.43, 1.02)e-2: 2J − tr J·I = diag(−1.02, −1.02,
        // 0.16)e-2, norm 0.0102. The flip's Ω_d = π Ry(4πt)ᵀe3 + 4π e2 has
        // ‖Ω_d‖ = √17 π (Ry(4πt)ᵀe3 ⟂ e2); position mode holds still
        // (Ω_c = 0 on the nominal trajectory).
        assert!((sb.j_norm - 0.0102).abs() < 1e-15);
        let w = 17f64.sqrt() * std::f64::consts::PI;
        assert!((sb.max_omega_d - w).abs() < 1e-9, "{}", sb.max_omega_d);
        let b2 = 0.0102 * w;
        assert!((sb.bounds.b2 - b2).abs() < 1e-10);
        // δ_x = ‖[−0.5, 0.2, 1]‖∞.
        assert_eq!(sb.bounds.delta_x, 1.0);
        let r = report(&scene, &scene.gains, &sb.bounds).unwrap();
        let [c2, kis, c1, wc] = r.conditions;
        // (eqn:c2): min{√(k_R λm)/λM, 4k_Ω/(8k_R λM + (k_Ω + B2)²)}, λm =
        // 0.0043, λM = 0.0102.
        let c2_bound = ((0.65f64 * 0.0043).sqrt() / 0.0102)
            .min(4.0 * 0.11 / (8.0 * 0.65 * 0.0102 + (0.11 + b2).powi(2)));
        assert!((c2.bound - c2_bound).abs() < 1e-12 && c2.holds);
        assert!((c2_bound - 3.940).abs() < 1e-3, "{c2_bound}");
        // (eqn:kisigma): 1.28 · 1 > 1.
        assert!(kis.holds && (kis.value - 1.28).abs() < 1e-15);
        // (eqn:c1b) with α = √(ψ1(2 − ψ1)) = √0.0975:
        let al = 0.0975f64.sqrt();
        let c1_bound = (4.0 * 12.8 * 4.22 * (1.0 - al).powi(2)
            / (4.22f64.powi(2) * (1.0 + al).powi(2) + 4.0 * m * 12.8 * (1.0 - al)))
            .min((12.8 / m).sqrt());
        assert!((c1.bound - c1_bound).abs() < 1e-12 && !c1.holds);
        // λm(W1) of [[c1 k_x (1−α), −c1 k_v (1+α)/2], [·, k_v(1−α) − m c1]]
        // by the 2×2 formula: negative, so (eqn:kRkWb)'s bound is ∞.
        let (a11, a12, a22) = (
            3.6 * 12.8 * (1.0 - al),
            -0.5 * 3.6 * 4.22 * (1.0 + al),
            4.22 * (1.0 - al) - m * 3.6,
        );
        let l1 = 0.5 * (a11 + a22) - (0.25 * (a11 - a22).powi(2) + a12 * a12).sqrt();
        assert!((r.lambda_min_w1 - l1).abs() < 1e-12 && l1 < 0.0);
        assert!(!wc.holds && wc.bound.is_infinite());
        // λm(W2), W2 = [[c2 k_R, −c2(k_Ω + B2)/2], [·, k_Ω − 2 c2 λM]].
        let (b11, b12, b22): (f64, f64, f64) = (
            0.8 * 0.65,
            -0.5 * 0.8 * (0.11 + b2),
            0.11 - 2.0 * 0.8 * 0.0102,
        );
        let l2 = 0.5 * (b11 + b22) - (0.25 * (b11 - b22).powi(2) + b12 * b12).sqrt();
        assert!((wc.value - l2).abs() < 1e-12, "{} vs {l2}", wc.value);
    }
}
