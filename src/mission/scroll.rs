//! The map scrolls under the robot (issue 11 §3). The robot image's map
//! is 12 × 12 m with the dock at its centre, in the frame the robot had on
//! the dock; a real home fits such a box but not centred on its dock (four
//! of the six Valetudo homes reach up to 9.8 m from it,
//! `host-sim/tests/dock_map.rs`). So in unknown mode, when the robot comes
//! within [`SCROLL_NEAR_MM`] of the map's edge and what it has seen leaves
//! room on the far side, the map moves by whole planning cells to put the
//! robot nearer its centre, and nothing seen is lost.
//!
//! **When.** At a planning step of the lanes between two moves: following
//! (no avoidance or back-off), no fine path or route being fed, no
//! boxed-in wait, not lost, the lanes not done. The way home, the edge
//! pass and a charge keep the frame they began in (the dock, seen from
//! the start, stays on the map: the seen box holds it).
//!
//! **What moves.** The evidence cells ([`crate::robot::lidar_map::EvidenceMap::shift`]), the
//! planning grid's covered layer (by whole planning cells: a shift is a
//! multiple of the planning cell), the fine grid's (the lanes' track,
//! which the edge pass leaves out: left in place, the track of the lanes
//! before a 3.9 m scroll told the edge pass that a wall 3.9 m further on
//! was swept), and every pose in world mm: the
//! odometry, the dock, the revolution being assembled and the last one,
//! the ring of lidar hits. What is planned is not moved but dropped and
//! planned again, as a restored progress is after a power loss
//! ([`super::progress`]): the queued cleaning goes back to the planner,
//! which starts again from the robot's cell keeping its covered layer;
//! the grids are derived again; the short-lived notes (a held move, a
//! replan target, bump places, the trail) are forgotten. The matcher's
//! levels are rebuilt from the moved map.
//!
//! **Cost.** One pass over the map's bytes for the seen box, only near
//! the edge and at most every [`LOOK_AGAIN_STEPS`] steps when no scroll
//! fits; a scroll moves every cell once and derives the grids whole (a
//! one-off of the size of the start's).
//!
//! Not with owner's zones (drawn in the map's frame), a saved map (its
//! frame is the one the next run relocalises in) or known mode (a floor
//! plan): [`MissionConfig::scroll_map`] is for a first, unknown-mode run.

use super::{Activity, Mission, Phase};
use crate::grid::Layer;
use crate::robot::odometry::Pose;

/// Within this of the map's edge the map scrolls, mm: beyond the lidar's
/// reliable range of walls from a lane's end, so the floor past the edge
/// is seen before the lanes would want it.
pub const SCROLL_NEAR_MM: i32 = 2000;

/// Planning steps between two looks for a scroll when none fitted (10 s at
/// 10 Hz): the look costs a pass over the map.
pub const LOOK_AGAIN_STEPS: u32 = 100;

/// Free cells this close to an edge, cells, say the map cuts through
/// floor there (a wall closes the home inside it otherwise).
pub const CUT_CELLS: i32 = 2;

/// The span of the cells seen, and of the free cells, along one axis.
pub type Spans = ((i32, i32), (i32, i32));

/// The shift along one axis, fine cells (positive: the contents move up
/// the index): the robot at cell `at` of a side of `side` cells, within
/// `near` cells of an edge where the free cells reach it (the map cuts
/// through floor there), is moved toward the centre as far as the seen
/// cells stay on the map, in multiples of `step` (the planning cell).
/// 0: not near such an edge, or no room. An edge the home's walls close
/// inside the map is never scrolled past: a room that nearly fills the
/// map would otherwise be scrolled back and forth as the lanes go from
/// end to end (the long room in `host-sim/tests/dock_map.rs`: 8 scrolls).
pub fn scroll_amount(
    at: i32,
    side: i32,
    ((lo, hi), (free_lo, free_hi)): Spans,
    near: i32,
    step: i32,
) -> i32 {
    let step = step.max(1);
    let to_centre = side / 2 - at;
    let s = if at < near && free_lo < CUT_CELLS {
        to_centre.min(side - 1 - hi)
    } else if at >= side - near && free_hi >= side - CUT_CELLS {
        -((-to_centre).min(lo))
    } else {
        0
    };
    // Whole planning cells, toward 0.
    s.checked_div(step).unwrap_or(0) * step
}

