//! Complete-coverage plans on the host: the core planner driven to
//! completion, its polyline, metrics, JSON and SVG.

use std::time::Instant;

use robovac::coverage::{Coverage, PlanStats, PlannerKind, Step, Waypoint};
use robovac::verify::metrics::{Metrics, MetricsRecorder, SegmentKind};
use robovac::Cell;

use crate::capacity::{
    new_grid, HostGrid, HOST_CELLS, HOST_LCAP, HOST_OPEN, HOST_PCAP, HOST_WORDS,
};
use crate::io::maps::MapData;

/// The host coverage planner.
pub type HostCoverage =
    Coverage<HOST_CELLS, HOST_WORDS, HOST_OPEN, HOST_LCAP, HOST_PCAP, HOST_CELLS>;

/// A host planner on the heap, without building it on the stack.
pub fn new_planner(kind: PlannerKind) -> Box<HostCoverage> {
    let b = Box::<HostCoverage>::new_zeroed();
    // SAFETY: `Coverage` documents that all-zero bytes are a valid idle
    // planner (integers, arrays of integers, `#[repr(u8)]` enums whose
    // discriminant 0 is a variant, and the zero-valid `SearchState`).
    let mut p = unsafe { b.assume_init() };
    p.set_kind(kind);
    p
}

/// Parses a planner name.
pub fn planner_by_name(s: &str) -> Option<PlannerKind> {
    ALL_PLANNERS.iter().copied().find(|k| k.name() == s)
}

/// Seed 000's planners (its Table 2), baselines first.
pub const SEED000_PLANNERS: [PlannerKind; 4] = [
    PlannerKind::BaStar,
    PlannerKind::BTheta,
    PlannerKind::BOha,
    PlannerKind::BOhaPc,
];

/// Every coverage planner ([`PlannerKind::ALL`]).
pub const ALL_PLANNERS: [PlannerKind; 11] = PlannerKind::ALL;

/// The planners' command-line names, comma-separated (for messages).
pub fn planner_names() -> String {
    ALL_PLANNERS.map(|k| k.name()).join(", ")
}

/// A segment of the output polyline: waypoints `from..=to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    /// Cover or transit.
    pub kind: SegmentKind,
    /// Index of the first waypoint.
    pub from: usize,
    /// Index of the last waypoint.
    pub to: usize,
}

/// A finished plan.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The planner.
    pub kind: PlannerKind,
    /// Start cell.
    pub start: Cell,
    /// Waypoints, collinear moves of one kind merged.
    pub waypoints: Vec<Cell>,
    /// Runs of one kind.
    pub segments: Vec<Segment>,
    /// Cells where local coverage ended (critical points).
    pub critical_points: Vec<Cell>,
    /// Backtracking points reached (ends of transits).
    pub backtrack_points: Vec<Cell>,
    /// Metrics (the core's single definition).
    pub metrics: Metrics,
    /// Planner counters.
    pub stats: PlanStats,
    /// Planning time, µs.
    pub time_us: f64,
    /// The largest number of nodes one `step` call expanded.
    pub max_nodes_per_call: u64,
    /// Every move as the planner emitted it (before merging).
    pub moves: Vec<Waypoint>,
}

impl Plan {
    /// coverage = covered / reachable.
    pub fn coverage(&self) -> f64 {
        ratio(self.metrics.covered_cells, self.metrics.reachable_cells)
    }
    /// repetition = repeated / reachable.
    pub fn repetition(&self) -> f64 {
        ratio(self.metrics.repeated_cells, self.metrics.reachable_cells)
    }
}

fn ratio(a: u32, b: u32) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// Plans a complete coverage of `map` from `start` (default: the first free
/// cell in reading order).
pub fn plan(map: &MapData, kind: PlannerKind, start: Option<Cell>) -> Result<Plan, String> {
    let mut grid = new_grid();
    map.to_grid(&mut *grid).map_err(|e| e.to_string())?;
    let start = match start {
        Some(s) => s,
        None => map.first_free().ok_or("the map has no free cell")?,
    };
    let mut planner = new_planner(kind);
    plan_on(&mut grid, &mut planner, start, u32::MAX)
}

