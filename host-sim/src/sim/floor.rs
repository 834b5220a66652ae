//! Floor coverage measured on the ground truth at fine resolution: the
//! reachable floor is every point the robot's body can reach (discs of the
//! body's radius around every centre position with clearance, clear of the
//! owner's no-go zones and virtual walls, connected to the start); the swept floor is the union of the body's disc along the
//! true trajectory (the cleaning width is the body's width).

use crate::sim::world::World;

/// Fine cells of the floor.
pub struct Floor {
    res_m: f64,
    w: usize,
    h: usize,
    floor: Vec<bool>,
    swept: Vec<bool>,
    radius_m: f64,
    /// Cells of reachable floor.
    pub floor_cells: usize,
}

impl Floor {
    /// The reachable floor for a body of `radius_m` starting at `start`.
    pub fn new(world: &World, start: (f64, f64), radius_m: f64, res_m: f64) -> Self {
        let (wm, hm) = world.size_m();
        let (w, h) = ((wm / res_m).ceil() as usize, (hm / res_m).ceil() as usize);
        let centre = |i: usize| {
            (
                (i % w) as f64 * res_m + res_m / 2.0,
                (i / w) as f64 * res_m + res_m / 2.0,
            )
        };
        // Centre positions with clearance, connected to the start.
        let ok: Vec<bool> = (0..w * h)
            .map(|i| {
                let (x, y) = centre(i);
                !world.disc_hits_wall(x, y, radius_m) && world.zone_intrusion(x, y, radius_m) <= 0.0
            })
            .collect();
        let mut reach = vec![false; w * h];
        let s =
            ((start.1 / res_m) as usize).min(h - 1) * w + ((start.0 / res_m) as usize).min(w - 1);
        let mut stack = vec![s];
        if ok.get(s).copied().unwrap_or(false) {
            reach[s] = true;
        }
        while let Some(i) = stack.pop() {
            if !reach[i] {
                continue;
            }
            let (x, y) = (i % w, i / w);
            for (dx, dy) in [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if ok[j] && !reach[j] {
                    reach[j] = true;
                    stack.push(j);
                }
            }
        }
        let mut f = Self {
            res_m,
            w,
            h,
            floor: vec![false; w * h],
            swept: vec![false; w * h],
            radius_m,
            floor_cells: 0,
        };
        let mut floor = vec![false; w * h];
        for i in (0..w * h).filter(|&i| reach[i]) {
            let (x, y) = centre(i);
            f.stamp(&mut floor, x, y);
        }
        // Only truly free floor counts.
        for (i, c) in floor.iter_mut().enumerate() {
            let (x, y) = centre(i);
            if world.blocked_at(x, y) {
                *c = false;
            }
        }
        f.floor_cells = floor.iter().filter(|c| **c).count();
        f.floor = floor;
        f
    }

    fn stamp(&self, cells: &mut [bool], x: f64, y: f64) {
        let r = self.radius_m;
        let (x0, x1) = (
            ((x - r) / self.res_m).floor().max(0.0) as usize,
            (((x + r) / self.res_m).floor() as usize).min(self.w - 1),
        );
        let (y0, y1) = (
            ((y - r) / self.res_m).floor().max(0.0) as usize,
            (((y + r) / self.res_m).floor() as usize).min(self.h - 1),
        );
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                let (px, py) = (
                    cx as f64 * self.res_m + self.res_m / 2.0,
                    cy as f64 * self.res_m + self.res_m / 2.0,
                );
                if (px - x).hypot(py - y) <= r {
                    cells[cy * self.w + cx] = true;
                }
            }
        }
    }

    /// Marks the body's disc at (x, y) as swept.
    pub fn sweep(&mut self, x: f64, y: f64) {
        let mut s = std::mem::take(&mut self.swept);
        self.stamp(&mut s, x, y);
        self.swept = s;
    }

    /// Share of the reachable floor swept.
    pub fn coverage(&self) -> f64 {
        self.swept_cells() as f64 / self.floor_cells.max(1) as f64
    }

    fn swept_cells(&self) -> usize {
        self.floor
            .iter()
            .zip(&self.swept)
            .filter(|(f, s)| **f && **s)
            .count()
    }

    /// Cell side, m, and the grid's width and height.
    pub fn dims(&self) -> (f64, usize, usize) {
        (self.res_m, self.w, self.h)
    }

    /// Reachable floor swept (true) or missed (false) at fine cell
    /// (x, y from the bottom); None where there is no reachable floor.
    pub fn state(&self, x: usize, y: usize) -> Option<bool> {
        let i = y * self.w + x;
        (x < self.w && self.floor.get(i).copied().unwrap_or(false))
            .then(|| self.swept.get(i).copied().unwrap_or(false))
    }

    /// Reachable floor swept, m².
    pub fn swept_area_m2(&self) -> f64 {
        self.swept_cells() as f64 * self.res_m * self.res_m
    }

    /// Cells (x, y in the fine grid, from the bottom) of reachable floor
    /// not swept, for pictures.
    pub fn missed(&self) -> Vec<(usize, usize)> {
        (0..self.w * self.h)
            .filter(|&i| self.floor[i] && !self.swept[i])
            .map(|i| (i % self.w, i / self.w))
            .collect()
    }
}
