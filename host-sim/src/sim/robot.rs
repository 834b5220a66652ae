//! The physical twin of the robot: motors, encoders, wheel slip, body
//! collisions and an LD06 lidar that emits real frames as bytes at the
//! baud rate's pace. Deterministic for a given seed. The core drives it
//! through its own hardware traits ([`robovac::robot::hal`], implemented
//! in [`super::hal`]).

use std::collections::VecDeque;

use robovac::grid::maps::SplitMix64;
use robovac::robot::hal::Bumper;
use robovac::robot::lidar::ld06;

use crate::sim::world::World;

pub use crate::sim::config::{exponential, gauss, in_range, signed_in, Noise, RobotConfig};

/// The LD06 on our robot: at the centre, angles clockwise from forward.
pub const MOUNT: robovac::robot::lidar_map::LidarMount =
    robovac::robot::lidar_map::LidarMount::ld06_centred(true);

/// A wheel driven forward stops when its contact point comes this close
/// to a cable's cell (m): a wheel's radius against a cable's.
const SNAG_REACH_M: f64 = 0.01;

/// A collision: the body moved into something.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collision {
    /// Sim time, s.
    pub t_s: f64,
    /// Where, m.
    pub pos: (f64, f64),
    /// True when a person walked into the robot (it stood still, or it
    /// was not moving toward them).
    pub by_person: bool,
    /// The robot drove into something its lidar cannot see (dark
    /// furniture, glass): a bumper contact, counted apart from collisions
    /// with what it could have seen.
    pub unseen: bool,
}

/// Byte corruption injected into the lidar stream.
#[derive(Clone, Copy, Debug, Default)]
pub struct Corruption {
    /// Probability per byte of one flipped bit.
    pub flip: f64,
    /// Probability per byte of the byte being lost.
    pub drop: f64,
}

/// A harsh floor's slip burst (a rug edge, a door threshold).
#[derive(Clone, Copy, Debug, Default)]
struct Burst {
    /// Travel at which the next burst starts, m.
    next_at_m: f64,
    /// The patch ends, µs.
    until_us: u64,
    /// Extra relative slip of each wheel while it lasts.
    slip: [f64; 2],
    /// The heading jump still to apply, rad, and its rate, rad/s.
    turn_left_rad: f64,
    turn_rate: f64,
    /// Bursts so far.
    count: u32,
}

/// The simulated robot in its world.
pub struct Sim {
    /// Parameters.
    pub cfg: RobotConfig,
    /// The world.
    pub world: World,
    noise: Noise,
    rng: SplitMix64,
    /// Sim time, µs.
    pub t_us: u64,
    /// True pose: x, y (m), heading (rad).
    pub pose: (f64, f64, f64),
    wheel_v: [f64; 2],
    pub(super) duty: [f64; 2],
    pub(super) braking: bool,
    ticks: [f64; 2],
    slip: [f64; 2],
    mismatch: [f64; 2],
    /// Ground speed per wheel rotation speed, from the true diameters.
    diameter_factor: [f64; 2],
    /// The effective wheelbase, m.
    wheelbase_true_m: f64,
    burst: Burst,
    in_contact: bool,
    /// Each wheel (left, right) is held by a cable or a rug's edge.
    snagged: [bool; 2],
    /// Every time a wheel ran onto a cable or a rug's edge and stalled:
    /// (sim time, s; where, m).
    pub snags: Vec<(f64, (f64, f64))>,
    /// Time a wheel was held by a cable or a rug's edge, s.
    pub snag_time_s: f64,
    /// Every collision.
    pub collisions: Vec<Collision>,
    /// The bumper's switches closed at some physics step since the last
    /// read ([`BumperSwitches::read_bumper`]).
    pub(super) bumper: Bumper,
    lidar_angle_deg: f64,
    sample_acc: f64,
    samples: Vec<(u16, u16, u8)>,
    pub(super) uart: VecDeque<(u64, u8)>,
    uart_free_us: f64,
    /// Injected corruption.
    pub corruption: Corruption,
    /// Every byte the lidar sent, when recording.
    pub capture: Option<Vec<u8>>,
    /// The true trajectory (every 10 ms).
    pub trajectory: Vec<(f64, f64)>,
    /// Distance driven, m.
    pub distance_m: f64,
}

