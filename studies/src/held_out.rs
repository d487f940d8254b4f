//! Whether a tuning generalises: the tuned and the starting scene flown on
//! noise seeds the tuning never saw, the cost compared seed by seed, with
//! a paired 95 % confidence interval of the mean difference.

use scenes::{Error, Registry, Scene};

use crate::sensitivity::{Cost, Tracking, plain_cost};

/// A two-sided 95 % confidence interval of a mean.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// The sample mean.
    pub mean: f64,
    /// Its lower and upper bounds.
    pub low: f64,
    /// See `low`.
    pub high: f64,
}

impl Interval {
    /// Whether zero lies outside it.
    pub fn excludes_zero(&self) -> bool {
        self.low > 0.0 || self.high < 0.0
    }
}

/// Student's t quantile at 0.975 for `dof ≥ 1` degrees of freedom: from
/// the table for 1 to 5, else the Cornish–Fisher expansion about the
/// normal quantile to the fourth order in `1/dof` (Abramowitz & Stegun
/// 26.7.5; within 5e-5 relative from 6 degrees on).
pub fn t_975(dof: usize) -> f64 {
    let z: f64 = 1.959_963_984_540_054;
    match dof {
        0 => f64::NAN,
        1 => 12.706_204_736_174_7,
        2 => 4.302_652_729_749_464,
        3 => 3.182_446_305_284_263,
        4 => 2.776_445_105_197_793,
        5 => 2.570_581_835_636_314,
        _ => {
            let n = dof as f64;
            let (z2, z3) = (z * z, z * z * z);
            let (z5, z7, z9) = (z3 * z2, z3 * z2 * z2, z3 * z3 * z3);
            z + (z3 + z) / (4.0 * n)
                + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * n * n)
                + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * n * n * n)
                + (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z)
                    / (92_160.0 * n * n * n * n)
        }
    }
}

/// The paired 95 % interval of `mean(a − b)` (the same seeds in the same
/// order); `None` for fewer than two pairs.
pub fn paired_interval(a: &[f64], b: &[f64]) -> Option<Interval> {
    let n = a.len().min(b.len());
    if n < 2 {
        return None;
    }
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let mean = d.iter().sum::<f64>() / n as f64;
    let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
    let half = t_975(n - 1) * (var / n as f64).sqrt();
    Some(Interval {
        mean,
        low: mean - half,
        high: mean + half,
    })
}

/// Two scenes' costs on the same held-out seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct HeldOut {
    /// The seeds flown.
    pub seeds: Vec<u64>,
    /// The starting scene's cost on each.
    pub start: Vec<f64>,
    /// The tuned scene's cost on each.
    pub tuned: Vec<f64>,
    /// The paired interval of `start − tuned`: above zero, the tuning
    /// lowered the cost on noise it never saw.
    pub improvement: Interval,
}

/// The seeds `count` held-out runs use: a million past the scene's own,
/// far from the `seed + i` a tuning over noise averages.
pub fn held_out_seeds(scene: &Scene, count: usize) -> Vec<u64> {
    (0..count as u64)
        .map(|j| scene.seed.wrapping_add(1_000_000 + j))
        .collect()
}

/// `start` and `tuned` flown on each of `seeds` (each scene's seed
/// replaced), `cost` sampled every `every`, and the paired interval.
///
/// Errors: fewer than two seeds ([`scenarios::SimError::Setting`] on
/// `seeds`), and those of the runs.
pub fn held_out<C: Cost>(
    registry: &Registry,
    start: &Scene,
    tuned: &Scene,
    seeds: &[u64],
    every: f64,
    cost: &mut C,
) -> Result<HeldOut, Error> {
    let run = |scene: &Scene, seed: u64, cost: &mut C| {
        let mut s = scene.clone();
        s.seed = seed;
        plain_cost(registry, &s, every, cost)
    };
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for &seed in seeds {
        a.push(run(start, seed, cost)?);
        b.push(run(tuned, seed, cost)?);
    }
    let improvement = paired_interval(&a, &b).ok_or_else(|| {
        Error::Run(scenarios::SimError::Setting {
            field: "seeds",
            message: format!(
                "{} held-out seeds: a paired interval needs 2 or more",
                seeds.len()
            ),
        })
    })?;
    Ok(HeldOut {
        seeds: seeds.to_vec(),
        start: a,
        tuned: b,
        improvement,
    })
}

/// [`held_out`] with the [`Tracking`] cost of `start`'s first position
/// segment, as [`crate::sensitivity::tune_gains`] tunes it. Compiled once
/// here, so a command line calls it without instantiating the engine (at
/// its own optimisation level) again.
///
/// Errors: those of [`Tracking::of`] and [`held_out`].
pub fn held_out_tracking(
    registry: &Registry,
    start: &Scene,
    tuned: &Scene,
    seeds: &[u64],
    every: f64,
) -> Result<HeldOut, Error> {
    let mut cost = Tracking::of(start, every)?;
    held_out(registry, start, tuned, seeds, every, &mut cost)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles_match_the_tables() {
        // Student's t at 0.975 from standard tables (six digits).
        for (dof, want) in [
            (1, 12.7062),
            (2, 4.30265),
            (3, 3.18245),
            (4, 2.77645),
            (5, 2.57058),
            (6, 2.44691),
            (7, 2.36462),
            (9, 2.26216),
            (19, 2.09302),
            (49, 2.00958),
            (1000, 1.96234),
        ] {
            let got = t_975(dof);
            assert!(
                ((got - want) / want).abs() < 1e-4,
                "dof {dof}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn a_paired_interval_sees_a_shift_hidden_in_the_spread() {
        // Costs spread over 1..20 with a constant shift of 0.1: the paired
        // interval is the shift exactly (zero width), which an unpaired
        // comparison of the two spreads would not resolve.
        let a: Vec<f64> = (1..=20).map(f64::from).collect();
        let b: Vec<f64> = a.iter().map(|x| x - 0.1).collect();
        let i = paired_interval(&a, &b).unwrap();
        assert!(
            (i.mean - 0.1).abs() < 1e-12 && (i.high - i.low) < 1e-12,
            "{i:?}"
        );
        assert!(i.excludes_zero());
        let c: Vec<f64> = a
            .iter()
            .enumerate()
            .map(|(k, x)| x + if k % 2 == 0 { 0.5 } else { -0.5 })
            .collect();
        let j = paired_interval(&a, &c).unwrap();
        assert!(!j.excludes_zero(), "{j:?}");
        assert!(paired_interval(&a[..1], &b[..1]).is_none());
    }
}
