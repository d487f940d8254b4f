//! The whole closed loop on the dual scalar: the real part of a dual run is
//! the `f64` run bit for bit, on every stepper (the paper-flip crosses the
//! integral's saturation and switches modes, so events and switches are
//! located on the real part alone).

use lie::{NalgebraDual, NalgebraF64};
use scenarios::{Registry, builtin};

#[test]
fn paper_flip_real_part_is_the_f64_run_on_every_stepper() {
    let reg = Registry::new();
    for kind in ["lgvi", "rk4", "rk4-projected", "rkmk4", "euler", "dopri"] {
        let mut scene = builtin::paper_flip();
        scene.integrator.kind = kind.into();
        let mut a = reg
            .builder::<NalgebraF64, 6>(&scene)
            .unwrap()
            .build()
            .unwrap();
        let mut b = reg
            .builder::<NalgebraDual<1>, 6>(&scene)
            .unwrap()
            .build()
            .unwrap();
        a.advance_to(scene.duration).unwrap();
        b.advance_to(scene.duration).unwrap();
        let (sa, sb) = (a.state(), b.state());
        assert_eq!(sa.segment, sb.segment, "{kind}: segment");
        let fa = [sa.body.x, sa.body.v, sa.body.omega];
        let fb = [sb.body.x, sb.body.v, sb.body.omega];
        for (u, w) in fa.iter().zip(&fb) {
            for k in 0..3 {
                assert_eq!(u[k].to_bits(), w[k].re.to_bits(), "{kind}: {u} vs {w}");
            }
        }
        for (u, w) in sa.integrals.iter().zip(sb.integrals) {
            assert_eq!(u.to_bits(), w.re.to_bits(), "{kind}: integrals");
        }
        println!(
            "{kind}: real part identical to the f64 run at t = {} (segment {})",
            b.time(),
            sb.segment
        );
    }
}
