//! The phases of a flight from the ground and back: take-off to a height at
//! a bounded climb rate, hover, landing at a bounded descent rate, and the
//! motors cut once down. Each is the paper's position law (eqn:f, eqn:M)
//! on a vertical reference anchored where the phase starts, so a scheduler
//! chains them with any other mode: take-off → waypoints → land → motors
//! off.
//!
//! The vertical moves are smooth to the fourth derivative, as the law's
//! exact `Ω_c`, `Ω̇_c` need: a climb follows the degree-9 step
//! `p(τ) = τ⁵(126 − 420τ + 540τ² − 315τ³ + 70τ⁴)`, whose first four
//! derivatives vanish at both ends, over the time that makes its peak speed
//! the given rate; a descent ramps its speed up along the same step and then
//! keeps it, without end, until the scheduler leaves the phase (at a
//! touchdown, or a height above the ground).

use crate::mode::{IntegralLayout, Mode, ModeOutput, PositionMode, PositionSource, sealed};
use crate::position_pid::{
    AccelerationModel, PositionGains, PositionReference, SatBranch, VehicleState,
};
use crate::{AttitudeGains, ControlError, RigidBodyParams};
use lie::ops::zero;
use lie::{Backend, Real, Rotation, S, So3Mat, V3};

/// `p′(½)`, the degree-9 step's peak slope, 315/128.
const PEAK_SLOPE: f64 = 315.0 / 128.0;

/// The degree-9 step's integral `∫₀^τ p` at `τ ∈ [0, 1]`, and the step
/// with its first four derivatives in `τ`, `[p, p′, p″, p‴, p⁗]`.
fn step<T: Real>(tau: T) -> (T, [T; 5]) {
    let l = T::lit;
    let t = tau;
    let t2 = t * t;
    let t3 = t2 * t;
    let t4 = t2 * t2;
    let t5 = t4 * t;
    let u = l(1.0) - t;
    let u2 = u * u;
    let p = t5 * (l(126.0) + t * (l(-420.0) + t * (l(540.0) + t * (l(-315.0) + t * l(70.0)))));
    let p1 = l(630.0) * t4 * u2 * u2;
    let p2 = l(2520.0) * t3 * u2 * u * (l(1.0) - l(2.0) * t);
    let p3 = l(2520.0) * t2 * u2 * (l(3.0) - l(14.0) * t + l(14.0) * t2);
    let p4 = l(15120.0) * t * u * (l(1.0) - l(2.0) * t) * (l(1.0) - l(7.0) * t + l(7.0) * t2);
    let integral =
        t5 * t * (l(21.0) + t * (l(-60.0) + t * (l(67.5) + t * (l(-35.0) + t * l(7.0)))));
    (integral, [p, p1, p2, p3, p4])
}

/// A vertical move relative to where a phase starts (e3 points down, so a
/// climb moves along `−e3`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Vertical<B: Backend> {
    /// Rise by `height`, m, at a speed that peaks at `rate`, m/s, then
    /// hold; the climb lasts `315/128 · height / rate`.
    Climb {
        /// How far up, m (positive).
        height: S<B>,
        /// The peak climb speed, m/s (positive).
        rate: S<B>,
    },
    /// Hold the start.
    Hold,
    /// Descend at `rate`, m/s, reached along the step over `ramp`, s, then
    /// kept without end (peak acceleration `315/128 · rate / ramp`).
    Descend {
        /// The descent speed, m/s (positive).
        rate: S<B>,
        /// How long the speed takes to build up, s (positive).
        ramp: S<B>,
    },
}

impl<B: Backend> Vertical<B> {
    /// The offset along e3 from the start and its first four derivatives
    /// at `s` seconds after the start (zero before it).
    pub fn offset(&self, s: S<B>) -> [S<B>; 5] {
        let l = S::<B>::lit;
        let z = l(0.0);
        if s <= z {
            return [z; 5];
        }
        match *self {
            Vertical::Hold => [z; 5],
            Vertical::Climb { height, rate } => {
                let duration = l(PEAK_SLOPE) * height / rate;
                if s >= duration {
                    return [-height, z, z, z, z];
                }
                let (_, p) = step(s / duration);
                let mut k = -height;
                let mut out = [z; 5];
                for (o, d) in out.iter_mut().zip(p) {
                    *o = k * d;
                    k /= duration;
                }
                out
            }
            Vertical::Descend { rate, ramp } => {
                if s >= ramp {
                    return [rate * (ramp * l(0.5) + (s - ramp)), rate, z, z, z];
                }
                let (integral, p) = step(s / ramp);
                let mut out = [rate * ramp * integral, z, z, z, z];
                let mut k = rate;
                for (o, d) in out[1..].iter_mut().zip(p) {
                    *o = k * d;
                    k /= ramp;
                }
                out
            }
        }
    }

    /// Checks the numbers: `(field, value)` of the first that is not
    /// finite and positive.
    pub fn check(&self) -> Result<(), (&'static str, f64)> {
        let bad = |v: S<B>| !(v.is_finite() && v > S::<B>::lit(0.0));
        let f = |v: S<B>| v.to_f64_lossless();
        match *self {
            Vertical::Hold => Ok(()),
            Vertical::Climb { height, .. } if bad(height) => Err(("height", f(height))),
            Vertical::Climb { rate, .. } | Vertical::Descend { rate, .. } if bad(rate) => {
                Err(("rate", f(rate)))
            }
            Vertical::Descend { ramp, .. } if bad(ramp) => Err(("ramp", f(ramp))),
            _ => Ok(()),
        }
    }
}

