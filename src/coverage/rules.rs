//! What distinguishes one coverage planner from another, as data: each
//! planner file under [`super::planners`] names its [`Rules`], and the step
//! loop in [`super`] acts on them. A leaf: uses `search` (for [`Algo`]).

use crate::search::Algo;

/// The move priority of local coverage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Priority {
    /// A fixed order of (dx, dy) moves.
    Fixed([(i32, i32); 4]),
    /// Along the map's long side (B-OHA* §2.1).
    ByAspect,
}

/// How the next local move is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LocalMove {
    /// The highest-priority free uncovered 4-neighbour.
    Priority,
    /// A neighbour leading into a small pocket first (B-OHA*-PC, and seed
    /// 001's closed areas).
    PocketsFirst,
    /// The neighbour the bio-inspired network's activity and turn term
    /// rank first (seed 004's BINN, [`super::planners::binn`]).
    LeastTurn,
    /// The unvisited neighbour farthest from the start by the distance
    /// transform in the field (seed 004's wavefront,
    /// [`super::planners::wavefront`]).
    Wavefront,
    /// Around the spanning tree of 2 × 2 mega-cells in the field (seed
    /// 004's STC, [`super::planners::stc`]).
    SpanningTree,
    /// Boustrophedon inside the robot's decomposition cell, labelled in the
    /// field (seed 004's BCD, [`super::planners::bcd`]).
    CellSweep,
    /// Comb or inner spiral inside the robot's region, classed in the
    /// field (seed 003, [`super::planners::regions`]).
    Regions,
}

impl LocalMove {
    /// Whether the rule keeps a value per cell in the planner's field.
    pub const fn needs_field(self) -> bool {
        matches!(
            self,
            LocalMove::Wavefront
                | LocalMove::SpanningTree
                | LocalMove::CellSweep
                | LocalMove::Regions
        )
    }
}

/// What enters the backtracking list, and when it is trimmed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ListRule {
    /// Uncovered 8-neighbours on arrival at each cell; at a critical point
    /// only uncovered corner cells stay (B-OHA*). Points are uncovered
    /// cells.
    NeighboursPrunedToCorners,
    /// Rebuilt at every critical point from covered cells with b(s) ≥ 1
    /// (BA*). Points are covered cells next to uncovered ones.
    RebuiltFromCovered,
    /// Uncovered 8-neighbours on arrival; at a critical point the cells at
    /// corners or edges of their uncovered region stay (seed 002's
    /// dead-zone list, [`super::planners::template`]).
    NeighboursPrunedToEdges,
    /// North and south backtracking marks set while sweeping east or west
    /// (seed 001, [`super::planners::mark_backtrack`]).
    Marks,
    /// Nothing is listed while sweeping; at a dead end the completeness
    /// rescan lists every uncovered region's corner cells
    /// ([`super::planners::binn`]: the network's activity leads to the
    /// nearest uncovered region).
    RescanOnly,
}

impl ListRule {
    /// Whether the list's points are uncovered cells (every rule but BA*'s).
    pub const fn points_uncovered(self) -> bool {
        !matches!(self, ListRule::RebuiltFromCovered)
    }
}

/// A planner's rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rules {
    /// Move priority.
    pub priority: Priority,
    /// Local move choice.
    pub local: LocalMove,
    /// Backtracking list rule.
    pub list: ListRule,
    /// Goals per transit search (the nearest points, straight-line).
    pub transit_goals: usize,
    /// The transit search.
    pub transit: Algo,
    /// Whether a transit path is pruned (Algorithm 1) before it is driven.
    pub prune_transit: bool,
}
