//! `[ground]`: a flat ground under the vehicle, touched at its feet.

use serde::{Deserialize, Serialize};

/// A flat ground at `height` along e3 (which points down), touched at
/// `feet`; every number per contact point. Absent: no ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GroundSpec {
    /// The plane `z = height`, m.
    pub height: f64,
    /// Spring constant per foot, N/m.
    pub stiffness: f64,
    /// Damping per foot, N s/m.
    pub damping: f64,
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Slip speed below which friction is viscous, m/s.
    pub slip_speed: f64,
    /// A touchdown faster than this, m/s, is a crash: the run ends there
    /// (`inf`: never).
    pub crash_speed: f64,
    /// Contact points in the body frame, m (+b3 down); empty: four feet
    /// 0.1 m below the centre of mass, under the ends of the arms on b1
    /// and b2 (`vehicle.arm` out).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub feet: Vec<[f64; 3]>,
}

impl Default for GroundSpec {
    fn default() -> Self {
        let g = dynamics::Ground::at(0.0);
        Self {
            height: g.height,
            stiffness: g.stiffness,
            damping: g.damping,
            friction: g.friction,
            slip_speed: g.slip_speed,
            crash_speed: g.crash_speed,
            feet: Vec::new(),
        }
    }
}

impl GroundSpec {
    /// The ground's numbers.
    pub fn ground(&self) -> dynamics::Ground {
        dynamics::Ground {
            height: self.height,
            stiffness: self.stiffness,
            damping: self.damping,
            friction: self.friction,
            slip_speed: self.slip_speed,
            crash_speed: self.crash_speed,
        }
    }

    /// The contact points: `feet`, or four under arms of length `arm`.
    pub fn feet(&self, arm: f64) -> Vec<[f64; 3]> {
        if self.feet.is_empty() {
            vec![
                [arm, 0.0, 0.1],
                [0.0, arm, 0.1],
                [-arm, 0.0, 0.1],
                [0.0, -arm, 0.1],
            ]
        } else {
            self.feet.clone()
        }
    }

    /// Checks the numbers: the key and value at fault.
    pub(crate) fn check(&self) -> Result<(), (&'static str, String)> {
        if let Err(dynamics::DynamicsError::InvalidParameter {
            field,
            value,
            expected,
        }) = self.ground().check()
        {
            return Err((field, format!("`{field}` = {value}: expected {expected}")));
        }
        if let Some(c) = self.feet.iter().flatten().find(|c| !c.is_finite()) {
            return Err((
                "ground.feet",
                format!("`ground.feet` has {c}: must be finite (m)"),
            ));
        }
        Ok(())
    }
}
