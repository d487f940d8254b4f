//! Checking a scene before anything runs: each error names the key and
//! the value.

use super::*;

impl Scene {
    /// Checks that the vehicle kind is a built-in or one of `custom_kinds`.
    pub fn check_kind(&self, custom_kinds: &[&str]) -> Result<(), (&'static str, String)> {
        if let VehicleKind::Custom(name) = &self.vehicle.kind
            && !custom_kinds.contains(&name.as_str())
        {
            let mut names: Vec<&str> = VehicleKind::BUILT_IN.iter().map(|k| k.name()).collect();
            names.extend_from_slice(custom_kinds);
            return Err((
                "vehicle.kind",
                format!(
                    "vehicle `kind` = \"{name}\": expected one of {} (a program can register \
                     its own kinds with scenes::Registry)",
                    names.join(", ")
                ),
            ));
        }
        if !matches!(self.vehicle.kind, VehicleKind::Custom(_)) && !self.vehicle.params.is_empty() {
            return Err((
                "vehicle.params",
                format!(
                    "`vehicle.params` is for registered kinds; the built-in `{}` takes none",
                    self.vehicle.kind.name()
                ),
            ));
        }
        Ok(())
    }

    /// Checks values; on failure returns the dotted key and a message naming
    /// it and the value.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        pos("duration", self.duration)?;
        self.validate_vehicle()?;
        self.validate_settings()?;
        self.validate_sensing()?;
        let mut last = 0.0;
        for (k, seg) in self.plan.iter().enumerate() {
            self.validate_segment(k, seg, &mut last)?;
            validate_references(k, seg)?;
        }
        if !self.plan.is_empty() && self.vehicle.kind == VehicleKind::FreeRigidBody {
            return Err((
                "plan",
                "a free rigid body has no actuators; remove the `[[plan]]` segments".into(),
            ));
        }
        Ok(())
    }

    /// The vehicle table: positive mass, arm and principal moments that a
    /// rigid body can have (unless the file allows otherwise), finite rest.
    fn validate_vehicle(&self) -> Result<(), (&'static str, String)> {
        let ve = &self.vehicle;
        pos("vehicle.mass", ve.mass)?;
        if let Some(m) = ve.model_mass {
            pos("vehicle.model_mass", m)?;
        }
        for j in ve.inertia {
            pos("vehicle.inertia", j)?;
        }
        // Principal moments of a rigid body: each is at most the sum of
        // the other two (J3 = ∫(x² + y²) ≤ ∫(y² + z²) + ∫(x² + z²)).
        let [j1, j2, j3] = ve.inertia;
        for (k, (a, b, c)) in [(j1, j2, j3), (j2, j1, j3), (j3, j1, j2)]
            .into_iter()
            .enumerate()
        {
            if a > (b + c) * (1.0 + 1e-12) && !ve.allow_nonphysical_inertia {
                return Err((
                    "vehicle.inertia",
                    format!(
                        "`vehicle.inertia` = {:?}: J{} = {a} exceeds the sum of the other two ({}); \
                         no rigid body has these principal moments (set \
                         `allow_nonphysical_inertia = true` to use them anyway, as the paper's \
                         example does)",
                        ve.inertia,
                        k + 1,
                        b + c
                    ),
                ));
            }
        }
        nonneg("vehicle.gravity", ve.gravity)?;
        pos("vehicle.arm", ve.arm)?;
        self.validate_multirotor()?;
        nonneg("vehicle.stand_height", ve.stand_height)?;
        if !(ve.c_tau_f.is_finite() && ve.c_tau_f != 0.0) {
            return Err((
                "vehicle.c_tau_f",
                format!(
                    "`vehicle.c_tau_f` = {}: must be finite and non-zero",
                    ve.c_tau_f
                ),
            ));
        }
        Ok(())
    }

    /// The `[vehicle.multirotor]` table: present exactly for the
    /// `multirotor` kind, parameters the vehicle accepts, and rotors that
    /// can lift the airframe (a scene that names a preset but keeps the
    /// default airframe, the paper's 4.34 kg, would otherwise fall).
    fn validate_multirotor(&self) -> Result<(), (&'static str, String)> {
        let ve = &self.vehicle;
        let key = "vehicle.multirotor";
        match (&ve.kind, &ve.multirotor) {
            (VehicleKind::Multirotor, None) => {
                return Err((
                    key,
                    "the `multirotor` kind needs a `[vehicle.multirotor]` table with \
                     `preset = \"crazyflie\"` or `\"hummingbird\"`"
                        .into(),
                ));
            }
            (VehicleKind::Multirotor, Some(_)) => {}
            (k, Some(_)) => {
                return Err((
                    key,
                    format!(
                        "`[vehicle.multirotor]` is for the `multirotor` kind, not `{}`",
                        k.name()
                    ),
                ));
            }
            (_, None) => return Ok(()),
        }
        if let Some(spec) = &ve.multirotor {
            match (&spec.rotor_positions, &spec.rotor_directions) {
                (Some(p), Some(d)) if p.len() != d.len() => {
                    return Err((
                        "vehicle.multirotor.rotor_directions",
                        format!(
                            "`rotor_directions` has {} entries for {} `rotor_positions`; give one per rotor",
                            d.len(),
                            p.len()
                        ),
                    ));
                }
                (Some(_), None) | (None, Some(_)) => {
                    return Err((
                        "vehicle.multirotor.rotor_positions",
                        "`rotor_positions` and `rotor_directions` go together (the X layout is the default for neither)".into(),
                    ));
                }
                _ => {}
            }
        }
        let p = multirotor_params::<lie::NalgebraF64>(self);
        let lift = p.rotors.len() as f64 * p.k_eta * p.rotor_speed_max * p.rotor_speed_max;
        if let Err(e) = dynamics::Multirotor::new(p) {
            return Err((key, format!("`[vehicle.multirotor]`: {e}")));
        }
        if lift <= ve.mass * ve.gravity {
            return Err((
                "vehicle.mass",
                format!(
                    "`vehicle.mass` = {} kg: the rotors lift at most {lift:.4} N (n k_eta \
                     rotor_speed_max²), not the weight {:.4} N; give the airframe's own mass, \
                     inertia and arm (the crazyflie's: mass = 0.03, inertia = [1.43e-5, \
                     1.43e-5, 2.89e-5], arm = 0.043)",
                    ve.mass,
                    ve.mass * ve.gravity
                ),
            ));
        }
        Ok(())
    }

    /// Disturbances, initial state, gains, integrator, control, recording.
    fn validate_settings(&self) -> Result<(), (&'static str, String)> {
        if let Some(w) = &self.wind {
            w.build()?;
        }
        if let Some(g) = &self.ground {
            g.check()?;
            if matches!(self.integrator.kind.as_str(), "euler" | "lgvi") {
                return Err((
                    "integrator.kind",
                    format!(
                        "`integrator.kind` = \"{}\" cannot step the ground contact (explicit \
                         Euler is unstable on it, the LGVI's iteration does not converge): \
                         use rk4, rk4-projected, rkmk4 or dopri",
                        self.integrator.kind
                    ),
                ));
            }
        }
        if let Some(d) = &self.disturbance {
            finite3("disturbance.force", &d.force)?;
            finite3("disturbance.moment", &d.moment)?;
        }
        let i = &self.initial;
        finite3("initial.x", &i.x)?;
        finite3("initial.v", &i.v)?;
        finite3("initial.rotation", &i.rotation)?;
        finite3("initial.omega", &i.omega)?;
        let g = &self.gains;
        for (k, v) in [
            ("gains.k_x", g.k_x),
            ("gains.k_v", g.k_v),
            ("gains.k_r", g.k_r),
            ("gains.k_omega", g.k_omega),
            ("gains.sigma", g.sigma),
        ] {
            pos(k, v)?;
        }
        for (k, v) in [
            ("gains.k_i", g.k_i),
            ("gains.k_att_i", g.k_att_i),
            ("gains.c1", g.c1),
            ("gains.c2", g.c2),
        ] {
            nonneg(k, v)?;
        }
        pos("integrator.dt", self.integrator.dt)?;
        if self
            .integrator
            .kind
            .parse::<integrators::IntegratorKind>()
            .is_err()
        {
            return Err((
                "integrator.kind",
                format!(
                    "integrator `kind` = \"{}\": expected one of lgvi, rk4, rk4-projected, rkmk4, euler, dopri",
                    self.integrator.kind
                ),
            ));
        }
        pos("integrator.tol", self.integrator.tol)?;
        // Checked even when unused (continuous control): a NaN in a file
        // is a mistake whatever the timing.
        self.control.control()?;
        if self.control.timing == Timing::Sampled && self.control.loop_rates.is_none() {
            if !(self.control.rate.is_finite() && self.control.rate > 0.0) {
                return Err((
                    "control.rate",
                    format!(
                        "`rate` = {}: `timing = \"sampled\"` needs a controller rate > 0 (Hz) in [control]",
                        self.control.rate
                    ),
                ));
            }
        } else {
            nonneg("control.rate", self.control.rate)?;
        }
        pos("record.sample", self.record.sample)?;
        Ok(())
    }

    /// Segment `k`: its switch (`until` after the previous one's, or
    /// `until_psi` in (0, 2) with a segment after it) and its mode's
    /// references; `last` is the previous `until`.
    fn validate_segment(
        &self,
        k: usize,
        seg: &SegmentSpec,
        last: &mut f64,
    ) -> Result<(), (&'static str, String)> {
        let is_last = k + 1 == self.plan.len();
        if let Some(p) = seg.until_psi {
            if seg.until.is_some() {
                return Err((
                    "until_psi",
                    format!("plan[{k}] has both `until` and `until_psi`; give one"),
                ));
            }
            if !(p.is_finite() && p > 0.0 && p < 2.0) {
                return Err((
                    "until_psi",
                    format!("plan[{k}] `until_psi` = {p}: must be in (0, 2)"),
                ));
            }
            if is_last {
                return Err((
                    "until_psi",
                    format!("plan[{k}] is the last segment: `until_psi` has nothing to switch to"),
                ));
            }
        }
        self.validate_clearance(k, seg)?;
        match seg.until {
            // A condition-switched segment's own checks are above; its mode
            // and references are checked below like any other's.
            _ if seg.until_psi.is_some() || seg.until_clearance.is_some() => {}
            Some(u) if !(u.is_finite() && u > *last) => {
                return Err((
                    "until",
                    format!("plan[{k}] `until` = {u}: must be finite and after {last}"),
                ));
            }
            Some(u) => *last = u,
            None if !is_last => {
                return Err((
                    "until",
                    format!("plan[{k}] has no `until`; only the last segment may omit it"),
                ));
            }
            None => {}
        }
        match seg.mode {
            ModeKind::Attitude if seg.attitude.is_none() => {
                return Err((
                    "mode",
                    format!("plan[{k}] is `attitude` mode but has no `[plan.attitude]` reference"),
                ));
            }
            ModeKind::Attitude
                if seg.thrust == ThrustSpec::PdProjection && seg.position.is_none() =>
            {
                return Err((
                    "thrust",
                    format!(
                        "plan[{k}] `thrust` = \"pd-projection\" needs a `[plan.position]` target"
                    ),
                ));
            }
            ModeKind::Position if seg.position.is_none() => {
                return Err((
                    "mode",
                    format!("plan[{k}] is `position` mode but has no `[plan.position]` reference"),
                ));
            }
            ModeKind::Position | ModeKind::TakeOff | ModeKind::Hover | ModeKind::Land
                if !matches!(
                    self.vehicle.kind,
                    VehicleKind::Quadrotor
                        | VehicleKind::Hexarotor
                        | VehicleKind::Multirotor
                        | VehicleKind::Custom(_)
                ) =>
            {
                return Err((
                    "mode",
                    format!(
                        "plan[{k}] is `{}` mode but the vehicle `{}` cannot translate",
                        seg.mode.name(),
                        self.vehicle.kind.name()
                    ),
                ));
            }
            _ => {}
        }
        validate_phase(k, seg)
    }

    /// Segment `k`'s `until_clearance`: finite and ≥ 0, over a `[ground]`,
    /// alone, with a segment after it.
    fn validate_clearance(
        &self,
        k: usize,
        seg: &SegmentSpec,
    ) -> Result<(), (&'static str, String)> {
        let Some(c) = seg.until_clearance else {
            return Ok(());
        };
        let key = "until_clearance";
        let problem = if seg.until.is_some() || seg.until_psi.is_some() {
            "give one of `until`, `until_psi` and `until_clearance`".to_string()
        } else if !(c.is_finite() && c >= 0.0) {
            format!("`until_clearance` = {c}: must be finite and ≥ 0 (m)")
        } else if self.ground.is_none() {
            "`until_clearance` needs a `[ground]` to measure from".to_string()
        } else if k + 1 == self.plan.len() {
            "is the last segment: `until_clearance` has nothing to switch to".to_string()
        } else {
            return Ok(());
        };
        Err((key, format!("plan[{k}] {problem}")))
    }
}

