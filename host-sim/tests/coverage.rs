//! Complete coverage, checked independently: every plan's waypoints are
//! re-verified (no obstacle entered, no corner cut, every reachable cell
//! covered) and every metric is recomputed from the waypoints alone and
//! compared with what the planner reported.

use host_sim::capacity::{new_grid, HOST_WORDS};
use host_sim::io::maps::MapData;
use host_sim::run::plan::{new_planner, plan, plan_on, Plan, ALL_PLANNERS, SEED000_PLANNERS};
use proptest::prelude::*;
use robovac::coverage::{Coverage, PlannerKind, Step};
use robovac::verify::check::Checker;
use robovac::verify::metrics::SegmentKind;
use robovac::{Cell, Grid};

fn map_from_ascii(s: &str) -> MapData {
    let rows: Vec<&str> = s.lines().filter(|l| !l.is_empty()).collect();
    MapData {
        width: rows[0].len() as u32,
        height: rows.len() as u32,
        blocked: rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| b == b'#'))
            .collect(),
        cell_m: None,
        ..Default::default()
    }
}

/// The independent check of a plan (see the module docs).
fn check(map: &MapData, p: &Plan) {
    let mut grid = new_grid();
    map.to_grid(&mut *grid).unwrap();
    let wp = &p.waypoints;
    // segments tile the waypoints
    assert_eq!(
        p.segments.first().map(|s| s.from),
        if wp.len() > 1 { Some(0) } else { None }
    );
    for w in p.segments.windows(2) {
        assert_eq!(w[0].to, w[1].from);
    }
    if let Some(s) = p.segments.last() {
        assert_eq!(s.to, wp.len() - 1);
    }
    let mut ck: Box<Checker<HOST_WORDS>> = Box::new(Checker::new());
    ck.start(&*grid, p.start).unwrap();
    assert_eq!(wp[0], p.start);
    let (mut cover_len, mut transit_len, mut rot) = (0.0f64, 0.0f64, 0.0f64);
    let mut last_dir: Option<(f64, f64)> = None;
    for seg in &p.segments {
        for i in seg.from + 1..=seg.to {
            let starts = seg.kind == SegmentKind::Cover && i == seg.from + 1;
            ck.push(&*grid, wp[i], seg.kind, starts)
                .unwrap_or_else(|e| panic!("{:?}: {e:?}", p.kind));
            let (dx, dy) = (
                wp[i].x as f64 - wp[i - 1].x as f64,
                wp[i].y as f64 - wp[i - 1].y as f64,
            );
            let len = (dx * dx + dy * dy).sqrt();
            match seg.kind {
                SegmentKind::Cover => cover_len += len,
                SegmentKind::Transit => transit_len += len,
            }
            if let Some((px, py)) = last_dir {
                rot += (px * dy - py * dx).abs().atan2(px * dx + py * dy);
            }
            last_dir = Some((dx, dy));
        }
    }
    let c = ck.finish(&*grid);
    let m = &p.metrics;
    let name = p.kind.name();
    assert_eq!(c.missed_cells, 0, "{name}: reachable cells left uncovered");
    assert_eq!(c.reachable_cells, m.reachable_cells, "{name}: reachable");
    assert_eq!(c.covered_cells, m.covered_cells, "{name}: covered");
    assert_eq!(c.repeated_cells, m.repeated_cells, "{name}: repeated");
    assert_eq!(c.turns, m.turns, "{name}: turns");
    assert_eq!(c.segments, m.segments, "{name}: segments");
    assert!(
        (p.coverage() - 1.0).abs() < 1e-12,
        "{name}: coverage {}",
        p.coverage()
    );
    let cells = |v: u64| v as f64 / robovac::math::cost::COST_PER_CELL as f64;
    let tol = |x: f64| 1e-4 * x + 1e-3 * (p.waypoints.len() as f64).sqrt();
    assert!(
        (cells(m.coverage_path_cost) - cover_len).abs() <= tol(cover_len),
        "{name}: cover length {} vs {cover_len}",
        cells(m.coverage_path_cost)
    );
    assert!(
        (cells(m.backtrack_path_cost) - transit_len).abs() <= tol(transit_len),
        "{name}: transit length"
    );
    let rot_reported = m.rotation_urad as f64 * 1e-6;
    assert!(
        (rot_reported - rot).abs() <= 1e-5 * (m.turns as f64 + 1.0),
        "{name}: rotation {rot_reported} vs {rot}"
    );
    // the planner's moves, unmerged, give the same counts
    let mut ck2: Box<Checker<HOST_WORDS>> = Box::new(Checker::new());
    ck2.start(&*grid, p.start).unwrap();
    for w in &p.moves {
        ck2.push(&*grid, w.to, w.kind, w.starts_segment).unwrap();
    }
    let c2 = ck2.finish(&*grid);
    assert_eq!(
        (c2.covered_cells, c2.repeated_cells, c2.turns, c2.segments),
        (c.covered_cells, c.repeated_cells, c.turns, c.segments)
    );
}

