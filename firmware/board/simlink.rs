//! The sim-link board (issue 11 §4): the firmware in QEMU's
//! `netduinoplus2` (an STM32F405), wired to host-sim through its USARTs
//! instead of to motors, encoders and a lidar.
//!
//! - USART1: the LD06 byte stream from host-sim (receive only).
//! - USART2: the link ([`robovac::link`]): ticks in, motor commands,
//!   events and the report out.
//! - USART6: the defmt log out (see [`super::super::log`]).
//!
//! Both receivers are interrupt-driven into single-producer queues. QEMU
//! models no RCC, DMA or watchdog: nothing here waits for a clock. Time
//! is the host's (each tick carries it), so a run is deterministic.
//! Instructions are counted with SysTick (`-icount shift=0`: one
//! instruction is one nanosecond of virtual time; see [`super::meter`]).

use core::ptr::addr_of_mut;
use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::{syst::SystClkSource, NVIC, SYST};
use heapless::spsc::{Consumer, Producer, Queue};
use robovac::link::msg::{Down, Up};
use robovac::link::{encode, FrameReader, LinkStats, MAX_FRAME};
use stm32f4xx_hal::pac::{self, interrupt, Interrupt, USART1, USART2, USART6};

/// Bytes the lidar queue holds (a period carries about 100).
const LIDAR_Q: usize = 1024;
/// Bytes the link queue holds.
const LINK_Q: usize = 1024;

static mut LIDAR_QUEUE: Queue<u8, LIDAR_Q> = Queue::new();
static mut LINK_QUEUE: Queue<u8, LINK_Q> = Queue::new();
static mut LIDAR_IN: Option<Producer<'static, u8>> = None;
static mut LINK_IN: Option<Producer<'static, u8>> = None;
/// Receive errors (overrun, framing, noise) and bytes lost to a full queue.
static RX_ERRORS: AtomicU32 = AtomicU32::new(0);
static RX_DROPPED: AtomicU32 = AtomicU32::new(0);

/// The board as the sim-link mission runner uses it.
pub struct SimLink {
    lidar: Consumer<'static, u8>,
    link: Consumer<'static, u8>,
    reader: FrameReader<MAX_FRAME>,
}

/// Enables one USART for 8N1 with the receive interrupt (the baud rate
/// register is set for a real chip's 230400 at 84 MHz; QEMU ignores it).
fn enable_usart(u: &pac::usart1::RegisterBlock, rx: bool) {
    u.brr()
        .write(|w| unsafe { w.bits((84_000_000u32 / 230_400) as u16) });
    u.cr1().write(|w| {
        w.ue().set_bit();
        w.te().set_bit();
        w.re().bit(rx);
        w.rxneie().bit(rx)
    });
}

impl SimLink {
    /// Takes the USARTs and SysTick; unmasks the receive interrupts.
    pub fn new(syst: &mut SYST) -> Self {
        // SAFETY: called once at boot, before the interrupts are unmasked;
        // the queues are split once and their halves live for ever.
        let (lidar, link) = unsafe {
            let (lp, lc) = (*addr_of_mut!(LIDAR_QUEUE)).split();
            let (kp, kc) = (*addr_of_mut!(LINK_QUEUE)).split();
            *addr_of_mut!(LIDAR_IN) = Some(lp);
            *addr_of_mut!(LINK_IN) = Some(kp);
            (lc, kc)
        };
        // SAFETY: the registers are only touched here and in the handlers.
        unsafe {
            enable_usart(&*USART1::ptr(), true);
            enable_usart(&*USART2::ptr(), true);
            enable_usart(&*USART6::ptr(), false);
            NVIC::unmask(Interrupt::USART1);
            NVIC::unmask(Interrupt::USART2);
        }
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00FF_FFFF);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Self {
            lidar,
            link,
            reader: FrameReader::new(),
        }
    }

    /// Sends a message on the link (a message that does not encode is
    /// dropped: it cannot happen with the messages' bounded sizes).
    pub fn send(&mut self, msg: &Up) {
        let mut buf = [0u8; MAX_FRAME];
        if let Ok(n) = encode(msg, &mut buf) {
            // SAFETY: USART2's transmitter is only used from thread mode.
            write_bytes(unsafe { &*USART2::ptr() }, buf.get(..n).unwrap_or(&[]));
        }
    }

    /// Waits for the next message from the host (frames that fail their
    /// check are counted and skipped).
    pub fn recv(&mut self) -> Down {
        loop {
            let next = self.link.dequeue();
            // SAFETY: only CR1's interrupt enable is changed, as the
            // handler does; the handler cannot run between (it is masked).
            resume(unsafe { &*USART2::ptr() });
            match next {
                Some(b) => {
                    if let Some(Ok(m)) = self.reader.push::<Down>(b) {
                        return m;
                    }
                }
                None => cortex_m::asm::nop(),
            }
        }
    }

    /// Waits until `n` lidar bytes have arrived and copies them into `buf`
    /// (at most its length; the rest are read and dropped).
    pub fn lidar_bytes(&mut self, n: usize, buf: &mut [u8]) -> usize {
        let mut got = 0;
        while got < n {
            let next = self.lidar.dequeue();
            // SAFETY: as in `recv`.
            resume(unsafe { &*USART1::ptr() });
            match next {
                Some(b) => {
                    if let Some(slot) = buf.get_mut(got) {
                        *slot = b;
                    }
                    got += 1;
                }
                None => cortex_m::asm::nop(),
            }
        }
        got.min(buf.len())
    }

    /// The link reader's counters.
    pub fn link_stats(&self) -> LinkStats {
        self.reader.stats()
    }

    /// The USARTs' receive errors (overrun, framing, noise) and the bytes
    /// lost to a full queue.
    pub fn rx_counts(&self) -> (u32, u32) {
        (
            RX_ERRORS.load(Ordering::Relaxed),
            RX_DROPPED.load(Ordering::Relaxed),
        )
    }
}

