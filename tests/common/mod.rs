//! Helpers shared by the core's integration tests: an independent float
//! Dijkstra (the oracle) and path checkers that do not use the core's code.
#![allow(dead_code)]

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use robovac::{Cell, Grid};

pub const SQ2: f64 = std::f64::consts::SQRT_2;

pub fn free(grid: &Grid<{ W }>, x: i32, y: i32) -> bool {
    x >= 0
        && y >= 0
        && (x as u32) < grid.width()
        && (y as u32) < grid.height()
        && !grid.is_blocked(x, y)
}

/// Test capacity: up to 64 × 64 cells.
pub const CELLS: usize = 64 * 64;
pub const W: usize = CELLS / 32;
pub type TGrid = Grid<W>;
pub type TSearch = robovac::SearchState<CELLS, W, CELLS>;

pub fn new_state() -> Box<TSearch> {
    Box::new(TSearch::new())
}

#[derive(PartialEq)]
struct Node(f64, i32, i32);
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0)
    }
}

/// Float Dijkstra from `s`, 8-connected, no corner cutting. Distances for
/// every cell (infinite where unreachable), row-major.
pub fn dijkstra(grid: &TGrid, s: Cell) -> Vec<f64> {
    let (w, h) = (grid.width() as i32, grid.height() as i32);
    let mut dist = vec![f64::INFINITY; (w * h) as usize];
    let mut pq = BinaryHeap::new();
    dist[(s.y as i32 * w + s.x as i32) as usize] = 0.0;
    pq.push(Node(0.0, s.x as i32, s.y as i32));
    while let Some(Node(d, x, y)) = pq.pop() {
        if d > dist[(y * w + x) as usize] {
            continue;
        }
        for dy in -1..=1 {
            for dx in -1..=1 {
                if dx == 0 && dy == 0 {
                    continue;
                }
                let (nx, ny) = (x + dx, y + dy);
                if !free(grid, nx, ny) {
                    continue;
                }
                if dx != 0 && dy != 0 && !(free(grid, x + dx, y) && free(grid, x, y + dy)) {
                    continue;
                }
                let nd = d + if dx != 0 && dy != 0 { SQ2 } else { 1.0 };
                let k = (ny * w + nx) as usize;
                if nd < dist[k] - 1e-12 {
                    dist[k] = nd;
                    pq.push(Node(nd, nx, ny));
                }
            }
        }
    }
    let _ = h;
    dist
}

/// Checks that a path is a chain of 8-connected steps over free cells with
/// no corner cutting; returns its length.
pub fn check_grid_path(grid: &TGrid, path: &[Cell]) -> f64 {
    let mut len = 0.0;
    for c in path {
        assert!(
            free(grid, c.x as i32, c.y as i32),
            "path enters blocked {c:?}"
        );
    }
    for w in path.windows(2) {
        let (dx, dy) = (w[1].x as i32 - w[0].x as i32, w[1].y as i32 - w[0].y as i32);
        assert!(
            dx.abs() <= 1 && dy.abs() <= 1 && (dx, dy) != (0, 0),
            "not a step: {w:?}"
        );
        if dx != 0 && dy != 0 {
            assert!(
                free(grid, w[0].x as i32 + dx, w[0].y as i32)
                    && free(grid, w[0].x as i32, w[0].y as i32 + dy),
                "corner cut at {w:?}"
            );
            len += SQ2;
        } else {
            len += 1.0;
        }
    }
    len
}

/// Conservative line test independent of the supercover walk in
/// `robovac::grid::los`: the checker's exact segment/closed-square intersection.
pub fn segment_clear(grid: &TGrid, a: Cell, b: Cell) -> bool {
    robovac::verify::check::touched_cells(a, b, |x, y| free(grid, x, y))
}

pub fn polyline_len(p: &[Cell]) -> f64 {
    p.windows(2)
        .map(|w| {
            ((w[0].x as f64 - w[1].x as f64).powi(2) + (w[0].y as f64 - w[1].y as f64).powi(2))
                .sqrt()
        })
        .sum()
}

/// A random map from a seed (density in percent).
pub fn random_grid(w: u32, h: u32, density: u32, seed: u64) -> Box<TGrid> {
    test_support::random_grid(w, h, density, seed)
}
