//! Flying on an estimate: how well the filters track the truth in closed
//! loop, whether the invariant EKF's covariance is honest (NEES and NIS
//! over noise seeds), and how fast each filter recovers from a large
//! initial attitude error.
//!
//! The consistency check replays a run's recorded measurements through a
//! fresh invariant EKF with the settings the run used: the filter in the
//! loop saw exactly that stream in that order, so the replay's estimates
//! are the loop's, and its covariance is at hand for the NEES.

use lie::{ExtTwist, NalgebraF64, Se23, So3Mat};
use scenarios::{MeasurementRecord, RunOptions, RunOutput};
use scenes::scene::{EstimatorKind, EstimatorSpec};
use scenes::{Error, Scene};
use sensors::{Estimator, Iekf, ImuSample, Measurement, MocapSample, NavState};

type B = NalgebraF64;

/// The two-sided 95 % band of the mean of `m` independent NEES of `dof`
/// degrees of freedom each (`m·mean` is χ² with `m·dof` degrees): the
/// Wilson–Hilferty cube-root normal approximation, within 1e-3 relative
/// for the hundreds of degrees here.
pub fn chi2_band(m: usize, dof: usize) -> (f64, f64) {
    let k = (m * dof) as f64;
    let q = |z: f64| k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3) / m as f64;
    (q(-1.959_964), q(1.959_964))
}

/// The NEES and NIS figures of one scene over its seeds.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Consistency {
    /// Runs.
    pub runs: usize,
    /// Record instants after the burn-in.
    pub instants: usize,
    /// The mean NEES over every run and instant (15 states for the
    /// invariant EKF, 10 for the FDCL EKF).
    pub nees: f64,
    /// The band the mean over the runs at one instant should lie in.
    pub nees_band: (f64, f64),
    /// The share of instants whose mean over the runs is in the band.
    pub nees_inside: f64,
    /// The same for the NIS of the mocap (invariant EKF) or GPS (FDCL
    /// EKF) updates, 6 rows each.
    pub nis: f64,
    /// Its band.
    pub nis_band: (f64, f64),
    /// Its share.
    pub nis_inside: f64,
}

fn v3(a: [f64; 3]) -> lie::V3<B> {
    B::vec3(a[0], a[1], a[2])
}

/// A run's measurements as the estimator received them: `(arrival,
/// measurement)` in arrival order (capture time, then sensor, among equal
/// arrivals, as the simulation hands them over).
pub fn arrivals(out: &RunOutput) -> Vec<(f64, Measurement<B>)> {
    let mut ev: Vec<(f64, f64, usize, Measurement<B>)> = Vec::new();
    for m in &out.measurements {
        match *m {
            MeasurementRecord::Imu {
                t,
                accel,
                gyro,
                attitude,
            } => ev.push((
                t,
                t,
                0,
                Measurement::Imu(ImuSample {
                    k: 0,
                    t,
                    accel: v3(accel),
                    gyro: v3(gyro),
                    attitude: attitude.map(lie::ops::from_elems::<B>),
                }),
            )),
            MeasurementRecord::Mocap { t, arrival, state } => ev.push((
                arrival,
                t,
                1,
                Measurement::Mocap(MocapSample {
                    k: 0,
                    t,
                    x: v3(state.x),
                    v: v3(state.v),
                    r: lie::ops::from_elems::<B>(state.r),
                    omega: v3(state.omega),
                }),
            )),
            MeasurementRecord::Gps { t, arrival, x, v } => ev.push((
                arrival,
                t,
                2,
                Measurement::Gps(sensors::GpsSample {
                    k: 0,
                    t,
                    x: v3(x),
                    v: v3(v),
                }),
            )),
            _ => {}
        }
    }
    ev.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
    });
    ev.into_iter().map(|(a, _, _, m)| (a, m)).collect()
}

/// One run's NEES at each record instant from `burn_in` and the NIS of
/// each mocap update after it, by replaying its measurements through the
/// invariant EKF it flew on (true biases zero: the suites here have none).
fn replay(scene: &Scene, out: &RunOutput, burn_in: f64) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let spec = scene.estimator.clone().unwrap_or_default();
    let suite = scene
        .sensors
        .as_ref()
        .map(|s| s.suite())
        .transpose()
        .map_err(|(k, m)| Error::at_key(k, m))?
        .unwrap_or(sensors::SensorSuite {
            imu: None,
            mocap: None,
            gps: None,
            baro: None,
        });
    let cfg = scenes::iekf_config(&spec, &suite, scene.vehicle.gravity);
    let mut f = Iekf::<B>::new(cfg).map_err(|e| Error::at_key("estimator.kind", e.to_string()))?;
    replay_with(&mut f, out, burn_in, Measurement::is_mocap, |f, s| {
        let truth = Se23::<B>::new(
            So3Mat::from_matrix_unchecked(lie::ops::from_elems::<B>(s.r)),
            v3(s.v),
            v3(s.x),
        );
        let x = f.estimate(s.t);
        let est = Se23::<B>::new(So3Mat::from_matrix_unchecked(x.r), x.v, x.x);
        let eta: ExtTwist<B> = (est * truth.inverse()).log();
        let (bg, ba) = f.biases();
        let mut e = [0.0; 15];
        e[..9].copy_from_slice(&eta.to_array());
        e[9..12].copy_from_slice(&lie::ops::vec3_f64::<B>(bg));
        e[12..].copy_from_slice(&lie::ops::vec3_f64::<B>(ba));
        (nees_n(f.covariance(), &e), f.last_nis())
    })
}

