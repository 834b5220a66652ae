//! Resume after a power loss (issue 12): the caller saves the map and the
//! cleaning progress through [`MissionParts::save_progress`] every so
//! often; after a reset it loads the map, begins, and restores the
//! progress here, so the mission cleans only what is left
//! ([`crate::robot::progress_image`]).

use super::{Mission, MissionParts, Phase};
use crate::robot::hal::Storage;
use crate::robot::map_image::MapImageError;

impl Mission {
    /// After [`Mission::begin`] on a map an earlier run saved with its
    /// progress ([`MissionParts::save_progress`], as after a power loss):
    /// the planning cells it had cleaned are marked, and the lanes plan
    /// only the rest. Returns the cells marked; on any error none are
    /// (the whole home is cleaned again).
    pub fn restore_progress(
        &mut self,
        parts: &mut (impl MissionParts + ?Sized),
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError> {
        parts.restore_progress(self, store)
    }

    /// The edge pass has started on a restored progress that holds the
    /// fine cells swept (the lanes' track, and the edge pass's own when the
    /// save came in the pass): call [`Mission::restore_edge_progress`] now
    /// (its grid is built only when the pass starts).
    pub fn wants_edge_progress(&self) -> bool {
        self.edge_progress_pending && self.phase == Phase::Edge && self.fine_is_edge
    }

    /// Marks the fine cells the saved run had swept (its lanes' track and
    /// the contour cells its edge pass had cleaned), so the pass skips the
    /// walls the lanes swept and goes on where it was cut short. Once;
    /// returns the cells marked.
    pub fn restore_edge_progress(
        &mut self,
        parts: &mut (impl MissionParts + ?Sized),
        store: &mut dyn Storage,
    ) -> Result<u32, MapImageError> {
        parts.restore_edge_progress(self, store)
    }
}
