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
// cortex-m-rt turns each `static mut` of the entry point into an argument.
#[allow(clippy::too_many_arguments)]
mod emu {
    use super::common::{self, exit, fail, Meter};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::debug;
    use defmt_semihosting as _;
    // Links the device's interrupt vector table; nothing touches RCC.
    use robovac::capacity::{
        BenchCoverage, BenchGrid, BENCH_CELLS, BENCH_WORDS, COVERAGE128_BYTES, GRID128_BYTES,
        SEARCH128_BYTES,
    };
    use robovac::coverage::{PlannerKind, Step};
    use robovac::grid::los::line_of_sight;
    use robovac::grid::maps::{table1_instance, SplitMix64, FLAT_40X20, TABLE1_CORNER, TABLE1_MAP};
    use robovac::grid::Grid;
    use robovac::math::cost::{COST_DIAGONAL, COST_PER_CELL};
    use robovac::robot::lidar::ld06::{encode, Ld06};
    use robovac::robot::lidar::scan::{Scan, ScanAssembler};
    use robovac::robot::lidar::LidarProtocol;
    use robovac::robot::lidar_map::{CellState, EvidenceMap, LidarMount};
    use robovac::robot::odometry::{DriveGeometry, Odometry, Pose};
    use robovac::search::prune::prune;
    use robovac::verify::check::Checker;
    use robovac::verify::metrics::MetricsRecorder;
    use robovac::{Algo, Cell};
    use stm32f4xx_hal as _;

    /// Table 1 instances run on the target (the same generator and seed as
    /// `host-sim bench table1 --seed 1`).
    const INSTANCES: u32 = 20;

    // ---- independent checker: a small Dijkstra of its own -------------

    /// Oracle heap entries (lazy deletion; a full heap fails the run loudly).
    const HEAP_CAP: usize = 1024;
    /// Node budget per planner call in the bounded coverage runs.
    const NODE_BUDGET: u32 = 64;
    /// Longest path the run reads out.
    const PATH_CAP: usize = 512;

    struct Oracle {
        dist: [u32; BENCH_CELLS],
        heap: [(u32, u32); HEAP_CAP],
    }

    impl Oracle {
        const fn new() -> Self {
            Self {
                dist: [0; BENCH_CELLS],
                heap: [(0, 0); HEAP_CAP],
            }
        }

