//! The record formats of the firmware test: stored sequences of inputs
//! (taken from host runs in `f32`) that a Cortex-M image runs the laws and
//! the filters on, and the words it prints of what they computed. The
//! image and the host read and write records through these functions, so
//! the two sides cannot disagree on the layout. Not part of the C ABI.

use crate::{
    GpcAttitudeOutput, GpcAttitudeReference, GpcComplementary, GpcIekf, GpcIekfDiagnostics,
    GpcImuSample, GpcIntegrals, GpcMocapSample, GpcPositionOutput, GpcPositionReference, GpcState,
    GpcStatus, gpc_complementary_default_config, gpc_complementary_estimate, gpc_complementary_imu,
    gpc_complementary_init, gpc_complementary_mocap, gpc_iekf_default_config, gpc_iekf_diagnostics,
    gpc_iekf_estimate, gpc_iekf_imu, gpc_iekf_init, gpc_iekf_mocap,
};

/// Floats per input record: state 18, integrals 6, attitude reference 15,
/// position reference 24.
pub const RECORD_FLOATS: usize = 63;
/// Bytes per input record (little-endian `f32`).
pub const RECORD_BYTES: usize = 4 * RECORD_FLOATS;
/// Words per printed output: the position output's 38 floats and 2 flags,
/// the attitude output's 13 floats.
pub const OUTPUT_WORDS: usize = 53;

/// One instant's inputs to both laws.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Record {
    /// The vehicle's state.
    pub state: GpcState,
    /// `e_I`, `e_i`.
    pub integrals: GpcIntegrals,
    /// For the attitude law.
    pub attitude: GpcAttitudeReference,
    /// For the position law.
    pub position: GpcPositionReference,
}

impl Record {
    /// Every float field, in the stored order.
    fn slots(&mut self) -> [&mut [f32]; 17] {
        let Record {
            state: s,
            integrals: i,
            attitude: a,
            position: p,
        } = self;
        [
            &mut s.x,
            &mut s.v,
            s.r.as_flattened_mut(),
            &mut s.omega,
            &mut i.e_i_att,
            &mut i.e_i_pos,
            a.rd.as_flattened_mut(),
            &mut a.omega_d,
            &mut a.omega_d_dot,
            &mut p.x,
            &mut p.v,
            &mut p.a,
            &mut p.jerk,
            &mut p.snap,
            &mut p.b1d,
            &mut p.b1d_dot,
            &mut p.b1d_ddot,
        ]
    }

    /// The record as stored: `RECORD_FLOATS` little-endian `f32`s.
    pub fn encode(&self) -> [u8; RECORD_BYTES] {
        let mut copy = *self;
        let mut out = [0u8; RECORD_BYTES];
        let mut k = 0;
        for slot in copy.slots() {
            for x in slot.iter() {
                out[k..k + 4].copy_from_slice(&x.to_le_bytes());
                k += 4;
            }
        }
        out
    }

    /// Reads a record from `RECORD_BYTES` bytes; `None` if there are fewer.
    pub fn decode(bytes: &[u8]) -> Option<Self> {
        let bytes = bytes.get(..RECORD_BYTES)?;
        let mut r = Record::default();
        let mut words = bytes.chunks_exact(4);
        for slot in r.slots() {
            for x in slot.iter_mut() {
                let w = words.next()?;
                *x = f32::from_le_bytes([w[0], w[1], w[2], w[3]]);
            }
        }
        Some(r)
    }
}

/// The bits of both outputs, in a fixed order: what the image prints and
/// the host compares.
pub fn output_words(p: &GpcPositionOutput, a: &GpcAttitudeOutput) -> [u32; OUTPUT_WORDS] {
    let floats: [&[f32]; 17] = [
        core::slice::from_ref(&p.thrust),
        &p.moment,
        p.rc.as_flattened(),
        &p.omega_c,
        &p.omega_c_dot,
        &p.e_x,
        &p.e_v,
        &p.e_r,
        &p.e_omega,
        core::slice::from_ref(&p.psi),
        &p.e_i_pos_rate,
        &p.e_i_att_rate,
        &a.moment,
        &a.e_r,
        &a.e_omega,
        core::slice::from_ref(&a.psi),
        &a.e_i_rate,
    ];
    let mut out = [0u32; OUTPUT_WORDS];
    let mut k = 0;
    for x in floats.iter().flat_map(|s| s.iter()) {
        out[k] = x.to_bits();
        k += 1;
    }
    out[k] = p.thrust_direction_undefined.into();
    out[k + 1] = p.heading_undefined.into();
    debug_assert_eq!(k + 2, OUTPUT_WORDS);
    out
}

/// Bytes per event of the estimators' stream: kind (`u32`), a reserved
/// `u32`, the time (`f64`) and 18 `f32` of payload, little-endian.
pub const EVENT_BYTES: usize = 4 + 4 + 8 + 4 * 18;
/// Words per printed estimator output: the invariant EKF's estimate (18)
/// and covariance diagonal (15), the complementary filter's estimate (18).
pub const ESTIMATE_WORDS: usize = 51;

/// One event of a recorded estimator stream.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Event {
    /// Both filters start from this state at this time (the stream's first
    /// event).
    Start(f64, GpcState),
    /// An IMU sample.
    Imu(GpcImuSample),
    /// A motion-capture frame, at its arrival.
    Mocap(GpcMocapSample),
}

