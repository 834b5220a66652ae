//! The windowed search ([`robovac::search::WindowSearch`]): on a grid that
//! fits, the very search over the grid itself; on a larger grid, valid
//! paths on the larger grid that stay inside the window, never shorter
//! than the independent Dijkstra's, and typed errors when no goal fits.

mod common;

use common::*;
use proptest::prelude::*;
use robovac::search::{Progress, SearchError, WindowSearch};
use robovac::{Algo, Cell, SearchState};

/// A window of 16 × 16 cells over the test grids (up to 64 × 64).
type Small = WindowSearch<256, 8>;
/// The state a small window runs on.
type SmallState = SearchState<256, 8, 256>;
/// A window as large as the test grids.
type Whole = WindowSearch<CELLS, W>;

fn finish<const N: usize, const NW: usize, const O: usize>(
    s: &mut WindowSearch<N, NW>,
    st: &mut SearchState<N, NW, O>,
) -> Result<Vec<Cell>, SearchError> {
    while let Progress::Pending { .. } = s.resume(st, 50)? {}
    let mut out = vec![Cell::default(); 4096];
    let n = s.write_path(st, &mut out)?;
    out.truncate(n);
    Ok(out)
}

fn pick_free(g: &TGrid, k: u32) -> Option<Cell> {
    let cells: Vec<Cell> = (0..g.height() as i32)
        .flat_map(|y| (0..g.width() as i32).map(move |x| (x, y)))
        .filter(|&(x, y)| free(g, x, y))
        .map(|(x, y)| Cell::new(x as u16, y as u16))
        .collect();
    (!cells.is_empty()).then(|| cells[k as usize % cells.len()])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// A grid that fits: the same path as the search on the grid itself.
    #[test]
    fn whole_grid_is_the_plain_search(seed in any::<u64>(), w in 2u32..40, h in 2u32..40, d in 0u32..40, k in any::<(u32, u32)>()) {
        let g = random_grid(w, h, d, seed);
        let (Some(s), Some(t)) = (pick_free(&g, k.0), pick_free(&g, k.1)) else { return Ok(()) };
        let mut plain = new_state();
        let mut st = new_state();
        let mut win = Box::new(Whole::new());
        for algo in [Algo::AStar, Algo::Oha, Algo::Theta] {
            let a = plain.search(&g, s, &[t], algo).and_then(|_| {
                let mut out = vec![Cell::default(); 4096];
                let n = plain.write_path(&mut out)?;
                out.truncate(n);
                Ok(out)
            });
            let b = win.begin(&mut st, &g, s, &[t], algo).and_then(|_| finish(&mut win, &mut st));
            prop_assert_eq!(a, b);
            prop_assert!(win.is_whole());
        }
    }

    /// A larger grid: the path is valid on it, stays in the window, and is
    /// never shorter than the optimum; with both ends 8 cells apart or
    /// less, a goal is always inside the window.
    #[test]
    fn window_paths_are_valid_on_the_big_grid(seed in any::<u64>(), w in 20u32..64, h in 20u32..64, d in 0u32..35, k in any::<(u32, u32)>()) {
        let g = random_grid(w, h, d, seed);
        let (Some(s), Some(t)) = (pick_free(&g, k.0), pick_free(&g, k.1)) else { return Ok(()) };
        let near = (s.x as i32 - t.x as i32).abs() <= 8 && (s.y as i32 - t.y as i32).abs() <= 8;
        let mut win = Box::new(Small::new());
        let mut st = Box::new(SmallState::new());
        match win.begin(&mut st, &g, s, &[t], Algo::AStar) {
            Err(SearchError::OutOfWindow) => prop_assert!(!near, "near goal left out"),
            Err(e) => prop_assert!(false, "{e:?}"),
            Ok(()) => {
                let wdw = win.window();
                prop_assert!(wdw.w <= 16 && wdw.h <= 16);
                prop_assert!(wdw.contains(s) && wdw.contains(t));
                if let Ok(path) = finish(&mut win, &mut st) {
                    let len = check_grid_path(&g, &path);
                    prop_assert!(path.iter().all(|&c| wdw.contains(c)));
                    prop_assert_eq!(path.first().copied(), Some(s));
                    prop_assert_eq!(path.last().copied(), Some(t));
                    let opt = dijkstra(&g, s)[(t.y as u32 * g.width() + t.x as u32) as usize];
                    prop_assert!(len >= opt - 1e-9);
                }
            }
        }
    }
}

