//! The checkpoints a run's steps land on.

use lie::Backend;

use super::Until;

/// The checkpoints that change the dynamics: control instants `k·Δ` of
/// sampled control (`ctrl` = Δ, 0 for continuous control) and the times
/// at which segments end, each computed, never accumulated.
pub(super) struct Grid {
    pub(super) ctrl: f64,
    pub(super) k_ctrl: u64,
    pub(super) switch_times: Vec<f64>,
    pub(super) k_sw: usize,
    /// Times the wind jumps at (sorted): checkpoints, not switches.
    pub(super) jumps: Vec<f64>,
    pub(super) k_jump: usize,
}

impl Grid {
    pub(super) fn new<B: Backend>(
        plan: &[super::Segment<'_, B>],
        ctrl: f64,
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
        if let Some(&ts) = self.switch_times.get(self.k_sw) {
            t_next = t_next.min(ts);
        }
        if let Some(&tj) = self.jumps.get(self.k_jump) {
            t_next = t_next.min(tj);
        }
        t_next
    }

    /// Arrived at checkpoint `t`: whether a time switch is due there,
    /// whether it is a control instant, and whether the wind jumps there.
    pub(super) fn arrive(&mut self, t: f64) -> (bool, bool, bool) {
        let mut jump = false;
        while self.jumps.get(self.k_jump).is_some_and(|&tj| tj <= t) {
            self.k_jump += 1;
            jump = true;
        }
        let switch_due = self.switch_times.get(self.k_sw).is_some_and(|&ts| ts <= t);
        if switch_due {
            self.k_sw += 1;
        }
        let on = |k: u64| (k as f64 * self.ctrl - t).abs() <= 1e-9 * self.ctrl;
        if self.ctrl > 0.0 && on(self.k_ctrl + 1) {
            self.k_ctrl += 1;
        }
        (switch_due, self.ctrl > 0.0 && on(self.k_ctrl), jump)
    }
}
