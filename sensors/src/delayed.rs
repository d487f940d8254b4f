//! Delayed measurements applied at the instant they describe: a short
//! history of the filter's states, the late measurement put in its place,
//! and every later one replayed to now (the delayed Kalman filter of the
//! FDCL lab's GPS work).
//!
//! [`Delayed`] wraps any estimator that can be cloned. Each measurement
//! that arrives in order is applied at once, as the filter alone would
//! apply it, and the filter's state before it is kept; a measurement whose
//! capture time lies before the last one applied rolls the filter back to
//! the kept state at that time, applies it, and replays the later ones.
//! With no late measurement it is the wrapped filter step for step, bit
//! for bit. The history spans `horizon` seconds: a measurement older than
//! that is refused and counted.
//!
//! Host only (`std`): the history holds one copy of the filter per
//! measurement, about 2 kB each for the invariant EKF in `f64`, 250 kB
//! for 0.2 s of a 1 kHz IMU, more than a Crazyflie-class flight CPU has.

extern crate std;
use std::collections::VecDeque;

use lie::Backend;

use crate::estimator::{Estimator, Measurement, NavState, SensorSet};
use crate::{SensorError, error::setting};

/// An estimator that applies late measurements at their capture time.
#[derive(Clone, Debug)]
pub struct Delayed<B: Backend, E> {
    filter: E,
    /// `(measurement, the filter's state before it)`, by capture time.
    log: VecDeque<(Measurement<B>, E)>,
    horizon: f64,
    rejected: u64,
    replayed: u64,
}

impl<B: Backend, E: Estimator<B> + Clone> Delayed<B, E> {
    /// `filter` with a history of `horizon` s (at least the longest delay
    /// of its sensors), checked finite and not negative.
    pub fn new(filter: E, horizon: f64) -> Result<Self, SensorError> {
        if !(horizon.is_finite() && horizon >= 0.0) {
            return Err(setting(
                "delayed.horizon",
                horizon,
                "finite and not negative (s)",
            ));
        }
        Ok(Self {
            filter,
            log: VecDeque::new(),
            horizon,
            rejected: 0,
            replayed: 0,
        })
    }

    /// The wrapped filter as it stands now.
    pub fn filter(&self) -> &E {
        &self.filter
    }
    /// Measurements refused as older than the history.
    pub fn rejections(&self) -> u64 {
        self.rejected
    }
    /// Measurements replayed after a late one.
    pub fn replayed(&self) -> u64 {
        self.replayed
    }

    fn latest(&self) -> f64 {
        self.log
            .back()
            .map_or(f64::NEG_INFINITY, |(m, _)| m.captured())
    }

    /// Drops what lies more than `horizon` before the latest measurement,
    /// keeping at least one entry so a measurement at the edge can still
    /// be placed.
    fn prune(&mut self) {
        let edge = self.latest() - self.horizon;
        while self.log.len() > 1 && self.log[1].0.captured() < edge {
            self.log.pop_front();
        }
    }
}

impl<B: Backend, E: Estimator<B> + Clone> Estimator<B> for Delayed<B, E> {
    fn name(&self) -> &'static str {
        self.filter.name()
    }
    fn needs(&self) -> SensorSet {
        self.filter.needs()
    }
    fn wants(&self) -> SensorSet {
        self.filter.wants()
    }
    fn reset(&mut self, t: f64, initial: &NavState<B>) {
        self.filter.reset(t, initial);
        self.log.clear();
    }
    fn update(&mut self, m: &Measurement<B>) {
        let t = m.captured();
        if !t.is_finite() {
            // The filter counts it.
            self.filter.update(m);
            return;
        }
        if t >= self.latest() {
            self.log.push_back((*m, self.filter.clone()));
            self.filter.update(m);
            self.prune();
            return;
        }
        // Late: after every kept measurement of the same or an earlier time.
        let at = self.log.partition_point(|(k, _)| k.captured() <= t);
        if at == 0 || t < self.latest() - self.horizon {
            self.rejected += 1;
            return;
        }
        self.filter = self.log[at].1.clone();
        self.log.insert(at, (*m, self.filter.clone()));
        self.filter.update(m);
        for i in at + 1..self.log.len() {
            self.log[i].1 = self.filter.clone();
            let later = self.log[i].0;
            self.filter.update(&later);
            self.replayed += 1;
        }
        self.prune();
    }
    fn estimate(&self, t: f64) -> NavState<B> {
        self.filter.estimate(t)
    }
    fn diagnostics(&self) -> Option<crate::Diagnostics> {
        self.filter.diagnostics()
    }
}
