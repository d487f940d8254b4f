//! Flight modes as a trait: the paper's attitude and position PID are two
//! implementations of [`Mode`], and a user's own law (a landing mode, a
//! rate mode, a different attitude controller) is a third, scheduled and
//! simulated the same way.
//!
//! # Integral states
//! A mode owns no hidden state that a simulation must integrate: it reads
//! its integral states from a slice the caller holds and writes their time
//! derivatives into another, so continuous control (integrate the rates with
//! the vehicle) and sampled control (multiply by the period) both work.
//! Every mode of a plan sees the *same* register of integral states, slots
//! `0..integrals().count`; what one mode leaves there is what the next one
//! finds. What carries across a switch is therefore the modes' decision,
//! made in [`Mode::enter`]: the paper's two modes share the layout
//! `[e_I (3), e_i (3)]`, so the attitude integral `e_I` carries across every
//! switch, and [`PositionMode`] zeroes `e_i` when it is entered (as the
//! paper's scheduler does when position mode first starts).
//!
//! # References
//! References are anything implementing [`AttitudeSource`] or
//! [`PositionSource`]; every closure `Fn(t) -> AttitudeReference` or
//! `Fn(t) -> PositionReference` is one, so a spline or a recorded path
//! needs no new type.

use crate::attitude_pid::{AttitudeGains, AttitudeReference, attitude_control};
use crate::position_pid::{
    AccelerationModel, PositionGains, PositionReference, SatBranch, VehicleState, position_control,
    thrust_pd_projection,
};
use crate::{ControlError, RigidBodyParams};
use lie::ops::zero;
use lie::{Backend, Real, Rotation, S, So3Mat, V3};

/// `t ↦ (R_d, Ω_d, Ω̇_d)`: the reference of an attitude-tracking law. Any
/// closure `Fn(t) -> AttitudeReference` is one.
///
/// ```
/// use controllers::{AttitudeReference, AttitudeSource};
/// use lie::{Backend, NalgebraF64, Rotation, So3Mat};
/// type B = NalgebraF64;
///
/// // A constant yaw rate of 0.5 rad/s about e3.
/// let spin = |t: f64| AttitudeReference {
///     rd: So3Mat::<B>::exp(B::vec3(0.0, 0.0, 0.5 * t)),
///     omega_d: B::vec3(0.0, 0.0, 0.5),
///     omega_d_dot: B::vec3(0.0, 0.0, 0.0),
/// };
/// let r = AttitudeSource::<B>::attitude(&spin, 2.0);
/// assert!((r.rd.log()[2] - 1.0).abs() < 1e-15);
/// ```
pub trait AttitudeSource<B: Backend, R: Rotation<B> = So3Mat<B>> {
    /// The reference at time `t`.
    fn attitude(&self, t: S<B>) -> AttitudeReference<B, R>;
}

impl<B: Backend, R: Rotation<B>, F: Fn(S<B>) -> AttitudeReference<B, R>> AttitudeSource<B, R>
    for F
{
    #[inline]
    fn attitude(&self, t: S<B>) -> AttitudeReference<B, R> {
        self(t)
    }
}

/// `t ↦ (x_d … x_d⁽⁴⁾, b1d, ḃ1d, b̈1d)`: the reference of a position law.
/// Any closure `Fn(t) -> PositionReference` is one.
///
/// ```
/// use controllers::{PositionReference, PositionSource};
/// use lie::{Backend, NalgebraF64};
/// type B = NalgebraF64;
///
/// // Climb at 1 m/s (e3 points down), heading e1.
/// let climb = |t: f64| {
///     let mut r = PositionReference::<B>::hold(B::vec3(0.0, 0.0, -t), B::vec3(1.0, 0.0, 0.0));
///     r.v = B::vec3(0.0, 0.0, -1.0);
///     r
/// };
/// assert_eq!(climb.position_f64(3.0), [0.0, 0.0, -3.0]);
/// ```
pub trait PositionSource<B: Backend> {
    /// The reference at time `t`.
    fn position(&self, t: S<B>) -> PositionReference<B>;
    /// `x_d(t)` in f64, for logs and metrics. The default converts
    /// [`PositionSource::position`]; a source that can evaluate in f64
    /// overrides it so that an f32 run still logs an exact `x_d`.
    fn position_f64(&self, t: f64) -> [f64; 3] {
        B::vec3_to_array(self.position(S::<B>::lit(t)).x).map(|c| c.to_f64_lossless())
    }
    /// The reference, if it does not depend on time: [`PositionMode`] then
    /// reads it where it lies instead of a copy from
    /// [`PositionSource::position`]. More than a copy is saved: the law
    /// loads the 24-byte vectors of an f64 reference in 16-byte pairs,
    /// which straddle the stores of a copy made just before and miss store
    /// forwarding. The
    /// default, `None`, asks `position` at every evaluation.
    #[inline]
    fn constant(&self) -> Option<&PositionReference<B>> {
        None
    }
}

