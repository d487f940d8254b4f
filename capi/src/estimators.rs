//! Two state estimators for flight software, the same code the simulation
//! flies: the invariant EKF on SE₂(3) with gyroscope and accelerometer
//! biases (`gpc_iekf_*`), and the passive complementary filter on SO(3)
//! with a gyroscope bias, position and velocity from the motion capture
//! (`gpc_complementary_*`).
//!
//! A filter is an opaque block of words the caller owns (a `static`, a
//! task's stack, a struct member: no heap); `*_init` makes it a filter and
//! every other call refuses a block it did not initialise. Feed it each IMU
//! sample and each motion-capture frame as they arrive, then read the
//! state a control law takes at the control instant with `*_estimate`:
//!
//! ```c
//! static GpcIekf filter;
//! GpcIekfConfig cfg = gpc_iekf_default_config();
//! gpc_iekf_init(&filter, &cfg, t0, &initial_state);
//! // each IMU sample, in time order:
//! GpcImuSample imu = { .t = t, .accel = {ax, ay, az}, .gyro = {gx, gy, gz} };
//! gpc_iekf_imu(&filter, &imu);
//! // each motion-capture frame, when it arrives:
//! gpc_iekf_mocap(&filter, &frame);
//! gpc_iekf_estimate(&filter, t_control, &state);
//! ```
//!
//! Times are `double` seconds: at 1 kHz a `float` time loses the sample
//! spacing after a few hours, and the filters' only `double` arithmetic is
//! on times and on the configuration's noise settings.
//!
//! The IMU reading is the sensor's own: specific force (m/s², a level
//! sensor at rest reads `−g` along its third axis, which points down) and
//! rate (rad/s), each for the interval that ends at the sample's time. A
//! motion-capture frame that arrives late (its capture time before the
//! filter's) is applied on arrival; the history that would apply it at
//! its capture time (the simulation's `Delayed`) needs a heap and is not
//! here.

use core::mem::{align_of, needs_drop, size_of};

use lie::{GlamF32, So3Mat};
use sensors::{
    Complementary, ComplementaryConfig, Estimator, IEKF_DIM, Iekf, IekfConfig, ImuSample,
    InitialSigma, Measurement, MocapSample, NavState,
};

use crate::check::{finite_all, rotation_ok};
use crate::convert::{mat, rows, vec};
use crate::{GpcState, GpcStatus};

type B = GlamF32;

/// Words (`uint64_t`) of a [`GpcIekf`]'s storage.
pub const GPC_IEKF_WORDS: usize = 192;
/// Words (`uint64_t`) of a [`GpcComplementary`]'s storage.
pub const GPC_COMPLEMENTARY_WORDS: usize = 40;

/// The first word of an initialised filter of each kind.
const IEKF_TAG: u64 = u64::from_le_bytes(*b"gpc iekf");
const COMPLEMENTARY_TAG: u64 = u64::from_le_bytes(*b"gpc comp");

/// What a block holds after its tag: the filter and the latest IMU
/// sample's time (a sample before it goes back in time; a frame may have
/// carried the filter itself past it).
struct Held<F> {
    filter: F,
    last_imu: f64,
}

// The filters live in the words after the tag: they must fit, need at most
// the words' alignment, and own nothing to drop (a block is overwritten or
// abandoned freely).
const _: () = {
    assert!(size_of::<Held<Iekf<B>>>() <= 8 * (GPC_IEKF_WORDS - 1));
    assert!(size_of::<Held<Complementary<B>>>() <= 8 * (GPC_COMPLEMENTARY_WORDS - 1));
    assert!(align_of::<Held<Iekf<B>>>() <= 8 && align_of::<Held<Complementary<B>>>() <= 8);
    assert!(!needs_drop::<Held<Iekf<B>>>() && !needs_drop::<Held<Complementary<B>>>());
};

/// The invariant EKF's storage. Opaque: initialise it with
/// [`gpc_iekf_init`], then only pass it to the `gpc_iekf_*` functions (it
/// may be copied as bytes).
#[repr(C)]
#[derive(Copy, Clone, Debug)]
pub struct GpcIekf {
    /// The filter's words.
    pub opaque: [u64; GPC_IEKF_WORDS],
}

