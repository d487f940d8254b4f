//! Minimum-snap trajectories through waypoints (Mellinger & Kumar 2011):
//! on each axis, degree-7 pieces minimising `∫ (x⁽⁴⁾)² dt` with the
//! position at every waypoint, velocity, acceleration, jerk and snap
//! continuous at interior waypoints, and at the ends the given velocity
//! (rest by default) with zero acceleration and jerk. Only equalities are
//! active, so the QP is its KKT system, solved directly.

use nalgebra::{DMatrix, DVector};

use crate::error::{MissionError, input};
use crate::poly::{COEFFS, Piece, falling};
use crate::trajectory::Trajectory;

/// How the time between waypoints is allotted.
#[derive(Clone, Debug, PartialEq)]
pub enum Timing {
    /// Each segment's duration is its length over this mean speed, m/s
    /// (RotorPy's rule; its default is 1 m/s).
    MeanSpeed(f64),
    /// The time at each waypoint, s, from 0 at the first and increasing.
    At(Vec<f64>),
    /// A total time, s, shared out between the segments to minimise the
    /// snap cost of x, y and z (Mellinger & Kumar's time allocation, by
    /// gradient descent from durations in proportion to the lengths).
    Budget(f64),
}

/// A minimum-snap problem: waypoints, an optional yaw at each, the timing
/// and the velocities at the two ends.
///
/// ```
/// use missions::MinSnap;
/// let square = [[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 1.0, -1.5], [0.0, 1.0, -1.0]];
/// let traj = MinSnap::through(&square).mean_speed(0.5).solve()?;
/// // At the end: the last waypoint, at rest.
/// let end = traj.flat(traj.duration());
/// assert!((end.x[0][1] - 1.0).abs() < 1e-12);
/// assert!(end.x[1].iter().all(|v| v.abs() < 1e-12));
/// # Ok::<(), missions::MissionError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct MinSnap {
    waypoints: Vec<[f64; 3]>,
    yaw: Option<Vec<f64>>,
    timing: Timing,
    ends: [[f64; 3]; 2],
}

impl MinSnap {
    /// Through `waypoints` (m, e₃ down) at a mean speed of 1 m/s, from
    /// rest to rest, yaw 0.
    pub fn through(waypoints: &[[f64; 3]]) -> Self {
        Self {
            waypoints: waypoints.to_vec(),
            yaw: None,
            timing: Timing::MeanSpeed(1.0),
            ends: [[0.0; 3]; 2],
        }
    }

    /// A yaw at each waypoint, rad (about e₃, down): the yaw trajectory
    /// is a minimum-snap polynomial of its own on the same times, at rest
    /// at both ends.
    pub fn yaw(mut self, yaw: &[f64]) -> Self {
        self.yaw = Some(yaw.to_vec());
        self
    }

    /// Segment durations from their lengths at `speed` m/s.
    pub fn mean_speed(mut self, speed: f64) -> Self {
        self.timing = Timing::MeanSpeed(speed);
        self
    }

    /// The time at each waypoint, s (0 at the first, increasing).
    pub fn times(mut self, times: &[f64]) -> Self {
        self.timing = Timing::At(times.to_vec());
        self
    }

    /// A total time of `seconds`, shared out between the segments to
    /// minimise the snap cost ([`Timing::Budget`]).
    pub fn time_budget(mut self, seconds: f64) -> Self {
        self.timing = Timing::Budget(seconds);
        self
    }

    /// The velocity at the first and at the last waypoint, m/s.
    pub fn end_velocities(mut self, start: [f64; 3], end: [f64; 3]) -> Self {
        self.ends = [start, end];
        self
    }

