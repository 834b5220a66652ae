//! The simulated world: the ground-truth floor (from any map format, in
//! metres), people walking loops, and ray casting against both.
//!
//! World frame: metres, x east, y north, origin at the map's bottom-left
//! corner (the same frame as the core's evidence map, in mm).

use robovac::grid::maps::SplitMix64;

use crate::io::maps::MapData;

/// A person: a disc walking a loop of waypoints.
#[derive(Clone, Debug)]
pub struct Person {
    /// Centre, m.
    pub pos: (f64, f64),
    /// Radius, m (about 0.15: a 0.3 m disc).
    pub radius_m: f64,
    /// Walking speed, m/s.
    pub speed_m_s: f64,
    /// The loop.
    pub waypoints: Vec<(f64, f64)>,
    /// Index of the waypoint walked to.
    pub next: usize,
    /// The positions walked (for pictures).
    pub track: Vec<(f64, f64)>,
    /// How long they have waited for the robot, s.
    pub waited_s: f64,
    /// Velocity over the last step, m/s.
    pub vel: (f64, f64),
}

impl Person {
    /// Speed (m/s) at which the person walks toward point (x, y) now (0
    /// when waiting or walking away).
    pub fn approach_speed(&self, x: f64, y: f64) -> f64 {
        let (ox, oy) = (x - self.pos.0, y - self.pos.1);
        let o = ox.hypot(oy).max(1e-9);
        (self.vel.0 * ox / o + self.vel.1 * oy / o).max(0.0)
    }
}

/// How long a person waits for the robot to get out of their way, s.
pub const PATIENCE_S: f64 = 4.0;

/// The shortest leg of a person's loop, m: people walk across a room (to
/// the kitchen, the door, the sofa), not round a spot. Without it a loop's
/// waypoints could fall within a metre of one another: on a real home
/// (S8, seed 9) one person walked a 0.45 m triangle for the whole hour,
/// always over the same patch of floor, and pinned the robot in a nook
/// between it and a wall for 1,600 s (93.5 % covered).
pub const MIN_LEG_M: f64 = 1.0;

/// The fewest waypoints in a person's loop: a triangle at least, so that
/// nobody paces one line to and fro ([`World::add_people`]).
pub const MIN_LOOP: usize = 3;

/// The ground truth.
pub struct World {
    /// The floor plan.
    pub map: MapData,
    /// Metres per map cell.
    pub cell_m: f64,
    /// People.
    pub people: Vec<Person>,
    /// Blocked cells (column, row) of dark furniture: a ray that ends on
    /// one returns nothing (harsh floors).
    pub dark: std::collections::HashSet<(i32, i32)>,
    /// Blocked cells of a glass door or mirror: rays pass through and
    /// return from beyond (harsh floors). The body still cannot.
    pub glass: std::collections::HashSet<(i32, i32)>,
    /// Blocked cells of objects under or over the lidar's plane (a sofa's
    /// frame, a chair's crossbar: [`crate::sim::objects`]): rays pass
    /// through, the body cannot.
    pub low: std::collections::HashSet<(i32, i32)>,
    /// Free cells of a cable or a rug's edge: a wheel driven onto one
    /// stalls.
    pub snag: std::collections::HashSet<(i32, i32)>,
    /// The objects placed ([`crate::sim::objects::place`]).
    pub objects: Vec<crate::sim::objects::LowObject>,
    /// The owner's no-go zones and virtual walls (the map's own and the
    /// command line's): rules the body keeps to, nothing the lidar sees.
    pub zones: Vec<robovac::grid::Zone>,
}

impl World {
    /// A world from a map with `cell_m` metres per cell.
    pub fn new(map: MapData, cell_m: f64) -> Self {
        Self {
            map,
            cell_m,
            people: Vec::new(),
            dark: Default::default(),
            glass: Default::default(),
            low: Default::default(),
            snag: Default::default(),
            objects: Vec::new(),
            zones: Vec::new(),
        }
    }

