//! The lidar event: bytes into frames, hits into the ring ([`HitRing`]:
//! the last [`super::RING`] points, each tagged with whether the map
//! explains it), revolutions matched against the map ([`super::locate`])
//! and then into the evidence map. Before the mission begins, frames are
//! parsed and go no further.

use super::{MapMode, Mission, Phase};
use crate::localize::ScanMatcher;
use crate::nav::geometry::explained;
use crate::robot::beam::{beams, Beam};
use crate::robot::lidar::LidarProtocol;
use crate::robot::lidar_map::EvidenceMap;

/// A lidar hit: world mm, and whether the map explains it.
pub(super) type Hit = (i32, i32, bool);

/// The last `N` hits; a new one overwrites the oldest. Its slice is in
/// storage order, as `heapless::HistoryBuf::as_slice` (which it replaces:
/// that one indexes its storage with a bounds check the compiler cannot
/// remove, a panicking branch in the firmware, issue 11 §6).
pub(super) struct HitRing<const N: usize> {
    buf: [Hit; N],
    len: usize,
    next: usize,
}

impl<const N: usize> HitRing<N> {
    pub(super) const fn new() -> Self {
        Self {
            buf: [(0, 0, false); N],
            len: 0,
            next: 0,
        }
    }

    /// Adds a hit, overwriting the oldest when full.
    pub(super) fn write(&mut self, h: Hit) {
        if let Some(slot) = self.buf.get_mut(self.next) {
            *slot = h;
        }
        self.next = if self.next + 1 >= N { 0 } else { self.next + 1 };
        self.len = (self.len + 1).min(N);
    }

    /// The hits held, in storage order.
    pub(super) fn as_slice(&self) -> &[Hit] {
        self.buf.get(..self.len).unwrap_or(&[])
    }
}

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
            if self.phase == Phase::Idle {
                // Before `begin` (the robot image waits at the dock for
                // its button) the pose is not yet known: odometry says
                // the map's corner. The frames are parsed and counted,
                // and go no further.
                continue;
            }
            let ring = &mut self.lidar.ring;
            let known = &*map;
            beams(
                &pose,
                &self.cfg.mount,
                &frame,
                0,
                |&Beam {
                     end: (hx, hy), hit, ..
                 }| {
                    if hit {
                        ring.write((hx, hy, explained(known, (hx, hy))));
                    }
                },
            );
            if self.lidar.asm.push(&frame, pose, &mut self.lidar.scan) {
                self.counters.scans += 1;
                let mappable = self.locate(map, matcher, now_us);
                if mappable && (self.cfg.mode == MapMode::Unknown || self.cfg.map_known_updates) {
                    map.integrate_scan(&self.lidar.scan, &self.cfg.mount);
                    self.map_dirty = true;
                    // The derived grids change only where a cell's state
                    // did (most revolutions change none).
                    if let Some(changed) = map.take_changed() {
                        self.note_map_change(map.res_mm(), changed);
                    }
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
