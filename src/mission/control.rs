//! The real-time path, every control period (100 Hz): odometry and wheel
//! speeds, lidar silence, the sub-path follower, the escape from touching
//! distance, the guard, wheel control and stall handling. It touches no
//! big buffer: what the planner's buffers must learn of goes into the
//! hand-off ([`super::handoff`]).
//!
//! Work per call: one odometry update, one pass over the lidar ring for
//! the escape check and, when moving, one guard pass over it (two
//! headings × the wall points mapped hits stand for, other mapped points
//! and unmapped points at once), each transforming only
//! the points near enough to matter; one follower step, one wheel PI step.
//! Measured on the emulated Cortex-M4 in the studio: at most 131 k
//! instructions, 15.6 % of the period at 84 MHz.

use super::handoff::Note;
use super::lidar::Hit;
use super::start_check::{START_HOLD_US, START_STILL_US};
use super::{Activity, Capacity, EventKind, Fault, MapMode, Mission, MotorCmd, Phase};
use crate::nav::cspace;
use crate::nav::follow::{follow, FollowCmd};
use crate::nav::geometry::{within_square, RobotFrame};
use crate::nav::guard::{limit_speed, FreeDistance, GuardParams, MappedFree};
use crate::nav::keep_off;
use crate::robot::odometry::Pose;
use crate::robot::wheel_control::WheelFault;

/// How long the robot backs off (at 100 mm/s) after a bump: 80 mm, which
/// takes the body clear of the marked spot by more than the planner's
/// clearance (radius + margin) before the leg is planned again.
pub const BUMP_BACK_OFF_US: u64 = 800_000;

/// How near the dock (mm along both axes) the way home stops counting
/// map cells in the guard ([`Mission::near_dock`]): the last legs.
pub const DOCK_APPROACH_MM: i64 = 300;

/// What the sensing half measured, for the acting half.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sensed {
    pose: Pose,
    /// Encoder ticks this period.
    d: [i32; 2],
    /// Wheel speeds over the last two periods, mm/s.
    meas: [i32; 2],
    dt_us: u64,
}

impl Mission {
    /// The sensing half: odometry, speeds, lidar silence, the swept cell.
    /// `Err` is the command when the robot must not move this period.
    pub(super) fn sense(&mut self, now_us: u64, enc: (u16, u16)) -> Result<Sensed, MotorCmd> {
        self.drive.sensed_ok = false;
        let pose = self.drive.odom.update(enc.0, enc.1);
        let Some(last) = self.drive.last_tick_us.replace(now_us) else {
            self.first_tick(now_us, enc);
            return Err(MotorCmd::Brake);
        };
        let dt_us = now_us.saturating_sub(last).max(1);
        let (d, meas) = self.wheel_speeds(enc, dt_us);
        if matches!(self.phase, Phase::Done | Phase::Failed(_) | Phase::Idle) {
            self.cmd = (0, 0);
            return Err(MotorCmd::Brake);
        }
        if self.lidar_silent(now_us) || self.relocalising(now_us) {
            return Err(MotorCmd::Brake);
        }
        if self.halted_since.take().is_some() {
            self.subpath_since_us = now_us;
        }
        if self.phase == Phase::Cover {
            let c = &self.cfg;
            let cell =
                cspace::coarse_of_mm(self.drive.map_h_mm, c.plan_cell_mm, pose.x_mm, pose.y_mm);
            self.hand_off(now_us, Note::Swept(cell));
        }
        self.drive.sensed_ok = true;
        Ok(Sensed {
            pose,
            d,
            meas,
            dt_us,
        })
    }

    fn first_tick(&mut self, now_us: u64, enc: (u16, u16)) {
        self.drive.enc_last = enc;
        self.plan_due_us = now_us;
        self.lidar.last_frame_us = now_us;
        if let Phase::SelfTestScan { since_us } = &mut self.phase {
            *since_us = now_us;
        }
        self.started_us = now_us;
    }

