//! The checkpoints a run's steps land on.

use lie::Backend;

use super::Until;

/// The checkpoints that change the dynamics: control instants `k·Δ` of
/// sampled control (`ctrl` = Δ, 0 for continuous control), the outer
/// instants `k·Δ_o` of a multi-rate loop (`outer` = Δ_o, 0 for none) and
/// the times at which segments end, each computed, never accumulated.
pub(super) struct Grid {
    pub(super) ctrl: f64,
    pub(super) k_ctrl: u64,
    pub(super) outer: f64,
    pub(super) k_outer: u64,
    pub(super) switch_times: Vec<f64>,
    pub(super) k_sw: usize,
    /// Times the wind jumps at (sorted): checkpoints, not switches.
    pub(super) jumps: Vec<f64>,
    pub(super) k_jump: usize,
}

impl Grid {
    pub(super) fn new<B: Backend>(
        plan: &[super::Segment<'_, B>],
        (ctrl, outer): (f64, f64),
        t_end: f64,
        mut jumps: Vec<f64>,
    ) -> Self {
        jumps.retain(|t| *t > 0.0 && *t < t_end);
        jumps.sort_by(f64::total_cmp);
        let switch_times = plan
            .iter()
            .filter_map(|s| match s.until {
                Until::Time(u) => Some(u),
                _ => None,
            })
            .filter(|u| *u < t_end)
            .collect();
        Self {
            ctrl,
            k_ctrl: 0,
            outer,
            k_outer: 0,
            switch_times,
            k_sw: 0,
            jumps,
            k_jump: 0,
        }
    }

    /// The next checkpoint, or `t_end`.
    pub(super) fn next(&self, t_end: f64) -> f64 {
        let mut t_next = t_end;
        if self.ctrl > 0.0 {
            t_next = t_next.min((self.k_ctrl + 1) as f64 * self.ctrl);
        }
        if self.outer > 0.0 {
            t_next = t_next.min((self.k_outer + 1) as f64 * self.outer);
        }
        if let Some(&ts) = self.switch_times.get(self.k_sw) {
            t_next = t_next.min(ts);
        }
        if let Some(&tj) = self.jumps.get(self.k_jump) {
            t_next = t_next.min(tj);
        }
        t_next
    }

    /// Arrived at checkpoint `t`: what is due there.
    pub(super) fn arrive(&mut self, t: f64) -> Arrival {
        let mut jump = false;
        while self.jumps.get(self.k_jump).is_some_and(|&tj| tj <= t) {
            self.k_jump += 1;
            jump = true;
        }
        let switch_due = self.switch_times.get(self.k_sw).is_some_and(|&ts| ts <= t);
        if switch_due {
            self.k_sw += 1;
        }
        Arrival {
            switch_due,
            control_due: on_series(self.ctrl, &mut self.k_ctrl, t),
            outer_due: on_series(self.outer, &mut self.k_outer, t),
            jump,
        }
    }
}

/// What is due at a checkpoint.
#[derive(Copy, Clone, Debug)]
pub(super) struct Arrival {
    /// A segment's end time.
    pub switch_due: bool,
    /// A control instant.
    pub control_due: bool,
    /// An outer instant of a multi-rate loop.
    pub outer_due: bool,
    /// A wind jump.
    pub jump: bool,
}

/// Whether `t` is on the series `k·period` (none for period 0), moving
/// `k` onto it when it is the next instant.
fn on_series(period: f64, k: &mut u64, t: f64) -> bool {
    if period <= 0.0 {
        return false;
    }
    let on = |k: u64| (k as f64 * period - t).abs() <= 1e-9 * period;
    if on(*k + 1) {
        *k += 1;
    }
    on(*k)
}
