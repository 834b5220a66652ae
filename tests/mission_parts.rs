//! The executive's building blocks, checked independently: the safety
//! guard's geometry, the configuration space's clearance, the planning
//! cells' anchors, the stale-leg test's flicker tolerance, and the edge
//! pass (every reachable boundary cell visited, moves between neighbours,
//! never into an obstacle, what it never drove given back).

use robovac::grid::{Cell, Grid, Layer};
use robovac::nav::cspace::{self, build_fine, coarse_anchor, disc_blocked, update_coarse};
use robovac::nav::edge::{is_boundary, EdgePass, EdgeStep};
use robovac::nav::geometry::{explained, segment_clear, segment_surely_clear, wall_offset};
use robovac::nav::guard::{free_distance_mm, limit_speed, GuardParams, MappedFree};
use robovac::robot::lidar_map::{evidence_bytes, CellState, EvidenceMap};
use robovac::search::WindowSearch;

type G = Grid<{ robovac::math::bits::words_for(120 * 100) }>;
type S = WindowSearch<{ 120 * 100 }, { robovac::math::bits::words_for(120 * 100) }>;
type St = robovac::SearchState<{ 120 * 100 }, { robovac::math::bits::words_for(120 * 100) }, 4096>;

const GUARD: GuardParams = GuardParams {
    radius_mm: 165,
    brake_mm_s2: 500,
    reserve_mm: 20,
    creep_mm_s: 40,
    moving_margin_mm: 60,
    mapped_slack_mm: 0,
};

#[test]
fn guard_free_distance_is_the_disc_geometry() {
    // Two points straight ahead at 500 mm: the front of the body (165 mm)
    // touches after 335 mm.
    let pts = [(500, 0), (501, 0)];
    assert_eq!(free_distance_mm(pts.iter().copied(), 165, true), 336);
    // Off to the side by 100 mm: the chord is √(165² − 100²) ≈ 131 mm.
    let pts = [(500, 100), (500, 100)];
    assert_eq!(free_distance_mm(pts.iter().copied(), 165, true), 500 - 131);
    // Beside the body (|y| ≥ r) or behind: nothing in the way.
    let pts = [(300, 165), (300, -170), (-200, 0), (-300, 10)];
    assert_eq!(free_distance_mm(pts.iter().copied(), 165, true), i32::MAX);
    // Backing up sees the points behind (the second nearest counts:
    // 300 − √(165² − 10²) = 136).
    assert_eq!(free_distance_mm(pts.iter().copied(), 165, false), 136);
    // One stray point (range noise) alone does not stop the robot.
    let pts = [(200, 0), (900, 0), (901, 0)];
    assert_eq!(free_distance_mm(pts.iter().copied(), 165, true), 900 - 165);
}

#[test]
fn guard_speed_brakes_in_time() {
    // v² = 2·a·(free − reserve): 480 mm of room at 500 mm/s² → 692 mm/s.
    assert_eq!(limit_speed(&GUARD, 300, 500), 300);
    assert_eq!(limit_speed(&GUARD, 300, 20 + 81), 284);
    // Below the creep speed: stop.
    assert_eq!(limit_speed(&GUARD, 300, 21), 0);
    assert_eq!(limit_speed(&GUARD, -100, 0), 0);
    assert_eq!(limit_speed(&GUARD, 0, 1000), 0);
    // Never faster than asked, either way.
    assert_eq!(limit_speed(&GUARD, -100, 10_000), -100);
}