    /// Blocks cell (column, row from the top) with something the lidar
    /// cannot see ([`Self::low`]); cells off the map are left alone.
    pub fn add_low(&mut self, c: i32, r: i32) {
        let (w, h) = (self.map.width as i32, self.map.height as i32);
        if c < 0 || r < 0 || c >= w || r >= h {
            return;
        }
        if let Some(b) = self.map.blocked.get_mut((r * w + c) as usize) {
            *b = true;
            self.low.insert((c, r));
        }
    }

    /// True when the lidar sees the blocked cell (column, row): not dark,
    /// not glass, not under or over its plane.
    pub fn seen(&self, cell: (i32, i32)) -> bool {
        !self.dark.contains(&cell) && !self.glass.contains(&cell) && !self.low.contains(&cell)
    }

    /// The grid cell (column, row from the top) of a world point.
    pub fn cell_of(&self, x: f64, y: f64) -> (i32, i32) {
        let c = (x / self.cell_m).floor() as i32;
        (
            c,
            self.map.height as i32 - 1 - (y / self.cell_m).floor() as i32,
        )
    }

    /// True when the world point lies on a cable's or rug edge's cell.
    pub fn snag_at(&self, x: f64, y: f64) -> bool {
        self.snag.contains(&self.cell_of(x, y))
    }

    /// True when the world point lies on something the lidar cannot see
    /// because it is under or over its plane.
    pub fn low_at(&self, x: f64, y: f64) -> bool {
        self.low.contains(&self.cell_of(x, y))
    }

    /// How far (m) a disc of radius `r` at (x, y) reaches into the
    /// deepest zone; at most 0 when it is clear of all (or there are none).
    pub fn zone_intrusion(&self, x: f64, y: f64, r: f64) -> f64 {
        crate::sim::zones::deepest_m(&self.zones, x, y, r).unwrap_or(f64::NEG_INFINITY)
    }

    /// Harsh floors: three pieces of dark furniture (the blocked cells
    /// within 0.25 m of three random wall faces) and one glass pane (the
    /// blocked cells within 0.4 m of a fourth).
    pub fn add_materials(&mut self, rng: &mut SplitMix64) {
        let faces: Vec<(i32, i32)> = (0..self.map.height as i32)
            .flat_map(|r| (0..self.map.width as i32).map(move |c| (c, r)))
            .filter(|&(c, r)| {
                self.map.is_blocked(c, r)
                    && [(1, 0), (-1, 0), (0, 1), (0, -1)]
                        .iter()
                        .any(|(dc, dr)| !self.map.is_blocked(c + dc, r + dr))
            })
            .collect();
        if faces.is_empty() {
            return;
        }
        for k in 0..4 {
            let Some(&(c0, r0)) = faces.get(rng.below(faces.len() as u32) as usize) else {
                continue;
            };
            let reach = if k < 3 { 0.25 } else { 0.4 };
            let n = (reach / self.cell_m).round() as i32;
            for r in r0 - n..=r0 + n {
                for c in c0 - n..=c0 + n {
                    if self.map.is_blocked(c, r) && c >= 0 && r >= 0 {
                        if k < 3 {
                            self.dark.insert((c, r));
                        } else {
                            self.glass.insert((c, r));
                        }
                    }
                }
            }
        }
    }

    /// Width and height in metres.
    pub fn size_m(&self) -> (f64, f64) {
        (
            self.map.width as f64 * self.cell_m,
            self.map.height as f64 * self.cell_m,
        )
    }

    /// True when the world point is inside a blocked cell or off the map.
    pub fn blocked_at(&self, x: f64, y: f64) -> bool {
        let cx = (x / self.cell_m).floor();
        let row = self.map.height as f64 - 1.0 - (y / self.cell_m).floor();
        if cx < 0.0 || row < 0.0 {
            return true;
        }
        self.map.is_blocked(cx as i32, row as i32)
    }

    /// Visits the squared distance from (x, y) to every blocked cell (or
    /// off-map cell) within `reach`, until `f` returns true; returns
    /// whether it did.
    fn any_wall_within(&self, x: f64, y: f64, reach: f64, mut f: impl FnMut(f64) -> bool) -> bool {
        self.any_wall_cell_within(x, y, reach, |d2, _, _| f(d2))
    }

