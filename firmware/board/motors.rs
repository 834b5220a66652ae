//! The wheel motors: a TB6612FNG-class dual H-bridge, PWM on two channels
//! of one timer (20 kHz, above hearing) and two direction pins per motor
//! ([`super::wiring`]). Registers are written directly: the HAL's PWM
//! needs its own frozen clocks, which this firmware does not use (see
//! [`super::clock`]).
//!
//! TB6612 truth table: IN1/IN2 = H/L forward, L/H reverse, H/H short
//! brake, L/L stop (high impedance: coasting).

use super::wiring::{self, DirPins, PwmPins};
use robovac::robot::hal::MotorDriver;

/// PWM period in timer ticks: 84 MHz / 4200 = 20 kHz.
const PERIOD_TICKS: u32 = 4200;
const _: () = assert!(wiring::TICK_TIMER_HZ / PERIOD_TICKS == 20_000);

/// The two motors.
pub struct Motors {
    _pwm: PwmPins,
    dir: DirPins,
}

/// How one motor's two inputs are driven.
#[derive(Clone, Copy)]
enum Drive {
    Forward,
    Reverse,
    Brake,
    Coast,
}

impl Motors {
    /// Sets the PWM timer up (TIM4 enabled in RCC by the caller) and
    /// enables the driver (STBY high), motors braked.
    pub fn new(pwm: PwmPins, dir: DirPins) -> Self {
        let t = wiring::pwm_timer();
        t.psc().write(|w| unsafe { w.psc().bits(0) });
        t.arr().write(|w| unsafe { w.bits(PERIOD_TICKS - 1) });
        // PWM mode 1 with preload on CH1 and CH2.
        t.ccmr1_output().write(|w| unsafe {
            w.oc1m().bits(0b110);
            w.oc1pe().set_bit();
            w.oc2m().bits(0b110);
            w.oc2pe().set_bit()
        });
        t.ccr(0).write(|w| unsafe { w.bits(0) });
        t.ccr(1).write(|w| unsafe { w.bits(0) });
        t.ccer().write(|w| w.cc1e().set_bit().cc2e().set_bit());
        t.cr1().write(|w| w.arpe().set_bit());
        t.egr().write(|w| w.ug().set_bit());
        t.cr1().modify(|_, w| w.cen().set_bit());
        let mut m = Self { _pwm: pwm, dir };
        m.brake();
        m.dir.4.set_high();
        m
    }

    fn set(&mut self, left: Drive, right: Drive) {
        let (a1, a2, b1, b2, _) = &mut self.dir;
        pins(a1, a2, left);
        let right = if wiring::RIGHT_MOTOR_MIRRORED {
            match right {
                Drive::Forward => Drive::Reverse,
                Drive::Reverse => Drive::Forward,
                d => d,
            }
        } else {
            right
        };
        pins(b1, b2, right);
    }
}

/// Drives one H-bridge's inputs.
fn pins(
    in1: &mut impl stm32f4xx_hal::hal::digital::OutputPin,
    in2: &mut impl stm32f4xx_hal::hal::digital::OutputPin,
    d: Drive,
) {
    let (h1, h2) = match d {
        Drive::Forward => (true, false),
        Drive::Reverse => (false, true),
        Drive::Brake => (true, true),
        Drive::Coast => (false, false),
    };
    // The HAL's GPIO writes are infallible (`Infallible` errors).
    let _ = in1.set_state(h1.into());
    let _ = in2.set_state(h2.into());
}

/// A signed permille duty as a direction and a compare value.
fn split(duty_pm: i16) -> (Drive, u32) {
    let mag = duty_pm.unsigned_abs().min(1000) as u32;
    let ticks = mag * PERIOD_TICKS / 1000;
    (
        if duty_pm < 0 {
            Drive::Reverse
        } else {
            Drive::Forward
        },
        ticks,
    )
}

impl MotorDriver for Motors {
    fn set_duty(&mut self, left_pm: i16, right_pm: i16) {
        let (dl, cl) = split(left_pm);
        let (dr, cr) = split(right_pm);
        let t = wiring::pwm_timer();
        t.ccr(0).write(|w| unsafe { w.bits(cl) });
        t.ccr(1).write(|w| unsafe { w.bits(cr) });
        self.set(dl, dr);
    }

    fn brake(&mut self) {
        self.set(Drive::Brake, Drive::Brake);
        let t = wiring::pwm_timer();
        // Full duty with both inputs high: the bridge shorts the motor.
        t.ccr(0).write(|w| unsafe { w.bits(PERIOD_TICKS) });
        t.ccr(1).write(|w| unsafe { w.bits(PERIOD_TICKS) });
    }

    fn coast(&mut self) {
        self.set(Drive::Coast, Drive::Coast);
        let t = wiring::pwm_timer();
        t.ccr(0).write(|w| unsafe { w.bits(0) });
        t.ccr(1).write(|w| unsafe { w.bits(0) });
    }
}

/// Stops both motors from anywhere (the fault handler): PWM off and the
/// driver in standby, by register.
pub fn emergency_stop() {
    let t = wiring::pwm_timer();
    t.ccr(0).write(|w| unsafe { w.bits(0) });
    t.ccr(1).write(|w| unsafe { w.bits(0) });
    wiring::driver_standby_now();
}

/// A fault (a stack overflow into the guard, a bad access): the motors
/// stop at once; the watchdog, no longer fed, resets the chip.
#[cortex_m_rt::exception]
unsafe fn HardFault(ef: &cortex_m_rt::ExceptionFrame) -> ! {
    emergency_stop();
    defmt::error!(
        "hard fault at pc {=u32:#x}, lr {=u32:#x}: motors stopped",
        ef.pc(),
        ef.lr()
    );
    loop {
        cortex_m::asm::wfi();
    }
}
