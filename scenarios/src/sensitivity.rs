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
//! use scenarios::{Registry, builtin, sensitivity};
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
//! # Ok::<(), scenarios::SimError>(())
//! ```
//!
//! Located events move with the parameters: a saturation crossing and a
//! switch on `Ψ` below a threshold carry their time's derivative. A switch
//! on a user predicate cannot (a boolean has no derivative): a gradient
//! through one is an error. Dormand–Prince's step sizes are taken as the
//! `f64` run chose them (constants), so its derivative is that of the
//! flight with those steps.

use lie::{Dual, NalgebraDual, Real, S, SimdReal};

use crate::from_scene::{Seeds, builder_from};
use crate::scene::{Scene, VehicleKind};
use crate::sim::{SimState, Simulation};
use crate::{Registry, SceneError, SimError};

pub use crate::from_scene::PARAMETERS;

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
/// parameter of a kind that does not read it ([`SimError::Scene`], naming
/// it); `every` not positive ([`SimError::Setting`]); a derivative of the
/// state or the cost turning non-finite
/// ([`SimError::NonFiniteDerivative`], naming the parameter, the time and
/// the component); and whatever the run itself can fail with.
pub fn gradient<const K: usize>(
    registry: &Registry,
    scene: &Scene,
    seeds: [&str; K],
    every: f64,
    mut cost: impl FnMut(f64, &SimState<'_, NalgebraDual<K>>) -> Dual<K>,
) -> Result<Gradient<K>, SimError> {
    check_seeds(scene, &seeds)?;
    if !(every.is_finite() && every > 0.0) {
        return Err(SimError::Setting {
            field: "every",
            message: format!("must be a positive number of seconds, got {every}"),
        });
    }
    registry.check(scene)?;
    let s = Seeds::new(&seeds);
    let (vehicle, plan, capacity) = registry.parts::<NalgebraDual<K>>(scene, None, s)?;
    let total = match capacity {
        6 => fly(
            builder_from::<_, 6>(scene, vehicle, plan, s)?.build()?,
            scene.duration,
            every,
            &seeds,
            &mut cost,
        ),
        _ => fly(
            builder_from::<_, 16>(scene, vehicle, plan, s)?.build()?,
            scene.duration,
            every,
            &seeds,
            &mut cost,
        ),
    }?;
    Ok(Gradient {
        parameters: seeds.map(String::from),
        value: total.re,
        gradient: total.eps,
    })
}

/// Runs `sim` to `duration`, summing `cost` at every `every` and checking
/// the derivatives at each of those instants.
fn fly<const K: usize, const N: usize>(
    mut sim: Simulation<'static, NalgebraDual<K>, N>,
    duration: f64,
    every: f64,
    seeds: &[&str; K],
    cost: &mut impl FnMut(f64, &SimState<'_, NalgebraDual<K>>) -> Dual<K>,
) -> Result<Dual<K>, SimError> {
    let mut total = Dual::constant(0.0);
    let mut k = 1u64;
    loop {
        let t = (k as f64 * every).min(duration);
        sim.advance_to(t)?;
        let state = sim.state();
        if let Some(e) = non_finite_derivative(&state, seeds) {
            return Err(e);
        }
        total += cost(t, &state);
        if !total.is_finite() && total.re.is_finite() {
            return Err(named(seeds, &total, t, "the cost".into()));
        }
        if t >= duration {
            return Ok(total);
        }
        k += 1;
    }
}

/// The error for `x`, whose first non-finite derivative names the
/// parameter.
fn named<const K: usize>(seeds: &[&str; K], x: &Dual<K>, t: f64, component: String) -> SimError {
    let i = x.eps.iter().position(|e| !e.is_finite()).unwrap_or(0);
    SimError::NonFiniteDerivative {
        parameter: seeds[i].to_string(),
        t,
        component,
    }
}

/// The first state component whose value is finite and a derivative not.
fn non_finite_derivative<const K: usize>(
    s: &SimState<'_, NalgebraDual<K>>,
    seeds: &[&str; K],
) -> Option<SimError> {
    let b = s.body;
    let mut parts: Vec<(String, S<NalgebraDual<K>>)> = Vec::new();
    for (name, v) in [("x", b.x), ("v", b.v), ("omega", b.omega)] {
        parts.extend((0..3).map(|k| (format!("{name}[{k}]"), v[k])));
    }
    for r in 0..3 {
        parts.extend((0..3).map(|c| (format!("R[{r}][{c}]"), b.r[(r, c)])));
    }
    parts.extend(
        s.integrals
            .iter()
            .enumerate()
            .map(|(i, x)| (format!("integrals[{i}]"), *x)),
    );
    let states = s.vehicle_states.iter().enumerate();
    parts.extend(states.map(|(i, x)| (format!("vehicle_states[{i}]"), *x)));
    parts
        .into_iter()
        .find(|(_, x)| x.re.is_finite() && !x.simd_is_finite())
        .map(|(name, x)| named(seeds, &x, s.t, name))
}

/// Every seed a parameter, named once, and read by the scene's vehicle.
fn check_seeds(scene: &Scene, seeds: &[&str]) -> Result<(), SimError> {
    let bad = |name: &str, message: String| Err(SimError::Scene(SceneError::at_key(name, message)));
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