impl<B: Backend, F: Fn(S<B>) -> PositionReference<B>> PositionSource<B> for F {
    #[inline]
    fn position(&self, t: S<B>) -> PositionReference<B> {
        self(t)
    }
}

/// A constant position reference (hover at `x` facing `b1d`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct HoldPosition<B: Backend>(pub PositionReference<B>);

impl<B: Backend> PositionSource<B> for HoldPosition<B> {
    #[inline]
    fn position(&self, _t: S<B>) -> PositionReference<B> {
        self.0
    }
    #[inline]
    fn constant(&self) -> Option<&PositionReference<B>> {
        Some(&self.0)
    }
}

/// A constant attitude reference (`Ω_d = Ω̇_d = 0`), computed once.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct HoldAttitude<B: Backend, R: Rotation<B> = So3Mat<B>>(pub AttitudeReference<B, R>);

impl<B: Backend, R: Rotation<B>> HoldAttitude<B, R> {
    /// Hold `rd`.
    pub fn new(rd: R) -> Self {
        Self(AttitudeReference {
            rd,
            omega_d: zero::<B>(),
            omega_d_dot: zero::<B>(),
        })
    }
}

impl<B: Backend, R: Rotation<B>> AttitudeSource<B, R> for HoldAttitude<B, R> {
    #[inline]
    fn attitude(&self, _t: S<B>) -> AttitudeReference<B, R> {
        self.0
    }
}

/// The most rotor speeds a mode may command (a vehicle with more rotors
/// takes a wrench).
pub const MAX_ROTORS: usize = 16;

/// Rotor speeds a mode commands instead of its wrench, rad/s, one per
/// rotor in the vehicle's order.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RotorSpeeds<B: Backend> {
    speeds: [S<B>; MAX_ROTORS],
    count: usize,
}

impl<B: Backend> RotorSpeeds<B> {
    /// The speeds in `speeds`; `None` for more than [`MAX_ROTORS`].
    pub fn new(speeds: &[S<B>]) -> Option<Self> {
        let mut buf = [S::<B>::lit(0.0); MAX_ROTORS];
        buf.get_mut(..speeds.len())?.copy_from_slice(speeds);
        Some(Self {
            speeds: buf,
            count: speeds.len(),
        })
    }
    /// The speeds, one per rotor.
    pub fn as_slice(&self) -> &[S<B>] {
        &self.speeds[..self.count]
    }
}

/// What a mode commands and what the logs show of it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ModeOutput<B: Backend, R: Rotation<B> = So3Mat<B>> {
    /// Total thrust `f` along `−b3`, N.
    pub thrust: S<B>,
    /// Body moment `M`, N m.
    pub moment: V3<B>,
    /// The desired attitude the law tracks (`R_d`, or `R_c` in position
    /// mode); the identity-free choice for a law without one is the current
    /// attitude.
    pub desired: R,
    /// Its angular velocity (`Ω_d` or `Ω_c`), desired body frame.
    pub desired_omega: V3<B>,
    /// `Ψ(R, desired)`: what `until_psi` switches compare.
    pub psi: S<B>,
    /// Rotor speeds to command *instead of* the wrench (`None`: the
    /// wrench is the command): for a law of another family that outputs
    /// rotor speeds (RotorPy's `SE3Control`), or a recorded sequence
    /// replayed open loop. The vehicle must take rotor-speed commands, else
    /// the run stops with [`ControlError::RotorSpeedsUnsupported`]; the
    /// thrust, moment and desired attitude are still what the logs show.
    pub rotor_speeds: Option<RotorSpeeds<B>>,
}

