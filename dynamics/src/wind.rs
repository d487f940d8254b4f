//! Wind: the inertial velocity of the air as a function of time and
//! position, part of the environment a simulation evaluates at the vehicle
//! and hands to [`Vehicle::loads`](crate::Vehicle::loads) in its
//! [`LoadInput`](crate::LoadInput) (vehicles without aerodynamics ignore it). Frames are this crate's
//! (inertial `e3` down), units m/s.
//!
//! Built in: [`ConstantWind`], [`SinusoidWind`], [`LadderWind`] (steps; the
//! simulation lands its steps on them) and [`DrydenWind`] (MIL-F-8785C /
//! MIL-HDBK-1797 turbulence over a mean wind, reproducible from its seed and
//! independent of the integrator's steps).

/// A wind parameter out of range: the field and what is wrong with it.
#[derive(Clone, Debug, PartialEq)]
pub struct WindError {
    /// The parameter (`times`, `sigma`, `speed`, …).
    pub field: &'static str,
    /// The value and what was expected.
    pub message: String,
}

impl core::fmt::Display for WindError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for WindError {}

fn werr(field: &'static str, message: String) -> WindError {
    WindError { field, message }
}

/// A wind field. `velocity` takes `&mut self` so that a field may extend a
/// cache as time goes on (Dryden's filter states), but its value must be a
/// function of `(t, x)` alone: integrators evaluate it at stage times, out
/// of order and more than once.
pub trait Wind: Send {
    /// The air's inertial velocity at time `t` and position `x`, m/s.
    fn velocity(&mut self, t: f64, x: [f64; 3]) -> [f64; 3];
    /// Times in `[0, t_end)` where the field jumps, so that steps can land
    /// on them (the default: none, a continuous field).
    fn jumps(&self, _t_end: f64) -> Vec<f64> {
        Vec::new()
    }
}

/// A uniform, steady wind.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ConstantWind(pub [f64; 3]);

impl Wind for ConstantWind {
    fn velocity(&mut self, _t: f64, _x: [f64; 3]) -> [f64; 3] {
        self.0
    }
}

/// `mean + amplitude · sin(2π f t + phase)`, uniform in space.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SinusoidWind {
    /// Mean velocity, m/s.
    pub mean: [f64; 3],
    /// Amplitude per axis, m/s.
    pub amplitude: [f64; 3],
    /// Frequency, Hz.
    pub frequency: f64,
    /// Phase, rad.
    pub phase: f64,
}

impl Wind for SinusoidWind {
    fn velocity(&mut self, t: f64, _x: [f64; 3]) -> [f64; 3] {
        let s = (2.0 * core::f64::consts::PI * self.frequency * t + self.phase).sin();
        core::array::from_fn(|i| self.mean[i] + self.amplitude[i] * s)
    }
}

/// Piecewise-constant wind: `velocities[k]` after `times[k]` (and
/// `velocities[0]` before `times[0]`), uniform in space. At a jump itself
/// the value before it (left-continuous): a step that ends on the jump
/// reads the old side throughout, and a simulation that lands there reads
/// the new side just after it for the steps that follow.
#[derive(Clone, Debug, PartialEq)]
pub struct LadderWind {
    times: Vec<f64>,
    velocities: Vec<[f64; 3]>,
}

impl LadderWind {
    /// Checks that there is one velocity per time, at least one, times
    /// finite and strictly increasing, velocities finite; the error names
    /// the field and the value.
    pub fn new(times: Vec<f64>, velocities: Vec<[f64; 3]>) -> Result<Self, WindError> {
        if times.is_empty() || times.len() != velocities.len() {
            return Err(werr(
                "times",
                format!(
                    "{} times for {} velocities; give one time per velocity, at least one",
                    times.len(),
                    velocities.len()
                ),
            ));
        }
        if let Some(w) = times
            .windows(2)
            .find(|w| w[1].partial_cmp(&w[0]) != Some(core::cmp::Ordering::Greater))
        {
            return Err(werr(
                "times",
                format!("{} then {}; times must increase strictly", w[0], w[1]),
            ));
        }
        if let Some(t) = times.iter().find(|t| !t.is_finite()) {
            return Err(werr("times", format!("{t} is not finite")));
        }
        if let Some(v) = velocities.iter().find(|v| v.iter().any(|c| !c.is_finite())) {
            return Err(werr("velocities", format!("{v:?} is not finite")));
        }
        Ok(Self { times, velocities })
    }
}