impl Sim {
    /// A robot at `pose` (m, m, rad) in `world`.
    pub fn new(
        cfg: RobotConfig,
        world: World,
        pose: (f64, f64, f64),
        noise: Noise,
        seed: u64,
    ) -> Self {
        let mut rng = SplitMix64::new(seed);
        let mismatch = if noise.noisy() {
            [
                1.0 + cfg.motor_mismatch * gauss(&mut rng),
                1.0 + cfg.motor_mismatch * gauss(&mut rng),
            ]
        } else {
            [1.0, 1.0]
        };
        let (mut diameter_factor, mut wheelbase_true_m) = ([1.0, 1.0], cfg.wheelbase_m);
        let mut world = world;
        if noise.noisy() {
            let d = signed_in(&mut rng, cfg.wheel_diameter_diff);
            diameter_factor = [1.0 + d / 2.0, 1.0 - d / 2.0];
            wheelbase_true_m *= 1.0 + signed_in(&mut rng, cfg.wheelbase_error);
        }
        if noise == Noise::Harsh {
            world.add_materials(&mut rng);
        }
        let burst = Burst {
            next_at_m: cfg.burst_every_m * exponential(&mut rng),
            ..Burst::default()
        };
        Self {
            cfg,
            world,
            noise,
            rng,
            t_us: 0,
            pose,
            wheel_v: [0.0; 2],
            duty: [0.0; 2],
            braking: false,
            ticks: [0.0; 2],
            slip: [0.0; 2],
            mismatch,
            diameter_factor,
            wheelbase_true_m,
            burst,
            in_contact: false,
            snagged: [false; 2],
            snags: Vec::new(),
            snag_time_s: 0.0,
            collisions: Vec::new(),
            bumper: Bumper::RELEASED,
            lidar_angle_deg: 0.0,
            sample_acc: 0.0,
            samples: Vec::new(),
            uart: VecDeque::new(),
            uart_free_us: 0.0,
            corruption: Corruption::default(),
            capture: None,
            trajectory: Vec::new(),
            distance_m: 0.0,
        }
    }

    /// The true wheel surface speeds, m/s.
    pub fn wheel_speeds(&self) -> [f64; 2] {
        self.wheel_v
    }

    /// Advances the physics by one step.
    pub fn step(&mut self) {
        let dt = self.cfg.physics_step_us as f64 * 1e-6;
        self.step_motors(dt);
        let (nx, ny, nth) = self.ground_motion(dt);
        self.move_body(nx, ny, nth, dt);
        // Encoders count wheel rotation (slip is invisible to them).
        let c = &self.cfg;
        let per_m = c.ticks_per_rev as f64 / (std::f64::consts::PI * c.wheel_diameter_m);
        for i in 0..2 {
            self.ticks[i] += self.wheel_v[i] * dt * per_m;
        }
        let body = (self.pose.0, self.pose.1, c.diameter_m / 2.0);
        self.world.step_people_near(dt, Some(body));
        self.step_lidar(dt);
        self.t_us += self.cfg.physics_step_us;
        if self.t_us.is_multiple_of(10_000) {
            self.trajectory.push((self.pose.0, self.pose.1));
            if self.t_us.is_multiple_of(100_000) {
                for p in &mut self.world.people {
                    p.track.push(p.pos);
                }
            }
        }
    }

    /// The wheels' duty as the motors get it (0 while braking), −1..1.
    pub fn duty(&self) -> [f64; 2] {
        if self.braking {
            [0.0; 2]
        } else {
            self.duty
        }
    }

    /// Motors: duty → steady speed (dead band, saturation) → first order.
    fn step_motors(&mut self, dt: f64) {
        let c = &self.cfg;
        for i in 0..2 {
            let d = self.duty[i].clamp(-1.0, 1.0);
            let target = if self.braking || d.abs() < c.motor_deadband {
                0.0
            } else {
                d.signum() * (d.abs() - c.motor_deadband) / (1.0 - c.motor_deadband)
                    * c.full_duty_speed_m_s
                    * self.mismatch[i]
            };
            let tau = if self.braking {
                c.motor_tau_s * 0.3
            } else {
                c.motor_tau_s
            };
            self.wheel_v[i] += (target - self.wheel_v[i]) * (dt / tau).min(1.0);
        }
    }

