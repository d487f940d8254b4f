//! The README's gradient example: the paper-flip's final height and its
//! exact derivatives with respect to three gains, beside central
//! differences of plain runs for comparison.
//!
//! `cargo run -p geopid --example gradient`

use lie::{Dual, NalgebraF64};
use scenes::Error;
use scenes::{Registry, Scene, builtin};
use studies::sensitivity;

fn final_height(scene: &Scene) -> Result<f64, Error> {
    let mut sim = Registry::new().builder::<NalgebraF64>(scene)?.build()?;
    sim.advance_to(scene.duration)?;
    Ok(sim.state().body.x[2])
}

fn main() -> Result<(), Error> {
    let scene = builtin::paper_flip();
    let names = ["gains.k_x", "gains.k_v", "gains.k_i"];
    let g = sensitivity::gradient(&Registry::new(), &scene, names, scene.duration, |_, s| {
        s.body.x[2] * Dual::constant(1.0)
    })?;
    println!(
        "final height {:.6} m (plain run: {:.6} m)",
        g.value,
        final_height(&scene)?
    );
    for (name, d) in g.parameters.iter().zip(g.gradient) {
        let h = 1e-5;
        let mut up = scene.clone();
        let mut down = scene.clone();
        let (u, w) = match name.as_str() {
            "gains.k_x" => (&mut up.gains.k_x, &mut down.gains.k_x),
            "gains.k_v" => (&mut up.gains.k_v, &mut down.gains.k_v),
            _ => (&mut up.gains.k_i, &mut down.gains.k_i),
        };
        *u += h;
        *w -= h;
        let fd = (final_height(&up)? - final_height(&down)?) / (2.0 * h);
        println!("d/d {name:<10} {d:+.9e}   central difference {fd:+.9e}");
    }
    Ok(())
}