    /// As [`Self::any_wall_within`], with each cell's (column, row) and its
    /// nearest point to (x, y).
    fn any_wall_cell_within(
        &self,
        x: f64,
        y: f64,
        reach: f64,
        mut f: impl FnMut(f64, (i32, i32), (f64, f64)) -> bool,
    ) -> bool {
        let c = self.cell_m;
        let (x0, x1) = (
            ((x - reach) / c).floor() as i32,
            ((x + reach) / c).floor() as i32,
        );
        let (y0, y1) = (
            ((y - reach) / c).floor() as i32,
            ((y + reach) / c).floor() as i32,
        );
        for gy in y0..=y1 {
            for gx in x0..=x1 {
                let row = self.map.height as i32 - 1 - gy;
                if !self.map.is_blocked(gx, row) {
                    continue;
                }
                // nearest point of the cell square to the centre
                let nx = x.clamp(gx as f64 * c, (gx + 1) as f64 * c);
                let ny = y.clamp(gy as f64 * c, (gy + 1) as f64 * c);
                if f((nx - x).powi(2) + (ny - y).powi(2), (gx, row), (nx, ny)) {
                    return true;
                }
            }
        }
        false
    }

    /// True when a disc of radius `r` at (x, y) overlaps a wall.
    pub fn disc_hits_wall(&self, x: f64, y: f64, r: f64) -> bool {
        self.any_wall_within(x, y, r, |d2| d2 < r * r)
    }

    /// Distance from (x, y) to the nearest wall (blocked cell or the map's
    /// edge), searched up to `max` (returns `max` when nothing is nearer).
    pub fn wall_distance(&self, x: f64, y: f64, max: f64) -> f64 {
        let mut best = max * max;
        self.any_wall_within(x, y, max, |d2| {
            best = best.min(d2);
            false
        });
        best.sqrt()
    }

    /// The nearest point of a wall (a blocked cell, or the map's edge)
    /// to (x, y) within `reach`, and whether the lidar can see that wall
    /// (dark furniture returns no echo, glass lets the beam through): the
    /// bumper's contact and how a collision counts.
    pub fn nearest_wall(&self, x: f64, y: f64, reach: f64) -> Option<((f64, f64), bool)> {
        // (squared distance, point, cell) of the nearest so far.
        type Near = (f64, (f64, f64), (i32, i32));
        let mut best: Option<Near> = None;
        self.any_wall_cell_within(x, y, reach, |d2, cell, p| {
            if d2 <= reach * reach && best.is_none_or(|b| d2 < b.0) {
                best = Some((d2, p, cell));
            }
            false
        });
        best.map(|(_, p, cell)| (p, self.seen(cell)))
    }

    /// Distance from (x, y) along heading `a` to the first wall or person,
    /// up to `max` (None past it). Walls by an exact grid traversal.
    pub fn ray(&self, x: f64, y: f64, a: f64, max: f64) -> Option<f64> {
        let (dx, dy) = (a.cos(), a.sin());
        // A dark wall ends the ray with no echo unless a person is nearer.
        let (wall, dark) = self
            .ray_walls(x, y, dx, dy, max)
            .unwrap_or((f64::INFINITY, false));
        let mut best = wall.is_finite().then_some(wall);
        for p in &self.people {
            // ray–circle
            let (ox, oy) = (x - p.pos.0, y - p.pos.1);
            let b = ox * dx + oy * dy;
            let c = ox * ox + oy * oy - p.radius_m * p.radius_m;
            let disc = b * b - c;
            if disc >= 0.0 {
                let t = -b - disc.sqrt();
                if t > 0.0 && best.is_none_or(|d| t < d) {
                    best = Some(t);
                }
            }
        }
        if dark && best == Some(wall) {
            return None;
        }
        best.filter(|d| *d <= max)
    }

