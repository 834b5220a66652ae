//! The big buffers the executive works in, owned by the caller, and the
//! [`MissionParts`] trait through which the entry points take them, so an
//! entry point names one type parameter instead of eight const generics.

use super::{Exec, Mission};
use crate::coverage::{Coverage, PlanStats};
use crate::grid::{Cell, Grid, Layer};
use crate::localize::ScanMatcher;
use crate::robot::hal::Storage;
use crate::robot::lidar_map::EvidenceMap;
use crate::robot::map_image::MapImageError;
use crate::robot::odometry::Pose;
use crate::search::WindowSearch;

/// The big buffers the executive works in, owned by the caller (statics
/// on the robot, heap boxes on the host).
pub struct Parts<
    'a,
    const N: usize,
    const NW: usize,
    const OPEN: usize,
    const LCAP: usize,
    const PCAP: usize,
    const FW: usize,
    const EV: usize,
    const MW: usize,
> {
    /// The coverage planner (on the planning cells).
    pub planner: &'a mut Coverage<N, NW, OPEN, LCAP, PCAP>,
    /// The fine-grid searches (detours, edge transits, the way home),
    /// bounded to a window of `N` fine cells; they run on the planner's
    /// search state, lent ([`Coverage::search_state_mut`]), so `N` is the
    /// larger of the planning cells and the window.
    pub search: &'a mut WindowSearch<N, NW>,
    /// Planning cells.
    pub coarse: &'a mut Grid<NW>,
    /// The fine configuration space (the evidence map's cells).
    pub fine: &'a mut Grid<FW>,
    /// The evidence map (known mode: filled with the prior map).
    pub map: &'a mut EvidenceMap<EV>,
    /// Fine path buffer (detours, edge transits, the way home).
    pub path: &'a mut [Cell],
    /// The scan matcher's points and coarse levels.
    pub matcher: &'a mut ScanMatcher<MW>,
}

/// What the entry points of [`Mission`] need of the caller's buffers.
/// Implemented by [`Parts`] of every size; the methods are the entry
/// points' bodies (call the ones on [`Mission`]).
pub trait MissionParts {
    /// See [`Mission::begin`].
    fn begin(&mut self, m: &mut Mission, start: Pose);
    /// See [`Mission::feed_lidar`].
    fn feed_lidar(&mut self, m: &mut Mission, bytes: &[u8], now_us: u64);
    /// See [`Mission::plan`].
    fn plan(&mut self, m: &mut Mission, now_us: u64);
    /// Saves the evidence map and the `dock` pose on it to `store`, for
    /// the next run ([`crate::robot::map_image`]); the bytes written.
    fn save_map(&self, dock: Pose, store: &mut dyn Storage) -> Result<u32, MapImageError>;
    /// For diagnosis: the coverage planner's counters and position.
    fn planner_view(&self) -> PlannerView;
    /// For diagnosis: planning cell (x, y) as (blocked, covered); `None`
    /// off the planning grid.
    fn planning_cell(&self, x: i32, y: i32) -> Option<(bool, bool)>;
}

/// For diagnosis: what the coverage planner is doing.
#[derive(Clone, Copy, Debug)]
pub struct PlannerView {
    /// Its counters.
    pub stats: PlanStats,
    /// Search nodes of its last step.
    pub last_step_nodes: u32,
    /// Where it stands.
    pub position: Cell,
    /// Points on its backtracking list.
    pub list_len: usize,
}

sized_impl!([MissionParts for Parts<'_, N, NW, OPEN, LCAP, PCAP, FW, EV, MW>] {
    fn begin(&mut self, m: &mut Mission, start: Pose) {
        Exec { m, p: self }.begin(start);
    }

    fn feed_lidar(&mut self, m: &mut Mission, bytes: &[u8], now_us: u64) {
        m.feed_bytes(self.map, self.matcher, bytes, now_us);
    }

    fn plan(&mut self, m: &mut Mission, now_us: u64) {
        Exec { m, p: self }.plan(now_us);
    }

    fn save_map(&self, dock: Pose, store: &mut dyn Storage) -> Result<u32, MapImageError> {
        crate::robot::map_image::save(self.map, dock, store)
    }

    fn planner_view(&self) -> PlannerView {
        PlannerView {
            stats: self.planner.stats(),
            last_step_nodes: self.planner.last_step_nodes(),
            position: self.planner.position(),
            list_len: self.planner.backtrack_list().len(),
        }
    }

    fn planning_cell(&self, x: i32, y: i32) -> Option<(bool, bool)> {
        let g = &*self.coarse;
        g.contains(x, y)
            .then(|| (g.is_blocked(x, y), g.get(Layer::Covered, x, y)))
    }
});
