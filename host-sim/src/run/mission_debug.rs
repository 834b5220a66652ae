//! `ROBOVAC_DEBUG_GRID` and `ROBOVAC_DEBUG_TRACE`: what a mission shows on
//! stderr for diagnosis (nothing unless the variable is set).

use robovac::mission::Mission;

use super::mission::HostMissionParts;
use crate::sim::robot::Sim;

/// `ROBOVAC_DEBUG_GRID`: the planning grid on stderr (`covered`: with the
/// covered cells and the planner's counters).
pub fn debug_grid(parts: &HostMissionParts<'_>, covered: bool) {
    if std::env::var_os("ROBOVAC_DEBUG_GRID").is_none() {
        return;
    }
    let g = &*parts.coarse;
    for y in 0..g.height() as i32 {
        let row: String = (0..g.width() as i32)
            .map(|x| {
                if g.is_blocked(x, y) {
                    '#'
                } else if covered && g.get(robovac::grid::Layer::Covered, x, y) {
                    'c'
                } else {
                    '.'
                }
            })
            .collect();
        eprintln!("{row}");
    }
    if covered {
        eprintln!("{:?}", parts.planner.stats());
    }
}

/// `ROBOVAC_DEBUG_TRACE`: a collision on stderr.
pub fn debug_collision(sim: &Sim, mission: &Mission) {
    if let Some(c) = sim.collisions.last() {
        eprintln!(
            "COLLISION t {:.2} by_person {} robot ({:.3},{:.3},{:.2}) state {:?} wheels {:?} people {:?}",
            c.t_s,
            c.by_person,
            sim.pose.0,
            sim.pose.1,
            sim.pose.2,
            mission.state(),
            sim.wheel_speeds(),
            sim.world.people.iter().map(|p| (p.pos, p.waited_s)).collect::<Vec<_>>()
        );
        let (x, y, _) = sim.pose;
        let nearest = (0..360)
            .filter_map(|d| {
                let a = (d as f64).to_radians();
                sim.world.ray(x, y, a, 1.0).map(|r| (r, d))
            })
            .fold((f64::MAX, 0), |b, c| if c.0 < b.0 { c } else { b });
        eprintln!("   nearest wall {:.3} m at {}°", nearest.0, nearest.1);
    }
}

/// `ROBOVAC_DEBUG_TRACE`: the executive's view every simulated second.
pub fn debug_tick(sim: &Sim, mission: &Mission, parts: &HostMissionParts<'_>) {
    let (x, y, th) = sim.pose;
    eprintln!(
        "t {:.0} {:?} {:?} truth ({:.2},{:.2},{:.2}) dwa {:?} front {:?} {:?}",
        sim.t_us as f64 * 1e-6,
        mission.state(),
        mission.corridor_status(),
        x,
        y,
        th,
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
    eprintln!(
        "   planner nodes {} {:?} pos {:?} list {}",
        parts.planner.last_step_nodes(),
        parts.planner.stats(),
        parts.planner.position(),
        parts.planner.backtrack_list().len()
    );
}
