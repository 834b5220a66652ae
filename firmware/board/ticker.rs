//! The control clock: a 32-bit timer counting microseconds, extended to
//! 64 bits in software, with a compare interrupt every control period
//! (the control task's trigger). The time the core is given comes from
//! here ([`Clock`]); nothing in the core reads a clock itself.

use super::wiring::{self, TICK_TIMER_HZ};
use core::sync::atomic::{AtomicU32, Ordering};
use robovac::robot::hal::Clock;

/// The control period, µs (100 Hz).
pub const PERIOD_US: u32 = 10_000;
/// Counter wraps (every 2^32 µs, 71.6 minutes).
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// The clock and the control period's trigger (TIM5 enabled in RCC by
/// the caller).
pub struct Ticker;

impl Ticker {
    /// Starts the counter at 1 MHz and the first compare one period on.
    pub fn start() -> Self {
        let t = wiring::tick_timer();
        t.psc()
            .write(|w| unsafe { w.psc().bits((TICK_TIMER_HZ / 1_000_000 - 1) as u16) });
        t.arr().write(|w| unsafe { w.bits(u32::MAX) });
        t.ccr(0).write(|w| unsafe { w.bits(PERIOD_US) });
        t.egr().write(|w| w.ug().set_bit());
        t.sr().write(|w| unsafe { w.bits(0) });
        t.dier().write(|w| w.cc1ie().set_bit().uie().set_bit());
        t.cr1().write(|w| w.cen().set_bit());
        Self
    }

    /// The timer's interrupt: counts a wrap; true when a control period
    /// is due (the next compare is then set one period on).
    pub fn on_interrupt(&mut self) -> bool {
        let t = wiring::tick_timer();
        let sr = t.sr().read();
        if sr.uif().bit_is_set() {
            t.sr().write(|w| unsafe { w.bits(!1) });
            WRAPS.fetch_add(1, Ordering::Release);
        }
        if sr.cc1if().bit_is_set() {
            t.sr().write(|w| unsafe { w.bits(!(1 << 1)) });
            let next = t.ccr(0).read().bits().wrapping_add(PERIOD_US);
            t.ccr(0).write(|w| unsafe { w.bits(next) });
            return true;
        }
        false
    }
}

/// Microseconds since boot (safe from any priority: the wrap count is
/// read on both sides of the counter, and a wrap still pending counted).
pub fn now_us() -> u64 {
    let t = wiring::tick_timer();
    loop {
        let w1 = WRAPS.load(Ordering::Acquire);
        let cnt = t.cnt().read().bits();
        let pending = t.sr().read().uif().bit_is_set();
        let w2 = WRAPS.load(Ordering::Acquire);
        if w1 == w2 {
            // A wrap not yet counted by the interrupt: the low count is
            // past it when small.
            let extra = u64::from(pending && cnt < u32::MAX / 2);
            return ((u64::from(w1) + extra) << 32) | u64::from(cnt);
        }
    }
}

impl Clock for Ticker {
    fn now_us(&mut self) -> u64 {
        now_us()
    }
}
