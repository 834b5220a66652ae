//! Where a mission starts: the dock's place on the map (given, in front of
//! a ValetudoMap's charger, or a free spot near the centre), people kept
//! off it, and the pose the executive is told (off by up to ±0.2 m and
//! ±15° in noisy known runs: a person put the robot down).

use robovac::mission::MapMode;
use robovac::robot::odometry::Pose;

use super::mission::{MissionOptions, ZONE_MARGIN_M};
use crate::sim::world::World;

/// A free spot for the dock near the map's centre (the body plus 5 cm fits).
pub fn default_start(world: &World, r: f64) -> Option<(f64, f64)> {
    let (w, h) = world.size_m();
    let mut best: Option<(f64, (f64, f64))> = None;
    let step = 0.05;
    let mut y = r;
    while y < h - r {
        let mut x = r;
        while x < w - r {
            if !world.disc_hits_wall(x, y, r + 0.05) && world.zone_intrusion(x, y, r + 0.1) <= 0.0 {
                let d = (x - w / 2.0).hypot(y - h / 2.0);
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, (x, y)));
                }
            }
            x += step;
        }
        y += step;
    }
    best.map(|(_, p)| p)
}

/// The dock pose the executive is given: the truth, or in known mode
/// under noise the truth off by up to ±0.2 m and ±15° (a person put the
/// robot down; the executive relocalises within that window), drawn from
/// the seed.
pub(crate) fn given_dock(opts: &MissionOptions, (x, y, th): (f64, f64, f64)) -> Pose {
    let (mut dx, mut dy, mut dt) = (0.0, 0.0, 0.0);
    let placed = opts.mode == MapMode::Known || opts.map_store.load.is_some();
    if opts.noise.noisy() && placed {
        let mut rng = robovac::grid::maps::SplitMix64::new(opts.seed ^ 0xD0C);
        dx = crate::sim::robot::in_range(&mut rng, (-0.2, 0.2));
        dy = crate::sim::robot::in_range(&mut rng, (-0.2, 0.2));
        dt = crate::sim::robot::in_range(&mut rng, (-15.0, 15.0)).to_radians();
    }
    let t =
        (th + dt + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    Pose {
        x_mm: ((x + dx) * 1000.0).round() as i32,
        y_mm: ((y + dy) * 1000.0).round() as i32,
        theta_mrad: (t * 1000.0).round() as i32,
    }
}

/// The dock: the given start or a free spot near the centre, clear of
/// walls; people are added and none starts on it.
pub(crate) fn place_dock(
    opts: &MissionOptions,
    world: &mut World,
    r: f64,
) -> Result<((f64, f64), f64), String> {
    let (start, heading) = match (opts.start, opts.map.dock) {
        (Some(s), _) => (s, 0.0),
        (None, Some(c)) => docked_pose(world, c, r)
            .ok_or("no place for the robot in front of the map's charger")?,
        (None, None) => (
            default_start(world, r).ok_or("no free spot for the robot on this map")?,
            0.0,
        ),
    };
    if world.disc_hits_wall(start.0, start.1, r + 0.01) {
        return Err(format!(
            "the start ({:.2}, {:.2}) m is too close to a wall for the robot",
            start.0, start.1
        ));
    }
    if world.zone_intrusion(start.0, start.1, r + ZONE_MARGIN_M) > 0.0 {
        return Err(format!(
            "the dock ({:.2}, {:.2}) m is in or next to a no-go zone or virtual wall",
            start.0, start.1
        ));
    }
    let mut rng = robovac::grid::maps::SplitMix64::new(opts.seed ^ 0x5EED);
    world.add_people(opts.people, &mut rng);
    for p in &mut world.people {
        if (p.pos.0 - start.0).hypot(p.pos.1 - start.1) < 0.6 {
            p.next = (p.next + 1) % p.waypoints.len();
        }
    }
    Ok((start, heading))
}

/// Docked at a charger (x, y m, its angle rad): the nearest place to it
/// where the body fits with 2 cm to spare, facing away from the charger
/// (the charger's own angle when the robot fits on it).
pub fn docked_pose(
    world: &World,
    (cx, cy, angle): (f64, f64, f64),
    r: f64,
) -> Option<((f64, f64), f64)> {
    let step = 0.01;
    let mut best: Option<(f64, (f64, f64))> = None;
    for iy in -100..=100 {
        for ix in -100..=100 {
            let (x, y) = (cx + ix as f64 * step, cy + iy as f64 * step);
            let d = (x - cx).hypot(y - cy);
            if best.is_some_and(|(b, _)| d >= b) || world.disc_hits_wall(x, y, r + 0.02) {
                continue;
            }
            best = Some((d, (x, y)));
        }
    }
    let (d, (x, y)) = best?;
    let heading = if d < 0.01 {
        angle
    } else {
        (y - cy).atan2(x - cx)
    };
    Some(((x, y), heading))
}
