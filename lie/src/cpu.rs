//! Which x86-64 instructions a build was compiled for, and whether the CPU it
//! runs on has them.
//!
//! The SIMD lanes (`wide`, through simba) choose their instructions when
//! they are compiled, not when they run: a build for the baseline x86-64
//! runs the four `f64` lanes as two SSE2 halves, a build with
//! `-C target-cpu=x86-64-v3` (or `native` on a CPU since 2013) as one AVX2
//! register, faster on the lane Monte Carlo and with results
//! identical to the bit (no fused multiply-add is formed implicitly). So the
//! choice is between *builds*: the workspace's own builds use the machine's
//! instruction set, a wheel carries a baseline and an x86-64-v3 build of
//! its extension and imports the one the CPU runs, and a program built for
//! more than the CPU has calls [`check`] first to stop with the missing
//! feature named instead of an illegal instruction.

/// The x86-64 microarchitecture levels that decide the lanes' speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// SSE2 only (any x86-64), or a CPU that is not x86-64.
    Baseline,
    /// AVX2 and FMA with the rest of x86-64-v3 (Haswell, 2013, and later).
    X86_64V3,
}

impl Level {
    /// The level's usual name: `"baseline"` or `"x86-64-v3"`.
    pub fn name(self) -> &'static str {
        match self {
            Level::Baseline => "baseline",
            Level::X86_64V3 => "x86-64-v3",
        }
    }
}

/// The level this build was compiled for (x86-64-v3 when every feature
/// of that level is enabled, as by `-C target-cpu=x86-64-v3` or `native`
/// on such a CPU).
pub const fn compiled() -> Level {
    if cfg!(all(
        target_arch = "x86_64",
        target_feature = "avx",
        target_feature = "avx2",
        target_feature = "fma",
        target_feature = "bmi1",
        target_feature = "bmi2",
        target_feature = "f16c",
        target_feature = "lzcnt",
        target_feature = "movbe"
    )) {
        Level::X86_64V3
    } else {
        Level::Baseline
    }
}

/// The x86-64 features whose absence would make a build's code fault (the
/// x86-64-v2, v3 and common AVX-512 ones), each with whether this build was
/// compiled to use it.
#[cfg(feature = "std")]
const FEATURE_COUNT: usize = 18;

/// Feature `i`'s bit in [`UnsupportedCpu`], from a table: a shift by a
/// variable count compiles to BMI2's `shlx` in a build that has it, which
/// is one of the features this code must not assume.
#[cfg(feature = "std")]
const BIT: [u32; FEATURE_COUNT] = {
    let mut b = [0; FEATURE_COUNT];
    let mut i = 0;
    while i < FEATURE_COUNT {
        b[i] = 1 << i;
        i += 1;
    }
    b
};

/// Where x86-64-v3's features (avx, avx2, fma, bmi1, bmi2, f16c, lzcnt,
/// movbe) sit in [`COMPILED_FEATURES`] (a test checks the names).
#[cfg(all(feature = "std", target_arch = "x86_64"))]
const V3: core::ops::Range<usize> = 5..13;

#[cfg(all(feature = "std", target_arch = "x86_64"))]
const COMPILED_FEATURES: [(&str, bool); FEATURE_COUNT] = [
    ("sse3", cfg!(target_feature = "sse3")),
    ("ssse3", cfg!(target_feature = "ssse3")),
    ("sse4.1", cfg!(target_feature = "sse4.1")),
    ("sse4.2", cfg!(target_feature = "sse4.2")),
    ("popcnt", cfg!(target_feature = "popcnt")),
    ("avx", cfg!(target_feature = "avx")),
    ("avx2", cfg!(target_feature = "avx2")),
    ("fma", cfg!(target_feature = "fma")),
    ("bmi1", cfg!(target_feature = "bmi1")),
    ("bmi2", cfg!(target_feature = "bmi2")),
    ("f16c", cfg!(target_feature = "f16c")),
    ("lzcnt", cfg!(target_feature = "lzcnt")),
    ("movbe", cfg!(target_feature = "movbe")),
    ("avx512f", cfg!(target_feature = "avx512f")),
    ("avx512cd", cfg!(target_feature = "avx512cd")),
    ("avx512bw", cfg!(target_feature = "avx512bw")),
    ("avx512dq", cfg!(target_feature = "avx512dq")),
    ("avx512vl", cfg!(target_feature = "avx512vl")),
];

/// Whether the running CPU (and the operating system, for the vector
/// registers' state) supports each of [`COMPILED_FEATURES`], read from
/// `cpuid` and `xgetbv`. Not `is_x86_feature_detected!`: that answers
/// `true` without asking the CPU for every feature the build was compiled
/// with, which is exactly the question here.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
#[allow(unused_unsafe)] // `__cpuid` is safe on newer toolchains
fn cpu_features() -> [bool; FEATURE_COUNT] {
    use core::arch::x86_64::{__cpuid, __cpuid_count};
    let bit = |r: u32, b: u32| r >> b & 1 == 1;
    // SAFETY: `cpuid` exists on every x86-64 CPU, and leaves above the
    // maximum reported one are not read.
    let (max, max_ext) = unsafe { (__cpuid(0).eax, __cpuid(0x8000_0000).eax) };
    let l1 = unsafe { __cpuid(1) };
    let l7 = if max >= 7 {
        unsafe { __cpuid_count(7, 0) }.ebx
    } else {
        0
    };
    let e1 = if max_ext >= 0x8000_0001 {
        unsafe { __cpuid(0x8000_0001) }.ecx
    } else {
        0
    };
    let xcr0 = if bit(l1.ecx, 27) {
        // SAFETY: OSXSAVE is set, so the OS enabled `xgetbv`.
        unsafe { xgetbv0() }
    } else {
        0
    };
    // AVX needs the OS to save the YMM state; AVX-512 the opmask and ZMM.
    let ymm = xcr0 & 0b110 == 0b110;
    let zmm = ymm && xcr0 & 0b1110_0000 == 0b1110_0000;
    [
        bit(l1.ecx, 0),
        bit(l1.ecx, 9),
        bit(l1.ecx, 19),
        bit(l1.ecx, 20),
        bit(l1.ecx, 23),
        ymm && bit(l1.ecx, 28),
        ymm && bit(l7, 5),
        ymm && bit(l1.ecx, 12),
        bit(l7, 3),
        bit(l7, 8),
        ymm && bit(l1.ecx, 29),
        bit(e1, 5),
        bit(l1.ecx, 22),
        zmm && bit(l7, 16),
        zmm && bit(l7, 28),
        zmm && bit(l7, 30),
        zmm && bit(l7, 17),
        zmm && bit(l7, 31),
    ]
}

