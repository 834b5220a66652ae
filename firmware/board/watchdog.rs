//! The independent watchdog (IWDG, on its own 32 kHz oscillator): reset
//! unless fed within [`TIMEOUT_MS`]. Only the control task feeds it
//! (firmware/app.rs), so a hung control task resets the chip; a hung
//! planner stops the motors through control (which then keeps feeding:
//! control alive and the motors safe); a step that holds the executive
//! past the reflex's `HUNG_US` (6 s) stops the feeding, so the chip resets.

use stm32f4xx_hal::pac::IWDG;

/// The timeout, ms. Control runs every 10 ms whatever the planner does
/// (firmware/app.rs: the executive is only ever tried), so this need only
/// cover control's own jitter with a wide margin; short, because a hung
/// control task leaves the motors at their last duty until the reset.
pub const TIMEOUT_MS: u32 = 500;
/// The LSI's nominal frequency, Hz.
const LSI_HZ: u32 = 32_000;
/// Prescaler /32 (PR = 3): 1 kHz, 1 ms per count.
const PR_DIV32: u8 = 3;
const RELOAD: u32 = TIMEOUT_MS * LSI_HZ / 32 / 1000;
const _: () = assert!(RELOAD > 0 && RELOAD <= 0x0FFF);

/// The running watchdog.
pub struct Watchdog(IWDG);

impl Watchdog {
    /// Starts it (it cannot be stopped again until reset).
    pub fn start(iwdg: IWDG) -> Self {
        iwdg.kr().write(|w| unsafe { w.key().bits(0xCCCC) });
        iwdg.kr().write(|w| unsafe { w.key().bits(0x5555) });
        iwdg.pr().write(|w| unsafe { w.pr().bits(PR_DIV32) });
        iwdg.rlr().write(|w| unsafe { w.rl().bits(RELOAD as u16) });
        // The new values take effect when the registers' update flags
        // clear (a few LSI periods); not waited for: feeding meanwhile is
        // harmless.
        iwdg.kr().write(|w| unsafe { w.key().bits(0xAAAA) });
        Self(iwdg)
    }

    /// Sets the timeout to `ms` (at most 4,095 ms) and reloads: stretched
    /// while a flash sector erases (the CPU stalls up to 2 s), then set
    /// back to [`TIMEOUT_MS`].
    pub fn set_timeout_ms(&mut self, ms: u32) {
        let reload = (ms * (LSI_HZ / 32) / 1000).clamp(1, 0x0FFF);
        self.0.kr().write(|w| unsafe { w.key().bits(0x5555) });
        self.0.pr().write(|w| unsafe { w.pr().bits(PR_DIV32) });
        self.0
            .rlr()
            .write(|w| unsafe { w.rl().bits(reload as u16) });
        self.0.kr().write(|w| unsafe { w.key().bits(0xAAAA) });
    }

    /// Reloads the counter.
    pub fn feed(&mut self) {
        self.0.kr().write(|w| unsafe { w.key().bits(0xAAAA) });
    }
}
