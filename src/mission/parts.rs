//! The big buffers the executive works in, owned by the caller, and the
//! [`MissionParts`] trait through which the entry points take them, so an
//! entry point names one type parameter instead of nine const generics.

use super::{Exec, Mission};
use crate::coverage::{Coverage, PlanStats};
use crate::grid::{Cell, Grid, Layer};
use crate::localize::ScanMatcher;
use crate::nav::cspace;
use crate::robot::hal::Storage;
use crate::robot::lidar_map::EvidenceMap;
use crate::robot::map_image::MapImageError;
use crate::robot::odometry::Pose;
use crate::robot::progress_image;
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
    const CF: usize,
> {
    /// The coverage planner (on the planning cells).
    pub planner: &'a mut Coverage<N, NW, OPEN, LCAP, PCAP, CF>,
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
    /// The planning cells' rooms, a byte a cell ([`crate::grid::rooms`];
    /// known mode). Shorter than the planning grid: no room tour.
    pub rooms: &'a mut [u8],
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
    /// Saves the map (as [`MissionParts::save_map`]) and after it the
    /// cleaning progress: the planning cells cleaned, less those whose
    /// lanes are still queued ([`crate::robot::progress_image`]). For a
    /// reset mid-mission; the bytes written.
    fn save_progress(
        &self,
        m: &Mission,
        dock: Pose,
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError>;
    /// After [`Mission::begin`] on a map loaded from `store`: marks the
    /// planning cells its saved progress says are clean, so the mission
    /// cleans only the rest. Returns the cells marked.
    fn restore_progress(
        &mut self,
        m: &mut Mission,
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError>;
    /// Once the edge pass has started on a restored progress
    /// ([`Mission::wants_edge_progress`]): marks the contour cells the
    /// saved run's edge pass had cleaned. Returns the cells marked.
    fn restore_edge_progress(
        &mut self,
        m: &mut Mission,
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError>;
    /// For diagnosis: the coverage planner's counters and position.
    fn planner_view(&self) -> PlannerView;
    /// For diagnosis: planning cell (x, y) as (blocked, covered); `None`
    /// off the planning grid.
    fn planning_cell(&self, x: i32, y: i32) -> Option<(bool, bool)>;
    /// The planning grid's width and height, cells.
    fn planning_size(&self) -> (u32, u32);
    /// The room of planning cell (x, y) ([`crate::grid::rooms`]; 0: none).
    fn room_of(&self, x: i32, y: i32) -> u8;
    /// For diagnosis: the evidence counter of the cell holding world
    /// point (x, y) mm (0 off the map).
    fn evidence_at(&self, x_mm: i32, y_mm: i32) -> i8;
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

sized_impl!([Parts<'_, N, NW, OPEN, LCAP, PCAP, FW, EV, MW, CF>] {
    /// Where the progress image starts: after the map image of this map.
    fn progress_at(&self) -> u32 {
        let n = crate::robot::map_image::HEADER_BYTES + self.map.cell_bytes().len() as u32;
        progress_image::offset_after(n)
    }
});

sized_impl!([MissionParts for Parts<'_, N, NW, OPEN, LCAP, PCAP, FW, EV, MW, CF>] {
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

    fn save_progress(
        &self,
        m: &Mission,
        dock: Pose,
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError> {
        let n = crate::robot::map_image::save(self.map, dock, store)?;
        let at = progress_image::offset_after(n);
        let cell = m.cfg.plan_cell_mm;
        let map = &*self.map;
        let pending = |x: i32, y: i32| {
            let ends = m.queue.iter().filter(|&(_, c)| c).map(|(s, _)| s.to);
            let fed = m.feed.filter(|f| f.cover).and_then(|f| f.then);
            ends.chain(fed)
                .any(|(px, py)| cspace::coarse_of(map, cell, px, py) == (x, y))
        };
        let g = &*self.coarse;
        let clean = |x: i32, y: i32| g.get(Layer::Covered, x, y) && !pending(x, y);
        let mut end = at + progress_image::save(g, cell, clean, store, at)?;
        let f = &*self.fine;
        if (f.width(), f.height()) == (map.width(), map.height()) {
            // The fine cells swept: the lanes' track, which the edge pass
            // takes as swept ([`super::edge`]), and in the edge pass its
            // visited contour cells, not the rooms outside its scope
            // ([`super::rooms`]). Saved from the lanes on, not only in the
            // edge pass: without the lanes' track, the rerun after a power
            // loss in the lanes edged every wall the first run's lanes had
            // swept (studio and home flat, realistic, 5 cuts: 63-65 % of
            // the studio swept again by the rerun, 46-48 % with it).
            let at = progress_image::offset_after(end);
            let scoped = |x: i32, y: i32| {
                let (mx, my) = cspace::fine_centre_mm(map, x, y);
                let (gx, gy) = cspace::coarse_of(map, cell, mx, my);
                m.rooms.out_of_scope(g, self.rooms, gx, gy)
            };
            let visited = |x: i32, y: i32| f.get(Layer::Covered, x, y) && !scoped(x, y);
            end = at + progress_image::save(f, self.map.res_mm(), visited, store, at)?;
        }
        Ok(end)
    }

    fn restore_progress(
        &mut self,
        m: &mut Mission,
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError> {
        let at = self.progress_at();
        let marked = progress_image::load(self.coarse, m.cfg.plan_cell_mm, store, at)?;
        m.restored = true;
        let edges = progress_image::offset_after(at + progress_image::bytes(self.coarse));
        m.edge_progress_pending = progress_image::present(store, edges);
        Ok(marked)
    }

    fn restore_edge_progress(
        &mut self,
        m: &mut Mission,
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError> {
        m.edge_progress_pending = false;
        let at = self.progress_at();
        let edges = progress_image::offset_after(at + progress_image::bytes(self.coarse));
        let n = progress_image::load(self.fine, self.map.res_mm(), store, edges)?;
        // The saved run drove them: not for the pass's recheck.
        crate::nav::edge::settle_driven(self.fine);
        Ok(n)
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

    fn planning_size(&self) -> (u32, u32) {
        (self.coarse.width(), self.coarse.height())
    }

    fn room_of(&self, x: i32, y: i32) -> u8 {
        crate::grid::rooms::label_at(self.coarse, self.rooms, x, y)
    }

    fn evidence_at(&self, x_mm: i32, y_mm: i32) -> i8 {
        let (cx, cy) = self.map.cell_of(x_mm, y_mm);
        self.map.evidence(cx, cy)
    }
});
