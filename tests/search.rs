//! Search correctness against an independent Dijkstra, path validity, error
//! paths and the resumable interface.

mod common;

use common::*;
use proptest::prelude::*;
use robovac::search::prune::prune;
use robovac::search::{Progress, SearchError};
use robovac::{Algo, Cell, Grid};

fn free_cells(g: &TGrid) -> Vec<Cell> {
    let mut v = Vec::new();
    for y in 0..g.height() as i32 {
        for x in 0..g.width() as i32 {
            if free(g, x, y) {
                v.push(Cell::new(x as u16, y as u16));
            }
        }
    }
    v
}

fn run(
    state: &mut TSearch,
    g: &TGrid,
    s: Cell,
    goals: &[Cell],
    algo: Algo,
) -> Result<(robovac::SearchStats, Vec<Cell>), SearchError> {
    let st = state.search(g, s, goals, algo)?;
    let mut buf = vec![Cell::default(); g.cells()];
    let n = state.write_path(&mut buf)?;
    buf.truncate(n);
    Ok((st, buf))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A* is optimal (to 1e-6) and its path is valid; OHA* and Theta* find a
    /// path exactly when one exists, valid and never shorter than possible.
    #[test]
    fn searches_agree_with_dijkstra(seed in any::<u64>(), w in 2u32..40, h in 2u32..40, density in 0u32..45, pick in any::<(u32, u32)>()) {
        let g = random_grid(w, h, density, seed);
        let cells = free_cells(&g);
        prop_assume!(cells.len() >= 2);
        let s = cells[pick.0 as usize % cells.len()];
        let t = cells[pick.1 as usize % cells.len()];
        let dist = dijkstra(&g, s);
        let opt = dist[(t.y as u32 * g.width() + t.x as u32) as usize];
        let mut st = new_state();
        for algo in [Algo::AStar, Algo::Oha, Algo::Theta, Algo::AStarOctile, Algo::Bfs, Algo::Dfs, Algo::Jps] {
            match run(&mut st, &g, s, &[t], algo) {
                Ok((stats, path)) => {
                    prop_assert!(opt.is_finite(), "{algo:?} found a path where none exists");
                    prop_assert_eq!(path.first().copied(), Some(s));
                    prop_assert_eq!(path.last().copied(), Some(t));
                    prop_assert_eq!(stats.goal, t);
                    prop_assert_eq!(stats.path_cells as usize, path.len());
                    if algo == Algo::Theta {
                        for w in path.windows(2) {
                            prop_assert!(segment_clear(&g, w[0], w[1]), "Theta* segment {w:?} not clear");
                        }
                        let len = polyline_len(&path);
                        let straight = ((s.x as f64 - t.x as f64).powi(2) + (s.y as f64 - t.y as f64).powi(2)).sqrt();
                        prop_assert!(len >= straight - 1e-9);
                        prop_assert!((stats.cost as f64 / 5741.0 - len).abs() < 1e-3 * (1.0 + len));
                    } else {
                        let len = check_grid_path(&g, &path);
                        prop_assert!((stats.cost as f64 / 5741.0 - len).abs() < 1e-6 * (1.0 + len));
                        if matches!(algo, Algo::AStar | Algo::AStarOctile | Algo::Jps) {
                            prop_assert!((len - opt).abs() < 1e-6, "{algo:?} {len} vs optimum {opt}");
                        } else {
                            prop_assert!(len >= opt - 1e-6);
                        }
                    }
                    // Pruning keeps the ends, never lengthens, never cuts a corner.
                    let before = polyline_len(&path);
                    let mut p = path.clone();
                    let m = prune(&g, &mut p);
                    let p = &p[..m];
                    prop_assert_eq!(p.first().copied(), Some(s));
                    prop_assert_eq!(p.last().copied(), Some(t));
                    prop_assert!(polyline_len(p) <= before + 1e-9);
                    for w in p.windows(2) {
                        prop_assert!(segment_clear(&g, w[0], w[1]), "pruned segment {w:?} not clear");
                    }
                }
                Err(SearchError::NoPath) => prop_assert!(opt.is_infinite(), "{algo:?}: no path, optimum {opt}"),
                Err(e) => prop_assert!(false, "{algo:?}: unexpected {e:?}"),
            }
        }
    }

    /// Jump point search on maps wider than its 31-cell row words, with
    /// long open runs: the same cost as A* octile (the optimum) and a valid
    /// cell-by-cell path. (Not always fewer nodes: on a short query the
    /// start's jumps can outnumber A*'s few expansions.)
    #[test]
    fn jps_matches_astar_octile_on_wide_maps(seed in any::<u64>(), w in 20u32..128, h in 2u32..64, density in 0u32..30, pick in any::<(u32, u32)>()) {
        let h = h.min(4096 / w); // the test grid's capacity
        let g = random_grid(w, h, density, seed);
        let cells = free_cells(&g);
        prop_assume!(cells.len() >= 2);
        let s = cells[pick.0 as usize % cells.len()];
        let t = cells[pick.1 as usize % cells.len()];
        let mut st = new_state();
        let want = run(&mut st, &g, s, &[t], Algo::AStarOctile);
        let got = run(&mut st, &g, s, &[t], Algo::Jps);
        match (want, got) {
            (Ok((a, _)), Ok((j, path))) => {
                prop_assert_eq!(a.cost, j.cost);
                prop_assert_eq!(path.first().copied(), Some(s));
                prop_assert_eq!(path.last().copied(), Some(t));
                prop_assert_eq!(j.path_cells as usize, path.len());
                let len = check_grid_path(&g, &path);
                prop_assert!((j.cost as f64 / 5741.0 - len).abs() < 1e-6 * (1.0 + len));
            }
            (Err(a), Err(j)) => prop_assert_eq!(a, j),
            (a, j) => prop_assert!(false, "A* octile {a:?}, JPS {j:?}"),
        }
    }

    /// Multi-goal A* reaches the goal nearest by true path cost.
    #[test]
    fn multi_goal_reaches_nearest(seed in any::<u64>(), w in 4u32..40, h in 4u32..40, density in 0u32..35, k in 1usize..10, pick in any::<u64>()) {
        let g = random_grid(w, h, density, seed);
        let cells = free_cells(&g);
        prop_assume!(cells.len() > k + 1);
        let mut rng = robovac::grid::maps::SplitMix64::new(pick);
        let s = cells[rng.below(cells.len() as u32) as usize];
        let goals: Vec<Cell> = (0..k).map(|_| cells[rng.below(cells.len() as u32) as usize]).collect();
        let dist = dijkstra(&g, s);
        let best = goals.iter().map(|t| dist[(t.y as u32 * g.width() + t.x as u32) as usize]).fold(f64::INFINITY, f64::min);
        let mut st = new_state();
        for algo in [Algo::AStar, Algo::AStarOctile, Algo::Jps] {
            match run(&mut st, &g, s, &goals, algo) {
                Ok((stats, path)) => {
                    prop_assert!(goals.contains(&stats.goal));
                    let len = check_grid_path(&g, &path);
                    prop_assert!((len - best).abs() < 1e-6, "{algo:?} multi-goal {len} vs nearest {best}");
                }
                Err(SearchError::NoPath) => prop_assert!(best.is_infinite()),
                Err(e) => prop_assert!(false, "unexpected {e:?}"),
            }
        }
        // OHA* and Theta* also stop at one of the goals.
        for algo in [Algo::Oha, Algo::Theta] {
            if let Ok((stats, _)) = run(&mut st, &g, s, &goals, algo) {
                prop_assert!(goals.contains(&stats.goal));
            }
        }
    }

    /// A search spread over many bounded calls gives the same answer as one
    /// call, and no call expands more than its budget.
    #[test]
    fn resumable_matches_batch(seed in any::<u64>(), density in 0u32..35, budget in 1u32..50) {
        let g = random_grid(40, 30, density, seed);
        let cells = free_cells(&g);
        prop_assume!(cells.len() >= 2);
        let (s, t) = (cells[0], cells[cells.len() - 1]);
        for algo in [Algo::AStar, Algo::Oha, Algo::Theta] {
            let mut a = new_state();
            let batch = a.search(&g, s, &[t], algo);
            let mut b = new_state();
            b.begin(&g, s, &[t], algo).unwrap();
            let mut last = 0;
            let inc = loop {
                match b.resume(&g, budget) {
                    Ok(Progress::Pending { nodes_expanded }) => {
                        prop_assert!(nodes_expanded - last <= budget);
                        last = nodes_expanded;
                    }
                    Ok(Progress::Found(st)) => {
                        prop_assert!(st.nodes_expanded - last <= budget);
                        break Ok(st);
                    }
                    Err(e) => break Err(e),
                }
            };
            prop_assert_eq!(batch, inc);
        }
    }
}

