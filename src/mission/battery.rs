//! Recharge and resume (issue 12): when the charge left covers only the
//! way home and a reserve, the robot stops cleaning, goes home, charges,
//! and goes on where it stopped.
//!
//! **The rule** ([`BatteryParams`]): at every planning step while
//! cleaning, the charge needed to get home is
//! `reserve + drain × (straight line to the dock × detour ÷ speed)`,
//! where the drain is the larger of the configured one and the one
//! measured since the robot last left the dock (after 2 minutes). At or
//! below it, home. [open] The way home's true length is not known until
//! it is searched (a search over the whole map every step would cost more
//! than the step has); twice the straight line, and a reserve for the
//! rest, is the choice, checked on the twin's battery in the tests (the
//! robot never arrives with less than the reserve's half).
//!
//! **Resume.** The lanes or edges still queued go back to the planner
//! (as a given-up sub-path's do), so nothing planned is lost; on the
//! dock (the turn to its heading done) the robot charges to `resume_pm`
//! and drives back to where the planner (or the edge pass) stood, then
//! goes on. Without a state of charge given
//! ([`super::Mission::set_charge`]), the time budget `battery_us` ends
//! the mission instead, as before.

use super::{Activity, Fault, Phase};
use crate::math::cost::dist_mm;
use crate::mission::config::BatteryParams;
use crate::nav::cspace;
use crate::robot::odometry::Pose;

/// The battery as the executive knows it.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Charge {
    /// The latest state of charge, ‰ (None: never given).
    pub now_pm: Option<u16>,
    /// The charge and time when the robot last set out, ‰ and µs.
    depart: Option<(u16, u64)>,
    /// Gone home to charge: what to go on with.
    pub resume: Option<Resume>,
}

/// What the robot goes on with after charging.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Resume {
    /// The lanes ([`Phase::Cover`]).
    Lanes,
    /// The edge pass ([`Phase::Edge`]).
    Edges,
}

impl super::Mission {
    /// The battery's state of charge, ‰ (0..=1000; more saturates), from
    /// the pack's fuel gauge or [`crate::robot::battery::charge_from_mv`];
    /// as often as it is measured (every control period at most). Once
    /// given, the charge decides when to go home to recharge and when to
    /// go on ([`super::MissionConfig::battery`]); never given, the time budget
    /// `battery_us` ends the mission.
    pub fn set_charge(&mut self, charge_pm: u16) {
        self.battery.now_pm = Some(charge_pm.min(1000));
    }

    /// The owner (the robot's button) or a low battery asks the robot
    /// home: at the next planning step in which it is cleaning (the lanes
    /// or the edge pass) it stops cleaning and returns to the dock, as
    /// when the cleaning budget runs out. Already on its way home, done
    /// or failed: nothing changes.
    pub fn request_home(&mut self) {
        self.home_requested = true;
    }
}

impl Charge {
    /// No charge known yet.
    pub const fn new() -> Self {
        Self {
            now_pm: None,
            depart: None,
            resume: None,
        }
    }

    /// The drain to plan with, ‰ per minute: the configured one, or the
    /// one measured since setting out when higher.
    fn drain_pm_per_min(&mut self, p: &BatteryParams, pm: u16, now_us: u64) -> u64 {
        let (pm0, t0) = *self.depart.get_or_insert((pm, now_us));
        let dt_us = now_us.saturating_sub(t0);
        let measured = if dt_us >= 120_000_000 {
            (pm0.saturating_sub(pm) as u64) * 60_000_000 / dt_us
        } else {
            0
        };
        measured.max(p.drain_pm_per_min as u64)
    }

    /// The charge now covers only the way home from `here` to `dock`
    /// and the reserve.
    pub fn low(
        &mut self,
        p: &BatteryParams,
        here: (i32, i32),
        dock: (i32, i32),
        now_us: u64,
    ) -> bool {
        let Some(pm) = self.now_pm else {
            return false;
        };
        let drain = self.drain_pm_per_min(p, pm, now_us);
        let home_mm = dist_mm(here, dock) as u64 * p.home_detour_pct as u64 / 100;
        let speed = (p.home_speed_mm_s as u64).max(1);
        let need = p.reserve_pm as u64 + drain * home_mm / (speed * 60);
        (pm as u64) <= need
    }
}

