//! What the steppers report and refuse, pinned: their names, invalid step
//! sizes, Dormand–Prince's evaluation count (seven stages, first same as
//! last) and its substep cap through `Integrator::limit_substeps`, the
//! LGVI's load evaluations and the discrete equations its step solves.

use dynamics::RigidBodyState;
use integrators::{
    Dopri, EndLoad, Integrator, Lgvi, Load, State, StepError, Stepper, StepperConfig, System,
};
use lie::{NalgebraF64, V3, ops};

type B = NalgebraF64;

const NAMES: [&str; 6] = ["lgvi", "rk4", "rk4-projected", "rkmk4", "euler", "dopri"];

/// A body with dampers and a constant push: `M = m0 − c Ω` and
/// `F = f0 − d v` read the rates (so the LGVI iterates its end point)
/// unless `rates` is false, when the loads are the constant parts only.
struct Damped {
    c: f64,
    d: f64,
    rates: bool,
}

impl System<B, 1> for Damped {
    fn mass(&self) -> f64 {
        1.0
    }
    fn inertia(&self) -> lie::M3<B> {
        ops::diag::<B>(1.0, 2.0, 3.0)
    }
    fn load_depends_on_rates(&self) -> bool {
        self.rates
    }
    fn load(&mut self, _t: f64, y: &State<B, 1>) -> Load<B, 1> {
        let (m0, f0): (V3<B>, V3<B>) = (B::vec3(0.3, -0.2, 0.1), B::vec3(0.0, 0.0, 1.0));
        let (c, d) = if self.rates {
            (self.c, self.d)
        } else {
            (0.0, 0.0)
        };
        Load {
            force: f0 - y.body.v * d,
            moment: m0 - y.body.omega * c,
            extra_rate: [-0.3],
        }
    }
}

fn start() -> State<B, 1> {
    let mut body = RigidBodyState::<B>::at_rest();
    body.omega = B::vec3(1.5, -2.0, 1.0);
    body.v = B::vec3(-1.0, 2.5, 0.5);
    State { body, extra: [0.7] }
}

#[test]
fn every_stepper_answers_to_its_name() {
    for name in NAMES {
        let s = Stepper::<B, 1>::from_name(name, StepperConfig::default()).unwrap();
        assert_eq!(Integrator::<B, 1>::name(&s), name);
    }
    assert_eq!(Integrator::<B, 1>::name(&Lgvi::<B, 1>::default()), "lgvi");
    assert_eq!(Integrator::<B, 1>::name(&Dopri::<B>::new(1e-9)), "dopri");
}

/// A step of zero, negative, infinite or NaN size is refused by every
/// stepper with the size in the error, and the state is left alone.
#[test]
fn invalid_step_sizes_are_refused_by_value() {
    for name in NAMES {
        for h in [0.0, -1e-3, f64::INFINITY, f64::NAN] {
            let mut s = Stepper::<B, 1>::from_name(name, StepperConfig::default()).unwrap();
            let mut y = start();
            let err = s
                .step(
                    &mut Damped {
                        c: 0.5,
                        d: 0.4,
                        rates: true,
                    },
                    0.0,
                    h,
                    &mut y,
                )
                .expect_err("an invalid step");
            match err {
                StepError::InvalidStep { h: got } => {
                    assert!(got == h || (got.is_nan() && h.is_nan()), "{name}: {got}")
                }
                other => panic!("{name} at h = {h}: {other:?}"),
            }
            assert_eq!(y, start(), "{name}: the state moved");
        }
    }
}