    /// Encoder ticks this period and speeds over the last two, mm/s.
    fn wheel_speeds(&mut self, enc: (u16, u16), dt_us: u64) -> ([i32; 2], [i32; 2]) {
        let dr = &mut self.drive;
        let d = [
            enc.0.wrapping_sub(dr.enc_last.0) as i16 as i32,
            enc.1.wrapping_sub(dr.enc_last.1) as i16 as i32,
        ];
        dr.enc_last = enc;
        let span = (dt_us + dr.prev_dt_us).max(1) as i64;
        let upt = self.cfg.geometry.um_per_tick();
        let meas = [0usize, 1].map(|i| {
            let p = dr.prev_delta.get(i).copied().unwrap_or(0);
            let di = d.get(i).copied().unwrap_or(0);
            ((di + p) as i64 * upt * 1000 / span) as i32
        });
        dr.prev_delta = d;
        dr.prev_dt_us = dt_us;
        (d, meas)
    }

    /// Lidar silence (after the self-test's own wait): brake, and fail
    /// after `lidar_lost_us`. True while silent.
    fn lidar_silent(&mut self, now_us: u64) -> bool {
        let past_selftest = !matches!(self.phase, Phase::SelfTestScan { .. });
        let quiet = now_us.saturating_sub(self.lidar.last_frame_us);
        if !past_selftest || quiet <= self.cfg.lidar_timeout_us {
            return false;
        }
        let counters = &mut self.counters;
        let since = *self.halted_since.get_or_insert_with(|| {
            counters.lidar_silences += 1;
            now_us
        });
        if now_us.saturating_sub(since) > self.cfg.lidar_lost_us {
            self.phase = Phase::Failed(Fault::LidarLost);
        }
        self.cmd = (0, 0);
        self.drive.wheels.clear_fault();
        true
    }

    /// Lost: brake until relocalised; fail after `lost_timeout_us`. True
    /// while lost.
    fn relocalising(&mut self, now_us: u64) -> bool {
        if !self.loc.lost {
            return false;
        }
        self.halted_since.get_or_insert(now_us);
        if now_us.saturating_sub(self.lost_since_us) > self.cfg.lost_timeout_us {
            self.phase = Phase::Failed(Fault::Lost);
        }
        self.cmd = (0, 0);
        self.drive.wheels.clear_fault();
        true
    }

    /// Adds a note for the planning step (dropped and reported when full).
    fn hand_off(&mut self, now_us: u64, n: Note) {
        if !self.handoff.push(n) {
            self.counters.handoff_dropped += 1;
            self.events
                .push(now_us, EventKind::Capacity(Capacity::Handoff));
        }
    }

    /// The acting half: follower, escape, guard, wheel control.
    pub(super) fn act(&mut self, now_us: u64, s: Sensed) -> MotorCmd {
        if self.bumped(now_us, &s.pose) {
            return MotorCmd::Brake;
        }
        let (v, w) = self.motion(now_us, &s.pose);
        let (v, w) = self.escape(&s.pose, v, w);
        let v = self.guard(now_us, &s.pose, v, w);
        let (dl, dr) = self.drive.wheels.step(
            v,
            w,
            s.meas[0],
            s.meas[1],
            s.d[0] != 0,
            s.d[1] != 0,
            s.dt_us as u32,
        );
        if self.drive.wheels.fault().is_some() {
            self.stalled(now_us, &s.pose);
            return MotorCmd::Brake;
        }
        self.cmd = (v, w);
        if v == 0 {
            self.still_since_us.get_or_insert(now_us);
        } else {
            self.still_since_us = None;
        }
        MotorCmd::Duty(dl, dr)
    }

