//! The reference wiring and robot (issue 11 §1): a **Nucleo-F411RE**, a
//! **TB6612FNG** dual H-bridge, two **N20-class** encoder gear motors and
//! an **LD06** lidar. Every pin, timer, UART, DMA stream and ADC channel
//! the board uses is named here, with the robot's own measures; another
//! board changes this file only (and, for another chip, the
//! stm32f4xx-hal feature in Cargo.toml, memory.x and probe-rs's `--chip`
//! in .cargo/config.toml). README's wiring table is this file.
//!
//! | signal | pin (Nucleo header) | peripheral |
//! |---|---|---|
//! | left PWM (TB6612 PWMA) | PB6 (D10) | TIM4 CH1, 20 kHz |
//! | right PWM (PWMB) | PB7 (CN7-21) | TIM4 CH2 |
//! | AIN1, AIN2 | PA8 (D7), PA9 (D8) | GPIO |
//! | BIN1, BIN2 | PC7 (D9), PB5 (D4) | GPIO |
//! | STBY | PB4 (D5) | GPIO (high: driver on) |
//! | left encoder A, B | PA6 (D12), PA7 (D11) | TIM3 encoder mode |
//! | right encoder A, B | PA0 (A0), PA1 (A1) | TIM2 encoder mode |
//! | LD06 TX → | PA10 (D2) | USART1 RX, DMA2 stream 2 channel 4 |
//! | battery (divider 1:4) | PA4 (A2) | ADC1 IN4 |
//! | defmt over serial | PA2 | USART2 TX (the ST-LINK virtual COM port) |
//! | start / home button | PC13 (the Nucleo's blue B1) | GPIO input, low = pressed |
//! | bumper, left switch | PC0 (A5) | GPIO input, pull-up, closed to GND = pressed |
//! | bumper, right switch | PC1 (A4) | GPIO input, pull-up, closed to GND = pressed |
//! | control clock | — | TIM5, 1 MHz, compare every 10 ms |
//!
//! Power: the LD06 and the TB6612's VM from the battery side (5 V for the
//! LD06), logic at 3.3 V; all grounds common.

use robovac::mission::{MapMode, MissionConfig};
use robovac::robot::lidar_map::LidarMount;
use robovac::robot::odometry::DriveGeometry;
use robovac::robot::wheel_control::WheelGains;
use stm32f4xx_hal::gpio::{
    gpioa, gpiob, gpioc, Alternate, Analog, Input, Output, PushPull, PA0, PA1, PA6, PA7,
};
use stm32f4xx_hal::pac;

/// The PWM timer's two channels (left = CH1, right = CH2).
pub fn pwm_timer() -> &'static pac::tim3::RegisterBlock {
    // SAFETY: TIM4 is used by the motor driver only.
    unsafe { &*pac::TIM4::ptr() }
}
/// The PWM pins: TIM4 CH1/CH2 (alternate function 2).
pub type PwmPins = (
    gpiob::PB6<Alternate<2, PushPull>>,
    gpiob::PB7<Alternate<2, PushPull>>,
);
/// Direction pins: AIN1, AIN2, BIN1, BIN2, STBY.
pub type DirPins = (
    gpioa::PA8<Output<PushPull>>,
    gpioa::PA9<Output<PushPull>>,
    gpioc::PC7<Output<PushPull>>,
    gpiob::PB5<Output<PushPull>>,
    gpiob::PB4<Output<PushPull>>,
);
/// Puts the driver in standby (STBY low: both bridges open) by register,
/// without the pin's owner: for the fault handler, which cannot borrow it.
pub fn driver_standby_now() {
    // SAFETY: one atomic write to BSRR (bit 16 + 4 resets PB4).
    unsafe { (*pac::GPIOB::ptr()).bsrr().write(|w| w.bits(1 << (16 + 4))) };
}

/// The left encoder's timer and pins.
pub type LeftEncoderTim = pac::TIM3;
/// Its pins (A, B).
pub type LeftEncoderPins = (PA6, PA7);
/// The right encoder's timer (32 bits on the F411: its low 16 bits wrap
/// as a 16-bit counter's do) and pins.
pub type RightEncoderTim = pac::TIM2;
/// Its pins (A, B).
pub type RightEncoderPins = (PA0, PA1);
/// The right motor is mounted mirrored: its encoder counts down forward.
pub const RIGHT_ENCODER_MIRRORED: bool = true;
/// And so is its drive: forward is the other way round on BIN1/BIN2.
pub const RIGHT_MOTOR_MIRRORED: bool = true;

