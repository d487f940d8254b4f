//! A second vehicle through the same trait: the paper's attitude test stand
//! (Section VI), the quadrotor on a spherical joint 5 cm below its centre of
//! gravity — an inverted 3D pendulum that cannot translate.
//!
//! The geometric PID attitude controller tracks the paper's experiment
//! reference (3-2-1 Euler angles φ = (π/9) sin πt, θ = (π/9) cos πt, ψ = 0)
//! under Δ_R, once with the gravity-moment compensation term the paper adds
//! for the stand (M = M_PID − m g ρ × Rᵀe3) and once without. Integrated with
//! the LGVI; the stand's capabilities say it does not translate, so x and v are
//! never touched.
//!
//! Run: `cargo run -p geopid-dynamics --example attitude_stand`

use controllers::{AttitudeGains, AttitudeReference, RigidBodyParams, attitude_control};
use dynamics::{AttitudeStand, Quadrotor, RigidBodyState, Vehicle, Wrench, loads};
use integrators::{Integrator, Lgvi, Load, State, System};
use lie::{M3, NalgebraF64, Rotation, S, So3Mat, V3};

type B = NalgebraF64;

/// The closed loop on the stand: body state plus the attitude integral e_I.
struct StandLoop {
    stand: Box<dyn Vehicle<B>>,
    gravity_moment: Box<dyn Fn(M3<B>) -> V3<B>>,
    params: RigidBodyParams<B>,
    gains: AttitudeGains<B>,
    compensate: bool,
}

fn rx(a: f64) -> So3Mat<B> {
    So3Mat::exp(B::vec3(a, 0.0, 0.0))
}
fn ry(a: f64) -> So3Mat<B> {
    So3Mat::exp(B::vec3(0.0, a, 0.0))
}

/// R_d = R_y(θ) R_x(φ) with Ω_d = φ̇ e1 + θ̇ R_x(φ)ᵀe2 and its derivative.
fn reference(t: f64) -> AttitudeReference<B, So3Mat<B>> {
    use std::f64::consts::PI;
    let a = PI / 9.0;
    let (s, c) = (PI * t).sin_cos();
    let (phi, phid, phidd) = (a * s, a * PI * c, -a * PI * PI * s);
    let (th, thd, thdd) = (a * c, -a * PI * s, -a * PI * PI * c);
    let e1 = B::vec3(1.0, 0.0, 0.0);
    let e2r = rx(phi).inverse_act(B::vec3(0.0, 1.0, 0.0));
    AttitudeReference {
        rd: ry(th) * rx(phi),
        omega_d: e1 * phid + e2r * thd,
        omega_d_dot: e1 * phidd + e2r * thdd - e1.cross(&e2r) * (thd * phid),
    }
}

impl StandLoop {
    fn command(&self, t: f64, y: &State<B, 3>) -> (Wrench<B>, V3<B>, f64) {
        let e_i = B::vec3(y.extra[0], y.extra[1], y.extra[2]);
        let out = attitude_control(
            &self.params,
            &self.gains,
            So3Mat::from_matrix_unchecked(y.body.r),
            y.body.omega,
            e_i,
            &reference(t),
        )
        .expect("finite state");
        let mut moment = out.moment;
        if self.compensate {
            moment -= (self.gravity_moment)(y.body.r);
        }
        let w = Wrench {
            thrust: self.params.mass * self.params.gravity,
            moment,
        };
        (w, out.e_i_rate, out.psi)
    }
}

impl System<B, 3> for StandLoop {
    fn mass(&self) -> S<B> {
        self.stand.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.stand.inertia()
    }
    fn translates(&self) -> bool {
        self.stand.capabilities().translates
    }
    fn load(&mut self, t: f64, y: &State<B, 3>) -> Load<B, 3> {
        let (w, rate, _) = self.command(t, y);
        let l = loads(self.stand.as_ref(), t, &y.body, &w);
        Load {
            force: l.force,
            moment: l.moment,
            extra_rate: [rate[0], rate[1], rate[2]],
        }
    }
}

fn main() {
    let height = 0.05;
    let quad = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .expect("finite disturbance");
    let stand = AttitudeStand::new(quad, height).expect("valid height");
    let (m, g) = (stand.mass(), stand.gravity());

    println!("Attitude test stand: pivot {height} m below the centre of gravity, m = {m} kg");
    println!("Inertia about the pivot (parallel axes), diagonal: {:?}", {
        let j = stand.inertia();
        [j[(0, 0)], j[(1, 1)], j[(2, 2)]]
    });
    // Something to check by hand: the gravity moment at a 10° roll is
    // m g l sin 10° about b1, tipping the body further.
    let roll = 10f64.to_radians();
    let mg = stand.gravity_moment(rx(roll).matrix());
    println!(
        "Gravity moment at 10° roll: {:.6} N m about b1 (closed form m g l sin 10° = {:.6})",
        mg[0],
        m * g * height * roll.sin()
    );

    let s2 = stand;
    let run = |compensate: bool| {
        let mut sys = StandLoop {
            stand: Box::new(stand),
            gravity_moment: Box::new(move |r| s2.gravity_moment(r)),
            params: RigidBodyParams {
                mass: m,
                inertia: stand.inertia(),
                gravity: g,
            },
            gains: AttitudeGains::paper(),
            compensate,
        };
        let mut y = State::<B, 3>::new(RigidBodyState::at_rest());
        let mut lgvi = Lgvi::<B, 3>::default();
        let h = 1e-3;
        let mut rows = Vec::new();
        for k in 0..=10_000usize {
            let t = k as f64 * h;
            if k % 1000 == 0 {
                let (w, _, psi) = sys.command(t, &y);
                let mut rotors = [0.0; 4];
                stand
                    .actuators_from_wrench(&w, &mut rotors)
                    .expect("4 rotors");
                rows.push((t, psi, w.moment, rotors));
            }
            if k < 10_000 {
                lgvi.step(&mut sys, t, h, &mut y).expect("LGVI step");
            }
        }
        rows
    };
    let with = run(true);
    let without = run(false);
    println!(
        "\nTracking the paper's experiment reference under Δ_R (LGVI, h = 1 ms, paper gains):"
    );
    println!("   t [s]   Ψ compensated   Ψ uncompensated   rotor thrusts f1..f4 [N] (compensated)");
    for (a, b) in with.iter().zip(&without) {
        println!(
            "  {:5.1}   {:13.3e}   {:15.3e}   [{:.4}, {:.4}, {:.4}, {:.4}]",
            a.0, a.1, b.1, a.3[0], a.3[1], a.3[2], a.3[3]
        );
    }
    let sum: f64 = with.last().unwrap().3.iter().sum();
    println!(
        "\nCheck: the rotor thrusts sum to the commanded thrust m g = {:.4} N: {:.4} N",
        m * g,
        sum
    );
    let worst = |rows: &[(f64, f64, V3<B>, [f64; 4])]| {
        rows.iter()
            .filter(|r| r.0 >= 5.0)
            .map(|r| r.1)
            .fold(0.0, f64::max)
    };
    println!(
        "Largest Ψ over 5–10 s: {:.2e} compensated, {:.2e} uncompensated",
        worst(&with),
        worst(&without)
    );
}