    /// The velocity wanted now, before the guard.
    fn motion(&mut self, now_us: u64, pose: &Pose) -> (i32, i32) {
        match self.phase {
            Phase::SelfTestWheels { .. } => return (0, 800),
            Phase::Align => return self.align(now_us, pose),
            p if p.driving() => {}
            _ => return (0, 0),
        }
        match self.activity {
            Activity::BackOff { until_us } => {
                if now_us < until_us {
                    return (-100, 0);
                }
                self.activity = Activity::Follow;
                if self.retries > self.cfg.stall_retries {
                    self.skip_front(now_us, true);
                }
                (0, 0)
            }
            Activity::Avoid => self.dwa_cmd,
            Activity::Follow => {
                let (cmd, cleaning) = self.follow_front(now_us, pose);
                let k = if cleaning {
                    &self.cfg.keep_off
                } else {
                    &self.cfg.keep_off_transit
                };
                keep_off::steer(k, &self.near_walls, pose, self.cfg.radius_mm, cmd)
            }
        }
    }

    /// At the dock: turn in place to the start's heading (proportional,
    /// 0.15–0.8 rad/s), done within 15 mrad.
    fn align(&mut self, now_us: u64, pose: &Pose) -> (i32, i32) {
        let e = crate::math::angle::wrap_mrad(self.start.theta_mrad - pose.theta_mrad);
        if e.abs() <= 15 {
            self.phase = if self.battery.resume.is_some() {
                Phase::Charging {
                    since_us: now_us,
                    from_pm: self.battery.now_pm.unwrap_or(0),
                }
            } else {
                Phase::Done
            };
            return (0, 0);
        }
        let w = (3 * e).clamp(-800, 800);
        (0, if w.abs() < 150 { 150 * e.signum() } else { w })
    }

    /// The bumper closed while the robot was driving (not already backing
    /// off): brake this period, back off [`BUMP_BACK_OFF_US`] straight,
    /// and hand the contact to the planner (which marks the spot when the
    /// lidar sees nothing there, then plans the leg again).
    fn bumped(&mut self, now_us: u64, pose: &Pose) -> bool {
        let driving = self.phase.driving();
        let backing = matches!(self.activity, Activity::BackOff { .. });
        if !self.bumper.pressed() || !driving || backing {
            return false;
        }
        self.counters.bumps += 1;
        let bearing_mrad = self.bumper.bearing_mrad();
        self.hand_off(
            now_us,
            Note::Bumped {
                at_us: now_us,
                pose: *pose,
                bearing_mrad,
            },
        );
        self.drive.wheels.clear_fault();
        self.activity = Activity::BackOff {
            until_us: now_us + BUMP_BACK_OFF_US,
        };
        self.cmd = (0, 0);
        true
    }

    /// Drives the front sub-path; drops it when done or timed out. The
    /// command, and whether the sub-path cleans (true with none queued).
    fn follow_front(&mut self, now_us: u64, pose: &Pose) -> ((i32, i32), bool) {
        let Some((seg, cover)) = self.queue.front() else {
            self.subpath_since_us = now_us;
            return ((0, 0), true);
        };
        if now_us.saturating_sub(self.subpath_since_us) > self.cfg.subpath_timeout_us {
            self.skip_front(now_us, false);
            return ((0, 0), cover);
        }
        let cmd = match follow(&self.cfg.follow, &seg, pose) {
            FollowCmd::Arrived => {
                self.queue.pop();
                self.subpath_since_us = now_us;
                self.retries = 0;
                (0, 0)
            }
            FollowCmd::Drive { v_mm_s, w_mrad_s } => (v_mm_s, w_mrad_s),
        };
        (cmd, cover)
    }

    /// Gives up the current sub-path: the planner learns of it through the
    /// hand-off (its cells go back for a later pass, or after repeated
    /// stalls its planning cell is marked blocked).
    fn skip_front(&mut self, now_us: u64, stalled: bool) {
        if let Some((seg, cover)) = self.queue.front() {
            let last_end = self.queue.last_end();
            self.hand_off(
                now_us,
                Note::GaveUp {
                    seg,
                    cover,
                    stalled,
                    last_end,
                },
            );
        }
        self.queue.pop();
        self.counters.skipped += 1;
        self.subpath_since_us = now_us;
        self.retries = 0;
        self.activity = Activity::Follow;
    }

