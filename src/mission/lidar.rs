//! The lidar event: bytes into frames, hits into the ring (a
//! `heapless::HistoryBuf` of the last [`super::RING`] points, each tagged
//! with whether the map explains it), revolutions matched against the map
//! ([`super::locate`]) and then into the evidence map.

use super::{MapMode, Mission};
use crate::localize::ScanMatcher;
use crate::nav::geometry::explained;
use crate::robot::lidar::LidarProtocol;
use crate::robot::lidar_map::{beams, EvidenceMap};

impl Mission {
    /// The lidar event's body (see [`Mission::feed_lidar`]).
    pub(super) fn feed_bytes<const EV: usize, const MW: usize>(
        &mut self,
        map: &mut EvidenceMap<EV>,
        matcher: &mut ScanMatcher<MW>,
        bytes: &[u8],
        now_us: u64,
    ) {
        let pose = self.drive.odom.pose();
        for &b in bytes {
            let Some(frame) = self.lidar.parser.feed(b) else {
                continue;
            };
            self.lidar.last_frame_us = now_us;
            let ring = &mut self.lidar.ring;
            let known = &*map;
            beams(&pose, &self.cfg.mount, &frame, 0, |_, _, hx, hy, hit| {
                if hit {
                    ring.write((hx, hy, explained(known, (hx, hy))));
                }
            });
            if self.lidar.asm.push(&frame, pose, &mut self.lidar.scan) {
                self.counters.scans += 1;
                let mappable = self.locate(map, matcher, now_us);
                if mappable && (self.cfg.mode == MapMode::Unknown || self.cfg.map_known_updates) {
                    map.integrate_scan(&self.lidar.scan, &self.cfg.mount);
                    self.map_dirty = true;
                    self.fine_stale = true;
                }
            }
        }
    }

    /// The latest lidar hits, world mm.
    pub(super) fn points(&self) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.lidar.ring.as_slice().iter().map(|&(x, y, _)| (x, y))
    }

    /// The latest lidar hits the map explains (walls, furniture) or not
    /// (people, a moved chair, an unmapped wall).
    pub(super) fn points_where(&self, mapped: bool) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.lidar
            .ring
            .as_slice()
            .iter()
            .filter(move |p| p.2 == mapped)
            .map(|&(x, y, _)| (x, y))
    }
}
