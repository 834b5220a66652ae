//! The emulated Cortex-M4 run: the core's searches on built-in maps under
//! `qemu-system-arm -machine netduinoplus2 -icount shift=0` (see
//! `scripts/emu.sh`), with results checked on the target and each call's
//! cost reported in instructions.
//!
//! **Instruction counting.** QEMU's `-icount shift=0` advances virtual time
//! by exactly 1 ns per instruction, and SysTick (clocked from the CPU clock)
//! counts virtual time, so SysTick ticks are proportional to instructions.
//! The ratio is calibrated at start-up with a hand-written loop of a known
//! instruction count (2 instructions per iteration) and every measurement is
//! converted with it. SysTick wraps every 2^24 ticks; an exception counts
//! the wraps, giving a 64-bit tick count. Nothing here touches RCC (QEMU
//! does not model it: code there must not wait for a clock to lock).
//!
//! **Checks.** Every A* cost is compared with an independent Dijkstra
//! written below (its own binary heap, no shared code), every path is
//! checked step by step for obstacles and corner cutting, pruned paths are
//! checked with line of sight and must not be longer, and OHA* must expand
//! fewer nodes than A* overall. Any failure exits with status 1; a panic or
//! a hard fault exits too, so CI never hangs.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
#[path = "emu_common/mod.rs"]
mod common;
#[cfg(target_os = "none")]
#[path = "emu_parts/oracle.rs"]
mod oracle;
#[cfg(target_os = "none")]
#[path = "emu_parts/sensors.rs"]
mod sensors;

#[cfg(target_os = "none")]
// cortex-m-rt turns each `static mut` of the entry point into an argument.
#[allow(clippy::too_many_arguments)]
mod emu {
    use super::common::{self, exit, fail, Meter};
    use super::oracle::{check_steps, Oracle};
    use super::sensors::{dwa_cycle, lidar_and_odometry};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::debug;
    use defmt_semihosting as _;
    // Links the device's interrupt vector table; nothing touches RCC.
    use robovac::capacity::{
        BenchCoverage, BenchGrid, BENCH_WORDS, COVERAGE128_BYTES, GRID128_BYTES, SEARCH128_BYTES,
    };
    use robovac::coverage::{PlannerKind, Step};
    use robovac::grid::los::line_of_sight;
    use robovac::grid::maps::{table1_instance, SplitMix64, FLAT_40X20, TABLE1_CORNER, TABLE1_MAP};
    use robovac::math::cost::COST_PER_CELL;
    use robovac::robot::lidar::scan::{Scan, ScanAssembler};
    use robovac::robot::lidar_map::{evidence_bytes, EvidenceMap};
    use robovac::search::prune::prune;
    use robovac::verify::check::Checker;
    use robovac::verify::metrics::MetricsRecorder;
    use robovac::{Algo, Cell};
    use stm32f4xx_hal as _;

    /// Table 1 instances run on the target (the same generator and seed as
    /// `host-sim bench table1 --seed 1`).
    const INSTANCES: u32 = 20;

    /// Node budget per planner call in the bounded coverage runs.
    const NODE_BUDGET: u32 = 64;
    /// Longest path the run reads out.
    const PATH_CAP: usize = 512;

    /// Prunes a path and checks every pruned segment's line of sight.
    fn prune_checked(grid: &BenchGrid, path: &mut [Cell]) -> usize {
        let m = prune(grid, path);
        if path[..m]
            .windows(2)
            .any(|w| !line_of_sight(grid, w[0], w[1]))
        {
            fail("pruned path crosses an obstacle");
        }
        m
    }

    fn first_free(g: &BenchGrid) -> Option<Cell> {
        (0..g.cells())
            .map(|i| g.cell_at(i))
            .find(|c| g.is_free(c.x as i32, c.y as i32))
    }