/// A [`Vertical`] move anchored at a start position, time and heading: the
/// reference of a [`FlightPhase`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct VerticalReference<B: Backend> {
    /// The move.
    pub vertical: Vertical<B>,
    /// Where it starts, m.
    pub start: V3<B>,
    /// When it starts, s.
    pub t0: S<B>,
    /// The heading held, `b1d`.
    pub b1d: V3<B>,
}

impl<B: Backend> VerticalReference<B> {
    /// `vertical` from `state` at `t0`, facing the horizontal part of the
    /// body's `b1` (`e1` when `b1` is vertical).
    pub fn from_state(vertical: Vertical<B>, state: &VehicleState<B, So3Mat<B>>, t0: S<B>) -> Self {
        let l = S::<B>::lit;
        let [b1, _, _] = B::mat3_cols(state.r.matrix());
        let [c, s, _] = B::vec3_to_array(b1);
        let n = (c * c + s * s).sqrt();
        let b1d = if n > l(1e-6) {
            B::vec3(c / n, s / n, l(0.0))
        } else {
            B::vec3(l(1.0), l(0.0), l(0.0))
        };
        Self {
            vertical,
            start: state.x,
            t0,
            b1d,
        }
    }
}

impl<B: Backend> PositionSource<B> for VerticalReference<B> {
    fn position(&self, t: S<B>) -> PositionReference<B> {
        let l = S::<B>::lit;
        let [z0, z1, z2, z3, z4] = self.vertical.offset(t - self.t0);
        let e3 = |c: S<B>| B::vec3(l(0.0), l(0.0), c);
        PositionReference {
            x: self.start + e3(z0),
            v: e3(z1),
            a: e3(z2),
            jerk: e3(z3),
            snap: e3(z4),
            ..PositionReference::hold(self.start, self.b1d)
        }
    }
}

/// Take-off, hover or landing: the paper's position law tracking a
/// [`Vertical`] move that starts where the phase is entered. Integral
/// layout `[e_I, e_i]`, as [`PositionMode`]'s; a take-off zeroes `e_i` on
/// entry (the vehicle starts from the ground), a hover or landing keeps it
/// (the disturbance it has learnt still acts).
pub struct FlightPhase<B: Backend> {
    name: &'static str,
    law: PositionMode<B, VerticalReference<B>>,
}

impl<B: Backend> FlightPhase<B> {
    /// `vertical` from `start` at `t0` (the phase's own start when it is a
    /// plan's first; a switch into it re-anchors it), named
    /// `"take-off"`, `"hover"` or `"land"` after the move.
    pub fn new(
        params: RigidBodyParams<B>,
        gains: (PositionGains<B>, AttitudeGains<B>),
        model: AccelerationModel<B>,
        vertical: Vertical<B>,
        start: (&VehicleState<B, So3Mat<B>>, S<B>),
    ) -> Self {
        let reference = VerticalReference::from_state(vertical, start.0, start.1);
        let law = PositionMode::new(params, gains.0, gains.1, model, reference);
        let (name, law) = match vertical {
            Vertical::Climb { .. } => ("take-off", law),
            Vertical::Hold => ("hover", law.keep_integral_on_entry()),
            Vertical::Descend { .. } => ("land", law.keep_integral_on_entry()),
        };
        Self { name, law }
    }

    /// The reference tracked now.
    pub fn reference(&self) -> &VerticalReference<B> {
        self.law.reference()
    }
}

impl<B: Backend> Mode<B> for FlightPhase<B> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        self.law.integrals()
    }
    fn enter(&mut self, t: S<B>, state: &VehicleState<B, So3Mat<B>>, integrals: &mut [S<B>]) {
        let vertical = self.law.reference().vertical;
        *self.law.reference_mut() = VerticalReference::from_state(vertical, state, t);
        self.law.enter(t, state, integrals);
    }
    #[inline]
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        self.law.command(t, state, integrals, rates)
    }
    fn force_branch(&mut self, index: usize, branch: SatBranch) {
        self.law.force_branch(index, branch)
    }
    fn update_outer(
        &mut self,
        sealed: sealed::Token,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
    ) -> Result<(), ControlError> {
        self.law.update_outer(sealed, t, state, integrals)
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        self.law.desired_position(t)
    }
}

/// The motors cut: no thrust and no moment, whatever the state (after a
/// touchdown, so that the vehicle settles on its feet). No integral states.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct MotorsOff;

impl<B: Backend> Mode<B> for MotorsOff {
    fn name(&self) -> &'static str {
        "motors-off"
    }
    fn command(
        &self,
        _t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        _integrals: &[S<B>],
        _rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        Ok(ModeOutput {
            thrust: S::<B>::lit(0.0),
            moment: zero::<B>(),
            desired: state.r,
            desired_omega: state.omega,
            psi: S::<B>::lit(0.0),
            rotor_speeds: None,
        })
    }
}

#[cfg(test)]
mod tests;
