//! The sample stream: where samples go, and when, taken from the steps'
//! continuous extension so that recording never moves the step grid.

use integrators::{Integrator, State, System, dense};
use lie::{Backend, Real, S};

use super::Sink;
use super::closed_loop::ClosedLoop;
use super::record::sample;
use super::{RunOutput, Sample, SimError, SwitchRecord};

/// Where samples go: kept in the output, handed to the sink, or both; and
/// when: every `rec` seconds, taken from the steps' continuous extension
/// ([`integrators::dense`]) so that recording never moves the step grid.
pub(super) struct Emit<'o, 's> {
    pub(super) r: Record,
    pub(super) sink: Option<&'o mut (dyn Sink + 's)>,
}

/// Where the sample stream is: kept between calls of `advance_to`.
#[derive(Copy, Clone)]
pub(super) struct Record {
    pub(super) keep: bool,
    /// Time of the last sample emitted (a checkpoint that coincides with
    /// a located stop is not sampled twice).
    pub(super) last_t: f64,
    /// Record interval, s (0: only the start and the end).
    pub(super) rec: f64,
    /// Record instants emitted so far; the next is `(k + 1)·rec`.
    pub(super) k: u64,
}

impl<'o, 's> Emit<'o, 's> {
    pub(super) fn sample(&mut self, out: &mut RunOutput, s: Sample) -> Result<(), SimError> {
        if s.t != self.r.last_t {
            self.r.last_t = s.t;
            if let Some(k) = self.sink.as_deref_mut() {
                k.sample(&s).map_err(SimError::Output)?;
            }
            if self.r.keep {
                out.samples.push(s.clone());
            }
        }
        out.last = s;
        Ok(())
    }

    pub(super) fn switch(&mut self, out: &mut RunOutput, sw: SwitchRecord) -> Result<(), SimError> {
        out.switches.push(sw);
        if let Some(k) = self.sink.as_deref_mut() {
            let name = out.mode_names.get(sw.to).copied().unwrap_or("none");
            k.switch(&sw, name).map_err(SimError::Output)?;
        }
        Ok(())
    }

    pub(super) fn next(&self) -> f64 {
        (self.r.k + 1) as f64 * self.r.rec
    }

    /// Whether the next record instant is `t` (to rounding of `k·rec`).
    pub(super) fn due_at(&self, t: f64) -> bool {
        self.r.rec > 0.0 && (self.next() - t).abs() <= 1e-9 * self.r.rec
    }

    /// Samples the state itself when the next record instant is `t`.
    pub(super) fn exact<B: Backend, const N: usize>(
        &mut self,
        out: &mut RunOutput,
        sys: &mut ClosedLoop<'_, '_, B, N>,
        t: f64,
        y: &State<B, N>,
    ) -> Result<(), SimError> {
        if self.due_at(t) {
            // Labelled with the instant `k·rec` itself, from which `t`
            // differs by the rounding of the step grid at most.
            let tk = self.next();
            self.r.k += 1;
            let s = sample(sys, tk, y)?;
            self.sample(out, s)?;
        }
        Ok(())
    }

    /// At a checkpoint, after what happens there: the sample of a record
    /// instant that falls on it, and the run's last sample at the end.
    pub(super) fn at_checkpoint<B: Backend, const N: usize>(
        &mut self,
        out: &mut RunOutput,
        sys: &mut ClosedLoop<'_, '_, B, N>,
        t: f64,
        y: &State<B, N>,
        end: bool,
    ) -> Result<(), SimError> {
        if self.due_at(t) {
            self.exact(out, sys, t, y)
        } else if end {
            let s = sample(sys, t, y)?;
            self.sample(out, s)
        } else {
            Ok(())
        }
    }

    /// Samples every record instant strictly inside the step from
    /// `(t0, y0)` to `(t1, y1)` from its continuous extension (for an
    /// adaptive stepper, by integrating a copy of it from `t0`: see
    /// [`Integrator::resampler`]). The loads evaluated for it are not
    /// counted in the run's evaluations, which stay the same with and
    /// without recording; the stepper itself is not touched.
    pub(super) fn inside<B: Backend, const N: usize, I: Integrator<B, N>>(
        &mut self,
        out: &mut RunOutput,
        sys: &mut ClosedLoop<'_, '_, B, N>,
        stepper: &I,
        (t0, y0): (f64, &State<B, N>),
        (t1, y1): (f64, &State<B, N>),
    ) -> Result<(), SimError> {
        if self.r.rec <= 0.0 || self.next() >= t1 - 1e-9 * self.r.rec {
            return Ok(());
        }
        let l = S::<B>::lit;
        let counted = sys.evaluations;
        // An adaptive stepper re-integrates a copy of itself; a one-step
        // method interpolates between the end states and their rates.
        let mut ext = match stepper.resampler() {
            Some(copy) => Extension::Redo(copy),
            None => {
                let (l0, l1) = (sys.load(l(t0), y0), sys.load(l(t1), y1));
                sys.evaluations = counted;
                if let Some(source) = sys.error.take() {
                    return Err(SimError::Control { t: t0, source });
                }
                Extension::Hermite(
                    dense::Rates::of(sys, y0, &l0),
                    dense::Rates::of(sys, y1, &l1),
                )
            }
        };
        let h = t1 - t0;
        while self.next() < t1 - 1e-9 * self.r.rec {
            let tk = self.next();
            self.r.k += 1;
            let y = match &mut ext {
                Extension::Redo(c) => {
                    let mut y = *y0;
                    c.reset();
                    let stepped = c.step(sys, l(t0), l(tk - t0), &mut y);
                    sys.evaluations = counted;
                    stepped.map_err(|e| sys.step_error(t0, tk - t0, e))?;
                    y
                }
                Extension::Hermite(r0, r1) => {
                    dense::interpolate(y0, r0, y1, r1, l(h), l((tk - t0) / h))
                }
            };
            let s = sample(sys, tk, &y)?;
            self.sample(out, s)?;
        }
        Ok(())
    }
}

/// How samples inside a step are made: by re-integrating a copy of an
/// adaptive stepper, or from the cubic Hermite extension through the end
/// states and their rates.
pub(super) enum Extension<B: Backend, const N: usize, I> {
    Redo(I),
    Hermite(dense::Rates<B, N>, dense::Rates<B, N>),
}
