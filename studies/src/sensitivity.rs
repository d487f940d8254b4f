//! Exact derivatives of a whole closed-loop run with respect to a scene's
//! parameters: the same simulation, on the forward-mode dual scalar
//! ([`lie::Dual`]), with the chosen parameters seeded.
//!
//! The real part of the run is the `f64` run bit for bit (every branch,
//! step and event decision reads it), and the derivatives are those of
//! that discrete flight: through every stepper, the LGVI's implicit solve,
//! and the saturation crossings the run locates (their times move with the
//! parameters; see the engine's event location). Derivatives of the
//! attitude are in the body-frame tangent space: seeding
//! `initial.attitude[k]` perturbs `R₀` as `R₀ Exp(δ)`.
//!
//! ```
//! use scenes::{Registry, builtin};
//! use studies::sensitivity;
//! use lie::Dual;
//!
//! let mut scene = builtin::paper_flip();
//! scene.duration = 1.0;
//! // Final height error, with respect to two gains.
//! let g = sensitivity::gradient(
//!     &Registry::new(),
//!     &scene,
//!     ["gains.k_x", "gains.k_v"],
//!     scene.duration,
//!     |_, s| {
//!         let e = s.body.x[2] - Dual::constant(0.0);
//!         e * e
//!     },
//! )?;
//! assert!(g.gradient.iter().all(|d| d.is_finite()));
//! # Ok::<(), scenes::Error>(())
//! ```
//!
//! With sensors, a run's noise is a constant of its seed: the derivatives
//! flow through the measurements of the true state and through the
//! estimator (naming `estimator.q_scale` or `estimator.r_scale` seeds the
//! invariant EKF's noise scales).
//!
//! Located events move with the parameters: a saturation crossing and a
//! switch on `Ψ` below a threshold carry their time's derivative. A switch
//! on a user predicate cannot (a boolean has no derivative): a gradient
//! through one is an error. Dormand–Prince's step sizes are taken as the
//! `f64` run chose them (constants), so its derivative is that of the
//! flight with those steps.

use lie::{Backend, Dual, NalgebraDual, NalgebraF64, Real, S, SimdReal};
use scenes::Error;

use scenarios::SimError;
use scenarios::{RunOptions, SimState, Simulation};
use scenes::Registry;
use scenes::scene::{Scene, VehicleKind};
use scenes::{Seeds, builder_from};

pub use scenes::{PARAMETERS, parameter_mut};

/// A run's cost and its derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct Gradient<const K: usize> {
    /// The parameters, in the order of [`Gradient::gradient`].
    pub parameters: [String; K],
    /// The cost (the `f64` run's, bit for bit).
    pub value: f64,
    /// `∂cost/∂parameter`, one per parameter.
    pub gradient: [f64; K],
}