/// Plans on a prepared grid with a node budget per `step` call.
pub fn plan_on(
    grid: &mut HostGrid,
    planner: &mut HostCoverage,
    start: Cell,
    budget: u32,
) -> Result<Plan, String> {
    let (sx, sy) = start.xy();
    if !grid.contains(sx, sy) {
        return Err(format!(
            "start ({sx},{sy}) is off the {}x{} map",
            grid.width(),
            grid.height()
        ));
    }
    if grid.is_blocked(sx, sy) {
        return Err(format!("start ({sx},{sy}) is an obstacle"));
    }
    let mut rec: Box<MetricsRecorder<HOST_WORDS>> = Box::new(MetricsRecorder::new());
    rec.start(&*grid, start);
    let t0 = Instant::now();
    planner
        .start(&mut *grid, start)
        .map_err(|e| e.to_string())?;
    let mut steps: Vec<Waypoint> = Vec::new();
    let mut max_nodes = 0u64;
    loop {
        let s = planner
            .step(&mut *grid, budget)
            .map_err(|e| e.to_string())?;
        max_nodes = max_nodes.max(planner.last_step_nodes() as u64);
        match s {
            Step::Move(w) => steps.push(w),
            Step::Pending => {}
            Step::Done => break,
        }
    }
    let time_us = t0.elapsed().as_secs_f64() * 1e6;
    let stats = planner.stats();
    for w in &steps {
        rec.push(w.to, w.kind, w.starts_segment);
    }

    rec.add_planner_counts(stats.backtrack_points_total, stats.nodes_expanded);
    let (waypoints, kinds, critical_points, backtrack_points) = shape_moves(&steps, start);
    let segments = group_segments(&kinds);
    Ok(Plan {
        kind: planner.kind(),
        start,
        waypoints,
        segments,
        critical_points,
        backtrack_points,
        metrics: rec.metrics(),
        stats,
        time_us,
        max_nodes_per_call: max_nodes,
        moves: steps,
    })
}

/// The moves as a drawing: collinear moves of one kind merged into
/// waypoints (with, per waypoint, the kind of the segment ending there and
/// whether a new cover segment starts with it), the critical points, and
/// the backtracking points reached.
#[allow(clippy::type_complexity)]
fn shape_moves(
    steps: &[Waypoint],
    start: Cell,
) -> (Vec<Cell>, Vec<(SegmentKind, bool)>, Vec<Cell>, Vec<Cell>) {
    let mut waypoints = vec![start];
    // Per waypoint: kind of the segment ending there, and whether a new
    // cover segment starts with it.
    let mut kinds: Vec<(SegmentKind, bool)> = vec![(SegmentKind::Cover, true)];
    let mut critical_points = Vec::new();
    let mut backtrack_points = Vec::new();
    for (i, w) in steps.iter().enumerate() {
        let (c, k) = (w.to, w.kind);
        if w.starts_segment && i > 0 {
            critical_points.push(*waypoints.last().unwrap_or(&start));
        }
        if k == SegmentKind::Transit
            && steps
                .get(i + 1)
                .is_none_or(|s| s.kind != SegmentKind::Transit || s.starts_segment)
        {
            // the end of a transit: the backtracking point (or the cell
            // before it, when the goal was uncovered)
            let goal = steps
                .get(i + 1)
                .filter(|s| s.starts_segment)
                .map_or(c, |s| s.to);
            backtrack_points.push(goal);
        } else if w.starts_segment
            && i > 0
            && steps
                .get(i.wrapping_sub(1))
                .is_some_and(|s| s.kind == SegmentKind::Cover)
        {
            backtrack_points.push(c); // a neighbouring point: no transit
        }
        let n = waypoints.len();
        let collinear = !w.starts_segment && n >= 2 && kinds[n - 1].0 == k && {
            let (a, b) = (waypoints[n - 2], waypoints[n - 1]);
            let (ux, uy) = (b.x as i64 - a.x as i64, b.y as i64 - a.y as i64);
            let (vx, vy) = (c.x as i64 - b.x as i64, c.y as i64 - b.y as i64);
            ux * vy - uy * vx == 0 && ux * vx + uy * vy > 0
        };
        if collinear {
            waypoints[n - 1] = c;
        } else {
            waypoints.push(c);
            kinds.push((k, w.starts_segment));
        }
    }
    (waypoints, kinds, critical_points, backtrack_points)
}