/// The corner the guard must see (every wall contact in the real homes
/// was one): the robot drives east 161 mm beside the line of a table's
/// south face, so its body (165 mm) will touch the table's corner. The
/// hits on the table, judged a noise σ (10 mm) inside the corridor's edge
/// as the guard judges mapped points, all lie beyond that edge: the
/// corner goes unseen. The wall points they stand for ([`wall_offset`])
/// are judged at full width and stop the robot short of the corner.
#[test]
fn the_guard_sees_a_corner_through_the_wall_points_of_its_hits() {
    let map = room();
    // The table's south-west corner, world mm (cells 50..70 × 40..52).
    let corner = (2500, 2400);
    let robot = (2000, corner.1 - 161);
    // Hits along the west face and the south face, ±8 mm of range noise
    // along each beam (the LD06's is about ±10 mm).
    let mut hits = Vec::new();
    for k in 0..12 {
        let noise = [-8, -3, 2, 8][k % 4];
        for q in [
            (corner.0, corner.1 + 20 + 40 * k as i32),
            (corner.0 + 20 + 40 * k as i32, corner.1),
        ] {
            let (dx, dy) = ((q.0 - robot.0) as f64, (q.1 - robot.1) as f64);
            let d = dx.hypot(dy);
            let k = (d + noise as f64) / d;
            hits.push((robot.0 + (dx * k) as i32, robot.1 + (dy * k) as i32));
        }
    }
    // Robot frame (heading east): x forward, y left.
    let local = |q: (i32, i32)| (q.0 - robot.0, q.1 - robot.1);
    let raw = hits.iter().map(|&q| local(q));
    assert_eq!(free_distance_mm(slack_rule(raw), 167, true), i32::MAX);
    let walls: Vec<(i32, i32)> = hits
        .iter()
        .filter_map(|&q| {
            let [dx, dy] = wall_offset(&*map, q, robot, 25, false)?;
            Some(local((q.0 + dx as i32, q.1 + dy as i32)))
        })
        .collect();
    assert_eq!(walls.len(), hits.len());
    // The corner itself, 500 mm ahead and 161 mm to the left: the body
    // touches it after 500 − √(167² − 161²) = 456 mm.
    assert!(walls.contains(&(500, 161)));
    assert_eq!(free_distance_mm(walls.into_iter(), 167, true), 456);
}

/// A wall the map holds only weakly (its cells not yet occupied, as a
/// diagonal wall's staircase or a wall not yet mapped): its hits are
/// mapped but stand for no wall point. The robot drives east toward such
/// a wall closing in on its left at 1 in 4. Judged a noise σ (10 mm)
/// inside the corridor's edge, as until stop 59, the guard would let the
/// body drive on into it; judged at full width ([`MappedFree`]) it stops
/// where the body meets the wall. Checked on the geometry: how many hits
/// the body, moved that far, would overlap.
#[test]
fn the_guard_judges_hits_without_a_wall_point_at_full_width() {
    let mut map = room();
    let robot = (1000, 1500);
    let hits: Vec<(i32, i32)> = (0..60)
        .map(|k| (robot.0 + 300 + 20 * k, robot.1 + 300 - (300 + 20 * k) / 4))
        .collect();
    for &(x, y) in &hits {
        let (cx, cy) = map.cell_of(x, y);
        map.set_state(cx, cy, CellState::Unknown);
    }
    for &q in &hits {
        assert!(explained(&*map, q) && wall_offset(&*map, q, robot, 25, false).is_none());
    }
    let local: Vec<(i32, i32)> = hits
        .iter()
        .map(|q| (q.0 - robot.0, q.1 - robot.1))
        .collect();
    let overlapped = |d: i32| {
        let inside = |&&(x, y): &&(i32, i32)| ((x - d) as f64).hypot(y as f64) < 166.0;
        local.iter().filter(inside).count()
    };
    let slack = free_distance_mm(slack_rule(local.iter().copied()), 167, true);
    let mut full = MappedFree::new(167, true);
    for &p in &local {
        full.push(p, false);
    }
    let full = full.result();
    assert!(full < slack, "full width {full} mm, slack {slack} mm");
    assert!(
        overlapped(full) <= 1,
        "{} hits inside the body",
        overlapped(full)
    );
    assert!(
        overlapped(slack) >= 2,
        "{} hits inside the body",
        overlapped(slack)
    );
    // The two kinds are counted apart: one stray hit and one wall point
    // straight ahead are not an obstacle together.
    let mut pair = MappedFree::new(167, true);
    pair.push((300, 0), true);
    pair.push((310, 0), false);
    assert_eq!(pair.result(), i32::MAX);
}

/// A 6 m × 5 m evidence map (50 mm cells): walls around, a 1 m × 0.6 m
/// table in the middle, all else seen free.
/// The guard's rule until stop 59 for a 167 mm body: only points more
/// than a noise σ (10 mm) inside the corridor's edge counted.
fn slack_rule(points: impl Iterator<Item = (i32, i32)>) -> impl Iterator<Item = (i32, i32)> {
    points.filter(|&(_, y)| y.abs() < 167 - 10)
}