    /// Where the ground takes the body this step: the wheels' speeds
    /// through their true diameters, with slip (a slowly varying relative
    /// error between wheel and ground) and, on harsh floors, bursts,
    /// turned by the true wheelbase and integrated along the arc.
    fn ground_motion(&mut self, dt: f64) -> (f64, f64, f64) {
        let c = &self.cfg;
        if self.noise.noisy() && self.t_us.is_multiple_of(100_000) {
            self.slip = [
                c.slip_sd * gauss(&mut self.rng),
                c.slip_sd * gauss(&mut self.rng),
            ];
        }
        if self.noise == Noise::Harsh {
            self.step_burst();
        }
        self.hold_snagged_wheels(dt);
        let b = &self.burst;
        let extra = if self.t_us < b.until_us {
            b.slip
        } else {
            [0.0; 2]
        };
        let vg = [
            self.wheel_v[0] * self.diameter_factor[0] * (1.0 + self.slip[0] + extra[0]),
            self.wheel_v[1] * self.diameter_factor[1] * (1.0 + self.slip[1] + extra[1]),
        ];
        let v = 0.5 * (vg[0] + vg[1]);
        let mut w = (vg[1] - vg[0]) / self.wheelbase_true_m;
        if self.burst.turn_left_rad.abs() > 1e-9 {
            let d = (self.burst.turn_rate * dt).clamp(
                -self.burst.turn_left_rad.abs(),
                self.burst.turn_left_rad.abs(),
            );
            self.burst.turn_left_rad -= d;
            w += d / dt;
        }
        let (x, y, th) = self.pose;
        if w.abs() < 1e-9 {
            (x + v * dt * th.cos(), y + v * dt * th.sin(), th)
        } else {
            let r = v / w;
            let t2 = th + w * dt;
            (
                x + r * (t2.sin() - th.sin()),
                y - r * (t2.cos() - th.cos()),
                t2,
            )
        }
    }

    /// A wheel driven forward onto a cable's or rug edge's cell it is not
    /// on ([`World::snag`]) cannot climb it: it stops (no ground motion,
    /// no encoder ticks) while the other turns on, so the body pivots
    /// about it, until it is driven backward. The bumper stays open and
    /// nothing is touched. A wheel already on the cell (it turned onto
    /// it) rolls over.
    fn hold_snagged_wheels(&mut self, dt: f64) {
        if self.world.snag.is_empty() {
            return;
        }
        let (x, y, th) = self.pose;
        let half = self.wheelbase_true_m / 2.0;
        let mut any = false;
        for (i, side) in [1.0, -1.0].into_iter().enumerate() {
            let step = self.wheel_v[i] * self.diameter_factor[i] * dt;
            let at = (x - side * half * th.sin(), y + side * half * th.cos());
            // The wheel stops at the cable, not a step short of it.
            let ahead = step.max(SNAG_REACH_M);
            let to = (at.0 + ahead * th.cos(), at.1 + ahead * th.sin());
            let held =
                step > 0.0 && self.world.snag_at(to.0, to.1) && !self.world.snag_at(at.0, at.1);
            if held {
                if !self.snagged[i] {
                    self.snags.push((self.t_us as f64 * 1e-6, at));
                }
                self.wheel_v[i] = 0.0;
            }
            // One snag lasts until the wheel is driven backward.
            if step < 0.0 {
                self.snagged[i] = false;
            }
            self.snagged[i] |= held;
            any |= held;
        }
        if any {
            self.snag_time_s += dt;
        }
    }

    /// Harsh floors: a burst starts every `burst_every_m` of travel on
    /// average (exponential gaps): a heading jump over 0.2 s and a slip
    /// patch on one wheel.
    fn step_burst(&mut self) {
        if self.distance_m < self.burst.next_at_m {
            return;
        }
        let c = &self.cfg;
        let rng = &mut self.rng;
        let turn = signed_in(rng, c.burst_turn_deg).to_radians();
        let slip = -in_range(rng, c.burst_slip);
        let wheel = (rng.next_u64() & 1) as usize;
        let dur = in_range(rng, c.burst_s);
        let next = c.burst_every_m * exponential(rng);
        let b = &mut self.burst;
        b.turn_left_rad = turn;
        b.turn_rate = turn / 0.2;
        b.slip = [0.0; 2];
        if let Some(s) = b.slip.get_mut(wheel) {
            *s = slip;
        }
        b.until_us = self.t_us + (dur * 1e6) as u64;
        b.next_at_m = self.distance_m + next;
        b.count += 1;
    }

    /// Slip bursts so far (harsh floors).
    pub fn bursts(&self) -> u32 {
        self.burst.count
    }

