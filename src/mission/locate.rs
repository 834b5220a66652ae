//! Localisation in the executive ([`crate::localize`]): once per
//! revolution, before the scan is mapped.
//!
//! - **Start (known mode):** the first revolution, taken at a standstill
//!   on the dock, is matched over a window of ±0.24 m and ±15° around the
//!   given dock pose (a person put the robot down); the pose found becomes
//!   the odometry's and the dock's (the robot returns to where it truly
//!   started).
//! - **Tracking:** every revolution corrects the odometry as
//!   [`crate::localize::fusion`] allows, and the scan is then mapped at
//!   the corrected poses (unknown mode maps in the corrected frame). In
//!   unknown mode, where a scan mapped in a wrong frame stays in the map,
//!   a revolution whose pose is in doubt is not mapped
//!   ([`crate::localize::Fusion::mappable`]: a large correction still
//!   gliding in, or a prediction that fits poorly).
//! - **Lost:** control brakes ([`super::State::Relocalising`]); every
//!   revolution taken at a standstill is matched over the whole map until
//!   one is accepted; then the leg ahead is planned again from where the
//!   robot is. No scan is mapped while lost. Lost for `lost_timeout_us`:
//!   [`super::Fault::Lost`].
//! - **Standstill (unknown mode):** while the robot stands still, only
//!   one revolution in [`STILL_MAP_EVERY`] is mapped (the motion filter
//!   of Hector SLAM's map update thresholds, Kohlbrecher 2011, and of
//!   Cartographer's local SLAM). Each revolution's match follows the map
//!   and each mapped revolution moves the map's walls toward the pose just
//!   matched; ten of those a second from one spot fed each other, and a
//!   robot turning and waiting beside one wall dragged its pose and its
//!   map 60 mm in 10 s, then mapped the rest of the home in that frame
//!   (the 3790 home, unknown mode, realistic, 1 person, seed 9, 1,476 s:
//!   pose RMS 40.4 mm; 2.5 mm with the filter). Once a second still maps
//!   what changes about a robot standing still (a person stepping up).
//!   In both modes a revolution at a standstill corrects the heading but
//!   not the position, unless the match fits clearly better than the
//!   prediction ([`crate::localize::fusion::held_still`]): a person
//!   walking past must not slide a waiting robot.
//! - **Unknown mode** rebuilds the coarse levels every
//!   [`REBUILD_EVERY`] revolutions (the fine level reads the map live).

use super::events::EventKind;
use super::{Activity, MapMode, Mission, Phase};
use crate::localize::fusion::{standing_still, Correction, STILL_MM};
use crate::localize::trail::Trail;
use crate::localize::{PoseU, ScanMatcher};
use crate::robot::lidar_map::EvidenceMap;

/// Revolutions between coarse-level rebuilds in unknown mode.
pub const REBUILD_EVERY: u32 = 10;
/// At a standstill, unknown mode maps one revolution in this many (by the
/// scan count: 1 s at 10 Hz; the module doc).
pub const STILL_MAP_EVERY: u32 = 10;

