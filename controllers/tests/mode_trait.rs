//! The `Mode` trait's defaults, its forwarding through `&mut M` (how a
//! scheduler borrows a user's mode), and what the paper's two modes
//! declare: their integral counts and that forcing a sat′ branch reaches
//! the position law.

use controllers::*;
use dynamics::paper;
use lie::{NalgebraF64 as B, S, So3Mat};
use nalgebra::Vector3;

type V = Vector3<f64>;
type R = So3Mat<B>;

fn at_rest() -> VehicleState<B, R> {
    VehicleState {
        x: V::zeros(),
        v: V::zeros(),
        r: R::identity(),
        omega: V::zeros(),
    }
}

fn output(thrust: f64) -> ModeOutput<B> {
    ModeOutput {
        thrust,
        moment: V::zeros(),
        desired: R::identity(),
        desired_omega: V::zeros(),
        psi: 0.0,
        rotor_speeds: None,
    }
}

/// A mode that answers only what it must.
struct Bare;
impl Mode<B> for Bare {
    fn name(&self) -> &'static str {
        "bare"
    }
    fn command(
        &self,
        _t: S<B>,
        _s: &VehicleState<B, R>,
        _i: &[S<B>],
        _r: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        Ok(output(1.0))
    }
}

/// A mode that overrides everything, with answers no default gives.
#[derive(Default)]
struct Full {
    forced: Vec<(usize, SatBranch)>,
    entered: u32,
    bps: Vec<Breakpoint<B>>,
}
impl Mode<B> for Full {
    fn name(&self) -> &'static str {
        "full"
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        IntegralLayout {
            count: 2,
            breakpoints: &self.bps,
        }
    }
    fn enter(&mut self, _t: S<B>, _s: &VehicleState<B, R>, integrals: &mut [S<B>]) {
        self.entered += 1;
        integrals[0] = 7.0;
    }
    fn command(
        &self,
        _t: S<B>,
        _s: &VehicleState<B, R>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        rates[1] = -integrals[0];
        let speeds = [100.0 * integrals[0]; 4];
        Ok(ModeOutput {
            rotor_speeds: RotorSpeeds::new(&speeds),
            ..output(2.0)
        })
    }
    fn force_branch(&mut self, index: usize, branch: SatBranch) {
        self.forced.push((index, branch));
    }
    fn desired_position(&self, t: f64) -> Option<[f64; 3]> {
        Some([t, 2.0 * t, 3.0])
    }
}

#[test]
fn the_defaults_are_nothing_and_no() {
    let mut m = Bare;
    assert_eq!(m.integrals(), IntegralLayout::slots(0));
    assert!(m.integrals().breakpoints.is_empty());
    assert_eq!(m.desired_position(1.0), None);
    let mut reg = [1.0, 2.0];
    m.enter(0.0, &at_rest(), &mut reg);
    assert_eq!(reg, [1.0, 2.0], "the default entry keeps the register");
}

#[test]
fn a_borrowed_mode_answers_as_the_mode() {
    let mut full = Full {
        bps: vec![Breakpoint {
            slot: 4,
            level: 0.5,
        }],
        ..Default::default()
    };
    {
        let mut m: &mut Full = &mut full;
        let m: &mut dyn Mode<B> = &mut m;
        assert_eq!(m.name(), "full");
        assert_eq!(m.integrals().count, 2);
        let mut reg = [0.0, 0.0];
        m.enter(0.0, &at_rest(), &mut reg);
        assert_eq!(reg[0], 7.0);
        let mut rates = [0.0, 0.0];
        let out = m.command(0.0, &at_rest(), &reg, &mut rates).unwrap();
        assert_eq!((out.thrust, rates), (2.0, [0.0, -7.0]));
        let speeds = out.rotor_speeds.expect("Full commands rotor speeds");
        assert_eq!(speeds.as_slice(), &[700.0; 4]);
        assert_eq!(m.integrals().breakpoints.len(), 1);
        assert_eq!(m.integrals().breakpoints[0].slot, 4);
        m.force_branch(1, SatBranch::Outside);
        assert_eq!(m.desired_position(2.0), Some([2.0, 4.0, 3.0]));
    }
    assert_eq!(full.entered, 1);
    assert_eq!(full.forced, vec![(1, SatBranch::Outside)]);
}

/// The paper's position mode (quadrotor, gains) on reference `src`.
fn paper_position_mode<P: PositionSource<B>>(src: P) -> PositionMode<B, P> {
    PositionMode::new(
        RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        src,
    )
}

fn position_mode() -> PositionMode<B, HoldPosition<B>> {
    paper_position_mode(HoldPosition(PositionReference::hold(V::zeros(), V::y())))
}

