//! A Cortex-M4F test image for the C ABI: runs the position and the
//! attitude update on every stored paper-flip record, and both filters on
//! a stored IMU and motion-capture stream; prints the bits of what they
//! computed over semihosting (one line per record or event), then what
//! they cost: the instruction count of each call from SysTick, the stack's
//! high-water mark, and exits with a status.
//!
//! Run under QEMU (see `scripts/flight.sh`):
//! `qemu-system-arm -machine netduinoplus2 -cpu cortex-m4 -nographic
//!  -semihosting-config enable=on,target=native -icount shift=0 -kernel <elf>`
//!
//! Output lines:
//! - `R <index> <position status> <attitude status> <53 hex words>`;
//! - `C <what> <min> <max> <sum> <count>`: SysTick ticks of a call, and
//!   `C calibration` the ticks of 1 000 `nop`s (SysTick runs at the core
//!   clock; under `-icount` its ticks per instruction are what this
//!   measures);
//! - `S stack <bytes>`: the deepest stack either update reached, measured
//!   from the caller's stack pointer;
//! - `D <records>` when the laws are done;
//! - `E <index> <iekf status> <complementary status> <51 hex words>` per
//!   stream event (see `estimators`), then their `C` lines, `S filters
//!   <bytes>` and `F <events>`.

#![no_std]
#![no_main]

use core::fmt::Write;
use core::hint::black_box;
use cortex_m::peripheral::{SYST, syst::SystClkSource};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};
use geopid_control::vectors::{RECORD_BYTES, Record, output_words};
use geopid_control::{
    GpcAttitudeGains, GpcAttitudeOutput, GpcPositionGains, GpcPositionOutput, GpcStatus,
    GpcVehicle, gpc_attitude_update, gpc_paper_attitude_gains, gpc_paper_position_gains,
    gpc_paper_vehicle, gpc_position_update,
};

static VECTORS: &[u8] = include_bytes!("../vectors/paper-flip-f32.bin");

mod estimators;

/// How far below the caller's stack pointer the stack is painted for the
/// laws: twice their 4 KB budget, so an overrun still shows in the count.
const PAINT_BYTES: usize = 8 * 1024;
const PAINT: u32 = 0xC0FF_EE11;

/// A fixed line buffer: one semihosting write per line.
struct Line {
    buf: [u8; 640],
    len: usize,
}

impl Write for Line {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let end = self.len + s.len();
        let dst = self.buf.get_mut(self.len..end).ok_or(core::fmt::Error)?;
        dst.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

/// Ticks since `start` on the down-counting 24-bit SysTick.
fn elapsed(start: u32) -> u32 {
    start.wrapping_sub(SYST::get_current()) & 0x00FF_FFFF
}

struct Stats {
    min: u32,
    max: u32,
    sum: u64,
    n: u32,
}

impl Stats {
    const fn new() -> Self {
        Stats {
            min: u32::MAX,
            max: 0,
            sum: 0,
            n: 0,
        }
    }
    fn add(&mut self, x: u32) {
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.sum += u64::from(x);
        self.n += 1;
    }
}

struct Setup {
    vehicle: GpcVehicle,
    position: GpcPositionGains,
    attitude: GpcAttitudeGains,
}

#[inline(never)]
fn position(s: &Setup, r: &Record, out: &mut GpcPositionOutput) -> (GpcStatus, u32) {
    let (s, r) = (black_box(s), black_box(r));
    let start = SYST::get_current();
    let status = gpc_position_update(
        Some(&s.vehicle),
        Some(&s.position),
        Some(&s.attitude),
        Some(&r.state),
        Some(&r.integrals),
        Some(&r.position),
        Some(out),
    );
    (black_box(status), elapsed(start))
}

#[inline(never)]
fn attitude(s: &Setup, r: &Record, out: &mut GpcAttitudeOutput) -> (GpcStatus, u32) {
    let (s, r) = (black_box(s), black_box(r));
    let start = SYST::get_current();
    let status = gpc_attitude_update(
        Some(&s.vehicle),
        Some(&s.attitude),
        Some(&r.state),
        Some(&r.integrals),
        Some(&r.attitude),
        Some(out),
    );
    (black_box(status), elapsed(start))
}

/// The ticks of a block of 1 000 `nop`s: SysTick's ticks per instruction
/// under QEMU's `-icount`.
#[inline(never)]
fn calibration() -> u32 {
    let start = SYST::get_current();
    // SAFETY: `nop`s touch no register or memory.
    unsafe { core::arch::asm!(".rept 1000", "nop", ".endr", options(nomem, nostack)) };
    elapsed(start)
}

/// Fills `depth` bytes of the stack below the caller with a pattern
/// (leaving this function's own frame alone) and returns the caller's
/// stack pointer.
#[inline(never)]
fn paint(depth: usize) -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let low = sp - depth;
    for a in (low..sp - 64).step_by(4) {
        // SAFETY: below this frame's stack pointer, inside RAM (the image
        // uses a few KB of the 128 KB), and nothing lives there.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
    }
    sp
}

