//! The control keys as the engine's [`scenarios::Control`]: one rate, a
//! multi-rate loop, or a flight computer's rates by name.

use super::{ControlSpec, Timing};

impl ControlSpec {
    /// The engine's control these keys give, or the key at fault and why.
    pub fn control(&self) -> Result<scenarios::Control, (&'static str, String)> {
        use scenarios::{Control, LoopRates};
        if let Some(name) = &self.loop_rates {
            let rates = match name.as_str() {
                "crazyflie" => LoopRates::crazyflie(),
                other => {
                    return Err((
                        "control.loop_rates",
                        format!("`loop_rates` = \"{other}\": expected crazyflie"),
                    ));
                }
            };
            if self.rate != 0.0 || self.position_rate != 0.0 || self.estimator_rate != 0.0 {
                return Err((
                    "control.loop_rates",
                    format!(
                        "`loop_rates` = \"{name}\" sets the rates: give it or `rate`, `position_rate` and `estimator_rate`, not both"
                    ),
                ));
            }
            return Ok(Control::MultiRate(rates));
        }
        let fields = [
            ("control.position_rate", self.position_rate),
            ("control.estimator_rate", self.estimator_rate),
        ];
        for (key, v) in fields {
            if !(v.is_finite() && v >= 0.0) {
                return Err((
                    key,
                    format!("`{key}` = {v}: must be finite and ≥ 0 (Hz; 0: the control rate)"),
                ));
            }
        }
        if self.timing == Timing::Continuous {
            if let Some((key, _)) = fields.iter().find(|(_, v)| *v > 0.0) {
                return Err((
                    key,
                    format!(
                        "`{key}` needs `timing = \"sampled\"`: a continuous law has no instants"
                    ),
                ));
            }
            return Ok(Control::Continuous);
        }
        if self.position_rate == 0.0 && self.estimator_rate == 0.0 {
            return Ok(Control::Sampled { rate: self.rate });
        }
        let or_rate = |v: f64| if v > 0.0 { v } else { self.rate };
        let rates = LoopRates {
            estimator: or_rate(self.estimator_rate),
            attitude: self.rate,
            position: or_rate(self.position_rate),
        };
        rates.check().map_err(|(field, msg)| {
            let key = match field {
                "position" => "control.position_rate",
                "estimator" => "control.estimator_rate",
                _ => "control.rate",
            };
            (key, msg)
        })?;
        Ok(Control::MultiRate(rates))
    }

    /// The timing for a report line: `continuous`, `sampled 500 Hz`, or
    /// the three rates of a multi-rate loop.
    pub fn describe(&self) -> String {
        match self.control() {
            Ok(scenarios::Control::Continuous) => "continuous".into(),
            Ok(scenarios::Control::Sampled { rate }) => format!("sampled {rate} Hz"),
            Ok(scenarios::Control::MultiRate(r)) => format!(
                "multi-rate (estimator {} Hz, attitude {} Hz, position {} Hz)",
                r.estimator, r.attitude, r.position
            ),
            Err((_, msg)) => msg,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenarios::{Control, LoopRates};

    fn spec(timing: Timing, rate: f64, position: f64, estimator: f64) -> ControlSpec {
        ControlSpec {
            timing,
            rate,
            position_rate: position,
            estimator_rate: estimator,
            ..ControlSpec::default()
        }
    }

    /// One rate is sampled control, a second rate a multi-rate loop (the
    /// missing one taken from `rate`), the preset the Crazyflie's rates;
    /// each bad value is reported at its own key with the value.
    #[test]
    fn the_keys_give_the_engines_control_and_name_a_bad_one() {
        let s = Timing::Sampled;
        assert_eq!(
            spec(s, 250.0, 0.0, 0.0).control(),
            Ok(Control::Sampled { rate: 250.0 })
        );
        assert_eq!(
            spec(s, 500.0, 100.0, 0.0).control(),
            Ok(Control::MultiRate(LoopRates {
                estimator: 500.0,
                attitude: 500.0,
                position: 100.0
            }))
        );
        let cf = ControlSpec {
            loop_rates: Some("crazyflie".into()),
            ..ControlSpec::default()
        };
        assert_eq!(cf.control(), Ok(Control::MultiRate(LoopRates::crazyflie())));
        let bad = [
            (spec(s, 100.0, 500.0, 0.0), "control.position_rate", "500"),
            (spec(s, 100.0, -1.0, 0.0), "control.position_rate", "-1"),
            (
                spec(s, 100.0, 0.0, f64::NAN),
                "control.estimator_rate",
                "NaN",
            ),
            (
                spec(Timing::Continuous, 0.0, 50.0, 0.0),
                "control.position_rate",
                "sampled",
            ),
            (
                ControlSpec {
                    rate: 200.0,
                    ..cf.clone()
                },
                "control.loop_rates",
                "not both",
            ),
            (
                ControlSpec {
                    loop_rates: Some("px4".into()),
                    ..ControlSpec::default()
                },
                "control.loop_rates",
                "\"px4\"",
            ),
        ];
        for (c, key, word) in bad {
            let (k, msg) = c.control().unwrap_err();
            assert_eq!(k, key, "{msg}");
            assert!(msg.contains(word), "{msg}");
        }
    }
}