    /// Plans a complete coverage step by step with `budget` nodes per call,
    /// checks it with the independent checker and the metrics recorder, and
    /// reports instructions for the whole plan and for the largest call.
    #[allow(clippy::too_many_arguments)]
    fn coverage_run(
        meter: &Meter,
        cov: &mut BenchCoverage,
        grid: &mut BenchGrid,
        check: &mut Checker<BENCH_WORDS>,
        rec: &mut MetricsRecorder<BENCH_WORDS>,
        start: Cell,
        kind: PlannerKind,
        budget: u32,
        name: &str,
    ) {
        cov.set_kind(kind);
        if check.start(grid, start).is_err() {
            fail("checker start");
        }
        rec.start(grid, start);
        let (r, mut total) = meter.measure(|| cov.start(grid, start));
        if r.is_err() {
            fail("planner start");
        }
        let (mut max_call, mut calls, mut max_nodes) = (0u64, 0u32, 0u32);
        loop {
            let (r, insn) = meter.measure(|| cov.step(grid, budget));
            total += insn;
            max_call = max_call.max(insn);
            calls += 1;
            max_nodes = max_nodes.max(cov.last_step_nodes());
            match r {
                Ok(Step::Move(w)) => {
                    if check.push(grid, w.to, w.kind, w.starts_segment).is_err() {
                        fail("coverage move enters an obstacle or cuts a corner");
                    }
                    rec.push(w.to, w.kind, w.starts_segment);
                }
                Ok(Step::Pending) => {}
                Ok(Step::Done) => break,
                Err(_) => fail("coverage planner error"),
            }
        }
        let c = check.finish(grid);
        let m = rec.metrics();
        if c.missed_cells != 0 {
            fail("coverage incomplete");
        }
        if (
            c.reachable_cells,
            c.covered_cells,
            c.repeated_cells,
            c.turns,
            c.segments,
        ) != (
            m.reachable_cells,
            m.covered_cells,
            m.repeated_cells,
            m.turns,
            m.segments,
        ) {
            fail("checker and metrics disagree");
        }
        if max_nodes > budget {
            fail("a call exceeded its node budget");
        }
        defmt::println!(
            "coverage {} {}: {}/{} cells, {} segments, {} turns, backtracking {} cells; {} instructions in {} calls, largest call {} instructions ({} nodes, budget {})",
            name,
            kind.name(),
            c.covered_cells,
            c.reachable_cells,
            c.segments,
            c.turns,
            m.backtrack_path_cost / COST_PER_CELL as u64,
            total,
            calls,
            max_call,
            max_nodes,
            budget
        );
    }