/// The value and gradient of a cost summed over a run of `scene`, with
/// respect to the `K` named parameters (each one of [`PARAMETERS`]).
///
/// `cost(t, state)` is evaluated at `t = every, 2·every, …` up to the
/// scene's duration (and at the duration itself if it is not such a
/// multiple) and the values are summed: a running cost (scale by `every`
/// for an integral) or, with `every` the duration, a cost of the final
/// state. A cost that does not read a seeded parameter's influence gets
/// an exact zero.
///
/// Errors: a name that is not a parameter, named twice, or a vehicle
/// parameter of a kind that does not read it ([`Error::Scene`], naming
/// it); `every` not positive ([`SimError::Setting`]); a derivative of the
/// state or the cost turning non-finite
/// ([`Error::NonFiniteDerivative`], naming the parameter, the time and
/// the component); and whatever the run itself can fail with.
pub fn gradient<const K: usize>(
    registry: &Registry,
    scene: &Scene,
    seeds: [&str; K],
    every: f64,
    mut cost: impl FnMut(f64, &SimState<'_, NalgebraDual<K>>) -> Dual<K>,
) -> Result<Gradient<K>, Error> {
    check_seeds(scene, &seeds)?;
    if !(every.is_finite() && every > 0.0) {
        return Err(Error::Run(SimError::Setting {
            field: "every",
            message: format!("must be a positive number of seconds, got {every}"),
        }));
    }
    registry.check(scene)?;
    let s = Seeds::new(&seeds);
    let (vehicle, plan) = registry.parts::<NalgebraDual<K>>(scene, None, s)?;
    let total = fly_dual(
        builder_from(scene, vehicle, plan, s)?.build()?,
        scene.duration,
        every,
        &seeds,
        &mut cost,
    )?;
    Ok(Gradient {
        parameters: seeds.map(String::from),
        value: total.re,
        gradient: total.eps,
    })
}

/// Runs `sim` to `duration`, calling `at` at `every, 2·every, …` and at
/// the duration.
///
/// No samples are recorded (the cost reads the state where the run
/// pauses), and the per-step extrema only when `extrema` asks for the
/// largest thrust: each costs a controller evaluation per step (together
/// 28 % of a dual run's instructions), and neither moves a step, so the
/// flight is the one a recorded run flies.
fn fly<B: Backend>(
    mut sim: Simulation<'static, B>,
    duration: f64,
    every: f64,
    extrema: bool,
    mut at: impl FnMut(f64, &SimState<'_, B>) -> Result<(), Error>,
) -> Result<f64, Error> {
    let opts = || RunOptions {
        record: false,
        extrema,
        ..RunOptions::default()
    };
    let mut k = 1u64;
    loop {
        let t = (k as f64 * every).min(duration);
        sim.advance_to_with(t, opts())?;
        at(t, &sim.state())?;
        if t >= duration {
            return Ok(sim.output().max_thrust);
        }
        k += 1;
    }
}

/// [`fly`] on duals: the cost summed, the derivatives checked at each
/// instant.
fn fly_dual<const K: usize>(
    sim: Simulation<'static, NalgebraDual<K>>,
    duration: f64,
    every: f64,
    seeds: &[&str; K],
    cost: &mut impl FnMut(f64, &SimState<'_, NalgebraDual<K>>) -> Dual<K>,
) -> Result<Dual<K>, Error> {
    let mut total = Dual::constant(0.0);
    fly(sim, duration, every, false, |t, state| {
        if let Some(e) = non_finite_derivative(state, seeds) {
            return Err(e);
        }
        total += cost(t, state);
        if !total.is_finite() && total.re.is_finite() {
            return Err(named(seeds, &total, t, "the cost".into()));
        }
        Ok(())
    })?;
    Ok(total)
}

/// The error for `x`, whose first non-finite derivative names the
/// parameter.
fn named<const K: usize>(seeds: &[&str; K], x: &Dual<K>, t: f64, component: String) -> Error {
    let i = x.eps.iter().position(|e| !e.is_finite()).unwrap_or(0);
    Error::NonFiniteDerivative {
        parameter: seeds[i].to_string(),
        t,
        component,
    }
}

/// The first state component whose value is finite and a derivative not.
/// The components are named only once one is found: this runs at every
/// sampled instant of a gradient run.
fn non_finite_derivative<const K: usize>(
    s: &SimState<'_, NalgebraDual<K>>,
    seeds: &[&str; K],
) -> Option<Error> {
    let b = s.body;
    let bad = |x: &Dual<K>| x.re.is_finite() && !x.simd_is_finite();
    let name = |part: &str, x: &Dual<K>, at: String| named(seeds, x, s.t, format!("{part}{at}"));
    for (part, v) in [("x", b.x), ("v", b.v), ("omega", b.omega)] {
        if let Some(k) = v.iter().position(bad) {
            return Some(name(part, &v[k], format!("[{k}]")));
        }
    }
    if let Some(i) = b.r.iter().position(bad) {
        // nalgebra's storage is column-major.
        return Some(name("R", &b.r[i], format!("[{}][{}]", i % 3, i / 3)));
    }
    for (part, xs) in [
        ("integrals", s.integrals),
        ("vehicle_states", s.vehicle_states),
    ] {
        if let Some(i) = xs.iter().position(bad) {
            return Some(name(part, &xs[i], format!("[{i}]")));
        }
    }
    None
}

/// Every seed a parameter, named once, and read by the scene's vehicle.
fn check_seeds(scene: &Scene, seeds: &[&str]) -> Result<(), Error> {
    let bad =
        |name: &str, message: String| Err(Error::Scene(scenes::SceneError::at_key(name, message)));
    for (i, name) in seeds.iter().enumerate() {
        if !PARAMETERS.contains(name) {
            return bad(
                name,
                format!(
                    "`{name}` is not a parameter a gradient can seed; one of: {}",
                    PARAMETERS.join(", ")
                ),
            );
        }
        if seeds[..i].contains(name) {
            return bad(name, format!("`{name}` is seeded twice"));
        }
        let reads = match scene.vehicle.kind {
            VehicleKind::Quadrotor
            | VehicleKind::PinnedQuadrotor
            | VehicleKind::AttitudeStand
            | VehicleKind::Hexarotor => true,
            VehicleKind::FreeRigidBody => name.starts_with("vehicle.inertia"),
            _ => false,
        };
        let iekf = scene
            .estimator
            .as_ref()
            .is_some_and(|e| e.kind == scenes::scene::EstimatorKind::Iekf);
        if name.starts_with("estimator.") && !iekf {
            return bad(
                name,
                format!(
                    "`{name}` is read only by an `iekf` estimator, which the scene does not fly"
                ),
            );
        }
        if name.starts_with("vehicle.") && !reads {
            return bad(
                name,
                format!(
                    "`{name}` is not read from the scene by a `{:?}` vehicle",
                    scene.vehicle.kind
                ),
            );
        }
    }
    Ok(())
}

/// A cost written once for a plain run and a dual one: [`tune`] evaluates
/// it on both (line searches on plain `f64` runs, gradients on dual ones).
pub trait Cost {
    /// The term at an instant `t` of state `state`; the cost is their sum.
    fn at<B: Backend>(&mut self, t: f64, state: &SimState<'_, B>) -> S<B>;
}

/// `Σ ‖x(t_k) − x_d(t_k)‖² Δt` at `t_k = k Δt`: the squared position
/// tracking error of a scene's (first) position reference, integrated.
#[derive(Clone, Debug)]
pub struct Tracking {
    reference: scenes::scene::PositionRef,
    dt: f64,
}

impl Tracking {
    /// The tracking cost of `scene`'s first position segment, sampled
    /// every `dt` (the `every` of the run it is summed over).
    pub fn of(scene: &Scene, dt: f64) -> Result<Self, Error> {
        let reference = scene
            .plan
            .iter()
            .find_map(|s| s.position.clone())
            .ok_or_else(|| {
                Error::Scene(scenes::SceneError::at_key(
                    "plan",
                    "a tracking cost needs a position segment".into(),
                ))
            })?;
        Ok(Self { reference, dt })
    }
}

impl Cost for Tracking {
    fn at<B: Backend>(&mut self, t: f64, state: &SimState<'_, B>) -> S<B> {
        let ([xd, ..], _) = scenes::reference::position_f64(&self.reference, t);
        let e = state.body.x - scenes::reference::v::<B>(xd);
        B::dot(e, e) * S::<B>::lit(self.dt)
    }
}

/// The cost of a plain `f64` run of `scene` (nalgebra), summed at every
/// `every` as [`gradient`] sums it.
pub fn plain_cost<C: Cost>(
    registry: &Registry,
    scene: &Scene,
    every: f64,
    cost: &mut C,
) -> Result<f64, Error> {
    plain_flight(registry, scene, every, cost).map(|f| f.0)
}

/// [`plain_cost`] and the largest |thrust| commanded along the flight, N.
fn plain_flight<C: Cost>(
    registry: &Registry,
    scene: &Scene,
    every: f64,
    cost: &mut C,
) -> Result<(f64, f64), Error> {
    registry.check(scene)?;
    let (vehicle, plan) = registry.parts::<NalgebraF64>(scene, None, Seeds::NONE)?;
    let mut total = 0.0;
    let mut add = |t: f64, s: &SimState<'_, NalgebraF64>| {
        total += cost.at(t, s);
        Ok(())
    };
    let max_thrust = fly(
        builder_from(scene, vehicle, plan, Seeds::NONE)?.build()?,
        scene.duration,
        every,
        true,
        &mut add,
    )?;
    Ok((total, max_thrust))
}

/// One iteration of [`tune`]: the parameters it started from, their cost
/// and gradient, and the step taken from them.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneStep<const K: usize> {
    /// 0, 1, …: gradient evaluations so far.
    pub iteration: usize,
    /// The parameters' values.
    pub values: [f64; K],
    /// Their cost (the mean over the noise seeds).
    pub cost: f64,
    /// `∂cost/∂parameter`.
    pub gradient: [f64; K],
    /// The accepted step in `ln(parameter)` (0: none found, the search
    /// stops).
    pub step: f64,
    /// Plain runs the line search took.
    pub plain_runs: usize,
    /// The largest |thrust| commanded along the flight with `values`, N.
    pub max_thrust: f64,
}

/// What [`tune`] tunes, within which bounds, and for how long.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneSpec<'p, const K: usize> {
    /// The parameters (of [`PARAMETERS`], each with a positive scene
    /// number: the gains, say).
    pub params: [&'p str; K],
    /// `(lo, hi)` per parameter, `0 < lo ≤ value ≤ hi`.
    pub bounds: [(f64, f64); K],
    /// The cost's sampling interval, s (as [`gradient`]'s `every`).
    pub every: f64,
    /// Gradient evaluations at most.
    pub max_gradients: usize,
    /// The thrust the flight may command, N: the line search takes no
    /// step whose flight commands more at any step (`None`: no limit).
    pub max_thrust: Option<f64>,
    /// Noise realisations the cost and its gradient are averaged over: the
    /// scene flown with seeds `seed, seed + 1, …` (0 or 1: its own seed
    /// alone). Averaging tunes for the noise's distribution, not for one
    /// draw of it; [`crate::held_out`] then measures the result on seeds
    /// the tuning never saw.
    pub noise_seeds: usize,
}

/// `scene` with its seed advanced by `0, 1, …, n − 1` (by 0 alone for
/// `n ≤ 1`): a Monte Carlo sample adds its index to the scene's seed.
pub fn noise_variants(scene: &Scene, n: usize) -> Vec<Scene> {
    (0..n.max(1) as u64)
        .map(|i| {
            let mut s = scene.clone();
            s.seed = s.seed.wrapping_add(i);
            s
        })
        .collect()
}

/// [`plain_flight`] averaged over `scene`'s noise variants: the mean cost
/// and the largest thrust of any.
fn plain_mean<C: Cost>(
    registry: &Registry,
    scene: &Scene,
    every: f64,
    noise_seeds: usize,
    cost: &mut C,
) -> Result<(f64, f64), Error> {
    let variants = noise_variants(scene, noise_seeds);
    let (mut total, mut thrust) = (0.0, 0.0f64);
    for v in &variants {
        let (c, f) = plain_flight(registry, v, every, cost)?;
        total += c;
        thrust = thrust.max(f);
    }
    Ok((total / variants.len() as f64, thrust))
}

/// [`gradient`] averaged over `scene`'s noise variants.
fn gradient_mean<const K: usize, C: Cost>(
    registry: &Registry,
    scene: &Scene,
    params: [&str; K],
    every: f64,
    noise_seeds: usize,
    cost: &mut C,
) -> Result<Gradient<K>, Error> {
    let variants = noise_variants(scene, noise_seeds);
    let n = variants.len() as f64;
    let mut mean: Option<Gradient<K>> = None;
    for v in &variants {
        let g = gradient(registry, v, params, every, |t, s| cost.at(t, s))?;
        match &mut mean {
            None => mean = Some(g),
            Some(m) => {
                m.value += g.value;
                for (a, b) in m.gradient.iter_mut().zip(g.gradient) {
                    *a += b;
                }
            }
        }
    }
    let mut m = mean.expect("at least one variant");
    m.value /= n;
    m.gradient.iter_mut().for_each(|d| *d /= n);
    Ok(m)
}

/// Minimises `cost` over the named (positive) parameters of `scene` within
/// their bounds, by projected gradient descent on their logarithms (a step
/// changes each by a factor, so gains of different sizes move alike and
/// stay positive) with a backtracking line search on plain runs (Armijo,
/// halving; the next search starts from twice the last accepted step), for
/// at most `spec.max_gradients` gradient evaluations. A trial whose flight
/// diverges ([`Error::is_divergence`]) or commands more than
/// `spec.max_thrust` counts as a rise in cost: the search halves the step.
/// `report` sees each iteration. Returns the scene with the best parameters
/// found, the iterations and that scene's cost (from the run that accepted
/// it: no run is flown twice).
///
/// Errors: a bound not `0 < lo ≤ value ≤ hi` or a parameter without a
/// scene number (`initial.attitude[k]`), naming it; a starting flight above
/// `max_thrust` ([`SimError::Setting`] on `max_thrust`); and those of
/// [`gradient`] and of the plain runs.
pub fn tune<const K: usize, C: Cost>(
    registry: &Registry,
    scene: &Scene,
    spec: &TuneSpec<'_, K>,
    cost: &mut C,
    mut report: impl FnMut(&TuneStep<K>),
) -> Result<Tuned<K>, Error> {
    let TuneSpec {
        params,
        bounds,
        every,
        max_gradients,
        max_thrust,
        noise_seeds,
    } = *spec;
    let mut best = scene.clone();
    let mut x = [0.0; K];
    for (i, name) in params.iter().enumerate() {
        let v = scenes::parameter_mut(&mut best, name).map(|p| *p);
        let (lo, hi) = bounds[i];
        match v {
            Some(v) if lo > 0.0 && lo <= v && v <= hi => x[i] = v.ln(),
            _ => {
                let got = v.map_or("no scene number".to_string(), |v| format!("{v}"));
                return Err(Error::Scene(scenes::SceneError::at_key(
                    name,
                    format!("tuning needs 0 < lo ≤ value ≤ hi, got {got} in [{lo}, {hi}]"),
                )));
            }
        }
    }
    let with = |x: &[f64; K]| {
        let mut s = scene.clone();
        for (i, name) in params.iter().enumerate() {
            if let Some(p) = scenes::parameter_mut(&mut s, name) {
                *p = x[i].exp();
            }
        }
        s
    };
    let (mut best_cost, mut thrust) = plain_mean(registry, &best, every, noise_seeds, cost)?;
    let within = |f: f64| max_thrust.is_none_or(|limit| f <= limit);
    if !within(thrust) {
        return Err(Error::Run(SimError::Setting {
            field: "max_thrust",
            message: format!(
                "{} N: the starting flight commands {thrust} N",
                max_thrust.unwrap_or_default()
            ),
        }));
    }
    let mut history = Vec::new();
    let mut alpha: Option<f64> = None;
    for iteration in 0..max_gradients {
        let g = gradient_mean(registry, &best, params, every, noise_seeds, cost)?;
        // The gradient in ln(p): ∂c/∂ln p = p ∂c/∂p.
        let gl: [f64; K] = core::array::from_fn(|i| g.gradient[i] * x[i].exp());
        let norm = gl.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        // The first step changes no parameter by more than 20 %.
        let mut a = alpha.unwrap_or(0.2 / norm.max(f64::MIN_POSITIVE));
        let mut step = TuneStep {
            iteration,
            values: core::array::from_fn(|i| x[i].exp()),
            cost: g.value,
            gradient: g.gradient,
            step: 0.0,
            plain_runs: 0,
            max_thrust: thrust,
        };
        let mut accepted = None;
        for _ in 0..10 {
            let trial: [f64; K] = core::array::from_fn(|i| {
                (x[i] - a * gl[i]).clamp(bounds[i].0.ln(), bounds[i].1.ln())
            });
            let moved: f64 = (0..K).map(|i| gl[i] * (x[i] - trial[i])).sum();
            step.plain_runs += 1;
            match plain_mean(registry, &with(&trial), every, noise_seeds, cost) {
                Ok((c, f)) if c <= g.value - 1e-4 * moved && moved > 0.0 && within(f) => {
                    accepted = Some((trial, c, f));
                    break;
                }
                Ok(_) => {}
                Err(e) if e.is_divergence() => {}
                Err(e) => return Err(e),
            }
            a *= 0.5;
        }
        let Some((trial, c, f)) = accepted else {
            report(&step);
            history.push(step);
            break;
        };
        step.step = a;
        report(&step);
        history.push(step);
        x = trial;
        best_cost = c;
        thrust = f;
        best = with(&x);
        // Try a longer step next time: the search only ever halves.
        alpha = Some(2.0 * a);
    }
    Ok(Tuned {
        scene: best,
        history,
        final_cost: best_cost,
    })
}

/// The gains [`tune_gains`] tunes: the position and attitude loops'
/// proportional and derivative gains (the paper's `k_x`, `k_v`, `k_R`,
/// `k_Ω`).
pub const TUNED_GAINS: [&str; 4] = ["gains.k_x", "gains.k_v", "gains.k_r", "gains.k_omega"];

/// What [`tune_gains`] does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GainTuning {
    /// Each gain stays within `[g₀ / factor, g₀ · factor]` of its starting
    /// value `g₀` (`factor ≥ 1`).
    pub factor: f64,
    /// The tracking cost's sampling interval, s.
    pub every: f64,
    /// Gradient evaluations at most.
    pub max_gradients: usize,
    /// The thrust the flight may command, N (`None`: no limit).
    pub max_thrust: Option<f64>,
    /// Noise realisations to average over (see [`TuneSpec::noise_seeds`]).
    pub noise_seeds: usize,
}

/// [`tune`] on [`TUNED_GAINS`] with the [`Tracking`] cost of the scene's
/// first position segment: `Σ ‖e_x‖² Δt`, so `sqrt(cost / duration)` is
/// the RMS position error. Compiled once here (the dual engine for four
/// directions), so a command line or a binding calls it without
/// instantiating the engine again.
///
/// Errors: those of [`Tracking::of`] and [`tune`]; a `factor` below 1 or
/// not finite ([`SimError::Setting`] on `factor`).
pub fn tune_gains(
    registry: &Registry,
    scene: &Scene,
    spec: &GainTuning,
    report: &mut dyn FnMut(&TuneStep<4>),
) -> Result<Tuned<4>, Error> {
    if !(spec.factor.is_finite() && spec.factor >= 1.0) {
        return Err(Error::Run(SimError::Setting {
            field: "factor",
            message: format!("{}: must be finite and ≥ 1", spec.factor),
        }));
    }
    let mut start = scene.clone();
    let mut bounds = [(0.0, 0.0); 4];
    for (b, name) in bounds.iter_mut().zip(TUNED_GAINS) {
        let g0 = scenes::parameter_mut(&mut start, name).map_or(0.0, |p| *p);
        *b = (g0 / spec.factor, g0 * spec.factor);
    }
    let mut cost = Tracking::of(scene, spec.every)?;
    let tune_spec = TuneSpec {
        params: TUNED_GAINS,
        bounds,
        every: spec.every,
        max_gradients: spec.max_gradients,
        max_thrust: spec.max_thrust,
        noise_seeds: spec.noise_seeds,
    };
    tune(registry, scene, &tune_spec, &mut cost, report)
}

/// What [`tune`] returns ([`tune_gains`]: with `K = 4`).
#[derive(Clone, Debug)]
pub struct Tuned<const K: usize> {
    /// The scene with the tuned parameters.
    pub scene: Scene,
    /// One step per gradient evaluation, the starting parameters' first.
    pub history: Vec<TuneStep<K>>,
    /// The cost of `scene` (a plain `f64` run); for [`Tracking`], its
    /// square root over the duration is the RMS position error.
    pub final_cost: f64,
}

/// The [`Tracking`] cost of `scene` sampled every `every` and its gradient
/// with respect to `params` (at most 4 of [`PARAMETERS`]), for callers
/// that name the parameters at run time (a binding, a command line). The
/// dual engine runs with 4 directions, the unused ones seeded with gains
/// not asked for, whose derivatives are dropped: one instantiation,
/// [`tune_gains`]'s, serves every call.
///
/// Errors: more than 4 names or none ([`SimError::Setting`] on `params`),
/// and those of [`gradient`] and [`Tracking::of`].
pub fn tracking_gradient(
    registry: &Registry,
    scene: &Scene,
    params: &[&str],
    every: f64,
) -> Result<(f64, Vec<f64>), Error> {
    if params.is_empty() || params.len() > 4 {
        return Err(Error::Run(SimError::Setting {
            field: "params",
            message: format!(
                "{} names: between 1 and 4 at a time ({})",
                params.len(),
                params.join(", ")
            ),
        }));
    }
    let mut spare = PARAMETERS
        .iter()
        .filter(|p| p.starts_with("gains.") && !params.contains(p));
    let seeds: [&str; 4] = core::array::from_fn(|i| match params.get(i) {
        Some(p) => *p,
        None => spare.next().copied().unwrap_or_default(),
    });
    let mut cost = Tracking::of(scene, every)?;
    let g = gradient(registry, scene, seeds, every, |t, s| cost.at(t, s))?;
    Ok((g.value, g.gradient[..params.len()].to_vec()))
}
