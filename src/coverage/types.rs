//! What the coverage planner hands out: waypoints, steps, errors and its
//! counters. A leaf of the coverage layer.

use crate::grid::Cell;
use crate::search::SearchError;
use crate::verify::metrics::SegmentKind;

/// A waypoint to drive straight to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Waypoint {
    /// The cell to drive to.
    pub to: Cell,
    /// Cleaning (local coverage) or transit to a backtracking point.
    pub kind: SegmentKind,
    /// The first cover move after a critical point (or of the run).
    pub starts_segment: bool,
}

/// The next thing for the robot to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Step {
    /// Drive straight to a waypoint.
    Move(Waypoint),
    /// A transit search used up this call's node budget; call again.
    Pending,
    /// Every reachable cell is covered.
    Done,
}

/// Why planning stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CoverageError {
    /// The start is off the map or an obstacle.
    BadStart,
    /// `step` before `start`.
    NotStarted,
    /// A transit search failed for capacity (open list, map size).
    Search(SearchError),
    /// A transit path is longer than the path buffer `PCAP`.
    PathTooLong,
    /// The planner keeps a value per cell (wavefront, STC, BCD, regions) and this
    /// build's field (`F`) is smaller than the map.
    NoField,
}

impl CoverageError {
    /// A short human-readable description.
    pub const fn as_str(self) -> &'static str {
        match self {
            CoverageError::BadStart => "start is off the map or blocked",
            CoverageError::NotStarted => "planner not started",
            CoverageError::Search(e) => e.as_str(),
            CoverageError::PathTooLong => "transit path exceeds the path buffer",
            CoverageError::NoField => {
                "this planner needs a per-cell field larger than this build's"
            }
        }
    }
}

impl core::fmt::Display for CoverageError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Counters the planner keeps (the metrics' planner-side fields).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlanStats {
    /// Points ever inserted into the backtracking list.
    pub backtrack_points_total: u32,
    /// The list's size after each critical point's pruning (B-OHA*) or
    /// rebuild (BA*), summed: the paper's count, as its ≈ 700 (B-OHA*) and
    /// ≈ 3 885 (BA*) suggest.
    pub backtrack_points_kept: u32,
    /// Nodes expanded by transit searches.
    pub nodes_expanded: u64,
    /// Critical points reached (ends of local coverage).
    pub critical_points: u32,
    /// Transit searches run.
    pub searches: u32,
    /// Rescans that found uncovered cells the list had lost.
    pub rescans_with_points: u32,
    /// Points dropped because the list was full.
    pub list_overflows: u32,
    /// Goals abandoned as unreachable.
    pub abandoned_goals: u32,
    /// Transit segments re-planned because the grid changed under them.
    pub replans: u32,
}
