//! The LD06's bytes: USART1 RX at 230400 baud through DMA into a circular
//! buffer, drained on the half- and full-transfer interrupts and on the
//! idle line (a frame's end), into the core's parser ([`ByteSource`]).
//!
//! Overruns, framing and noise errors are counted, never fatal: the DMA
//! keeps running and the parser resynchronises on the next frame header.
//! If the drain falls more than a whole buffer behind (a planning step
//! holding the executive longer than [`RING`] bytes take to arrive: about
//! 90 ms), the bytes written over are lost; the parser counts the broken
//! frames.

use super::wiring::{self, LIDAR_BAUD, LIDAR_DMA_CHANNEL, LIDAR_DMA_STREAM, LIDAR_PCLK_HZ};
use core::ptr::addr_of_mut;
use core::sync::atomic::{AtomicU32, Ordering};
use robovac::robot::hal::ByteSource;

/// Bytes of the DMA ring (about 90 ms of the LD06's 23 kB/s).
pub const RING: usize = 2048;
/// USART1's baud rate divider (oversampling by 16: BRR = f / baud).
const LIDAR_BRR: u16 = ((LIDAR_PCLK_HZ + LIDAR_BAUD / 2) / LIDAR_BAUD) as u16;
const _: () = assert!(LIDAR_BRR >= 16);
static mut DMA_RING: [u8; RING] = [0; RING];

/// Receive errors seen (overrun, framing, noise).
static ERRORS: AtomicU32 = AtomicU32::new(0);

/// Receive errors so far (overrun, framing, noise).
pub fn errors() -> u32 {
    ERRORS.load(Ordering::Relaxed)
}

/// The lidar's receiver (USART1 and DMA2 enabled in RCC by the caller).
pub struct LidarDma {
    _rx: wiring::LidarRxPin,
    /// Where the next unread byte is in the ring.
    read: usize,
}

impl LidarDma {
    /// Starts the circular transfer and the receiver. Called once.
    pub fn new(rx: wiring::LidarRxPin) -> Self {
        let u = wiring::lidar_usart();
        let dma = wiring::lidar_dma();
        let s = dma.st(LIDAR_DMA_STREAM);
        let ring = addr_of_mut!(DMA_RING) as u32;
        s.cr().modify(|_, w| w.en().clear_bit());
        s.par().write(|w| unsafe { w.bits(u.dr().as_ptr() as u32) });
        s.m0ar().write(|w| unsafe { w.bits(ring) });
        s.ndtr().write(|w| unsafe { w.bits(RING as u32) });
        s.cr().write(|w| unsafe {
            w.chsel().bits(LIDAR_DMA_CHANNEL);
            w.dir().peripheral_to_memory();
            w.minc().set_bit();
            w.circ().set_bit();
            w.htie().set_bit();
            w.tcie().set_bit();
            w.en().set_bit()
        });
        u.brr().write(|w| unsafe { w.bits(LIDAR_BRR) });
        u.cr3().write(|w| w.dmar().set_bit().eie().set_bit());
        u.cr1()
            .write(|w| w.ue().set_bit().re().set_bit().idleie().set_bit());
        Self { _rx: rx, read: 0 }
    }

    /// The DMA stream's interrupt: acknowledges half/full transfer.
    pub fn on_dma(&mut self) {
        let dma = wiring::lidar_dma();
        dma.lifcr().write(|w| {
            w.chtif2().set_bit();
            w.ctcif2().set_bit();
            w.cteif2().set_bit();
            w.cfeif2().set_bit();
            w.cdmeif2().set_bit()
        });
    }

    /// The USART's interrupt: the idle line, and errors (counted; reading
    /// SR then DR clears them).
    pub fn on_usart(&mut self) {
        let u = wiring::lidar_usart();
        let sr = u.sr().read();
        if sr.ore().bit_is_set() || sr.fe().bit_is_set() || sr.nf().bit_is_set() {
            ERRORS.fetch_add(1, Ordering::Relaxed);
        }
        if sr.idle().bit_is_set() || sr.ore().bit_is_set() || sr.fe().bit_is_set() {
            let _ = u.dr().read();
        }
    }

    /// Where the DMA will write next.
    fn write_pos() -> usize {
        let s = wiring::lidar_dma().st(LIDAR_DMA_STREAM);
        let left = (s.ndtr().read().bits() as usize).clamp(1, RING);
        RING - left
    }
}

impl ByteSource for LidarDma {
    fn read(&mut self, buf: &mut [u8]) -> usize {
        let w = Self::write_pos();
        let mut n = 0;
        while self.read != w && n < buf.len() {
            // SAFETY: the DMA writes other bytes of the ring meanwhile;
            // each byte is read with a volatile load.
            let b = unsafe {
                core::ptr::read_volatile((addr_of_mut!(DMA_RING) as *const u8).add(self.read))
            };
            if let Some(slot) = buf.get_mut(n) {
                *slot = b;
            }
            n += 1;
            self.read = (self.read + 1) % RING;
        }
        n
    }
}
