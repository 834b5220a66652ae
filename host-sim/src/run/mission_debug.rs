//! `ROBOVAC_DEBUG_GRID`, `ROBOVAC_DEBUG_TRACE`, `ROBOVAC_DEBUG_FINE` and
//! `ROBOVAC_DEBUG_NEAR`:
//! what a mission shows on stderr for diagnosis (nothing unless the
//! variable is set).

use robovac::mission::{Mission, MissionParts};

use crate::sim::robot::Sim;

/// `ROBOVAC_DEBUG_GRID`: the planning grid on stderr (`covered`: with the
/// covered cells and the planner's counters).
pub fn debug_grid(parts: &dyn MissionParts, covered: bool) {
    if std::env::var_os("ROBOVAC_DEBUG_GRID").is_none() {
        return;
    }
    for y in 0.. {
        if parts.planning_cell(0, y).is_none() {
            break;
        }
        let row: String = (0..)
            .map_while(|x| parts.planning_cell(x, y))
            .map(|cell| match cell {
                (true, _) => '#',
                (false, true) if covered => 'c',
                _ => '.',
            })
            .collect();
        eprintln!("{row}");
    }
    if covered {
        eprintln!("{:?}", parts.planner_view().stats);
    }
}

/// `ROBOVAC_DEBUG_TRACE`: a collision on stderr, with the evidence map's
/// counters 250 mm around (north up, 50 mm apart).
pub fn debug_collision(sim: &Sim, mission: &Mission, parts: &dyn MissionParts) {
    if let Some(c) = sim.collisions.last() {
        eprintln!(
            "COLLISION t {:.2} by_person {} unseen {} robot ({:.3},{:.3},{:.2}) state {:?} wheels {:?} people {:?}",
            c.t_s,
            c.by_person,
            c.unseen,
            sim.pose.0,
            sim.pose.1,
            sim.pose.2,
            mission.state(),
            sim.wheel_speeds(),
            sim.world.people.iter().map(|p| (p.pos, p.waited_s)).collect::<Vec<_>>()
        );
        let (x, y, _) = sim.pose;
        // Walls only (`World::ray` would also hit people).
        let at = sim.world.nearest_wall(x, y, 1.0).map(|(p, _)| p);
        let d = at.map_or(1.0, |(wx, wy)| (wx - x).hypot(wy - y));
        eprintln!("   nearest wall {d:.3} m from the centre, at {at:?}");
        let (px, py) = ((x * 1000.0) as i32, (y * 1000.0) as i32);
        for dy in (-5..=5).rev() {
            let row: Vec<String> = (-5..=5)
                .map(|dx| format!("{:4}", parts.evidence_at(px + dx * 50, py + dy * 50)))
                .collect();
            eprintln!("   ev {}", row.join(""));
        }
        for k in (-6..=6).rev() {
            eprintln!("   tw {}", twin_row(sim, k, 6));
        }
    }
}

/// Row `k` (north positive) of the twin's grid round the robot, sampled
/// 50 mm apart over `reach` points each side, as the evidence map is
/// printed beside it (the twin's cells may be 50 or 100 mm): `#` wall, `d`
/// dark furniture, `g` glass, `R` the robot's cell, `.` floor.
fn twin_row(sim: &Sim, k: i32, reach: i32) -> String {
    let (x, y, _) = sim.pose;
    let robot = sim.world.cell_of(x, y);
    (-reach..=reach)
        .map(|dx| {
            let cell = sim.world.cell_of(x + dx as f64 * 0.05, y + k as f64 * 0.05);
            if cell == robot {
                'R'
            } else if sim.world.dark.contains(&cell) {
                'd'
            } else if sim.world.glass.contains(&cell) {
                'g'
            } else if sim.world.map.is_blocked(cell.0, cell.1) {
                '#'
            } else {
                '.'
            }
        })
        .collect()
}

