//! Studies on many runs of the geopid engine: what the paper claims,
//! checked at scale.
//!
//! | module | what it holds |
//! |---|---|
//! | [`metrics`] | metrics over recorded samples, and the work-precision sweep |
//! | [`gains`] | the conditions of Propositions 2 and 3 for a scene's gains, and a search for gains that meet them |
//! | [`montecarlo`] | many runs from random initial conditions, classified, with statistics and confidence bounds |
//! | [`sensing`] | flying on measurements: RMS error against the motion capture's latency and the sensors' noise |
//! | [`missions`] | planned flights: the exact Ω_c, Ω̇_c against differences of the commanded attitude |
//! | [`sensitivity`] | exact derivatives of a whole run with respect to a scene's numbers, and gain tuning on them |
//! | [`held_out`] | a tuning on noise seeds it never saw: paired costs and a 95 % interval |
//! | [`regress`] | the regression suite: every built-in scene against independently computed expectations |
//! | [`stress`] | the numerical stress suite: long horizons, non-finite loads, rates, precision |
//! | `figures` | SVG figures of runs, studies and sweeps (feature `plot`) |
//!
//! ```
//! // Four runs of the paper's attitude experiment from random attitudes,
//! // on one thread: each converges (Proposition 2's almost-global claim).
//! use studies::montecarlo::Setup;
//! let rows = Setup::default().run(&[0, 1, 2, 3], Some(1), None)?;
//! assert_eq!(rows.len(), 4);
//! assert!(rows.iter().all(|r| r.converged));
//! # Ok::<(), scenes::Error>(())
//! ```

#![deny(missing_docs)]

pub mod estimation;
#[cfg(feature = "plot")]
pub mod figures;
pub mod gains;
pub mod held_out;
pub mod metrics;
pub mod missions;
pub mod montecarlo;
pub mod regress;
pub mod sensing;
pub mod sensitivity;
pub mod stress;