/// Dormand–Prince with first same as last: one evaluation for the call's
/// first stage, then six per trial substep, accepted or rejected.
#[test]
fn dopri_evaluates_six_stages_per_trial_and_one_to_start() {
    // Capped at ten times what it takes, so a broken step control fails
    // here at once instead of running on.
    let mut d = Dopri::<B>::new(1e-10).max_substeps(1000);
    let mut y = start();
    let stats = d
        .step(
            &mut Damped {
                c: 0.5,
                d: 0.4,
                rates: true,
            },
            0.0,
            2.0,
            &mut y,
        )
        .unwrap();
    assert!(stats.substeps > 5, "{stats:?}");
    assert_eq!(
        stats.evaluations,
        1 + 6 * (stats.substeps + stats.rejected),
        "{stats:?}"
    );
    println!("dopri tol 1e-10 over 2 s: {stats:?}");
    // The step control's efficiency, pinned: measured 96 accepted and 3
    // rejected substeps. A 5th-order method's count goes as tol^(−1/5), so
    // ±20 % is a factor 2.5 in the error it keeps; a controller with a
    // wrong safety factor, exponent or clamp lands outside.
    assert!(
        (80..=115).contains(&stats.substeps) && stats.rejected <= 10,
        "{stats:?}"
    );
    // The cap through the trait (what a simulation's guard sets).
    let mut capped = Dopri::<B>::new(1e-10);
    Integrator::<B, 1>::limit_substeps(&mut capped, 3);
    let mut y = start();
    let err = capped
        .step(
            &mut Damped {
                c: 0.5,
                d: 0.4,
                rates: true,
            },
            0.0,
            2.0,
            &mut y,
        )
        .expect_err("more than 3 substeps needed");
    assert!(
        matches!(err, StepError::TooManySubsteps { substeps: 3, .. }),
        "{err:?}"
    );
    assert_eq!(y, start());
}

/// A load that does not read the rates is evaluated once at each end of
/// a step, and the start load of the next step is the end load of this
/// one (same time, same state), so a run costs one evaluation per step.
#[test]
fn lgvi_evaluates_a_configuration_load_once_per_end() {
    let mut s = Lgvi::<B, 1>::default();
    let mut sys = Damped {
        c: 0.0,
        d: 0.0,
        rates: false,
    };
    let mut y = start();
    let first = s.step(&mut sys, 0.0, 0.01, &mut y).unwrap();
    assert_eq!(first.evaluations, 2);
    let second = s.step(&mut sys, 0.01, 0.01, &mut y).unwrap();
    assert_eq!(second.evaluations, 1);
}

/// Iterated to rounding, the LGVI step satisfies its implicit end-point
/// equations: with `F = R_kᵀR_{k+1}` and `p = JΩ_k + h/2 M_k`,
/// `JΩ_{k+1} = Fᵀp + h/2 M(t + h, y_{k+1})`, and `v` by the trapezoidal
/// rule, each to a few ε of its size. One damper at a time (rotation, then
/// translation), so that each relative change alone decides when the
/// iteration stops; |Ω|, |v| > 1, so a change formed with the wrong sign
/// stops it after one pass and shows (as 5e-6).
#[test]
fn lgvi_step_satisfies_its_discrete_equations() {
    let mut worst = 0.0f64;
    for (c, d) in [(0.8, 0.0), (0.0, 0.8)] {
        let mut s = Lgvi::<B, 1>::default();
        s.end_load = EndLoad::IterateToRounding { max: 50 };
        let mut sys = Damped { c, d, rates: true };
        let (t, h) = (0.0, 0.05);
        let y0 = start();
        let mut y1 = y0;
        s.step(&mut sys, t, h, &mut y1).unwrap();
        let (l0, l1) = (sys.load(t, &y0), sys.load(t + h, &y1));
        let j = sys.inertia();
        let p = j * y0.body.omega + l0.moment * (0.5 * h);
        let f = y0.body.r.transpose() * y1.body.r;
        let rhs = f.transpose() * p + l1.moment * (0.5 * h);
        let e_omega = (j * y1.body.omega - rhs).norm() / (1.0 + rhs.norm());
        let v = y0.body.v + (l0.force + l1.force) * (0.5 * h);
        let e_v = (y1.body.v - v).norm() / (1.0 + v.norm());
        println!("LGVI discrete equations (c = {c}, d = {d}): Ω {e_omega:.1e}, v {e_v:.1e}");
        worst = [e_omega, e_v].into_iter().fold(worst, testkit::nan_max);
    }
    // Measured ≤ 8e-17 (Ω) and 3e-17 (v); bound ~100×.
    assert!(worst < 1e-14, "{worst:e}");
}

/// The one-step methods report one substep and their stage count per
/// call (Euler 1, RK4 and RKMK4 4), with or without projection.
#[test]
fn fixed_steppers_report_their_stages() {
    for (name, stages) in [("euler", 1), ("rk4", 4), ("rk4-projected", 4), ("rkmk4", 4)] {
        let mut s = Stepper::<B, 1>::from_name(name, StepperConfig::default()).unwrap();
        let mut y = start();
        let stats = s
            .step(
                &mut Damped {
                    c: 0.5,
                    d: 0.4,
                    rates: true,
                },
                0.0,
                0.01,
                &mut y,
            )
            .unwrap();
        assert_eq!(
            (stats.substeps, stats.evaluations, stats.rejected),
            (1, stages, 0),
            "{name}"
        );
    }
}

