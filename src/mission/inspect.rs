//! For diagnosis: what the executive sees and does, read by the host's
//! debug traces and the tests (nothing here changes the mission).

use super::{in_corridor, Mission};
use crate::nav::follow::SubPath;

impl Mission {
    /// For diagnosis: the blocking map cells the guard and keep-off count
    /// now (south-west corner, side; mm).
    pub fn near_cells(&self) -> impl Iterator<Item = ((i32, i32), i32)> + '_ {
        self.near_walls.squares()
    }

    /// For diagnosis: the guard's free distance to those cells (mm) ahead
    /// and behind, at the present heading.
    pub fn cells_free_now(&self) -> (i32, i32) {
        let pose = self.drive.odom.pose();
        let f = [crate::nav::geometry::RobotFrame::of(&pose); 2];
        let here = (pose.x_mm, pose.y_mm);
        (
            self.cells_free(here, &f, true),
            self.cells_free(here, &f, false),
        )
    }

    /// For diagnosis: the activity (following, avoiding, backing off) and
    /// the guard's free distances (mapped, unmapped; mm) for the command
    /// sent last, and that command (mm/s, mrad/s).
    pub fn guard_status(&self) -> (&'static str, (i32, i32), (i32, i32)) {
        let pose = self.drive.odom.pose();
        let (v, w) = self.cmd;
        let free = if v == 0 {
            (i32::MAX, i32::MAX)
        } else {
            self.free_distances(&pose, &super::control::turned(&pose, w), v)
        };
        let act = match self.activity {
            super::Activity::Follow => "follow",
            super::Activity::Avoid => "avoid",
            super::Activity::BackOff { .. } => "back-off",
        };
        (act, free, self.cmd)
    }

    /// For diagnosis: unmapped lidar points in the corridor ahead of the
    /// current sub-path, and how far the guard would let the robot drive
    /// toward its end (mm).
    pub fn corridor_status(&self) -> (usize, i64) {
        let Some((seg, _)) = self.queue.front() else {
            return (0, 0);
        };
        let pose = self.drive.odom.pose();
        let here = (pose.x_mm, pose.y_mm);
        let (reach, _, ahead) = self.corridor(here, seg.to);
        let n = self
            .points_where(false)
            .filter(|&q| in_corridor(here, ahead, q, reach))
            .count();
        (n, self.free_toward(here, seg.to))
    }

    /// For diagnosis: the lidar hits within `r_mm` of the robot (world
    /// mm), whether mapped, and the wall point a mapped one stands for.
    pub fn hits_near(
        &self,
        r_mm: i64,
    ) -> impl Iterator<Item = ((i32, i32), bool, Option<(i32, i32)>)> + '_ {
        let pose = self.drive.odom.pose();
        self.lidar.ring.as_slice().iter().filter_map(move |h| {
            let (dx, dy) = ((h.x - pose.x_mm) as i64, (h.y - pose.y_mm) as i64);
            (dx * dx + dy * dy < r_mm * r_mm).then_some((h.at(), h.mapped, h.wall_point()))
        })
    }

    /// For diagnosis: the lidar points within `r_mm` of the robot (world
    /// mm, mapped or not).
    pub fn points_near(&self, r_mm: i64) -> impl Iterator<Item = (i32, i32, bool)> + '_ {
        self.hits_near(r_mm)
            .map(|((x, y), mapped, _)| (x, y, mapped))
    }

    /// The last DWA command (v mm/s, ω mrad/s) while avoiding.
    pub fn dwa_command(&self) -> (i32, i32) {
        self.dwa_cmd
    }

    /// The straight sub-path being driven and whether it cleans.
    pub fn current_subpath(&self) -> Option<(SubPath, bool)> {
        self.queue.front()
    }
}
