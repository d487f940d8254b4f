//! The gain conditions of Propositions 2 and 3 — (eqn:c2), (eqn:kisigma),
//! (eqn:c1b), (eqn:kRkWb) with `W1`, `W12`, `W2` — evaluated with their
//! margins, plus the slowest time constant of the linearised closed loops.
//!
//! The checker works in `f64` whatever the controller's scalar: it is an
//! offline design tool. Diagonal gains are checked axis by axis (each
//! condition with that axis's gains) and the worst axis is reported.
//!
//! # The paper's gains
//!
//! With `B1 = 8 N` (hover needs `m g = 7.41 N`), `B2 = 0.1`
//! (`‖2J − tr(J) I‖ = 0.0102` times `‖Ω_d‖ ≈ 10 rad/s`), `δ_x = 1 N`,
//! `ψ1 = 0.05`, `e_xmax = 1 m`, the checker reports (test
//! `controllers/tests/gain_report.rs`, values confirmed with numpy):
//!
//! ```text
//! condition      statement                                 value        bound       margin  holds
//! (eqn:c2)       c2 < min{√(k_R λm)/λM, 4k_Ω/(…)}        0.80000      4.52954      3.72954  yes
//! (eqn:kisigma)  k_i σ > δ_x                             1.28000      1.00000      0.28000  yes
//! (eqn:c1b)      c1 < min{4k_xk_v(1−α)²/(…), √(k_x/m)}      3.60000      1.78507     -1.81493  NO
//! (eqn:kRkWb)    λm(W2) > ‖W12‖²/(4 λm(W1))              0.07773          inf         -inf  NO
//! α = √(ψ1(2−ψ1)) = 0.31225
//! slowest time constant, linearised attitude loop: 14.636 s
//! slowest time constant, linearised position loop: 2.744 s
//! ```
//!
//! So the paper's numerical example meets the attitude conditions but not
//! (eqn:c1b): `c1 = 3.6` is above its bound, which also leaves `W1`
//! indefinite (`λm(W1) = −2.70`) so (eqn:kRkWb) cannot hold. The conditions
//! are sufficient, not necessary: the closed loop still converges in
//! simulation (`closed_loop` tests). The slow attitude time constant is the
//! integral mode, root `≈ −k_I c2/(k_R + k_I)`.

use crate::{AttitudeGains, PositionGains, RigidBodyParams};
#[allow(unused_imports)] // needed for f64 maths without std (libm through num-traits)
use lie::{Backend, Real};

/// The bounds the conditions are stated with.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GainBounds {
    /// `B1 > ‖−m g e3 + m ẍ_d‖` (eqn:B).
    pub b1: f64,
    /// `B2 ≥ ‖2J − tr(J) I‖ ‖Ω_d‖` (eqn:B_2).
    pub b2: f64,
    /// `δ_x ≥ ‖Δ_x‖_∞`.
    pub delta_x: f64,
    /// `ψ1 < 1`, the bound on the initial attitude error (eqn:Psi0).
    pub psi1: f64,
    /// `e_xmax`, the bound on the initial position error (eqn:ex0).
    pub e_x_max: f64,
}

/// One evaluated condition.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GainCondition {
    /// The paper's equation label.
    pub label: &'static str,
    /// The inequality, in words.
    pub statement: &'static str,
    /// Left-hand side.
    pub value: f64,
    /// Right-hand side.
    pub bound: f64,
    /// Whether it holds.
    pub holds: bool,
    /// By how much it holds (negative: by how much it fails), in the units
    /// of `value`.
    pub margin: f64,
}

/// The checker's result.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GainReport {
    /// (eqn:c2), (eqn:kisigma), (eqn:c1b), (eqn:kRkWb), worst axis each.
    pub conditions: [GainCondition; 4],
    /// `α = √(ψ1(2 − ψ1))`.
    pub alpha: f64,
    /// Slowest time constant (s) of the linearised attitude loop
    /// `J s³ + k_Ω s² + (k_R + k_I) s + k_I c2` over the three axes.
    pub attitude_time_constant: f64,
    /// Slowest time constant (s) of the linearised position loop
    /// `m s³ + k_v s² + (k_x + k_i) s + k_i c1`, unsaturated.
    pub position_time_constant: f64,
    /// `λm(W1)` on the worst axis: (eqn:kRkWb) can only hold when it is
    /// positive (its bound is `∞` otherwise).
    pub lambda_min_w1: f64,
}

impl GainReport {
    /// Whether every condition holds.
    pub fn all_hold(&self) -> bool {
        self.conditions.iter().all(|c| c.holds)
    }

