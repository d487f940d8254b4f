//! What the exact `Ω_c`, `Ω̇_c` of the position law buy on a planned
//! trajectory: the same flight with both taken instead from backward
//! differences of the commanded attitude between control instants, as
//! most implementations do (PX4 and the Crazyflie firmware differentiate
//! nothing and set them to zero; RotorPy's SE(3) controller too).

use std::cell::Cell;

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, ControlError, IntegralLayout, Mode,
    ModeOutput, PositionGains, PositionInput, PositionSource, RigidBodyParams, VehicleState,
    attitude_control, position_control,
};
use lie::{Backend, NalgebraF64, Real, S, So3Mat, V3, ops};
use scenarios::{RunOptions, RunOutput, Segment, Until};
use scenes::scene::Timing;
use scenes::{Error, Registry, Scene, ScenePosition, Seeds};

use crate::metrics::norm;

/// The paper's position law with `Ω_c = log(R_c,prevᵀ R_c)/h` and
/// `Ω̇_c = (Ω_c − Ω_c,prev)/h` from the previous control instant, `h`
/// apart, in place of the exact derivatives (zero at the first instant).
/// Meant for sampled control: it keeps the last two instants, and a
/// second call less than `h/2` after one reuses the same previous one.
pub struct FiniteDifferenced<B: Backend, P> {
    params: RigidBodyParams<B>,
    pos_gains: PositionGains<B>,
    att_gains: AttitudeGains<B>,
    model: AccelerationModel<B>,
    reference: P,
    period: f64,
    /// `(t, R_c, Ω_c)` at the last two control instants, oldest first.
    history: Cell<[Option<Instant<B>>; 2]>,
}

/// `(t, R_c, Ω_c)` at one control instant.
type Instant<B> = (f64, So3Mat<B>, V3<B>);

impl<B: Backend, P: PositionSource<B>> FiniteDifferenced<B, P> {
    /// The law with these gains, tracking `reference`, differencing over
    /// control instants `period` seconds apart.
    pub fn new(
        params: RigidBodyParams<B>,
        (pos_gains, att_gains, model): (PositionGains<B>, AttitudeGains<B>, AccelerationModel<B>),
        reference: P,
        period: f64,
    ) -> Self {
        Self {
            params,
            pos_gains,
            att_gains,
            model,
            reference,
            period,
            history: Cell::new([None, None]),
        }
    }

    /// `(Ω_c, Ω̇_c)` at `t` for the commanded `rc`, updating the history.
    fn differences(&self, t: f64, rc: So3Mat<B>) -> (V3<B>, V3<B>) {
        let mut h = self.history.get();
        let repeat = h[1].is_some_and(|(tl, ..)| t < tl + 0.5 * self.period);
        let prev = if repeat { h[0] } else { h[1] };
        let (w, wd) = match prev {
            Some((tp, rp, wp)) => {
                let k = S::<B>::lit(1.0 / (t - tp));
                let w = (rp.inverse() * rc).log() * k;
                (w, (w - wp) * k)
            }
            None => (ops::zero::<B>(), ops::zero::<B>()),
        };
        let now = Some((t, rc, w));
        h = if repeat { [h[0], now] } else { [h[1], now] };
        self.history.set(h);
        (w, wd)
    }
}

impl<B: Backend, P: PositionSource<B>> Mode<B> for FiniteDifferenced<B, P> {
    fn name(&self) -> &'static str {
        "position (Ω_c by differences)"
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        IntegralLayout {
            count: 6,
            breakpoints: &[],
        }
    }
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        let i = |k: usize| integrals[k];
        let (e_att, e_pos) = (B::vec3(i(0), i(1), i(2)), B::vec3(i(3), i(4), i(5)));
        let reference = self.reference.position(t);
        let out = position_control(
            &self.params,
            &self.pos_gains,
            &self.att_gains,
            &PositionInput {
                state,
                e_i_pos: e_pos,
                e_i_att: e_att,
                reference: &reference,
                model: self.model,
            },
        )?;
        let (w, wd) = self.differences(t.to_f64_lossless(), out.rc);
        let att = attitude_control(
            &self.params,
            &self.att_gains,
            state.r,
            state.omega,
            e_att,
            &AttitudeReference {
                rd: out.rc,
                omega_d: w,
                omega_d_dot: wd,
            },
        )?;
        let (a, p) = (
            B::vec3_to_array(att.e_i_rate),
            B::vec3_to_array(out.e_i_pos_rate),
        );
        rates[..6].copy_from_slice(&[a[0], a[1], a[2], p[0], p[1], p[2]]);
        Ok(ModeOutput {
            thrust: out.thrust,
            moment: att.moment,
            desired: out.rc,
            desired_omega: w,
            psi: att.psi,
            rotor_speeds: None,
        })
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        Some(self.reference.position_f64(t))
    }
}