/// A breakpoint of a law's vector field: the law is discontinuous where
/// `|integrals[slot]|` crosses `level` (the paper's `sat′_σ` at `|e_i| = σ`).
/// A simulation locates such crossings and integrates each side on its own
/// branch (see [`Mode::force_branch`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Breakpoint<B: Backend> {
    /// Index in the integral register.
    pub slot: usize,
    /// The magnitude at which the law switches branch.
    pub level: S<B>,
}

/// The integral register a mode reads: how many slots, and the levels on
/// them where the law switches branch.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct IntegralLayout<'a, B: Backend> {
    /// Slots `0..count` of the plan's shared register.
    pub count: usize,
    /// Where the law is discontinuous (none for most laws).
    pub breakpoints: &'a [Breakpoint<B>],
}

impl<B: Backend> IntegralLayout<'_, B> {
    /// `count` slots and no breakpoints.
    pub const fn slots(count: usize) -> Self {
        Self {
            count,
            breakpoints: &[],
        }
    }
}

/// A flight mode: a control law with its references.
///
/// Object safe: a plan is a list of `Box<dyn Mode<B>>`. Only
/// [`Mode::name`] and [`Mode::command`] are required; rotor-speed
/// commanding is a variant of the output ([`ModeOutput::rotor_speeds`]),
/// not a method.
///
/// [`Mode::command`] takes `&self`: its answer is a function of the time,
/// the state, the integrals and the mode's configuration alone. A
/// simulation asks it at every stage of a step, again for each sample and
/// for the run's figures, a number of times that depends on what is
/// recorded, and may reuse an answer at the same point instead of asking
/// twice. What a mode may change is its configuration, at the two moments
/// the loop names: [`Mode::enter`] (where the mode starts from) and
/// [`Mode::force_branch`] (which side of a breakpoint it is on).
///
/// # Example
/// A mode of one's own: hold the current attitude with a thrust that
/// cancels the weight and no moment (no integral states).
///
/// ```
/// use controllers::{ControlError, Mode, ModeOutput, VehicleState};
/// use lie::{Backend, GlamF64, Rotation, So3Mat, S};
/// type B = GlamF64;
///
/// struct Float { weight: f64 }
///
/// impl Mode<B> for Float {
///     fn name(&self) -> &'static str {
///         "float"
///     }
///     fn command(
///         &self,
///         _t: S<B>,
///         state: &VehicleState<B, So3Mat<B>>,
///         _integrals: &[S<B>],
///         _rates: &mut [S<B>],
///     ) -> Result<ModeOutput<B>, ControlError> {
///         Ok(ModeOutput {
///             thrust: self.weight,
///             moment: B::vec3(0.0, 0.0, 0.0),
///             desired: state.r,
///             desired_omega: B::vec3(0.0, 0.0, 0.0),
///             psi: 0.0,
///             rotor_speeds: None,
///         })
///     }
/// }
///
/// let m: Box<dyn Mode<B>> = Box::new(Float { weight: 0.755 * 9.81 });
/// let zero = B::vec3(0.0, 0.0, 0.0);
/// let s = VehicleState { x: zero, v: zero, r: So3Mat::<B>::identity(), omega: zero };
/// let out = m.command(0.0, &s, &[], &mut [])?;
/// assert_eq!(out.thrust, 0.755 * 9.81);
/// assert_eq!(m.integrals().count, 0);
/// # Ok::<(), ControlError>(())
/// ```
pub trait Mode<B: Backend, R: Rotation<B> = So3Mat<B>> {
    /// Short name for logs (`"attitude"`, `"position"`, `"landing"`).
    fn name(&self) -> &'static str;
    /// The integral states the law reads and integrates (slots
    /// `0..count` of the plan's shared register) and its breakpoints on
    /// them; none by default.
    fn integrals(&self) -> IntegralLayout<'_, B> {
        IntegralLayout::slots(0)
    }
    /// Called when a scheduler switches *into* this mode at time `t` in
    /// `state` (not for the plan's first mode, whose integrals are the
    /// initial ones), with the whole register: zero what must not carry
    /// over, note where the mode starts from. The default keeps everything.
    fn enter(&mut self, _t: S<B>, _state: &VehicleState<B, R>, _integrals: &mut [S<B>]) {}
    /// The command at time `t` in `state`. `integrals` holds the law's
    /// `integrals().count` states; write their time derivatives into
    /// `rates` (same length, zeroed by the caller; an idle state keeps rate
    /// zero).
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, R>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B, R>, ControlError>;
    /// Forces the branch taken at breakpoint `index` of
    /// [`IntegralLayout::breakpoints`] ([`SatBranch::Auto`] lets the law
    /// decide from the state again).
    fn force_branch(&mut self, _index: usize, _branch: SatBranch) {}
    /// An outer instant of a multi-rate loop at time `t`: a cascaded law
    /// computes its outer loop here from `state` and `integrals` and keeps
    /// its output, which [`Mode::command`] then tracks until the next call
    /// ([`PositionMode`] holds `f, R_c, Ω_c, Ω̇_c` and the rate of `e_i`
    /// while its attitude law runs at every command). A loop calls it
    /// before `command` at the same instant and after [`Mode::enter`];
    /// a single-rate loop never calls it, and the law stays the paper's.
    /// The default does nothing: a law without an outer loop runs whole at
    /// every command. Not a method to implement, like
    /// [`Mode::load_command`]: the multi-rate hold belongs to this crate's
    /// cascaded laws, and a mode of yours runs whole at every command.
    #[doc(hidden)]
    fn update_outer(
        &mut self,
        _sealed: sealed::Token,
        _t: S<B>,
        _state: &VehicleState<B, R>,
        _integrals: &[S<B>],
    ) -> Result<(), ControlError> {
        Ok(())
    }
    /// The desired position at time `t` in f64, for logs (`x_d`, `‖e_x‖`),
    /// if the law has one.
    fn desired_position(&self, _t: f64) -> Option<[f64; 3]> {
        None
    }
    /// What a simulation's load evaluation reads of [`Mode::command`]: the
    /// thrust and moment, and the rotor speeds written into `speeds` when
    /// there are any. Not a method to implement: its parameter type cannot
    /// be named outside this crate, so every mode has this default, a copy
    /// of `command` per mode in which the compiler drops what a load does
    /// not read (the desired attitude and `Ψ`) even through `dyn Mode`.
    #[doc(hidden)]
    #[inline]
    fn load_command(
        &self,
        _sealed: sealed::Token,
        t: S<B>,
        state: &VehicleState<B, R>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
        speeds: &mut Option<RotorSpeeds<B>>,
    ) -> Result<(S<B>, V3<B>), ControlError> {
        let out = self.command(t, state, integrals, rates)?;
        if out.rotor_speeds.is_some() {
            *speeds = out.rotor_speeds;
        }
        Ok((out.thrust, out.moment))
    }
}