    /// Each condition as `ln(value/bound)` oriented so that positive means
    /// it holds (a log ratio does not flatten out far from the bound, as a
    /// relative margin does): what a gain search maximises the worst of.
    /// (eqn:kRkWb) with `λm(W1) ≤ 0` or `λm(W2) ≤ 0` scores below −10,
    /// increasing towards positive eigenvalues, so a search makes them
    /// positive first.
    pub fn log_margins(&self) -> [f64; 4] {
        let [c2, kis, c1, w] = self.conditions;
        let ln_ratio = |big: f64, small: f64| {
            if big > 0.0 && small > 0.0 {
                (big / small).ln()
            } else {
                -10.0 - (big - small).abs().min(1e6).ln_1p()
            }
        };
        let wscore = if self.lambda_min_w1 > 0.0 && w.value > 0.0 && w.bound.is_finite() {
            (w.value / w.bound).ln()
        } else {
            -10.0 - self.lambda_min_w1.min(0.0).abs().ln_1p() - w.value.min(0.0).abs().ln_1p()
        };
        [
            ln_ratio(c2.bound, c2.value),
            ln_ratio(kis.value, kis.bound.max(1e-9)),
            ln_ratio(c1.bound, c1.value),
            wscore,
        ]
    }

    /// The worst of [`GainReport::log_margins`] and its condition's index.
    pub fn worst_log_margin(&self) -> (f64, usize) {
        self.log_margins()
            .iter()
            .enumerate()
            .fold(
                (f64::INFINITY, 0),
                |(v, k), (i, &x)| if x < v { (x, i) } else { (v, k) },
            )
    }
}

impl core::fmt::Display for GainReport {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        writeln!(
            f,
            "{:<14} {:<34} {:>12} {:>12} {:>12}  holds",
            "condition", "statement", "value", "bound", "margin"
        )?;
        for c in &self.conditions {
            writeln!(
                f,
                "{:<14} {:<34} {:>12.5} {:>12.5} {:>12.5}  {}",
                c.label,
                c.statement,
                c.value,
                c.bound,
                c.margin,
                if c.holds { "yes" } else { "NO" }
            )?;
        }
        writeln!(f, "α = √(ψ1(2−ψ1)) = {:.5}", self.alpha)?;
        writeln!(
            f,
            "slowest time constant, linearised attitude loop: {:.3} s",
            self.attitude_time_constant
        )?;
        write!(
            f,
            "slowest time constant, linearised position loop: {:.3} s",
            self.position_time_constant
        )
    }
}

/// Eigenvalues of a symmetric 3×3 matrix, ascending (trigonometric method).
fn sym3_eigen(a: [[f64; 3]; 3]) -> [f64; 3] {
    let p1 = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    if p1 == 0.0 {
        let mut d = [a[0][0], a[1][1], a[2][2]];
        d.sort_unstable_by(|x, y| x.total_cmp(y));
        return d;
    }
    let p2 = (a[0][0] - q).powi(2) + (a[1][1] - q).powi(2) + (a[2][2] - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    let mut b = a;
    for (i, row) in b.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (a[i][j] - if i == j { q } else { 0.0 }) / p;
        }
    }
    let det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
        - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
        + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    let big = q + 2.0 * p * phi.cos();
    let small = q + 2.0 * p * (phi + 2.0 * core::f64::consts::PI / 3.0).cos();
    [small, 3.0 * q - big - small, big]
}

/// Smallest eigenvalue of a symmetric 2×2 matrix.
fn sym2_min_eig(a: [[f64; 2]; 2]) -> f64 {
    let (m, d) = (
        (a[0][0] + a[1][1]) / 2.0,
        ((a[0][0] - a[1][1]) / 2.0).hypot(a[0][1]),
    );
    m - d
}

/// Spectral norm of a 2×2 matrix.
fn norm2x2(a: [[f64; 2]; 2]) -> f64 {
    // largest eigenvalue of AᵀA
    let ata = [
        [
            a[0][0] * a[0][0] + a[1][0] * a[1][0],
            a[0][0] * a[0][1] + a[1][0] * a[1][1],
        ],
        [
            a[0][0] * a[0][1] + a[1][0] * a[1][1],
            a[0][1] * a[0][1] + a[1][1] * a[1][1],
        ],
    ];
    let (m, d) = (
        (ata[0][0] + ata[1][1]) / 2.0,
        ((ata[0][0] - ata[1][1]) / 2.0).hypot(ata[0][1]),
    );
    (m + d).sqrt()
}

