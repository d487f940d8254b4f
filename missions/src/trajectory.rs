//! A piecewise-polynomial trajectory as a position reference.

use controllers::{PositionReference, PositionSource};
use lie::{Backend, Real, S, V3};

use crate::error::{MissionError, input};
use crate::poly::{Piece, derivative};

/// Pieces flown one after another from `t = 0`: `x_d` to its fourth
/// derivative and the yaw `ψ` to its second, the heading
/// `b1d = (cos ψ, sin ψ, 0)` (a yaw about e₃, which points down).
///
/// Before `t = 0` the trajectory holds its start and after its end it
/// holds its end, every derivative zero there.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    pieces: Vec<Piece>,
    /// Start time of each piece, and the end of the last.
    starts: Vec<f64>,
}

/// `x_d … x_d⁽⁴⁾` and `ψ, ψ̇, ψ̈` at one time, in f64.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Flat {
    /// `x_d` and its first four derivatives: `x[d][axis]`.
    pub x: [[f64; 3]; 5],
    /// `ψ`, `ψ̇`, `ψ̈`, rad.
    pub yaw: [f64; 3],
}

const AXES: [&str; 4] = ["x", "y", "z", "yaw"];

impl Trajectory {
    /// The trajectory of `pieces`; each needs a positive finite duration
    /// and finite coefficients, and there must be at least one.
    pub fn new(pieces: Vec<Piece>) -> Result<Self, MissionError> {
        if pieces.is_empty() {
            return Err(input("pieces", 0.0, "at least one piece"));
        }
        let mut starts = Vec::with_capacity(pieces.len() + 1);
        let mut t = 0.0;
        starts.push(t);
        for (i, p) in pieces.iter().enumerate() {
            if !(p.duration.is_finite() && p.duration > 0.0) {
                return Err(input(
                    format!("pieces[{i}].duration"),
                    p.duration,
                    "positive and finite (s)",
                ));
            }
            for (a, c) in p.coeffs.iter().enumerate() {
                if let Some((j, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                    let field = format!("pieces[{i}].{}^{j}", AXES[a]);
                    return Err(input(field, *v, "finite"));
                }
            }
            t += p.duration;
            starts.push(t);
        }
        Ok(Self { pieces, starts })
    }

    /// The pieces, in order.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }

    /// When each piece starts, and (last) when the trajectory ends, s.
    pub fn times(&self) -> &[f64] {
        &self.starts
    }

    /// The whole trajectory's length in time, s.
    pub fn duration(&self) -> f64 {
        self.starts[self.starts.len() - 1]
    }

    /// The piece flown at `t` and the time into it, or `None` with the
    /// clamped end (`false` before the start, `true` after the end).
    fn locate(&self, t: f64) -> Result<(usize, f64), bool> {
        if t.is_nan() || t < 0.0 {
            return Err(false);
        }
        if t > self.duration() {
            return Err(true);
        }
        let i = self.starts.partition_point(|s| *s <= t);
        let i = i.saturating_sub(1).min(self.pieces.len() - 1);
        Ok((i, t - self.starts[i]))
    }

    /// `x_d … x_d⁽⁴⁾` and `ψ, ψ̇, ψ̈` at `t`, s.
    pub fn flat(&self, t: f64) -> Flat {
        let mut out = Flat {
            x: [[0.0; 3]; 5],
            yaw: [0.0; 3],
        };
        let (i, tau, orders) = match self.locate(t) {
            Ok((i, tau)) => (i, tau, 5),
            Err(false) => (0, 0.0, 1),
            Err(true) => (
                self.pieces.len() - 1,
                self.pieces[self.pieces.len() - 1].duration,
                1,
            ),
        };
        let p = &self.pieces[i];
        for d in 0..orders {
            for a in 0..3 {
                out.x[d][a] = p.eval(a, d, tau);
            }
            if d < 3 {
                out.yaw[d] = p.eval(3, d, tau);
            }
        }
        out
    }

    /// The velocity at each piece's midpoint in time, m/s: where RotorPy
    /// bounds each component by its `v_max` (as an inequality of its QP).
    /// This planner enforces no such bound; compare these with yours.
    pub fn midpoint_velocities(&self) -> Vec<[f64; 3]> {
        self.pieces
            .iter()
            .map(|p| std::array::from_fn(|a| p.eval(a, 1, 0.5 * p.duration)))
            .collect()
    }

    /// The same trajectory in a z-up frame (the Crazyflie's, RotorPy's):
    /// `(x, y, z) ↦ (x, −y, −z)` and `ψ ↦ −ψ`, a rotation by π about e₁;
    /// coefficients are negated, so the map is exact and its own inverse.
    pub fn flipped(&self) -> Self {
        let mut t = self.clone();
        for p in &mut t.pieces {
            for a in 1..4 {
                p.coeffs[a] = p.coeffs[a].map(|c| -c);
            }
        }
        t
    }
}

impl<B: Backend> PositionSource<B> for Trajectory {
    fn position(&self, t: S<B>) -> PositionReference<B> {
        let tf = t.to_f64_lossless();
        let (i, tau, moving) = match self.locate(tf) {
            Ok((i, _)) => (i, t - S::<B>::lit(self.starts[i]), true),
            Err(false) => (0, S::<B>::lit(0.0), false),
            Err(true) => {
                let last = self.pieces.len() - 1;
                (last, S::<B>::lit(self.pieces[last].duration), false)
            }
        };
        let c = &self.pieces[i].coeffs;
        let zero = S::<B>::lit(0.0);
        let d = |a: usize, k: usize| {
            if moving || k == 0 {
                derivative(&c[a], k, tau)
            } else {
                zero
            }
        };
        let v3 = |k: usize| -> V3<B> { B::vec3(d(0, k), d(1, k), d(2, k)) };
        let (psi, psi_dot, psi_ddot) = (d(3, 0), d(3, 1), d(3, 2));
        let (s, co) = psi.sin_cos();
        let mut r = PositionReference::<B>::hold(v3(0), B::vec3(co, s, zero));
        r.v = v3(1);
        r.a = v3(2);
        r.jerk = v3(3);
        r.snap = v3(4);
        // d/dt (cos ψ, sin ψ) = ψ̇ (−sin ψ, cos ψ); twice: ψ̈ (−sin ψ, cos ψ)
        // − ψ̇² (cos ψ, sin ψ).
        r.b1d_dot = B::vec3(-psi_dot * s, psi_dot * co, zero);
        let w2 = psi_dot * psi_dot;
        r.b1d_ddot = B::vec3(-psi_ddot * s - w2 * co, psi_ddot * co - w2 * s, zero);
        r
    }

    fn position_f64(&self, t: f64) -> [f64; 3] {
        self.flat(t).x[0]
    }
}
