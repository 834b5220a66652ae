//! D* Lite against the independent Dijkstra of `common`, on random maps
//! that change while the robot walks: after every change its cost is the
//! optimum on the map as it is then, and its path is valid.

mod common;

use common::*;
use proptest::prelude::*;
use robovac::math::cost::to_cells;
use robovac::search::dstar_lite::DStarLite;
use robovac::search::SearchError;
use robovac::{Cell, Grid};

type Planner = DStarLite<CELLS, CELLS>;

fn planner() -> Box<Planner> {
    Box::new(Planner::new())
}

fn free_cells(g: &TGrid) -> Vec<Cell> {
    (0..g.height() as i32)
        .flat_map(|y| (0..g.width() as i32).map(move |x| (x, y)))
        .filter(|&(x, y)| free(g, x, y))
        .map(|(x, y)| Cell::new(x as u16, y as u16))
        .collect()
}

/// The optimum from `s` to `t` by the independent Dijkstra, in cells.
fn optimum(g: &TGrid, s: Cell, t: Cell) -> f64 {
    dijkstra(g, s)[(t.y as u32 * g.width() + t.x as u32) as usize]
}

fn path(p: &Planner, g: &TGrid) -> Vec<Cell> {
    let mut buf = vec![Cell::default(); g.cells()];
    let n = p.write_path(g, &mut buf).unwrap();
    buf.truncate(n);
    buf
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]
    /// The robot walks its path; every few steps some cells are blocked or
    /// freed (never its own cell or the goal). After each change D* Lite's
    /// cost equals Dijkstra's on the changed map, its path is valid and
    /// ends at the goal, and "no path" agrees too.
    #[test]
    fn dstar_lite_stays_optimal_as_the_map_changes(seed in any::<u64>(), w in 4u32..28, h in 4u32..28, density in 0u32..35, flips in proptest::collection::vec((any::<u32>(), any::<u32>()), 1..8), pick in any::<(u32, u32)>()) {
        let mut g = random_grid(w, h, density, seed);
        let cells = free_cells(&g);
        prop_assume!(cells.len() >= 2);
        let mut at = cells[pick.0 as usize % cells.len()];
        let goal = cells[pick.1 as usize % cells.len()];
        prop_assume!(at != goal);
        let mut p = planner();
        p.begin(&*g, at, goal).unwrap();
        for (fx, fy) in flips {
            let want = optimum(&g, at, goal);
            match p.compute(&*g) {
                Ok(r) => {
                    prop_assert!((to_cells(r.cost) as f64 - want).abs() < 1e-3, "cost {} vs {}", to_cells(r.cost), want);
                    let walk = path(&p, &g);
                    let len = check_grid_path(&g, &walk);
                    prop_assert!((len - want).abs() < 1e-3);
                    prop_assert_eq!(*walk.last().unwrap(), goal);
                    // Two steps along it, then the map changes.
                    at = walk[walk.len().min(3) - 1];
                    p.move_to(&*g, at).unwrap();
                }
                Err(SearchError::NoPath) => prop_assert!(want.is_infinite(), "no path, but Dijkstra {}", want),
                Err(e) => prop_assert!(false, "{:?}", e),
            }
            let c = Cell::new((fx % w) as u16, (fy % h) as u16);
            if c != at && c != goal {
                let blocked = g.is_blocked(c.x as i32, c.y as i32);
                g.set_obstacle(c.x as i32, c.y as i32, !blocked).unwrap();
                p.cells_changed(&*g, &[c]).unwrap();
            }
        }
    }
}

/// The robot has walked half way when a wall appears just ahead of it (what
/// its lidar would see): D* Lite repairs its path with fewer expansions than
/// a fresh search from where the robot stands, and finds the detour's
/// optimum.
#[test]
fn a_wall_ahead_is_repaired_with_less_work_than_a_fresh_search() {
    let mut g: Box<TGrid> = Box::new(Grid::new());
    g.reset(60, 30).unwrap();
    let (s, t) = (Cell::new(1, 15), Cell::new(58, 15));
    let mut p = planner();
    p.begin(&*g, s, t).unwrap();
    let first = p.compute(&*g).unwrap();
    let walk = path(&p, &g);
    let at = walk[30];
    p.move_to(&*g, at).unwrap();
    let wall: Vec<Cell> = (8..23).map(|y| Cell::new(at.x + 3, y)).collect();
    for c in &wall {
        g.set_obstacle(c.x as i32, c.y as i32, true).unwrap();
    }
    p.cells_changed(&*g, &wall).unwrap();
    let again = p.compute(&*g).unwrap();
    assert!((to_cells(again.cost) as f64 - optimum(&g, at, t)).abs() < 1e-3);
    let mut fresh = planner();
    fresh.begin(&*g, at, t).unwrap();
    let scratch = fresh.compute(&*g).unwrap();
    assert_eq!(scratch.cost, again.cost);
    assert!(
        again.nodes_expanded < scratch.nodes_expanded,
        "repair {} vs fresh {} (first {})",
        again.nodes_expanded,
        scratch.nodes_expanded,
        first.nodes_expanded
    );
}

/// Typed errors: blocked or off-map ends, a changed map size, no query.
#[test]
fn dstar_lite_errors_are_typed() {
    let mut g: Box<TGrid> = Box::new(Grid::new());
    g.load_ascii("...\n.#.\n...").unwrap();
    let mut p = planner();
    assert_eq!(p.compute(&*g), Err(SearchError::NotRunning));
    let (a, b) = (Cell::new(0, 0), Cell::new(2, 2));
    assert_eq!(
        p.begin(&*g, Cell::new(1, 1), b),
        Err(SearchError::StartBlocked)
    );
    assert_eq!(
        p.begin(&*g, a, Cell::new(1, 1)),
        Err(SearchError::GoalBlocked)
    );
    assert_eq!(
        p.begin(&*g, a, Cell::new(3, 0)),
        Err(SearchError::GoalOffMap)
    );
    p.begin(&*g, a, b).unwrap();
    assert!(p.compute(&*g).is_ok());
    g.set_obstacle(2, 2, true).unwrap();
    assert_eq!(p.cells_changed(&*g, &[b]), Err(SearchError::GoalBlocked));
    let mut other: Box<TGrid> = Box::new(Grid::new());
    other.reset(4, 4).unwrap();
    p.begin(&*g, a, Cell::new(2, 0)).unwrap();
    assert_eq!(p.compute(&*other), Err(SearchError::MapChanged));
}
