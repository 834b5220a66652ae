//! The hardware the core talks to, as small traits of our own (embedded-hal
//! 1.0 has no encoder or PWM-motor traits). The STM32 board implements them
//! with timers and UARTs; host-sim implements them with physics. Time is
//! always passed in ([`Clock`]), never read from a global.

/// Two wheel motors driven by signed duty cycles.
pub trait MotorDriver {
    /// Sets the duty of each wheel in permille of full voltage, −1000..=1000
    /// (positive drives the robot forward). Out-of-range values saturate.
    fn set_duty(&mut self, left_pm: i16, right_pm: i16);
    /// Shorts both motors (active braking).
    fn brake(&mut self);
    /// Disconnects both motors (free wheeling).
    fn coast(&mut self);
}

/// A quadrature encoder read as the raw 16-bit hardware counter, which
/// wraps. Forward rotation counts up.
pub trait QuadratureEncoder {
    /// The counter now.
    fn count(&mut self) -> u16;
}

/// Bytes from the lidar's UART (filled by an interrupt or DMA).
pub trait ByteSource {
    /// Copies the bytes received since the last call into `buf`, returns
    /// how many. Never blocks.
    fn read(&mut self, buf: &mut [u8]) -> usize;
}

/// A monotonic clock.
pub trait Clock {
    /// Microseconds since an arbitrary start.
    fn now_us(&mut self) -> u64;
}