    #[entry]
    fn main() -> ! {
        static mut GRID: BenchGrid = BenchGrid::new();
        static mut COV: BenchCoverage = BenchCoverage::new(PlannerKind::BOha);
        static mut CHECK: Checker<BENCH_WORDS> = Checker::new();
        static mut REC: MetricsRecorder<BENCH_WORDS> = MetricsRecorder::new();
        static mut EVID: EvidenceMap<{ evidence_bytes(64 * 64) }> = EvidenceMap::new();
        static mut ASM: ScanAssembler<40> = ScanAssembler::new();
        static mut SCAN: Scan<40> = Scan::new();
        static mut ORACLE: Oracle = Oracle::new();
        static mut PATH: [Cell; PATH_CAP] = [Cell::new(0, 0); PATH_CAP];

        let meter = common::start_meter();
        // Point-to-point searches use the coverage planner's own search
        // state: one search state in RAM, not two.
        let search = COV.search_state_mut();

        // --- Built-in flat: OHA* with pruning ---------------------------
        if GRID.load_ascii(FLAT_40X20).is_err() {
            fail("built-in flat");
        }
        let (s, t) = (Cell::new(1, 1), Cell::new(38, 18));
        let (res, insn) = meter.measure(|| search.search(GRID, s, &[t], Algo::Oha));
        let Ok(stats) = res else {
            fail("OHA* on the flat")
        };
        let Ok(n) = search.write_path(PATH) else {
            fail("path read-out")
        };
        if check_steps(GRID, &PATH[..n]).is_none() {
            fail("OHA* flat path invalid");
        }
        let m = prune_checked(GRID, &mut PATH[..n]);
        defmt::println!(
            "flat 40x20 OHA*: cost {} units ({} cells), {} nodes, {} waypoints pruned, {} instructions",
            stats.cost,
            stats.cost / COST_PER_CELL,
            stats.nodes_expanded,
            m,
            insn
        );

        // --- Seed 000 Table 1 maps ------------------------------------------
        let mut rng = SplitMix64::new(1);
        let mut sums = [(0u64, 0u64, 0u64); 5]; // (instructions, nodes, cost)
        let mut max_insn = [0u64; 5];
        let mut done = 0u32;
        let algos = [
            (Algo::AStar, "A*"),
            (Algo::Oha, "OHA*"),
            (Algo::Theta, "Theta*"),
            (Algo::AStarOctile, "A* octile"),
            (Algo::Jps, "JPS"),
        ];
        while done < INSTANCES {
            let Ok(Some((s, t))) = table1_instance(GRID, &mut rng, TABLE1_MAP, TABLE1_CORNER)
            else {
                continue;
            };
            if search.search(GRID, s, &[t], Algo::AStar).is_err() {
                continue; // unreachable: draw again, as the host does
            }
            let Some(opt) = ORACLE.cost(GRID, s, t) else {
                fail("oracle found no path where A* did");
            };
            let mut a_cost = 0u32;
            for (k, (algo, name)) in algos.iter().enumerate() {
                let (res, insn) = meter.measure(|| search.search(GRID, s, &[t], *algo));
                let Ok(st) = res else { fail(name) };
                let Ok(n) = search.write_path(PATH) else {
                    fail("path read-out")
                };
                if *algo == Algo::Theta {
                    if PATH[..n]
                        .windows(2)
                        .any(|w| !line_of_sight(GRID, w[0], w[1]))
                    {
                        fail("Theta* segment crosses an obstacle");
                    }
                } else {
                    let Some(c) = check_steps(GRID, &PATH[..n]) else {
                        fail("path invalid")
                    };
                    if c != st.cost {
                        fail("reported cost differs from the path's");
                    }
                    if matches!(*algo, Algo::AStar | Algo::AStarOctile | Algo::Jps) {
                        if st.cost != opt {
                            fail("A* cost differs from the independent Dijkstra");
                        }
                        a_cost = st.cost;
                    } else if st.cost < a_cost {
                        fail("OHA* beat the optimum");
                    }
                }
                prune_checked(GRID, &mut PATH[..n]);
                sums[k].0 += insn;
                sums[k].1 += st.nodes_expanded as u64;
                sums[k].2 += st.cost as u64;
                max_insn[k] = max_insn[k].max(insn);
            }
            done += 1;
        }
        for (k, (_, name)) in algos.iter().enumerate() {
            let n = INSTANCES as u64;
            defmt::println!(
                "table1 100x50 {}: mean {} instructions/query (max {}), mean {} nodes, {} instructions/node",
                name,
                sums[k].0 / n,
                max_insn[k],
                sums[k].1 / n,
                sums[k].0 / sums[k].1.max(1)
            );
        }
        if sums[1].1 >= sums[0].1 {
            fail("OHA* did not expand fewer nodes than A*");
        }
        // --- Complete coverage ------------------------------------------
        if GRID.load_ascii(FLAT_40X20).is_err() {
            fail("built-in flat");
        }
        let flat_start = Cell::new(1, 1);
        let mut run = |grid: &mut BenchGrid, start, kind, budget, name| {
            coverage_run(&meter, COV, grid, CHECK, REC, start, kind, budget, name)
        };
        for kind in PlannerKind::ALL {
            if GRID.load_ascii(FLAT_40X20).is_err() {
                fail("built-in flat");
            }
            run(GRID, flat_start, kind, u32::MAX, "flat 40x20");
        }
        let mut rng = SplitMix64::new(1);
        let spec = robovac::grid::maps::RandomMap {
            width: 30,
            height: 50,
            ..robovac::grid::maps::TABLE2_MAP
        };
        if robovac::grid::maps::random_obstacles(GRID, spec, &mut rng).is_err() {
            fail("table 2 map");
        }
        let Some(t2_start) = first_free(GRID) else {
            fail("table 2 map has no free cell")
        };
        for kind in [PlannerKind::BOha, PlannerKind::BOhaPc, PlannerKind::BaStar] {
            // Whole, then stepped with the firmware's node budget per call.
            for budget in [u32::MAX, NODE_BUDGET] {
                run(GRID, t2_start, kind, budget, "table2 50x30");
            }
        }
        lidar_and_odometry(&meter, EVID, ASM, SCAN);
        dwa_cycle(&meter);
        defmt::println!(
            "memory: planner 100x50 {} bytes; at 128x128 search state {} bytes, planner {} bytes, grid {} bytes (asserted at compile time)",
            core::mem::size_of::<BenchCoverage>(),
            SEARCH128_BYTES,
            COVERAGE128_BYTES,
            GRID128_BYTES
        );
        defmt::println!("emulated run: all checks passed");
        exit(debug::EXIT_SUCCESS)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("emu runs on the emulated Cortex-M4: bash scripts/emu.sh");
    std::process::exit(2);
}