/// Slowest time constant `1/min |Re s|` of `a s³ + b s² + c s + d` (all
/// roots assumed in the left half-plane; `∞` if a root is not).
fn slowest_time_constant(a: f64, b: f64, c: f64, d: f64) -> f64 {
    // Real root by bisection on [−R, 0], R a Cauchy bound.
    let (b, c, d) = (b / a, c / a, d / a);
    let p = |s: f64| ((s + b) * s + c) * s + d;
    let r = 1.0 + b.abs().max(c.abs()).max(d.abs());
    let (mut lo, mut hi) = (-r, 0.0);
    if p(hi) <= 0.0 {
        return f64::INFINITY; // a root at or right of 0
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if p(mid) > 0.0 { hi = mid } else { lo = mid }
    }
    let s1 = 0.5 * (lo + hi);
    // Deflate: s² + (b + s1) s + (c + s1 (b + s1)).
    let (qb, qc) = (b + s1, c + s1 * (b + s1));
    let disc = qb * qb - 4.0 * qc;
    let slow_pair = if disc >= 0.0 {
        let sq = disc.sqrt();
        let r1 = (-qb + sq) / 2.0;
        let r2 = (-qb - sq) / 2.0;
        r1.max(r2)
    } else {
        -qb / 2.0
    };
    let slowest = s1.max(slow_pair);
    if slowest >= 0.0 {
        f64::INFINITY
    } else {
        -1.0 / slowest
    }
}

/// Evaluates the conditions of Propositions 2 and 3 for the given vehicle,
/// gains and bounds.
pub fn check_gains<B: Backend>(
    params: &RigidBodyParams<B>,
    pos: &PositionGains<B>,
    att: &AttitudeGains<B>,
    bounds: &GainBounds,
) -> GainReport {
    let f = |x: lie::S<B>| x.to_f64_lossless();
    let arr = |v: lie::V3<B>| B::vec3_to_array(v).map(f);
    let cols = B::mat3_cols(params.inertia).map(arr);
    let j = [0, 1, 2].map(|i| [0, 1, 2].map(|k| 0.5 * (cols[k][i] + cols[i][k])));
    let eig = sym3_eigen(j);
    let (lam_m, lam_big) = (eig[0], eig[2]);
    let m = f(params.mass);
    let (k_r, k_w, k_ia) = (arr(att.k_r), arr(att.k_omega), arr(att.k_i));
    let (k_x, k_v, k_ip) = (arr(pos.k_x), arr(pos.k_v), arr(pos.k_i));
    let (c1, c2, sigma) = (f(pos.c1), f(att.c2), f(pos.sigma));
    let alpha = (bounds.psi1 * (2.0 - bounds.psi1)).sqrt();

    let worst = |conds: [GainCondition; 3]| {
        conds
            .into_iter()
            .fold(conds[0], |w, c| if c.margin < w.margin { c } else { w })
    };
    let c2_cond = worst([0, 1, 2].map(|i| {
        let bound = ((k_r[i] * lam_m).sqrt() / lam_big)
            .min(4.0 * k_w[i] / (8.0 * k_r[i] * lam_big + (k_w[i] + bounds.b2).powi(2)));
        GainCondition {
            label: "(eqn:c2)",
            statement: "c2 < min{√(k_R λm)/λM, 4k_Ω/(…)}",
            value: c2,
            bound,
            holds: c2 < bound,
            margin: bound - c2,
        }
    }));
    let kis_cond = worst([0, 1, 2].map(|i| {
        let v = k_ip[i] * sigma;
        GainCondition {
            label: "(eqn:kisigma)",
            statement: "k_i σ > δ_x",
            value: v,
            bound: bounds.delta_x,
            holds: v > bounds.delta_x,
            margin: v - bounds.delta_x,
        }
    }));
    let c1_cond = worst([0, 1, 2].map(|i| {
        let bound = (4.0 * k_x[i] * k_v[i] * (1.0 - alpha).powi(2)
            / (k_v[i].powi(2) * (1.0 + alpha).powi(2) + 4.0 * m * k_x[i] * (1.0 - alpha)))
            .min((k_x[i] / m).sqrt());
        GainCondition {
            label: "(eqn:c1b)",
            statement: "c1 < min{4k_xk_v(1−α)²/(…), √(k_x/m)}",
            value: c1,
            bound,
            holds: c1 < bound,
            margin: bound - c1,
        }
    }));
    let mut lambda_min_w1 = f64::INFINITY;
    let w_cond = worst([0, 1, 2].map(|i| {
        let off1 = -0.5 * c1 * k_v[i] * (1.0 + alpha);
        let w1 = [
            [c1 * k_x[i] * (1.0 - alpha), off1],
            [off1, k_v[i] * (1.0 - alpha) - m * c1],
        ];
        let w12 = [
            [c1 * (3f64.sqrt() * k_ip[i] * sigma + bounds.b1), 0.0],
            [k_ip[i] * sigma + bounds.b1 + k_x[i] * bounds.e_x_max, 0.0],
        ];
        let off2 = -0.5 * c2 * (k_w[i] + bounds.b2);
        let w2 = [[c2 * k_r[i], off2], [off2, k_w[i] - 2.0 * c2 * lam_big]];
        let l1 = sym2_min_eig(w1);
        lambda_min_w1 = lambda_min_w1.min(l1);
        let value = sym2_min_eig(w2);
        let bound = if l1 > 0.0 {
            norm2x2(w12).powi(2) / (4.0 * l1)
        } else {
            f64::INFINITY
        };
        GainCondition {
            label: "(eqn:kRkWb)",
            statement: "λm(W2) > ‖W12‖²/(4 λm(W1))",
            value,
            bound,
            holds: value > bound,
            margin: value - bound,
        }
    }));

    let jd = [j[0][0], j[1][1], j[2][2]];
    let att_tc = (0..3)
        .map(|i| slowest_time_constant(jd[i], k_w[i], k_r[i] + k_ia[i], k_ia[i] * c2))
        .fold(0.0, f64::max);
    let pos_tc = (0..3)
        .map(|i| slowest_time_constant(m, k_v[i], k_x[i] + k_ip[i], k_ip[i] * c1))
        .fold(0.0, f64::max);
    GainReport {
        conditions: [c2_cond, kis_cond, c1_cond, w_cond],
        alpha,
        attitude_time_constant: att_tc,
        position_time_constant: pos_tc,
        lambda_min_w1,
    }
}

