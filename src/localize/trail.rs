//! The floor the robot's own body has just swept: no wall stands there.
//!
//! **Why** (issue 10 §2, "unmapped points must not pull"; unknown mode):
//! a person who follows the robot walks on the floor it has just left.
//! Unknown mode maps them like a wall when they stand still for a moment,
//! and their later returns, landing on their own mapped cells, then pull
//! the pose back toward where they stood. [`super::points::ScanPoints::drop_foreground`]
//! drops a person standing free in front of a wall, but not one standing
//! against a wall seen edge-on, where person and wall are one run of
//! returns. In the twin (the studio, unknown mode, harsh floors,
//! 3 people, seed 3) a person followed the robot 0.35 m behind along the
//! bottom wall: every revolution's match pulled the pose back by its full
//! step while the robot drove 0.5 m, and the robot was lost for good.
//!
//! The robot's centre passed every sample of the trail, so a disc of
//! [`CLEAR_MM`] round it was inside its body a moment ago: any return
//! landing there is something that moved in since. Those returns are left
//! out of the match ([`super::points::ScanPoints::drop_on`]); the map still
//! gets them, since the planner must avoid people.
//!
//! This is free-space evidence from the robot's footprint, as occupancy
//! mappers that clear the robot's own cells do (ROS costmap_2d's
//! footprint clearing), kept to a short trail so that it costs no map
//! layer: 32 samples 100 mm apart, the last 3.2 m driven.
//!
//! Samples are in the frame the pose is estimated in, as the scan points
//! are: a relocalisation that moves the pose elsewhere empties the trail
//! ([`Trail::clear`]).

use crate::math::cost::dist_mm;

/// Samples kept.
pub const TRAIL_LEN: usize = 32;
/// Distance driven between samples, mm.
pub const STEP_MM: i64 = 100;
/// Radius round each sample taken as swept, mm. The body's radius is
/// 165 mm and the planner keeps it 10 mm off walls, so a wall's returns
/// lie at least 175 mm from the trail; this keeps 35 mm for the pose's
/// drift between a sample and the scan. With samples 100 mm apart the
/// discs cover a band of ± 130 mm round the path without gaps.
pub const CLEAR_MM: i64 = 140;

/// The last [`TRAIL_LEN`] positions of the robot's centre, [`STEP_MM`]
/// apart, in cm (a 4-byte sample; ± 327 m).
#[derive(Clone, Debug, Default)]
pub struct Trail {
    at_cm: [(i16, i16); TRAIL_LEN],
    len: u8,
    next: u8,
}

impl Trail {
    /// An empty trail.
    pub const fn new() -> Self {
        Self {
            at_cm: [(0, 0); TRAIL_LEN],
            len: 0,
            next: 0,
        }
    }

    /// Forgets every sample (the pose moved elsewhere).
    pub fn clear(&mut self) {
        self.len = 0;
        self.next = 0;
    }

    /// Samples held.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    /// True when no sample is held.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The samples, mm, in no particular order.
    fn samples(&self) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.at_cm
            .iter()
            .take(self.len())
            .map(|&(x, y)| (i32::from(x) * 10, i32::from(y) * 10))
    }

    /// The newest sample, mm.
    fn last(&self) -> Option<(i32, i32)> {
        let i = (usize::from(self.next) + TRAIL_LEN - 1) % TRAIL_LEN;
        let &(x, y) = self.at_cm.get(i).filter(|_| !self.is_empty())?;
        Some((i32::from(x) * 10, i32::from(y) * 10))
    }

    /// Records the robot's centre at `at_mm` when it is [`STEP_MM`] or
    /// more from the newest sample; the oldest goes when the trail is
    /// full. A position beyond ± 327 m is not recorded.
    pub fn note(&mut self, at_mm: (i32, i32)) {
        if self.last().is_some_and(|l| dist_mm(l, at_mm) < STEP_MM) {
            return;
        }
        let cm = |v: i32| i16::try_from(v.div_euclid(10)).ok();
        let (Some(x), Some(y)) = (cm(at_mm.0), cm(at_mm.1)) else {
            return;
        };
        if let Some(slot) = self.at_cm.get_mut(usize::from(self.next)) {
            *slot = (x, y);
        }
        self.next = ((usize::from(self.next) + 1) % TRAIL_LEN) as u8;
        self.len = (self.len() + 1).min(TRAIL_LEN) as u8;
    }

    /// The box (x0, y0, x1, y1, mm) holding every disc of the trail; a
    /// point outside it is not [`Self::swept`] (most of a scan: the walls
    /// beyond the trail, rejected with four comparisons).
    pub fn bounds(&self) -> Option<(i32, i32, i32, i32)> {
        let r = CLEAR_MM as i32;
        self.samples().fold(None, |b, (x, y)| {
            let (x0, y0, x1, y1) = b.unwrap_or((x, y, x, y));
            Some((x0.min(x - r), y0.min(y - r), x1.max(x + r), y1.max(y + r)))
        })
    }

    /// True when `p_mm` lies within [`CLEAR_MM`] of a sample: floor the
    /// body swept.
    pub fn swept(&self, p_mm: (i32, i32)) -> bool {
        self.samples().any(|s| {
            let (dx, dy) = ((p_mm.0 - s.0).abs(), (p_mm.1 - s.1).abs());
            i64::from(dx.max(dy)) <= CLEAR_MM && dist_mm(s, p_mm) <= CLEAR_MM
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_every_step_and_keeps_the_last_ones() {
        let mut t = Trail::new();
        assert!(!t.swept((0, 0)));
        for x in (0..10_000).step_by(10) {
            t.note((x, 500));
        }
        assert_eq!(t.len(), TRAIL_LEN);
        // The last 3.2 m are swept, the beginning is forgotten.
        assert!(t.swept((9_990, 500)));
        assert!(t.swept((9_990 - 3_000, 500 + 130)));
        assert!(!t.swept((1_000, 500)));
        let (x0, y0, x1, y1) = t.bounds().unwrap_or_default();
        assert_eq!((x0, y0, x1, y1), (6_800 - 140, 360, 9_900 + 140, 640));
        // Beside the path: within the disc, and not at a wall's distance.
        assert!(t.swept((9_550, 500 - 130)));
        assert!(!t.swept((9_550, 500 - 175)));
        t.clear();
        assert!(t.is_empty() && !t.swept((9_990, 500)) && t.bounds().is_none());
    }

    #[test]
    fn a_scan_loses_only_its_points_on_the_trail() {
        use crate::localize::{PoseU, ScanPoints};
        // The robot drove north along x = 500 mm and faces north.
        let mut t = Trail::new();
        for y in (0..=1_000).step_by(20) {
            t.note((500, y));
        }
        let here = PoseU {
            x_mm: 500,
            y_mm: 1_000,
            theta_urad: 1_570_796,
        };
        let mut pts = ScanPoints::new();
        // Behind (on the trail), a wall 180 mm left of the trail, ahead.
        pts.set(here, &[(-350, 0), (-350, 180), (350, 0), (-700, -30)]);
        assert_eq!(pts.drop_on(&t), 2);
        assert_eq!(pts.as_slice(), &[(-350, 180), (350, 0)]);
        assert_eq!(pts.drop_on(&Trail::new()), 0);
    }

    #[test]
    fn far_positions_are_not_recorded() {
        let mut t = Trail::new();
        t.note((i32::MAX, 0));
        t.note((-400_000, 0));
        assert!(t.is_empty());
        t.note((-5, -5));
        assert!(t.swept((0, 0)));
    }
}