/// Waypoints grouped into segments (a new cover segment also starts where
/// the planner marks one).
fn group_segments(kinds: &[(SegmentKind, bool)]) -> Vec<Segment> {
    let mut segments: Vec<Segment> = Vec::new();
    for (i, &(k, new)) in kinds.iter().enumerate().skip(1) {
        match segments.last_mut() {
            Some(s) if s.kind == k && s.to == i - 1 && !(new && k == SegmentKind::Cover) => {
                s.to = i
            }
            _ => segments.push(Segment {
                kind: k,
                from: i - 1,
                to: i,
            }),
        }
    }
    segments
}

/// Metrics as JSON (lengths in cells, rotation in degrees).
pub fn metrics_json(p: &Plan) -> serde_json::Value {
    serde_json::to_value(PlanMetrics::of(p)).unwrap_or_default()
}

/// A plan's metrics as reported (lengths in cells, rotation in degrees).
#[derive(Clone, Debug, serde::Serialize)]
pub struct PlanMetrics {
    /// Free cells reachable from the start.
    pub reachable_cells: u32,
    /// Of those, covered.
    pub covered_cells: u32,
    /// covered ÷ reachable.
    pub coverage: f64,
    /// Cells covered more than once.
    pub repeated_cells: u32,
    /// repeated ÷ covered.
    pub repetition: f64,
    /// Length of the cover moves, cells.
    pub coverage_path_length: f64,
    /// Length of the transits, cells.
    pub backtrack_path_length: f64,
    /// Both, cells.
    pub total_path_length: f64,
    /// Heading changes.
    pub turns: u32,
    /// Total rotation, degrees.
    pub rotation_deg: f64,
    /// Cover segments.
    pub segments: u32,
    /// Points ever put on the backtracking list.
    pub backtrack_points_total: u32,
    /// Search nodes expanded.
    pub nodes_expanded: u64,
    /// Planning time on this host, µs.
    pub time_us: f64,
}

impl PlanMetrics {
    /// The metrics of `p`.
    pub fn of(p: &Plan) -> Self {
        let m = &p.metrics;
        let cells = |c: u64| c as f64 / robovac::math::cost::COST_PER_CELL as f64;
        Self {
            reachable_cells: m.reachable_cells,
            covered_cells: m.covered_cells,
            coverage: p.coverage(),
            repeated_cells: m.repeated_cells,
            repetition: p.repetition(),
            coverage_path_length: cells(m.coverage_path_cost),
            backtrack_path_length: cells(m.backtrack_path_cost),
            total_path_length: cells(m.coverage_path_cost + m.backtrack_path_cost),
            turns: m.turns,
            rotation_deg: m.rotation_urad as f64 * 1e-6 * 180.0 / std::f64::consts::PI,
            segments: m.segments,
            backtrack_points_total: m.backtrack_points_total,
            nodes_expanded: m.nodes_expanded,
            time_us: p.time_us,
        }
    }
}

/// The plan as the JSON document of `host-sim plan --json`.
pub fn plan_json(map: &MapData, p: &Plan) -> serde_json::Value {
    let rows: Vec<String> = map.to_ascii().lines().map(str::to_string).collect();
    serde_json::json!({
        "planner": p.kind.name(),
        "map": {"width": map.width, "height": map.height, "cell_m": map.cell_m},
        "grid": rows,
        "start": [p.start.x, p.start.y],
        "waypoints": p.waypoints.iter().map(|c| [c.x, c.y]).collect::<Vec<_>>(),
        "segments": p.segments.iter().map(|s| serde_json::json!({
            "kind": match s.kind { SegmentKind::Cover => "cover", SegmentKind::Transit => "transit" },
            "from": s.from, "to": s.to,
        })).collect::<Vec<_>>(),
        "critical_points": p.critical_points.iter().map(|c| [c.x, c.y]).collect::<Vec<_>>(),
        "backtrack_points": p.backtrack_points.iter().map(|c| [c.x, c.y]).collect::<Vec<_>>(),
        "metrics": metrics_json(p),
    })
}