impl<B: Backend, R: Rotation<B>, M: Mode<B, R> + ?Sized> Mode<B, R> for &mut M {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        (**self).integrals()
    }
    fn enter(&mut self, t: S<B>, state: &VehicleState<B, R>, integrals: &mut [S<B>]) {
        (**self).enter(t, state, integrals)
    }
    #[inline]
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, R>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B, R>, ControlError> {
        (**self).command(t, state, integrals, rates)
    }
    fn force_branch(&mut self, index: usize, branch: SatBranch) {
        (**self).force_branch(index, branch)
    }
    fn update_outer(
        &mut self,
        sealed: sealed::Token,
        t: S<B>,
        state: &VehicleState<B, R>,
        integrals: &[S<B>],
    ) -> Result<(), ControlError> {
        (**self).update_outer(sealed, t, state, integrals)
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        (**self).desired_position(t)
    }
    #[inline]
    fn load_command(
        &self,
        sealed: sealed::Token,
        t: S<B>,
        state: &VehicleState<B, R>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
        speeds: &mut Option<RotorSpeeds<B>>,
    ) -> Result<(S<B>, V3<B>), ControlError> {
        (**self).load_command(sealed, t, state, integrals, rates, speeds)
    }
}

/// The key to [`Mode::load_command`]: public so that a simulation can call
/// it, in a private module so that no mode can override it.
pub(crate) mod sealed {
    /// Only this crate's [`token`](super::load_token) makes one.
    #[derive(Copy, Clone, Debug)]
    pub struct Token(pub(super) ());
}

