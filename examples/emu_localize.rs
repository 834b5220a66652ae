//! The scan matcher on the emulated Cortex-M4 (`scripts/emu.sh` runs it
//! after `emu.rs`, on `qemu-system-arm -machine netduinoplus2 -icount
//! shift=0`): a recorded twin revolution in the home flat
//! (`tests/golden/scan_home.txt`, checked against the twin by host-sim's
//! `recorded_revolution_is_the_twins`) matched against the prior map, with
//! the results checked on the target against the recorded true pose and
//! each step's cost reported in instructions:
//! - building the coarse levels of the prior;
//! - one tracking match (a guess 39 mm and 1.1° off), and one wide
//!   match, the search after a poor fit (12° off);
//! - the start's window relocalisation (150 mm, 150 mm and 10° off);
//! - a whole-map relocalisation (a kidnap: no guess at all).
//!
//! And the matcher's RAM for the firmware's 12 × 12 m home at 5 cm,
//! asserted at compile time in `robovac::capacity`.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
#[path = "emu_common/mod.rs"]
mod common;

#[cfg(target_os = "none")]
mod run {
    use super::common::{self, exit, fail, Meter};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::debug;
    use defmt_semihosting as _;
    use robovac::localize::{fusion, matcher_words, Fusion, PoseU, ScanMatcher};
    use robovac::robot::lidar_map::{evidence_bytes, CellState, EvidenceMap};
    use robovac::Grid;
    use stm32f4xx_hal as _;

    const MAP: &str = include_str!("../maps/flat/home.txt");
    const SCAN: &str = include_str!("../tests/golden/scan_home.txt");
    /// The home flat: 96 × 72 cells of 10 cm, as 192 × 144 of 5 cm.
    const W: usize = 192;
    const H: usize = 144;
    const MW: usize = matcher_words(W, H);
    /// Bitset words of the fine configuration space over the prior.
    const FW: usize = (W * H).div_ceil(32);
    /// The mission's clearance: the robot's radius and its margin, mm.
    const CLEARANCE_MM: u32 = 175;

