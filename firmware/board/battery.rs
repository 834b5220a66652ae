//! The battery's voltage on an ADC pin through a divider
//! ([`super::wiring`]): one 12-bit conversion on request, logged by the
//! firmware (the next issue's return-to-charge uses it).

use super::wiring::{BatteryPin, BATTERY_CHANNEL, BATTERY_DIVIDER};
use stm32f4xx_hal::pac::{ADC1, ADC_COMMON};

/// The ADC's reference, mV (the Nucleo's VDDA).
const VREF_MV: u32 = 3300;
/// Polls of the end-of-conversion flag before giving up (a conversion
/// takes about 20 µs).
const EOC_POLLS: u32 = 10_000;

/// The battery monitor (ADC1 enabled in RCC by the caller).
pub struct Battery {
    adc: ADC1,
    _pin: BatteryPin,
}

impl Battery {
    /// Powers the ADC on, channel as the only regular conversion, the
    /// longest sampling time (the divider's source impedance is high).
    pub fn new(adc: ADC1, pin: BatteryPin) -> Self {
        // The ADC's clock at most 36 MHz: APB2's 84 MHz / 4 = 21 MHz.
        // SAFETY: the common register is only touched here.
        unsafe { (*ADC_COMMON::ptr()).ccr().modify(|_, w| w.adcpre().div4()) };
        adc.smpr2()
            .write(|w| unsafe { w.bits(0b111 << (3 * BATTERY_CHANNEL as u32)) });
        adc.sqr3()
            .write(|w| unsafe { w.bits(BATTERY_CHANNEL as u32) });
        adc.cr2().write(|w| w.adon().set_bit());
        Self { adc, _pin: pin }
    }

    /// The battery's voltage, mV (None when the conversion did not end).
    pub fn read_mv(&mut self) -> Option<u32> {
        self.adc.cr2().modify(|_, w| w.swstart().set_bit());
        if !(0..EOC_POLLS).any(|_| self.adc.sr().read().eoc().bit_is_set()) {
            return None;
        }
        let raw = self.adc.dr().read().bits() & 0x0FFF;
        Some(raw * VREF_MV * BATTERY_DIVIDER / 4095)
    }
}