/// Writes bytes on a USART, waiting for its transmit register each time
/// (QEMU sends at once).
fn write_bytes(u: &pac::usart1::RegisterBlock, bytes: &[u8]) {
    for &b in bytes {
        while u.sr().read().txe().bit_is_clear() {}
        u.dr().write(|w| unsafe { w.bits(b as u16) });
    }
}

/// The defmt log's transport on this board: USART6.
pub fn log_write(bytes: &[u8]) {
    // SAFETY: called by the logger inside its critical section only.
    write_bytes(unsafe { &*USART6::ptr() }, bytes);
}

/// Moves a received byte (if any) into a queue; counts errors. With the
/// queue full, the byte stays in the data register and the interrupt is
/// masked until the reader has made room ([`resume`]): QEMU holds the rest
/// of its input meanwhile (flow control the emulated link has and a real
/// lidar UART would not: there it would be an overrun).
fn receive(u: &pac::usart1::RegisterBlock, q: Option<&mut Producer<'static, u8>>) {
    let sr = u.sr().read();
    if sr.ore().bit_is_set() || sr.fe().bit_is_set() || sr.nf().bit_is_set() {
        RX_ERRORS.fetch_add(1, Ordering::Relaxed);
    }
    let Some(q) = q else {
        let _ = u.dr().read();
        RX_DROPPED.fetch_add(1, Ordering::Relaxed);
        return;
    };
    if !q.ready() {
        u.cr1().modify(|_, w| w.rxneie().clear_bit());
        return;
    }
    if sr.rxne().bit_is_set() || sr.ore().bit_is_set() {
        // Reading DR clears RXNE and the error flags (after the SR read).
        let b = u.dr().read().bits() as u8;
        if q.enqueue(b).is_err() {
            RX_DROPPED.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// Unmasks a receiver that [`receive`] paused (a byte waiting in its data
/// register raises the interrupt at once).
fn resume(u: &pac::usart1::RegisterBlock) {
    if u.cr1().read().rxneie().bit_is_clear() {
        u.cr1().modify(|_, w| w.rxneie().set_bit());
    }
}

#[interrupt]
fn USART1() {
    // SAFETY: the producer is only used in this handler.
    unsafe { receive(&*USART1::ptr(), (*addr_of_mut!(LIDAR_IN)).as_mut()) };
}

#[interrupt]
fn USART2() {
    // SAFETY: the producer is only used in this handler.
    unsafe { receive(&*USART2::ptr(), (*addr_of_mut!(LINK_IN)).as_mut()) };
}

#[cortex_m_rt::exception]
unsafe fn HardFault(ef: &cortex_m_rt::ExceptionFrame) -> ! {
    defmt::error!("hard fault at pc {=u32:#x}, lr {=u32:#x}", ef.pc(), ef.lr());
    loop {
        cortex_m::asm::wfi();
    }
}

#[cortex_m_rt::exception]
fn SysTick() {
    super::meter::on_wrap();
}