/// The argument [`Mode::load_command`] is called with.
///
/// No mode outside this crate can override `load_command`, since its token's
/// type cannot be named; this fails to compile for that reason alone:
///
/// ```compile_fail
/// use controllers::{ControlError, Mode, ModeOutput, RotorSpeeds, VehicleState};
/// use lie::{Backend, GlamF64 as B, S, So3Mat, V3};
/// struct Sly;
/// impl Mode<B> for Sly {
///     fn name(&self) -> &'static str { "sly" }
///     fn command(&self, _: S<B>, s: &VehicleState<B, So3Mat<B>>, _: &[S<B>], _: &mut [S<B>])
///         -> Result<ModeOutput<B>, ControlError> {
///         let z = B::vec3(0.0, 0.0, 0.0);
///         Ok(ModeOutput { thrust: 1.0, moment: z, desired: s.r, desired_omega: z, psi: 0.0,
///             rotor_speeds: None })
///     }
///     fn load_command(&self, _: controllers::mode::sealed::Token, _: S<B>,
///         _: &VehicleState<B, So3Mat<B>>, _: &[S<B>], _: &mut [S<B>],
///         _: &mut Option<RotorSpeeds<B>>) -> Result<(S<B>, V3<B>), ControlError> {
///         Ok((2.0, B::vec3(0.0, 0.0, 0.0)))
///     }
/// }
/// ```
#[doc(hidden)]
#[inline(always)]
pub fn load_token() -> sealed::Token {
    sealed::Token(())
}

/// The first `K` entries of a register slice (a mode's documented layout;
/// a shorter slice is a caller bug).
#[inline(always)]
fn first<B: Backend, const K: usize>(s: &[S<B>]) -> &[S<B>; K] {
    s[..K]
        .try_into()
        .expect("integral register shorter than the mode's integral count")
}

#[inline(always)]
fn first_mut<B: Backend, const K: usize>(s: &mut [S<B>]) -> &mut [S<B>; K] {
    (&mut s[..K])
        .try_into()
        .expect("integral register shorter than the mode's integral count")
}

/// The thrust of an [`AttitudeMode`].
#[derive(Copy, Clone, Debug)]
pub enum AttitudeThrust<B: Backend, P> {
    /// A constant thrust, e.g. `m g`.
    Constant(S<B>),
    /// The position-PD projection `(k_x e_x + k_v e_v + m g e3 − m ẍ_d)·R e3`
    /// towards `reference` (the paper's flip).
    PdProjection {
        /// `k_x`, `k_v` are read from these.
        gains: PositionGains<B>,
        /// The position the thrust holds.
        reference: P,
    },
}

/// The paper's attitude-controlled flight mode (eqn:aM, eqn:eI) with a
/// thrust rule. Integral layout: `[e_I]` (3 slots); entering it keeps
/// `e_I` (it carries across the switch, as in the paper).
pub struct AttitudeMode<B: Backend, A, P = HoldPosition<B>> {
    params: RigidBodyParams<B>,
    gains: AttitudeGains<B>,
    reference: A,
    thrust: AttitudeThrust<B, P>,
}

impl<B: Backend, A: AttitudeSource<B>, P: PositionSource<B>> AttitudeMode<B, A, P> {
    /// Track `reference` with `gains`, thrust by `thrust`.
    pub fn new(
        params: RigidBodyParams<B>,
        gains: AttitudeGains<B>,
        reference: A,
        thrust: AttitudeThrust<B, P>,
    ) -> Self {
        Self {
            params,
            gains,
            reference,
            thrust,
        }
    }
}