    /// Escape: touching distance to something (a person stepped in, or
    /// the pose drifted onto a corner). A turn with unequal motors would
    /// edge the body into it, so back straight away from it instead.
    fn escape(&mut self, pose: &Pose, v: i32, w: i32) -> (i32, i32) {
        let close = (self.cfg.radius_mm + self.cfg.escape_mm) as i64;
        let slack = self.cfg.guard.mapped_slack_mm as i64;
        let (mut n_close, mut sum_x) = (0i64, 0i64);
        let frame = RobotFrame::of(pose);
        for &Hit {
            x: qx,
            y: qy,
            mapped,
            ..
        } in self.lidar.ring.as_slice()
        {
            // Farther than `close` along either axis: not touching (the
            // test below would fail; skipped before the transform).
            if !within_square(pose, (qx, qy), close) {
                continue;
            }
            let (x, y) = frame.to_robot((qx, qy));
            let c = if mapped { close - slack } else { close };
            if (x as i64).pow(2) + (y as i64).pow(2) < c * c {
                n_close += 1;
                sum_x += x as i64;
            }
        }
        if n_close >= 2 && !matches!(self.phase, Phase::SelfTestWheels { .. }) {
            self.counters.escapes += 1;
            return (if sum_x > 0 { -60 } else { 60 }, 0);
        }
        (v, w)
    }

    /// The guard: mapped things with the normal reserve; unmapped ones
    /// (which may be people walking) with a wider corridor and a reserve
    /// for how far they move while the lidar comes round again. Returns
    /// the capped linear speed.
    fn guard(&mut self, now_us: u64, pose: &Pose, v: i32, w: i32) -> i32 {
        if v == 0 {
            return v;
        }
        let g = self.cfg.guard;
        let (free_static, free_moving) = self.free_distances(pose, &turned(pose, w), v);
        let lim_static = limit_speed(&g, v, free_static);
        let moving = GuardParams {
            reserve_mm: g.reserve_mm + g.moving_margin_mm,
            ..g
        };
        let lim_moving = limit_speed(&moving, v, free_moving);
        let lim = if v > 0 {
            let stood = self.still_since_us.is_some_and(|t| {
                let d = now_us.saturating_sub(t);
                (START_STILL_US..START_STILL_US + START_HOLD_US).contains(&d)
            });
            let lim_start = if stood && self.cfg.mode == MapMode::Unknown {
                limit_speed(&g, v, self.start_free(pose))
            } else {
                v
            };
            lim_static.min(lim_moving).min(lim_start)
        } else {
            lim_static.max(lim_moving)
        };
        if lim != v {
            self.counters.guard_ticks += 1;
        }
        if v > 0 && lim == 0 && self.activity == Activity::Follow {
            self.guard_block_since.get_or_insert(now_us);
        } else {
            self.guard_block_since = None;
        }
        lim
    }

    /// The free distances ahead (`v`'s direction) for mapped points and
    /// for unmapped ones (wider corridor), each the nearer of the present
    /// heading's and the turned one's: one pass over the ring, far points
    /// skipped before their transform ([`guard_reach_mm`]). Mapped hits
    /// are judged at full width ([`MappedFree`]): a hit on a wall cell's
    /// square by the wall point it stands for ([`Hit::wall_point`]: no
    /// range noise, so a door jamb's corner beside the path stops the
    /// robot short of touching it, and a wall passed 10 mm away returns
    /// no 2 σ outliers to stop it), any other as measured. The mapped
    /// distance also counts the nearest blocking map cells
    /// ([`Self::cells_free`]): a corner no beam of the last revolution
    /// struck (S6, unknown, realistic, seed 3: a lane begun 9 mm off its
    /// line grazed one).
    pub(super) fn free_distances(&self, pose: &Pose, turned: &Pose, v: i32) -> (i32, i32) {
        let g = &self.cfg.guard;
        let fwd = v > 0;
        let reach = guard_reach_mm(g, v);
        let frames = [RobotFrame::of(pose), RobotFrame::of(turned)];
        let mut mapped = [MappedFree::new(g.radius_mm, fwd); 2];
        let mut moving = [FreeDistance::new(g.radius_mm + g.moving_margin_mm, fwd); 2];
        for h in self.lidar.ring.as_slice() {
            if !within_square(pose, h.at(), reach) {
                continue;
            }
            let wall = h.wall_point();
            for (f, (m, u)) in frames.iter().zip(mapped.iter_mut().zip(moving.iter_mut())) {
                match (h.mapped, wall) {
                    (false, _) => u.push(f.to_robot(h.at())),
                    (true, Some(w)) => m.push(f.to_robot(w), true),
                    (true, None) => m.push(f.to_robot(h.at()), false),
                }
            }
        }
        let cells = if self.near_dock((pose.x_mm, pose.y_mm)) {
            i32::MAX
        } else {
            self.cells_free((pose.x_mm, pose.y_mm), &frames, fwd)
        };
        let [m0, m1] = &mapped;
        let [u0, u1] = &moving;
        (
            m0.result().min(m1.result()).min(cells),
            u0.result().min(u1.result()),
        )
    }

