//! The stack's high-water mark: painted at boot, measured at the end
//! (issue 11 §3: the stack measured, not guessed).
//!
//! Everything between the end of the statics (`__sheap`, cortex-m-rt's
//! heap start: this firmware has no heap) and a little below the current
//! stack pointer is filled with a pattern; the lowest word that no longer
//! holds it is as deep as the stack has been.

const PAINT: u32 = 0xC0FF_EE11;
/// Left unpainted below the stack pointer at boot (the painting's own
/// frame).
const MARGIN: usize = 256;

extern "C" {
    static mut __sheap: u32;
    static _stack_start: u32;
}

fn bottom() -> usize {
    // Only the symbol's address is taken.
    core::ptr::addr_of_mut!(__sheap) as usize
}

/// Bytes of stack: from the end of the statics to the top of RAM.
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