    /// The first wall along the ray and whether it is dark; glass and
    /// what lies under or over the scan plane are passed through.
    fn ray_walls(&self, x: f64, y: f64, dx: f64, dy: f64, max: f64) -> Option<(f64, bool)> {
        let c = self.cell_m;
        let (mut gx, mut gy) = ((x / c).floor() as i64, (y / c).floor() as i64);
        let step_x = if dx > 0.0 { 1 } else { -1 };
        let step_y = if dy > 0.0 { 1 } else { -1 };
        let t_delta_x = if dx != 0.0 {
            c / dx.abs()
        } else {
            f64::INFINITY
        };
        let t_delta_y = if dy != 0.0 {
            c / dy.abs()
        } else {
            f64::INFINITY
        };
        let next_x = if dx > 0.0 {
            (gx + 1) as f64 * c
        } else {
            gx as f64 * c
        };
        let next_y = if dy > 0.0 {
            (gy + 1) as f64 * c
        } else {
            gy as f64 * c
        };
        let mut t_max_x = if dx != 0.0 {
            (next_x - x) / dx
        } else {
            f64::INFINITY
        };
        let mut t_max_y = if dy != 0.0 {
            (next_y - y) / dy
        } else {
            f64::INFINITY
        };
        let mut t = 0.0;
        while t <= max {
            let row = self.map.height as i64 - 1 - gy;
            if gx < 0 || row < 0 || gx >= self.map.width as i64 || row >= self.map.height as i64 {
                return Some((t, false)); // the map's edge is a wall
            }
            let cell = (gx as i32, row as i32);
            let through = self.glass.contains(&cell) || self.low.contains(&cell);
            if self.map.is_blocked(cell.0, cell.1) && !through {
                return Some((t, self.dark.contains(&cell)));
            }
            if t_max_x < t_max_y {
                t = t_max_x;
                t_max_x += t_delta_x;
                gx += step_x;
            } else {
                t = t_max_y;
                t_max_y += t_delta_y;
                gy += step_y;
            }
        }
        None
    }

    /// Adds `n` people walking loops of 3–5 waypoints at 0.5–1.0 m/s, each
    /// leg a straight line clear of walls by the person's radius and at
    /// least [`MIN_LEG_M`] long. A person for whom 50 tries find no loop of
    /// [`MIN_LOOP`] waypoints (a map too small or too cramped) is left
    /// out: the mission report counts them (`people_missing`).
    pub fn add_people(&mut self, n: usize, rng: &mut SplitMix64) {
        let r = 0.15;
        for _ in 0..n {
            let want = 3 + rng.below(3) as usize;
            // A first waypoint in a pocket with no leg out of it, or a
            // "loop" of two waypoints: start over. Two waypoints are one
            // line walked to and fro for the whole mission, and where the
            // line crossed a doorway the person paced in it for an hour:
            // the room behind was never entered (home flat, unknown mode,
            // realistic, 3 people, seed 7: 92.6 %), or the way home stayed
            // shut (z10 home, unknown mode, realistic, 1 person, seed 8:
            // `NoWayHome`). People at home walk between places.
            let Some(pts) = (0..50)
                .map(|_| self.person_loop(want, r, rng))
                .find(|pts| pts.len() >= MIN_LOOP)
            else {
                continue;
            };
            let speed = 0.5 + rng.below(501) as f64 / 1000.0;
            self.people.push(Person {
                pos: pts[0],
                radius_m: r,
                speed_m_s: speed,
                waypoints: pts,
                next: 1,
                track: Vec::new(),
                waited_s: 0.0,
                vel: (0.0, 0.0),
            });
        }
    }

    /// Up to `want` random waypoints joined by legs a person of radius `r`
    /// may walk ([`Self::leg_ok`]), closing leg included (fewer than two:
    /// none found).
    fn person_loop(&self, want: usize, r: f64, rng: &mut SplitMix64) -> Vec<(f64, f64)> {
        let (w, h) = self.size_m();
        let mut pts: Vec<(f64, f64)> = Vec::new();
        let mut tries = 0;
        while pts.len() < want && tries < 500 {
            tries += 1;
            let p = (
                rng.below(10_000) as f64 / 10_000.0 * w,
                rng.below(10_000) as f64 / 10_000.0 * h,
            );
            if self.disc_hits_wall(p.0, p.1, r + 0.05) {
                continue;
            }
            if let Some(&q) = pts.last() {
                if !self.leg_ok(q, p, r) {
                    continue;
                }
            }
            pts.push(p);
        }
        // close the loop only if the last leg is clear and long enough
        while pts.len() > 2 && !self.leg_ok(pts[pts.len() - 1], pts[0], r) {
            pts.pop();
        }
        pts
    }

