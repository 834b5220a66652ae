//! `bench replan --to-dock` (issue 13): D* Lite's case in the mission,
//! measured on a real home. The mission plans its way home on the fine
//! configuration space and plans again when someone steps into it; this
//! builds the same situation from a ValetudoMap for [`super::replan`].
//!
//! **Protocol** (ours): the home's cells are made a configuration space by
//! growing every wall by the robot's radius and margin (a disc, as the
//! mission's fine map does); the goal is the free cell nearest the map's
//! charger; the starts are `count` cells spread over everything reachable
//! from it, taken at even steps of the breadth-first order from the dock
//! (so from near to far). [`super::replan::run_replan`] then walks each way
//! home with obstacles appearing ahead. An obstacle's `--side` there is in
//! configuration-space cells: a person 0.4 m across, grown by the robot's
//! 0.18 m on each side, is about 15 cells at 5 cm.

use std::collections::VecDeque;

use robovac::Cell;

use crate::io::maps::{MapData, MapError};
use crate::io::scen::Problem;

/// The mission's robot: 170 mm radius and 10 mm margin.
pub const ROBOT_RADIUS_M: f64 = 0.18;

/// The configuration space of `map` for the robot, and `count` ways home
/// to its dock.
pub fn way_home_problems(map: &MapData, count: usize) -> Result<(MapData, Vec<Problem>), MapError> {
    let (dx, dy, _) = map
        .dock
        .ok_or_else(|| MapError("--to-dock needs a map with a charger (a ValetudoMap)".into()))?;
    let cell_m = map.cell_m.unwrap_or(0.05);
    let cspace = grown(map, (ROBOT_RADIUS_M / cell_m).ceil() as i32);
    let dock = (
        (dx / cell_m).floor() as i32,
        map.height as i32 - 1 - (dy / cell_m).floor() as i32,
    );
    let goal = nearest_free(&cspace, dock, (1.0 / cell_m) as i32)
        .ok_or_else(|| MapError("no free cell within 1 m of the charger".into()))?;
    let order = reachable(&cspace, goal);
    let step = (order.len() / count.max(1)).max(1);
    let problems = order
        .iter()
        .skip(step)
        .step_by(step)
        .take(count)
        .map(|&start| Problem {
            bucket: 0,
            map: "way home".into(),
            width: cspace.width,
            height: cspace.height,
            start,
            goal,
            optimal: 0.0,
        })
        .collect();
    Ok((cspace, problems))
}

/// `map` with every blocked cell grown by a disc of `r` cells.
fn grown(map: &MapData, r: i32) -> MapData {
    let mut out = map.clone();
    for y in 0..map.height as i32 {
        for x in 0..map.width as i32 {
            if !map.is_blocked(x, y) {
                continue;
            }
            for oy in -r..=r {
                for ox in -r..=r {
                    let (nx, ny) = (x + ox, y + oy);
                    let inside =
                        nx >= 0 && ny >= 0 && (nx as u32) < out.width && (ny as u32) < out.height;
                    if ox * ox + oy * oy <= r * r && inside {
                        out.blocked[(ny as u32 * out.width + nx as u32) as usize] = true;
                    }
                }
            }
        }
    }
    out
}

/// The free cell nearest `(x, y)` within `reach` cells.
fn nearest_free(map: &MapData, (x, y): (i32, i32), reach: i32) -> Option<Cell> {
    let mut best: Option<(i32, Cell)> = None;
    for oy in -reach..=reach {
        for ox in -reach..=reach {
            let d = ox * ox + oy * oy;
            let (cx, cy) = (x + ox, y + oy);
            if map.is_blocked(cx, cy) || best.is_some_and(|(b, _)| d >= b) {
                continue;
            }
            best = Cell::from_xy(cx, cy).map(|c| (d, c));
        }
    }
    best.map(|(_, c)| c)
}

/// The free cells reachable from `from` (4-connected), in breadth-first
/// order.
fn reachable(map: &MapData, from: Cell) -> Vec<Cell> {
    let w = map.width as usize;
    let mut seen = vec![false; w * map.height as usize];
    let mut order = vec![from];
    let mut queue = VecDeque::from([from]);
    seen[from.y as usize * w + from.x as usize] = true;
    while let Some(c) = queue.pop_front() {
        for (ox, oy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (x, y) = (c.x as i32 + ox, c.y as i32 + oy);
            if map.is_blocked(x, y) || seen[y as usize * w + x as usize] {
                continue;
            }
            seen[y as usize * w + x as usize] = true;
            if let Some(n) = Cell::from_xy(x, y) {
                order.push(n);
                queue.push_back(n);
            }
        }
    }
    order
}
