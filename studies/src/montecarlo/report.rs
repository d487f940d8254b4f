//! The report of a whole Monte Carlo run: the counts and percentiles of
//! [`Summary`], the extremes of the initial conditions, the slowest
//! samples, and the cost; `summary.json` is its serialisation, and its
//! `Display` is what the command line prints.

use std::fmt;

use super::{DIVERGED_OMEGA, DIVERGED_X, MAX_SUBSTEPS, Outcome, Setup, Summary};

/// One of the slowest samples, with the command that replays it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SlowSample {
    /// Sample index.
    pub index: u64,
    /// Whether it converged.
    pub converged: bool,
    /// How it ended ([`super::Status::name`]).
    pub status: &'static str,
    /// Time to converge, s (NaN when not converged).
    pub t_converge: f64,
    /// Initial angle from R_d = I, degrees.
    pub angle_deg: f64,
    /// Its axis.
    pub axis: [f64; 3],
    /// |Ω(0)|, rad/s.
    pub omega0: f64,
    /// ‖e_x(0)‖, m.
    pub ex0: f64,
    /// What replays it (given by the caller: a command line, a call).
    pub command: String,
}

/// Cost of the run, when it was timed.
#[derive(Copy, Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cost {
    /// Wall time, s.
    pub wall_s: f64,
    /// Samples per second of wall time.
    pub samples_per_s: f64,
    /// Wall time per integrator step, ns.
    pub ns_per_step: f64,
}

/// The report of a complete run (every index present).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Report {
    /// What was run.
    pub setup: Setup,
    /// Counts and times to converge.
    #[serde(flatten)]
    pub summary: Summary,
    /// The largest initial angle drawn, degrees.
    pub largest_angle_deg: f64,
    /// The largest rotor thrust over every sample, N.
    pub max_rotor_thrust: f64,
    /// The five slowest: not converged first, then by time to converge.
    pub slowest: Vec<SlowSample>,
    /// Wall time and throughput.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub cost: Option<Cost>,
}

impl Report {
    /// The report of `rows`; `replay(index)` says how to re-run a sample.
    pub fn new(
        setup: &Setup,
        rows: &[Outcome],
        wall: Option<f64>,
        replay: impl Fn(u64) -> String,
    ) -> Self {
        let summary = Summary::from_rows(rows.iter().map(|r| (r.status, r.t_converge, r.steps)));
        let mut slow: Vec<&Outcome> = rows.iter().collect();
        slow.sort_by(|a, b| {
            a.converged
                .cmp(&b.converged)
                .then(b.t_converge.total_cmp(&a.t_converge))
                .then(a.index.cmp(&b.index))
        });
        let slowest = slow
            .iter()
            .take(5)
            .map(|r| SlowSample {
                index: r.index,
                converged: r.converged,
                status: r.status.name(),
                t_converge: r.t_converge,
                angle_deg: r.angle.to_degrees(),
                axis: r.axis,
                omega0: r.omega0,
                ex0: r.ex0,
                command: replay(r.index),
            })
            .collect();
        let steps = summary.integrator_steps;
        Self {
            setup: setup.clone(),
            largest_angle_deg: rows
                .iter()
                .map(|r| r.angle)
                .fold(0.0, f64::max)
                .to_degrees(),
            max_rotor_thrust: rows.iter().map(|r| r.max_rotor).fold(0.0, f64::max),
            slowest,
            cost: wall.map(|w| Cost {
                wall_s: w,
                samples_per_s: rows.len() as f64 / w,
                ns_per_step: w * 1e9 / steps.max(1) as f64,
            }),
            summary,
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.summary;
        writeln!(
            f,
            "{} samples, {} converged ({:.4} %); largest initial angle {:.3}°",
            s.samples,
            s.converged,
            100.0 * s.converged_fraction,
            self.largest_angle_deg,
        )?;
        writeln!(
            f,
            "not converged: {} at the deadline, {} diverged (|Ω| > {DIVERGED_OMEGA} rad/s, ‖e_x‖ > {DIVERGED_X} m, or more than {MAX_SUBSTEPS} substeps in one dopri call), {} integrator errors",
            s.deadline, s.diverged, s.errors
        )?;
        let t = &s.t_converge;
        writeln!(
            f,
            "time to converge: median {:.3} s, 95th {:.3} s, 99th {:.3} s, worst {:.3} s",
            t.median, t.p95, t.p99, t.worst
        )?;
        if let Some(c) = &self.cost {
            writeln!(
                f,
                "wall {:.2} s: {:.0} samples/s, {:.0} ns per integrator step ({} steps)",
                c.wall_s, c.samples_per_s, c.ns_per_step, s.integrator_steps
            )?;
        }
        writeln!(f, "slowest samples:")?;
        for r in &self.slowest {
            writeln!(
                f,
                "  #{:<6} {}, t = {:.3} s, from {:.2}° (axis {:.3?}), |Ω(0)| = {:.3}, ‖e_x(0)‖ = {:.3}\n          {}",
                r.index, r.status, r.t_converge, r.angle_deg, r.axis, r.omega0, r.ex0, r.command,
            )?;
        }
        Ok(())
    }
}
