//! The wheel encoders: two timers in quadrature encoder mode (the HAL's
//! `Qei`: both edges of both channels, a hardware counter that wraps),
//! read as the 16-bit counts the core's [`QuadratureEncoder`] expects.
//! A 32-bit timer's low 16 bits wrap exactly as a 16-bit counter does.

use super::wiring::{
    LeftEncoderPins, LeftEncoderTim, RightEncoderPins, RightEncoderTim, RIGHT_ENCODER_MIRRORED,
};
use robovac::robot::hal::QuadratureEncoder;
use stm32f4xx_hal::pac::RCC;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::qei::Qei;

/// The left wheel's encoder.
pub struct LeftEncoder(Qei<LeftEncoderTim>);
/// The right wheel's encoder.
pub struct RightEncoder(Qei<RightEncoderTim>);

impl LeftEncoder {
    /// Puts the timer in encoder mode on its pins.
    pub fn new(tim: LeftEncoderTim, pins: LeftEncoderPins, rcc: &mut RCC) -> Self {
        Self(Qei::new(tim, pins, rcc))
    }
}

impl RightEncoder {
    /// Puts the timer in encoder mode on its pins.
    pub fn new(tim: RightEncoderTim, pins: RightEncoderPins, rcc: &mut RCC) -> Self {
        Self(Qei::new(tim, pins, rcc))
    }
}

impl QuadratureEncoder for LeftEncoder {
    // The cast is needed when the wiring puts this wheel on a 32-bit timer.
    #[allow(clippy::unnecessary_cast)]
    fn count(&mut self) -> u16 {
        self.0.count() as u16
    }
}

impl QuadratureEncoder for RightEncoder {
    fn count(&mut self) -> u16 {
        let c = self.0.count() as u16;
        if RIGHT_ENCODER_MIRRORED {
            c.wrapping_neg()
        } else {
            c
        }
    }
}
