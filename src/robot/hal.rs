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

/// The front bumper's two switches, each closing over one half of the
/// front arc (as on common robot vacuums); a contact dead ahead closes
/// both. It feels what the lidar cannot see: dark furniture that returns
/// no echo, a glass pane, a chair's crossbar below the scan plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Bumper {
    /// The left half's switch is closed.
    pub left: bool,
    /// The right half's switch is closed.
    pub right: bool,
}

impl Bumper {
    /// Both switches open.
    pub const RELEASED: Self = Self {
        left: false,
        right: false,
    };
    /// Bearing of a contact on one half only, from the heading, mrad: the
    /// middle of that half's arc as far as a switch can tell (about 35°).
    pub const SIDE_BEARING_MRAD: i32 = 600;

    /// Either switch is closed.
    pub fn pressed(self) -> bool {
        self.left || self.right
    }

    /// Where the contact is, from the heading (mrad, left positive): 0 for
    /// both switches, ±[`Self::SIDE_BEARING_MRAD`] for one.
    pub fn bearing_mrad(self) -> i32 {
        match (self.left, self.right) {
            (true, false) => Self::SIDE_BEARING_MRAD,
            (false, true) => -Self::SIDE_BEARING_MRAD,
            _ => 0,
        }
    }
}

/// The bumper's switches, read each control period.
pub trait BumperSwitches {
    /// The switches now (debounced by the switch's own travel: a contact
    /// holds them closed for many periods).
    fn read_bumper(&mut self) -> Bumper;
}

/// Why a [`Storage`] access failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StorageError {
    /// The bytes asked for lie beyond the store's capacity.
    OutOfRange,
    /// The device refused (a flash program or erase error, a file error).
    Device,
}

/// A small non-volatile store, addressed in bytes from 0: a flash sector
/// on the chip, a file on the host. What the robot keeps between runs
/// (its map) lives here. Erased bytes read 0xFF, as flash does.
pub trait Storage {
    /// Bytes it holds.
    fn capacity(&self) -> u32;
    /// Reads `buf.len()` bytes from `offset`.
    fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError>;
    /// Erases every byte (to 0xFF): needed before writing, as on flash.
    fn erase(&mut self) -> Result<(), StorageError>;
    /// Writes `data` at `offset` into erased bytes.
    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError>;
}