impl Mission {
    /// Matches the revolution just completed; returns whether it may be
    /// mapped.
    pub(super) fn locate<const EV: usize, const MW: usize>(
        &mut self,
        map: &EvidenceMap<EV>,
        mt: &mut ScanMatcher<MW>,
        now_us: u64,
    ) -> bool {
        if !self.cfg.localize {
            return true;
        }
        let prior_only = self.cfg.mode == MapMode::Known;
        if !prior_only && self.counters.scans % REBUILD_EVERY == 1 {
            mt.pyramid.build(map, false);
            self.loc.stats.rebuilds += 1;
        }
        mt.points.load(&self.lidar.scan, &self.cfg.mount);
        if !prior_only {
            // People are mapped in unknown mode: their returns must not
            // pull the pose toward where they stood (`drop_foreground`).
            mt.points.drop_foreground();
            // Nor may those of someone following on the floor the body
            // has just swept (`localize::trail`).
            mt.points.drop_on(&mt.trail);
            let r = mt.points.reference();
            mt.trail.note((r.x_mm, r.y_mm));
        }
        let (moved, turned) = self.lidar.scan.motion();
        let still = standing_still(moved, turned);
        let start_window = prior_only || self.cfg.prior_saved;
        if start_window && !self.start_fixed && matches!(self.phase, Phase::SelfTestScan { .. }) {
            if still {
                self.start_fixed = true;
                if let Ok(p) = self.loc.relocalise(mt, map, prior_only, false) {
                    self.jump_to(&mut mt.trail, p, now_us);
                    self.start = self.drive.odom.pose();
                    return true;
                }
            }
            // Not matched at the dock yet (or not at all): the pose may be
            // up to the window off. A known map's prior is fixed, but a
            // saved map's walls are the lidar's to move
            // ([`EvidenceMap::thaw_prior`]): mapped there, a revolution
            // 90 mm and 60 mrad off wiped the walls by the dock, and the
            // robot never found itself again (a power-loss rerun on the
            // home flat, realistic, seed 1: failed lost at its start).
            return prior_only;
        }
        if self.loc.lost {
            if still {
                if let Ok(p) = self.loc.relocalise(mt, map, prior_only, true) {
                    self.jump_to(&mut mt.trail, p, now_us);
                    self.relocated = true;
                    self.activity = Activity::Follow;
                }
            }
            return false;
        }
        let r = self.loc.track(mt, map, prior_only, still, moved > STILL_MM);
        // Known mode maps only what the prior lacks (people, a moved
        // chair) beside a prior that stays fixed: nothing drifts into it.
        let filtered = still && !self.counters.scans.is_multiple_of(STILL_MAP_EVERY);
        let mappable = prior_only || (self.loc.mappable() && !filtered);
        match r {
            Ok(c) => {
                self.apply(c);
                mappable
            }
            Err(_) if self.loc.lost => {
                self.lost_since_us = now_us;
                self.events.push(now_us, EventKind::Lost);
                false
            }
            Err(_) => mappable,
        }
    }

    /// Applies a tracking correction to the odometry and to the scan about
    /// to be mapped.
    fn apply(&mut self, c: Correction) {
        let (dx, dy, dt) = c;
        self.drive.odom.correct(dx, dy, dt);
        let dt_mrad = ((dt + dt.signum() * 500) / 1000) as i32;
        self.lidar.scan.shift(dx, dy, dt_mrad);
    }

    /// Sets the odometry to a relocalised pose and reports it. The trail
    /// is emptied: it was drawn in the frame the jump leaves.
    fn jump_to(&mut self, trail: &mut Trail, p: PoseU, now_us: u64) {
        trail.clear();
        let (x, y, t) = self.drive.odom.pose_fine();
        let (dx, dy) = (
            p.x_mm - (x / 1_000_000) as i32,
            p.y_mm - (y / 1_000_000) as i32,
        );
        let dt = crate::localize::correlative::wrap_urad(p.theta_urad - t);
        // The revolution just matched was taken at the pose the jump
        // leaves: it moves with the odometry, and is mapped (at the start)
        // at the pose found. Exact for a revolution taken standing, as
        // every relocalisation's is.
        self.apply((dx, dy, dt));
        let now = self.drive.odom.pose();
        self.events.push(
            now_us,
            EventKind::Relocalised {
                x_mm: now.x_mm,
                y_mm: now.y_mm,
                theta_mrad: now.theta_mrad,
                moved_mm: dx.abs() + dy.abs(),
            },
        );
    }

    /// Localisation's counters.
    pub fn loc_stats(&self) -> crate::localize::LocStats {
        self.loc.stats
    }

    /// True while lost (braked, relocalising).
    pub fn lost(&self) -> bool {
        self.loc.lost
    }
}