fn room() -> Box<EvidenceMap<{ evidence_bytes(120 * 100) }>> {
    let mut m = Box::new(EvidenceMap::<{ evidence_bytes(120 * 100) }>::new());
    m.reset(120, 100, 50).unwrap();
    for cy in 0..100 {
        for cx in 0..120 {
            let wall = cx < 2 || cy < 2 || cx >= 118 || cy >= 98;
            let table = (50..70).contains(&cx) && (40..52).contains(&cy);
            let st = if wall || table {
                CellState::Occupied
            } else {
                CellState::Free
            };
            m.set_state(cx, cy, st);
        }
    }
    m
}

#[test]
fn fine_space_keeps_exactly_the_clearance() {
    let map = room();
    let mut fine = Box::new(G::new());
    build_fine(&map, &mut fine, 175, false).unwrap();
    // The wall's face is at x = 100 mm; cell centres at 25 + 50k mm: the
    // first free column is the one whose centre is 175 mm from the face.
    for cx in 0..10 {
        let centre_x = cx as i64 * 50 + 25;
        let clear = centre_x - 100;
        assert_eq!(fine.is_free(cx, 50), clear >= 175, "column {cx}");
    }
    // Every free cell really has the clearance (checked by the disc test),
    // and every blocked one really lacks it.
    for cy in 0..100 {
        for cx in 0..120 {
            let (px, py) = (cx as i64 * 50 + 25, cy as i64 * 50 + 25);
            assert_eq!(
                fine.is_blocked(cx, cy),
                disc_blocked(&map, px, py, 175, false),
                "cell ({cx}, {cy})"
            );
        }
    }
}

#[test]
fn planning_cells_anchor_where_the_robot_fits() {
    let map = room();
    let mut coarse = Box::new(G::new());
    cspace::size_coarse(&map, &mut coarse, 300).unwrap();
    update_coarse(&map, &mut coarse, 300, 175, false).unwrap();
    for gy in 0..coarse.height() as i32 {
        for gx in 0..coarse.width() as i32 {
            let a = coarse_anchor(&map, 300, 175, false, gx, gy);
            assert_eq!(a.is_some(), coarse.is_free(gx, gy));
            if let Some((x, y)) = a {
                // Inside its cell, on free floor, with the clearance.
                assert!(x >= gx as i64 * 300 && x < (gx as i64 + 1) * 300);
                assert!(y >= gy as i64 * 300 && y < (gy as i64 + 1) * 300);
                assert!(!disc_blocked(&map, x, y, 175, false));
            }
        }
    }
    // The cells along the walls are usable (anchored off-centre), so the
    // lanes reach the strip a centre rule would leave.
    assert!(coarse.is_free(0, 5), "the first column is anchored");
    // A straight move that would graze the table is refused.
    let hmm = 100 * 50;
    let a = (2000, hmm - 2200);
    let b = (4000, hmm - 2200);
    assert!(!segment_clear(&map, a, b, 170));
    let c = (2000, hmm - 1500);
    let d = (4000, hmm - 1500);
    assert!(segment_clear(&map, c, d, 170));
}

/// Runs an edge pass to its end, checking every move (between
/// neighbours, never into an obstacle, no corner cut); the cells moved
/// to, and how many moves were along contours.
fn run_pass(fine: &mut G, pass: &mut EdgePass, start: Cell) -> (Vec<Cell>, usize) {
    let mut search = Box::new(S::new());
    let mut state = Box::new(St::new());
    let mut path = vec![Cell::default(); 120 * 100];
    let (mut last, mut moves, mut edge_moves) = (start, Vec::new(), 0usize);
    for _ in 0..200_000 {
        match pass
            .step(fine, &mut search, &mut state, &mut path, 500)
            .unwrap()
        {
            EdgeStep::Move { to, edge } => {
                moves.push(to);
                let (dx, dy) = (to.x as i32 - last.x as i32, to.y as i32 - last.y as i32);
                assert!(dx.abs() <= 1 && dy.abs() <= 1, "a move between neighbours");
                assert!(
                    fine.is_free(to.x as i32, to.y as i32),
                    "never into an obstacle"
                );
                if dx != 0 && dy != 0 {
                    let (x, y) = (last.x as i32, last.y as i32);
                    assert!(
                        fine.is_free(x + dx, y) && fine.is_free(x, y + dy),
                        "no corner cut"
                    );
                }
                edge_moves += usize::from(edge);
                last = to;
            }
            EdgeStep::Pending => {}
            EdgeStep::Done => break,
        }
    }
    assert!(pass.is_done());
    (moves, edge_moves)
}