/// The FDCL EKF's NEES in its own coordinates, `(x − x̂, v − v̂,
/// Log(R̂ᵀ R), b − b̂)` with the true bias zero, and its GPS updates' NIS,
/// by replaying the run's measurements through it.
fn replay_fdcl(
    scene: &Scene,
    out: &RunOutput,
    burn_in: f64,
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let mounting = scene
        .sensors
        .as_ref()
        .map(|s| s.suite())
        .transpose()
        .map_err(|(k, m)| Error::at_key(k, m))?
        .and_then(|s| s.imu)
        .map(|i| i.mounting);
    let d = sensors::FdclConfig::default();
    let mut f = sensors::FdclEkf::<B>::new(sensors::FdclConfig {
        r_bi: mounting.unwrap_or(d.r_bi),
        gravity: scene.vehicle.gravity,
        ..d
    });
    replay_with(&mut f, out, burn_in, Measurement::is_gps, |f, s| {
        let (x, v, _, r, _) = f.states();
        let mut e = [0.0; 10];
        let rt = So3Mat::<B>::from_matrix_unchecked(lie::ops::from_elems::<B>(s.r));
        let da = So3Mat::<B>::from_matrix_unchecked(r)
            .inverse()
            .compose(rt)
            .log();
        e[..3].copy_from_slice(&lie::ops::vec3_f64::<B>(v3(s.x) - x));
        e[3..6].copy_from_slice(&lie::ops::vec3_f64::<B>(v3(s.v) - v));
        e[6..9].copy_from_slice(&lie::ops::vec3_f64::<B>(da));
        e[9] = -f.bias();
        (nees_n(f.covariance(), &e), f.last_nis())
    })
}

/// Replays `out`'s measurements through `f` (reset at the run's first
/// sample) in arrival order; at each record sample from `burn_in` the
/// NEES `err` gives, and after each measurement `nis_after` picks, the
/// filter's last NIS (`NaN` where either is missing).
fn replay_with<E: Estimator<B>>(
    f: &mut E,
    out: &RunOutput,
    burn_in: f64,
    nis_after: fn(&Measurement<B>) -> bool,
    err: impl Fn(&E, &scenarios::Sample) -> (Option<f64>, Option<(f64, usize)>),
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let s0 = &out.samples[0];
    f.reset(
        0.0,
        &NavState {
            x: v3(s0.x),
            v: v3(s0.v),
            r: lie::ops::from_elems::<B>(s0.r),
            omega: v3(s0.omega),
        },
    );
    let events = arrivals(out);
    let (mut next, mut ne, mut ni) = (0usize, Vec::new(), Vec::new());
    for s in &out.samples {
        while next < events.len() && events[next].0 <= s.t + 1e-9 * s.t.max(1e-3) {
            f.update(&events[next].1);
            if nis_after(&events[next].1) && s.t >= burn_in {
                ni.push(err(f, s).1.map_or(f64::NAN, |n| n.0));
            }
            next += 1;
        }
        if s.t >= burn_in {
            ne.push(err(f, s).0.unwrap_or(f64::NAN));
        }
    }
    Ok((ne, ni))
}

/// `eᵀ P⁻¹ e` for an `N`-state filter.
fn nees_n<const N: usize>(p: &[[f64; N]; N], e: &[f64; N]) -> Option<f64> {
    let pi = sensors::kalman::spd_inverse(p)?;
    Some(
        (0..N)
            .map(|i| e[i] * (0..N).map(|j| pi[i][j] * e[j]).sum::<f64>())
            .sum(),
    )
}

/// Per-instant means over the runs, their band and the share inside.
fn summarise(runs: &[Vec<f64>], dof: usize) -> (f64, (f64, f64), f64, usize) {
    let len = runs.iter().map(Vec::len).min().unwrap_or(0);
    let band = chi2_band(runs.len(), dof);
    let means: Vec<f64> = (0..len)
        .map(|i| runs.iter().map(|r| r[i]).sum::<f64>() / runs.len() as f64)
        .collect();
    let inside = means
        .iter()
        .filter(|m| (band.0..=band.1).contains(*m))
        .count();
    let avg = means.iter().sum::<f64>() / len.max(1) as f64;
    (avg, band, inside as f64 / len.max(1) as f64, len)
}

