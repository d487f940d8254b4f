//! Sensors and an estimator in the loop: samples taken from each step's
//! continuous extension at every sensor's own instants (so sampling moves
//! no step), queued until they arrive (capture time plus latency), and
//! handed to the estimator at each control instant, whose estimate the
//! flight mode then reads in place of the true state.
//!
//! A sample at an instant where a step ends is taken from that step's end
//! state itself, so a noise-free tracker at the control rate gives the
//! mode the true state bit for bit. A sample taken at a control instant
//! sees the command from before the update there (the accelerometer reads
//! the loads of the step that ended there); at `t = 0`, where there is no
//! earlier command, the IMU reads the first one.

use integrators::{Integrator, State, System, dense};
use lie::{Backend, Real, S};

use super::SimError;
use super::closed_loop::ClosedLoop;
use super::sensing::{BARO, GPS, IMU, MOCAP};

/// The start of a sensed run: the estimator reset to the true state, every
/// sensor but the IMU sampled at `t = 0` and delivered, the estimate for
/// the first command. The IMU's sample at 0 comes after that command
/// ([`after_first_command`]).
pub(super) fn start<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    y: &State<B, N>,
) -> Result<(), SimError> {
    let Some(sn) = sys.sensing.as_deref_mut() else {
        return Ok(());
    };
    sn.reset(y);
    let g = sys.vehicle.gravity();
    for s in [MOCAP, GPS, BARO] {
        if sn.due(s).0 == 0.0 {
            sn.take(s, 0.0, y, None, g)?;
        }
    }
    sn.refresh(0.0);
    Ok(())
}

/// The IMU's sample at `t = 0`, under the first command.
pub(super) fn after_first_command<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    y: &State<B, N>,
) -> Result<(), SimError> {
    let imu_due = sys
        .sensing
        .as_deref()
        .is_some_and(|sn| sn.due(IMU).0 == 0.0);
    if imu_due {
        let r = rates_at(sys, 0.0, y)?;
        let g = sys.vehicle.gravity();
        if let Some(sn) = sys.sensing.as_deref_mut() {
            sn.take(IMU, 0.0, y, Some(&r), g)?;
        }
    }
    Ok(())
}

/// The rates of `y` at `t` under the loop's loads, not counted as an
/// evaluation and leaving the loop's kept answer where it was.
fn rates_at<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    t: f64,
    y: &State<B, N>,
) -> Result<dense::Rates<B, N>, SimError> {
    // The kept answer is moved out and back only when there is one (a
    // continuous loop's): it holds a whole state.
    let counted = sys.evaluations;
    let kept = if sys.answer.is_some() {
        sys.answer.take()
    } else {
        None
    };
    let l = sys.load(S::<B>::lit(t), y);
    sys.evaluations = counted;
    if kept.is_some() {
        sys.answer = kept;
    }
    if let Some(source) = sys.error.take() {
        return Err(SimError::Control { t, source });
    }
    Ok(dense::Rates::of(sys, y, &l))
}

/// Every sensor instant in `(t0, t1]` of the piece of a step from
/// `(t0, y0)` to `(t1, y1)`, sampled: from `y1` itself at `t1`, from the
/// piece's continuous extension inside it (as recording is).
#[inline(always)]
pub(super) fn piece<B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    stepper: &I,
    start: (f64, &State<B, N>),
    end: (f64, &State<B, N>),
) -> Result<(), SimError> {
    // A run without sensors pays this test, not a call.
    if sys.sensing.is_none() {
        return Ok(());
    }
    sample_piece(sys, stepper, start, end)
}

/// [`piece`] in a run with sensors.
#[inline(never)]
fn sample_piece<B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    stepper: &I,
    (t0, y0): (f64, &State<B, N>),
    (t1, y1): (f64, &State<B, N>),
) -> Result<(), SimError> {
    let Some(sn) = sys.sensing.as_deref() else {
        return Ok(());
    };
    if sn.earliest() > t1 {
        return Ok(());
    }
    let g = sys.vehicle.gravity();
    let mut ext: Option<super::emit::Extension<B, N, I>> = None;
    for s in [IMU, MOCAP, GPS, BARO] {
        loop {
            let Some((tk, tol)) = sys.sensing.as_deref().map(|sn| sn.due(s)) else {
                return Ok(());
            };
            if tk > t1 + tol {
                break;
            }
            let inside;
            let y = if (tk - t1).abs() <= tol {
                y1
            } else {
                inside = state_inside(sys, stepper, &mut ext, (t0, y0), (t1, y1), tk)?;
                &inside
            };
            let rates = if s == IMU {
                Some(rates_at(sys, tk, y)?)
            } else {
                None
            };
            if let Some(sn) = sys.sensing.as_deref_mut() {
                sn.take(s, tk, y, rates.as_ref(), g)?;
            }
        }
    }
    Ok(())
}

/// The state at `tk` inside the piece, from its continuous extension
/// (built on first use: a copy of an adaptive stepper re-integrating from
/// `t0`, or the cubic Hermite through the ends).
fn state_inside<B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    stepper: &I,
    ext: &mut Option<super::emit::Extension<B, N, I>>,
    (t0, y0): (f64, &State<B, N>),
    (t1, y1): (f64, &State<B, N>),
    tk: f64,
) -> Result<State<B, N>, SimError> {
    use super::emit::Extension;
    let l = S::<B>::lit;
    if ext.is_none() {
        *ext = Some(match stepper.resampler() {
            Some(copy) => Extension::Redo(copy),
            None => Extension::Hermite(rates_at(sys, t0, y0)?, rates_at(sys, t1, y1)?),
        });
    }
    let h = t1 - t0;
    Ok(match ext.as_mut() {
        Some(Extension::Redo(c)) => {
            let (counted, kept) = (sys.evaluations, sys.answer.take());
            let mut y = *y0;
            c.reset();
            let stepped = c.step(sys, l(t0), l(tk - t0), &mut y);
            sys.evaluations = counted;
            sys.answer = kept;
            stepped.map_err(|e| sys.step_error(t0, tk - t0, e))?;
            y
        }
        Some(Extension::Hermite(r0, r1)) => {
            dense::interpolate(y0, r0, y1, r1, l(h), l((tk - t0) / h))
        }
        None => *y0,
    })
}

/// Hands the measurements taken in this call to the sink and keeps them
/// in the output when the run records.
pub(super) fn drain<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    emit: &mut super::emit::Emit<'_, '_>,
    out: &mut super::RunOutput,
) -> Result<(), SimError> {
    let Some(sn) = sys.sensing.as_deref_mut() else {
        return Ok(());
    };
    if let Some(k) = emit.sink.as_deref_mut() {
        for m in &sn.log {
            k.measurement(m).map_err(SimError::Output)?;
        }
    }
    if emit.r.keep {
        out.measurements.append(&mut sn.log);
    } else {
        sn.log.clear();
    }
    Ok(())
}