impl Event {
    /// The event as stored.
    pub fn encode(&self) -> [u8; EVENT_BYTES] {
        let (kind, t, payload): (u32, f64, [f32; 18]) = match self {
            Event::Start(t, s) => (0, *t, state_floats(s)),
            Event::Imu(s) => {
                let mut p = [0.0; 18];
                p[..3].copy_from_slice(&s.accel);
                p[3..6].copy_from_slice(&s.gyro);
                (1, s.t, p)
            }
            Event::Mocap(s) => {
                let mut p = [0.0; 18];
                p[..3].copy_from_slice(&s.x);
                p[3..6].copy_from_slice(&s.v);
                p[6..15].copy_from_slice(s.r.as_flattened());
                (2, s.t, p)
            }
        };
        let mut out = [0u8; EVENT_BYTES];
        out[..4].copy_from_slice(&kind.to_le_bytes());
        out[8..16].copy_from_slice(&t.to_le_bytes());
        for (k, x) in payload.iter().enumerate() {
            out[16 + 4 * k..20 + 4 * k].copy_from_slice(&x.to_le_bytes());
        }
        out
    }

    /// Reads an event from `EVENT_BYTES` bytes; `None` if there are fewer
    /// or the kind is unknown.
    pub fn decode(bytes: &[u8]) -> Option<Self> {
        let b = bytes.get(..EVENT_BYTES)?;
        let word = |k: usize| [b[k], b[k + 1], b[k + 2], b[k + 3]];
        let kind = u32::from_le_bytes(word(0));
        let mut t = [0u8; 8];
        t.copy_from_slice(&b[8..16]);
        let t = f64::from_le_bytes(t);
        let p: [f32; 18] = core::array::from_fn(|k| f32::from_le_bytes(word(16 + 4 * k)));
        let v = |k: usize| [p[k], p[k + 1], p[k + 2]];
        let m = |k: usize| [v(k), v(k + 3), v(k + 6)];
        match kind {
            0 => Some(Event::Start(
                t,
                GpcState {
                    x: v(0),
                    v: v(3),
                    r: m(6),
                    omega: v(15),
                },
            )),
            1 => Some(Event::Imu(GpcImuSample {
                t,
                accel: v(0),
                gyro: v(3),
            })),
            2 => Some(Event::Mocap(GpcMocapSample {
                t,
                x: v(0),
                v: v(3),
                r: m(6),
            })),
            _ => None,
        }
    }

    /// Its time, s.
    pub fn time(&self) -> f64 {
        match self {
            Event::Start(t, _) => *t,
            Event::Imu(s) => s.t,
            Event::Mocap(s) => s.t,
        }
    }
}

fn state_floats(s: &GpcState) -> [f32; 18] {
    let mut p = [0.0; 18];
    p[..3].copy_from_slice(&s.x);
    p[3..6].copy_from_slice(&s.v);
    p[6..15].copy_from_slice(s.r.as_flattened());
    p[15..].copy_from_slice(&s.omega);
    p
}

/// The bits of both filters' outputs after an event, in a fixed order:
/// what the image prints and the host compares.
pub fn estimate_words(
    iekf: &GpcState,
    diagnostics: &GpcIekfDiagnostics,
    complementary: &GpcState,
) -> [u32; ESTIMATE_WORDS] {
    let mut out = [0u32; ESTIMATE_WORDS];
    let floats = state_floats(iekf)
        .into_iter()
        .chain(diagnostics.variances)
        .chain(state_floats(complementary));
    for (o, x) in out.iter_mut().zip(floats) {
        *o = x.to_bits();
    }
    out
}

/// What one event does to both filters: starts them, or feeds them the
/// sample. Returns the two statuses (IEKF, complementary).
pub fn apply(
    iekf: &mut GpcIekf,
    complementary: &mut GpcComplementary,
    event: &Event,
) -> (GpcStatus, GpcStatus) {
    match event {
        Event::Start(t, s) => (
            gpc_iekf_init(Some(iekf), Some(&gpc_iekf_default_config()), *t, Some(s)),
            gpc_complementary_init(
                Some(complementary),
                Some(&gpc_complementary_default_config()),
                *t,
                Some(s),
            ),
        ),
        Event::Imu(s) => (
            gpc_iekf_imu(Some(iekf), Some(s)),
            gpc_complementary_imu(Some(complementary), Some(s)),
        ),
        Event::Mocap(s) => (
            gpc_iekf_mocap(Some(iekf), Some(s)),
            gpc_complementary_mocap(Some(complementary), Some(s)),
        ),
    }
}

/// Both filters' outputs at `t`, as [`estimate_words`] orders them.
pub fn outputs_at(
    iekf: &GpcIekf,
    complementary: &GpcComplementary,
    t: f64,
) -> [u32; ESTIMATE_WORDS] {
    let (mut a, mut d, mut c) = (
        GpcState::default(),
        GpcIekfDiagnostics::default(),
        GpcState::default(),
    );
    gpc_iekf_estimate(Some(iekf), t, Some(&mut a));
    gpc_iekf_diagnostics(Some(iekf), Some(&mut d));
    gpc_complementary_estimate(Some(complementary), t, Some(&mut c));
    estimate_words(&a, &d, &c)
}