/// The register layouts the plan relies on: attitude `[e_I]`, position
/// `[e_I, e_i]`; the position mode's breakpoints are e_i's three slots at
/// ±σ; forcing a branch changes the law's command where sat′ decides.
#[test]
fn the_papers_modes_declare_their_register_and_obey_forced_branches() {
    let att = AttitudeMode::<B, _, HoldPosition<B>>::new(
        RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        AttitudeGains::paper(),
        |_t: f64| AttitudeReference {
            rd: R::identity(),
            omega_d: V::zeros(),
            omega_d_dot: V::zeros(),
        },
        AttitudeThrust::Constant(7.4),
    );
    assert_eq!(Mode::<B>::integrals(&att), IntegralLayout::slots(3));
    let mut pos = position_mode();
    assert_eq!(Mode::<B>::integrals(&pos).count, 6);
    let slots: Vec<(usize, f64)> = Mode::<B>::integrals(&pos)
        .breakpoints
        .iter()
        .map(|b| (b.slot, b.level))
        .collect();
    assert_eq!(slots, vec![(3, 1.0), (4, 1.0), (5, 1.0)]);
    // e_i outside σ in its first component, moving: sat′ = 0 there unless
    // the branch is forced inside.
    let mut s = at_rest();
    s.v = V::new(0.3, -0.2, 0.1);
    let reg = [0.0, 0.0, 0.0, 1.5, 0.2, -0.1];
    let mut rates = [0.0; 6];
    let auto = pos.command(0.0, &s, &reg, &mut rates).unwrap();
    pos.force_branch(0, SatBranch::Inside);
    let inside = pos.command(0.0, &s, &reg, &mut rates).unwrap();
    pos.force_branch(0, SatBranch::Auto);
    let again = pos.command(0.0, &s, &reg, &mut rates).unwrap();
    assert!((auto.desired_omega - inside.desired_omega).norm() > 1e-3);
    assert_eq!(auto.desired_omega, again.desired_omega);
}

/// Rotor speeds keep their order and count up to `MAX_ROTORS`; one more
/// is refused rather than cut (a vehicle with more rotors takes a wrench).
#[test]
fn rotor_speeds_hold_up_to_max_rotors_in_order() {
    let w: Vec<f64> = (0..=MAX_ROTORS).map(|k| 400.0 + k as f64).collect();
    for n in [0, 1, 4, 6, MAX_ROTORS] {
        let s = RotorSpeeds::<B>::new(&w[..n]).expect("within MAX_ROTORS");
        assert_eq!(s.as_slice(), &w[..n]);
    }
    assert_eq!(RotorSpeeds::<B>::new(&w), None, "{} speeds", w.len());
}

/// A held reference is lent (`PositionSource::constant`) and the position
/// mode reads it in place; a closure's reference is computed at every
/// evaluation. The two paths command the same thrust, moment and
/// integral rates bit for bit, in a tilted, spinning, moving state with
/// nonzero integrals and a reference whose derivatives are all nonzero.
#[test]
fn a_held_reference_read_in_place_commands_what_a_computed_one_does() {
    let reference = PositionReference::<B> {
        x: V::new(0.4, -0.3, -1.2),
        v: V::new(0.2, 0.1, -0.05),
        a: V::new(-0.1, 0.3, 0.02),
        jerk: V::new(0.2, -0.1, 0.01),
        snap: V::new(-0.3, 0.1, 0.0),
        b1d: V::new(1.0, 0.2, 0.0),
        b1d_dot: V::new(-0.1, 0.3, 0.0),
        b1d_ddot: V::new(0.05, -0.2, 0.0),
    };
    let held = HoldPosition(reference);
    assert_eq!(held.constant(), Some(&reference));
    assert_eq!(held.position(2.5), reference);
    let computed = move |_t: f64| reference;
    assert!(computed.constant().is_none());
    let (a, b) = (paper_position_mode(held), paper_position_mode(computed));
    let s = VehicleState::<B, R> {
        x: V::new(0.1, 0.2, -1.0),
        v: V::new(0.5, -0.4, 0.2),
        r: R::exp(V::new(0.3, -0.2, 0.6)),
        omega: V::new(0.7, -0.3, 0.4),
    };
    let reg = [0.05, -0.02, 0.01, 0.3, -0.6, 0.2];
    let (mut ra, mut rb) = ([0.0; 6], [0.0; 6]);
    let oa = a.command(0.7, &s, &reg, &mut ra).unwrap();
    let ob = b.command(0.7, &s, &reg, &mut rb).unwrap();
    assert_eq!(oa.thrust.to_bits(), ob.thrust.to_bits());
    assert_eq!(oa.moment, ob.moment);
    assert_eq!(oa.desired_omega, ob.desired_omega);
    assert_eq!(ra, rb);
}