impl<B: Backend, A: AttitudeSource<B>, P: PositionSource<B>> Mode<B> for AttitudeMode<B, A, P> {
    fn name(&self) -> &'static str {
        "attitude"
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        IntegralLayout::slots(3)
    }
    #[inline(always)]
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        let r = self.reference.attitude(t);
        let [a0, a1, a2] = *first::<B, 3>(integrals);
        let e_att = B::vec3(a0, a1, a2);
        let out = attitude_control(&self.params, &self.gains, state.r, state.omega, e_att, &r)?;
        let f = match &self.thrust {
            AttitudeThrust::Constant(f) => *f,
            AttitudeThrust::PdProjection { gains, reference } => {
                thrust_pd_projection(&self.params, gains, state, &reference.position(t))
            }
        };
        *first_mut::<B, 3>(rates) = B::vec3_to_array(out.e_i_rate);
        Ok(ModeOutput {
            thrust: f,
            moment: out.moment,
            desired: r.rd,
            desired_omega: r.omega_d,
            psi: out.psi,
            rotor_speeds: None,
        })
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        match &self.thrust {
            AttitudeThrust::Constant(_) => None,
            AttitudeThrust::PdProjection { reference, .. } => Some(reference.position_f64(t)),
        }
    }
}

/// The paper's position-controlled flight mode (eqn:f, eqn:M) with the
/// computed attitude and its exact derivatives. Integral layout:
/// `[e_I (3), e_i (3)]`. Entering it zeroes `e_i` unless
/// [`PositionMode::keep_integral_on_entry`] was set; `e_I` carries over.
/// Its breakpoints are the three components of `e_i` at `±σ` (when any
/// `k_i > 0`: otherwise `sat′` does not reach the command).
///
/// In a multi-rate loop (`scenarios::Control::MultiRate`) the position law runs at
/// the outer instants and its output is held between them: the thrust
/// `f`, the computed attitude `R_c` with `Ω_c` and `Ω̇_c` (eqn:RdWc), and
/// the rate of `e_i`; at every command the attitude law (eqn:aM) tracks
/// the held `R_c` from the state then. When the outer instant is the
/// command's own, the moment is the single-rate law's, bit for bit.
pub struct PositionMode<B: Backend, P> {
    params: RigidBodyParams<B>,
    pos_gains: PositionGains<B>,
    att_gains: AttitudeGains<B>,
    model: AccelerationModel<B>,
    reference: P,
    reset_on_entry: bool,
    breakpoints: [Breakpoint<B>; 3],
    has_breakpoints: bool,
    /// The outer loop's output a multi-rate loop holds (`None`: the
    /// single-rate law).
    held: Option<HeldOuter<B>>,
}

/// What [`PositionMode`] holds between the outer instants of a multi-rate
/// loop.
#[derive(Copy, Clone, Debug, PartialEq)]
struct HeldOuter<B: Backend> {
    thrust: S<B>,
    /// `R_c, Ω_c, Ω̇_c`: the attitude law's reference.
    attitude: AttitudeReference<B, So3Mat<B>>,
    e_i_pos_rate: V3<B>,
}

impl<B: Backend, P: PositionSource<B>> PositionMode<B, P> {
    /// Track `reference` with the given gains and acceleration model.
    pub fn new(
        params: RigidBodyParams<B>,
        pos_gains: PositionGains<B>,
        att_gains: AttitudeGains<B>,
        model: AccelerationModel<B>,
        reference: P,
    ) -> Self {
        let z = S::<B>::lit(0.0);
        let has_breakpoints = B::vec3_to_array(pos_gains.k_i).iter().any(|k| *k > z);
        let level = pos_gains.sigma;
        Self {
            params,
            pos_gains,
            att_gains,
            model,
            reference,
            reset_on_entry: true,
            breakpoints: [3, 4, 5].map(|slot| Breakpoint { slot, level }),
            has_breakpoints,
            held: None,
        }
    }

    /// Keep `e_i` when this mode is entered (for a second position segment
    /// that continues the first one's integral).
    pub fn keep_integral_on_entry(mut self) -> Self {
        self.reset_on_entry = false;
        self
    }

    /// The reference tracked.
    pub(crate) fn reference(&self) -> &P {
        &self.reference
    }

    /// The reference, to re-anchor it (a flight phase on entry).
    pub(crate) fn reference_mut(&mut self) -> &mut P {
        &mut self.reference
    }
}