#[test]
fn errors_are_typed() {
    let mut g = TGrid::new();
    g.load_ascii("....\n.##.\n.#..\n#...\n").unwrap();
    let mut st = new_state();
    let a = Algo::AStar;
    assert_eq!(
        st.search(&g, Cell::new(9, 0), &[Cell::new(0, 0)], a),
        Err(SearchError::StartOffMap)
    );
    assert_eq!(
        st.search(&g, Cell::new(1, 1), &[Cell::new(0, 0)], a),
        Err(SearchError::StartBlocked)
    );
    assert_eq!(
        st.search(&g, Cell::new(0, 0), &[Cell::new(0, 9)], a),
        Err(SearchError::GoalOffMap)
    );
    assert_eq!(
        st.search(&g, Cell::new(0, 0), &[Cell::new(2, 1)], a),
        Err(SearchError::GoalBlocked)
    );
    assert_eq!(
        st.search(&g, Cell::new(0, 0), &[], a),
        Err(SearchError::NoGoals)
    );
    let many = [Cell::new(0, 0); robovac::search::MAX_GOALS + 1];
    assert_eq!(
        st.search(&g, Cell::new(0, 0), &many, a),
        Err(SearchError::TooManyGoals)
    );
    // (0,2) is enclosed: (1,2) and (0,3) blocked, and the diagonal to (1,3)
    // would cut the corner between them.
    assert_eq!(
        st.search(&g, Cell::new(0, 0), &[Cell::new(1, 3)], a)
            .map(|s| s.goal),
        Ok(Cell::new(1, 3))
    );
    let mut g2 = TGrid::new();
    g2.load_ascii("..#.\n.#..\n").unwrap();
    assert_eq!(
        st.search(&g2, Cell::new(0, 0), &[Cell::new(3, 0)], a),
        Err(SearchError::NoPath)
    );
    let mut buf = [Cell::default(); 1];
    assert_eq!(st.write_path(&mut buf), Err(SearchError::NotRunning));
    // start == goal
    let s = st
        .search(&g, Cell::new(0, 0), &[Cell::new(0, 0)], a)
        .unwrap();
    assert_eq!((s.cost, s.path_cells), (0, 1));
    assert_eq!(st.write_path(&mut buf), Ok(1));
    // path buffer too small
    st.search(&g, Cell::new(0, 0), &[Cell::new(3, 3)], a)
        .unwrap();
    assert_eq!(
        st.write_path(&mut buf),
        Err(SearchError::PathBufferTooSmall)
    );
    // resume without begin
    let mut fresh = new_state();
    assert_eq!(fresh.resume(&g, 10), Err(SearchError::NotRunning));
}

