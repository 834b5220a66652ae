//! Room by room: a known-mode mission splits the home into rooms, starts
//! in the dock's room and enters every room, each once for its lanes and
//! its edges; checked on the true trajectory, room by room.

use host_sim::run::mission::{run_mission, MissionOptions};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::MapMode;

/// The rooms under the true trajectory, one a second, with runs of one
/// room merged: (room, seconds there).
fn room_runs(t: &host_sim::run::mission::MissionTrace) -> Vec<(u8, usize)> {
    let rooms = t.rooms.as_ref().expect("rooms").filled();
    let mut runs: Vec<(u8, usize)> = Vec::new();
    for &(x, y) in t.truth.iter().step_by(100) {
        let id = rooms.room_at(x, y);
        match runs.last_mut() {
            Some((r, n)) if *r == id => *n += 1,
            _ => runs.push((id, 1)),
        }
    }
    runs
}

#[test]
fn the_home_is_cleaned_room_by_room() {
    let o = MissionOptions::new(
        suite_map("home").unwrap(),
        MapMode::Known,
        0,
        Noise::None,
        1,
    );
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    assert!(rep.finished && rep.docked, "{rep:?}");
    assert!(rep.coverage >= 0.98, "coverage {:.4}", rep.coverage);
    let figures = rep.rooms.expect("a room tour");
    assert!(figures.found >= 3, "{figures:?}");
    assert_eq!(figures.entered, figures.found as u32, "{figures:?}");
    let runs = room_runs(&t);
    let rooms = t.rooms.as_ref().unwrap().filled();
    // The first room cleaned is the dock's.
    let dock_room = rooms.room_at(t.start.0, t.start.1);
    let first = runs.iter().find(|r| r.1 >= 30).unwrap();
    assert_eq!(first.0, dock_room, "{runs:?}");
    // Every room is visited on the truth.
    for id in 1..=figures.found {
        assert!(
            runs.iter().any(|r| r.0 == id),
            "room {id} never visited: {runs:?}"
        );
    }
    // Long stays (a minute or more): each room once, for its lanes and
    // then its edges.
    let long = runs.iter().filter(|r| r.1 >= 60).count();
    eprintln!("rooms {figures:?}; stays {runs:?}");
    assert!(long <= figures.found as usize, "{runs:?}");
    // An edge pass per room (more when one restarts).
    use robovac::mission::{EventKind, State};
    let edges = t
        .events
        .iter()
        .filter(|e| {
            matches!(
                e.kind,
                EventKind::State {
                    to: State::Edge,
                    ..
                }
            )
        })
        .count();
    assert!(edges >= figures.found as usize, "{edges} edge passes");
}