/// `xgetbv` with `ecx = 0`: the state components the OS saves.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
#[target_feature(enable = "xsave")]
unsafe fn xgetbv0() -> u64 {
    // SAFETY: the caller checked OSXSAVE.
    unsafe { core::arch::x86_64::_xgetbv(0) }
}

/// Whether the running CPU has every feature of x86-64-v3 (read from
/// `cpuid` at run time, whatever the build; `false` on other
/// architectures).
#[cfg(feature = "std")]
pub fn cpu_has_x86_64_v3() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        cpu_features()[V3].iter().all(|&present| present)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The running CPU lacks instructions this build was compiled to use: a
/// set of features, one bit each (no allocation, so that little code runs
/// between learning it and reporting it).
#[cfg(feature = "std")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnsupportedCpu {
    missing: u32,
}

#[cfg(feature = "std")]
impl UnsupportedCpu {
    /// The missing features, by their `target_feature` names.
    pub fn missing(self) -> impl Iterator<Item = &'static str> {
        (0..FEATURE_COUNT).filter_map(move |i| self.name(i))
    }

    /// Feature `i`'s name if it is missing: a plain loop over this is all
    /// the reporting does (iterator adaptors over arrays get vectorised,
    /// with the very instructions that are missing).
    fn name(self, i: usize) -> Option<&'static str> {
        #[cfg(target_arch = "x86_64")]
        if self.missing & BIT[i] != 0 {
            return Some(COMPILED_FEATURES[i].0);
        }
        let _ = i;
        None
    }
}

#[cfg(feature = "std")]
impl core::fmt::Display for UnsupportedCpu {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("this build uses CPU features this processor lacks (")?;
        let mut first = true;
        let mut i = 0;
        while i < FEATURE_COUNT {
            if let Some(name) = self.name(i) {
                f.write_str(if first { "" } else { ", " })?;
                f.write_str(name)?;
                first = false;
            }
            i += 1;
        }
        f.write_str(
            "); it was built for another machine (for example with -C target-cpu=native): \
             rebuild it here, or with RUSTFLAGS=\"-C target-cpu=x86-64\" for any x86-64",
        )
    }
}

#[cfg(feature = "std")]
impl std::error::Error for UnsupportedCpu {}

/// `Ok` when the running CPU has every feature this build was compiled to
/// use; a program calls it first thing. Best effort: code compiled for
/// more than the CPU has may fault anywhere, this check's own included
/// (it allocates nothing and leaves formatting to the error path, which
/// keeps it to a few integer instructions). The guarantee for a build
/// that travels is the baseline build, which runs anywhere.
#[cfg(feature = "std")]
pub fn check() -> Result<(), UnsupportedCpu> {
    let mut missing = 0u32;
    #[cfg(target_arch = "x86_64")]
    {
        let present = cpu_features();
        let mut i = 0;
        while i < FEATURE_COUNT {
            if COMPILED_FEATURES[i].1 && !present[i] {
                missing |= BIT[i];
            }
            i += 1;
        }
    }
    if missing == 0 {
        Ok(())
    } else {
        Err(UnsupportedCpu { missing })
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    #[test]
    fn the_build_runs_on_the_machine_that_built_it() {
        // Tests run where they were compiled: whatever the flags, nothing
        // compiled in can be missing here, and a v3 build implies a v3 CPU.
        assert_eq!(check(), Ok(()));
        #[cfg(target_arch = "x86_64")]
        {
            // What cpuid reports agrees with std's detection on every
            // feature this build was *not* compiled with (for those it was,
            // std answers from the build flags, without asking).
            let v3: Vec<&str> = COMPILED_FEATURES[V3].iter().map(|f| f.0).collect();
            assert_eq!(
                v3,
                [
                    "avx", "avx2", "fma", "bmi1", "bmi2", "f16c", "lzcnt", "movbe"
                ]
            );
            let have = cpu_features();
            assert!(have[0] && have[1] && have[2] && have[3] && have[4] || !cpu_has_x86_64_v3());
            assert_eq!(have[6], std::is_x86_feature_detected!("avx2"));
            assert_eq!(have[7], std::is_x86_feature_detected!("fma"));
            assert_eq!(have[13], std::is_x86_feature_detected!("avx512f"));
            assert_eq!(have[11], std::is_x86_feature_detected!("lzcnt"));
        }
        if compiled() == Level::X86_64V3 {
            assert!(cpu_has_x86_64_v3());
        }
    }
}