    /// Lifts the robot and puts it down 1–3 m away, at a heading at least
    /// 45° from its own, on a free spot clear of the owner's zones (the wheels
    /// and encoders notice nothing). Returns where, or `None` when no spot
    /// was found.
    pub fn kidnap(&mut self) -> Option<(f64, f64, f64)> {
        let r = self.cfg.diameter_m / 2.0;
        let (x, y, th) = self.pose;
        for _ in 0..2000 {
            let d = in_range(&mut self.rng, (1.0, 3.0));
            let a = in_range(&mut self.rng, (0.0, std::f64::consts::TAU));
            let (nx, ny) = (x + d * a.cos(), y + d * a.sin());
            let turn = signed_in(&mut self.rng, (0.8, 3.1));
            let free = !self.world.disc_hits_wall(nx, ny, r + 0.1)
                && self.world.zone_intrusion(nx, ny, r + 0.1) <= 0.0
                && self
                    .world
                    .people
                    .iter()
                    .all(|p| (p.pos.0 - nx).hypot(p.pos.1 - ny) > 1.0);
            if free {
                self.pose = (nx, ny, th + turn);
                self.in_contact = false;
                return Some(self.pose);
            }
        }
        None
    }

    /// Moves the body to (nx, ny, nth) unless a wall or a person blocks
    /// it; records collisions and contact.
    fn move_body(&mut self, nx: f64, ny: f64, nth: f64, dt: f64) {
        let (x, y, _) = self.pose;
        let r = self.cfg.diameter_m / 2.0;
        // A person blocks a move that brings the body closer to them;
        // moving away from someone touching the robot is possible.
        let into_person = |px: f64, py: f64| {
            self.world.people.iter().any(|p| {
                let d1 = (p.pos.0 - px).hypot(p.pos.1 - py);
                d1 < p.radius_m + r && d1 < (p.pos.0 - x).hypot(p.pos.1 - y)
            })
        };
        let blocked = self.world.disc_hits_wall(nx, ny, r) || into_person(nx, ny);
        let moving = (nx - x).hypot(ny - y) > 1e-9;
        if blocked && moving {
            self.blocked_move(nx, ny, dt);
            return;
        }
        let hits_person = |px: f64, py: f64| {
            self.world
                .people
                .iter()
                .any(|p| (p.pos.0 - px).hypot(p.pos.1 - py) < p.radius_m + r)
        };
        if !moving && hits_person(x, y) && !self.in_contact {
            self.collisions.push(Collision {
                t_s: self.t_us as f64 * 1e-6,
                pos: (x, y),
                by_person: true,
                unseen: false,
            });
            self.in_contact = true;
            self.press_bumper_toward_person(x, y);
        } else if self.in_contact {
            // Contact ends once the body is 5 mm clear of everything.
            let near_person = self
                .world
                .people
                .iter()
                .any(|p| (p.pos.0 - nx).hypot(p.pos.1 - ny) < p.radius_m + r + 0.005);
            if !near_person && !self.world.disc_hits_wall(nx, ny, r + 0.005) {
                self.in_contact = false;
            }
        }
        self.distance_m += (nx - x).hypot(ny - y);
        self.pose = (nx, ny, nth);
    }

    /// The body cannot move into a wall or person: it stops, the wheels
    /// stall (no motion, no turn, no encoder ticks; turning in place, a
    /// move of zero length, is never blocked). It is the robot's doing
    /// when it drives into a wall, or into a person it was not already
    /// touching, toward them (along the contact normal, the robot's
    /// approach speed is compared with the person's); a person who walked
    /// into the robot is theirs.
    fn blocked_move(&mut self, nx: f64, ny: f64, dt: f64) {
        let (x, y, _) = self.pose;
        let r = self.cfg.diameter_m / 2.0;
        let robot_into = self.world.disc_hits_wall(nx, ny, r)
            || self.world.people.iter().any(|p| {
                let (ox, oy) = (p.pos.0 - x, p.pos.1 - y);
                let dist = ox.hypot(oy).max(1e-9);
                let (ux, uy) = (ox / dist, oy / dist);
                let robot_v = ((nx - x) * ux + (ny - y) * uy) / dt;
                let person_v = p.approach_speed(x, y);
                // Already touching (the person walked into or through the
                // robot): not the robot's doing.
                let touching = dist < p.radius_m + r;
                (p.pos.0 - nx).hypot(p.pos.1 - ny) < p.radius_m + r
                    && !touching
                    && robot_v > 0.005
                    && robot_v >= person_v
            });
        let wall = self.world.nearest_wall(nx, ny, r + 0.01);
        if !self.in_contact {
            self.collisions.push(Collision {
                t_s: self.t_us as f64 * 1e-6,
                pos: (x, y),
                by_person: !robot_into,
                unseen: robot_into && wall.is_some_and(|(_, seen)| !seen),
            });
        }
        match wall {
            Some((p, _)) => self.press_bumper(p),
            None => self.press_bumper_toward_person(nx, ny),
        }
        self.in_contact = true;
        self.wheel_v = [0.0; 2];
    }

