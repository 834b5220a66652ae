//! A SEGGER RTT control block with one up channel, for the defmt logger.
//!
//! The probe (probe-rs) finds `_SEGGER_RTT` in RAM, reads the up buffer and
//! advances its read offset; the firmware only writes. Static, so there is
//! nothing to initialise twice, and free of panicking branches (see
//! [`super::log`]). Non-blocking: bytes that do not fit are dropped.

use core::cell::UnsafeCell;
use core::sync::atomic::{AtomicU32, Ordering};

/// Bytes of the up buffer.
const SIZE: usize = 1024;
/// Channel flags: non-blocking, bytes that do not fit are dropped (RTT's
/// "no block, trim" mode).
const MODE_NO_BLOCK_TRIM: u32 = 1;

/// One RTT up channel, laid out as the probe expects.
#[repr(C)]
struct Channel {
    name: *const u8,
    buffer: *mut u8,
    size: u32,
    /// Written by the firmware.
    write: AtomicU32,
    /// Written by the probe.
    read: AtomicU32,
    flags: u32,
}

/// The control block: "SEGGER RTT", one up channel, no down channel.
#[repr(C)]
struct Header {
    id: [u8; 16],
    max_up: u32,
    max_down: u32,
    up: Channel,
}

struct Buffer(UnsafeCell<[u8; SIZE]>);
// SAFETY: written only by `write`, which the logger calls inside a
// critical section; the probe reads it from outside the core.
unsafe impl Sync for Buffer {}
// SAFETY: the pointers point at statics; the offsets are atomics.
unsafe impl Sync for Header {}

static BUFFER: Buffer = Buffer(UnsafeCell::new([0; SIZE]));
static NAME: &[u8] = b"defmt\0";

#[no_mangle]
#[used]
static _SEGGER_RTT: Header = Header {
    id: *b"SEGGER RTT\0\0\0\0\0\0",
    max_up: 1,
    max_down: 0,
    up: Channel {
        name: NAME.as_ptr(),
        buffer: BUFFER.0.get() as *mut u8,
        size: SIZE as u32,
        write: AtomicU32::new(0),
        read: AtomicU32::new(0),
        flags: MODE_NO_BLOCK_TRIM,
    },
};

/// Appends `bytes` to the up buffer, as many as fit. Called with
/// interrupts off (by the logger), so there is one writer.
pub fn write(mut bytes: &[u8]) {
    let ch = &_SEGGER_RTT.up;
    while !bytes.is_empty() {
        let w = ch.write.load(Ordering::Acquire) as usize % SIZE;
        let r = ch.read.load(Ordering::Acquire) as usize % SIZE;
        // Contiguous room after `w`, one byte kept free so that a full
        // buffer is not mistaken for an empty one.
        let room = if r > w {
            r - w - 1
        } else if r == 0 {
            SIZE - w - 1
        } else {
            SIZE - w
        };
        let n = room.min(bytes.len());
        if n == 0 {
            return;
        }
        let (now, rest) = bytes.split_at(n);
        // SAFETY: `w + n <= SIZE` by the room computed above; the buffer is
        // a static only this function writes.
        unsafe {
            let dst = (BUFFER.0.get() as *mut u8).add(w);
            core::ptr::copy_nonoverlapping(now.as_ptr(), dst, n);
        }
        ch.write.store(((w + n) % SIZE) as u32, Ordering::Release);
        bytes = rest;
    }
}