fn boundary_of(fine: &G) -> Vec<(i32, i32)> {
    (0..100)
        .flat_map(|y| (0..120).map(move |x| (x, y)))
        .filter(|&(x, y)| is_boundary(fine, x, y))
        .collect()
}

#[test]
fn edge_pass_visits_every_reachable_boundary_cell() {
    let map = room();
    let mut fine = Box::new(G::new());
    build_fine(&map, &mut fine, 175, false).unwrap();
    let boundary = boundary_of(&fine);
    assert!(boundary.len() > 300);
    let mut pass = EdgePass::new();
    let start = Cell::new(30, 30);
    assert!(pass.start(&mut fine, start));
    let (moves, edge_moves) = run_pass(&mut fine, &mut pass, start);
    for &(x, y) in &boundary {
        assert!(
            fine.get(Layer::Covered, x, y),
            "boundary cell ({x}, {y}) visited"
        );
    }
    // Mostly along contours: transits are the exception.
    assert!(
        edge_moves * 10 > moves.len() * 8,
        "{edge_moves} of {} moves along contours",
        moves.len()
    );
    assert_eq!(pass.stats.unreachable, 0);
}

#[test]
fn edge_pass_skips_the_stretches_the_lanes_swept() {
    let map = room();
    let mut fine = Box::new(G::new());
    build_fine(&map, &mut fine, 175, false).unwrap();
    let boundary = boundary_of(&fine);
    // The lanes' track ran along the whole bottom wall's boundary row.
    let row = boundary.iter().map(|&(_, y)| y).max().unwrap();
    let swept: Vec<(i32, i32)> = boundary
        .iter()
        .copied()
        .filter(|&(_, y)| y == row)
        .collect();
    assert!(swept.len() > 60, "{} cells along the wall", swept.len());
    for &(x, y) in &swept {
        fine.set(Layer::Covered, x, y, true).unwrap();
    }
    // Rebuilding the configuration space keeps the marks.
    build_fine(&map, &mut fine, 175, false).unwrap();
    assert!(swept.iter().all(|&(x, y)| fine.get(Layer::Covered, x, y)));
    let mut full = fine.clone();
    let start = Cell::new(30, 30);
    let mut pass = EdgePass::new();
    assert!(pass.start_keeping(&mut fine, start));
    let (moves, edge_moves) = run_pass(&mut fine, &mut pass, start);
    assert!(boundary
        .iter()
        .all(|&(x, y)| fine.get(Layer::Covered, x, y)));
    // The swept row is crossed at most where a transit passes.
    let on_row = moves.iter().filter(|c| c.y as i32 == row).count();
    assert!(on_row * 4 < swept.len(), "{on_row} moves on the swept row");
    // A full pass walks it along the wall (the moves saved in time depend
    // on where the pass meets the stretch: the way round to its other end
    // may be a transit instead).
    let mut again = EdgePass::new();
    assert!(again.start(&mut full, start));
    let (_, all_edge) = run_pass(&mut full, &mut again, start);
    assert!(
        edge_moves + swept.len() * 3 / 4 < all_edge,
        "{edge_moves} against {all_edge}"
    );
}

/// Steps `pass` until it moves `moves` times; then `close` changes the
/// grid (the map changed under the pass), and the pass is stepped to its
/// end or its first error.
fn pass_with_change(
    moves: usize,
    close: impl Fn(&mut G, Cell),
) -> (EdgePass, Result<EdgeStep, robovac::search::SearchError>) {
    let map = room();
    let mut fine = Box::new(G::new());
    build_fine(&map, &mut fine, 175, false).unwrap();
    let mut pass = EdgePass::new();
    assert!(pass.start(&mut fine, Cell::new(30, 30)));
    let mut search = Box::new(S::new());
    let mut state = Box::new(St::new());
    let mut path = vec![Cell::default(); 120 * 100];
    let mut moved = 0;
    for _ in 0..200_000 {
        let r = pass.step(&mut fine, &mut search, &mut state, &mut path, 500);
        match r {
            Ok(EdgeStep::Move { .. }) => {
                moved += 1;
                if moved == moves {
                    close(&mut fine, pass.position());
                }
            }
            Ok(EdgeStep::Pending) => {}
            _ => return (pass, r),
        }
    }
    panic!("the pass never ended");
}