fn check_all(map: &MapData, start: Option<Cell>) -> Vec<Plan> {
    ALL_PLANNERS
        .iter()
        .map(|&k| {
            let p = plan(map, k, start).unwrap_or_else(|e| panic!("{}: {e}", k.name()));
            check(map, &p);
            p
        })
        .collect()
}

const FLAT: &str = "
##########################
#..........#.............#
#..........#....####.....#
#...###....#....####.....#
#...###..................#
#..........#.............#
#####..#########..########
#........................#
#..##..........###.......#
#..##....#.....###.......#
#........#...............#
##########################
";

#[test]
fn flat_every_planner_complete() {
    let map = map_from_ascii(FLAT);
    let plans = check_all(&map, None);
    for p in &plans {
        assert!(p.metrics.segments >= 1);
        assert_eq!(
            p.metrics.reachable_cells as usize,
            map.blocked.iter().filter(|b| !**b).count()
        );
    }
}

#[test]
fn enclosed_pocket_is_not_reachable_and_not_missed() {
    // The 3x2 room in the middle is walled off: the run covers everything
    // else and reports coverage 1.0 of the reachable cells.
    let map = map_from_ascii(
        "
############
#..........#
#..#####...#
#..#...#...#
#..#...#...#
#..#####...#
#..........#
############
",
    );
    for p in check_all(&map, None) {
        assert_eq!(p.metrics.reachable_cells, 40);
    }
}

#[test]
fn one_cell_corridors() {
    let map = map_from_ascii(
        "
#############
#.#...#.....#
#.#.#.#.###.#
#.#.#.#.#...#
#...#...#.###
#####.###...#
#.........#.#
#############
",
    );
    check_all(&map, Some(Cell::new(1, 1)));
}

#[test]
fn movingai_and_table2_maps() {
    for m in ["rooms64", "maze49"] {
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join(format!("../maps/movingai/{m}.map"));
        let map = host_sim::io::maps::load_map(&path, Default::default()).unwrap();
        check_all(&map, None);
    }
    let mut rng = robovac::grid::maps::SplitMix64::new(5);
    for (_, w, h) in host_sim::run::bench::TABLE2_SIZES {
        for _ in 0..5 {
            let (map, start) = host_sim::run::bench::table2_instance(
                w,
                h,
                robovac::grid::maps::TABLE2_MAP,
                &mut rng,
            )
            .unwrap();
            check_all(&map, Some(start));
        }
    }
}

