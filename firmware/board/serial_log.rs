//! defmt over a UART, for runs with no probe (feature `log-serial`): the
//! logger's bytes go into a ring that the UART's transmit interrupt
//! drains, so a log line never stalls the control task (bytes that do not
//! fit are dropped and counted). Decode on the PC with
//! `defmt-print -e ELF serial --path PORT --baud 460800`.

use super::wiring::{self, LOG_BAUD, LOG_PCLK_HZ};
use core::sync::atomic::{AtomicU32, Ordering};
use heapless::Deque;

/// Bytes waiting to be sent.
const RING: usize = 1024;
/// USART2's baud rate divider (oversampling by 16: BRR = f / baud).
const LOG_BRR: u16 = ((LOG_PCLK_HZ + LOG_BAUD / 2) / LOG_BAUD) as u16;
const _: () = assert!(LOG_BRR >= 16);
static mut OUT: Deque<u8, RING> = Deque::new();
/// Bytes dropped because the ring was full.
static DROPPED: AtomicU32 = AtomicU32::new(0);

/// Starts the transmitter (USART2 enabled in RCC by the caller).
pub fn start(_tx: wiring::LogTxPin) {
    let u = wiring::log_usart();
    u.brr().write(|w| unsafe { w.bits(LOG_BRR) });
    u.cr1().write(|w| w.ue().set_bit().te().set_bit());
}

/// Queues bytes (called by the logger inside its critical section).
pub fn write(bytes: &[u8]) {
    // SAFETY: the logger holds a critical section; the interrupt below
    // takes one too.
    let q = unsafe { &mut *core::ptr::addr_of_mut!(OUT) };
    for &b in bytes {
        if q.push_back(b).is_err() {
            DROPPED.fetch_add(1, Ordering::Relaxed);
        }
    }
    wiring::log_usart().cr1().modify(|_, w| w.txeie().set_bit());
}

/// The UART's interrupt: sends the next byte, or stops when none is left.
pub fn on_interrupt() {
    critical_section::with(|_| {
        // SAFETY: inside a critical section, as `write` is.
        let q = unsafe { &mut *core::ptr::addr_of_mut!(OUT) };
        let u = wiring::log_usart();
        if u.sr().read().txe().bit_is_clear() {
            return;
        }
        match q.pop_front() {
            Some(b) => {
                u.dr().write(|w| unsafe { w.bits(u16::from(b)) });
            }
            None => {
                u.cr1().modify(|_, w| w.txeie().clear_bit());
            }
        }
    });
}

/// Bytes dropped so far.
pub fn dropped() -> u32 {
    DROPPED.load(Ordering::Relaxed)
}
