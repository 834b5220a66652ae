//! The robovac firmware for the STM32F4.
//!
//! The robot image (`app`): the mission on the board's motors, encoders
//! and lidar as RTIC tasks, logging through defmt over RTT (or a UART with
//! the `log-serial` feature). With the `pil` feature, the same executive
//! and capacities on the sim-link board instead (`pil`): the mission in
//! QEMU with host-sim as the robot.
//!
//! On the host this file builds a stub that explains how to build the real
//! firmware, so `cargo test --workspace` works without the target.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod board;
#[cfg(all(target_os = "none", feature = "home16"))]
mod ccm;
#[cfg(target_os = "none")]
mod log;
#[cfg(all(target_os = "none", feature = "pil"))]
mod pil;
#[cfg(all(target_os = "none", not(any(feature = "pil", feature = "log-serial"))))]
mod rtt;
#[cfg(target_os = "none")]
mod stack;
#[cfg(target_os = "none")]
mod status;

/// The image with the sim-link board: the mission in the emulator, wired
/// to host-sim (`host-sim mission --pil`).
#[cfg(all(target_os = "none", feature = "pil"))]
// cortex-m-rt turns each `static mut` of the entry point into an argument.
#[allow(clippy::too_many_arguments)]
mod pil_entry {
    use super::{board, pil, stack};
    use cortex_m_rt::entry;
    use panic_probe as _;
    use robovac::capacity::{
        FwEvidence, FwFineGrid, FwMatcher, FwPlanGrid, FwPlanner, FwWindow, FW_FINE_PATH,
        FW_PLAN_CELLS,
    };
    use robovac::coverage::PlannerKind;
    use robovac::mission::{MapMode, Mission, MissionConfig};
    use robovac::robot::lidar_map::LidarMount;
    use robovac::robot::odometry::DriveGeometry;
    use robovac::robot::wheel_control::WheelGains;
    use robovac::Cell;

    /// Replaced by the host's configuration before each mission
    /// ([`Mission::configure`]).
    const PLACEHOLDER: MissionConfig = MissionConfig::new(
        MapMode::Unknown,
        DriveGeometry {
            ticks_per_rev: 1,
            wheel_diameter_um: 1,
            wheelbase_um: 1000,
        },
        WheelGains {
            kff_q8: 0,
            kp_q8: 0,
            ki_q8: 0,
            max_duty_pm: 0,
            stall_duty_pm: 0,
            stall_ms: 0,
        },
        LidarMount::ld06_centred(true),
    );

    /// The evidence map: outside the entry point's statics, which
    /// cortex-m-rt turns into arguments (where `link_section` is not
    /// allowed); in the CCM at 16 x 16 m (`ccm`).
    #[cfg_attr(feature = "home16", link_section = ".ccmram.map")]
    static mut MAP: FwEvidence = FwEvidence::new();

    #[entry]
    fn main() -> ! {
        static mut MISSION: Mission = Mission::new(PLACEHOLDER);
        static mut PLANNER: FwPlanner = FwPlanner::new(PlannerKind::BOha);
        static mut SEARCH: FwWindow = FwWindow::new();
        static mut COARSE: FwPlanGrid = FwPlanGrid::new();
        static mut FINE: FwFineGrid = FwFineGrid::new();
        static mut PATH: [Cell; FW_FINE_PATH] = [Cell::new(0, 0); FW_FINE_PATH];
        static mut MATCHER: FwMatcher = FwMatcher::new();
        static mut ROOMS: [u8; FW_PLAN_CELLS] = [0; FW_PLAN_CELLS];

        stack::paint();
        let mut cp = match cortex_m::Peripherals::take() {
            Some(cp) => cp,
            None => loop {
                cortex_m::asm::wfi();
            },
        };
        stack::guard(&mut cp.MPU);
        let mut link = board::simlink::SimLink::new(&mut cp.SYST);
        let meter = board::meter::Meter::calibrate();
        defmt::info!(
            "meter: {} instructions per 1000 SysTick ticks ({} ticks for a {}-instruction loop)",
            meter.ratio(),
            meter.calibration_ticks(),
            board::meter::CALIBRATION_INSTRUCTIONS
        );
        defmt::info!("robovac sim-link image {}", env!("CARGO_PKG_VERSION"));
        let buffers = pil::Buffers {
            mission: MISSION,
            planner: PLANNER,
            search: SEARCH,
            coarse: COARSE,
            fine: FINE,
            // SAFETY: the entry point runs once and never returns, and
            // nothing else names MAP: this is its only reference.
            map: unsafe { &mut *core::ptr::addr_of_mut!(MAP) },
            path: PATH,
            matcher: MATCHER,
            rooms: ROOMS,
        };
        pil::run(buffers, &mut link, &meter)
    }
}

/// The robot image: the mission as RTIC tasks on the board
/// (`firmware/app.rs`).
#[cfg(all(target_os = "none", not(feature = "pil")))]
mod app;
#[cfg(all(target_os = "none", not(feature = "pil")))]
use panic_probe as _;

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "robovac is the STM32F4 firmware. Build it with\n  \
         cargo build --release --target thumbv7em-none-eabihf\n\
         flash it with\n  cargo run --release --target thumbv7em-none-eabihf\n\
         or try the core on this PC with\n  cargo run -p host-sim -- demo"
    );
    std::process::exit(2);
}