/// After `reset` (a simulation calls it when the dynamics change at an
/// instant without the state changing: a mode switch), the LGVI must not
/// reuse the start load it kept from the last step, also when it is
/// driven through `Stepper`.
#[test]
fn reset_drops_the_lgvis_kept_load() {
    struct Push(f64);
    impl System<B, 1> for Push {
        fn mass(&self) -> f64 {
            1.0
        }
        fn inertia(&self) -> lie::M3<B> {
            ops::diag::<B>(1.0, 2.0, 3.0)
        }
        fn load_depends_on_rates(&self) -> bool {
            false
        }
        fn load(&mut self, _t: f64, _y: &State<B, 1>) -> Load<B, 1> {
            Load {
                force: B::vec3(0.0, 0.0, 0.0),
                moment: B::vec3(self.0, 0.0, 0.0),
                extra_rate: [0.0],
            }
        }
    }
    let mut s = Stepper::<B, 1>::from_name("lgvi", StepperConfig::default()).unwrap();
    let mut y = start();
    s.step(&mut Push(0.1), 0.0, 0.01, &mut y).unwrap();
    let y1 = y;
    s.reset();
    s.step(&mut Push(-2.0), 0.01, 0.01, &mut y).unwrap();
    let mut fresh = Lgvi::<B, 1>::default();
    let mut want = y1;
    fresh.step(&mut Push(-2.0), 0.01, 0.01, &mut want).unwrap();
    assert_eq!(
        y, want,
        "the new load must be used from the start of the step"
    );
}

/// Only the adaptive method hands out a copy to sample inside its long
/// calls; the one-step methods are sampled by the cubic extension.
#[test]
fn only_dopri_has_a_resampler() {
    for name in NAMES {
        let s = Stepper::<B, 1>::from_name(name, StepperConfig::default()).unwrap();
        assert_eq!(s.resampler().is_some(), name == "dopri", "{name}");
    }
}

/// A solution that blows up in finite time: `Ω̇₁ = c Ω₁²` about a
/// principal axis (`M = c Ω₁² J e1`, no gyroscopic term on an axis)
/// reaches infinity at `t* = 1/(c Ω₀)`. Dormand–Prince must stop there with
/// `StepTooSmall`, at a step of at most `16 ε (|t| + h)` (its documented
/// floor) and, shrinking by at most 5× per rejection, not far below it.
#[test]
fn dopri_stops_at_a_blow_up_with_its_step_floor() {
    struct Blow;
    impl System<B, 1> for Blow {
        fn mass(&self) -> f64 {
            1.0
        }
        fn inertia(&self) -> lie::M3<B> {
            ops::diag::<B>(1.0, 2.0, 3.0)
        }
        fn load(&mut self, _t: f64, y: &State<B, 1>) -> Load<B, 1> {
            let w = y.body.omega[0];
            Load {
                force: B::vec3(0.0, 0.0, 0.0),
                moment: B::vec3(4.0 * w * w, 0.0, 0.0),
                extra_rate: [0.0],
            }
        }
    }
    let mut y = State::<B, 1>::new(RigidBodyState::<B>::at_rest());
    y.body.omega = B::vec3(1.0, 0.0, 0.0);
    // t* = 1/(4·1) = 0.25 inside a call of 0.5 s.
    let h_call = 0.5;
    // Capped (it takes ~200 substeps), so a broken step control fails here
    // instead of creeping towards the blow-up for ever.
    let err = Dopri::<B>::new(1e-10)
        .max_substeps(100_000)
        .step(&mut Blow, 0.0, h_call, &mut y)
        .expect_err("the solution blows up at t = 0.25");
    match err {
        StepError::StepTooSmall { t, h } => {
            let floor = 16.0 * f64::EPSILON * (t.abs() + h_call);
            println!("blow-up: stopped at t = {t}, h = {h:e} (floor {floor:e})");
            assert!((t - 0.25).abs() < 1e-6, "t = {t}");
            assert!(h <= floor && h > 0.2 * floor, "h = {h:e}, floor {floor:e}");
        }
        other => panic!("{other:?}"),
    }
}