/// The lidar's UART (RX only) and its DMA stream and channel.
pub fn lidar_usart() -> &'static pac::usart1::RegisterBlock {
    // SAFETY: USART1 is used by the lidar driver only.
    unsafe { &*pac::USART1::ptr() }
}
/// DMA2 carries USART1's receive requests.
pub fn lidar_dma() -> &'static pac::dma1::RegisterBlock {
    // SAFETY: DMA2 stream 2 is used by the lidar driver only.
    unsafe { &*pac::DMA2::ptr() }
}
/// USART1_RX is DMA2 stream 2, channel 4 (RM0383 table 28).
pub const LIDAR_DMA_STREAM: usize = 2;
/// Its channel.
pub const LIDAR_DMA_CHANNEL: u8 = 4;
/// The lidar's RX pin: PA10, alternate function 7.
pub type LidarRxPin = gpioa::PA10<Alternate<7, PushPull>>;
/// USART1 is on APB2 (84 MHz).
pub const LIDAR_PCLK_HZ: u32 = super::clock::PCLK2_HZ;
/// The LD06's baud rate.
pub const LIDAR_BAUD: u32 = 230_400;

/// The start / home button: the Nucleo's blue B1 on PC13 (pulled up on
/// the board; pressed reads low). Pressed once: the mission begins;
/// pressed again: the robot goes home.
pub type ButtonPin = gpioc::PC13<Input>;
/// Whether the button reads low when pressed.
pub const BUTTON_ACTIVE_LOW: bool = true;

/// The bumper's left microswitch: PC0 (A5), pulled up, closing to ground.
pub type BumperLeftPin = gpioc::PC0<Input>;
/// The bumper's right microswitch: PC1 (A4), likewise.
pub type BumperRightPin = gpioc::PC1<Input>;
/// Whether a bumper switch reads low when closed.
pub const BUMPER_ACTIVE_LOW: bool = true;

/// The battery's ADC pin (PA4 = ADC1 IN4) and channel.
pub type BatteryPin = gpioa::PA4<Analog>;
/// Its ADC channel.
pub const BATTERY_CHANNEL: u8 = 4;
/// The divider's ratio: the battery's voltage is 4 × the pin's (a 30 kΩ /
/// 10 kΩ divider: a 2S pack at 8.4 V reads 2.1 V).
pub const BATTERY_DIVIDER: u32 = 4;
/// Li-ion cells in series in the pack (2S: within the TB6612's 13.5 V).
pub const BATTERY_CELLS: u32 = 2;

/// The defmt serial port: USART2 (APB1, 42 MHz), TX on PA2 (AF7).
#[cfg(feature = "log-serial")]
pub fn log_usart() -> &'static pac::usart1::RegisterBlock {
    // SAFETY: USART2 is used by the serial logger only.
    unsafe { &*pac::USART2::ptr() }
}
/// The log's TX pin.
#[cfg(feature = "log-serial")]
pub type LogTxPin = gpioa::PA2<Alternate<7, PushPull>>;
/// USART2's clock.
#[cfg(feature = "log-serial")]
pub const LOG_PCLK_HZ: u32 = super::clock::PCLK1_HZ;
/// The log's baud rate (the ST-LINK V2-1 virtual COM port takes it).
#[cfg(feature = "log-serial")]
pub const LOG_BAUD: u32 = 460_800;

/// The control clock: TIM5 (32 bits, APB1 timers at 84 MHz).
pub fn tick_timer() -> &'static pac::tim5::RegisterBlock {
    // SAFETY: TIM5 is used by the control clock only.
    unsafe { &*pac::TIM5::ptr() }
}
/// APB1's timers run at twice its 42 MHz.
pub const TICK_TIMER_HZ: u32 = 2 * super::clock::PCLK1_HZ;

/// The reference robot: 72 mm wheels 235 mm apart, encoders of 1000
/// counts per wheel turn (an N20 with a 7-pole hall encoder on a ~1:36
/// gear, counted on both edges of both channels). host-sim's twin is this
/// robot.
pub const GEOMETRY: DriveGeometry = DriveGeometry {
    ticks_per_rev: 1000,
    wheel_diameter_um: 72_000,
    wheelbase_um: 235_000,
};
/// The wheel controllers' gains for these motors (as host-sim's twin).
pub const GAINS: WheelGains = WheelGains {
    kff_q8: 374,
    kp_q8: 300,
    ki_q8: 2500,
    max_duty_pm: 1000,
    stall_duty_pm: 450,
    stall_ms: 400,
};
/// The LD06 at the robot's centre, zero bearing forward, clockwise.
pub const MOUNT: LidarMount = LidarMount::ld06_centred(true);
/// The robot's mission: a home it has not seen (unknown mode), on a map in
/// the robot's own frame, centred on the dock, that scrolls as the robot
/// nears its edge (`robovac::mission::scroll`; off once a saved map is
/// loaded: its frame is kept).
pub const MISSION: MissionConfig = {
    let mut c = MissionConfig::new(MapMode::Unknown, GEOMETRY, GAINS, MOUNT);
    c.scroll_map = true;
    c
};
