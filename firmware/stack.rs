//! The stack's high-water mark, and a guard below it.
//!
//! **High-water mark** (issue 11 §3: the stack measured, not guessed).
//! Everything between the guard and a little below the current stack
//! pointer is filled with a pattern at boot; the lowest word that no
//! longer holds it is as deep as the stack has been.
//!
//! **Guard.** The stack grows down toward the statics (`_stack_end`: on
//! the F411 cortex-m-rt's end of the statics, `__sheap`; at 16 × 16 m the
//! end of the CCM's statics, the stack being in the CCM above them:
//! `memory-f407.x`). An overflow would
//! silently overwrite them (it did: the sim-link image's receive queue, in
//! the studio at 261 s). [`guard`] makes the [`GUARD`] bytes below the
//! stack a no-access MPU region, so an overflow faults at once instead
//! (HardFault: the robot image's handler stops the motors; the watchdog
//! then resets the chip). A frame that skips more than the guard in one
//! step could still pass it: none in this firmware does (the largest
//! local buffer is 1 KiB, in the sim-link image, whose overflow the
//! high-water mark would show first).

const PAINT: u32 = 0xC0FF_EE11;
/// Left unpainted below the stack pointer at boot (the painting's own
/// frame).
const MARGIN: usize = 256;

extern "C" {
    static mut _stack_end: u32;
    static _stack_start: u32;
}

/// Bytes of the guard region (an MPU region: a power of two, aligned to
/// its size).
pub const GUARD: usize = 256;
/// Its RASR size field: 2^(SIZE+1) bytes.
const GUARD_SIZE_FIELD: u32 = 7;
const _: () = assert!(1 << (GUARD_SIZE_FIELD + 1) == GUARD);

/// Where the guard starts: the end of the statics, rounded up.
fn guard_base() -> usize {
    // Only the symbol's address is taken.
    (core::ptr::addr_of_mut!(_stack_end) as usize).next_multiple_of(GUARD)
}

/// The lowest byte of stack (just above the guard).
fn bottom() -> usize {
    guard_base() + GUARD
}

/// Turns the guard on: region 0 of the MPU, no access, never executed;
/// everything else keeps the default memory map. Call after [`paint`].
pub fn guard(mpu: &mut cortex_m::peripheral::MPU) {
    // SAFETY: region 0 covers only the guard bytes, below the stack and
    // above every static; the default map stays on for the rest.
    unsafe {
        mpu.ctrl.write(0);
        mpu.rnr.write(0);
        mpu.rbar.write(guard_base() as u32);
        // XN, AP = 000 (no access), SIZE, ENABLE.
        mpu.rasr.write((1 << 28) | (GUARD_SIZE_FIELD << 1) | 1);
        // PRIVDEFENA | ENABLE.
        mpu.ctrl.write((1 << 2) | 1);
    }
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}

/// Bytes of stack: from above the guard to the top of RAM.
pub fn size() -> usize {
    // Only the symbol's address is taken.
    let top = core::ptr::addr_of!(_stack_start) as usize;
    top.saturating_sub(bottom())
}

/// Paints the free stack (call first thing at boot).
pub fn paint() {
    let sp = cortex_m::register::msp::read() as usize;
    let mut p = bottom().next_multiple_of(4);
    while p + 4 <= sp.saturating_sub(MARGIN) {
        // SAFETY: between the statics and the live stack: memory nothing
        // uses yet.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
}

/// Bytes of stack used at most since [`paint`].
pub fn used() -> usize {
    let top = bottom() + size();
    let mut p = bottom().next_multiple_of(4);
    // SAFETY: reads of the painted region, word by word.
    while p + 4 <= top && unsafe { core::ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    top.saturating_sub(p)
}