/// The lowest address of `depth` painted bytes that was overwritten since
/// [`paint`].
fn high_water(sp: usize, depth: usize) -> usize {
    let low = sp - depth;
    (low..sp - 64)
        .step_by(4)
        // SAFETY: the same painted words as above.
        .find(|&a| unsafe { core::ptr::read_volatile(a as *const u32) } != PAINT)
        .unwrap_or(sp)
}

fn emit(line: &mut Line) {
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_all(&line.buf[..line.len]);
    }
    line.len = 0;
}

#[entry]
fn main() -> ! {
    let mut syst = cortex_m::Peripherals::take().map(|p| p.SYST);
    if let Some(syst) = syst.as_mut() {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00FF_FFFF);
        syst.clear_current();
        syst.enable_counter();
    }
    let setup = Setup {
        vehicle: gpc_paper_vehicle(),
        position: gpc_paper_position_gains(),
        attitude: gpc_paper_attitude_gains(),
    };
    let mut line = Line {
        buf: [0; 640],
        len: 0,
    };
    let (mut pos_ticks, mut att_ticks, mut cal) = (Stats::new(), Stats::new(), Stats::new());
    let (mut stack, mut records, mut ok) = (0usize, 0u32, true);
    for chunk in VECTORS.chunks_exact(RECORD_BYTES) {
        let Some(record) = Record::decode(chunk) else {
            break;
        };
        let (mut p, mut a) = (GpcPositionOutput::default(), GpcAttitudeOutput::default());
        let sp = paint(PAINT_BYTES);
        let (ps, pt) = position(&setup, &record, &mut p);
        let (as_, at) = attitude(&setup, &record, &mut a);
        stack = stack.max(sp - high_water(sp, PAINT_BYTES));
        pos_ticks.add(pt);
        att_ticks.add(at);
        cal.add(calibration());
        ok &= ps == GpcStatus::Ok && as_ == GpcStatus::Ok;
        let _ = write!(line, "R {records} {} {}", ps as i32, as_ as i32);
        for w in output_words(&p, &a) {
            let _ = write!(line, " {w:08x}");
        }
        let _ = writeln!(line);
        emit(&mut line);
        records += 1;
    }
    for (name, s) in [
        ("position", &pos_ticks),
        ("attitude", &att_ticks),
        ("calibration", &cal),
    ] {
        let _ = writeln!(line, "C {name} {} {} {} {}", s.min, s.max, s.sum, s.n);
        emit(&mut line);
    }
    let _ = writeln!(line, "S stack {stack}\nD {records}");
    emit(&mut line);
    let events = estimators::run(&mut line);
    ok &= events.is_some();
    debug::exit(if ok && records > 0 {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::bkpt();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    if let Ok(mut out) = hio::hstderr() {
        let _ = writeln!(out, "panic: {info}");
    }
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}