impl Default for GpcIekf {
    /// Zeroed: not a filter until [`gpc_iekf_init`].
    fn default() -> Self {
        Self {
            opaque: [0; GPC_IEKF_WORDS],
        }
    }
}

/// The complementary filter's storage. Opaque, as [`GpcIekf`]: initialise
/// it with [`gpc_complementary_init`].
#[repr(C)]
#[derive(Copy, Clone, Debug)]
pub struct GpcComplementary {
    /// The filter's words.
    pub opaque: [u64; GPC_COMPLEMENTARY_WORDS],
}

impl Default for GpcComplementary {
    /// Zeroed: not a filter until [`gpc_complementary_init`].
    fn default() -> Self {
        Self {
            opaque: [0; GPC_COMPLEMENTARY_WORDS],
        }
    }
}

/// The noise the invariant EKF assumes and the IMU's mounting.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcIekfConfig {
    /// Gyroscope white noise, rad/s/√Hz (> 0).
    pub gyro_density: f32,
    /// Accelerometer white noise, m/s²/√Hz (> 0).
    pub accel_density: f32,
    /// Gyroscope bias random walk, rad/s/√s (≥ 0).
    pub gyro_walk: f32,
    /// Accelerometer bias random walk, m/s²/√s (≥ 0).
    pub accel_walk: f32,
    /// Motion-capture position σ, m (> 0).
    pub mocap_position: f32,
    /// Motion-capture attitude σ (a right perturbation), rad (> 0).
    pub mocap_attitude: f32,
    /// Initial σ of the position, velocity, attitude, gyroscope bias and
    /// accelerometer bias errors (m, m/s, rad, rad/s, m/s²; each > 0).
    pub initial_sigma: [f32; 5],
    /// The IMU's axes in the body frame (`R_BS`, row-major, a rotation),
    /// mounted at the centre of mass.
    pub mounting: [[f32; 3]; 3],
    /// Gravity, m/s², acting along `+e3` (down).
    pub gravity: f32,
}

/// The complementary filter's gains and the IMU's mounting.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcComplementaryConfig {
    /// Attitude gain `k_P`, 1/s (≥ 0).
    pub k_p: f32,
    /// Gyroscope-bias gain `k_I`, 1/s² (≥ 0; below `k_P²/4` for a
    /// well-damped bias).
    pub k_i: f32,
    /// The longest interval one attitude correction may span, s (> 0, with
    /// `k_P · max_interval < 1`).
    pub max_interval: f32,
    /// The IMU's axes in the body frame (`R_BS`, row-major, a rotation).
    pub mounting: [[f32; 3]; 3],
}

/// One IMU sample, in the sensor's axes.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcImuSample {
    /// Its time, s: the end of the interval it describes.
    pub t: f64,
    /// Specific force, m/s².
    pub accel: [f32; 3],
    /// Angular rate, rad/s.
    pub gyro: [f32; 3],
}

/// One motion-capture frame.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcMocapSample {
    /// Its capture time, s.
    pub t: f64,
    /// Position, inertial frame, m.
    pub x: [f32; 3],
    /// Velocity, inertial frame, m/s (the complementary filter's; the
    /// invariant EKF reads only the pose).
    pub v: [f32; 3],
    /// Attitude (body to inertial), row-major.
    pub r: [[f32; 3]; 3],
}

/// What the invariant EKF knows of its own accuracy.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcIekfDiagnostics {
    /// The error covariance's diagonal, in the order position, velocity,
    /// attitude (the log of the right-invariant error), gyroscope bias,
    /// accelerometer bias.
    pub variances: [f32; 15],
    /// The gyroscope bias estimate, sensor axes rotated to the body, rad/s.
    pub gyro_bias: [f32; 3],
    /// The accelerometer bias estimate, m/s².
    pub accel_bias: [f32; 3],
    /// The last update's normalised innovation squared (6 degrees of
    /// freedom); negative before the first.
    pub nis: f32,
    /// IMU samples and motion-capture frames the filter refused (an
    /// innovation variance that was not positive).
    pub rejected: [u32; 2],
}