/// Segment `k`'s take-off, hover, landing or motor cut: no reference of
/// its own (it starts where it is entered), and `height`, `rate`, `ramp`
/// only where they apply, each finite and positive.
fn validate_phase(k: usize, seg: &SegmentSpec) -> Result<(), (&'static str, String)> {
    let mode = seg.mode.name();
    let phase = !matches!(seg.mode, ModeKind::Attitude | ModeKind::Position);
    if phase && (seg.position.is_some() || seg.attitude.is_some()) {
        return Err((
            "mode",
            format!(
                "plan[{k}] is `{mode}` mode: it starts where it is entered and takes no reference"
            ),
        ));
    }
    let applies = [
        ("height", seg.height, seg.mode == ModeKind::TakeOff),
        (
            "rate",
            seg.rate,
            matches!(seg.mode, ModeKind::TakeOff | ModeKind::Land),
        ),
        ("ramp", seg.ramp, seg.mode == ModeKind::Land),
    ];
    for (key, value, fits) in applies {
        if value.is_some() && !fits {
            return Err((
                key,
                format!("plan[{k}] `{key}` does not apply to `{mode}` mode"),
            ));
        }
    }
    if let Some(Err((key, value))) = seg.vertical::<lie::NalgebraF64>().map(|v| v.check()) {
        return Err((
            key,
            format!("plan[{k}] `{key}` = {value}: must be finite and > 0"),
        ));
    }
    Ok(())
}

