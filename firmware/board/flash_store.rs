//! The robot's store ([`Storage`]): flash sector 7 of the F411, 128 KiB at
//! 0x0806_0000, kept out of the image by `memory.x` (FLASH is 384 KiB
//! there). It holds the map kept between runs
//! ([`robovac::robot::map_image`]).
//!
//! Written to the flash controller's registers (RM0383 §3.5) rather than
//! through stm32f4xx-hal's `UnlockedFlash`, whose unlock asserts and would
//! link a panicking branch into the image (the panic check forbids any).
//!
//! **Stalls.** The F411 has one flash bank: while a sector erases (up to
//! 2 s at 2.7–3.6 V, x32) or a byte programs, every fetch from flash
//! waits, interrupts included. The firmware saves only when the mission
//! is done (motors braked), with the watchdog stretched first
//! (firmware/app.rs).

use robovac::robot::hal::{Storage, StorageError};
use stm32f4xx_hal::pac::FLASH;

/// The sector's first byte.
const BASE: usize = 0x0806_0000;
/// Its number.
const SECTOR: u8 = 7;
/// Its size.
const BYTES: u32 = 128 * 1024;
const KEY1: u32 = 0x4567_0123;
const KEY2: u32 = 0xCDEF_89AB;
/// Polls of the busy flag before giving up: several seconds at 84 MHz,
/// beyond the longest erase.
const BUSY_POLLS: u32 = 1 << 28;

/// Flash sector 7 as the robot's store.
pub struct FlashStore(FLASH);

impl FlashStore {
    /// Takes the flash controller (after the clock set its wait states).
    pub fn new(flash: FLASH) -> Self {
        Self(flash)
    }

    /// The absolute address of `len` bytes at `offset`, when inside.
    fn span(offset: u32, len: usize) -> Result<usize, StorageError> {
        let end = (offset as usize).checked_add(len);
        match end {
            Some(e) if e <= BYTES as usize => Ok(BASE + offset as usize),
            _ => Err(StorageError::OutOfRange),
        }
    }

    /// Unlocks the control register and clears old error flags.
    fn unlock(&mut self) -> Result<(), StorageError> {
        self.0.keyr().write(|w| unsafe { w.key().bits(KEY1) });
        self.0.keyr().write(|w| unsafe { w.key().bits(KEY2) });
        self.0.sr().write(|w| {
            w.pgserr().clear();
            w.pgperr().clear();
            w.pgaerr().clear();
            w.wrperr().clear();
            w.operr().clear()
        });
        if self.0.cr().read().lock().is_locked() {
            return Err(StorageError::Device);
        }
        Ok(())
    }

    /// Waits for the operation to end; an error flag fails it.
    fn wait(&self) -> Result<(), StorageError> {
        if !(0..BUSY_POLLS).any(|_| self.0.sr().read().bsy().is_not_busy()) {
            return Err(StorageError::Device);
        }
        let sr = self.0.sr().read();
        let failed = sr.pgserr().is_active()
            || sr.pgperr().is_active()
            || sr.pgaerr().is_active()
            || sr.wrperr().is_active()
            || sr.operr().is_active();
        if failed {
            Err(StorageError::Device)
        } else {
            Ok(())
        }
    }

    /// Ends programming or erasing and locks the controller again.
    fn lock(&mut self) {
        self.0.cr().modify(|_, w| {
            w.pg().clear_bit();
            w.ser().clear_bit();
            w.lock().locked()
        });
    }
}

impl Storage for FlashStore {
    fn capacity(&self) -> u32 {
        BYTES
    }

    fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError> {
        let at = Self::span(offset, buf.len())?;
        for (k, b) in buf.iter_mut().enumerate() {
            // SAFETY: inside sector 7, memory-mapped flash, always readable.
            *b = unsafe { core::ptr::read_volatile((at + k) as *const u8) };
        }
        Ok(())
    }

    fn erase(&mut self) -> Result<(), StorageError> {
        self.unlock()?;
        self.0.cr().modify(|_, w| {
            w.ser().sector_erase();
            unsafe { w.snb().bits(SECTOR) };
            w.psize().psize32()
        });
        self.0.cr().modify(|_, w| w.strt().start());
        let r = self.wait();
        self.lock();
        r
    }

    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError> {
        let at = Self::span(offset, data.len())?;
        self.unlock()?;
        self.0.cr().modify(|_, w| {
            w.ser().clear_bit();
            w.psize().psize8();
            w.pg().program()
        });
        let mut r = Ok(());
        for (k, &b) in data.iter().enumerate() {
            // SAFETY: inside sector 7, erased by `erase`, programming on.
            unsafe { core::ptr::write_volatile((at + k) as *mut u8, b) };
            r = self.wait();
            if r.is_err() {
                break;
            }
        }
        self.lock();
        r
    }
}
