//! The robovac firmware for the STM32F4.
//!
//! For now it boots, sets the clocks, logs through defmt over RTT, plans an
//! OHA* path across the built-in flat and logs its cost, node count and
//! cycle count. The motors, encoders and lidar come in later.
//!
//! On the host this file builds a stub that explains how to build the real
//! firmware, so `cargo test --workspace` works without the target.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod board;
#[cfg(target_os = "none")]
mod log;
#[cfg(all(target_os = "none", feature = "pil"))]
mod pil;
#[cfg(all(target_os = "none", not(feature = "pil")))]
mod rtt;
#[cfg(all(target_os = "none", feature = "pil"))]
mod stack;

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

    #[entry]
    fn main() -> ! {
        static mut MISSION: Mission = Mission::new(PLACEHOLDER);
        static mut PLANNER: FwPlanner = FwPlanner::new(PlannerKind::BOha);
        static mut SEARCH: FwWindow = FwWindow::new();
        static mut COARSE: FwPlanGrid = FwPlanGrid::new();
        static mut FINE: FwFineGrid = FwFineGrid::new();
        static mut MAP: FwEvidence = FwEvidence::new();
        static mut PATH: [Cell; FW_FINE_PATH] = [Cell::new(0, 0); FW_FINE_PATH];
        static mut MATCHER: FwMatcher = FwMatcher::new();

        stack::paint();
        let mut cp = match cortex_m::Peripherals::take() {
            Some(cp) => cp,
            None => loop {
                cortex_m::asm::wfi();
            },
        };
        let mut link = board::simlink::SimLink::new(&mut cp.SYST);
        let meter = board::simlink::Meter::calibrate();
        defmt::info!(
            "meter: {} instructions per 1000 SysTick ticks",
            meter.ratio()
        );
        defmt::info!("robovac sim-link image {}", env!("CARGO_PKG_VERSION"));
        let buffers = pil::Buffers {
            mission: MISSION,
            planner: PLANNER,
            search: SEARCH,
            coarse: COARSE,
            fine: FINE,
            map: MAP,
            path: PATH,
            matcher: MATCHER,
        };
        pil::run(buffers, &mut link, &meter)
    }
}

#[cfg(all(target_os = "none", not(feature = "pil")))]
mod firmware {
    use super::{board, log};
    use cortex_m::peripheral::DWT;
    use cortex_m_rt::entry;
    use panic_probe as _;
    use robovac::capacity::{FwGrid, FwSearch, FW_CELLS, FW_SIDE};
    use robovac::grid::maps::FLAT_40X20;
    use robovac::math::cost::COST_PER_CELL;
    use robovac::search::prune::prune;
    use robovac::{Algo, Cell};
    use stm32f4xx_hal::pac;

    #[entry]
    fn main() -> ! {
        static mut GRID: FwGrid = FwGrid::new();
        static mut SEARCH: FwSearch = FwSearch::new();
        static mut PATH: [Cell; FW_CELLS] = [Cell::new(0, 0); FW_CELLS];

        defmt::info!("robovac firmware {}", env!("CARGO_PKG_VERSION"));
        let (Some(dp), Some(mut cp)) = (pac::Peripherals::take(), cortex_m::Peripherals::take())
        else {
            defmt::error!("peripherals already taken");
            halt();
        };
        // 84 MHz from the internal oscillator: no crystal needed on any board.
        let (sysclk_hz, clock_err) = board::clock::setup(&dp.RCC, &dp.FLASH);
        defmt::info!("sysclk {} Hz", sysclk_hz);
        if let Some(e) = clock_err {
            defmt::warn!("clocks left on the internal oscillator: {}", e);
        }
        cp.DCB.enable_trace();
        cp.DWT.enable_cycle_counter();

        defmt::info!(
            "capacity: maps up to {}x{} cells, search state {} bytes",
            FW_SIDE,
            FW_SIDE,
            core::mem::size_of::<FwSearch>()
        );
        if let Err(e) = GRID.load_ascii(FLAT_40X20) {
            defmt::error!("built-in map: {}", defmt::Display2Format(&e));
            halt();
        }
        let (start, goal) = (Cell::new(1, 1), Cell::new(38, 18));
        let t0 = DWT::cycle_count();
        let res = SEARCH.search(GRID, start, &[goal], Algo::Oha);
        let cycles = DWT::cycle_count().wrapping_sub(t0);
        match res {
            Ok(stats) => {
                let n = SEARCH.write_path(PATH).unwrap_or(0);
                let path = PATH.get_mut(..n).unwrap_or(&mut []);
                let m = prune(GRID, path);
                defmt::info!(
                    "OHA* ({},{}) -> ({},{}): cost {}.{:03} cells, {} path cells, {} waypoints after pruning, {} nodes expanded, {} cycles",
                    start.x,
                    start.y,
                    goal.x,
                    goal.y,
                    stats.cost / COST_PER_CELL,
                    (stats.cost % COST_PER_CELL) * 1000 / COST_PER_CELL,
                    n,
                    m,
                    stats.nodes_expanded,
                    cycles
                );
                for c in path.iter().take(m) {
                    defmt::info!("  waypoint ({}, {})", c.x, c.y);
                }
            }
            Err(e) => defmt::error!("OHA* failed: {}", e.as_str()),
        }
        defmt::info!(
            "idle: motors, encoders and lidar arrive in later releases ({} log frames dropped)",
            log::dropped()
        );
        loop {
            cortex_m::asm::wfi();
        }
    }

    fn halt() -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }
}

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
