//! RotorPy's multirotor model term by term, against the model's equations
//! written out here on plain arrays (not through the crate's allocation,
//! its inverse or its helpers):
//!
//! ```text
//! thrust_i = −(k_η ω_i² + k_h (v_i,x² + v_i,y²)) e3,  v_i = v_a + Ω × r_i
//! H_i      = −ω_i diag(k_d, k_d, k_z) v_i
//! D        = −|v_a| diag(c_D) v_a
//! F_body   = Σ (thrust_i + H_i) + D
//! M_body   = Σ [ r_i × (thrust_i + H_i) − s_i k_m ω_i² e3 + k_flap ω_i (v_i × e3) ]
//! ```
//!
//! The RotorPy comparisons (`integrators/tests/rotorpy.rs`, the closed
//! loop in `scenarios`) check the model against RotorPy itself; these pin
//! each term where the vehicle is defined, so a broken term fails here.

use dynamics::{
    Actuators, Command, LoadInput, Multirotor, MultirotorParams, RigidBodyState, Vehicle, Wrench,
    loads,
};
use lie::{NalgebraF64, So3Mat};

type B = NalgebraF64;
type A3 = [f64; 3];

fn cross(a: A3, b: A3) -> A3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn arr(v: lie::V3<B>) -> A3 {
    [v[0], v[1], v[2]]
}

/// A small deterministic generator (xorshift), uniform in [−1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn v(&mut self, s: f64) -> A3 {
        [s * self.next(), s * self.next(), s * self.next()]
    }
}

/// The hummingbird with every aerodynamic term on (its own set has no
/// flapping), on RotorPy's X layout, on six rotors in a ring, or on five
/// rotors placed irregularly (so that `AAᵀ` is a full matrix, not the
/// diagonal one the symmetric layouts give, and the inverse is exercised).
fn params(rotors: usize) -> MultirotorParams<B> {
    let mut p = MultirotorParams::<B>::hummingbird();
    p.k_flap = 2.1e-5;
    if rotors == 5 {
        let at = [
            (0.1, 0.2),
            (1.3, 0.15),
            (2.2, 0.25),
            (3.9, 0.18),
            (5.0, 0.22),
        ];
        p.rotors = at
            .iter()
            .enumerate()
            .map(|(k, &(a, r)): (usize, &(f64, f64))| dynamics::Rotor {
                position: B::vec3(r * a.cos(), r * a.sin(), 0.01 * k as f64),
                direction: if k % 2 == 0 { 1.0 } else { -1.0 },
            })
            .collect();
    }
    if rotors == 6 {
        p.rotors = (0..6)
            .map(|k| {
                let a = k as f64 * std::f64::consts::PI / 3.0;
                dynamics::Rotor {
                    position: B::vec3(0.2 * a.cos(), 0.2 * a.sin(), -0.01),
                    direction: if k % 2 == 0 { 1.0 } else { -1.0 },
                }
            })
            .collect();
    }
    p
}

/// The model's body force and moment, from the equations above.
fn reference(p: &MultirotorParams<B>, speeds: &[f64], omega: A3, va: A3) -> (A3, A3) {
    let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
    let kd = [p.k_d, p.k_d, p.k_z];
    for (r, &w) in p.rotors.iter().zip(speeds) {
        let ri = arr(r.position);
        let oxr = cross(omega, ri);
        let vi = [va[0] + oxr[0], va[1] + oxr[1], va[2] + oxr[2]];
        let (lift, flap) = if p.aero {
            (p.k_h * (vi[0] * vi[0] + vi[1] * vi[1]), p.k_flap * w)
        } else {
            (0.0, 0.0)
        };
        let mut fi = [0.0, 0.0, -(p.k_eta * w * w + lift)];
        if p.aero {
            for k in 0..3 {
                fi[k] -= w * kd[k] * vi[k];
            }
        }
        let rxf = cross(ri, fi);
        let vxe3 = cross(vi, [0.0, 0.0, 1.0]);
        for k in 0..3 {
            f[k] += fi[k];
            m[k] += rxf[k] + flap * vxe3[k];
        }
        m[2] -= r.direction * p.k_m * w * w;
    }
    if p.aero {
        let n = (va[0] * va[0] + va[1] * va[1] + va[2] * va[2]).sqrt();
        let cd = arr(p.c_d);
        for k in 0..3 {
            f[k] -= n * cd[k] * va[k];
        }
    }
    (f, m)
}

fn rel(a: A3, b: A3) -> f64 {
    let d = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    d / (1.0 + b.iter().map(|x| x * x).sum::<f64>().sqrt())
}

