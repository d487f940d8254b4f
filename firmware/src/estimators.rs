//! The filters on the flight CPU: both filters over the stored stream
//! (`vectors/estimators-f32.bin`), the bits of their outputs after each
//! event, and what each kind of call cost.

use core::fmt::Write;
use core::hint::black_box;
use cortex_m::peripheral::SYST;
use geopid_control::vectors::{EVENT_BYTES, Event, apply, outputs_at};
use geopid_control::{
    GpcComplementary, GpcIekf, GpcImuSample, GpcMocapSample, GpcStatus, gpc_complementary_imu,
    gpc_complementary_mocap, gpc_iekf_imu, gpc_iekf_mocap,
};

use crate::{Line, Stats, elapsed, emit, high_water, paint};

static STREAM: &[u8] = include_bytes!("../vectors/estimators-f32.bin");

/// How far below the caller the stack is painted: well past what the
/// invariant EKF's updates need (a correction copies its 900 B covariance).
const PAINT_BYTES: usize = 16 * 1024;

/// The filters' blocks: statics, as a flight image would hold them.
static mut IEKF: GpcIekf = GpcIekf {
    opaque: [0; geopid_control::GPC_IEKF_WORDS],
};
static mut COMPLEMENTARY: GpcComplementary = GpcComplementary {
    opaque: [0; geopid_control::GPC_COMPLEMENTARY_WORDS],
};

/// A wrapper that times one C call: its own symbol, so the exact count can
/// trace the call from its entry back to here.
macro_rules! timed {
    ($name:ident, $filter:ty, $sample:ty, $call:ident) => {
        #[inline(never)]
        fn $name(f: &mut $filter, s: &$sample) -> (GpcStatus, u32) {
            let (f, s) = (black_box(f), black_box(s));
            // Through a pointer the optimiser cannot see into, so that the
            // call stays a call.
            let call = black_box($call as extern "C" fn(_, _) -> GpcStatus);
            let start = SYST::get_current();
            let status = call(Some(f), Some(s));
            (black_box(status), elapsed(start))
        }
    };
}

timed!(iekf_imu, GpcIekf, GpcImuSample, gpc_iekf_imu);
timed!(iekf_mocap, GpcIekf, GpcMocapSample, gpc_iekf_mocap);
timed!(
    complementary_imu,
    GpcComplementary,
    GpcImuSample,
    gpc_complementary_imu
);
timed!(
    complementary_mocap,
    GpcComplementary,
    GpcMocapSample,
    gpc_complementary_mocap
);

/// Runs the stream; prints an `E` line per event, the costs, the stack's
/// high-water mark and `F <events>`. `None` if an event failed.
pub fn run(line: &mut Line) -> Option<u32> {
    // SAFETY: the image is single-threaded and these are its only
    // references to the two statics.
    let (iekf, comp) = unsafe {
        (
            &mut *core::ptr::addr_of_mut!(IEKF),
            &mut *core::ptr::addr_of_mut!(COMPLEMENTARY),
        )
    };
    let mut stats = [Stats::new(), Stats::new(), Stats::new(), Stats::new()];
    let (mut stack, mut events, mut ok) = (0usize, 0u32, true);
    for chunk in STREAM.chunks_exact(EVENT_BYTES) {
        let event = Event::decode(chunk)?;
        let sp = paint(PAINT_BYTES);
        let (si, sc) = match &event {
            Event::Start(..) => apply(iekf, comp, &event),
            Event::Imu(s) => {
                let ((si, ti), (sc, tc)) = (iekf_imu(iekf, s), complementary_imu(comp, s));
                stats[0].add(ti);
                stats[2].add(tc);
                (si, sc)
            }
            Event::Mocap(s) => {
                let ((si, ti), (sc, tc)) = (iekf_mocap(iekf, s), complementary_mocap(comp, s));
                stats[1].add(ti);
                stats[3].add(tc);
                (si, sc)
            }
        };
        stack = stack.max(sp - high_water(sp, PAINT_BYTES));
        ok &= si == GpcStatus::Ok && sc == GpcStatus::Ok;
        let _ = write!(line, "E {events} {} {}", si as i32, sc as i32);
        for w in outputs_at(iekf, comp, event.time()) {
            let _ = write!(line, " {w:08x}");
        }
        let _ = writeln!(line);
        emit(line);
        events += 1;
    }
    let names = [
        "iekf-imu",
        "iekf-mocap",
        "complementary-imu",
        "complementary-mocap",
    ];
    for (name, s) in names.iter().zip(&stats) {
        let _ = writeln!(line, "C {name} {} {} {} {}", s.min, s.max, s.sum, s.n);
        emit(line);
    }
    let _ = writeln!(line, "S filters {stack}\nF {events}");
    emit(line);
    (ok && events > 0).then_some(events)
}
