//! The buffers a host mission lends the executive, at one of three
//! capacities: the host's (large, for benchmarks) or the firmware's (the
//! F411's: `--capacity fw`; the F405/F407's: `--capacity fw16`), so that
//! the figures reported for the robot are the ones its own buffers give.

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
    /// The F411 firmware's (`robovac::capacity::home12`): homes up to
    /// 12 × 12 m, fine searches in 2.4 m windows.
    Fw,
    /// The F405/F407 firmware's (`robovac::capacity::home16`, feature
    /// `f407`): homes up to 16 × 16 m.
    Fw16,
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

/// A firmware capacity's buffers (`robovac::capacity::home12` or
/// `home16`), on the heap.
macro_rules! fw_parts {
    ($(#[$doc:meta])* $name:ident, $cap:ident) => {
        $(#[$doc])*
        pub struct $name {
            planner: Box<robovac::capacity::$cap::FwPlanner>,
            search: Box<robovac::capacity::$cap::FwWindow>,
            coarse: Box<robovac::capacity::$cap::FwPlanGrid>,
            fine: Box<robovac::capacity::$cap::FwFineGrid>,
            /// The evidence map.
            pub map: Box<robovac::capacity::$cap::FwEvidence>,
            path: Vec<Cell>,
            matcher: Box<robovac::capacity::$cap::FwMatcher>,
            /// The planning cells' rooms.
            pub rooms: Vec<u8>,
        }

        impl $name {
            /// Fresh buffers.
            pub fn new(kind: PlannerKind) -> Self {
                use robovac::capacity::$cap as c;
                Self {
                    planner: Box::new(c::FwPlanner::new(kind)),
                    search: Box::new(c::FwWindow::new()),
                    coarse: Box::new(c::FwPlanGrid::new()),
                    fine: Box::new(c::FwFineGrid::new()),
                    map: Box::new(c::FwEvidence::new()),
                    path: vec![Cell::default(); c::FW_FINE_PATH],
                    matcher: Box::new(c::FwMatcher::new()),
                    rooms: vec![0; c::FW_PLAN_CELLS],
                }
            }
        }
    };
}
fw_parts!(
    /// The F411's buffers: homes up to 12 × 12 m.
    FwHostParts,
    home12
);
fw_parts!(
    /// The F405/F407's buffers: homes up to 16 × 16 m.
    Fw16HostParts,
    home16
);

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
lend!(Fw16HostParts);