fn rotation_field(r: &[[f32; 3]; 3]) -> Result<[[f64; 3]; 3], GpcStatus> {
    if finite_all(r.as_flattened()) && rotation_ok(r) {
        Ok(r.map(|row| row.map(f64::from)))
    } else {
        Err(GpcStatus::InvalidConfig)
    }
}

fn iekf_config(c: &GpcIekfConfig) -> Result<IekfConfig, GpcStatus> {
    let s = c.initial_sigma.map(f64::from);
    let cfg = IekfConfig {
        gyro_density: c.gyro_density.into(),
        accel_density: c.accel_density.into(),
        gyro_walk: c.gyro_walk.into(),
        accel_walk: c.accel_walk.into(),
        mocap_position: c.mocap_position.into(),
        mocap_attitude: c.mocap_attitude.into(),
        initial: InitialSigma {
            position: s[0],
            velocity: s[1],
            attitude: s[2],
            gyro_bias: s[3],
            accel_bias: s[4],
        },
        mounting: rotation_field(&c.mounting)?,
        gravity: c.gravity.into(),
        ..IekfConfig::default()
    };
    cfg.validate().map_err(|_| GpcStatus::InvalidConfig)?;
    Ok(cfg)
}

fn complementary_config(c: &GpcComplementaryConfig) -> Result<ComplementaryConfig, GpcStatus> {
    let cfg = ComplementaryConfig {
        k_p: c.k_p.into(),
        k_i: c.k_i.into(),
        max_interval: c.max_interval.into(),
        mounting: rotation_field(&c.mounting)?,
    };
    cfg.validate().map_err(|_| GpcStatus::InvalidConfig)?;
    Ok(cfg)
}

/// The state a filter starts from, checked as the laws check a state.
fn initial(t: f64, s: &GpcState) -> Result<NavState<B>, GpcStatus> {
    if !t.is_finite() {
        return Err(GpcStatus::InvalidTime);
    }
    let all = [s.x, s.v, s.omega];
    if !(finite_all(all.as_flattened()) && finite_all(s.r.as_flattened())) {
        return Err(GpcStatus::NonFiniteState);
    }
    if !rotation_ok(&s.r) {
        return Err(GpcStatus::NotARotation);
    }
    Ok(NavState {
        x: vec(s.x),
        v: vec(s.v),
        r: So3Mat::<B>::from_matrix_unchecked(mat(&s.r)).as_matrix(),
        omega: vec(s.omega),
    })
}

/// An IMU sample as a measurement, if its values are finite and it does not
/// go back before `now`.
fn imu(s: &GpcImuSample, now: f64) -> Result<Measurement<B>, GpcStatus> {
    if !(s.t.is_finite() && s.t >= now) {
        return Err(GpcStatus::InvalidTime);
    }
    if !(finite_all(&s.accel) && finite_all(&s.gyro)) {
        return Err(GpcStatus::NonFiniteMeasurement);
    }
    Ok(Measurement::Imu(ImuSample {
        k: 0,
        t: s.t,
        accel: vec(s.accel),
        gyro: vec(s.gyro),
        attitude: None,
    }))
}

/// A motion-capture frame as a measurement, if its values are finite and
/// its attitude a rotation.
fn mocap(s: &GpcMocapSample) -> Result<Measurement<B>, GpcStatus> {
    if !s.t.is_finite() {
        return Err(GpcStatus::InvalidTime);
    }
    if !(finite_all(&s.x) && finite_all(&s.v) && finite_all(s.r.as_flattened())) {
        return Err(GpcStatus::NonFiniteMeasurement);
    }
    if !rotation_ok(&s.r) {
        return Err(GpcStatus::NotARotation);
    }
    let z = vec([0.0; 3]);
    Ok(Measurement::Mocap(MocapSample {
        k: 0,
        t: s.t,
        x: vec(s.x),
        v: vec(s.v),
        r: mat(&s.r),
        omega: z,
    }))
}