/// Every term of the body wrench, aerodynamics on and off, four and six
/// rotors, at random speeds, rates and airspeeds.
#[test]
fn body_wrench_is_the_models_term_by_term() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut worst = 0.0f64;
    for (rotors, aero) in [(4, true), (4, false), (5, true), (6, true), (6, false)] {
        let mut p = params(rotors);
        p.aero = aero;
        let v = Multirotor::new(p.clone()).unwrap();
        for _ in 0..200 {
            let speeds: Vec<f64> = (0..rotors).map(|_| 700.0 + 500.0 * rng.next()).collect();
            let (omega, va) = (rng.v(4.0), rng.v(8.0));
            let (f, m) = v.body_wrench(
                &speeds,
                B::vec3(omega[0], omega[1], omega[2]),
                B::vec3(va[0], va[1], va[2]),
            );
            let (fr, mr) = reference(&p, &speeds, omega, va);
            let e = rel(arr(f), fr).max(rel(arr(m), mr));
            assert!(e.is_finite());
            worst = testkit::nan_max(worst, e);
        }
    }
    println!("body wrench vs the model's equations: worst relative {worst:.1e}");
    // Sums of a dozen products: rounding only (measured 4.4e-16).
    assert!(worst < 1e-14, "{worst:e}");
}

/// `loads_at`: gravity `m g e3` plus `R F_body` in the inertial frame, the
/// body moment as it is, the constant disturbance on top; the airspeed is
/// `Rᵀ(v − w)`.
#[test]
fn loads_add_gravity_the_rotated_body_force_and_the_disturbance() {
    let p = params(4);
    let d = dynamics::Disturbance::<B> {
        force: B::vec3(-0.5, 0.2, 1.0),
        moment: B::vec3(0.2, -0.1, -0.02),
    };
    let v = Multirotor::new(p.clone()).unwrap().with_disturbance(d);
    let r = So3Mat::<B>::exp(B::vec3(0.3, -0.4, 1.1));
    let state = RigidBodyState::<B> {
        r: r.as_matrix(),
        x: B::vec3(1.0, 2.0, -3.0),
        v: B::vec3(2.0, -1.0, 0.5),
        omega: B::vec3(0.4, -0.2, 0.9),
    };
    let wind = B::vec3(-3.0, 1.0, 0.2);
    let speeds = [800.0, 820.0, 790.0, 810.0];
    let l = v.loads_at(&state, &speeds, wind);
    let rm = r.as_matrix();
    let va = rm.transpose() * (state.v - wind);
    let (fb, mb) = reference(&p, &speeds, arr(state.omega), arr(va));
    let fi = rm * B::vec3(fb[0], fb[1], fb[2]);
    let force = [fi[0] - 0.5, fi[1] + 0.2, fi[2] + 1.0 + p.mass * p.gravity];
    let moment = [mb[0] + 0.2, mb[1] - 0.1, mb[2] - 0.02];
    let e = rel(arr(l.force), force).max(rel(arr(l.moment), moment));
    println!("loads vs gravity + R F_body + Δ: relative {e:.1e}");
    assert!(e < 1e-14, "{e:e}");
}

/// Without aerodynamics the actuators are rotor thrusts `k_η ω²`: the
/// allocation and its minimum-norm inverse round-trip (four, five and six
/// rotors), the speed for a thrust is `√(f/k_η)` clamped to the limits,
/// and the applied wrench at given speeds is the wrench of `k_η ω²`.
#[test]
fn thrusts_speeds_and_the_allocation_inverse() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for rotors in [4, 5, 6] {
        let mut p = params(rotors);
        p.aero = false;
        p.tau_m = 0.0;
        let v = Multirotor::new(p.clone()).unwrap();
        for _ in 0..100 {
            let w = Wrench::<B> {
                thrust: 5.0 + rng.next(),
                moment: B::vec3(0.05 * rng.next(), 0.05 * rng.next(), 0.01 * rng.next()),
            };
            let mut u = vec![0.0; rotors];
            v.actuators_from_wrench(&w, &mut u).unwrap();
            let back = v.wrench_from_actuators(&u).unwrap();
            assert!((back.thrust - w.thrust).abs() < 1e-13, "{rotors} rotors");
            assert!((back.moment - w.moment).norm() < 1e-13, "{rotors} rotors");
            assert!(u.iter().all(|x| *x > 0.0), "thrusts {u:?}");
            // The wrench of those thrusts, from positions and spin directions.
            let speeds: Vec<f64> = u.iter().map(|x| (x / p.k_eta).sqrt()).collect();
            let (f, m) = reference(&p, &speeds, [0.0; 3], [0.0; 3]);
            assert!((-f[2] - w.thrust).abs() < 1e-13 && rel(m, arr(w.moment)) < 1e-13);
            // The speed for a thrust is √(f/k_η) inside the limits.
            for (s, x) in speeds.iter().zip(&u) {
                let got = v.speed_for_thrust(*x);
                assert!((got - s).abs() <= 1e-13 * s, "{got} vs {s}");
            }
            // Without a lag the rotors run at the command's speeds, so the
            // applied wrench is the command.
            let applied = v.delivered(&w, &[]);
            assert!((applied.thrust - w.thrust).abs() < 1e-12);
            assert!((applied.moment - w.moment).norm() < 1e-12);
            let mut states = vec![0.0; rotors];
            v.initial_states(Command::RotorSpeeds(&speeds), &mut states);
            assert_eq!(states, speeds, "speeds inside the limits are kept");
        }
        // Outside the limits: clamped, as the motors are.
        assert_eq!(v.speed_for_thrust(-1.0), p.rotor_speed_min);
        assert_eq!(v.speed_for_thrust(1e6), p.rotor_speed_max);
        let wild: Vec<f64> = (0..rotors)
            .map(|k| if k % 2 == 0 { -50.0 } else { 1e5 })
            .collect();
        let mut states = vec![0.0; rotors];
        v.initial_states(Command::RotorSpeeds(&wild), &mut states);
        for (k, s) in states.iter().enumerate() {
            let want = if k % 2 == 0 {
                p.rotor_speed_min
            } else {
                p.rotor_speed_max
            };
            assert_eq!(*s, want, "rotor {k}");
        }
    }
}