/// Segment `k`'s reference parameters: a NaN here would surface only as a
/// non-finite command mid-run.
fn validate_references(k: usize, seg: &SegmentSpec) -> Result<(), (&'static str, String)> {
    let num = |key: &'static str, v: f64| -> Result<(), (&'static str, String)> {
        if v.is_finite() {
            Ok(())
        } else {
            Err((key, format!("plan[{k}] `{key}` = {v}: must be finite")))
        }
    };
    let num3 = |key: &'static str, v: &[f64; 3]| -> Result<(), (&'static str, String)> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(())
        } else {
            Err((key, format!("plan[{k}] `{key}` = {v:?}: must be finite")))
        }
    };
    match &seg.attitude {
        Some(AttitudeRef::EulerExperiment {
            amplitude,
            frequency,
        }) => {
            num("amplitude", *amplitude)?;
            num("frequency", *frequency)?;
        }
        Some(AttitudeRef::Hold { rotation }) => num3("rotation", rotation)?,
        Some(AttitudeRef::PaperFlip {}) | None => {}
    }
    match &seg.position {
        Some(PositionRef::Hold { x, b1d }) => {
            num3("x", x)?;
            num3("b1d", b1d)?;
            if b1d.iter().map(|c| c * c).sum::<f64>() < 1e-12 {
                return Err((
                    "b1d",
                    format!("plan[{k}] `b1d` = {b1d:?}: must be non-zero"),
                ));
            }
        }
        Some(PositionRef::FigureEight {
            center,
            a,
            b,
            omega,
        }) => {
            num3("center", center)?;
            num("a", *a)?;
            num("b", *b)?;
            num("omega", *omega)?;
        }
        Some(PositionRef::Sinusoids {
            center,
            amplitude,
            omega,
            phase,
        }) => {
            num3("center", center)?;
            num3("amplitude", amplitude)?;
            num3("omega", omega)?;
            num3("phase", phase)?;
        }
        Some(PositionRef::Circle {
            center,
            radius,
            omega,
        }) => {
            num3("center", center)?;
            num("radius", *radius)?;
            num("omega", *omega)?;
        }
        Some(
            p @ (PositionRef::MinSnap { start, .. } | PositionRef::TrajectoryFile { start, .. }),
        ) => {
            num("start", *start)?;
            p.plan()
                .map_err(|e| (e.key(), format!("plan[{k}] position: {e}")))?;
        }
        None => {}
    }
    Ok(())
}

fn pos(key: &'static str, v: f64) -> Result<(), (&'static str, String)> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err((key, format!("`{key}` = {v}: must be finite and > 0")))
    }
}
fn nonneg(key: &'static str, v: f64) -> Result<(), (&'static str, String)> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err((key, format!("`{key}` = {v}: must be finite and ≥ 0")))
    }
}
fn finite3(key: &'static str, v: &[f64; 3]) -> Result<(), (&'static str, String)> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err((key, format!("`{key}` = {v:?}: must be finite")))
    }
}