    /// Each segment's duration, s, after checking the waypoints, the yaw
    /// and the timing.
    pub fn durations(&self) -> Result<Vec<f64>, MissionError> {
        let w = &self.waypoints;
        if w.len() < 2 {
            return Err(input("waypoints", w.len() as f64, "at least two waypoints"));
        }
        for (i, p) in w.iter().enumerate() {
            for (a, v) in p.iter().enumerate() {
                if !v.is_finite() {
                    return Err(input(
                        format!("waypoints[{i}].{}", ["x", "y", "z"][a]),
                        *v,
                        "finite (m)",
                    ));
                }
            }
        }
        if let Some(yaw) = &self.yaw {
            if yaw.len() != w.len() {
                let expected = format!("one yaw per waypoint ({})", w.len());
                return Err(input("yaw", yaw.len() as f64, expected));
            }
            if let Some((i, v)) = yaw.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(input(format!("yaw[{i}]"), *v, "finite (rad)"));
            }
        }
        for (e, name) in self.ends.iter().zip(["start_velocity", "end_velocity"]) {
            if let Some(v) = e.iter().find(|v| !v.is_finite()) {
                return Err(input(name, *v, "finite (m/s)"));
            }
        }
        match &self.timing {
            Timing::MeanSpeed(v) => {
                if !(v.is_finite() && *v > 0.0) {
                    return Err(input("mean_speed", *v, "positive and finite (m/s)"));
                }
                Ok(lengths(w)?.iter().map(|d| d / v).collect())
            }
            Timing::Budget(total) => {
                if !(total.is_finite() && *total > 0.0) {
                    return Err(input("time_budget", *total, "positive and finite (s)"));
                }
                let l = lengths(w)?;
                let sum: f64 = l.iter().sum();
                self.allot(l.iter().map(|d| total * d / sum).collect())
            }
            Timing::At(t) => {
                if t.len() != w.len() {
                    let expected = format!("one time per waypoint ({})", w.len());
                    return Err(input("times", t.len() as f64, expected));
                }
                if t[0] != 0.0 {
                    return Err(input("times[0]", t[0], "0 (the first waypoint's time)"));
                }
                let mut out = Vec::with_capacity(w.len() - 1);
                for i in 1..t.len() {
                    let d = t[i] - t[i - 1];
                    if !(t[i].is_finite() && d > 0.0) {
                        let expected = format!("finite and after times[{}] = {}", i - 1, t[i - 1]);
                        return Err(input(format!("times[{i}]"), t[i], expected));
                    }
                    out.push(d);
                }
                Ok(out)
            }
        }
    }

    /// The snap cost `Σ ∫ ‖x⁽⁴⁾‖² dt` of x, y and z (yaw left out) of the
    /// minimum-snap pieces with these segment `durations`, m²/s⁷: what
    /// [`Timing::Budget`] minimises, and a way to compare allocations.
    pub fn snap_cost(&self, durations: &[f64]) -> Result<f64, MissionError> {
        let mut cost = 0.0;
        for a in 0..3 {
            for (c, t) in self.solve_axis(a, durations)?.iter().zip(durations) {
                // ĉ = c Tʲ: the cost in normalised time, over T⁷.
                let n: Vec<f64> = (0..COEFFS).map(|j| c[j] * t.powi(j as i32)).collect();
                let mut q = 0.0;
                for j in 4..COEFFS {
                    for l in 4..COEFFS {
                        q += n[j] * snap_gram(j, l) * n[l];
                    }
                }
                cost += q / t.powi(7);
            }
        }
        Ok(cost)
    }

    /// Descends the snap cost over the durations with their sum fixed,
    /// from `start`: in softmax coordinates (so every duration stays
    /// positive), along the normalised central-difference gradient, with a
    /// step halved until the cost falls and doubled after it does; stops
    /// when the relative gradient is below 1e-9 or no step helps.
    fn allot(&self, start: Vec<f64>) -> Result<Vec<f64>, MissionError> {
        let m = start.len();
        if m < 2 {
            return Ok(start);
        }
        let total: f64 = start.iter().sum();
        let times = |z: &[f64]| -> Vec<f64> {
            let top = z.iter().fold(f64::NEG_INFINITY, |a, b| a.max(*b));
            let e: Vec<f64> = z.iter().map(|v| (v - top).exp()).collect();
            let sum: f64 = e.iter().sum();
            e.iter().map(|v| total * v / sum).collect()
        };
        let mut z: Vec<f64> = start.iter().map(|t| t.ln()).collect();
        let mut cost = self.snap_cost(&times(&z))?;
        let (h, mut step) = (1e-6, 0.1);
        for _ in 0..500 {
            let mut g = vec![0.0; m];
            for i in 0..m {
                z[i] += h;
                let up = self.snap_cost(&times(&z))?;
                z[i] -= 2.0 * h;
                let down = self.snap_cost(&times(&z))?;
                z[i] += h;
                g[i] = (up - down) / (2.0 * h * cost);
            }
            let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm < 1e-9 {
                break;
            }
            loop {
                let trial: Vec<f64> = z.iter().zip(&g).map(|(z, g)| z - step * g / norm).collect();
                let c = self.snap_cost(&times(&trial))?;
                if c < cost {
                    (z, cost, step) = (trial, c, (2.0 * step).min(1.0));
                    break;
                }
                step *= 0.5;
                if step < 1e-12 {
                    return Ok(times(&z));
                }
            }
        }
        Ok(times(&z))
    }

    /// The minimum-snap trajectory.
    pub fn solve(&self) -> Result<Trajectory, MissionError> {
        let durations = self.durations()?;
        let axes = (0..4)
            .map(|a| self.solve_axis(a, &durations))
            .collect::<Result<Vec<_>, _>>()?;
        let pieces = durations
            .iter()
            .enumerate()
            .map(|(i, &duration)| Piece {
                duration,
                coeffs: [axes[0][i], axes[1][i], axes[2][i], axes[3][i]],
            })
            .collect();
        Trajectory::new(pieces)
    }
}