#[test]
fn capacity_errors() {
    // Open list of 4 entries overflows on an open map.
    let mut g = TGrid::new();
    g.reset(20, 20).unwrap();
    let mut tiny: Box<robovac::SearchState<CELLS, W, 4>> = Box::new(robovac::SearchState::new());
    assert_eq!(
        tiny.search(&g, Cell::new(0, 0), &[Cell::new(19, 19)], Algo::AStar),
        Err(SearchError::OpenListFull)
    );
    // A map larger than the state.
    let mut big: Box<Grid<{ 128 * 128 / 32 }>> = Box::new(Grid::new());
    big.reset(100, 100).unwrap();
    let mut st = new_state();
    assert_eq!(
        st.search(&*big, Cell::new(0, 0), &[Cell::new(1, 1)], Algo::AStar),
        Err(SearchError::MapTooLarge)
    );
    // Resizing the map mid-search is detected.
    let mut g3 = TGrid::new();
    g3.reset(30, 30).unwrap();
    st.begin(&g3, Cell::new(0, 0), &[Cell::new(29, 29)], Algo::Oha)
        .unwrap();
    assert!(matches!(st.resume(&g3, 3), Ok(Progress::Pending { .. })));
    g3.reset(31, 30).unwrap();
    assert_eq!(st.resume(&g3, 3), Err(SearchError::MapChanged));
}