/// Position error of one flight along its recorded samples.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Tracking {
    /// RMS of ‖x − x_d‖, m.
    pub rms: f64,
    /// Largest ‖x − x_d‖, m.
    pub max: f64,
}

impl Tracking {
    /// The error of `out`'s samples.
    pub fn of(out: &RunOutput) -> Self {
        let e: Vec<f64> = out
            .samples
            .iter()
            .map(|s| norm([0, 1, 2].map(|k| s.x[k] - s.xd[k])))
            .collect();
        let rms = (e.iter().map(|e| e * e).sum::<f64>() / e.len().max(1) as f64).sqrt();
        Self {
            rms,
            max: e.iter().fold(0.0, |m, e| m.max(*e)),
        }
    }
}

/// A Markdown table of [`exact_against_differences`] for `scene` at each
/// of `rates`, with the paper's disturbances as the scene has them and
/// without.
pub fn table(scene: &Scene, rates: &[f64]) -> Result<String, Error> {
    let mut md = String::from(
        "| disturbances | control rate, Hz | RMS exact, mm | RMS differences, mm | ratio | largest exact, mm | largest differences, mm | ratio |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut calm = scene.clone();
    calm.disturbance = None;
    for (name, s) in [("Δ_x, Δ_R", scene), ("none", &calm)] {
        for &rate in rates {
            let (e, d) = exact_against_differences(s, rate)?;
            md.push_str(&format!(
                "| {name} | {rate} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |\n",
                1e3 * e.rms,
                1e3 * d.rms,
                d.rms / e.rms,
                1e3 * e.max,
                1e3 * d.max,
                d.max / e.max
            ));
        }
    }
    Ok(md)
}

/// `scene` (one position segment) flown under sampled control at
/// `rate` Hz twice: with the law's exact `Ω_c`, `Ω̇_c`, and with
/// [`FiniteDifferenced`]. Nalgebra, f64.
pub fn exact_against_differences(scene: &Scene, rate: f64) -> Result<(Tracking, Tracking), Error> {
    let mut s = scene.clone();
    s.control.timing = Timing::Sampled;
    s.control.rate = rate;
    let registry = Registry::new();
    let exact = registry.run_generic::<NalgebraF64>(&s, RunOptions::default())?;
    registry.check(&s)?;
    let vehicle = registry.build_vehicle::<NalgebraF64>(&s)?;
    let (params, pg, ag, model) = scenes::gains::<NalgebraF64>(&s, vehicle.as_ref(), Seeds::NONE);
    let [seg] = s.plan.as_slice() else {
        return Err(Error::at_key("plan", "one position segment".into()));
    };
    let Some(p) = &seg.position else {
        return Err(Error::at_key("plan", "one position segment".into()));
    };
    let mode = FiniteDifferenced::new(
        params,
        (pg, ag, model),
        ScenePosition::<NalgebraF64>::new(p),
        1.0 / rate,
    );
    let plan = vec![Segment {
        mode: Box::new(mode) as Box<dyn Mode<NalgebraF64>>,
        until: Until::Never,
    }];
    let fd = scenes::builder_from::<NalgebraF64>(&s, vehicle, plan, Seeds::NONE)?
        .build()?
        .run(RunOptions::default())
        .map_err(Error::Run)?;
    Ok((Tracking::of(&exact), Tracking::of(&fd)))
}