/// Someone beside the robot is mapped all round it (a ring two cells
/// out): the transit searches fail having explored a handful of cells.
/// The goals are not unreachable, the robot is: the pass says so
/// (`StartBlocked`, the mission builds it again from a fresher map) and
/// marks no contour visited that it never drove.
#[test]
fn edge_pass_boxed_in_gives_up_no_contour() {
    let (pass, r) = pass_with_change(20, |fine, at| {
        let (x, y) = (at.x as i32, at.y as i32);
        for (dx, dy) in (-2i32..=2).flat_map(|dy| (-2i32..=2).map(move |dx| (dx, dy))) {
            if dx.abs() == 2 || dy.abs() == 2 {
                fine.set_obstacle(x + dx, y + dy, true).unwrap();
            }
        }
    });
    assert_eq!(r, Err(robovac::search::SearchError::StartBlocked));
    assert_eq!(pass.stats.unreachable, 0);
}

/// A wall across the room after the fill: the robot's side is most of
/// the room, so the contours beyond the wall are unreachable, marked so,
/// and the pass ends.
#[test]
fn edge_pass_marks_contours_cut_off_beyond_a_new_wall() {
    let (pass, r) = pass_with_change(20, |fine, _| {
        for y in 0..100 {
            fine.set_obstacle(95, y, true).unwrap();
        }
    });
    assert_eq!(r, Ok(EdgeStep::Done));
    assert!(pass.stats.unreachable > 0, "{:?}", pass.stats);
}

#[test]
fn edge_pass_rechecks_the_contour_it_emitted_but_never_drove() {
    let map = room();
    let mut fine = Box::new(G::new());
    build_fine(&map, &mut fine, 175, false).unwrap();
    let start = Cell::new(30, 30);
    let mut pass = EdgePass::new();
    assert!(pass.start(&mut fine, start));
    let (moves, _) = run_pass(&mut fine, &mut pass, start);
    // The robot drove every move but a stretch of 30 in the middle (a
    // queue the mission dropped when it planned a leg again).
    let (a, b) = (moves.len() / 2, moves.len() / 2 + 30);
    let dropped: Vec<Cell> = moves[a..b].to_vec();
    for c in moves[..a].iter().chain(&moves[b..]) {
        pass.driven(&mut fine, c.x as i32, c.y as i32);
    }
    let given_back = pass.recheck(&mut fine);
    // The dropped stretch but its two ends (a driven neighbour counts).
    assert!(
        (20..=30).contains(&given_back),
        "{given_back} cells given back"
    );
    let back: Vec<Cell> = dropped
        .iter()
        .copied()
        .filter(|c| !fine.get(Layer::Covered, c.x as i32, c.y as i32))
        .collect();
    assert_eq!(back.len() as u32, given_back, "only dropped cells go back");
    assert!(!pass.is_done(), "the walk goes on");
    let (again, _) = run_pass(&mut fine, &mut pass, *moves.last().unwrap());
    assert!(
        back.iter().all(|c| again.contains(c)),
        "the walk takes them"
    );
    for c in &again {
        pass.driven(&mut fine, c.x as i32, c.y as i32);
    }
    assert_eq!(pass.recheck(&mut fine), 0, "all driven now");
    assert!(!pass.rechecks_left(), "two rounds at most");
    assert!(boundary_of(&fine)
        .iter()
        .all(|&(x, y)| fine.get(Layer::Covered, x, y)));
}

#[test]
fn a_flickering_cell_at_a_walls_face_is_not_sure_to_block() {
    let mut map = room();
    // A leg along the bottom wall at the edge pass's clearance: the wall's
    // face is at y = 100 mm, the leg 180 mm from it.
    let (a, b) = ((1000, 280), (4000, 280));
    assert!(segment_clear(&map, a, b, 175));
    // One noisy return lands in the unknown cell in front of the face.
    map.set_state(40, 97, CellState::Unknown);
    map.trace(2025, 1000, 2025, 125, true);
    assert_eq!(map.state(40, 97), CellState::Occupied);
    assert!(!segment_clear(&map, a, b, 175), "it grazes the sweep");
    assert!(
        segment_surely_clear(&map, a, b, 175, 4),
        "not sure to block"
    );
    // Hit again: a wall seen twice is sure.
    map.trace(2025, 1000, 2025, 125, true);
    assert!(!segment_surely_clear(&map, a, b, 175, 4));
    // The table, seen well, blocks a leg through it either way.
    let (c, d) = ((2000, 2700), (4000, 2700));
    assert!(!segment_surely_clear(&map, c, d, 175, 4));
}
