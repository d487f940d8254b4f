//! One step of every stepper on the dual scalar: the real part is the
//! `f64` step bit for bit, and the derivatives of the end state with
//! respect to the initial attitude (as `R₀ Exp(δ)`), the initial rate and
//! the heavy top's parameters equal central differences of `f64` steps.
//! Dormand–Prince runs at a tolerance that accepts the whole step as one
//! substep, so every difference replays the same step sequence (its step
//! size control reads values only; see the stepper).

use integrators::problems::Top;
use integrators::{Integrator, IntegratorKind, State, Stepper, StepperConfig};
use lie::{Backend, Dual, NalgebraDual, NalgebraF64, Real, RigidState, S, So3Mat, ops};

const K: usize = 12;

/// `[δ (3), ω₀ (3), m g ρ (3), diag J (3)]`.
const P0: [f64; K] = [0.0, 0.0, 0.0, 0.4, -0.3, 1.1, 0.0, 0.5, 1.0, 1.0, 2.0, 3.0];

/// The end state of one step, flattened: `R` (row by row), then `Ω`.
fn one_step<B: Backend>(kind: IntegratorKind, p: [S<B>; K]) -> Vec<S<B>> {
    let l = S::<B>::lit;
    let r0 = So3Mat::<B>::exp(B::vec3(l(0.3), l(-0.5), l(0.8))).as_matrix();
    let r = r0 * So3Mat::<B>::exp(B::vec3(p[0], p[1], p[2])).as_matrix();
    let mut body = RigidState::<B, lie::M3<B>>::at_rest();
    body.r = r;
    body.omega = B::vec3(p[3], p[4], p[5]);
    let mut y = State::<B, 0>::new(body);
    let mut top = Top::<B>::heavy(
        ops::diag::<B>(p[9], p[10], p[11]),
        B::vec3(p[6], p[7], p[8]),
    );
    let mut stepper = Stepper::<B, 0>::new(kind, StepperConfig { tol: 1.0 });
    stepper.step(&mut top, l(0.0), l(0.05), &mut y).unwrap();
    let e = ops::elems::<B>(y.body.r);
    let mut out: Vec<S<B>> = e.iter().flatten().copied().collect();
    out.extend(B::vec3_to_array(y.body.omega));
    out
}

#[test]
fn one_step_of_every_stepper_equals_central_differences() {
    for kind in IntegratorKind::ALL {
        let dual =
            one_step::<NalgebraDual<K>>(kind, core::array::from_fn(|i| Dual::variable(P0[i], i)));
        let plain = one_step::<NalgebraF64>(kind, P0);
        for (d, p) in dual.iter().zip(&plain) {
            assert_eq!(d.re.to_bits(), p.to_bits(), "{}: real part", kind.name());
        }
        let mut best = (f64::INFINITY, 0.0);
        for h in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let mut worst = 0.0f64;
            for i in 0..K {
                let at = |s: f64| {
                    let mut p = P0;
                    p[i] += s * h;
                    one_step::<NalgebraF64>(kind, p)
                };
                let (up, down) = (at(1.0), at(-1.0));
                for k in 0..plain.len() {
                    let scale = dual[k].eps.iter().fold(1e-12f64, |m, e| m.max(e.abs()));
                    let fd = (up[k] - down[k]) / (2.0 * h);
                    worst = worst.max((dual[k].eps[i] - fd).abs() / scale);
                }
            }
            if worst < best.0 {
                best = (worst, h);
            }
        }
        println!(
            "{}: one step vs central differences {:.1e} (best step {:.0e})",
            kind.name(),
            best.0,
            best.1
        );
        // Central differences reach ~1e-10 here (truncation h², rounding
        // ε/h); 1e-6 is the bound a gradient must meet, and a missing term
        // of any derivative is O(1).
        assert!(best.0 < 1e-6, "{}: {:e}", kind.name(), best.0);
    }
}
