//! Changes to a scene's settings from a front end (command-line flags,
//! keyword arguments), checked as the scene file's own values are.

use crate::scene::{BackendKind, Scalar, Scene, SceneError, Timing};

/// The settings a front end may override; `None` keeps the scene's value.
///
/// ```
/// use scenes::{Overrides, scene::Scalar};
/// let scene = scenes::load("paper-flip")?;
/// let fast = Overrides { duration: Some(1.0), scalar: Some(Scalar::F32), ..Default::default() }
///     .apply(scene)?;
/// assert_eq!(fast.duration, 1.0);
/// let bad = Overrides { dt: Some(-1.0), ..Default::default() }.apply(fast);
/// assert_eq!(bad.unwrap_err().key.as_deref(), Some("integrator.dt"));
/// # Ok::<(), scenes::SceneError>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Integrator name (`lgvi`, `rk4`, `rk4-projected`, `rkmk4`, `euler`,
    /// `dopri`).
    pub integrator: Option<String>,
    /// Fixed step, or dopri's initial step, s.
    pub dt: Option<f64>,
    /// dopri's tolerance.
    pub tol: Option<f64>,
    /// Simulated time, s.
    pub duration: Option<f64>,
    /// Record interval, s.
    pub sample: Option<f64>,
    /// Sampled control at this rate, Hz (zero-order hold between
    /// instants).
    pub control_rate: Option<f64>,
    /// A flight computer's loop rates by name (`control.loop_rates`), in
    /// place of the scene's rates.
    pub loop_rates: Option<String>,
    /// Scalar type.
    pub scalar: Option<Scalar>,
    /// Linear-algebra backend.
    pub backend: Option<BackendKind>,
    /// Zero both integral gains (the paper's comparison without integral
    /// terms).
    pub no_integral: bool,
    /// A sensor suite by name (`[sensors] preset`), in place of the
    /// scene's sensors.
    pub sensors: Option<String>,
    /// What the modes read (`[estimator] kind`).
    pub estimator: Option<crate::scene::EstimatorKind>,
    /// The seed of the run's random numbers.
    pub seed: Option<u64>,
}

