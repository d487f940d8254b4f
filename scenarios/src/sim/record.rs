//! One [`Sample`] from the state and the command, in f64.

use dynamics::Wrench;
use integrators::State;
use lie::{Backend, Real, Rotation, S, So3Mat};

use super::closed_loop::{Answer, ClosedLoop};
use super::{RunOutput, Sample, SimError};

pub(crate) fn empty_sample() -> Sample {
    Sample {
        t: 0.0,
        x: [0.0; 3],
        v: [0.0; 3],
        r: [[0.0; 3]; 3],
        omega: [0.0; 3],
        psi: 0.0,
        ex: 0.0,
        thrust: 0.0,
        moment: [0.0; 3],
        mode: "none",
        segment: 0,
        rd: [[0.0; 3]; 3],
        omega_d: [0.0; 3],
        xd: [0.0; 3],
        e_att: [0.0; 3],
        e_pos: [0.0; 3],
        rotors: Vec::new(),
        vehicle_states: Vec::new(),
        wind: [0.0; 3],
        sensors: None,
    }
}

/// Updates the run's extrema with the figures of one state (every step
/// end, located event and the start, never an interpolated sample: the
/// extrema do not depend on what is recorded).
pub(crate) fn track(out: &mut RunOutput, s: &Sample) {
    // ‖RᵀR − I‖_F from the rows.
    let r = &s.r;
    let mut e2 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let d = (0..3).map(|k| r[k][i] * r[k][j]).sum::<f64>() - if i == j { 1.0 } else { 0.0 };
            e2 += d * d;
        }
    }
    fold(out, s.thrust, s.psi, e2.sqrt(), s.rotors.iter().copied());
}

/// Folds one state's figures into the run's extrema; a NaN distance from
/// SO(3) stays NaN (`max` would drop it) so that it is seen.
fn fold(out: &mut RunOutput, thrust: f64, psi: f64, ortho: f64, rotors: impl Iterator<Item = f64>) {
    out.max_thrust = out.max_thrust.max(thrust.abs());
    out.max_rotor = rotors.fold(out.max_rotor, |a, r| a.max(r.abs()));
    out.max_orthogonality_error = if ortho.is_nan() {
        f64::NAN
    } else {
        out.max_orthogonality_error.max(ortho)
    };
    out.psi_range = out.psi_range.with(psi);
}

/// The rotor thrusts that command `c` asks of the vehicle in state `y`
/// (through its actuator dynamics), into `buf`: at most 8 rotors, on the
/// stack. Returns how many.
fn rotor_thrusts<B: Backend, const N: usize>(
    sys: &ClosedLoop<'_, '_, B, N>,
    c: &super::closed_loop::Command<B, N>,
    y: &State<B, N>,
    buf: &mut [S<B>; 8],
) -> Result<usize, SimError> {
    let vehicle = sys.vehicle;
    let n = vehicle.actuator_count().min(8);
    if n > 0 {
        let asked = Wrench {
            thrust: c.out.thrust,
            moment: c.out.moment,
        };
        let w = match sys.caps.actuators {
            Some(a) => a.delivered(&asked, sys.vehicle_states(y)),
            None => asked,
        };
        vehicle
            .actuators_from_wrench(&w, &mut buf[..n])
            .map_err(SimError::Vehicle)?;
    }
    Ok(n)
}

/// The command acting at `(t, y)`: the held one under sampled control,
/// else the active mode's; a mode's error names the time.
fn command_at<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    t: f64,
    y: &State<B, N>,
) -> Result<Option<super::closed_loop::Command<B, N>>, SimError> {
    let cmd = if sys.sampled {
        sys.held
    } else {
        sys.command(S::<B>::lit(t), y)
    };
    match sys.error.take() {
        Some(source) => Err(SimError::Control { t, source }),
        None => Ok(cmd),
    }
}

/// [`track`] on the state at `t` without forming a [`Sample`] (no
/// allocation): this runs after every step.
pub(crate) fn track_figures<B: Backend, const N: usize>(
    out: &mut RunOutput,
    sys: &mut ClosedLoop<'_, '_, B, N>,
    t: f64,
    y: &State<B, N>,
) -> Result<(), SimError> {
    let cmd = command_at(sys, t, y)?;
    if !sys.sampled
        && let Some(c) = &cmd
    {
        sys.answer = Answer::new(S::<B>::lit(t), y, sys.active, c);
    }
    let r = So3Mat::<B>::from_matrix_unchecked(y.body.r);
    let ortho = r.orthogonality_error().to_f64_lossless();
    let Some(c) = cmd else {
        fold(out, 0.0, 0.0, ortho, std::iter::empty());
        return Ok(());
    };
    let mut buf = [S::<B>::lit(0.0); 8];
    let n = rotor_thrusts(sys, &c, y, &mut buf)?;
    let psi = r.psi(c.out.desired).to_f64_lossless();
    let rotors = buf[..n].iter().map(|r| r.to_f64_lossless());
    fold(out, c.out.thrust.to_f64_lossless(), psi, ortho, rotors);
    Ok(())
}

pub(crate) fn sample<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    t: f64,
    y: &State<B, N>,
) -> Result<Sample, SimError> {
    let cmd = command_at(sys, t, y)?;
    let mut s = empty_sample();
    s.t = t;
    s.sensors = sys.sensing.as_deref().map(|sn| Box::new(sn.latest.clone()));
    s.x = lie::ops::vec3_f64::<B>(y.body.x);
    s.v = lie::ops::vec3_f64::<B>(y.body.v);
    s.r = lie::ops::mat3_f64::<B>(y.body.r);
    s.omega = lie::ops::vec3_f64::<B>(y.body.omega);
    s.wind = sys.wind_at(t, y);
    let integrals = sys.layout.integrals(&y.extra);
    let ex = |k: usize| integrals.get(k).map_or(0.0, |e| e.to_f64_lossless());
    s.e_att = [ex(0), ex(1), ex(2)];
    s.e_pos = [ex(3), ex(4), ex(5)];
    let states = sys.vehicle_states(y);
    s.vehicle_states = states.iter().map(|c| c.to_f64_lossless()).collect();
    if let Some(c) = cmd {
        let mode = &sys.plan[sys.active].mode;
        s.thrust = c.out.thrust.to_f64_lossless();
        s.moment = lie::ops::vec3_f64::<B>(c.out.moment);
        s.mode = mode.name();
        s.segment = sys.active;
        s.rd = lie::ops::mat3_f64::<B>(c.out.desired.matrix());
        s.omega_d = lie::ops::vec3_f64::<B>(c.out.desired_omega);
        // Ψ against the desired attitude at *this* state (the held command
        // may be older in sampled mode).
        let r = So3Mat::<B>::from_matrix_unchecked(y.body.r);
        s.psi = r.psi(c.out.desired).to_f64_lossless();
        if sys.caps.translates
            && let Some(d) = mode.desired_position(t)
        {
            s.xd = d;
            s.ex = (0..3).map(|k| (s.x[k] - d[k]).powi(2)).sum::<f64>().sqrt();
        }
        let mut buf = [S::<B>::lit(0.0); 8];
        let n = rotor_thrusts(sys, &c, y, &mut buf)?;
        if n > 0 {
            s.rotors = buf[..n].iter().map(|r| r.to_f64_lossless()).collect();
        }
    } else {
        s.rd = s.r;
    }
    Ok(s)
}
