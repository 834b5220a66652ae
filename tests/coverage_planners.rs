//! The rules of the seeds' coverage planners, each checked on a small map
//! where the right move is known by hand (completeness and validity on
//! random maps are host-sim's property tests, over every planner).

mod common;

use common::*;
use proptest::prelude::*;
use robovac::coverage::planners::{bcd, binn, mark_backtrack, regions, stc, template, wavefront};
use robovac::coverage::CoverageError;
use robovac::coverage::{BacktrackList, Coverage, PlannerKind, Step};
use robovac::grid::Layer;
use robovac::Cell;
use std::collections::VecDeque;

type TCoverage = Coverage<CELLS, W, CELLS, 256, 1024, CELLS>;

fn grid(ascii: &str) -> Box<TGrid> {
    let mut g = Box::new(TGrid::new());
    g.load_ascii(ascii).unwrap();
    g
}

/// The first `n` cover moves of a planner from `start`.
fn first_moves(g: &mut TGrid, kind: PlannerKind, start: Cell, n: usize) -> Vec<(u16, u16)> {
    let mut p: Box<TCoverage> = Box::new(TCoverage::new(kind));
    p.start(g, start).unwrap();
    let mut out = Vec::new();
    while out.len() < n {
        match p.step(g, u32::MAX).unwrap() {
            Step::Move(w) => out.push((w.to.x, w.to.y)),
            Step::Pending => {}
            Step::Done => break,
        }
    }
    out
}

const OPEN: &str = "......\n......\n......\n......\n......\n";

#[test]
fn template_runs_left_then_down_then_up_then_right() {
    let mut g = grid(OPEN);
    // TL to the wall, TD to the wall, TR one step, TU up one (TU outranks
    // TR), and at (1, 3), where left, down and up are covered, TR.
    let m = first_moves(&mut g, PlannerKind::Template, Cell::new(3, 2), 8);
    assert_eq!(
        m,
        [
            (2, 2),
            (1, 2),
            (0, 2),
            (0, 3),
            (0, 4),
            (1, 4),
            (1, 3),
            (2, 3)
        ]
    );
}

#[test]
fn template_keeps_edge_and_corner_cells_only() {
    let mut g = grid(OPEN);
    g.set(Layer::Covered, 0, 0, true).unwrap();
    let mut list: BacktrackList<64, W> = BacktrackList::new();
    for c in [(1, 0), (2, 2), (5, 4), (3, 1)] {
        list.push(&*g, Cell::new(c.0, c.1));
    }
    template::prune_list(&mut list, &*g);
    // (1, 0) borders the covered cell and the map's edge, (5, 4) is a
    // corner; (2, 2) and (3, 1) lie inside the uncovered area.
    assert_eq!(list.as_slice(), &[Cell::new(1, 0), Cell::new(5, 4)]);
    assert!(!template::is_edge(&*g, 2, 2));
}

#[test]
fn mark_backtrack_marks_north_corner_ahead_of_an_obstacle() {
    // Moving east along row 2: the cell ahead (3, 2) and north (2, 1) are
    // free and uncovered, the north-east diagonal (3, 1) is a wall.
    let g = grid("......\n...#..\n......\n...#..\n......\n");
    let mut list: BacktrackList<64, W> = BacktrackList::new();
    mark_backtrack::push_marks(&mut list, &*g, Cell::new(2, 2), (1, 0));
    assert_eq!(list.as_slice(), &[Cell::new(2, 1), Cell::new(2, 3)]);
    // Moving north sets no marks; moving west past no wall neither.
    let mut none: BacktrackList<64, W> = BacktrackList::new();
    mark_backtrack::push_marks(&mut none, &*g, Cell::new(2, 2), (0, -1));
    mark_backtrack::push_marks(&mut none, &*g, Cell::new(1, 2), (-1, 0));
    assert!(none.is_empty());
}

#[test]
fn mark_backtrack_goes_to_a_north_point_before_a_nearer_south_point() {
    let mut g = grid(OPEN);
    for x in 0..6 {
        g.set(Layer::Covered, x, 2, true).unwrap();
    }
    // (0, 1) is a north point (covered below), (4, 3) a south point.
    let pts = [Cell::new(4, 3), Cell::new(0, 1)];
    let from = Cell::new(5, 2);
    assert_eq!(mark_backtrack::kind(&*g, pts[1]), 0);
    assert_eq!(mark_backtrack::kind(&*g, pts[0]), 1);
    assert_eq!(
        mark_backtrack::choose(&pts, &*g, from),
        Some(Cell::new(0, 1))
    );
    assert_eq!(
        mark_backtrack::choose(&pts[..1], &*g, from),
        Some(Cell::new(4, 3))
    );
}

