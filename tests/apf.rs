//! The artificial potential field: every walk is a valid downhill path that
//! ends at the goal or at a true local minimum, and a U-shaped obstacle
//! traps it where A* still finds a way (its local minima shown, not hidden).

mod common;

use common::*;
use proptest::prelude::*;
use robovac::search::apf::{descend, potential, ApfEnd, APF_DEFAULT};
use robovac::search::{SearchError, NEIGHBOURS};
use robovac::{Algo, Cell, Grid};

fn walk(g: &TGrid, s: Cell, t: Cell) -> (robovac::search::apf::ApfWalk, Vec<Cell>) {
    let mut buf = vec![Cell::default(); g.cells()];
    let w = descend(g, s, t, APF_DEFAULT, &mut buf).unwrap();
    buf.truncate(w.cells);
    (w, buf)
}

/// Cells a move can reach from `c` (8-connected, no corner cutting), by
/// plain reads.
fn moves(g: &TGrid, c: Cell) -> Vec<Cell> {
    let (x, y) = (c.x as i32, c.y as i32);
    NEIGHBOURS
        .iter()
        .filter(|&&(dx, dy)| {
            free(g, x + dx, y + dy)
                && (dx == 0 || dy == 0 || (free(g, x + dx, y) && free(g, x, y + dy)))
        })
        .map(|&(dx, dy)| Cell::new((x + dx) as u16, (y + dy) as u16))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    /// On random maps: each step is a move; the field falls strictly at
    /// every step but the last into the goal; a walk that stops short ends
    /// where no neighbour is lower and the goal is not a move away.
    #[test]
    fn walks_go_downhill_to_the_goal_or_a_local_minimum(seed in any::<u64>(), w in 3u32..30, h in 3u32..30, density in 0u32..35, pick in any::<(u32, u32)>()) {
        let g = random_grid(w, h, density, seed);
        let cells: Vec<Cell> = (0..h as i32).flat_map(|y| (0..w as i32).map(move |x| (x, y)))
            .filter(|&(x, y)| free(&g, x, y)).map(|(x, y)| Cell::new(x as u16, y as u16)).collect();
        prop_assume!(cells.len() >= 2);
        let s = cells[pick.0 as usize % cells.len()];
        let t = cells[pick.1 as usize % cells.len()];
        let (res, path) = walk(&g, s, t);
        prop_assert_eq!(path[0], s);
        prop_assert_eq!(*path.last().unwrap(), res.at);
        let u = |c: Cell| potential(&*g, c, t, APF_DEFAULT);
        for step in path.windows(2) {
            prop_assert!(moves(&g, step[0]).contains(&step[1]), "{:?} -> {:?}", step[0], step[1]);
            prop_assert!(step[1] == t || u(step[1]) < u(step[0]));
        }
        match res.end {
            ApfEnd::Goal => prop_assert_eq!(res.at, t),
            ApfEnd::LocalMinimum => {
                prop_assert!(res.at != t);
                let around = moves(&g, res.at);
                prop_assert!(!around.contains(&t));
                prop_assert!(around.iter().all(|&n| u(n) >= u(res.at)));
            }
        }
    }
}

/// In the open the field leads straight to the goal.
#[test]
fn an_open_room_is_crossed() {
    let mut g: Box<TGrid> = Box::new(Grid::new());
    g.reset(30, 20).unwrap();
    let (res, path) = walk(&g, Cell::new(2, 10), Cell::new(27, 10));
    assert_eq!(res.end, ApfEnd::Goal);
    assert!((check_grid_path(&g, &path) - 25.0).abs() < 1e-9);
}

/// The classic trap: a U open toward the start with the goal behind its
/// bottom. The walk is held inside the U; A* goes round it.
#[test]
fn a_u_shaped_obstacle_traps_the_walk_where_a_star_goes_round() {
    let mut g: Box<TGrid> = Box::new(Grid::new());
    g.load_ascii(
        "..............................\n\
         ..............................\n\
         ..............................\n\
         ............######............\n\
         .................#............\n\
         .................#............\n\
         .................#............\n\
         .................#............\n\
         .................#............\n\
         ............######............\n\
         ..............................\n\
         ..............................",
    )
    .unwrap();
    let (s, t) = (Cell::new(2, 6), Cell::new(26, 6));
    let (res, path) = walk(&g, s, t);
    assert_eq!(res.end, ApfEnd::LocalMinimum, "{path:?}");
    assert!(
        (12..17).contains(&res.at.x) && (4..9).contains(&res.at.y),
        "held at {:?}",
        res.at
    );
    let mut st = new_state();
    assert!(st.search(&*g, s, &[t], Algo::AStarOctile).is_ok());
}

/// Bad ends are typed errors; a short buffer is too.
#[test]
fn apf_errors_are_typed() {
    let mut g: Box<TGrid> = Box::new(Grid::new());
    g.load_ascii(".....\n.#...\n.....").unwrap();
    let mut buf = [Cell::default(); 2];
    for ((s, t), want) in [
        ((1, 1), (4, 2), SearchError::StartBlocked),
        ((0, 0), (1, 1), SearchError::GoalBlocked),
        ((9, 0), (4, 2), SearchError::StartOffMap),
        ((0, 0), (4, 9), SearchError::GoalOffMap),
        ((0, 0), (4, 0), SearchError::PathBufferTooSmall),
        // Two faults: the start is checked whole first, as in every search.
        ((1, 1), (4, 9), SearchError::StartBlocked),
    ]
    .map(|((a, b), (c, d), e)| ((Cell::new(a, b), Cell::new(c, d)), e))
    {
        assert_eq!(descend(&*g, s, t, APF_DEFAULT, &mut buf), Err(want));
    }
}
