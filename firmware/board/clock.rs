//! The clock tree, set by register: 84 MHz from the internal 16 MHz
//! oscillator, so no board needs a crystal.
//!
//! Why not `stm32f4xx_hal::rcc::Rcc::freeze`: it computes the PLL
//! dividers at run time and checks them with `assert!`/`unwrap`, which
//! links 17 panicking branches into the image (issue 11 §6). The dividers
//! here are constants, checked at compile time, and every wait is bounded:
//! a PLL that never locks leaves the chip on the 16 MHz oscillator (slower,
//! still safe) instead of hanging before the watchdog is set.

use stm32f4xx_hal::pac::{FLASH, RCC};

/// The internal oscillator, Hz.
pub const HSI_HZ: u32 = 16_000_000;
/// PLL input divider: 16 MHz / 16 = 1 MHz into the VCO (1..=2 MHz allowed).
const PLLM: u8 = 16;
/// VCO multiplier: 336 MHz (100..=432 MHz allowed).
const PLLN: u16 = 336;
/// System clock divider: 336 / 4 = 84 MHz, the F411's rating at scale 2.
const PLLP_DIV: u32 = 4;
/// 48 MHz domain divider: 336 / 7 = 48 MHz (USB, SDIO).
const PLLQ: u8 = 7;
/// The system clock when the PLL runs, Hz.
pub const SYSCLK_HZ: u32 = HSI_HZ / PLLM as u32 * PLLN as u32 / PLLP_DIV;
/// APB1 runs at half the system clock (42 MHz; its limit is 50 MHz).
pub const PCLK1_HZ: u32 = SYSCLK_HZ / 2;
/// APB2 runs at the system clock (84 MHz; its limit is 100 MHz).
pub const PCLK2_HZ: u32 = SYSCLK_HZ;

const _: () = assert!(HSI_HZ / PLLM as u32 >= 1_000_000 && HSI_HZ / PLLM as u32 <= 2_000_000);
const _: () = assert!(SYSCLK_HZ == 84_000_000);
const _: () = assert!(HSI_HZ / PLLM as u32 * PLLN as u32 / PLLQ as u32 == 48_000_000);
const _: () = assert!(PCLK1_HZ <= 50_000_000 && PCLK2_HZ <= 100_000_000);

/// Polls of a ready flag before giving up (the PLL locks in about 100 µs,
/// a few hundred polls at 16 MHz).
const READY_POLLS: u32 = 100_000;

/// Why the clocks stayed on the internal oscillator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
pub enum ClockError {
    /// The PLL did not lock.
    PllNoLock,
    /// The switch to the PLL was not confirmed.
    NoSwitch,
}

/// Sets the clocks; returns the system clock in Hz (84 MHz, or the 16 MHz
/// oscillator with the reason when the PLL could not be used).
pub fn setup(rcc: &RCC, flash: &FLASH) -> (u32, Option<ClockError>) {
    rcc.pllcfgr().write(|w| unsafe {
        w.pllsrc().hsi();
        w.pllm().bits(PLLM);
        w.plln().bits(PLLN);
        w.pllp().div4();
        w.pllq().bits(PLLQ)
    });
    rcc.cr().modify(|_, w| w.pllon().set_bit());
    if !wait(|| rcc.cr().read().pllrdy().bit_is_set()) {
        rcc.cr().modify(|_, w| w.pllon().clear_bit());
        return (HSI_HZ, Some(ClockError::PllNoLock));
    }
    // Two wait states for 64..=90 MHz at 2.7..=3.6 V (RM0383 table 6), with
    // the caches and prefetch on; set before the clock rises.
    flash.acr().modify(|_, w| {
        w.latency().ws2();
        w.icen().set_bit();
        w.dcen().set_bit();
        w.prften().set_bit()
    });
    rcc.cfgr().modify(|_, w| {
        w.hpre().div1();
        w.ppre1().div2();
        w.ppre2().div1();
        w.sw().pll()
    });
    if !wait(|| rcc.cfgr().read().sws().is_pll()) {
        return (HSI_HZ, Some(ClockError::NoSwitch));
    }
    (SYSCLK_HZ, None)
}

/// True when `ready` held within [`READY_POLLS`] polls.
fn wait(mut ready: impl FnMut() -> bool) -> bool {
    (0..READY_POLLS).any(|_| ready())
}
