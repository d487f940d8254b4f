//! A scene's references as the sources its modes read.

use controllers::{AttitudeReference, AttitudeSource, PositionReference, PositionSource};
use lie::{Backend, Real, S, So3Mat, ops};
use missions::Trajectory;

use crate::reference::{self, m};
use crate::scene::{AttitudeRef, PositionRef};

/// A scene's attitude reference as an [`AttitudeSource`](controllers::AttitudeSource): a constant one is
/// computed once, the others are evaluated (in f64) per call.
pub enum SceneAttitude<B: Backend> {
    /// A constant reference.
    Const(AttitudeReference<B, So3Mat<B>>),
    /// A generator of [`crate::reference`].
    Generated(AttitudeRef),
}

impl<B: Backend> SceneAttitude<B> {
    /// The source for `r`.
    pub fn new(r: &AttitudeRef) -> Self {
        match r {
            AttitudeRef::Hold { rotation } => SceneAttitude::Const(AttitudeReference {
                rd: m::<B>(reference::rotation_f64(*rotation)),
                omega_d: ops::zero::<B>(),
                omega_d_dot: ops::zero::<B>(),
            }),
            other => SceneAttitude::Generated(other.clone()),
        }
    }
}

impl<B: Backend> AttitudeSource<B> for SceneAttitude<B> {
    #[inline]
    fn attitude(&self, t: S<B>) -> AttitudeReference<B, So3Mat<B>> {
        match self {
            SceneAttitude::Const(r) => *r,
            SceneAttitude::Generated(a) => reference::attitude::<B>(a, t),
        }
    }
}

/// A scene's position reference as a [`PositionSource`](controllers::PositionSource): a hold is
/// converted once, a generator evaluated (in f64) per call; logs read
/// `x_d` in f64 either way.
pub enum ScenePosition<B: Backend> {
    /// A constant reference, with its f64 position for the logs.
    Const(PositionReference<B>, [f64; 3]),
    /// A generator of [`crate::reference`].
    Generated(PositionRef),
    /// A planned trajectory (minimum-snap or a trajectory file) and the
    /// time it starts.
    Planned(Trajectory, f64),
}

impl<B: Backend> ScenePosition<B> {
    /// The source for `p`; a planned reference is planned here, once.
    ///
    /// # Panics
    /// If `p` is a planned reference that [`PositionRef::plan`] refuses:
    /// validate the scene first, as every run does.
    pub fn new(p: &PositionRef) -> Self {
        match p {
            PositionRef::MinSnap { .. } | PositionRef::TrajectoryFile { .. } => match p.plan() {
                Ok(Some((t, start))) => ScenePosition::Planned(t, start),
                Ok(None) => unreachable!("a planned reference plans"),
                Err(e) => panic!("position reference not validated: {e}"),
            },
            PositionRef::Hold { .. } => {
                ScenePosition::Const(reference::position::<B>(p, S::<B>::lit(0.0)), {
                    reference::position_f64(p, 0.0).0[0]
                })
            }
            other => ScenePosition::Generated(other.clone()),
        }
    }
}

/// A planned trajectory at `t`: out of line, so that the curves' arms
/// stay inlined into the law.
#[inline(never)]
fn planned<B: Backend>(tr: &Trajectory, start: f64, t: S<B>) -> PositionReference<B> {
    tr.position(t - S::<B>::lit(start))
}

impl<B: Backend> PositionSource<B> for ScenePosition<B> {
    // Inlined into the law, as before the planned arm was added (which
    // made it large enough to stay out of line at a call per load).
    #[inline(always)]
    fn position(&self, t: S<B>) -> PositionReference<B> {
        match self {
            ScenePosition::Const(r, _) => *r,
            ScenePosition::Generated(p) => reference::curve::<B>(p, t),
            ScenePosition::Planned(tr, start) => planned::<B>(tr, *start, t),
        }
    }
    #[inline]
    fn constant(&self) -> Option<&PositionReference<B>> {
        match self {
            ScenePosition::Const(r, _) => Some(r),
            ScenePosition::Generated(_) | ScenePosition::Planned(..) => None,
        }
    }
    fn position_f64(&self, t: f64) -> [f64; 3] {
        match self {
            ScenePosition::Const(_, x) => *x,
            ScenePosition::Generated(p) => reference::position_f64(p, t).0[0],
            ScenePosition::Planned(tr, start) => tr.flat(t - start).x[0],
        }
    }
}

impl<B: Backend> PositionSource<B> for PositionRef {
    #[inline]
    fn position(&self, t: S<B>) -> PositionReference<B> {
        reference::position::<B>(self, t)
    }
    fn position_f64(&self, t: f64) -> [f64; 3] {
        reference::position_f64(self, t).0[0]
    }
}