    /// A leg a person of radius `r` may walk: at least [`MIN_LEG_M`] long
    /// and clear of walls by 2 cm.
    fn leg_ok(&self, a: (f64, f64), b: (f64, f64), r: f64) -> bool {
        (b.0 - a.0).hypot(b.1 - a.1) >= MIN_LEG_M && self.segment_clear(a, b, r + 0.02)
    }

    /// True when a disc of radius `r` can slide from `a` to `b`.
    pub fn segment_clear(&self, a: (f64, f64), b: (f64, f64), r: f64) -> bool {
        let n = (((b.0 - a.0).hypot(b.1 - a.1)) / (self.cell_m * 0.5))
            .ceil()
            .max(1.0) as usize;
        (0..=n).all(|k| {
            let t = k as f64 / n as f64;
            !self.disc_hits_wall(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t, r)
        })
    }

    /// Moves the people by `dt` seconds, with no robot about.
    pub fn step_people(&mut self, dt: f64) {
        self.step_people_near(dt, None);
    }

    /// Moves the people by `dt` seconds. People look where they walk: one
    /// whose next step would come within 5 cm of the robot (a disc at
    /// `robot` = (x, y, radius)) waits, for up to `PATIENCE_S`; after that
    /// they walk on regardless (stepping over or into it).
    pub fn step_people_near(&mut self, dt: f64, robot: Option<(f64, f64, f64)>) {
        let mut people = std::mem::take(&mut self.people);
        for p in &mut people {
            let before = p.pos;
            self.step_person(p, dt, robot);
            p.vel = ((p.pos.0 - before.0) / dt, (p.pos.1 - before.1) / dt);
        }
        self.people = people;
    }

    fn step_person(&self, p: &mut Person, dt: f64, robot: Option<(f64, f64, f64)>) {
        {
            let Some(&goal) = p.waypoints.get(p.next) else {
                return;
            };
            let (dx, dy) = (goal.0 - p.pos.0, goal.1 - p.pos.1);
            let d = dx.hypot(dy);
            let s = p.speed_m_s * dt;
            let next = if d <= s {
                goal
            } else {
                (p.pos.0 + dx / d * s, p.pos.1 + dy / d * s)
            };
            if let Some((rx, ry, rr)) = robot {
                let radius = p.radius_m;
                let gap = |q: (f64, f64)| (q.0 - rx).hypot(q.1 - ry) - rr - radius;
                // Blocked: the step closes in on the robot within 5 cm. The
                // person steps around it (60° or 90° off their line, the
                // side that opens the gap), waits when boxed in, and after
                // `PATIENCE_S` walks on regardless.
                if gap(next) < 0.05 && gap(next) < gap(p.pos) && p.waited_s < PATIENCE_S {
                    let a = dy.atan2(dx);
                    let side = [1.05f64, -1.05, 1.57, -1.57].iter().find_map(|off| {
                        let q = (p.pos.0 + s * (a + off).cos(), p.pos.1 + s * (a + off).sin());
                        (gap(q) >= gap(p.pos).min(0.05)
                            && !self.disc_hits_wall(q.0, q.1, p.radius_m))
                        .then_some(q)
                    });
                    if let Some(q) = side {
                        p.pos = q;
                    }
                    p.waited_s += dt;
                    return;
                }
                if p.waited_s >= PATIENCE_S && gap(next) < 0.05 {
                    // Walking on through: stay impatient until clear.
                    p.pos = next;
                    if d <= s {
                        p.next = (p.next + 1) % p.waypoints.len();
                    }
                    return;
                }
            }
            p.waited_s = 0.0;
            p.pos = next;
            if d <= s {
                p.next = (p.next + 1) % p.waypoints.len();
            }
        }
    }
}
