//! The buffers a host mission lends the executive, at one of two
//! capacities: the host's (large, for benchmarks) or the firmware's (the
//! chip's: `--capacity fw`), so that the figures reported for the robot are
//! the ones its own buffers give.

use robovac::capacity::{
    FwEvidence, FwFineGrid, FwMatcher, FwPlanGrid, FwPlanner, FwWindow, FW_FINE_PATH, FW_PLAN_CELLS,
};
use robovac::coverage::PlannerKind;
use robovac::mission::Parts;
use robovac::robot::lidar_map::EvidenceMap;
use robovac::Cell;

use crate::capacity::{new_grid, HostGrid, HostMatcher, HostWindow, HOST_EVIDENCE};
use crate::run::plan::HostCoverage;

/// Whose buffers a mission runs in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Capacity {
    /// The host's: maps up to 1024 × 1024 cells, searches over the whole
    /// fine map.
    #[default]
    Host,
    /// The firmware's (`robovac::capacity`): homes up to 12 × 12 m, fine
    /// searches in 2.4 m windows.
    Fw,
}

/// The host's buffers.
pub struct HostParts {
    planner: Box<HostCoverage>,
    search: Box<HostWindow>,
    coarse: Box<HostGrid>,
    fine: Box<HostGrid>,
    /// The evidence map.
    pub map: Box<EvidenceMap<HOST_EVIDENCE>>,
    path: Vec<Cell>,
    matcher: Box<HostMatcher>,
    /// The planning cells' rooms.
    pub rooms: Vec<u8>,
}

impl HostParts {
    /// Fresh buffers.
    pub fn new(kind: PlannerKind) -> Self {
        Self {
            planner: crate::run::plan::new_planner(kind),
            search: crate::capacity::new_window(),
            coarse: new_grid(),
            fine: new_grid(),
            map: Box::new(EvidenceMap::new()),
            path: vec![Cell::default(); 1 << 18],
            matcher: Box::new(HostMatcher::new()),
            rooms: vec![0; crate::capacity::HOST_CELLS],
        }
    }
}

/// The firmware's buffers (`robovac::capacity::FwParts`), on the heap.
pub struct FwHostParts {
    planner: Box<FwPlanner>,
    search: Box<FwWindow>,
    coarse: Box<FwPlanGrid>,
    fine: Box<FwFineGrid>,
    /// The evidence map.
    pub map: Box<FwEvidence>,
    path: Vec<Cell>,
    matcher: Box<FwMatcher>,
    /// The planning cells' rooms.
    pub rooms: Vec<u8>,
}

impl FwHostParts {
    /// Fresh buffers.
    pub fn new(kind: PlannerKind) -> Self {
        Self {
            planner: Box::new(FwPlanner::new(kind)),
            search: Box::new(FwWindow::new()),
            coarse: Box::new(FwPlanGrid::new()),
            fine: Box::new(FwFineGrid::new()),
            map: Box::new(FwEvidence::new()),
            path: vec![Cell::default(); FW_FINE_PATH],
            matcher: Box::new(FwMatcher::new()),
            rooms: vec![0; FW_PLAN_CELLS],
        }
    }
}

/// Lends each set of buffers to the executive as its `Parts`.
macro_rules! lend {
    ($t:ty) => {
        impl $t {
            /// The buffers as the executive takes them.
            pub fn parts(&mut self) -> impl robovac::mission::MissionParts + '_ {
                Parts {
                    planner: &mut self.planner,
                    search: &mut self.search,
                    coarse: &mut self.coarse,
                    fine: &mut self.fine,
                    map: &mut self.map,
                    path: &mut self.path,
                    matcher: &mut self.matcher,
                    rooms: &mut self.rooms,
                }
            }
        }
    };
}
lend!(HostParts);
lend!(FwHostParts);
