//! Coverage metrics: one definition, used by every planner, the CLI and
//! the benchmarks (the tests recompute them independently).
//!
//! A run is the polyline the robot drives: waypoints joined by segments
//! tagged [`SegmentKind::Cover`] or [`SegmentKind::Transit`].
//! - A cell is **covered** when the centre line passes through it: a
//!   segment covers every cell of its supercover line ([`crate::grid::los`]),
//!   both side cells included where it passes exactly through a corner.
//! - **Repeated** cells count visits beyond the first; each segment visits
//!   its cells after its first (which the previous segment already
//!   visited), so a waypoint is not counted twice.
//! - Lengths are Euclidean, accumulated in cost units
//!   ([`crate::math::cost::COST_PER_CELL`] per cell, rounded per segment).
//! - A **turn** is a waypoint where the heading changes; a boustrophedon
//!   U-turn is two. Rotation sums the absolute heading changes (µrad,
//!   integer CORDIC).
//! - **Segments** count cover segments: a cover segment starts at every
//!   waypoint marked `starts_segment` (the first cover move of the run and
//!   after each critical point) and at a cover move that follows a transit.
//! - **Reachable** cells are the free cells connected to the start
//!   (8-connected without corner cutting, which connects exactly the
//!   4-connected components).

use crate::grid::los::supercover;
use crate::grid::{Cell, Grid};
use crate::math::angle::atan2_urad;
use crate::math::bits::Bits;
use crate::math::cost::euclid;

/// What a segment of the driven polyline is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SegmentKind {
    /// Cleaning by local boustrophedon motion.
    Cover,
    /// Travelling to a backtracking point (the paper's repeated travel).
    Transit,
}

/// A run's measurements (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Metrics {
    /// Free cells reachable from the start.
    pub reachable_cells: u32,
    /// Distinct cells the centre line passed through.
    pub covered_cells: u32,
    /// Visits beyond the first.
    pub repeated_cells: u32,
    /// Length of cover segments, cost units.
    pub coverage_path_cost: u64,
    /// Length of transit segments, cost units.
    pub backtrack_path_cost: u64,
    /// Heading changes at waypoints.
    pub turns: u32,
    /// Sum of absolute heading changes, µrad.
    pub rotation_urad: u64,
    /// Cover segments.
    pub segments: u32,
    /// Points ever inserted into the backtracking list.
    pub backtrack_points_total: u32,
    /// Nodes expanded by all transit searches.
    pub nodes_expanded: u64,
}

/// Records a polyline into [`Metrics`] as it is driven.
pub struct MetricsRecorder<const NW: usize> {
    visited: Bits<NW>,
    metrics: Metrics,
    width: u32,
    height: u32,
    last: Option<Cell>,
    last_dir: (i32, i32),
    last_kind: Option<SegmentKind>,
}

impl<const NW: usize> Default for MetricsRecorder<NW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NW: usize> MetricsRecorder<NW> {
    /// An empty recorder.
    pub const fn new() -> Self {
        Self {
            visited: Bits::new(),
            metrics: Metrics {
                reachable_cells: 0,
                covered_cells: 0,
                repeated_cells: 0,
                coverage_path_cost: 0,
                backtrack_path_cost: 0,
                turns: 0,
                rotation_urad: 0,
                segments: 0,
                backtrack_points_total: 0,
                nodes_expanded: 0,
            },
            width: 0,
            height: 0,
            last: None,
            last_dir: (0, 0),
            last_kind: None,
        }
    }

    /// Starts a run on `grid` at `start`: counts the reachable cells and
    /// visits the start.
    pub fn start<const GW: usize>(&mut self, grid: &Grid<GW>, start: Cell) {
        *self = Self::new();
        self.width = grid.width();
        self.height = grid.height();
        self.metrics.reachable_cells = reachable(grid, start, &mut self.visited);
        self.visited.clear_all();
        self.visit(start.xy());
        self.last = Some(start);
    }

    fn visit(&mut self, (x, y): (i32, i32)) {
        if x < 0 || y < 0 || x as u32 >= self.width || y as u32 >= self.height {
            return;
        }
        let i = y as usize * self.width as usize + x as usize;
        if self.visited.get(i) {
            self.metrics.repeated_cells += 1;
        } else {
            self.visited.put(i, true);
            self.metrics.covered_cells += 1;
        }
    }

    /// Adds the segment from the last waypoint to `to`; `starts_segment`
    /// marks the first cover move of a cover segment.
    pub fn push(&mut self, to: Cell, kind: SegmentKind, starts_segment: bool) {
        let Some(from) = self.last else {
            return;
        };
        let (dx, dy) = (to.x as i32 - from.x as i32, to.y as i32 - from.y as i32);
        if (dx, dy) == (0, 0) {
            return;
        }
        let len = euclid(dx, dy) as u64;
        match kind {
            SegmentKind::Cover => self.metrics.coverage_path_cost += len,
            SegmentKind::Transit => self.metrics.backtrack_path_cost += len,
        }
        if kind == SegmentKind::Cover
            && (starts_segment || self.last_kind != Some(SegmentKind::Cover))
        {
            self.metrics.segments += 1;
        }
        let (px, py) = self.last_dir;
        if (px, py) != (0, 0) {
            let cross = px as i64 * dy as i64 - py as i64 * dx as i64;
            let dot = px as i64 * dx as i64 + py as i64 * dy as i64;
            if cross != 0 || dot < 0 {
                self.metrics.turns += 1;
                self.metrics.rotation_urad += atan2_urad(cross.abs(), dot) as u64;
            }
        }
        let mut first = true;
        supercover(from.xy(), to.xy(), |x, y| {
            if first {
                first = false;
            } else {
                self.visit((x, y));
            }
            true
        });
        self.last = Some(to);
        self.last_dir = (dx, dy);
        self.last_kind = Some(kind);
    }

    /// Adds to the planner-side counters.
    pub fn add_planner_counts(&mut self, backtrack_points: u32, nodes: u64) {
        self.metrics.backtrack_points_total += backtrack_points;
        self.metrics.nodes_expanded += nodes;
    }

    /// The metrics so far.
    pub fn metrics(&self) -> Metrics {
        self.metrics
    }
}

/// Marks in `out` the free cells reachable from `start` (4-connected, which
/// equals 8-connected without corner cutting) and returns their number;
/// 0 when the start is blocked. Repeated forward and backward sweeps: no
/// queue, no allocation.
pub fn reachable<const GW: usize, const NW: usize>(
    grid: &Grid<GW>,
    start: Cell,
    out: &mut Bits<NW>,
) -> u32 {
    out.clear_all();
    let (w, h) = (grid.width() as i32, grid.height() as i32);
    let (sx, sy) = start.xy();
    let Some(si) = grid.index(sx, sy) else {
        return 0;
    };
    if grid.is_blocked(sx, sy) {
        return 0;
    }
    out.put(si, true);
    let mut count = 1u32;
    let mut changed = true;
    let mut forward = true;
    while changed {
        changed = false;
        for k in 0..(w * h) {
            let i = if forward { k } else { w * h - 1 - k };
            let (x, y) = (i % w, i / w);
            if out.get(i as usize) || grid.is_blocked(x, y) {
                continue;
            }
            let near = [(1, 0), (-1, 0), (0, 1), (0, -1)]
                .iter()
                .any(|&(dx, dy)| grid.index(x + dx, y + dy).is_some_and(|j| out.get(j)));
            if near {
                out.put(i as usize, true);
                count += 1;
                changed = true;
            }
        }
        forward = !forward;
    }
    count
}