/// Goals beyond the window are left out; none left is a typed error, and
/// so are too many goals.
#[test]
fn far_goals_are_out_of_window() {
    let g = random_grid(60, 60, 0, 1);
    let mut win = Box::new(Small::new());
    let mut st = Box::new(SmallState::new());
    let far = Cell::new(59, 59);
    let near = Cell::new(5, 5);
    assert_eq!(
        win.begin(&mut st, &g, Cell::new(0, 0), &[far], Algo::AStar),
        Err(SearchError::OutOfWindow)
    );
    win.begin(&mut st, &g, Cell::new(0, 0), &[far, near], Algo::AStar)
        .unwrap();
    assert_eq!(win.goals(), &[near]);
    assert!(!win.is_whole());
    let path = finish(&mut win, &mut st).unwrap();
    assert_eq!(path.last(), Some(&near));
    let many = vec![near; robovac::search::MAX_GOALS + 1];
    assert_eq!(
        win.begin(&mut st, &g, Cell::new(0, 0), &many, Algo::AStar),
        Err(SearchError::TooManyGoals)
    );
    assert_eq!(
        win.begin(&mut st, &g, Cell::new(70, 0), &[near], Algo::AStar),
        Err(SearchError::StartOffMap)
    );
}

/// The state is lent: a query whose state another query took meanwhile
/// fails with `Preempted` instead of reading the other query's nodes, and
/// begun again it finds its own path.
#[test]
fn a_query_whose_state_was_taken_is_preempted() {
    let g = random_grid(60, 60, 0, 1);
    let mut win = Box::new(Small::new());
    let mut st = Box::new(SmallState::new());
    let (a, b) = (Cell::new(2, 2), Cell::new(9, 9));
    win.begin(&mut st, &g, a, &[b], Algo::AStar).unwrap();
    let _ = win.resume(&mut st, 3);
    let small = random_grid(10, 10, 0, 2);
    st.search(&small, Cell::new(0, 0), &[Cell::new(9, 0)], Algo::AStar)
        .unwrap();
    assert_eq!(win.resume(&mut st, 50), Err(SearchError::Preempted));
    let mut out = [Cell::default(); 64];
    assert_eq!(win.write_path(&st, &mut out), Err(SearchError::Preempted));
    win.begin(&mut st, &g, a, &[b], Algo::AStar).unwrap();
    let path = finish(&mut win, &mut st).unwrap();
    assert_eq!((path.first(), path.last()), (Some(&a), Some(&b)));
    check_grid_path(&g, &path);
}

/// Two blocks either side of a wall too thin to close the block search do
/// not meet on the fine grid; a gap in the wall joins them, and so does a
/// way round through a diagonal step's side blocks.
#[test]
fn blocks_meet_only_through_free_cells() {
    use robovac::search::blocks::blocks_connected;
    let mut g: robovac::grid::Grid<8> = robovac::grid::Grid::new();
    g.reset(12, 12).unwrap();
    // A wall two cells thick along x = 5..=6, rows 0..=11: both blocks of
    // side 6 at (0, 0) and (1, 0) keep free cells.
    for y in 0..12 {
        g.set_obstacle(5, y, true).unwrap();
        g.set_obstacle(6, y, true).unwrap();
    }
    assert!(!blocks_connected(&g, (0, 0), (1, 0), 6));
    assert!(!blocks_connected(&g, (0, 0), (1, 1), 6));
    // Blocks that are not neighbours, and blocks too large to check, are
    // taken as connected.
    assert!(blocks_connected(&g, (0, 0), (2, 0), 6));
    assert!(blocks_connected(&g, (0, 0), (1, 0), 9));
    // A gap in the wall in the lower blocks joins the diagonal step (its
    // side block (1, 1)... and (0, 1)), not the upper straight one.
    g.set_obstacle(5, 9, false).unwrap();
    g.set_obstacle(6, 9, false).unwrap();
    assert!(blocks_connected(&g, (0, 0), (1, 1), 6));
    assert!(blocks_connected(&g, (0, 1), (1, 1), 6));
    assert!(!blocks_connected(&g, (0, 0), (1, 0), 6));
}