#[test]
fn oha_fewer_nodes_and_pruned_cost_no_higher() {
    // Seed 000's claim, on an empty 60x40 map and on random maps: OHA*
    // expands fewer nodes than A*, and after pruning costs no more than A*'s
    // unpruned 8-connected path.
    let mut st = new_state();
    let mut total = (0u64, 0u64);
    for seed in 0..40u64 {
        let g = if seed == 0 {
            let mut g = Box::new(TGrid::new());
            g.reset(60, 40).unwrap();
            g
        } else {
            random_grid(60, 40, 15, seed)
        };
        let (s, t) = (Cell::new(0, 0), Cell::new(59, 39));
        if !free(&g, 0, 0) || !free(&g, 59, 39) {
            continue;
        }
        let Ok((a, ap)) = run(&mut st, &g, s, &[t], Algo::AStar) else {
            continue;
        };
        let (o, mut op) = run(&mut st, &g, s, &[t], Algo::Oha).unwrap();
        let m = prune(&g, &mut op);
        assert!(
            polyline_len(&op[..m]) <= polyline_len(&ap) + 1e-9,
            "seed {seed}"
        );
        total.0 += a.nodes_expanded as u64;
        total.1 += o.nodes_expanded as u64;
        if seed == 0 {
            assert!(
                o.nodes_expanded * 10 < a.nodes_expanded * 6,
                "OHA* {} vs A* {}",
                o.nodes_expanded,
                a.nodes_expanded
            );
        }
    }
    assert!(
        total.1 * 10 < total.0 * 6,
        "OHA* {} vs A* {} nodes",
        total.1,
        total.0
    );
}

/// The ASCII loader: CRLF line ends, blank lines around the map and a
/// missing final newline read as plain lines; ragged rows and strange
/// characters are typed errors.
#[test]
fn ascii_maps_accept_crlf_and_blank_lines() {
    let mut a = TGrid::new();
    let mut b = TGrid::new();
    a.load_ascii("\n.#.\r\n#..\r\r\n\n").unwrap();
    b.load_ascii(".#.\n#..").unwrap();
    assert_eq!((a.width(), a.height()), (3, 2));
    for y in 0..2 {
        for x in 0..3 {
            assert_eq!(a.is_blocked(x, y), b.is_blocked(x, y));
        }
    }
    assert!(a.is_blocked(1, 0) && a.is_blocked(0, 1) && !a.is_blocked(2, 1));
    assert!(matches!(
        a.load_ascii("..\n...\n"),
        Err(robovac::grid::GridError::RaggedRows { row: 1 })
    ));
    assert!(matches!(
        a.load_ascii("..\n.x\n"),
        Err(robovac::grid::GridError::BadChar { row: 1, col: 1 })
    ));
}

proptest! {
    /// The 4-ary open list gives its entries back in the strict order
    /// (smallest f, then largest g, then smallest index), whatever the
    /// pushes and pops interleaved: the order a sorted list gives.
    #[test]
    fn open_list_pops_in_order(ops in proptest::collection::vec((any::<bool>(), 0u32..50, 0u32..50, 0u32..20), 1..400)) {
        use robovac::search::open_list::{Entry, OpenList};
        let mut heap: OpenList<512> = OpenList::new();
        let mut model: Vec<(u32, u32, u32)> = Vec::new();
        let key = |e: &(u32, u32, u32)| (e.0, u32::MAX - e.1, e.2);
        for (push, f, g, idx) in ops {
            if push {
                heap.push(Entry { f, g, idx }).unwrap();
                model.push((f, g, idx));
            } else {
                model.sort_by_key(key);
                let want = (!model.is_empty()).then(|| model.remove(0));
                let got = heap.pop().map(|e| (e.f, e.g, e.idx));
                prop_assert_eq!(got, want);
            }
            prop_assert_eq!(heap.len(), model.len());
        }
    }
}