#[test]
fn mark_backtrack_sweeps_east_first() {
    let mut g = grid(OPEN);
    let m = first_moves(&mut g, PlannerKind::MarkBacktrack, Cell::new(0, 4), 6);
    assert_eq!(m, [(1, 4), (2, 4), (3, 4), (4, 4), (5, 4), (5, 3)]);
}

#[test]
fn binn_goes_straight_and_turns_toward_more_activity() {
    let mut g = grid(OPEN);
    let pri = [(0, -1), (0, 1), (1, 0), (-1, 0)];
    // Straight on beats the priority order's north.
    let c = Cell::new(2, 2);
    assert_eq!(binn::next_move(&*g, c, (1, 0), &pri), Some(Cell::new(3, 2)));
    // Blocked ahead: a quarter turn, toward the side with more uncovered
    // neighbours (south: row 4 is uncovered, row 0 is covered).
    g.set_obstacle(3, 2, true).unwrap();
    for x in 0..6 {
        g.set(Layer::Covered, x, 0, true).unwrap();
    }
    assert_eq!(binn::next_move(&*g, c, (1, 0), &pri), Some(Cell::new(2, 3)));
    assert!(binn::activity_q8(&*g, 2, 3) > binn::activity_q8(&*g, 2, 1));
    // Turning back comes last.
    g.set_obstacle(2, 3, true).unwrap();
    g.set_obstacle(2, 1, true).unwrap();
    assert_eq!(binn::next_move(&*g, c, (1, 0), &pri), Some(Cell::new(1, 2)));
}

/// A random map of `w` × `h` cells, `density` % blocked (single cells).
fn random_grid(w: u32, h: u32, density: u32, seed: u64) -> Box<TGrid> {
    let mut g = Box::new(TGrid::new());
    g.reset(w, h).unwrap();
    let mut s = seed | 1;
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            if (s % 100) < density as u64 {
                g.set_obstacle(x, y, true).unwrap();
            }
        }
    }
    g
}

/// An independent 4-connected BFS from `s` (None where unreached).
fn bfs(g: &TGrid, s: Cell) -> Vec<Option<u32>> {
    let (w, h) = (g.width() as i32, g.height() as i32);
    let mut d = vec![None; (w * h) as usize];
    let mut q = VecDeque::new();
    d[(s.y as i32 * w + s.x as i32) as usize] = Some(0);
    q.push_back((s.x as i32, s.y as i32));
    while let Some((x, y)) = q.pop_front() {
        let v = d[(y * w + x) as usize].unwrap();
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (nx, ny) = (x + dx, y + dy);
            if free(g, nx, ny) && d[(ny * w + nx) as usize].is_none() {
                d[(ny * w + nx) as usize] = Some(v + 1);
                q.push_back((nx, ny));
            }
        }
    }
    d
}