    /// The free distance to the outlines of the nearest blocking map
    /// cells ([`NearWalls::outline_points`]), the nearer of the two frames',
    /// leaving out the cells under the body (`here`: its centre), more than
    /// [`UNDER_BODY_MM`] inside its rim: the body stands where they say
    /// something is, so the mark is wrong or what it marks lies flat under
    /// the robot, and it cannot keep the body off it by stopping.
    pub(super) fn cells_free(&self, here: (i32, i32), frames: &[RobotFrame; 2], fwd: bool) -> i32 {
        // A blocking cell is certain: its outline's nearest point decides
        // (the ring's wall points need two hits). At the body's own
        // radius, not the guard's: the plans pass walls 10 mm off, and a
        // guard 2 mm wider stopped bodies a few mm off their line at door
        // jambs (coverage lost).
        let mut cells = [FreeDistance::new(self.cfg.radius_mm, fwd); 2];
        let under = (self.cfg.radius_mm - UNDER_BODY_MM).max(0) as i64;
        for q in self.near_walls.outline_points_beside(here, under) {
            for (f, c) in frames.iter().zip(cells.iter_mut()) {
                c.push(f.to_robot(q));
            }
        }
        cells[0].nearest().min(cells[1].nearest())
    }

    /// On the way home within [`DOCK_APPROACH_MM`] of the dock (`here`,
    /// world mm), where the map's cells neither guard nor make the leg
    /// stale ([`super::avoid`]): the dock's pose hugs what is behind and
    /// beside it (the nearest pose where the body fits), so cells lie
    /// within the body's radius of the last leg. Counting them held a
    /// robot 77 mm short of the dock for 417 s (3790, unknown, harsh,
    /// seed 4), and then, the guard exempt, planned its last leg again
    /// every few tenths of a second, turning between the leg's two ends
    /// until the mission ended 77 mm off. The lidar's points still guard.
    pub(super) fn near_dock(&self, here: (i32, i32)) -> bool {
        self.phase == Phase::Return && within_square(&self.start, here, DOCK_APPROACH_MM)
    }

    /// Something the lidar sees explains a stall: a point within 60 mm of
    /// the rim, anywhere around (a person's foot, a wall).
    ///
    /// Tried and dropped: only points on the side the robot drove toward,
    /// and none for a turn in place (a round body turning pushes
    /// nothing). It marked people who had pushed into the robot from the
    /// side as walls, and next to a wall, where the robot cannot back off,
    /// every replan turned it onto the cable again (2,961 stalls in one
    /// home-flat mission against 86).
    fn stall_seen(&mut self, pose: &Pose) -> bool {
        let reach = (self.cfg.radius_mm + 60) as i64;
        self.points().any(|q| {
            let (dx, dy) = ((q.0 - pose.x_mm) as i64, (q.1 - pose.y_mm) as i64);
            dx * dx + dy * dy < reach * reach
        })
    }