impl<B: Backend, P: PositionSource<B>> Mode<B> for PositionMode<B, P> {
    fn name(&self) -> &'static str {
        "position"
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        IntegralLayout {
            count: 6,
            breakpoints: if self.has_breakpoints {
                &self.breakpoints
            } else {
                &[]
            },
        }
    }
    fn enter(&mut self, _t: S<B>, _state: &VehicleState<B, So3Mat<B>>, integrals: &mut [S<B>]) {
        if self.reset_on_entry {
            integrals[3..6].fill(S::<B>::lit(0.0));
        }
        self.held = None;
    }
    #[inline(always)]
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        // One length check for the six slots, not six.
        let [a0, a1, a2, p0, p1, p2] = *first::<B, 6>(integrals);
        let (e_att, e_pos) = (B::vec3(a0, a1, a2), B::vec3(p0, p1, p2));
        if let Some(h) = &self.held {
            // A multi-rate loop asks once per control instant; the
            // continuous loop, at every load, never takes this path.
            core::hint::cold_path();
            return self.track_held(h, state, e_att, rates);
        }
        let fresh;
        let reference = match self.reference.constant() {
            Some(held) => held,
            None => {
                fresh = self.reference.position(t);
                &fresh
            }
        };
        let out = position_control(
            &self.params,
            &self.pos_gains,
            &self.att_gains,
            &crate::PositionInput {
                state,
                e_i_pos: e_pos,
                e_i_att: e_att,
                reference,
                model: self.model,
            },
        )?;
        let (a, p) = (
            B::vec3_to_array(out.e_i_att_rate),
            B::vec3_to_array(out.e_i_pos_rate),
        );
        *first_mut::<B, 6>(rates) = [a[0], a[1], a[2], p[0], p[1], p[2]];
        Ok(ModeOutput {
            thrust: out.thrust,
            moment: out.moment,
            desired: out.rc,
            desired_omega: out.omega_c,
            psi: out.psi,
            rotor_speeds: None,
        })
    }
    fn force_branch(&mut self, index: usize, branch: SatBranch) {
        if let Some(b) = self.pos_gains.sat_branch.get_mut(index) {
            *b = branch;
        }
    }
    fn update_outer(
        &mut self,
        _sealed: sealed::Token,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
    ) -> Result<(), ControlError> {
        let [a0, a1, a2, p0, p1, p2] = *first::<B, 6>(integrals);
        let fresh;
        let reference = match self.reference.constant() {
            Some(held) => held,
            None => {
                fresh = self.reference.position(t);
                &fresh
            }
        };
        let out = position_control(
            &self.params,
            &self.pos_gains,
            &self.att_gains,
            &crate::PositionInput {
                state,
                e_i_pos: B::vec3(p0, p1, p2),
                e_i_att: B::vec3(a0, a1, a2),
                reference,
                model: self.model,
            },
        )?;
        self.held = Some(HeldOuter {
            thrust: out.thrust,
            attitude: AttitudeReference {
                rd: out.rc,
                omega_d: out.omega_c,
                omega_d_dot: out.omega_c_dot,
            },
            e_i_pos_rate: out.e_i_pos_rate,
        });
        Ok(())
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        Some(self.reference.position_f64(t))
    }
}

impl<B: Backend, P: PositionSource<B>> PositionMode<B, P> {
    /// The command between outer instants: the attitude law (eqn:aM) on
    /// the held `R_c, Ω_c, Ω̇_c` with the held thrust and `e_i` rate.
    #[inline(never)]
    fn track_held(
        &self,
        h: &HeldOuter<B>,
        state: &VehicleState<B, So3Mat<B>>,
        e_att: V3<B>,
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        let out = attitude_control(
            &self.params,
            &self.att_gains,
            state.r,
            state.omega,
            e_att,
            &h.attitude,
        )?;
        let (a, p) = (
            B::vec3_to_array(out.e_i_rate),
            B::vec3_to_array(h.e_i_pos_rate),
        );
        *first_mut::<B, 6>(rates) = [a[0], a[1], a[2], p[0], p[1], p[2]];
        Ok(ModeOutput {
            thrust: h.thrust,
            moment: out.moment,
            desired: h.attitude.rd,
            desired_omega: h.attitude.omega_d,
            psi: out.psi,
            rotor_speeds: None,
        })
    }
}
