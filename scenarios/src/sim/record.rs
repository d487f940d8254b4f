//! One [`Sample`] from the state and the command, in f64.

use dynamics::Wrench;
use integrators::State;
use lie::{Backend, Real, Rotation, S, So3Mat, V3, ops};

use super::closed_loop::ClosedLoop;
use super::{RunOutput, Sample, SimError};

fn f3<B: Backend>(x: V3<B>) -> [f64; 3] {
    B::vec3_to_array(x).map(|c| c.to_f64_lossless())
}

fn fm<B: Backend>(x: lie::M3<B>) -> [[f64; 3]; 3] {
    ops::elems::<B>(x).map(|r| r.map(|c| c.to_f64_lossless()))
}

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
    }
}

/// Updates the run's extrema with the figures of one state (every step
/// end, located event and the start, never an interpolated sample: the
/// extrema do not depend on what is recorded).
pub(crate) fn track(out: &mut RunOutput, s: &Sample) {
    out.max_thrust = out.max_thrust.max(s.thrust.abs());
    out.max_rotor = s.rotors.iter().fold(out.max_rotor, |a, r| a.max(r.abs()));
    // ‖RᵀR − I‖_F from the rows (a NaN propagates through the max as NaN
    // would not: keep it visible).
    let r = &s.r;
    let mut e2 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let d = (0..3).map(|k| r[k][i] * r[k][j]).sum::<f64>() - if i == j { 1.0 } else { 0.0 };
            e2 += d * d;
        }
    }
    let e = e2.sqrt();
    out.max_orthogonality_error = if e.is_nan() {
        f64::NAN
    } else {
        out.max_orthogonality_error.max(e)
    };
    out.psi_range = (out.psi_range.0.min(s.psi), out.psi_range.1.max(s.psi));
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
        Some(e) => Err(SimError::Control(format!("at t = {t}: {e}"))),
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
    let r = So3Mat::<B>::from_matrix_unchecked(y.body.r);
    let e = r.orthogonality_error().to_f64_lossless();
    out.max_orthogonality_error = if e.is_nan() {
        f64::NAN
    } else {
        out.max_orthogonality_error.max(e)
    };
    let Some(c) = cmd else {
        out.psi_range = (out.psi_range.0.min(0.0), out.psi_range.1.max(0.0));
        return Ok(());
    };
    let psi = r.psi(c.out.desired).to_f64_lossless();
    out.psi_range = (out.psi_range.0.min(psi), out.psi_range.1.max(psi));
    out.max_thrust = out.max_thrust.max(c.out.thrust.to_f64_lossless().abs());
    let vehicle = sys.vehicle;
    let n = vehicle.actuator_count().min(8);
    if n > 0 {
        let mut buf = [S::<B>::lit(0.0); 8];
        let w = vehicle.applied_wrench(
            &Wrench {
                thrust: c.out.thrust,
                moment: c.out.moment,
            },
            sys.vehicle_states(y),
        );
        vehicle
            .actuators_from_wrench(&w, &mut buf[..n])
            .map_err(|e| SimError::Scene(e.to_string()))?;
        out.max_rotor = buf[..n]
            .iter()
            .fold(out.max_rotor, |a, r| a.max(r.to_f64_lossless().abs()));
    }
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
    s.x = f3::<B>(y.body.x);
    s.v = f3::<B>(y.body.v);
    s.r = fm::<B>(y.body.r);
    s.omega = f3::<B>(y.body.omega);
    let ex = |k: usize| {
        if k < sys.m {
            y.extra[k].to_f64_lossless()
        } else {
            0.0
        }
    };
    s.e_att = [ex(0), ex(1), ex(2)];
    s.e_pos = [ex(3), ex(4), ex(5)];
    let states = sys.vehicle_states(y);
    s.vehicle_states = states.iter().map(|c| c.to_f64_lossless()).collect();
    let vehicle = sys.vehicle;
    if let Some(c) = cmd {
        let mode = &sys.plan[sys.active].mode;
        s.thrust = c.out.thrust.to_f64_lossless();
        s.moment = f3::<B>(c.out.moment);
        s.mode = mode.name();
        s.segment = sys.active;
        s.rd = fm::<B>(c.out.desired.matrix());
        s.omega_d = f3::<B>(c.out.desired_omega);
        // Ψ against the desired attitude at *this* state (the held command
        // may be older in sampled mode).
        let r = So3Mat::<B>::from_matrix_unchecked(y.body.r);
        s.psi = r.psi(c.out.desired).to_f64_lossless();
        if vehicle.translates()
            && let Some(d) = mode.desired_position(t)
        {
            s.xd = d;
            s.ex = (0..3).map(|k| (s.x[k] - d[k]).powi(2)).sum::<f64>().sqrt();
        }
        let n = vehicle.actuator_count();
        if n > 0 {
            // At most 8 rotors on the stack; more would need a bigger buffer.
            let mut buf = [S::<B>::lit(0.0); 8];
            let rotors = &mut buf[..n.min(8)];
            let w = vehicle.applied_wrench(
                &Wrench {
                    thrust: c.out.thrust,
                    moment: c.out.moment,
                },
                states,
            );
            vehicle
                .actuators_from_wrench(&w, rotors)
                .map_err(|e| SimError::Scene(e.to_string()))?;
            s.rotors = rotors.iter().map(|r| r.to_f64_lossless()).collect();
        }
    } else {
        s.rd = s.r;
    }
    Ok(s)
}