fn to_state(n: &NavState<B>) -> GpcState {
    GpcState {
        x: n.x.to_array(),
        v: n.v.to_array(),
        r: rows(n.r),
        omega: n.omega.to_array(),
    }
}

/// The filter of type `T` a block tagged `tag` holds. Each tag is written
/// only by the `*_init` of its type (`IEKF_TAG`: `Iekf`,
/// `COMPLEMENTARY_TAG`: `Complementary`), and each caller here pairs them
/// so.
fn held<T>(words: &[u64], tag: u64) -> Option<&Held<T>> {
    // SAFETY: a block carries `tag` only after `place` wrote a `Held<T>`
    // behind it (see `place` for size and alignment).
    (words[0] == tag).then(|| unsafe { &*(words[1..].as_ptr() as *const Held<T>) })
}

/// [`held`], mutable.
fn held_mut<T>(words: &mut [u64], tag: u64) -> Option<&mut Held<T>> {
    // SAFETY: as `held`.
    (words[0] == tag).then(|| unsafe { &mut *(words[1..].as_mut_ptr() as *mut Held<T>) })
}

fn iekf_ref(f: &GpcIekf) -> Option<&Held<Iekf<B>>> {
    held(&f.opaque, IEKF_TAG)
}

fn iekf_mut(f: &mut GpcIekf) -> Option<&mut Held<Iekf<B>>> {
    held_mut(&mut f.opaque, IEKF_TAG)
}

fn complementary_ref(f: &GpcComplementary) -> Option<&Held<Complementary<B>>> {
    held(&f.opaque, COMPLEMENTARY_TAG)
}

fn complementary_mut(f: &mut GpcComplementary) -> Option<&mut Held<Complementary<B>>> {
    held_mut(&mut f.opaque, COMPLEMENTARY_TAG)
}

/// Writes `filter`, started at `t`, into the words after the tag, then
/// the tag.
fn place<T>(words: &mut [u64], tag: u64, filter: T, t: f64) {
    let h = Held {
        filter,
        last_imu: t,
    };
    // SAFETY: the words behind the tag are big and aligned enough for
    // `Held<T>` (the compile-time checks above) and it owns nothing to
    // drop, so overwriting whatever was there (an older filter, or
    // nothing) is sound.
    unsafe { core::ptr::write(words[1..].as_mut_ptr() as *mut Held<T>, h) };
    words[0] = tag;
}

/// Starts a built filter at `initial` at `t` and writes it into the
/// block; the block is left as it was on any error.
fn start<F: Estimator<B>>(
    words: &mut [u64],
    tag: u64,
    built: Result<F, GpcStatus>,
    t: f64,
    s: &GpcState,
) -> GpcStatus {
    let started = built.and_then(|mut e| {
        e.reset(t, &initial(t, s)?);
        Ok(e)
    });
    match started {
        Ok(e) => {
            place(words, tag, e, t);
            GpcStatus::Ok
        }
        Err(status) => status,
    }
}

/// Feeds an IMU sample to a held filter, unless it goes back before the
/// latest one or is not finite.
fn feed_imu<F: Estimator<B>>(h: &mut Held<F>, s: &GpcImuSample) -> Result<(), GpcStatus> {
    let m = imu(s, h.last_imu)?;
    h.filter.update(&m);
    h.last_imu = s.t;
    Ok(())
}

/// The invariant EKF's settings for a Crazyflie-class IMU (the BMI088's
/// densities) and a motion-capture system of 1 mm and 5 mrad, the IMU
/// mounted along the body axes, `g = 9.81`.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_iekf_default_config() -> GpcIekfConfig {
    let d = IekfConfig::default();
    let i = d.initial;
    GpcIekfConfig {
        gyro_density: d.gyro_density as f32,
        accel_density: d.accel_density as f32,
        gyro_walk: d.gyro_walk as f32,
        accel_walk: d.accel_walk as f32,
        mocap_position: d.mocap_position as f32,
        mocap_attitude: d.mocap_attitude as f32,
        initial_sigma: [
            i.position,
            i.velocity,
            i.attitude,
            i.gyro_bias,
            i.accel_bias,
        ]
        .map(|s| s as f32),
        mounting: d.mounting.map(|r| r.map(|x| x as f32)),
        gravity: d.gravity as f32,
    }
}

