//! What the emulated runs share: the SysTick instruction meter (the
//! sim-link board's, `firmware/board/meter.rs`), exit and
//! failure on the target, the fault handlers. Included by `emu.rs` and
//! `emu_localize.rs` with `#[path]` (examples cannot share a module
//! otherwise).

use cortex_m::peripheral::SYST;
use cortex_m_rt::{exception, ExceptionFrame};
use cortex_m_semihosting::debug;

#[path = "../../firmware/board/meter.rs"]
mod meter;
pub use meter::{known_loop, Meter};

#[exception]
fn SysTick() {
    meter::on_wrap();
}

#[exception]
unsafe fn HardFault(_ef: &ExceptionFrame) -> ! {
    defmt::error!("hard fault");
    exit(debug::EXIT_FAILURE)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    exit(debug::EXIT_FAILURE)
}

/// Ends the emulation with a status (QEMU exits with 0 or 1).
pub fn exit(status: debug::ExitStatus) -> ! {
    debug::exit(status);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Bytes of stack below the caller's frame that [`stack_depth`] paints
/// and reads.
#[allow(dead_code)] // emu_localize's only
const PROBE_BYTES: usize = 16 * 1024;
#[allow(dead_code)]
const PROBE_PAINT: u32 = 0xC0FF_EE11;

/// Runs `f` and returns its result with the bytes of stack it used below
/// this frame: [`PROBE_BYTES`] under the stack pointer are painted first,
/// and the deepest word no longer holding the paint is as deep as `f`
/// went (the statics lie far below on these examples' 128 KiB).
#[inline(never)]
#[allow(dead_code)]
pub fn stack_depth<R>(f: impl FnOnce() -> R) -> (R, usize) {
    let sp = cortex_m::register::msp::read() as usize;
    let (low, high) = (sp - PROBE_BYTES, sp - 64);
    let mut p = low;
    while p < high {
        // SAFETY: below the live stack, above every static: unused memory.
        unsafe { core::ptr::write_volatile(p as *mut u32, PROBE_PAINT) };
        p += 4;
    }
    let r = f();
    let mut p = low;
    // SAFETY: reads of the painted words.
    while p < high && unsafe { core::ptr::read_volatile(p as *const u32) } == PROBE_PAINT {
        p += 4;
    }
    (r, sp - p)
}

pub fn fail(what: &str) -> ! {
    defmt::error!("CHECK FAILED: {}", what);
    exit(debug::EXIT_FAILURE)
}

/// Starts SysTick as a free-running counter, calibrates the meter against
/// the known loop and checks it on a 100 000-instruction loop.
pub fn start_meter() -> Meter {
    use cortex_m::peripheral::syst::SystClkSource;
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        fail("core peripherals");
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_interrupt();
    cp.SYST.enable_counter();
    // The counter reads 0 until its first reload (which raises no
    // exception); wait for it so the first reading is not a false wrap.
    let mut spins = 0u32;
    while SYST::get_current() == 0 && spins < 1_000_000 {
        spins += 1;
    }
    let meter = Meter::calibrate();
    defmt::println!(
        "calibration: {} SysTick ticks for a {}-instruction loop",
        meter.calibration_ticks(),
        meter::CALIBRATION_INSTRUCTIONS
    );
    let kilo = meter.ratio();
    defmt::println!(
        "calibration: {}.{:03} instructions per SysTick tick",
        kilo / 1000,
        kilo % 1000
    );
    let ((), k) = meter.measure(|| known_loop(50_000));
    defmt::println!(
        "meter check: 100000-instruction loop measured as {} instructions",
        k
    );
    if !(99_000..=101_500).contains(&k) {
        fail("instruction meter calibration");
    }
    meter
}