/// A tilted, moving state away from the reference, and a register with
/// both integrals nonzero.
fn away() -> (VehicleState<B, R>, [f64; 6]) {
    let s = VehicleState {
        x: V::new(0.3, -0.2, 0.1),
        v: V::new(0.5, 0.1, -0.2),
        r: R::exp(V::new(0.2, -0.1, 0.4)),
        omega: V::new(0.3, -0.5, 0.2),
    };
    (s, [0.01, -0.02, 0.03, 0.1, -0.05, 0.2])
}

/// The multi-rate position law: at its own outer instant the command is
/// the single-rate law's bit for bit; between outer instants the thrust,
/// `R_c`, `Ω_c` and `e_i`'s rate stay what the outer instant computed
/// while the moment and `e_I`'s rate are the attitude law's (eqn:aM) on
/// the held `R_c, Ω_c, Ω̇_c` at the new state (an independent call of
/// `attitude_control`); entering the mode again drops the held output.
#[test]
fn the_position_mode_holds_its_outer_loop_between_outer_instants() {
    let circle = |t: f64| {
        let mut r = PositionReference::<B>::hold(V::new(t.cos(), t.sin(), 0.0), V::x());
        r.v = V::new(-t.sin(), t.cos(), 0.0);
        r.a = V::new(-t.cos(), -t.sin(), 0.0);
        r.jerk = V::new(t.sin(), -t.cos(), 0.0);
        r.snap = V::new(t.cos(), t.sin(), 0.0);
        r
    };
    let mut m = paper_position_mode(circle);
    let (s, reg) = away();
    let (mut rates1, mut rates2) = ([0.0; 6], [0.0; 6]);
    let single = m.command(0.4, &s, &reg, &mut rates1).unwrap();
    m.update_outer(controllers::load_token(), 0.4, &s, &reg)
        .unwrap();
    let held = m.command(0.4, &s, &reg, &mut rates2).unwrap();
    assert_eq!(single, held, "the outer instant's own command");
    assert_eq!(rates1, rates2);

    // 2 ms later, at another state: the attitude law on the held R_c.
    let mut s2 = s;
    s2.r = R::exp(V::new(0.21, -0.12, 0.41));
    s2.omega = V::new(0.35, -0.45, 0.25);
    s2.x += V::new(0.001, 0.0, 0.0);
    let mut rates3 = [0.0; 6];
    let later = m.command(0.402, &s2, &reg, &mut rates3).unwrap();
    let fresh = m.command(0.402, &s2, &reg, &mut [0.0; 6]).unwrap();
    assert_eq!(later, fresh, "a mode's answer is a function of its inputs");
    assert_eq!(later.thrust, single.thrust);
    assert_eq!(later.desired, single.desired);
    assert_eq!(later.desired_omega, single.desired_omega);
    assert_eq!(rates3[3..], rates1[3..], "e_i's rate is held");
    let pos = position_control(
        &RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &PositionGains::paper(),
        &AttitudeGains::paper(),
        &PositionInput {
            state: &s,
            e_i_pos: V::new(0.1, -0.05, 0.2),
            e_i_att: V::new(0.01, -0.02, 0.03),
            reference: &circle(0.4),
            model: AccelerationModel::Nominal,
        },
    )
    .unwrap();
    let att = attitude_control(
        &RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &AttitudeGains::paper(),
        s2.r,
        s2.omega,
        V::new(0.01, -0.02, 0.03),
        &AttitudeReference {
            rd: pos.rc,
            omega_d: pos.omega_c,
            omega_d_dot: pos.omega_c_dot,
        },
    )
    .unwrap();
    assert_eq!(later.moment, att.moment);
    assert_eq!(rates3[..3], *att.e_i_rate.as_slice());
    // The single-rate law at s2 differs: the hold is not a no-op.
    let mut plain = paper_position_mode(circle);
    let now = plain.command(0.402, &s2, &reg, &mut [0.0; 6]).unwrap();
    assert!((now.moment - later.moment).norm() > 1e-6);
    assert!((now.thrust - later.thrust).abs() > 1e-6);

    // Entering again: the single-rate law until the next outer instant.
    let mut reg2 = reg;
    m.enter(0.5, &s2, &mut reg2);
    plain.enter(0.5, &s2, &mut reg2.clone());
    assert_eq!(
        m.command(0.5, &s2, &reg2, &mut [0.0; 6]).unwrap(),
        plain.command(0.5, &s2, &reg2, &mut [0.0; 6]).unwrap()
    );
}
