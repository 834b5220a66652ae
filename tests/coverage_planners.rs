//! The rules of the seeds' coverage planners, each checked on a small map
//! where the right move is known by hand (completeness and validity on
//! random maps are host-sim's property tests, over every planner).

mod common;

use common::*;
use robovac::coverage::planners::{binn, mark_backtrack, template};
use robovac::coverage::{BacktrackList, Coverage, PlannerKind, Step};
use robovac::grid::Layer;
use robovac::Cell;

type TCoverage = Coverage<CELLS, W, CELLS, 256, 1024>;

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
