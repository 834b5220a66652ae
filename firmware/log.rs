//! The defmt global logger: frames go to an RTT up channel (a probe reads
//! it: `cargo run` through probe-rs).
//!
//! Why not `defmt-rtt` (or rtt-target): both `panic!` when the logger is
//! taken reentrantly, and rtt-target's `rtt_init!` when called twice,
//! which links panicking branches into an image that must have none
//! (issue 11 §6). Here a frame begun while another is open (only an NMI or
//! a fault handler can do that, since a frame holds a critical section) is
//! dropped and counted instead, and the RTT block ([`super::rtt`]) is
//! static.

#[cfg(not(any(feature = "pil", feature = "log-serial")))]
use super::rtt;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

#[defmt::global_logger]
struct Logger;

/// A frame is open.
static TAKEN: AtomicBool = AtomicBool::new(false);
/// The open frame is being dropped (begun reentrantly).
static DROPPING: AtomicBool = AtomicBool::new(false);
/// Frames dropped because the logger was taken.
static DROPPED: AtomicU32 = AtomicU32::new(0);
static mut CS_RESTORE: critical_section::RestoreState = critical_section::RestoreState::invalid();
static mut ENCODER: defmt::Encoder = defmt::Encoder::new();

/// Frames dropped so far (a nested log call).
pub fn dropped() -> u32 {
    DROPPED.load(Ordering::Relaxed)
}

unsafe impl defmt::Logger for Logger {
    fn acquire() {
        // SAFETY: paired with the release in `release`.
        let restore = unsafe { critical_section::acquire() };
        if TAKEN.load(Ordering::Relaxed) {
            // Nested: this frame is dropped; the outer one keeps its state.
            DROPPED.fetch_add(1, Ordering::Relaxed);
            DROPPING.store(true, Ordering::Relaxed);
            // SAFETY: the outer frame's restore state is kept; this one is
            // released at once (interrupts stay as the outer frame left them).
            unsafe { critical_section::release(restore) };
            return;
        }
        TAKEN.store(true, Ordering::Relaxed);
        // SAFETY: interrupts are off; only this frame touches the statics.
        unsafe {
            CS_RESTORE = restore;
            (*core::ptr::addr_of_mut!(ENCODER)).start_frame(put);
        }
    }

    unsafe fn flush() {}

    unsafe fn release() {
        if DROPPING.swap(false, Ordering::Relaxed) {
            return;
        }
        // SAFETY: interrupts are off since `acquire`.
        unsafe {
            (*core::ptr::addr_of_mut!(ENCODER)).end_frame(put);
            TAKEN.store(false, Ordering::Relaxed);
            critical_section::release(CS_RESTORE);
        }
    }

    unsafe fn write(bytes: &[u8]) {
        if DROPPING.load(Ordering::Relaxed) {
            return;
        }
        // SAFETY: interrupts are off since `acquire`.
        unsafe { (*core::ptr::addr_of_mut!(ENCODER)).write(bytes, put) };
    }
}

/// Writes encoded bytes to the RTT channel (what does not fit is lost:
/// the robot never waits for a probe); on the sim-link board, to its log
/// USART.
fn put(bytes: &[u8]) {
    #[cfg(not(any(feature = "pil", feature = "log-serial")))]
    rtt::write(bytes);
    #[cfg(all(not(feature = "pil"), feature = "log-serial"))]
    super::board::serial_log::write(bytes);
    #[cfg(feature = "pil")]
    super::board::simlink::log_write(bytes);
}