/// The octile heuristic expands no more nodes than the Euclidean one on
/// the same queries (it is tighter) and finds the same costs.
#[test]
fn octile_expands_fewer_nodes_than_euclidean() {
    let mut st = new_state();
    let (mut euclid, mut octile) = (0u64, 0u64);
    for seed in 0..40 {
        let g = random_grid(39, 31, 20, seed);
        let cells = free_cells(&g);
        let (s, t) = (cells[0], cells[cells.len() - 1]);
        let a = run(&mut st, &g, s, &[t], Algo::AStar);
        let b = run(&mut st, &g, s, &[t], Algo::AStarOctile);
        match (a, b) {
            (Ok((sa, _)), Ok((sb, _))) => {
                assert_eq!(sa.cost, sb.cost, "seed {seed}");
                euclid += sa.nodes_expanded as u64;
                octile += sb.nodes_expanded as u64;
            }
            (Err(SearchError::NoPath), Err(SearchError::NoPath)) => {}
            other => panic!("seed {seed}: {other:?}"),
        }
    }
    assert!(octile < euclid, "octile {octile} vs Euclidean {euclid}");
}

/// Fewest moves from `s` to every cell (8-connected, no corner cutting),
/// by an independent breadth-first search.
fn fewest_moves(g: &TGrid, s: Cell) -> Vec<Option<u32>> {
    let (w, h) = (g.width() as i32, g.height() as i32);
    let mut d: Vec<Option<u32>> = vec![None; (w * h) as usize];
    let mut q = std::collections::VecDeque::new();
    d[(s.y as i32 * w + s.x as i32) as usize] = Some(0);
    q.push_back((s.x as i32, s.y as i32));
    while let Some((x, y)) = q.pop_front() {
        let here = d[(y * w + x) as usize].unwrap();
        for (dx, dy) in robovac::search::NEIGHBOURS {
            let (nx, ny) = (x + dx, y + dy);
            let diagonal_ok = dx == 0 || dy == 0 || (free(g, x + dx, y) && free(g, x, y + dy));
            if free(g, nx, ny) && diagonal_ok && d[(ny * w + nx) as usize].is_none() {
                d[(ny * w + nx) as usize] = Some(here + 1);
                q.push_back((nx, ny));
            }
        }
    }
    d
}

proptest! {
    /// Breadth-first search finds a path of the fewest moves; depth-first
    /// search finds a valid one; both exactly when one exists (the path
    /// checks themselves are in `searches_agree_with_dijkstra`).
    #[test]
    fn bfs_takes_fewest_moves_and_dfs_finds_a_path(seed in any::<u64>(), w in 2u32..30, h in 2u32..30, density in 0u32..45, pick in any::<(u32, u32)>()) {
        let g = random_grid(w, h, density, seed);
        let cells = free_cells(&g);
        prop_assume!(cells.len() >= 2);
        let s = cells[pick.0 as usize % cells.len()];
        let t = cells[pick.1 as usize % cells.len()];
        let want = fewest_moves(&g, s)[(t.y as u32 * g.width() + t.x as u32) as usize];
        let mut st = new_state();
        match (run(&mut st, &g, s, &[t], Algo::Bfs), want) {
            (Ok((_, path)), Some(m)) => {
                check_grid_path(&g, &path);
                prop_assert_eq!(path.len() as u32 - 1, m);
            }
            (Err(SearchError::NoPath), None) => {}
            (r, m) => prop_assert!(false, "BFS {r:?}, fewest moves {m:?}"),
        }
        match (run(&mut st, &g, s, &[t], Algo::Dfs), want) {
            (Ok((_, path)), Some(m)) => {
                check_grid_path(&g, &path);
                prop_assert!(path.len() as u32 > m, "a path has at least the fewest moves");
            }
            (Err(SearchError::NoPath), None) => {}
            (r, m) => prop_assert!(false, "DFS {r:?}, fewest moves {m:?}"),
        }
    }
}