/// Each segment's length, m; an error for two waypoints at one place,
/// whose segment cannot be timed by its length.
fn lengths(w: &[[f64; 3]]) -> Result<Vec<f64>, MissionError> {
    let extent = w.iter().flatten().fold(1.0f64, |m, c| m.max(c.abs()));
    let mut out = Vec::with_capacity(w.len() - 1);
    for (i, s) in w.windows(2).enumerate() {
        let d = dist(s[0], s[1]);
        // Below this the segment's polynomial cannot be told from a
        // point: its coefficients scale as 1/T⁷.
        if d <= 1e-9 * extent {
            let expected = format!(
                "apart from waypoint {i} to time a segment by its length \
                 (give times, or drop one of the two)"
            );
            return Err(input(format!("waypoints[{}] distance", i + 1), d, expected));
        }
        out.push(d);
    }
    Ok(out)
}

impl MinSnap {
    /// Axis `a` (0 x, 1 y, 2 z, 3 yaw) solved on `durations`: its points
    /// and end velocities (the yaw's at rest; 0 throughout without yaw).
    fn solve_axis(&self, a: usize, durations: &[f64]) -> Result<Vec<[f64; COEFFS]>, MissionError> {
        let (points, ends): (Vec<f64>, [f64; 2]) = match (a, &self.yaw) {
            (3, Some(yaw)) => (yaw.clone(), [0.0; 2]),
            (3, None) => (vec![0.0; self.waypoints.len()], [0.0; 2]),
            _ => (
                self.waypoints.iter().map(|w| w[a]).collect(),
                [self.ends[0][a], self.ends[1][a]],
            ),
        };
        let axis = ["x", "y", "z", "yaw"][a];
        solve_axis(&points, durations, ends).ok_or(MissionError::Solve { axis })
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// `∫₀¹ (dⁿ/dτⁿ τʲ)(dⁿ/dτⁿ τᵏ) dτ` for the snap (`n = 4`).
fn snap_gram(j: usize, k: usize) -> f64 {
    if j < 4 || k < 4 {
        return 0.0;
    }
    falling(j, 4) * falling(k, 4) / (j + k - 7) as f64
}

/// One axis: the coefficients (in seconds) of each segment through
/// `points` with `durations`, the end velocities `ends`. The unknowns are
/// each piece's coefficients in its normalised time `τ = t/T ∈ [0, 1]`
/// (`ĉⱼ = cⱼ Tʲ`), and a derivative row of order `d` is scaled by
/// `(T̄/T)ᵈ` with `T̄` the mean duration, so that the KKT matrix's entries
/// stay near 1 whatever the durations; `None` when it is singular.
fn solve_axis(points: &[f64], durations: &[f64], ends: [f64; 2]) -> Option<Vec<[f64; COEFFS]>> {
    let m = durations.len();
    let n = COEFFS * m;
    let mean = durations.iter().sum::<f64>() / m as f64;
    let s: Vec<f64> = durations.iter().map(|t| mean / t).collect();
    let mut rows: Vec<(Vec<(usize, f64)>, f64)> = Vec::with_capacity(6 * m + 2);
    // The d-th derivative at τ = 1 of piece i, in units of T̄⁻ᵈ.
    let at_end = |i: usize, d: usize| -> Vec<(usize, f64)> {
        (d..COEFFS)
            .map(|j| (COEFFS * i + j, falling(j, d) * s[i].powi(d as i32)))
            .collect()
    };
    let at_start = |i: usize, d: usize| vec![(COEFFS * i + d, falling(d, d) * s[i].powi(d as i32))];
    for i in 0..m {
        rows.push((at_start(i, 0), points[i]));
        rows.push((at_end(i, 0), points[i + 1]));
        if i + 1 < m {
            for d in 1..=4 {
                let mut r = at_end(i, d);
                r.extend(at_start(i + 1, d).into_iter().map(|(k, v)| (k, -v)));
                rows.push((r, 0.0));
            }
        }
    }
    rows.push((at_start(0, 1), ends[0] * mean));
    rows.push((at_end(m - 1, 1), ends[1] * mean));
    for d in 2..=3 {
        rows.push((at_start(0, d), 0.0));
        rows.push((at_end(m - 1, d), 0.0));
    }
    let size = n + rows.len();
    let mut k = DMatrix::<f64>::zeros(size, size);
    let mut rhs = DVector::<f64>::zeros(size);
    for i in 0..m {
        let w = s[i].powi(7);
        for j in 4..COEFFS {
            for l in 4..COEFFS {
                k[(COEFFS * i + j, COEFFS * i + l)] = w * snap_gram(j, l);
            }
        }
    }
    for (r, (entries, b)) in rows.iter().enumerate() {
        for &(c, v) in entries {
            k[(n + r, c)] = v;
            k[(c, n + r)] = v;
        }
        rhs[n + r] = *b;
    }
    let sol = k.lu().solve(&rhs)?;
    if sol.iter().any(|v| !v.is_finite()) {
        return None;
    }
    Some(
        (0..m)
            .map(|i| std::array::from_fn(|j| sol[COEFFS * i + j] / durations[i].powi(j as i32)))
            .collect(),
    )
}
