//! The record format of the firmware test: a stored sequence of inputs
//! (taken from a host run of paper-flip in `f32`) that a Cortex-M image
//! runs both laws on, and the words it prints of what they computed. The
//! image and the host read and write records through these functions, so
//! the two sides cannot disagree on the layout. Not part of the C ABI.

use crate::{
    GpcAttitudeOutput, GpcAttitudeReference, GpcIntegrals, GpcPositionOutput, GpcPositionReference,
    GpcState,
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