impl Wind for LadderWind {
    fn velocity(&mut self, t: f64, _x: [f64; 3]) -> [f64; 3] {
        let k = self.times.partition_point(|&tk| tk < t);
        self.velocities[k.saturating_sub(1)]
    }
    fn jumps(&self, t_end: f64) -> Vec<f64> {
        self.times
            .iter()
            .copied()
            .filter(|&t| t > 0.0 && t < t_end)
            .collect()
    }
}

/// Dryden turbulence (MIL-F-8785C, MIL-HDBK-1797) over a mean wind:
/// the longitudinal component `u` through
/// `H_u(s) = σ_u √(2L_u/(πV)) / (1 + (L_u/V) s)`, the lateral `v` and
/// vertical `w` through
/// `H(s) = σ √(L/(πV)) (1 + √3 (L/V) s) / (1 + (L/V) s)²`, each driven by
/// white noise, `V` the speed the frozen turbulence field is carried past
/// the vehicle at. `u` lies along the mean wind's horizontal direction
/// (along `e1` without one), `v` across it, `w` along `e3`.
///
/// **Reproducible and independent of the step size**: the noise is sampled
/// on a fixed grid of spacing `grid` (zero-order hold, variance `π/grid`,
/// the intensity for which each component has variance σ², standard
/// normals from a counter-based generator keyed by `(seed, k, axis)`), and
/// the filters are solved exactly between grid points, so the field is a
/// continuous function of `t` and of the seed alone however an integrator
/// samples it. The grid only band-limits the noise: it must be well below
/// the filters' time constants `L/V` (the constructor checks `grid ≤
/// L/(10V)`). The filter state is therefore not part of the integrated
/// state: nothing is added to the vehicle's states and any stepper can run
/// it. Uniform in space (the field moves with the vehicle, the usual
/// assumption for a small vehicle).
#[derive(Clone, Debug)]
pub struct DrydenWind {
    mean: [f64; 3],
    sigma: [f64; 3],
    length: [f64; 3],
    speed: f64,
    seed: u64,
    grid: f64,
    /// Unit vectors of `u`, `v`, `w` in the inertial frame.
    axes: [[f64; 3]; 3],
    /// Filter states `[x_u, x_v1, x_v2, x_w1, x_w2]` at grid points
    /// `first, first + 1, …`: a window behind the latest time asked, so
    /// that an hour-long run keeps seconds of them, not megabytes.
    states: Vec<[f64; 5]>,
    first: usize,
}

/// Grid points of filter state kept behind the latest time asked (10 s at
/// the default 5 ms grid).
const WINDOW: usize = 2048;

/// Dryden's parameters; see [`DrydenWind`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DrydenSpec {
    /// Mean wind, m/s.
    pub mean: [f64; 3],
    /// Standard deviations of `u`, `v`, `w`, m/s.
    pub sigma: [f64; 3],
    /// Scale lengths `L_u`, `L_v`, `L_w`, m.
    pub length: [f64; 3],
    /// Speed the turbulence is carried at, m/s (`V > 0`; with a mean
    /// wind, its speed is the natural choice).
    pub speed: f64,
    /// Seed of the noise.
    pub seed: u64,
    /// Noise grid spacing, s.
    pub grid: f64,
}

impl DrydenSpec {
    /// σ = 1 m/s on every axis, no mean wind, MIL-HDBK-1797's low-altitude
    /// scale lengths at 15 m (50 ft): `L_w = 15 m`, `L_u = L_v =
    /// L_w/(0.177 + 0.000823 h)^1.2 = 94 m` (h in ft), carried at 5 m/s,
    /// seed 1, noise every 5 ms.
    pub fn gusty() -> Self {
        Self {
            mean: [0.0; 3],
            sigma: [1.0; 3],
            length: [94.0, 94.0, 15.0],
            speed: 5.0,
            seed: 1,
            grid: 0.005,
        }
    }
}