    /// The bumper closes for a contact at world point `p` on the front
    /// half of the body: the left switch for a contact more than 15° to
    /// the left, the right one likewise, both in between. The rear has
    /// none.
    fn press_bumper(&mut self, p: (f64, f64)) {
        let (x, y, th) = self.pose;
        let b = ((p.1 - y).atan2(p.0 - x) - th + std::f64::consts::PI)
            .rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        if b.abs() > std::f64::consts::FRAC_PI_2 {
            return;
        }
        let side = 15f64.to_radians();
        let now = Bumper {
            left: b > -side,
            right: b < side,
        };
        self.bumper.left |= now.left;
        self.bumper.right |= now.right;
    }

    /// The bumper closes against the nearest person touching the body.
    fn press_bumper_toward_person(&mut self, x: f64, y: f64) {
        let near = self
            .world
            .people
            .iter()
            .map(|p| ((p.pos.0 - x).hypot(p.pos.1 - y), p.pos))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, pos)) = near {
            self.press_bumper(pos);
        }
    }
    fn step_lidar(&mut self, dt: f64) {
        let c = &self.cfg;
        self.sample_acc += c.lidar_samples_per_s * dt;
        let deg_per_sample = 360.0 * c.lidar_hz / c.lidar_samples_per_s;
        while self.sample_acc >= 1.0 {
            self.sample_acc -= 1.0;
            let bearing = self.lidar_angle_deg; // clockwise from forward, as the LD06
            self.lidar_angle_deg = (self.lidar_angle_deg + deg_per_sample) % 360.0;
            let a = self.pose.2 - bearing.to_radians();
            let (lo, hi) = self.cfg.lidar_range_m;
            let mut d = self.world.ray(self.pose.0, self.pose.1, a, hi);
            if self.noise.noisy() {
                let u = (self.rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
                let dropout = if self.noise == Noise::Harsh {
                    self.cfg.harsh_dropout
                } else {
                    self.cfg.lidar_dropout
                };
                if u < dropout {
                    d = None;
                } else if let Some(v) = d.as_mut() {
                    *v += self.cfg.lidar_noise_m * gauss(&mut self.rng);
                }
            }
            let mm = match d {
                Some(v) if v >= lo && v <= hi => (v * 1000.0).round().clamp(0.0, 65535.0) as u16,
                _ => 0,
            };
            let cdeg = ((bearing * 100.0).round() as u32 % 36000) as u16;
            self.samples.push((cdeg, mm, if mm > 0 { 200 } else { 0 }));
            if self.samples.len() == 12 {
                self.emit_frame();
            }
        }
    }

    fn emit_frame(&mut self) {
        let s = std::mem::take(&mut self.samples);
        let start = s[0].0;
        let end = s[11].0;
        let pts: [(u16, u8); 12] = std::array::from_fn(|i| (s[i].1, s[i].2));
        let speed = (360.0 * self.cfg.lidar_hz).round() as u16;
        let ts = ((self.t_us / 1000) % 30_000) as u16;
        let frame = ld06::encode(speed, start, end, ts, &pts);
        let byte_us = 10.0 * 1e6 / self.cfg.baud as f64;
        for b in frame {
            let u = (self.rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
            if u < self.corruption.drop {
                continue;
            }
            let mut b = b;
            if u < self.corruption.drop + self.corruption.flip {
                b ^= 1 << self.rng.below(8);
            }
            self.uart_free_us = self.uart_free_us.max(self.t_us as f64) + byte_us;
            self.uart.push_back((self.uart_free_us as u64, b));
            if let Some(c) = self.capture.as_mut() {
                c.push(b);
            }
        }
    }

    /// The raw encoder counter of a wheel (0 left, 1 right), as hardware
    /// would show it: quantised, wrapping at 16 bits.
    pub fn encoder(&self, i: usize) -> u16 {
        (self.ticks[i].floor() as i64).rem_euclid(65536) as u16
    }
}