/// Makes `filter` an invariant EKF with `config`, at `initial` at time `t`
/// (s), zero biases and the configured initial covariance. The estimate
/// may start anywhere, e.g. far from the truth: the filter's error
/// dynamics do not depend on it. On a status other than
/// [`GpcStatus::Ok`], `filter` is not written.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_iekf_init(
    filter: Option<&mut GpcIekf>,
    config: Option<&GpcIekfConfig>,
    t: f64,
    initial_state: Option<&GpcState>,
) -> GpcStatus {
    let (Some(f), Some(c), Some(s)) = (filter, config, initial_state) else {
        return GpcStatus::NullPointer;
    };
    let built =
        iekf_config(c).and_then(|cfg| Iekf::<B>::new(cfg).map_err(|_| GpcStatus::InvalidConfig));
    start(&mut f.opaque, IEKF_TAG, built, t, s)
}

/// Propagates the filter to the sample's time on the previous sample's
/// reading and holds this one's until the next. A sample earlier than the
/// previous one (or than the start) is [`GpcStatus::InvalidTime`]; a
/// non-finite one [`GpcStatus::NonFiniteMeasurement`]; either leaves the
/// filter as it was.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_iekf_imu(
    filter: Option<&mut GpcIekf>,
    sample: Option<&GpcImuSample>,
) -> GpcStatus {
    let (Some(f), Some(s)) = (filter, sample) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = iekf_mut(f) else {
        return GpcStatus::NotInitialized;
    };
    let before = h.filter.rejections().imu;
    match feed_imu(h, s) {
        Ok(()) if h.filter.rejections().imu == before => GpcStatus::Ok,
        Ok(()) => GpcStatus::Rejected,
        Err(status) => status,
    }
}

/// Corrects the filter with a motion-capture pose (position and attitude;
/// the velocity is not read), propagated first to the frame's capture
/// time if that is later than the filter's, else applied on arrival. A
/// frame the filter refuses (an innovation variance that is not positive:
/// a covariance gone bad) is [`GpcStatus::Rejected`] and changes nothing.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_iekf_mocap(
    filter: Option<&mut GpcIekf>,
    sample: Option<&GpcMocapSample>,
) -> GpcStatus {
    let (Some(f), Some(s)) = (filter, sample) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = iekf_mut(f) else {
        return GpcStatus::NotInitialized;
    };
    let m = match mocap(s) {
        Ok(m) => m,
        Err(status) => return status,
    };
    let before = h.filter.rejections().mocap;
    h.filter.update(&m);
    if h.filter.rejections().mocap == before {
        GpcStatus::Ok
    } else {
        GpcStatus::Rejected
    }
}

/// The state a control law reads at `t` (s): the mean carried from the
/// filter's time on the held IMU sample, body rates from the gyroscope less
/// its bias.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_iekf_estimate(
    filter: Option<&GpcIekf>,
    t: f64,
    out: Option<&mut GpcState>,
) -> GpcStatus {
    let (Some(f), Some(out)) = (filter, out) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = iekf_ref(f) else {
        return GpcStatus::NotInitialized;
    };
    if !t.is_finite() {
        return GpcStatus::InvalidTime;
    }
    *out = to_state(&h.filter.estimate(t));
    GpcStatus::Ok
}

/// The covariance's diagonal, the bias estimates, the last NIS and the
/// refusals.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_iekf_diagnostics(
    filter: Option<&GpcIekf>,
    out: Option<&mut GpcIekfDiagnostics>,
) -> GpcStatus {
    let (Some(f), Some(out)) = (filter, out) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = iekf_ref(f) else {
        return GpcStatus::NotInitialized;
    };
    let e = &h.filter;
    let p = e.covariance();
    let (bg, ba) = e.biases();
    let r = e.rejections();
    *out = GpcIekfDiagnostics {
        variances: core::array::from_fn::<f32, IEKF_DIM, _>(|i| p[i][i]),
        gyro_bias: bg.to_array(),
        accel_bias: ba.to_array(),
        nis: e.last_nis().map_or(-1.0, |(n, _)| n as f32),
        rejected: [r.imu, r.mocap].map(|n| n.min(u64::from(u32::MAX)) as u32),
    };
    GpcStatus::Ok
}