    /// The flat into the evidence map, each 10 cm cell as 2 × 2 cells.
    fn load_map(map: &mut EvidenceMap<{ evidence_bytes(W * H) }>) {
        if map.reset(W as u32, H as u32, 50).is_err() {
            fail("evidence map size");
        }
        for (row, line) in MAP.lines().enumerate() {
            for (col, ch) in line.bytes().enumerate() {
                let st = if ch == b'#' {
                    CellState::Occupied
                } else {
                    CellState::Free
                };
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    map.set_state(2 * col as i32 + dx, 2 * row as i32 + dy, st);
                }
            }
        }
        map.freeze_prior();
    }

    fn int(s: Option<&str>) -> i64 {
        s.and_then(|t| t.trim().parse().ok())
            .unwrap_or_else(|| fail("scan file"))
    }

    /// The recorded revolution: the true pose and the points.
    fn load_scan(pts: &mut [(i32, i32); 512]) -> (PoseU, usize) {
        let mut lines = SCAN.lines().filter(|l| !l.starts_with('#'));
        let mut head = lines.next().unwrap_or_else(|| fail("scan file")).split(' ');
        let truth = PoseU {
            x_mm: int(head.next()) as i32,
            y_mm: int(head.next()) as i32,
            theta_urad: int(head.next()),
        };
        let mut n = 0;
        for (slot, l) in pts.iter_mut().zip(lines) {
            let mut f = l.split(' ');
            *slot = (int(f.next()) as i32, int(f.next()) as i32);
            n += 1;
        }
        (truth, n)
    }

    fn off(p: PoseU, dx: i32, dy: i32, dt: i64) -> PoseU {
        PoseU {
            x_mm: p.x_mm + dx,
            y_mm: p.y_mm + dy,
            theta_urad: p.theta_urad + dt,
        }
    }

    /// Fails unless `p` is within 10 mm and 0.5° of the truth; returns
    /// the error (mm, mrad).
    fn check(p: PoseU, t: PoseU, what: &str) -> (i64, i64) {
        let (dx, dy) = ((p.x_mm - t.x_mm) as i64, (p.y_mm - t.y_mm) as i64);
        let d = robovac::math::cost::isqrt_u64((dx * dx + dy * dy) as u64) as i64;
        let dt = robovac::localize::correlative::wrap_urad(p.theta_urad - t.theta_urad).abs();
        if d > 10 || dt > 8_727 {
            defmt::error!("{}: {} mm, {} urad off", what, d, dt);
            fail(what);
        }
        (d, dt / 1000)
    }

    /// The fine configuration space the mission builds on the prior (a
    /// call of its own, so its count does not move with this harness).
    #[inline(never)]
    fn build_fine(map: &EvidenceMap<{ evidence_bytes(W * H) }>, fine: &mut Grid<FW>) -> usize {
        if robovac::nav::cspace::build_fine(map, fine, CLEARANCE_MM, false).is_err() {
            fail("fine configuration space");
        }
        fine.cells() - fine.free_cells()
    }

    /// [`build_fine`] with the most zones a map holds (six no-go
    /// rectangles and two virtual walls across the flat), then none again:
    /// what the owner's zones cost per build.
    #[inline(never)]
    fn build_fine_zoned(
        map: &mut EvidenceMap<{ evidence_bytes(W * H) }>,
        fine: &mut Grid<FW>,
    ) -> usize {
        use robovac::grid::Zone;
        let rect = |x0_mm, y0_mm| Zone::NoGo {
            x0_mm,
            y0_mm,
            x1_mm: x0_mm + 600,
            y1_mm: y0_mm + 400,
        };
        let zones = [
            rect(1000, 1000),
            rect(3000, 1200),
            rect(5000, 800),
            rect(7000, 3000),
            rect(2000, 5000),
            rect(6000, 5500),
            Zone::Wall {
                ax_mm: 4000,
                ay_mm: 2000,
                bx_mm: 4000,
                by_mm: 4500,
            },
            Zone::Wall {
                ax_mm: 500,
                ay_mm: 3500,
                bx_mm: 3000,
                by_mm: 6000,
            },
        ];
        if map
            .set_zones(&zones, robovac::grid::zones::MARGIN_MM)
            .is_err()
        {
            fail("zones");
        }
        let blocked = build_fine(map, fine);
        if map.set_zones(&[], 0).is_err() {
            fail("zones");
        }
        blocked
    }

    /// One tracking match (1.1° off), and one wide match, the search a
    /// poor fit makes next (12° off: a slip burst on a turned pose).
    fn report_tracking(
        meter: &Meter,
        map: &EvidenceMap<{ evidence_bytes(W * H) }>,
        m: &mut ScanMatcher<MW>,
        truth: PoseU,
        pts: &[(i32, i32)],
    ) {
        m.points.set(off(truth, 30, -25, 20_000), pts);
        let (r, insn) = meter.measure(|| fusion::track(m, map, true));
        let Ok((mt, _)) = r else {
            fail("tracking match")
        };
        let (d, dt) = check(mt.pose, truth, "tracking match");
        defmt::println!(
            "localize: one match ({} points, {} on walls) in {} instructions; {} mm, {} mrad from the truth",
            m.points.as_slice().len(), mt.inliers, insn, d, dt
        );
        m.points.set(off(truth, 30, -25, -209_440), pts);
        let steps = fusion::WIDE_HEADING_STEPS;
        let (r, insn) = meter.measure(|| fusion::track_within(m, map, true, steps, true));
        let Ok((mt, _)) = r else { fail("wide match") };
        let (d, dt) = check(mt.pose, truth, "wide match");
        defmt::println!(
            "localize: one wide match (+-{} deg, a guess 12 deg off) in {} instructions; {} mm, {} mrad from the truth",
            steps, insn, d, dt
        );
    }

    fn report(
        meter: &Meter,
        map: &mut EvidenceMap<{ evidence_bytes(W * H) }>,
        m: &mut ScanMatcher<MW>,
        fine: &mut Grid<FW>,
    ) {
        let ((), insn) = meter.measure(|| load_map(map));
        defmt::println!(
            "localize: prior map 192x144 cells loaded in {} instructions",
            insn
        );
        let (ok, insn) = meter.measure(|| m.pyramid.build(map, true));
        if !ok {
            fail("coarse levels");
        }
        defmt::println!("localize: coarse levels built in {} instructions", insn);
        let (blocked, insn) = meter.measure(|| build_fine(map, fine));
        defmt::println!(
            "cspace: fine configuration space 192x144 ({} mm clearance, {} cells blocked) built in {} instructions",
            CLEARANCE_MM,
            blocked,
            insn
        );
        let (blocked, insn) = meter.measure(|| build_fine_zoned(map, fine));
        defmt::println!(
            "cspace: the same with 8 no-go zones and virtual walls ({} cells blocked) built in {} instructions",
            blocked,
            insn
        );
        let mut pts = [(0i32, 0i32); 512];
        let (truth, n) = load_scan(&mut pts);
        let pts = pts.get(..n).unwrap_or(&[]);
        report_tracking(meter, map, m, truth, pts);
        // Unknown mode's people filter, run on every revolution there
        // before the match (`ScanPoints::drop_foreground`).
        m.points.set(truth, pts);
        let kept = m.points.as_slice().len();
        let (dropped, insn) = meter.measure(|| m.points.drop_foreground());
        defmt::println!(
            "localize: people filter over {} points ({} dropped) in {} instructions",
            kept,
            dropped,
            insn
        );
        // And its trail filter (`ScanPoints::drop_on`), on a full trail:
        // the last 3.1 m driven, ending where the robot stands.
        m.points.set(truth, pts);
        for i in 0..robovac::localize::trail::TRAIL_LEN as i32 {
            m.trail.note((truth.x_mm - 3_100 + 100 * i, truth.y_mm));
        }
        let kept = m.points.as_slice().len();
        let (dropped, insn) = meter.measure(|| m.points.drop_on(&m.trail));
        defmt::println!(
            "localize: trail filter over {} points and {} samples ({} dropped) in {} instructions",
            kept,
            m.trail.len(),
            dropped,
            insn
        );
        m.trail.clear();
        m.points.set(off(truth, 150, -150, 174_533), pts);
        let (r, insn) = meter.measure(|| Fusion::new().relocalise(m, map, true, false));
        let Ok(p) = r else {
            fail("window relocalisation")
        };
        let (d, dt) = check(p, truth, "window relocalisation");
        defmt::println!(
            "localize: start relocalisation (+-240 mm, +-15 deg) in {} instructions; {} mm, {} mrad from the truth",
            insn, d, dt
        );
        m.points.set(PoseU::default(), pts);
        let ((r, insn), stack) =
            common::stack_depth(|| meter.measure(|| Fusion::new().relocalise(m, map, true, true)));
        let Ok(p) = r else {
            fail("global relocalisation")
        };
        let (d, dt) = check(p, truth, "global relocalisation");
        defmt::println!(
            "localize: whole-map relocalisation (48 m2 flat) in {} instructions and {} bytes of stack; {} mm, {} mrad from the truth",
            insn, stack, d, dt
        );
    }

    #[entry]
    fn main() -> ! {
        static mut MAP_EV: EvidenceMap<{ evidence_bytes(W * H) }> = EvidenceMap::new();
        static mut MATCHER: ScanMatcher<MW> = ScanMatcher::new();
        static mut FINE: Grid<FW> = Grid::new();
        let meter = common::start_meter();
        report(&meter, MAP_EV, MATCHER, FINE);
        defmt::println!(
            "localize memory: matcher {} bytes here, {} bytes for a 12x12 m home at 5 cm (asserted <= 16 KiB); evidence map {} bytes here",
            core::mem::size_of::<ScanMatcher<MW>>(),
            robovac::capacity::FW_MATCHER_BYTES,
            core::mem::size_of::<EvidenceMap<{ evidence_bytes(W * H) }>>()
        );
        defmt::println!("emulated localization run: all checks passed");
        exit(debug::EXIT_SUCCESS)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("emu_localize runs on the emulated Cortex-M4: bash scripts/emu.sh");
    std::process::exit(2);
}
