//! The instruction meter of the emulated runs (issue 11 §2, issue 13):
//! SysTick, free-running from the core clock, counts ticks, and a ratio
//! calibrated against a loop of known length turns ticks into instructions
//! (QEMU clocks SysTick from its model of the CPU clock, not one tick per
//! instruction; with `-icount shift=0` the ratio is fixed, so counts are
//! deterministic).
//!
//! Written once for the sim-link image ([`super::simlink`]) and the
//! emulated examples (`examples/emu_common`, which include this file with
//! `#[path]`). The user's `SysTick` exception handler calls [`on_wrap`].

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::SYST;

/// SysTick wraps since boot.
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// Counts one SysTick wrap: the whole body of the `SysTick` handler.
#[inline(always)]
pub fn on_wrap() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// SysTick ticks since it started (64 bits from the 24-bit counter and its
/// wraps).
pub fn ticks() -> u64 {
    loop {
        let w1 = WRAPS.load(Ordering::Acquire);
        let v = SYST::get_current();
        let w2 = WRAPS.load(Ordering::Acquire);
        if w1 == w2 {
            return ((w1 as u64) << 24) + (0x00FF_FFFF - v as u64);
        }
    }
}

/// `n` iterations of `subs; bne`: exactly 2n instructions.
pub fn known_loop(n: u32) {
    if n == 0 {
        return;
    }
    // SAFETY: a register-only countdown loop; touches no memory.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, {n}, #1",
            "bne 2b",
            n = inout(reg) n => _,
            options(nomem, nostack),
        );
    }
}

/// Iterations of [`known_loop`] the calibration runs.
const CALIBRATION_LOOPS: u32 = 2_000_000;
/// Instructions the calibration runs.
pub const CALIBRATION_INSTRUCTIONS: u64 = 2 * CALIBRATION_LOOPS as u64;

/// Counts instructions: SysTick ticks scaled by the calibrated ratio.
pub struct Meter {
    insn_per_ktick: u64,
    /// The ticks the calibration loop took.
    calibration_ticks: u64,
}

impl Meter {
    /// Calibrates against [`CALIBRATION_LOOPS`] iterations of the
    /// two-instruction [`known_loop`]. SysTick must be running.
    pub fn calibrate() -> Self {
        let t0 = ticks();
        known_loop(CALIBRATION_LOOPS);
        let t = ticks().saturating_sub(t0).max(1);
        Self {
            insn_per_ktick: CALIBRATION_INSTRUCTIONS * 1000 / t,
            calibration_ticks: t,
        }
    }

    /// The SysTick ticks the calibration's [`CALIBRATION_INSTRUCTIONS`]
    /// took.
    pub fn calibration_ticks(&self) -> u64 {
        self.calibration_ticks
    }

    /// Instructions per 1000 SysTick ticks.
    pub fn ratio(&self) -> u64 {
        self.insn_per_ktick
    }

    /// Runs `f`; returns its result and the instructions it took.
    pub fn measure<R>(&self, f: impl FnOnce() -> R) -> (R, u64) {
        let t0 = ticks();
        let r = f();
        let t = ticks().saturating_sub(t0);
        (r, t * self.insn_per_ktick / 1000)
    }
}