/// `ROBOVAC_DEBUG_TRACE`: the executive's view every simulated second.
pub fn debug_tick(sim: &Sim, mission: &Mission, parts: &dyn MissionParts) {
    let (x, y, th) = sim.pose;
    let est = mission.pose();
    eprintln!(
        "t {:.0} {:?} {:?} truth ({:.2},{:.2},{:.2}) est ({},{},{}) dwa {:?} front {:?} {:?}",
        sim.t_us as f64 * 1e-6,
        mission.state(),
        mission.corridor_status(),
        x,
        y,
        th,
        est.x_mm,
        est.y_mm,
        est.theta_mrad,
        mission.dwa_command(),
        mission.current_subpath(),
        mission.counters()
    );
    for p in &sim.world.people {
        eprintln!(
            "   person ({:.2},{:.2}) waited {:.1}",
            p.pos.0, p.pos.1, p.waited_s
        );
    }
    eprintln!(
        "   pose {:?} loc {:?} near {:?}",
        mission.pose(),
        mission.loc_stats(),
        mission.points_near(260).take(4).collect::<Vec<_>>()
    );
    let v = parts.planner_view();
    eprintln!(
        "   planner nodes {} {:?} pos {:?} list {}",
        v.last_step_nodes, v.stats, v.position, v.list_len
    );
}

/// `ROBOVAC_DEBUG_FINE=A,B`: the window, in simulated seconds, in which
/// [`debug_fine`] prints every control period (µs; None when unset or
/// malformed).
pub fn fine_window() -> Option<(u64, u64)> {
    let v = std::env::var("ROBOVAC_DEBUG_FINE").ok()?;
    let (a, b) = v.split_once(',')?;
    let us = |s: &str| s.trim().parse::<f64>().ok().map(|t| (t * 1e6) as u64);
    Some((us(a)?, us(b)?))
}

/// `ROBOVAC_DEBUG_FINE`: one line a control period: the true pose
/// (heading in mrad, wrapped), the estimate, the state, the guard's
/// corridor, the true wheel speeds, the escape and guard counters and the
/// sub-path followed.
pub fn debug_fine(sim: &Sim, mission: &Mission, parts: &dyn MissionParts) {
    if std::env::var_os("ROBOVAC_DEBUG_NEAR").is_some() {
        debug_near(sim, parts);
    }
    let (x, y, th) = sim.pose;
    let e = mission.pose();
    let c = mission.counters();
    eprintln!(
        "f {:.2} ({:.3},{:.3},{:.0}) est ({},{},{}) {:?} {:?} cs {:?} wh {:?} esc {} gt {} sub {:?}",
        sim.t_us as f64 * 1e-6,
        x,
        y,
        th.sin().atan2(th.cos()) * 1000.0,
        e.x_mm,
        e.y_mm,
        e.theta_mrad,
        mission.state(),
        mission.guard_status(),
        mission.corridor_status(),
        sim.wheel_speeds(),
        c.escapes,
        c.guard_ticks,
        mission.current_subpath().map(|s| s.0)
    );
    let cells: Vec<_> = mission.near_cells().collect();
    eprintln!("   cells {cells:?} free {:?}", mission.cells_free_now());
    if std::env::var_os("ROBOVAC_DEBUG_HITS").is_some() {
        let hits: Vec<_> = mission.hits_near(260).collect();
        eprintln!("   hits {hits:?}");
    }
}

/// `ROBOVAC_DEBUG_NEAR` (with `ROBOVAC_DEBUG_FINE`): 2.4 m around the
/// robot, north up, 50 mm apart: the evidence map (`#` occupied, `7` a
/// bumper's mark, `.` free, blank unknown) beside the twin's grid (`#`
/// wall, `d` dark furniture, `g` glass, `R` the robot).
fn debug_near(sim: &Sim, parts: &dyn MissionParts) {
    use robovac::robot::lidar_map::{FREE_AT, OCCUPIED_AT, PRIOR_WALL};
    let (x, y, _) = sim.pose;
    let (px, py) = ((x * 1000.0) as i32, (y * 1000.0) as i32);
    for k in (-24..=24).rev() {
        let ev: String = (-24..=24)
            .map(|dx| match parts.evidence_at(px + dx * 50, py + k * 50) {
                PRIOR_WALL => '7',
                e if e >= OCCUPIED_AT => '#',
                e if e <= FREE_AT => '.',
                _ => ' ',
            })
            .collect();
        eprintln!("   near {ev} | {}", twin_row(sim, k, 24));
    }
}
