//! A landing flight mode written outside the framework: descend at a set
//! speed from wherever the mode is entered, tracking the descent with the
//! paper's position law; below a cut-off height, cut the thrust and only
//! hold the attitude level. Public items of `controllers` and `lie` only.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, ControlError, IntegralLayout, Mode,
    ModeOutput, PositionGains, PositionReference, RigidBodyParams, VehicleState, attitude_control,
    position_control,
};
use lie::{Backend, Real, S, So3Mat};

/// Descend at `speed` m/s to `cut_height` m above the ground (`x₃ = 0`,
/// e3 down), then cut thrust.
///
/// Integral states: the paper's layout `[e_I, e_i]`, and the mode keeps
/// both on entry, so the disturbance estimate learned while hovering
/// carries into the descent.
pub struct Landing<B: Backend> {
    params: RigidBodyParams<B>,
    pos_gains: PositionGains<B>,
    att_gains: AttitudeGains<B>,
    speed: f64,
    cut_height: f64,
    /// Where and when the descent started (set on entry).
    start: Option<(f64, [f64; 3])>,
    /// The heading held after the cut.
    level: So3Mat<B>,
}

impl<B: Backend> Landing<B> {
    /// Landing with the paper's laws and gains.
    pub fn new(
        params: RigidBodyParams<B>,
        pos_gains: PositionGains<B>,
        att_gains: AttitudeGains<B>,
        speed: f64,
        cut_height: f64,
    ) -> Self {
        Self {
            params,
            pos_gains,
            att_gains,
            speed,
            cut_height,
            start: None,
            level: So3Mat::identity(),
        }
    }

    /// The descent reference at `t`: straight down from the entry point at
    /// `speed`, stopping at the cut-off height.
    fn descent(&self, t: f64) -> PositionReference<B> {
        let l = S::<B>::lit;
        let (t0, x0) = self.start.unwrap_or((0.0, [0.0, 0.0, -self.cut_height]));
        let floor = -self.cut_height;
        let z = (x0[2] + self.speed * (t - t0)).min(floor);
        let vz = if z < floor { self.speed } else { 0.0 };
        let mut r = PositionReference::hold(
            B::vec3(l(x0[0]), l(x0[1]), l(z)),
            B::vec3(l(1.0), l(0.0), l(0.0)),
        );
        r.v = B::vec3(l(0.0), l(0.0), l(vz));
        r
    }
}

impl<B: Backend> Mode<B> for Landing<B> {
    fn name(&self) -> &'static str {
        "landing"
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        IntegralLayout::slots(6)
    }
    fn enter(&mut self, t: S<B>, state: &VehicleState<B, So3Mat<B>>, _integrals: &mut [S<B>]) {
        let x = B::vec3_to_array(state.x).map(|c| c.to_f64_lossless());
        self.start = Some((t.to_f64_lossless(), x));
    }
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        let e_att = B::vec3(integrals[0], integrals[1], integrals[2]);
        let e_pos = B::vec3(integrals[3], integrals[4], integrals[5]);
        let height = -B::vec3_to_array(state.x)[2].to_f64_lossless();
        if height <= self.cut_height {
            // Thrust cut: hold level with the attitude law, integrals idle.
            let zero = B::vec3(S::<B>::lit(0.0), S::<B>::lit(0.0), S::<B>::lit(0.0));
            let hold = AttitudeReference {
                rd: self.level,
                omega_d: zero,
                omega_d_dot: zero,
            };
            let out = attitude_control(
                &self.params,
                &self.att_gains,
                state.r,
                state.omega,
                e_att,
                &hold,
            )?;
            return Ok(ModeOutput {
                thrust: S::<B>::lit(0.0),
                moment: out.moment,
                desired: self.level,
                desired_omega: zero,
                psi: out.psi,
                rotor_speeds: None,
            });
        }
        let out = position_control(
            &self.params,
            &self.pos_gains,
            &self.att_gains,
            &controllers::PositionInput {
                state,
                e_i_pos: e_pos,
                e_i_att: e_att,
                reference: &self.descent(t.to_f64_lossless()),
                model: AccelerationModel::Nominal,
            },
        )?;
        rates[..3].copy_from_slice(&B::vec3_to_array(out.e_i_att_rate));
        rates[3..6].copy_from_slice(&B::vec3_to_array(out.e_i_pos_rate));
        Ok(ModeOutput {
            thrust: out.thrust,
            moment: out.moment,
            desired: out.rc,
            desired_omega: out.omega_c,
            psi: out.psi,
            rotor_speeds: None,
        })
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        let x = B::vec3_to_array(self.descent(t).x);
        Some(x.map(|c| c.to_f64_lossless()))
    }
}
