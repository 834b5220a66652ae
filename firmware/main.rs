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
#[cfg(target_os = "none")]
mod rtt;

#[cfg(target_os = "none")]
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