    /// A wheel stalled: back off. Something the lidar sees against the
    /// body (a person, a chair) is an obstruction to back away from; a
    /// stall with nothing in sight (a rug's edge, a cable) is handed to
    /// the planner, which marks the spot ahead of that wheel and plans the
    /// leg again around it ([`Note::Stalled`]), and counts toward giving
    /// the sub-path up.
    ///
    /// A stall while already backing off (wedged: something behind, where
    /// there is no bumper) does not back off again, which would stall
    /// again forever: the sub-path is given up as stalled and the follower
    /// turns in place toward the next one, a move that cannot push.
    fn stalled(&mut self, now_us: u64, pose: &Pose) {
        let left = self.drive.wheels.fault() == Some(WheelFault::LeftStall);
        self.drive.wheels.clear_fault();
        self.counters.stalls += 1;
        if matches!(self.activity, Activity::BackOff { .. }) {
            self.skip_front(now_us, true);
            self.cmd = (0, 0);
            return;
        }
        if !self.stall_seen(pose) {
            self.retries = self.retries.saturating_add(1);
            let at_us = now_us;
            let pose = *pose;
            self.hand_off(now_us, Note::Stalled { at_us, pose, left });
        }
        self.activity = Activity::BackOff {
            until_us: now_us + 1_200_000,
        };
        self.cmd = (0, 0);
    }
}

/// How far inside the body's rim a blocking map cell lies (mm) before the
/// guard leaves it out ([`Mission::cells_free`]). A bumper's mark is made
/// half a cell outside the rim (its square reaches at most about 10 mm
/// in); a wheel's stall mark is made under the wheel (about 60 mm in), and
/// the back-off carries the body off it. Why: l10su (unknown, harsh, 1
/// person, seed 5, t = 1,296 s) stalled against a glass pane it cannot
/// see, and stalled again backing off (wedged: no back-off then, the
/// follower turns in place): both wheels' marks stayed under the body, 68
/// and 95 mm from its centre. Every leg out crossed one, the guard held
/// it (free distance 0), the leg was planned again the same, for 1,400 s,
/// and the way home failed (`NoWayHome`); now it docks (96.9 %). Also
/// tried: a robot the guard stopped not turning for keep-off's push (the
/// push turned it off its sub-path there, the follower turned it back,
/// and the guard's hold, reset by each turn in place, never ran out): the
/// office at the chip's capacities (known, no noise) then covered 38 %
/// before its battery ran flat, where it covers 99.5 %.
pub(super) const UNDER_BODY_MM: i32 = 40;

/// The pose a robot turning at `w` mrad/s will have in a quarter second:
/// the guard checks this heading beside the present one (the arc's
/// chord).
pub(super) fn turned(pose: &Pose, w: i32) -> Pose {
    Pose {
        theta_mrad: pose.theta_mrad + w / 4,
        ..*pose
    }
}

/// How far from the robot (world mm, along either axis) a lidar point can
/// still cap the guard's speed at `v_mm_s`; farther points are skipped, and
/// the speed allowed is exactly what it would be with them.
///
/// Why exact: a point caps the speed only if its free distance `d` is
/// below `reserve + max(v², creep²) / 2a` (below that room the cap is
/// under `v` or under the creep speed). In the corridor (`|y| < radius`),
/// `d ≥ x − radius`, so such a point has `x < x_min = radius + need`, and
/// lies within `√(x_min² + radius²)` of the robot. The widest radius and
/// reserve (the moving class's) bound both classes, and both headings the
/// guard checks share the robot's position. A point farther than that is
/// never among the two nearest that decide.
fn guard_reach_mm(g: &GuardParams, v_mm_s: i32) -> i64 {
    let r = (g.radius_mm.max(0) + g.moving_margin_mm.max(0)) as i64;
    let reserve = (g.reserve_mm.max(0) + g.moving_margin_mm.max(0)) as i64;
    let a2 = 2 * (g.brake_mm_s2.max(1) as i64);
    let vv = (v_mm_s as i64).pow(2).max((g.creep_mm_s as i64).pow(2));
    let need = reserve + (vv + a2 - 1) / a2 + 2;
    let x_min = r + need;
    crate::math::cost::isqrt_u64((x_min * x_min + r * r) as u64) as i64 + 2
}