/// The unstable root λ₊ of `J s³ + k_Ω s² + (k_I − k_R) s − k_I c2`: the
/// attitude loop (eqn:aM with eqn:eI) linearised at the rotation by π
/// about a principal axis with moment of inertia `J`. Near that
/// equilibrium the angle from it grows as `e^{λ₊ t}`, so the time to leave
/// it from a distance δ grows as `ln(1/δ)/λ₊`: why "almost global"
/// convergence is slow from near π.
pub fn lambda_plus(j: f64, k_r: f64, k_omega: f64, k_i: f64, c2: f64) -> f64 {
    let p = |s: f64| ((j * s + k_omega) * s + (k_i - k_r)) * s - k_i * c2;
    // p(0) = −k_I c2 ≤ 0 and p → +∞: bisection on a bracket, then it is
    // the only positive root when k_R > k_I (Descartes: one sign change).
    let (mut lo, mut hi) = (0.0, 1.0);
    while p(hi) < 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if p(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_helpers() {
        let e = sym3_eigen([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        assert!(
            (e[0] - 1.0).abs() < 1e-12 && (e[1] - 3.0).abs() < 1e-12 && (e[2] - 5.0).abs() < 1e-12
        );
        assert!((sym2_min_eig([[2.0, 1.0], [1.0, 2.0]]) - 1.0).abs() < 1e-12);
        assert!((norm2x2([[3.0, 0.0], [4.0, 0.0]]) - 5.0).abs() < 1e-12);
        // (s+1)(s+2)(s+10): slowest root −1, time constant 1 s.
        assert!((slowest_time_constant(1.0, 13.0, 32.0, 20.0) - 1.0).abs() < 1e-9);
        // (s+0.5)(s² + 2s + 5): complex pair at −1 ± 2i, slowest −0.5 → 2 s.
        assert!((slowest_time_constant(1.0, 2.5, 6.0, 2.5) - 2.0).abs() < 1e-9);
    }

    /// λ₊ against the cubic's value and the hand root for J = 0.0820:
    /// p(2.14) < 0 < p(2.15).
    #[test]
    fn lambda_plus_is_the_positive_root() {
        let (j, kr, kw, ki, c2) = (0.082, 0.65, 0.11, 0.06, 0.8);
        let l = lambda_plus(j, kr, kw, ki, c2);
        let p = |s: f64| j * s * s * s + kw * s * s + (ki - kr) * s - ki * c2;
        assert!(p(l).abs() < 1e-12);
        assert!(
            p(2.14) < 0.0 && p(2.15) > 0.0 && (2.14..2.15).contains(&l),
            "{l}"
        );
    }
}
