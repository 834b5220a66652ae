//! The lidar event: bytes into frames, hits into the ring ([`HitRing`]:
//! the last [`super::RING`] points, each tagged with whether the map
//! explains it), revolutions matched against the map ([`super::locate`])
//! and then into the evidence map. Before the mission begins, frames are
//! parsed and go no further.

use super::{MapMode, Mission, Phase};
use crate::localize::ScanMatcher;
use crate::nav::geometry::{explained, wall_offset};
use crate::robot::beam::{beams, Beam};
use crate::robot::lidar::LidarProtocol;
use crate::robot::lidar_map::EvidenceMap;

/// A lidar hit: world mm, whether the map explains it, and for a mapped
/// hit the wall surface it stands for ([`wall_offset`]: an offset, so the
/// hit keeps its 12 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Hit {
    pub x: i32,
    pub y: i32,
    pub mapped: bool,
    pub wall: Option<[i8; 2]>,
}

// The ring's memory is the firmware's (issue 11 §3): the wall offset
// lives in what was padding.
const _: () = assert!(core::mem::size_of::<Hit>() == 12);

impl Hit {
    const NONE: Self = Self {
        x: 0,
        y: 0,
        mapped: false,
        wall: None,
    };

    /// The hit's position, world mm.
    pub(super) fn at(&self) -> (i32, i32) {
        (self.x, self.y)
    }

    /// The wall surface point it stands for, world mm, if the map has one.
    pub(super) fn wall_point(&self) -> Option<(i32, i32)> {
        self.wall
            .map(|[dx, dy]| (self.x + dx as i32, self.y + dy as i32))
    }
}

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
            buf: [Hit::NONE; N],
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

    /// Every hit moved by (`dx`, `dy`) mm (the map scrolled,
    /// [`super::scroll`]); the wall offsets are relative and stay.
    pub(super) fn shift(&mut self, dx: i32, dy: i32) {
        for h in self.buf.iter_mut() {
            h.x = h.x.saturating_add(dx);
            h.y = h.y.saturating_add(dy);
        }
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
            // A hit stands for a wall point within 2.5 σ of the range
            // noise (the guard's slack is 1 σ); with an ideal sensor, only
            // a hit on the wall's square does ([`wall_offset`]).
            let tol_mm = self.cfg.guard.mapped_slack_mm.max(0) * 5 / 2;
            let ring = &mut self.lidar.ring;
            let known = &*map;
            let fixed_only = self.cfg.mode == MapMode::Known;
            beams(
                &pose,
                &self.cfg.mount,
                &frame,
                0,
                |&Beam {
                     end: (hx, hy), hit, ..
                 }| {
                    if hit {
                        let q = (hx, hy);
                        let mapped = explained(known, q);
                        let from = (pose.x_mm, pose.y_mm);
                        ring.write(Hit {
                            x: hx,
                            y: hy,
                            mapped,
                            wall: mapped
                                .then(|| wall_offset(known, q, from, tol_mm, fixed_only))
                                .flatten(),
                        });
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
        self.lidar.ring.as_slice().iter().map(Hit::at)
    }

    /// The latest lidar hits the map explains (walls, furniture) or not
    /// (people, a moved chair, an unmapped wall).
    pub(super) fn points_where(&self, mapped: bool) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.lidar
            .ring
            .as_slice()
            .iter()
            .filter(move |p| p.mapped == mapped)
            .map(Hit::at)
    }
}