sized_impl!([] {
    /// Going home to charge: the queued cleaning goes back to the planner
    /// (or the edge pass), to be driven after the charge.
    pub(super) fn leave_for_charge(&mut self, pose: &Pose) {
        let m = &mut *self.m;
        m.battery.resume = Some(if m.phase == Phase::Edge {
            Resume::Edges
        } else {
            Resume::Lanes
        });
        let tail = m.feed.filter(|f| f.cover).and_then(|f| f.then);
        self.put_back_queue(tail);
        let m = &mut *self.m;
        m.feed = None;
        m.route.clear();
        m.activity = Activity::Follow;
        m.queue.reset((pose.x_mm, pose.y_mm));
        // The edge pass keeps its grid (its visited cells are the pass's
        // progress); the way home plans on it.
        m.fine_is_edge = m.phase == Phase::Edge && m.fine_is_edge;
        self.begin_return(pose);
    }

    /// On the dock: charged to `resume_pm`, go on; the owner's button,
    /// stay (done); the charge not rising, fail.
    pub(super) fn charging_step(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        let Phase::Charging { since_us, from_pm } = m.phase else {
            return;
        };
        let pm = m.battery.now_pm.unwrap_or(0);
        let p = m.cfg.battery;
        if core::mem::take(&mut m.home_requested) {
            m.battery.resume = None;
            m.phase = Phase::Done;
        } else if pm >= p.resume_pm {
            self.resume_cleaning(now_us, pose, pm);
        } else if now_us.saturating_sub(since_us) > p.charge_timeout_us && pm < from_pm + 20 {
            self.fail(Fault::NotCharging);
        }
    }

    /// Back to the phase left, from the dock: a transit to where the
    /// planner or the edge pass stood, then on as before.
    fn resume_cleaning(&mut self, now_us: u64, pose: &Pose, pm: u16) {
        let m = &mut *self.m;
        let Some(resume) = m.battery.resume.take() else {
            m.phase = Phase::Done;
            return;
        };
        m.counters.charges += 1;
        m.battery.depart = Some((pm, now_us));
        m.home_tries = 0;
        m.home_best_mm = u16::MAX;
        m.guard_block_since = None;
        m.activity = Activity::Follow;
        m.queue.reset((pose.x_mm, pose.y_mm));
        m.subpath_since_us = now_us;
        m.phase = match resume {
            Resume::Lanes => Phase::Cover,
            Resume::Edges => Phase::Edge,
        };
        let to = if resume == Resume::Edges {
            let c = m.edge.position();
            cspace::fine_centre_mm(self.p.map, c.x as i32, c.y as i32)
        } else if !m.planner_done {
            let (x, y) = self.p.planner.position().xy();
            self.anchor(x, y)
        } else {
            // The lanes were done: the cover step starts the edge pass.
            return;
        };
        self.enqueue(to, false);
    }
});

#[cfg(test)]
mod tests {
    use super::*;

    const P: BatteryParams = BatteryParams::DEFAULT;

    /// The rule's numbers: 10 m from the dock is 20 m of way home, 100 s
    /// at 0.2 m/s, 14 ‰ a minute: 23 ‰ and the reserve's 60.
    #[test]
    fn low_when_the_way_home_takes_what_is_left() {
        let mut c = Charge::new();
        assert!(
            !c.low(&P, (10_000, 0), (0, 0), 0),
            "no charge known: never low"
        );
        c.now_pm = Some(84);
        assert!(!c.low(&P, (10_000, 0), (0, 0), 0));
        c.now_pm = Some(83);
        assert!(c.low(&P, (10_000, 0), (0, 0), 0));
        c.now_pm = Some(60);
        assert!(
            c.low(&P, (0, 0), (0, 0), 0),
            "at the reserve, even at the dock"
        );
    }

    /// A drain measured higher than the configured one is used: 300 ‰
    /// gone in 10 minutes is 30 ‰ a minute. 110 m out (1,100 s home) then
    /// needs 610 ‰; at the configured 14 ‰ a minute, 317.
    #[test]
    fn measured_drain_counts_when_higher() {
        let mut c = Charge::new();
        c.now_pm = Some(900);
        assert!(!c.low(&P, (10_000, 0), (0, 0), 0));
        c.now_pm = Some(600);
        assert!(c.low(&P, (110_000, 0), (0, 0), 600_000_000));
        let mut fresh = Charge::new();
        fresh.now_pm = Some(600);
        assert!(!fresh.low(&P, (110_000, 0), (0, 0), 600_000_000));
    }
}