/// Every cover move of a whole run: (moves, transit moves).
fn run_all(g: &mut TGrid, kind: PlannerKind, start: Cell) -> (Vec<Cell>, usize) {
    let mut p: Box<TCoverage> = Box::new(TCoverage::new(kind));
    let mut cover = Vec::new();
    let mut transit = 0;
    p.run(g, start, |w| {
        if w.kind == robovac::verify::metrics::SegmentKind::Cover {
            cover.push(w.to);
        } else {
            transit += 1;
        }
    })
    .unwrap();
    (cover, transit)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]
    /// The wavefront's raster passes give the BFS step distance exactly.
    #[test]
    fn wavefront_transform_is_the_bfs_distance(w in 1u32..40, h in 1u32..40, density in 0u32..45, seed in any::<u64>(), pick in any::<u32>()) {
        let g = random_grid(w, h, density, seed);
        let frees: Vec<Cell> = (0..w * h).map(|i| Cell::new((i % w) as u16, (i / w) as u16)).filter(|c| free(&g, c.x as i32, c.y as i32)).collect();
        prop_assume!(!frees.is_empty());
        let goal = frees[pick as usize % frees.len()];
        let mut field = vec![0u16; (w * h) as usize];
        wavefront::build(&*g, &mut field, goal);
        for (i, d) in bfs(&g, goal).iter().enumerate() {
            prop_assert_eq!(u32::from(field[i]), d.unwrap_or(u32::from(wavefront::UNREACHED)));
        }
    }

    /// On maps made of whole 2 × 2 blocks, spanning-tree coverage visits
    /// every cell of the start's group exactly once, with no transit.
    #[test]
    fn stc_visits_each_cell_of_whole_blocks_once(mw in 1u32..12, mh in 1u32..12, density in 0u32..40, seed in any::<u64>()) {
        let blocks = random_grid(mw, mh, density, seed);
        let mut g = Box::new(TGrid::new());
        g.reset(2 * mw, 2 * mh).unwrap();
        for y in 0..2 * mh as i32 {
            for x in 0..2 * mw as i32 {
                g.set_obstacle(x, y, blocks.is_blocked(x / 2, y / 2)).unwrap();
            }
        }
        let Some(start) = (0..4 * mw * mh).map(|i| Cell::new((i % (2 * mw)) as u16, (i / (2 * mw)) as u16)).find(|c| free(&g, c.x as i32, c.y as i32)) else {
            return Ok(());
        };
        let reach = bfs(&g, start).iter().filter(|d| d.is_some()).count();
        let (cover, transit) = run_all(&mut g, PlannerKind::Stc, start);
        prop_assert_eq!(transit, 0);
        prop_assert_eq!(cover.len() + 1, reach);
        let mut seen = std::collections::HashSet::new();
        seen.insert(start);
        for c in &cover {
            prop_assert!(seen.insert(*c), "{:?} visited twice", c);
        }
    }

    /// Every decomposition cell is one run per column, its runs in
    /// consecutive columns, each overlapping the next.
    #[test]
    fn bcd_cells_are_monotone_stacks_of_runs(w in 1u32..40, h in 1u32..40, density in 0u32..45, seed in any::<u64>()) {
        let g = random_grid(w, h, density, seed);
        let mut field = vec![0u16; (w * h) as usize];
        bcd::build(&*g, &mut field);
        let mut runs: std::collections::BTreeMap<u16, Vec<(i32, i32, i32)>> = Default::default();
        for x in 0..w as i32 {
            for y in 0..h as i32 {
                let l = bcd::label(&*g, &field, x, y);
                prop_assert_eq!(l == 0, !free(&g, x, y));
                if l == 0 { continue; }
                let v = runs.entry(l).or_default();
                match v.last_mut() {
                    Some((cx, _, b)) if *cx == x && *b == y - 1 => *b = y,
                    _ => v.push((x, y, y)),
                }
            }
        }
        for v in runs.values() {
            for pair in v.windows(2) {
                let ((x0, a0, b0), (x1, a1, b1)) = (pair[0], pair[1]);
                prop_assert_eq!(x1, x0 + 1, "one run per column, columns consecutive");
                prop_assert!(a1 <= b0 && a0 <= b1, "consecutive runs overlap");
            }
        }
    }
}

#[test]
fn wavefront_sweeps_the_far_end_first_and_ends_near_the_start() {
    let mut g = grid("........\n........\n");
    let (cover, _) = run_all(&mut g, PlannerKind::Wavefront, Cell::new(0, 0));
    // Both neighbours of the start are one step away: the order N, S, E,
    // W breaks the tie. Then the highest value leads east along row 1, to
    // the far end, and the sweep comes back along row 0 to the start.
    assert_eq!(cover.first(), Some(&Cell::new(0, 1)));
    assert_eq!(cover.len(), 15);
    assert_eq!(cover[7], Cell::new(7, 1));
    assert_eq!(cover.last(), Some(&Cell::new(1, 0)));
}

#[test]
fn bcd_splits_around_an_island_into_four_cells() {
    let g = grid("......\n......\n..##..\n......\n......\n");
    let mut field = vec![0u16; 30];
    bcd::build(&*g, &mut field);
    let l = |x, y| bcd::label(&*g, &field, x, y);
    // West of the island, above it, below it, east of it.
    assert_eq!((l(0, 0), l(1, 4)), (1, 1));
    assert_eq!((l(2, 0), l(3, 1)), (2, 2));
    assert_eq!((l(2, 3), l(3, 4)), (3, 3));
    assert_eq!((l(4, 2), l(5, 0)), (4, 4));
}