/// The complementary filter's default gains (`k_P = 2/s`, `k_I = 0.2/s²`,
/// a 0.1 s cap), for attitude measurements at about 100 Hz; the IMU
/// mounted along the body axes.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_complementary_default_config() -> GpcComplementaryConfig {
    let d = ComplementaryConfig::default();
    GpcComplementaryConfig {
        k_p: d.k_p as f32,
        k_i: d.k_i as f32,
        max_interval: d.max_interval as f32,
        mounting: d.mounting.map(|r| r.map(|x| x as f32)),
    }
}

/// Makes `filter` a complementary filter with `config`, at `initial` (its
/// attitude, position and velocity) at time `t` (s), zero bias. On a
/// status other than [`GpcStatus::Ok`], `filter` is not written.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_complementary_init(
    filter: Option<&mut GpcComplementary>,
    config: Option<&GpcComplementaryConfig>,
    t: f64,
    initial_state: Option<&GpcState>,
) -> GpcStatus {
    let (Some(f), Some(c), Some(s)) = (filter, config, initial_state) else {
        return GpcStatus::NullPointer;
    };
    let built = complementary_config(c)
        .and_then(|cfg| Complementary::<B>::new(cfg).map_err(|_| GpcStatus::InvalidConfig));
    start(&mut f.opaque, COMPLEMENTARY_TAG, built, t, s)
}

/// Turns the attitude to the sample's time on the previous sample's rate
/// (the mean of the two, less the bias) and holds this one's. Refuses a
/// sample as [`gpc_iekf_imu`] does.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_complementary_imu(
    filter: Option<&mut GpcComplementary>,
    sample: Option<&GpcImuSample>,
) -> GpcStatus {
    let (Some(f), Some(s)) = (filter, sample) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = complementary_mut(f) else {
        return GpcStatus::NotInitialized;
    };
    match feed_imu(h, s) {
        Ok(()) => GpcStatus::Ok,
        Err(status) => status,
    }
}

/// Turns the attitude toward the frame's and moves the bias against the
/// difference; takes the frame's position and velocity.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_complementary_mocap(
    filter: Option<&mut GpcComplementary>,
    sample: Option<&GpcMocapSample>,
) -> GpcStatus {
    let (Some(f), Some(s)) = (filter, sample) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = complementary_mut(f) else {
        return GpcStatus::NotInitialized;
    };
    match mocap(s) {
        Ok(m) => {
            h.filter.update(&m);
            GpcStatus::Ok
        }
        Err(status) => status,
    }
}

/// The state a control law reads at `t` (s): the attitude carried on the
/// held gyroscope rate, the position carried on the frame's velocity.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_complementary_estimate(
    filter: Option<&GpcComplementary>,
    t: f64,
    out: Option<&mut GpcState>,
) -> GpcStatus {
    let (Some(f), Some(out)) = (filter, out) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = complementary_ref(f) else {
        return GpcStatus::NotInitialized;
    };
    if !t.is_finite() {
        return GpcStatus::InvalidTime;
    }
    *out = to_state(&h.filter.estimate(t));
    GpcStatus::Ok
}

/// The gyroscope bias estimate (body frame, rad/s).
#[unsafe(no_mangle)]
pub extern "C" fn gpc_complementary_gyro_bias(
    filter: Option<&GpcComplementary>,
    out: Option<&mut [f32; 3]>,
) -> GpcStatus {
    let (Some(f), Some(out)) = (filter, out) else {
        return GpcStatus::NullPointer;
    };
    let Some(h) = complementary_ref(f) else {
        return GpcStatus::NotInitialized;
    };
    *out = h.filter.bias().to_array();
    GpcStatus::Ok
}