impl DrydenWind {
    /// Checks the parameters (σ ≥ 0, L > 0, V > 0, `0 < grid ≤ L/(10V)`,
    /// all finite); the error names the field and the value.
    pub fn new(p: DrydenSpec) -> Result<Self, WindError> {
        let finite = |name: &'static str, v: &[f64]| -> Result<(), WindError> {
            match v.iter().find(|c| !c.is_finite()) {
                Some(c) => Err(werr(name, format!("{c} is not finite"))),
                None => Ok(()),
            }
        };
        finite("mean", &p.mean)?;
        finite("sigma", &p.sigma)?;
        if let Some(s) = p.sigma.iter().find(|s| **s < 0.0) {
            return Err(werr("sigma", format!("{s} is negative")));
        }
        if let Some(l) = p.length.iter().find(|l| !(**l > 0.0 && l.is_finite())) {
            return Err(werr(
                "length",
                format!("{l}; scale lengths must be finite and > 0"),
            ));
        }
        if !(p.speed > 0.0 && p.speed.is_finite()) {
            return Err(werr(
                "speed",
                format!("{}; must be finite and > 0", p.speed),
            ));
        }
        let t_min = p
            .length
            .iter()
            .fold(f64::INFINITY, |m, l| m.min(l / p.speed));
        if !(p.grid > 0.0 && p.grid <= t_min / 10.0) {
            return Err(werr(
                "grid",
                format!(
                    "{} s; must be > 0 and at most a tenth of the shortest filter time constant L/V = {t_min} s",
                    p.grid
                ),
            ));
        }
        let h = (p.mean[0] * p.mean[0] + p.mean[1] * p.mean[1]).sqrt();
        let u = if h > 0.0 {
            [p.mean[0] / h, p.mean[1] / h, 0.0]
        } else {
            [1.0, 0.0, 0.0]
        };
        // v = e3 × u: horizontal, across the mean wind.
        let v = [-u[1], u[0], 0.0];
        Ok(Self {
            mean: p.mean,
            sigma: p.sigma,
            length: p.length,
            speed: p.speed,
            seed: p.seed,
            grid: p.grid,
            axes: [u, v, [0.0, 0.0, 1.0]],
            states: vec![[0.0; 5]],
            first: 0,
        })
    }

    /// The noise input held on grid interval `k`, per axis (`N(0, π/grid)`).
    fn noise(&self, k: u64) -> [f64; 3] {
        let s = (core::f64::consts::PI / self.grid).sqrt();
        core::array::from_fn(|axis| s * normal(self.seed, k, axis as u64))
    }

    /// The filter states `τ` after grid point `k` under noise `n`.
    fn advance(&self, x: [f64; 5], n: [f64; 3], tau: f64) -> [f64; 5] {
        let tu = self.length[0] / self.speed;
        let e = (-tau / tu).exp();
        let xu = e * x[0] + (1.0 - e) * n[0];
        let pair = |x1: f64, x2: f64, t: f64, n: f64| {
            // ẋ1 = x2, ẋ2 = −x1/T² − 2x2/T + n: a double pole at −1/T,
            // solved exactly (e^{Aτ} and its input integral in closed form).
            let e = (-tau / t).exp();
            let r = tau / t;
            (
                e * ((1.0 + r) * x1 + tau * x2) + t * t * (1.0 - e * (1.0 + r)) * n,
                e * (-(tau / (t * t)) * x1 + (1.0 - r) * x2) + e * tau * n,
            )
        };
        let (v1, v2) = pair(x[1], x[2], self.length[1] / self.speed, n[1]);
        let (w1, w2) = pair(x[3], x[4], self.length[2] / self.speed, n[2]);
        [xu, v1, v2, w1, w2]
    }

    /// The turbulence components `(u, v, w)` of filter states `x`.
    fn output(&self, x: [f64; 5]) -> [f64; 3] {
        let v = self.speed;
        let [lu, lv, lw] = self.length;
        let [su, sv, sw] = self.sigma;
        let ku = su * (2.0 * lu / (core::f64::consts::PI * v)).sqrt();
        let second = |x1: f64, x2: f64, s: f64, l: f64| {
            let t = l / v;
            let k = s * (l / (core::f64::consts::PI * v)).sqrt();
            k / (t * t) * x1 + k * 3f64.sqrt() / t * x2
        };
        [
            ku * x[0],
            second(x[1], x[2], sv, lv),
            second(x[3], x[4], sw, lw),
        ]
    }
}