#[test]
fn field_planners_refuse_a_build_without_a_field() {
    let mut g = grid(OPEN);
    for kind in [PlannerKind::Wavefront, PlannerKind::Stc, PlannerKind::Bcd] {
        let mut p: Box<Coverage<CELLS, W, CELLS, 256, 1024>> = Box::new(Coverage::new(kind));
        assert_eq!(
            p.start(&mut *g, Cell::new(0, 0)),
            Err(CoverageError::NoField)
        );
    }
    let mut p: Box<Coverage<CELLS, W, CELLS, 256, 1024>> =
        Box::new(Coverage::new(PlannerKind::Binn));
    assert!(p.start(&mut *g, Cell::new(0, 0)).is_ok());
    let _ = stc::RULES;
}

#[test]
fn regions_comb_the_inside_of_a_u_and_spiral_elsewhere() {
    // A U open to the south stands free; a wall joined to the edge at the
    // right is boundary, not furniture.
    let g = grid("..........\n.#####...#\n.#...#...#\n.#...#...#\n.......###\n..........\n");
    let mut field = vec![0u16; 60];
    regions::build(&*g, &mut field);
    let class = |x: i32, y: i32| bcd::label(&*g, &field, x, y);
    for (x, y) in [(2, 2), (3, 3), (4, 2)] {
        assert_eq!(class(x, y), regions::COMB_NS, "({x}, {y})");
    }
    for (x, y) in [(0, 0), (7, 2), (3, 5), (0, 4)] {
        assert_eq!(class(x, y), regions::SPIRAL, "({x}, {y})");
    }
}

proptest! {
    /// The pseudo-angle grows with the true angle, counter-clockwise from
    /// east, and stays within one turn.
    #[test]
    fn pseudo_angle_is_monotone_in_the_angle(a in (-200i64..200, -200i64..200), b in (-200i64..200, -200i64..200)) {
        prop_assume!(a != (0, 0) && b != (0, 0));
        let t = |p: (i64, i64)| (p.1 as f64).atan2(p.0 as f64).rem_euclid(std::f64::consts::TAU);
        let (pa, pb) = (regions::pseudo_angle(a.0, a.1), regions::pseudo_angle(b.0, b.1));
        prop_assert!((0..4096).contains(&pa));
        if t(a) + 1e-9 < t(b) {
            prop_assert!(pa <= pb, "{:?} {} vs {:?} {}", a, pa, b, pb);
        }
    }
}

/// Steps the planner until it reports `Done` (bounded); the cover moves.
fn until_done(g: &mut TGrid, p: &mut TCoverage) -> Vec<Cell> {
    let mut cover = Vec::new();
    for _ in 0..100_000 {
        match p.step(g, u32::MAX).unwrap() {
            Step::Move(w) if w.kind == robovac::verify::metrics::SegmentKind::Cover => {
                cover.push(w.to)
            }
            Step::Move(_) | Step::Pending => {}
            Step::Done => return cover,
        }
    }
    panic!("the planner never finished");
}

/// A room whose door is shut while the planner works (a person standing in
/// it, mapped): the goals behind it are abandoned when the search finds no
/// way, and the plan ends with the room uncovered. Once the door opens,
/// `retry_abandoned` forgets them and the planner, taken up again, covers
/// the room: the late retry the mission makes after its edge pass (unknown
/// mode), checked here on the planner alone, cell by cell.
#[test]
fn goals_behind_a_shut_door_are_abandoned_then_retried_once_it_opens() {
    let mut g = grid(
        "....#....\n\
         ....#....\n\
         ....#....\n\
         ....#....\n",
    );
    let mut p: Box<TCoverage> = Box::new(TCoverage::new(PlannerKind::BOha));
    p.start(&mut g, Cell::new(0, 0)).unwrap();
    let first = until_done(&mut g, &mut p);
    assert!(first.iter().all(|c| c.x < 4), "{first:?}");
    assert!(p.stats().abandoned_goals > 0, "{:?}", p.stats());
    let uncovered = |g: &TGrid| -> Vec<(i32, i32)> {
        (0..4)
            .flat_map(|y| (0..9).map(move |x| (x, y)))
            .filter(|&(x, y)| g.is_free(x, y) && !g.get(Layer::Covered, x, y))
            .collect()
    };
    assert_eq!(uncovered(&g).len(), 16, "the room behind the door");
    // Without a retry the plan stays finished.
    assert_eq!(until_done(&mut g, &mut p), vec![]);
    // The door opens; the abandoned goals are tried again.
    g.set_obstacle(4, 1, false).unwrap();
    let at = p.position();
    assert!(p.retry_abandoned(at) > 0);
    let second = until_done(&mut g, &mut p);
    assert!(second.iter().any(|c| c.x > 4), "{second:?}");
    assert_eq!(uncovered(&g), vec![], "every free cell covered");
}
