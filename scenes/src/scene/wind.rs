//! The wind a scene names: its schema and the field it builds.

use serde::{Deserialize, Serialize};

/// The air's velocity, inertial frame (e3 down), m/s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum WindSpec {
    /// A steady, uniform wind.
    Constant {
        /// m/s.
        velocity: [f64; 3],
    },
    /// `mean + amplitude · sin(2π frequency t + phase)`.
    Sinusoid {
        /// m/s.
        #[serde(default)]
        mean: [f64; 3],
        /// m/s.
        amplitude: [f64; 3],
        /// Hz.
        frequency: f64,
        /// rad.
        #[serde(default)]
        phase: f64,
    },
    /// `velocities[k]` from `times[k]` on; the steps land on the times.
    Ladder {
        /// s, increasing.
        times: Vec<f64>,
        /// m/s, one per time.
        velocities: Vec<[f64; 3]>,
    },
    /// Dryden turbulence over a mean wind (MIL-F-8785C forming filters
    /// driven by noise on a fixed grid, reproducible from `seed`).
    Dryden {
        /// Mean wind, m/s.
        #[serde(default)]
        mean: [f64; 3],
        /// σ of the longitudinal, lateral and vertical components, m/s
        /// (default 1).
        #[serde(default = "dryden_sigma")]
        sigma: [f64; 3],
        /// Scale lengths L_u, L_v, L_w, m (default 94, 94, 15: the
        /// low-altitude values at 15 m).
        #[serde(default = "dryden_length")]
        length: [f64; 3],
        /// Speed the turbulence is carried past the vehicle at, m/s
        /// (default 5).
        #[serde(default = "dryden_speed")]
        speed: f64,
        /// Noise seed (default 1).
        #[serde(default = "dryden_seed")]
        seed: u64,
        /// Noise grid, s (default 0.005).
        #[serde(default = "dryden_grid")]
        grid: f64,
    },
}

fn dryden_sigma() -> [f64; 3] {
    dynamics::DrydenSpec::gusty().sigma
}
fn dryden_length() -> [f64; 3] {
    dynamics::DrydenSpec::gusty().length
}
fn dryden_speed() -> f64 {
    dynamics::DrydenSpec::gusty().speed
}
fn dryden_seed() -> u64 {
    dynamics::DrydenSpec::gusty().seed
}
fn dryden_grid() -> f64 {
    dynamics::DrydenSpec::gusty().grid
}

impl WindSpec {
    /// Dryden turbulence with the parameters of `spec` (e.g.
    /// [`dynamics::DrydenSpec::gusty`], with its mean or speed changed).
    pub fn dryden(spec: dynamics::DrydenSpec) -> Self {
        let dynamics::DrydenSpec {
            mean,
            sigma,
            length,
            speed,
            seed,
            grid,
        } = spec;
        WindSpec::Dryden {
            mean,
            sigma,
            length,
            speed,
            seed,
            grid,
        }
    }

    /// The wind field; an error names the `wind.<field>` key.
    pub fn build(&self) -> Result<Box<dyn dynamics::Wind>, (&'static str, String)> {
        use dynamics::{ConstantWind, DrydenSpec, DrydenWind, LadderWind, SinusoidWind};
        let key = |e: dynamics::WindError| {
            let k = match e.field {
                "times" => "wind.times",
                "velocities" => "wind.velocities",
                "mean" => "wind.mean",
                "sigma" => "wind.sigma",
                "length" => "wind.length",
                "speed" => "wind.speed",
                _ => "wind.grid",
            };
            (k, format!("`{k}`: {}", e.message))
        };
        let finite = |k: &'static str, v: &[f64]| match v.iter().find(|c| !c.is_finite()) {
            Some(c) => Err((k, format!("`{k}` = {c}: must be finite"))),
            None => Ok(()),
        };
        Ok(match self {
            WindSpec::Constant { velocity } => {
                finite("wind.velocity", velocity)?;
                Box::new(ConstantWind(*velocity))
            }
            WindSpec::Sinusoid {
                mean,
                amplitude,
                frequency,
                phase,
            } => {
                finite("wind.mean", mean)?;
                finite("wind.amplitude", amplitude)?;
                finite("wind.frequency", &[*frequency])?;
                finite("wind.phase", &[*phase])?;
                Box::new(SinusoidWind {
                    mean: *mean,
                    amplitude: *amplitude,
                    frequency: *frequency,
                    phase: *phase,
                })
            }
            WindSpec::Ladder { times, velocities } => {
                Box::new(LadderWind::new(times.clone(), velocities.clone()).map_err(key)?)
            }
            WindSpec::Dryden {
                mean,
                sigma,
                length,
                speed,
                seed,
                grid,
            } => Box::new(
                DrydenWind::new(DrydenSpec {
                    mean: *mean,
                    sigma: *sigma,
                    length: *length,
                    speed: *speed,
                    seed: *seed,
                    grid: *grid,
                })
                .map_err(key)?,
            ),
        })
    }
}
