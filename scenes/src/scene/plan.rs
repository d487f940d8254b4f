//! `[[plan]]`: the flight-mode segments and when each ends.

use controllers::Vertical;
use lie::{Backend, Real, S};
use serde::{Deserialize, Serialize};

use super::{AttitudeRef, PositionRef};

/// One flight-mode segment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// `attitude`, `position`, `take-off`, `hover`, `land` or
    /// `motors-off`.
    pub mode: ModeKind,
    /// End time, s (absolute); absent for the last segment.
    #[serde(default)]
    pub until: Option<f64>,
    /// Or: leave the segment when Ψ against its desired attitude drops
    /// below this (0 < value < 2); the crossing is located to rounding.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_psi: Option<f64>,
    /// Attitude reference (attitude mode).
    #[serde(default)]
    pub attitude: Option<AttitudeRef>,
    /// Position reference (position mode; in attitude mode, the target of
    /// the `pd-projection` thrust).
    #[serde(default)]
    pub position: Option<PositionRef>,
    /// Thrust in attitude mode.
    #[serde(default)]
    pub thrust: ThrustSpec,
    /// Or: leave the segment when every foot is at most this far above
    /// the `[ground]`, m (0: when the last foot touches); located like
    /// `until_psi`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_clearance: Option<f64>,
    /// `take-off`: how far to climb from where the segment starts, m
    /// (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// `take-off`: the peak climb speed, m/s (default 0.5); `land`: the
    /// descent speed (default 0.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
    /// `land`: how long the descent speed takes to build up, s (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp: Option<f64>,
}

impl SegmentSpec {
    /// Position mode towards `reference`, with no end.
    pub fn position(reference: PositionRef) -> Self {
        Self {
            mode: ModeKind::Position,
            until: None,
            until_psi: None,
            until_clearance: None,
            height: None,
            rate: None,
            ramp: None,
            attitude: None,
            position: Some(reference),
            thrust: ThrustSpec::Hover,
        }
    }

    /// Attitude mode tracking `reference` with `thrust`, with no end.
    pub fn attitude(reference: AttitudeRef, thrust: ThrustSpec) -> Self {
        Self {
            mode: ModeKind::Attitude,
            until: None,
            until_psi: None,
            until_clearance: None,
            height: None,
            rate: None,
            ramp: None,
            attitude: Some(reference),
            position: None,
            thrust,
        }
    }

    /// The same segment, ending at time `t`, s (absolute).
    pub fn until(self, t: f64) -> Self {
        Self {
            until: Some(t),
            ..self
        }
    }

    /// The same segment, ending when Ψ drops below `psi`.
    pub fn until_psi(self, psi: f64) -> Self {
        Self {
            until_psi: Some(psi),
            ..self
        }
    }

    /// A segment of `mode` (`take-off`, `hover`, `land`, `motors-off`:
    /// they need no reference) with the default height and rates, with no
    /// end.
    pub fn phase(mode: ModeKind) -> Self {
        Self {
            mode,
            until: None,
            until_psi: None,
            attitude: None,
            position: None,
            thrust: ThrustSpec::Hover,
            until_clearance: None,
            height: None,
            rate: None,
            ramp: None,
        }
    }

    /// The same segment, ending when every foot is at most `clearance`
    /// above the ground, m.
    pub fn until_clearance(self, clearance: f64) -> Self {
        Self {
            until_clearance: Some(clearance),
            ..self
        }
    }

    /// The vertical move of a `take-off`, `hover` or `land` segment, its
    /// defaults filled in (`None` for another mode).
    pub fn vertical<B: Backend>(&self) -> Option<Vertical<B>> {
        let l = S::<B>::lit;
        match self.mode {
            ModeKind::TakeOff => Some(Vertical::Climb {
                height: l(self.height.unwrap_or(1.0)),
                rate: l(self.rate.unwrap_or(0.5)),
            }),
            ModeKind::Hover => Some(Vertical::Hold),
            ModeKind::Land => Some(Vertical::Descend {
                rate: l(self.rate.unwrap_or(0.3)),
                ramp: l(self.ramp.unwrap_or(1.0)),
            }),
            _ => None,
        }
    }

    /// The same attitude segment with `position` as the target of its
    /// `pd-projection` thrust.
    pub fn toward(self, position: PositionRef) -> Self {
        Self {
            position: Some(position),
            ..self
        }
    }
}

/// Flight mode.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModeKind {
    /// Attitude tracking (eqn:aM).
    Attitude,
    /// Position tracking (eqn:f, eqn:M).
    Position,
    /// Climb `height` from where the segment starts, at most at `rate`;
    /// zeroes `e_i` on entry.
    TakeOff,
    /// Hold where the segment starts.
    Hover,
    /// Descend at `rate` from where the segment starts, without end (leave
    /// it `until_clearance`).
    Land,
    /// No thrust and no moment.
    MotorsOff,
}

impl ModeKind {
    /// The name a scene file gives it.
    pub fn name(self) -> &'static str {
        match self {
            ModeKind::Attitude => "attitude",
            ModeKind::Position => "position",
            ModeKind::TakeOff => "take-off",
            ModeKind::Hover => "hover",
            ModeKind::Land => "land",
            ModeKind::MotorsOff => "motors-off",
        }
    }
}

/// Attitude-mode thrust.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ThrustSpec {
    /// m g.
    #[default]
    Hover,
    /// f = (k_x e_x + k_v e_v + m g e3 − m ẍ_d)·R e3 towards the segment's
    /// position reference (the paper's flip).
    PdProjection,
}
