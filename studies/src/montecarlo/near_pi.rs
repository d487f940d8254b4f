//! The measure-zero set, measured: how long the attitude loop takes to
//! leave the neighbourhood of the rotation by π.
//!
//! Near the rotation by π about a principal axis `a` (moment of inertia
//! `J`), with R_d = I, Ω_d = 0 and no disturbance, the motion stays a
//! rotation about `a` by an angle θ: `e_R = sin θ a`, `e_Ω = θ̇ a`, and the
//! law (eqn:aM) with (eqn:eI) reads
//! `J θ̈ = −k_R sin θ − k_Ω θ̇ − k_I e_I`, `ė_I = θ̇ + c2 sin θ`.
//! With θ = π − φ, sin θ ≈ φ, and Laplace transforms,
//! `J s² Φ = k_R Φ − k_Ω s Φ + k_I E`, `s E = (c2 − s) Φ`, so
//! `J s³ + k_Ω s² + (k_I − k_R) s − k_I c2 = 0`: a third-order system whose
//! one positive root λ₊ ([`controllers::gain_check::lambda_plus`]) drives
//! φ(t) ≈ c δ e^{λ₊ t} away from π. The time to reach any fixed Ψ grows as
//! `ln(1/δ)/λ₊` plus a constant, so the slope of the time to converge
//! against ln(1/δ) is 1/λ₊.

use controllers::ModeOutput;
use controllers::gain_check::lambda_plus;
use dynamics::RigidBodyState;
use lie::{GlamF64, Real};
use scenes::Error;

use scenarios::{RunOptions, Simulation};
use scenes::builtin;

/// The escape from near π about one principal axis.
#[derive(Clone, Debug, PartialEq)]
pub struct NearPiAxis {
    /// `e1` or `e3`.
    pub axis: &'static str,
    /// Its moment of inertia, kg m².
    pub j: f64,
    /// The unstable root λ₊ of the linearised loop, 1/s.
    pub lambda: f64,
    /// `(δ, time to Ψ < 10⁻³)` for δ = 10⁻¹ … 10⁻¹⁰, s.
    pub times: Vec<(f64, f64)>,
    /// Least-squares slope of the time against ln(1/δ) over δ = 10⁻⁴ …
    /// 10⁻¹⁰ (where the linearisation holds), s.
    pub slope: f64,
}

impl NearPiAxis {
    /// `|slope · λ₊ − 1|`: how far the measured escape rate is from the
    /// linearisation's.
    pub fn slope_error(&self) -> f64 {
        (self.slope * self.lambda - 1.0).abs()
    }
}

impl NearPiAxis {
    /// The first δ whose run never reached Ψ < 10⁻³ in its 60 s, if any.
    pub fn unsettled(&self) -> Option<f64> {
        self.times.iter().find(|p| p.1.is_nan()).map(|p| p.0)
    }
}

/// The escape times as CSV, `axis,delta,t_converge`, one row per axis and
/// δ (δ in exponent form, the time in the shortest form that reads back
/// the same).
pub fn near_pi_csv(report: &[NearPiAxis]) -> String {
    let mut csv = String::from("axis,delta,t_converge\n");
    for a in report {
        for (delta, t) in &a.times {
            csv.push_str(&format!("{},{delta:e},{t}\n", a.axis));
        }
    }
    csv
}

impl std::fmt::Display for NearPiAxis {
    /// Two lines: the times to converge, then the slope against 1/λ₊.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let t: Vec<String> = self.times.iter().map(|p| format!("{:.3}", p.1)).collect();
        writeln!(
            f,
            "  a = {} (J = {}): t_converge for δ = 1e-1 … 1e-10: {}",
            self.axis,
            self.j,
            t.join(", ")
        )?;
        write!(
            f,
            "  a = {}: slope of t_converge against ln(1/δ) over k = 4…10: {:.5} s; 1/λ₊ = {:.5} s (λ₊ = {:.5} /s); ratio {:.5}",
            self.axis,
            self.slope,
            1.0 / self.lambda,
            self.lambda,
            self.slope * self.lambda
        )
    }
}

/// From `R(0) = exp((π − δ) â)` for â = e1 and e3, δ = 10⁻¹ … 10⁻¹⁰: the
/// time to Ψ < 10⁻³ in the large-attitude-error scene without its
/// disturbance (RK4 at 1 ms, 60 s at most), and the fitted slope against
/// 1/λ₊.
pub fn near_pi() -> Result<Vec<NearPiAxis>, Error> {
    type B = GlamF64;
    let base = builtin::large_attitude_error();
    let g = &base.gains;
    let mut report = Vec::new();
    for (axis, dir, jk) in [("e1", [1.0, 0.0, 0.0], 0), ("e3", [0.0, 0.0, 1.0], 2)] {
        let j = base.vehicle.inertia[jk];
        let lambda = lambda_plus(j, g.k_r, g.k_omega, g.k_att_i, g.c2);
        let mut times = Vec::new();
        for k in 1..=10 {
            let delta = 10f64.powi(-k);
            let mut sc = base.clone();
            sc.disturbance = None;
            sc.initial = Default::default();
            let th = std::f64::consts::PI - delta;
            sc.initial.rotation = dir.map(|c: f64| c * th);
            sc.integrator.kind = "rk4".into();
            sc.integrator.dt = 1e-3;
            sc.duration = 60.0;
            let vehicle = scenes::build_vehicle::<B>(&sc)?;
            let plan = scenes::plan::<B>(&sc, vehicle.as_ref());
            let mut body = RigidBodyState::<B>::at_rest();
            body.r =
                lie::ops::from_elems::<B>(scenes::reference::rotation_f64(sc.initial.rotation));
            let stop = Box::new(|_: f64, _: &RigidBodyState<B>, o: &ModeOutput<B>| {
                o.psi.to_f64_lossless() < 1e-3
            });
            let mut b = Simulation::<B>::builder(vehicle)
                .initial(body)
                .dt(sc.integrator.dt)
                .duration(sc.duration)
                .record_every(0.0)
                .stop_when(stop);
            for seg in plan {
                b = b.segment(seg);
            }
            let out = b.build()?.run(RunOptions {
                record: false,
                ..Default::default()
            })?;
            times.push((delta, out.stopped_at().unwrap_or(f64::NAN)));
        }
        // Least squares over k = 4 … 10.
        let fit: Vec<(f64, f64)> = times[3..]
            .iter()
            .map(|&(d, t)| ((1.0 / d).ln(), t))
            .collect();
        let n = fit.len() as f64;
        let (sx, sy) = fit.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
        let (mx, my) = (sx / n, sy / n);
        let (sxy, sxx) = fit.iter().fold((0.0, 0.0), |(a, b), p| {
            (a + (p.0 - mx) * (p.1 - my), b + (p.0 - mx).powi(2))
        });
        report.push(NearPiAxis {
            axis,
            j,
            lambda,
            times,
            slope: sxy / sxx,
        });
    }
    Ok(report)
}