fn random_map(w: u32, h: u32, density: u32, seed: u64, kind: u8) -> MapData {
    let mut rng = robovac::grid::maps::SplitMix64::new(seed);
    let g: Box<Grid<{ 64 * 64 / 32 }>> = test_support::random_grid_with(w, h, density, &mut rng);
    let mut blocked: Vec<bool> = (0..h as i32)
        .flat_map(|y| (0..w as i32).map(move |x| (x, y)))
        .map(|(x, y)| g.is_blocked(x, y))
        .collect();
    let mut set = |x: u32, y: u32, b: bool| {
        if x < w && y < h {
            blocked[(y * w + x) as usize] = b;
        }
    };
    match kind % 3 {
        // an enclosed pocket: a ring of obstacles around a free interior
        1 if w >= 6 && h >= 6 => {
            let (x0, y0) = (rng.below(w - 5), rng.below(h - 5));
            for i in 0..5 {
                set(x0 + i, y0, true);
                set(x0 + i, y0 + 4, true);
                set(x0, y0 + i, true);
                set(x0 + 4, y0 + i, true);
            }
            for y in y0 + 1..y0 + 4 {
                for x in x0 + 1..x0 + 4 {
                    set(x, y, false);
                }
            }
        }
        // one-cell corridors: walls on every other column with one gap each
        2 => {
            for x in (1..w).step_by(2) {
                let gap = rng.below(h);
                for y in 0..h {
                    set(x, y, y != gap && rng.below(5) != 0);
                }
            }
        }
        _ => {}
    }
    MapData {
        width: w,
        height: h,
        blocked,
        cell_m: None,
        ..Default::default()
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    /// Every planner covers every reachable cell of random maps (with
    /// enclosed pockets and one-cell corridors), never enters an obstacle
    /// or cuts a corner, and reports metrics the checker reproduces.
    #[test]
    fn random_maps_complete_and_valid(w in 2u32..40, h in 2u32..40, density in 0u32..40, seed in any::<u64>(), kind in 0u8..3) {
        let map = random_map(w, h, density, seed, kind);
        prop_assume!(map.first_free().is_some());
        check_all(&map, None);
    }
}

#[test]
fn node_budget_bounds_every_call_and_changes_nothing() {
    let mut rng = robovac::grid::maps::SplitMix64::new(11);
    let (map, start) =
        host_sim::run::bench::table2_instance(30, 50, robovac::grid::maps::TABLE2_MAP, &mut rng)
            .unwrap();
    for kind in ALL_PLANNERS {
        let mut g1 = new_grid();
        map.to_grid(&mut *g1).unwrap();
        let full = plan_on(&mut g1, &mut new_planner(kind), start, u32::MAX).unwrap();
        for budget in [1u32, 7, 50] {
            let mut g2 = new_grid();
            map.to_grid(&mut *g2).unwrap();
            let p = plan_on(&mut g2, &mut new_planner(kind), start, budget).unwrap();
            assert!(
                p.max_nodes_per_call <= budget as u64,
                "{}: {} > {budget}",
                kind.name(),
                p.max_nodes_per_call
            );
            assert_eq!(p.moves, full.moves, "{} budget {budget}", kind.name());
        }
    }
}

/// The planner's search state is lent to the mission's fine searches
/// (issue 11 §3). Taken in the middle of a transit search, the planner
/// notices (the state's query id changed) and searches again: the same
/// waypoints as a run whose state nobody took.
#[test]
fn lending_the_search_state_mid_search_changes_nothing() {
    let mut rng = robovac::grid::maps::SplitMix64::new(11);
    let (map, start) =
        host_sim::run::bench::table2_instance(30, 50, robovac::grid::maps::TABLE2_MAP, &mut rng)
            .unwrap();
    let small = {
        let mut g = Grid::<HOST_WORDS>::new();
        g.reset(8, 8).unwrap();
        g
    };
    for kind in ALL_PLANNERS {
        let run = |lend: bool| {
            let mut g = new_grid();
            map.to_grid(&mut *g).unwrap();
            let mut p = new_planner(kind);
            p.start(&mut *g, start).unwrap();
            let (mut moves, mut lent, mut may_lend) = (Vec::new(), 0, lend);
            loop {
                match p.step(&mut *g, 7).unwrap() {
                    Step::Move(w) => {
                        moves.push(w.to);
                        may_lend = lend;
                    }
                    Step::Done => return (moves, lent),
                    // Once per transit: a search taken at every step would
                    // never finish (the executive only lends the state while
                    // the planner waits).
                    Step::Pending if may_lend => {
                        let st = p.search_state_mut();
                        st.search(
                            &small,
                            Cell::new(0, 0),
                            &[Cell::new(7, 7)],
                            robovac::Algo::AStar,
                        )
                        .unwrap();
                        lent += 1;
                        may_lend = false;
                    }
                    Step::Pending => {}
                }
            }
        };
        let (plain, _) = run(false);
        let (taken, lent) = run(true);
        assert!(
            lent > 0,
            "{}: no search was long enough to be taken",
            kind.name()
        );
        assert_eq!(plain, taken, "{}", kind.name());
    }
}

#[test]
fn full_list_keeps_coverage_complete() {
    // A backtracking list of 4 points overflows constantly; the rescan
    // policy still covers everything.
    type Tiny = Coverage<4096, 128, 4096, 4, 4096, 4096>;
    let mut rng = robovac::grid::maps::SplitMix64::new(3);
    for kind in ALL_PLANNERS {
        let (map, start) = host_sim::run::bench::table2_instance(
            30,
            50,
            robovac::grid::maps::TABLE2_MAP,
            &mut rng,
        )
        .unwrap();
        let mut grid: Box<Grid<128>> = Box::new(Grid::new());
        map.to_grid(&mut *grid).unwrap();
        let mut p: Box<Tiny> = Box::new(Tiny::new(kind));
        let mut ck: Box<Checker<128>> = Box::new(Checker::new());
        ck.start(&*grid, start).unwrap();
        let mut moves = Vec::new();
        let stats = p.run(&mut *grid, start, |w| moves.push(w)).unwrap();
        for w in &moves {
            ck.push(&*grid, w.to, w.kind, w.starts_segment).unwrap();
        }
        let c = ck.finish(&*grid);
        assert_eq!(c.missed_cells, 0, "{}", kind.name());
        assert!(
            stats.list_overflows > 0,
            "{}: the list never filled",
            kind.name()
        );
    }
}

#[test]
fn obstacles_appearing_mid_run_are_handled_without_restart() {
    let map = map_from_ascii(FLAT);
    for kind in ALL_PLANNERS {
        let mut grid = new_grid();
        map.to_grid(&mut *grid).unwrap();
        let mut p = new_planner(kind);
        let start = Cell::new(1, 1);
        p.start(&mut *grid, start).unwrap();
        let mut moves = Vec::new();
        let mut added = Vec::new();
        for n in 0.. {
            if n == 60 || n == 120 {
                // a chair appears on two uncovered free cells
                let mut k = 0;
                'find: for y in 1..11 {
                    for x in 1..25 {
                        if grid.is_free(x, y)
                            && !grid.get(robovac::grid::Layer::Covered, x, y)
                            && (x + y + n) % 7 == 0
                        {
                            grid.set_obstacle(x, y, true).unwrap();
                            added.push(Cell::new(x as u16, y as u16));
                            k += 1;
                            if k == 2 {
                                break 'find;
                            }
                        }
                    }
                }
            }
            match p.step(&mut *grid, u32::MAX).unwrap() {
                Step::Move(w) => moves.push(w),
                Step::Pending => {}
                Step::Done => break,
            }
        }
        assert!(!added.is_empty());
        // Checked against the final map: nothing entered the new obstacles,
        // and every cell still reachable was covered.
        let mut ck: Box<Checker<HOST_WORDS>> = Box::new(Checker::new());
        ck.start(&*grid, start).unwrap();
        for w in &moves {
            ck.push(&*grid, w.to, w.kind, w.starts_segment)
                .unwrap_or_else(|e| panic!("{}: {e:?}", kind.name()));
        }
        assert_eq!(ck.finish(&*grid).missed_cells, 0, "{}", kind.name());
    }
}