impl Wind for DrydenWind {
    fn velocity(&mut self, t: f64, _x: [f64; 3]) -> [f64; 3] {
        let t = t.max(0.0);
        let k = (t / self.grid).floor();
        if !k.is_finite() || k > 1e9 {
            return [f64::NAN; 3];
        }
        let k = k as usize;
        if k < self.first {
            // Further back than the window (integrators look back at most
            // one step): start the filters again from t = 0.
            self.states = vec![[0.0; 5]];
            self.first = 0;
        }
        while self.first + self.states.len() <= k {
            let j = self.first + self.states.len() - 1;
            let last = self.states[self.states.len() - 1];
            let next = self.advance(last, self.noise(j as u64), self.grid);
            self.states.push(next);
            if self.states.len() > 2 * WINDOW {
                self.states.drain(..WINDOW);
                self.first += WINDOW;
            }
        }
        let x = self.advance(
            self.states[k - self.first],
            self.noise(k as u64),
            t - k as f64 * self.grid,
        );
        let [u, v, w] = self.output(x);
        core::array::from_fn(|i| {
            self.mean[i] + u * self.axes[0][i] + v * self.axes[1][i] + w * self.axes[2][i]
        })
    }
}

/// A standard normal keyed by `(seed, k, axis)` ([`lie::noise`]): a
/// function of the key alone, so noise sample `k` is the same whichever
/// order the samples are asked for.
fn normal(seed: u64, k: u64, axis: u64) -> f64 {
    use lie::noise::mix;
    lie::noise::normal(mix(seed
        ^ mix(k
            .wrapping_mul(3)
            .wrapping_add(axis)
            .wrapping_add(0x9e37_79b9_7f4a_7c15))))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `advance` is the exact flow of the shaping filters
    /// (`ẋu = (n − xu)/T_u`; `ẋ1 = x2`, `ẋ2 = −x1/T² − 2x2/T + n` per
    /// lateral axis), checked against the equations, not against a second
    /// solution: (1) a short step moves the state by `h·ẋ` to O(h²);
    /// (2) two steps equal one of their sum (the flow's group property);
    /// (3) the equilibrium of a held input, `xu = n`, `x1 = T² n`, `x2 = 0`,
    /// stays put. A wrong sign or factor in the closed form breaks at least
    /// one of them by far more than rounding.
    #[test]
    fn advance_is_the_exact_flow_of_the_filters() {
        let mut spec = DrydenSpec::gusty();
        spec.length = [30.0, 20.0, 10.0];
        let w = DrydenWind::new(spec).expect("valid");
        let (tu, tv, tw) = (30.0 / spec.speed, 20.0 / spec.speed, 10.0 / spec.speed);
        let x = [0.3, -0.7, 0.4, 0.2, -0.5];
        let n = [0.9, -0.4, 1.3];
        let rate = [
            (n[0] - x[0]) / tu,
            x[2],
            -x[1] / (tv * tv) - 2.0 * x[2] / tv + n[1],
            x[4],
            -x[3] / (tw * tw) - 2.0 * x[4] / tw + n[2],
        ];
        let h = 1e-6;
        let y = w.advance(x, n, h);
        for k in 0..5 {
            let d = (y[k] - x[k]) / h;
            // O(h) from the second derivative (≤ ~1 here) plus rounding
            // ε|x|/h ≈ 2e-10: measured ≤ 8.7e-7.
            assert!((d - rate[k]).abs() < 1e-5, "state {k}: {d} vs {}", rate[k]);
        }
        let (a, b) = (0.37, 1.21);
        let two = w.advance(w.advance(x, n, a), n, b);
        let one = w.advance(x, n, a + b);
        for k in 0..5 {
            assert!(
                (two[k] - one[k]).abs() < 1e-14,
                "state {k}: {} vs {}",
                two[k],
                one[k]
            );
        }
        let eq = [n[0], tv * tv * n[1], 0.0, tw * tw * n[2], 0.0];
        let after = w.advance(eq, n, 2.5);
        for k in 0..5 {
            assert!(
                (after[k] - eq[k]).abs() < 1e-14 * (1.0 + eq[k].abs()),
                "state {k}"
            );
        }
    }

    /// The gust's frame: the filters' `(u, v, w)` lie along the mean
    /// wind's horizontal direction, across it (`e3 × û`, horizontal) and
    /// along e3 (down), written out here for a mean wind from (3, 4, 0).
    #[test]
    fn gusts_lie_along_the_mean_wind_across_it_and_down() {
        let mut spec = DrydenSpec::gusty();
        spec.mean = [3.0, 4.0, 0.5];
        let mut w = DrydenWind::new(spec).expect("valid");
        let (along, across, down) = ([0.6, 0.8, 0.0], [-0.8, 0.6, 0.0], [0.0, 0.0, 1.0]);
        for t in [0.37, 2.0, 5.55] {
            let g = w.velocity(t, [0.0; 3]);
            let k = (t / spec.grid).floor() as usize;
            let x = w.advance(
                w.states[k - w.first],
                w.noise(k as u64),
                t - k as f64 * spec.grid,
            );
            let [u, v, z] = w.output(x);
            assert!(
                u.abs() > 1e-3 && v.abs() > 1e-3 && z.abs() > 1e-3,
                "all three gusts act"
            );
            for i in 0..3 {
                let want = spec.mean[i] + u * along[i] + v * across[i] + z * down[i];
                assert!(
                    (g[i] - want).abs() < 1e-14,
                    "t = {t}, axis {i}: {} vs {want}",
                    g[i]
                );
            }
        }
    }

    /// The output gains are the Dryden spectra's (MIL-F-8785C): with
    /// `T = L/V`, `H_u(s) = σ_u √(2L_u/(πV)) / (1 + T_u s)` and
    /// `H_v(s) = σ_v √(L_v/(πV)) (1 + √3 T_v s)/(1 + T_v s)²` (and `w` as
    /// `v`). The filters' states are `x_u` (`ẋ_u = (n − x_u)/T_u`) and per
    /// lateral axis `x1` with `X1 = T² N/(1 + Ts)²`, `x2 = ẋ1`, so the
    /// outputs must be `k_u x_u` and `k/T² x1 + √3 k/T x2`. Checked on unit
    /// states with a different σ and L per axis, so a gain off by a few
    /// per cent (which the variance test cannot see) or two axes swapped
    /// fail here.
    #[test]
    fn output_gains_are_the_dryden_spectra() {
        let mut spec = DrydenSpec::gusty();
        spec.sigma = [1.2, 0.8, 0.5];
        spec.length = [30.0, 20.0, 10.0];
        let w = DrydenWind::new(spec).expect("valid");
        let pi_v = std::f64::consts::PI * spec.speed;
        let k = |s: f64, l: f64| s * (l / pi_v).sqrt();
        let (tv, tw) = (20.0 / spec.speed, 10.0 / spec.speed);
        let want = [
            [1.2 * (2.0 * 30.0 / pi_v).sqrt(), 0.0, 0.0],
            [0.0, k(0.8, 20.0) / (tv * tv), 0.0],
            [0.0, k(0.8, 20.0) * 3f64.sqrt() / tv, 0.0],
            [0.0, 0.0, k(0.5, 10.0) / (tw * tw)],
            [0.0, 0.0, k(0.5, 10.0) * 3f64.sqrt() / tw],
        ];
        for (j, row) in want.iter().enumerate() {
            let mut x = [0.0; 5];
            x[j] = 1.0;
            let got = w.output(x);
            for i in 0..3 {
                assert!(
                    (got[i] - row[i]).abs() <= 1e-15 * row[i].abs(),
                    "state {j}, output {i}"
                );
            }
        }
    }

    /// A constant wind is its velocity everywhere, at every time.
    #[test]
    fn constant_wind_is_its_velocity() {
        let mut w = ConstantWind([1.5, -2.0, 0.25]);
        for (t, x) in [(0.0, [0.0; 3]), (7.5, [3.0, -1.0, 2.0])] {
            assert_eq!(w.velocity(t, x), [1.5, -2.0, 0.25]);
        }
        assert!(w.jumps(10.0).is_empty());
    }

    /// `mean + amplitude · sin(2π f t + phase)`, component by component.
    #[test]
    fn sinusoid_is_mean_plus_amplitude_times_sine() {
        let mut w = SinusoidWind {
            mean: [1.0, -2.0, 0.5],
            amplitude: [0.3, 0.0, -1.5],
            frequency: 0.25,
            phase: 0.7,
        };
        for t in [0.0, 0.4, 1.0, 3.3] {
            let s = (std::f64::consts::PI * 0.5 * t + 0.7).sin();
            let v = w.velocity(t, [5.0, 6.0, 7.0]);
            let want = [1.0 + 0.3 * s, -2.0, 0.5 - 1.5 * s];
            for k in 0..3 {
                assert!((v[k] - want[k]).abs() < 1e-15, "t = {t}, axis {k}");
            }
        }
    }

    /// Sample variance of each component and u's autocorrelation over
    /// 3000 s with L = (30, 30, 10) m at 5 m/s: the variance within 15 % of
    /// σ² (u's correlation time L/V = 6 s gives 500 of them, a relative
    /// standard error of the variance near √(2·6/3000) = 6 %, so 15 % is
    /// 2.4 of them), and the autocorrelation at lag L_u/V within 0.1 of
    /// e⁻¹ (the first-order filter's exp(−Vτ/L); the estimate's standard
    /// error is about 0.05).
    #[test]
    fn dryden_has_its_variance_and_correlation_time() {
        let mut spec = DrydenSpec::gusty();
        spec.length = [30.0, 30.0, 10.0];
        let mut w = DrydenWind::new(spec).expect("valid");
        let dt = 0.05;
        let n = 60_000;
        let samples: Vec<[f64; 3]> = (0..n)
            .map(|k| w.velocity(k as f64 * dt, [0.0; 3]))
            .collect();
        for axis in 0..3 {
            let var = samples.iter().map(|s| s[axis] * s[axis]).sum::<f64>() / n as f64;
            println!("Dryden axis {axis}: variance {var:.3} (σ² = 1)");
            assert!((var - 1.0).abs() < 0.15, "axis {axis}: variance {var}");
        }
        let lag = (30.0 / 5.0 / dt) as usize;
        let c0: f64 = samples.iter().map(|s| s[0] * s[0]).sum();
        let c1: f64 = samples.windows(lag + 1).map(|s| s[0][0] * s[lag][0]).sum();
        let rho = c1 / c0;
        println!("Dryden u: autocorrelation at L/V {rho:.3} (e⁻¹ = 0.368)");
        assert!((rho - (-1.0f64).exp()).abs() < 0.1, "ρ(L/V) = {rho}");
    }

    /// The field is a function of (seed, t): asked in any order, on any
    /// grid of times, the same values; another seed differs.
    #[test]
    fn dryden_is_a_function_of_seed_and_time() {
        let spec = DrydenSpec::gusty();
        let mut a = DrydenWind::new(spec).expect("valid");
        let mut b = DrydenWind::new(spec).expect("valid");
        let ts = [3.21, 0.017, 1.5, 3.2, 0.0, 7.77];
        let fwd: Vec<_> = ts.iter().map(|t| a.velocity(*t, [0.0; 3])).collect();
        let back: Vec<_> = ts.iter().rev().map(|t| b.velocity(*t, [0.0; 3])).collect();
        for (x, y) in fwd.iter().zip(back.iter().rev()) {
            assert_eq!(x, y);
        }
        let mut c = DrydenWind::new(DrydenSpec { seed: 2, ..spec }).expect("valid");
        assert_ne!(c.velocity(3.21, [0.0; 3]), fwd[0]);
        // Far past the kept window and back: the same values.
        let early = a.velocity(1.0, [0.0; 3]);
        let _ = a.velocity(100.0, [0.0; 3]);
        assert_eq!(a.velocity(1.0, [0.0; 3]), early);
        // Continuous across a grid point.
        let g = spec.grid;
        let (l, r) = (
            a.velocity(100.0 * g - 1e-12, [0.0; 3]),
            a.velocity(100.0 * g, [0.0; 3]),
        );
        assert!((0..3).all(|i| (l[i] - r[i]).abs() < 1e-9), "{l:?} {r:?}");
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = DrydenWind::new(DrydenSpec {
            speed: 0.0,
            ..DrydenSpec::gusty()
        })
        .unwrap_err();
        assert_eq!(e.field, "speed");
        assert_eq!(e.to_string(), "speed: 0; must be finite and > 0");
        let e = DrydenWind::new(DrydenSpec {
            grid: 1.0,
            ..DrydenSpec::gusty()
        })
        .unwrap_err();
        assert_eq!(e.field, "grid");
        let e = LadderWind::new(vec![1.0, 1.0], vec![[0.0; 3]; 2]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "times: 1 then 1; times must increase strictly"
        );
        let mut l =
            LadderWind::new(vec![1.0, 2.0], vec![[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]).unwrap();
        assert_eq!(l.velocity(0.5, [0.0; 3])[0], 1.0);
        assert_eq!(l.velocity(2.0, [0.0; 3])[0], 1.0);
        assert_eq!(l.velocity(2.0f64.next_up(), [0.0; 3])[0], 2.0);
        assert_eq!(l.jumps(10.0), vec![1.0, 2.0]);
    }
}