impl Overrides {
    /// The scene with these settings, validated: a bad value is a
    /// [`SceneError`] whose key is the scene file's dotted key
    /// (`integrator.dt`, `control.rate`, …) and whose message names the value.
    pub fn apply(&self, mut scene: Scene) -> Result<Scene, SceneError> {
        if let Some(k) = &self.integrator {
            k.parse::<integrators::IntegratorKind>()
                .map_err(|e| SceneError::at_key("integrator.kind", e.to_string()))?;
            scene.integrator.kind = k.clone();
        }
        let fields: [(Option<f64>, &str, &mut f64); 5] = [
            (self.dt, "integrator.dt", &mut scene.integrator.dt),
            (self.tol, "integrator.tol", &mut scene.integrator.tol),
            (self.duration, "duration", &mut scene.duration),
            (self.sample, "record.sample", &mut scene.record.sample),
            (self.control_rate, "control.rate", &mut scene.control.rate),
        ];
        for (value, key, slot) in fields {
            if let Some(v) = value {
                if !(v.is_finite() && v > 0.0) {
                    return Err(SceneError::at_key(
                        key,
                        format!("{key} = {v}: must be finite and > 0"),
                    ));
                }
                *slot = v;
            }
        }
        if self.control_rate.is_some() {
            scene.control.timing = Timing::Sampled;
        }
        if let Some(name) = &self.loop_rates {
            if self.control_rate.is_some() {
                return Err(SceneError::at_key(
                    "control.loop_rates",
                    format!(
                        "loop rates \"{name}\" set the control rate: give them or a control rate, not both"
                    ),
                ));
            }
            scene.control.timing = Timing::Sampled;
            scene.control.loop_rates = Some(name.clone());
            scene.control.rate = 0.0;
            scene.control.position_rate = 0.0;
            scene.control.estimator_rate = 0.0;
        }
        scene.scalar = self.scalar.unwrap_or(scene.scalar);
        scene.backend = self.backend.unwrap_or(scene.backend);
        if self.no_integral {
            scene.gains.k_i = 0.0;
            scene.gains.k_att_i = 0.0;
        }
        if let Some(p) = &self.sensors {
            scene.sensors = Some(crate::scene::SensorsSpec {
                preset: p.clone(),
                noise_scale: 1.0,
                mocap_latency: None,
                mocap_rate: None,
                ..crate::scene::SensorsSpec::default()
            });
        }
        if let Some(kind) = self.estimator {
            use crate::scene::EstimatorKind::{Complementary, Iekf};
            // The scene's own initial error is kept for a filter that reads it.
            let old = scene.estimator.take().unwrap_or_default();
            scene.estimator = Some(crate::scene::EstimatorSpec {
                kind,
                attitude_error: old
                    .attitude_error
                    .filter(|_| matches!(kind, Iekf | Complementary)),
                attitude_sigma: old.attitude_sigma.filter(|_| kind == Iekf),
                ..crate::scene::EstimatorSpec::default()
            });
        }
        scene.seed = self.seed.unwrap_or(scene.seed);
        scene
            .validate()
            .map_err(|(k, msg)| SceneError::at_key(k, msg))?;
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_setting_lands_and_a_bad_one_names_its_key() {
        let scene = crate::load("paper-flip").unwrap();
        let o = Overrides {
            integrator: Some("rk4".into()),
            dt: Some(2e-4),
            tol: Some(1e-8),
            duration: Some(1.5),
            sample: Some(0.01),
            control_rate: Some(250.0),
            loop_rates: None,
            scalar: Some(Scalar::F32),
            backend: Some(BackendKind::Glam),
            no_integral: true,
            sensors: Some("crazyflie".into()),
            estimator: Some(crate::scene::EstimatorKind::Mocap),
            seed: Some(4),
        };
        let s = o.apply(scene.clone()).unwrap();
        assert_eq!(
            s.sensors.as_ref().map(|p| p.preset.as_str()),
            Some("crazyflie")
        );
        assert_eq!(s.estimator.as_ref().map(|e| e.kind.name()), Some("mocap"));
        assert_eq!(s.seed, 4);
        let unknown = Overrides {
            sensors: Some("vicon".into()),
            ..Default::default()
        };
        let e = unknown.apply(scene.clone()).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("sensors.preset"));
        assert!(e.message.contains("\"vicon\""), "{}", e.message);
        let continuous = Overrides {
            sensors: Some("rotorpy".into()),
            estimator: Some(crate::scene::EstimatorKind::Mocap),
            ..Default::default()
        };
        let e = continuous.apply(scene.clone()).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("estimator.kind"));
        let mut late = scene.clone();
        late.sensors = Some(crate::scene::SensorsSpec {
            preset: "rotorpy".into(),
            noise_scale: 1.0,
            mocap_latency: Some(-0.5),
            mocap_rate: None,
            ..crate::scene::SensorsSpec::default()
        });
        let e = Overrides::default().apply(late).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("sensors.mocap_latency"));
        assert!(e.message.contains("mocap.latency = -0.5"), "{}", e.message);
        assert_eq!(s.integrator.kind, "rk4");
        assert_eq!((s.integrator.dt, s.integrator.tol), (2e-4, 1e-8));
        assert_eq!((s.duration, s.record.sample), (1.5, 0.01));
        assert_eq!((s.control.timing, s.control.rate), (Timing::Sampled, 250.0));
        assert_eq!((s.scalar, s.backend), (Scalar::F32, BackendKind::Glam));
        assert_eq!((s.gains.k_i, s.gains.k_att_i), (0.0, 0.0));
        assert_eq!(Overrides::default().apply(scene.clone()).unwrap(), scene);
        for (o, key) in [
            (
                Overrides {
                    integrator: Some("rk5".into()),
                    ..Default::default()
                },
                "integrator.kind",
            ),
            (
                Overrides {
                    tol: Some(f64::NAN),
                    ..Default::default()
                },
                "integrator.tol",
            ),
            (
                Overrides {
                    sample: Some(0.0),
                    ..Default::default()
                },
                "record.sample",
            ),
            (
                Overrides {
                    control_rate: Some(-3.0),
                    ..Default::default()
                },
                "control.rate",
            ),
        ] {
            let e = o.apply(scene.clone()).unwrap_err();
            assert_eq!(e.key.as_deref(), Some(key), "{e}");
        }
        let e = Overrides {
            duration: Some(f64::INFINITY),
            ..Default::default()
        }
        .apply(scene)
        .unwrap_err();
        assert!(e.to_string().contains("duration = inf"), "{e}");
    }
}