        /// Exact optimal octile cost (same integer units) from s to t.
        fn cost<const NW: usize>(&mut self, g: &Grid<NW>, s: Cell, t: Cell) -> Option<u32> {
            let w = g.width() as i32;
            let n = g.cells();
            for d in self.dist.iter_mut().take(n) {
                *d = u32::MAX;
            }
            let free = |x: i32, y: i32| g.contains(x, y) && !g.is_blocked(x, y);
            let idx = |x: i32, y: i32| (y * w + x) as usize;
            let mut len = 0usize;
            self.dist[idx(s.x as i32, s.y as i32)] = 0;
            self.push(&mut len, 0, idx(s.x as i32, s.y as i32) as u32);
            while let Some((d, i)) = self.pop(&mut len) {
                if d > self.dist[i as usize] {
                    continue;
                }
                let (x, y) = ((i as i32) % w, (i as i32) / w);
                if (x, y) == (t.x as i32, t.y as i32) {
                    return Some(d);
                }
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        if (dx, dy) == (0, 0) || !free(x + dx, y + dy) {
                            continue;
                        }
                        let diag = dx != 0 && dy != 0;
                        if diag && !(free(x + dx, y) && free(x, y + dy)) {
                            continue;
                        }
                        let nd = d + if diag { COST_DIAGONAL } else { COST_PER_CELL };
                        let j = idx(x + dx, y + dy);
                        if nd < self.dist[j] {
                            self.dist[j] = nd;
                            if !self.push(&mut len, nd, j as u32) {
                                fail("oracle heap full");
                            }
                        }
                    }
                }
            }
            None
        }

        fn push(&mut self, len: &mut usize, d: u32, i: u32) -> bool {
            if *len >= HEAP_CAP {
                return false;
            }
            let mut k = *len;
            *len += 1;
            while k > 0 && self.heap[(k - 1) / 2].0 > d {
                self.heap[k] = self.heap[(k - 1) / 2];
                k = (k - 1) / 2;
            }
            self.heap[k] = (d, i);
            true
        }

        fn pop(&mut self, len: &mut usize) -> Option<(u32, u32)> {
            if *len == 0 {
                return None;
            }
            let top = self.heap[0];
            *len -= 1;
            let last = self.heap[*len];
            let mut k = 0;
            loop {
                let mut c = 2 * k + 1;
                if c >= *len {
                    break;
                }
                if c + 1 < *len && self.heap[c + 1].0 < self.heap[c].0 {
                    c += 1;
                }
                if self.heap[c].0 < last.0 {
                    self.heap[k] = self.heap[c];
                    k = c;
                } else {
                    break;
                }
            }
            self.heap[k] = last;
            Some(top)
        }
    }

    /// Path check: 8-connected steps on free cells, no corner cutting.
    /// Returns the octile cost in integer units.
    fn check_steps<const NW: usize>(g: &Grid<NW>, p: &[Cell]) -> Option<u32> {
        let mut cost = 0u32;
        if p.iter().any(|c| g.is_blocked(c.x as i32, c.y as i32)) {
            return None;
        }
        for w in p.windows(2) {
            let (dx, dy) = (w[1].x as i32 - w[0].x as i32, w[1].y as i32 - w[0].y as i32);
            if dx.abs() > 1 || dy.abs() > 1 || (dx, dy) == (0, 0) {
                return None;
            }
            if dx != 0 && dy != 0 {
                if g.is_blocked(w[0].x as i32 + dx, w[0].y as i32)
                    || g.is_blocked(w[0].x as i32, w[0].y as i32 + dy)
                {
                    return None;
                }
                cost += COST_DIAGONAL;
            } else {
                cost += COST_PER_CELL;
            }
        }
        Some(cost)
    }

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

    /// LD06 bytes of a 3 m square room seen from its centre, parsed on the
    /// target; odometry updates; one revolution's map update. Checked and
    /// measured.
    fn lidar_and_odometry(
        meter: &Meter,
        evid: &mut EvidenceMap<{ 64 * 64 }>,
        asm: &mut ScanAssembler<40>,
        scan: &mut Scan<40>,
    ) {
        // Three revolutions of 36 frames (10° each, 12 samples).
        let mut parser = Ld06::new();
        let (mut bytes, mut parse_insn, mut frames, mut revs) = (0u64, 0u64, 0u32, 0u32);
        let pose = Pose {
            x_mm: 1500,
            y_mm: 1500,
            theta_mrad: 0,
        };
        for rev in 0..3u32 {
            for k in 0..36u32 {
                let start = (k * 1000) as u16;
                let pts: [(u16, u8); 12] = core::array::from_fn(|i| {
                    let cdeg = k as i64 * 1000 + i as i64 * 917 / 11;
                    let (s, c) = robovac::math::angle::sin_cos_q30(cdeg * 174_533 / 1000);
                    let m = s.abs().max(c.abs()).max(1);
                    (((1500i64 << 30) / m) as u16, 200)
                });
                let frame = encode(3600, start, start + 917, (rev * 100 + k) as u16, &pts);
                // One measurement per frame (47 bytes), so the meter's own
                // cost is spread over the bytes.
                let (got, insn) = meter.measure(|| {
                    let mut got = None;
                    for &b in frame.iter() {
                        if let Some(f) = parser.feed(b) {
                            got = Some(f);
                        }
                    }
                    got
                });
                parse_insn += insn;
                bytes += frame.len() as u64;
                if let Some(f) = got {
                    frames += 1;
                    if asm.push(&f, pose, scan) {
                        revs += 1;
                    }
                }
            }
        }
        if frames != 108 || parser.stats().crc_failures != 0 || revs != 2 {
            fail("lidar parse or scan assembly");
        }
        defmt::println!(
            "lidar: {} bytes parsed into {} frames, {} instructions per byte",
            bytes,
            frames,
            parse_insn / bytes
        );
        if evid.reset(64, 64, 50).is_err() {
            fail("evidence map");
        }
        let mount = LidarMount::ld06_centred(false);
        let (cells, insn) = meter.measure(|| evid.integrate_scan(scan, &mount));
        let st = |x: i32, y: i32| {
            let (cx, cy) = evid.cell_of(x, y);
            evid.state(cx, cy)
        };
        if st(1500, 1500) != CellState::Free
            || st(2000, 1200) != CellState::Free
            || st(3010, 1500) != CellState::Occupied
        {
            fail("map update");
        }
        defmt::println!(
            "map update: one revolution ({} points) ray-cast {} cells in {} instructions",
            scan.point_count(),
            cells,
            insn
        );
        // Odometry: 2 m straight then a half turn, 100 Hz updates.
        let geom = DriveGeometry {
            ticks_per_rev: 1000,
            wheel_diameter_um: 72_000,
            wheelbase_um: 235_000,
        };
        let mut odo = Odometry::new(geom);
        let (mut l, mut r) = (65_000u16, 65_000u16);
        odo.update(l, r);
        let (mut total, mut n) = (0u64, 0u64);
        for _ in 0..885 {
            l = l.wrapping_add(10);
            r = r.wrapping_add(10);
            let (_, insn) = meter.measure(|| odo.update(l, r));
            total += insn;
            n += 1;
        }
        for _ in 0..(3264 / 2) {
            l = l.wrapping_sub(1);
            r = r.wrapping_add(1);
            let (_, insn) = meter.measure(|| odo.update(l, r));
            total += insn;
            n += 1;
        }
        let p = odo.pose();
        if (p.x_mm - 2001).abs() > 2 || p.y_mm.abs() > 2 || (p.theta_mrad.abs() - 3141).abs() > 5 {
            fail("odometry");
        }
        defmt::println!(
            "odometry: {} updates, {} instructions per update; pose ({} mm, {} mm, {} mrad)",
            n,
            total / n,
            p.x_mm,
            p.y_mm,
            p.theta_mrad
        );
    }

    /// One DWA cycle on the recorded situation: the same command as on the
    /// host, and its cost.
    fn dwa_cycle(meter: &Meter) {
        use robovac::nav::dwa::{
            plan, DwaResult, DEFAULT_PARAMS, RECORDED_COMMAND, RECORDED_GOAL, RECORDED_OBSTACLES,
            RECORDED_VELOCITY, V_SAMPLES, W_SAMPLES,
        };
        let (r, insn) = meter.measure(|| {
            plan(
                &DEFAULT_PARAMS,
                RECORDED_VELOCITY.0,
                RECORDED_VELOCITY.1,
                RECORDED_GOAL,
                &RECORDED_OBSTACLES,
            )
        });
        match r {
            DwaResult::Command {
                v_mm_s, w_mrad_s, ..
            } if (v_mm_s, w_mrad_s) == RECORDED_COMMAND => {}
            _ => fail("DWA command differs from the host's"),
        }
        defmt::println!(
            "DWA: one cycle ({} samples x 20 steps x {} obstacle points) in {} instructions; command ({} mm/s, {} mrad/s)",
            V_SAMPLES * W_SAMPLES,
            RECORDED_OBSTACLES.len(),
            insn,
            RECORDED_COMMAND.0,
            RECORDED_COMMAND.1
        );
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
        static mut EVID: EvidenceMap<{ 64 * 64 }> = EvidenceMap::new();
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
        let mut sums = [(0u64, 0u64, 0u64); 3]; // (instructions, nodes, cost)
        let mut max_insn = [0u64; 3];
        let mut done = 0u32;
        let algos = [
            (Algo::AStar, "A*"),
            (Algo::Oha, "OHA*"),
            (Algo::Theta, "Theta*"),
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
                    if *algo == Algo::AStar {
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
        run(GRID, flat_start, PlannerKind::BOha, u32::MAX, "flat 40x20");
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