#[test]
fn papers_claims_hold_in_direction_on_wide_maps() {
    // A small Table 2 run: our variant cuts repeated travel against B-OHA*.
    let rows = host_sim::run::bench::table2(
        20,
        9,
        robovac::grid::maps::TABLE2_MAP,
        |_, _, _, _| {},
        |_, _| {},
    )
    .unwrap();
    for (label, _, _) in host_sim::run::bench::TABLE2_SIZES {
        let get = |k: PlannerKind, m: &str| {
            rows.iter()
                .find(|r| r.0 == label && r.1 == k)
                .unwrap()
                .2
                .mean(m)
        };
        for k in SEED000_PLANNERS {
            assert_eq!(
                rows.iter()
                    .find(|r| r.0 == label && r.1 == k)
                    .unwrap()
                    .2
                    .min_coverage,
                1.0
            );
        }
        assert!(
            get(PlannerKind::BOhaPc, "backtrack_path_length")
                < get(PlannerKind::BOha, "backtrack_path_length")
        );
    }
}

/// The same floor in every supported format plans completely.
#[test]
fn every_format_plans_completely() {
    let map = map_from_ascii(FLAT);
    let dir = std::env::temp_dir().join(format!("robovac-formats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (w, h) = (map.width, map.height);
    // ASCII
    std::fs::write(dir.join("flat.txt"), map.to_ascii()).unwrap();
    // MovingAI
    let mut mai = format!("type octile\nheight {h}\nwidth {w}\nmap\n");
    for line in map.to_ascii().lines() {
        mai += &line.replace('#', "@");
        mai.push('\n');
    }
    std::fs::write(dir.join("flat.map"), mai).unwrap();
    // ROS YAML + PGM (254 free, 0 wall), and PNG (RGBA), both 2x2 pixels a cell
    let px: Vec<u8> = (0..2 * h)
        .flat_map(|y| (0..2 * w).map(move |x| (x / 2, y / 2)))
        .map(|(x, y)| {
            if map.is_blocked(x as i32, y as i32) {
                0u8
            } else {
                254
            }
        })
        .collect();
    let mut pgm = format!("P5\n{} {}\n255\n", 2 * w, 2 * h).into_bytes();
    pgm.extend(&px);
    std::fs::write(dir.join("flat.pgm"), pgm).unwrap();
    std::fs::write(dir.join("flat.yaml"), "image: flat.pgm\nresolution: 0.15\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n").unwrap();
    let f = std::fs::File::create(dir.join("flat.png")).unwrap();
    let mut e = png::Encoder::new(std::io::BufWriter::new(f), 2 * w, 2 * h);
    e.set_color(png::ColorType::Rgba);
    e.set_depth(png::BitDepth::Eight);
    let rgba: Vec<u8> = px.iter().flat_map(|&v| [v, v, v, 255]).collect();
    e.write_header().unwrap().write_image_data(&rgba).unwrap();
    for (file, cell) in [
        ("flat.txt", None),
        ("flat.map", None),
        ("flat.yaml", Some(0.3)),
        ("flat.png", Some(0.3)),
    ] {
        let opts = host_sim::io::maps::LoadOptions {
            cell_m: cell,
            png_resolution_m: Some(0.15),
        };
        let m = host_sim::io::maps::load_map(&dir.join(file), opts).unwrap();
        assert_eq!(m.blocked, map.blocked, "{file}");
        for p in check_all(&m, None) {
            assert_eq!(p.metrics.covered_cells, p.metrics.reachable_cells, "{file}");
        }
    }
}

/// The mission's room tour turns B-OHA*'s lanes along a room's long axis
/// (`Coverage::sweep_columns`): on a wide open map, columns when asked,
/// rows by the map's own aspect; complete either way. Planners with a
/// fixed priority ignore it.
#[test]
fn sweep_direction_can_be_set_after_start() {
    let map = map_from_ascii(&format!(
        "{}\n{}{}",
        "#".repeat(22),
        format!("#{}#\n", ".".repeat(20)).repeat(8),
        "#".repeat(22)
    ));
    // Cover moves along x and along y.
    let lanes = |kind: PlannerKind, columns: Option<bool>| {
        let mut grid = new_grid();
        map.to_grid(&mut *grid).unwrap();
        let mut p = new_planner(kind);
        let start = Cell::new(1, 1);
        p.start(&mut *grid, start).unwrap();
        if let Some(c) = columns {
            p.sweep_columns(c);
        }
        let (mut ck, mut at) = (Box::new(Checker::<HOST_WORDS>::new()), start);
        ck.start(&*grid, start).unwrap();
        let (mut along_x, mut along_y) = (0, 0);
        loop {
            let w = match p.step(&mut *grid, u32::MAX).unwrap() {
                Step::Move(w) => w,
                Step::Pending => continue,
                Step::Done => break,
            };
            ck.push(&*grid, w.to, w.kind, w.starts_segment).unwrap();
            if w.kind == SegmentKind::Cover {
                along_x += (w.to.x as i32 - at.x as i32).abs();
                along_y += (w.to.y as i32 - at.y as i32).abs();
            }
            at = w.to;
        }
        assert_eq!(ck.finish(&*grid).missed_cells, 0, "{}", kind.name());
        (along_x, along_y)
    };
    let (x, y) = lanes(PlannerKind::BOha, None);
    assert!(x > 5 * y, "rows by aspect: {x} {y}");
    let (x, y) = lanes(PlannerKind::BOha, Some(true));
    assert!(y > 3 * x, "columns when asked: {x} {y}");
    let (x, y) = lanes(PlannerKind::BOha, Some(false));
    assert!(x > 5 * y, "rows when asked: {x} {y}");
    assert_eq!(
        lanes(PlannerKind::BaStar, Some(true)),
        lanes(PlannerKind::BaStar, None),
        "a fixed priority is kept"
    );
}