sized_impl!([] {
    /// Scrolls the map when the robot nears its edge and what it has seen
    /// leaves room (the module doc). True when it scrolled (the lanes were
    /// started again: the step is over).
    pub(super) fn scroll_when_due(&mut self, now_us: u64, pose: &Pose) -> bool {
        if !self.scroll_ready() {
            return false;
        }
        let map = &*self.p.map;
        let res = map.res_mm().max(1) as i32;
        let (cx, cy) = map.cell_of(pose.x_mm, pose.y_mm);
        let (w, h) = (map.width() as i32, map.height() as i32);
        let near = SCROLL_NEAR_MM.checked_div(res).unwrap_or(0);
        let edge = cx < near || cy < near || cx >= w - near || cy >= h - near;
        if !edge || self.m.counters.plan_steps < self.m.scroll_look_at {
            return false;
        }
        let step = (self.m.cfg.plan_cell_mm as i32).checked_div(res).unwrap_or(1);
        let shift = map.seen_boxes().map(|((x0, y0, x1, y1), (fx0, fy0, fx1, fy1))| {
            (
                scroll_amount(cx, w, ((x0, x1), (fx0, fx1)), near, step),
                scroll_amount(cy, h, ((y0, y1), (fy0, fy1)), near, step),
            )
        });
        match shift {
            Some((dx, dy)) if (dx, dy) != (0, 0) => self.scroll(now_us, dx, dy),
            _ => {
                self.m.scroll_look_at = self.m.counters.plan_steps + LOOK_AGAIN_STEPS;
                false
            }
        }
    }

    /// The moment allows a scroll (the module doc's "when").
    fn scroll_ready(&self) -> bool {
        let m = &*self.m;
        m.cfg.scroll_map
            && m.cfg.mode == super::MapMode::Unknown
            && !m.cfg.prior_saved
            && m.phase == Phase::Cover
            && m.activity == Activity::Follow
            && !m.planner_done
            && m.feed.is_none()
            && !m.route.active()
            && m.boxed_wait.is_none()
            && !m.loc.lost
            && m.halted_since.is_none()
            && self.p.map.zone_count() == 0
    }

    /// Moves the map `dx` columns right and `dy` rows down (fine cells,
    /// multiples of the planning cell), everything in world mm with it,
    /// and starts the lanes again from where the robot stands.
    fn scroll(&mut self, now_us: u64, dx: i32, dy: i32) -> bool {
        self.put_back_queue(None);
        if !self.p.map.shift(dx, dy) {
            return false;
        }
        let res = self.p.map.res_mm() as i32;
        let step = (self.m.cfg.plan_cell_mm as i32).checked_div(res).unwrap_or(1).max(1);
        // Checked: no panicking branch in the firmware (issue 11 §6).
        let (gx, gy) = (dx.checked_div(step).unwrap_or(0), dy.checked_div(step).unwrap_or(0));
        for layer in [Layer::Covered, Layer::Known] {
            self.p.coarse.shift_layer(layer, gx, gy);
            // The fine grid's: the lanes' track, which the edge pass
            // leaves out (`super::edge`).
            self.p.fine.shift_layer(layer, dx, dy);
        }
        let (mx, my) = (dx * res, -dy * res);
        self.m.translate(mx, my);
        self.p.matcher.trail.clear();
        self.p.matcher.pyramid.build(self.p.map, false);
        self.m.loc.stats.rebuilds += 1;
        let pose = self.m.drive.odom.pose();
        self.m.events.push(now_us, super::EventKind::MapScrolled { dx_mm: mx, dy_mm: my });
        self.m.restored = true;
        self.m.fine_stale = true;
        self.start_cover(now_us, &pose);
        true
    }
});

impl Mission {
    /// Everything the executive keeps in world mm moves by (`dx`, `dy`)
    /// mm; what was planned in the old frame is forgotten (the module
    /// doc).
    fn translate(&mut self, dx: i32, dy: i32) {
        let mv = |p: (i32, i32)| (p.0.saturating_add(dx), p.1.saturating_add(dy));
        self.drive.odom.correct(dx, dy, 0);
        self.lidar.asm.shift(dx, dy);
        self.lidar.scan.shift(dx, dy, 0);
        self.lidar.ring.shift(dx, dy);
        (self.start.x_mm, self.start.y_mm) = mv((self.start.x_mm, self.start.y_mm));
        self.route.clear();
        self.in_route = false;
        self.replan_target = None;
        self.replan_count = 0;
        self.held_to = None;
        self.apf_minimum = None;
        self.bump_places = super::bump::BumpPlaces::new();
        self.edge_give_ups = super::bump::BumpPlaces::new();
        self.pocket = super::cover::Pocket::new();
        self.boxed_tries = 0;
        self.skipped_goals.clear();
        self.trace_at = None;
        self.edge_rejoined_at = None;
        self.guard_block_since = None;
        self.near_walls = crate::nav::keep_off::NearWalls::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Near the low edge the contents move up, as far as the seen span
    /// allows, in whole steps; near the high edge down; in the middle, or
    /// with no room, not at all.
    #[test]
    fn amounts() {
        // 240 cells, near 40, step 6: at 10 with the seen span 0..=150
        // and floor cut at the low edge, the centre is 110 away but only
        // 89 fit: 84.
        assert_eq!(scroll_amount(10, 240, ((0, 150), (1, 140)), 40, 6), 84);
        // Plenty of room: to the centre, rounded down to a step (110 → 108).
        assert_eq!(scroll_amount(10, 240, ((0, 60), (0, 50)), 40, 6), 108);
        // The high edge: at 230, seen from 100: the centre is 110 away,
        // 100 fit: −96.
        assert_eq!(
            scroll_amount(230, 240, ((100, 239), (110, 239)), 40, 6),
            -96
        );
        // In the middle, or no room, or less room than a step: none.
        assert_eq!(scroll_amount(120, 240, ((0, 239), (0, 239)), 40, 6), 0);
        assert_eq!(scroll_amount(5, 240, ((0, 239), (0, 239)), 40, 6), 0);
        assert_eq!(scroll_amount(5, 240, ((0, 235), (0, 230)), 40, 6), 0);
        // A wall closes the home 2 cells in: nothing is cut, no scroll.
        assert_eq!(scroll_amount(10, 240, ((2, 150), (3, 140)), 40, 6), 0);
        assert_eq!(scroll_amount(230, 240, ((100, 237), (110, 236)), 40, 6), 0);
    }
}