/// With a motor lag the applied wrench is that of the rotors' current
/// speeds (the states), not of the command; the motor rates are
/// `(clamp(ω_cmd) − ω)/τ_m`.
#[test]
fn lagged_rotors_apply_their_own_speeds() {
    let mut p = params(4);
    p.aero = false;
    let v = Multirotor::new(p.clone()).unwrap();
    let states = [600.0, 650.0, 700.0, 750.0];
    let cmd = Wrench::<B> {
        thrust: 6.0,
        moment: B::vec3(0.1, 0.0, 0.0),
    };
    let w = v.delivered(&cmd, &states);
    let (f, m) = reference(&p, &states, [0.0; 3], [0.0; 3]);
    assert!((w.thrust + f[2]).abs() < 1e-13 && rel(arr(w.moment), m) < 1e-14);
    let speeds = [100.0, 2000.0, -5.0, 900.0];
    let mut rates = [0.0; 4];
    let st = RigidBodyState::<B>::at_rest();
    let input = LoadInput::new(
        Command::RotorSpeeds(&speeds),
        &states,
        B::vec3(0.0, 0.0, 0.0),
    );
    v.loads(0.0, &st, input, &mut rates).unwrap();
    for k in 0..4 {
        let c = speeds[k].clamp(p.rotor_speed_min, p.rotor_speed_max);
        let want = (c - states[k]) / p.tau_m;
        assert!(
            (rates[k] - want).abs() <= 1e-12 * want.abs(),
            "rotor {k}: {} vs {want}",
            rates[k]
        );
    }
}

/// RotorPy's quadrotor layout in this crate's frame, by value: its rotor 1
/// at `d(½√2, ½√2, 0)` z-up is `d(½√2, −½√2, 0)` here (y and z flip), the
/// others a quarter turn apart counter-clockwise seen from above in
/// RotorPy's frame, directions `+1, −1, +1, −1`.
#[test]
fn x_layout_is_rotorpys_in_this_frame() {
    let d = 0.17;
    let h = d * std::f64::consts::FRAC_1_SQRT_2;
    let want = [
        ([h, -h, 0.0], 1.0),
        ([h, h, 0.0], -1.0),
        ([-h, h, 0.0], 1.0),
        ([-h, -h, 0.0], -1.0),
    ];
    let got = MultirotorParams::<B>::x_layout(d);
    assert_eq!(got.len(), 4);
    for (k, (r, (pos, dir))) in got.iter().zip(want).enumerate() {
        assert_eq!(
            (arr(r.position), r.direction),
            (pos, dir),
            "rotor {}",
            k + 1
        );
    }
}

/// What the simulation asks of the vehicle: one actuator per rotor, one
/// state per rotor only under a motor lag, and without a lag (`τ_m = 0`)
/// the rotors follow the command at once, so a hover command balances
/// gravity in the total loads (four and six rotors).
#[test]
fn counts_and_the_lagless_loads_follow_the_rotors() {
    for rotors in [4, 6] {
        let mut p = params(rotors);
        p.aero = false;
        let lagged = Multirotor::new(p.clone()).unwrap();
        assert_eq!(lagged.actuator_count(), rotors);
        assert_eq!(lagged.state_count(), rotors);
        p.tau_m = 0.0;
        let v = Multirotor::new(p.clone()).unwrap();
        assert_eq!(v.state_count(), 0);
        let hover = Wrench::<B> {
            thrust: p.mass * p.gravity,
            moment: B::vec3(0.0, 0.0, 0.0),
        };
        let l = loads(&v, 0.0, &RigidBodyState::<B>::at_rest(), &hover);
        assert!(
            l.force.norm() < 1e-13 && l.moment.norm() < 1e-15,
            "{rotors} rotors: {l:?}"
        );
    }
}
