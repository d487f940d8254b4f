//! A tour of `lie`: the paper's flip attitude command evaluated in all four
//! (backend, scalar) pairs through one generic function, and the log at
//! angle π. Run with `cargo run -p geopid-lie --example tour`.

use lie::{Backend, Real, Rotation, So3Mat, So3Quat, V3};

/// The flip of the paper's numerical example, `R_d(t) = exp(π t e3^)
/// exp(4π t e2^)`, and what the attitude error functions say about it,
/// written once for any backend and representation.
fn flip_row<B: Backend, R: Rotation<B>>(t: f64) -> (f64, f64, f64) {
    let s = |x: f64| B::Scalar::lit(x);
    let e2: V3<B> = B::vec3(s(0.0), s(1.0), s(0.0));
    let e3: V3<B> = B::vec3(s(0.0), s(0.0), s(1.0));
    let pi = std::f64::consts::PI;
    let rd = R::exp(e3 * s(pi * t)) * R::exp(e2 * s(4.0 * pi * t));
    let psi = R::identity().psi(rd).to_f64_lossless();
    let er = B::vec3_to_array(R::identity().e_r(rd)).map(|x| x.to_f64_lossless());
    let angle = rd.angle().to_f64_lossless();
    (
        psi,
        (er[0] * er[0] + er[1] * er[1] + er[2] * er[2]).sqrt(),
        angle,
    )
}

fn table<R32, R64, B32: Backend, B64: Backend>(label: &str)
where
    R32: Rotation<B32>,
    R64: Rotation<B64>,
{
    println!("\n{label}: Ψ(I, R_d(t)), ‖e_R‖ and the angle of R_d(t) along the flip");
    println!(
        "{:>5}  {:>12} {:>12}  {:>10} {:>10}  {:>10}",
        "t [s]", "Ψ f32", "Ψ f64", "‖e_R‖ f64", "angle f64", "|ΔΨ|"
    );
    for k in 0..=8 {
        let t = 0.05 * k as f64;
        let (p32, _, _) = flip_row::<B32, R32>(t);
        let (p64, er, ang) = flip_row::<B64, R64>(t);
        println!(
            "{t:>5.2}  {p32:>12.7} {p64:>12.9}  {er:>10.6} {ang:>10.6}  {:>10.1e}",
            (p32 - p64).abs()
        );
    }
}

fn main() {
    table::<So3Mat<_>, So3Mat<_>, lie::GlamF32, lie::GlamF64>("glam, rotation matrices");
    table::<So3Quat<_>, So3Quat<_>, lie::NalgebraF32, lie::NalgebraF64>(
        "nalgebra, unit quaternions",
    );

    // Ψ = 2 exactly when R_d is a half turn from R (a critical point of Ψ,
    // Proposition 1 (iii)); the log there still has angle π.
    let half_turn =
        So3Mat::<lie::NalgebraF64>::exp(nalgebra::Vector3::new(0.0, std::f64::consts::PI, 0.0));
    let l = half_turn.log();
    println!(
        "\nhalf turn about e2: log = [{:.3e}, {:.15}, {:.3e}], Ψ(I, R) = {}, e_R = {:.1e}",
        l.x,
        l.y.abs(),
        l.z,
        So3Mat::identity().psi(half_turn),
        So3Mat::identity().e_r(half_turn).norm()
    );
    println!(
        "At t = 0.25 s the flip is half done (4π·0.25 = π about b2, heading π/4): Ψ = 2 there."
    );
}