/// `scene` over `seeds`, `burn_in` s left out, on its estimator: the
/// invariant EKF (15 states; NIS of its mocap updates) or the FDCL EKF (10
/// states; NIS of its GPS updates); runs on `threads` threads.
pub fn consistency(
    scene: &Scene,
    seeds: &[u64],
    burn_in: f64,
    threads: Option<usize>,
) -> Result<Consistency, Error> {
    let fdcl = scene
        .estimator
        .as_ref()
        .is_some_and(|e| e.kind == EstimatorKind::FdclEkf);
    let runs = crate::montecarlo::parallel_map(seeds, threads, |&seed| {
        let mut s = scene.clone();
        s.seed = seed;
        let out = scenes::run(&s, RunOptions::default())?;
        if fdcl {
            replay_fdcl(&s, &out, burn_in)
        } else {
            replay(&s, &out, burn_in)
        }
    })?;
    let (ne, ni): (Vec<_>, Vec<_>) = runs.into_iter().unzip();
    let (nees, nees_band, nees_inside, instants) = summarise(&ne, if fdcl { 10 } else { 15 });
    let (nis, nis_band, nis_inside, _) = summarise(&ni, 6);
    Ok(Consistency {
        runs: seeds.len(),
        instants,
        nees,
        nees_band,
        nees_inside,
        nis,
        nis_band,
        nis_inside,
    })
}

/// RMS of the estimate's position error and of the flown ‖e_x‖ from
/// `skip` s, m (the estimate's is zero for a truth-fed run).
pub fn rms_errors(out: &RunOutput, skip: f64) -> (f64, f64) {
    let (mut est, mut ex, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for s in out.samples.iter().filter(|s| s.t >= skip) {
        if let Some(e) = s.sensors.as_ref().and_then(|r| r.estimate) {
            est += (0..3).map(|i| (e.x[i] - s.x[i]).powi(2)).sum::<f64>();
        }
        ex += s.ex * s.ex;
        n += 1.0;
    }
    ((est / n).sqrt(), (ex / n).sqrt())
}

/// The angle between the estimate's attitude and the truth's at each
/// record sample, rad.
pub fn attitude_errors(out: &RunOutput) -> Vec<(f64, f64)> {
    out.samples
        .iter()
        .filter_map(|s| {
            let e = s.sensors.as_ref()?.estimate?;
            let tr: f64 = (0..3)
                .map(|i| (0..3).map(|k| e.r[k][i] * s.r[k][i]).sum::<f64>())
                .sum();
            Some((s.t, ((tr - 1.0) / 2.0).clamp(-1.0, 1.0).acos()))
        })
        .collect()
}

/// `scene` with its estimator of `kind` (the scene's other keys kept where
/// they apply).
pub fn with_estimator(scene: &Scene, kind: EstimatorKind) -> Scene {
    let mut s = scene.clone();
    if kind == EstimatorKind::None {
        s.estimator = None;
        return s;
    }
    let old = s.estimator.take().unwrap_or_default();
    s.estimator = Some(EstimatorSpec {
        kind,
        attitude_error: old.attitude_error,
        ..EstimatorSpec::default()
    });
    s
}

/// `f` of each seed's run of `scene`, on `threads` threads.
pub fn map_seeds<T: Send>(
    scene: &Scene,
    seeds: &[u64],
    threads: Option<usize>,
    f: impl Fn(&RunOutput) -> T + Sync + Send,
) -> Result<Vec<T>, Error> {
    map_seeds_with(scene, seeds, threads, |_, _| {}, f)
}

/// `f` of each seed's run of `scene` changed by `edit` for that seed.
pub fn map_seeds_with<T: Send>(
    scene: &Scene,
    seeds: &[u64],
    threads: Option<usize>,
    edit: impl Fn(&mut Scene, u64) + Sync + Send,
    f: impl Fn(&RunOutput) -> T + Sync + Send,
) -> Result<Vec<T>, Error> {
    crate::montecarlo::parallel_map(seeds, threads, |&seed| {
        let mut s = scene.clone();
        s.seed = seed;
        edit(&mut s, seed);
        let out = scenes::run(&s, RunOptions::default())?;
        Ok(f(&out))
    })
}

/// A unit axis from `seed`, uniform on the sphere.
pub fn random_axis(seed: u64) -> [f64; 3] {
    let key = sensors::NoiseKey::new(seed, 99);
    let [a, b] = key.pair(0, 0);
    let [c, _] = key.pair(0, 1);
    let n = (a * a + b * b + c * c).sqrt();
    [a / n, b / n, c / n]
}
