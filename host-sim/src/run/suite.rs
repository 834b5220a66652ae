//! The built-in mission suite: its maps, its cases, and running them on a
//! thread pool.

use robovac::mission::MapMode;

use super::mission::{run_mission, MissionOptions, MissionReport};
use crate::io::maps::MapData;
use crate::sim::robot::Noise;

/// A built-in mission map: name, ASCII text (0.1 m cells).
pub const SUITE_MAPS: [(&str, &str); 3] = [
    ("studio", include_str!("../../../maps/flat/studio.txt")),
    ("home", include_str!("../../../maps/flat/home.txt")),
    ("office", include_str!("../../../maps/flat/office.txt")),
];

/// The six real homes (ValetudoMap exports, Apache-2.0, see
/// `maps/valetudo/README.md`): name, JSON text (5 cm pixels).
pub const HOME_MAPS: [(&str, &str); 6] = [
    (
        "S8",
        include_str!("../../../maps/valetudo/S8_FW1286_with_obstacles.json"),
    ),
    (
        "z10",
        include_str!("../../../maps/valetudo/z10_1056_paths.json"),
    ),
    (
        "1c",
        include_str!("../../../maps/valetudo/1c_1096_virtualwall_and_forbidden_zone.json"),
    ),
    (
        "S6",
        include_str!("../../../maps/valetudo/S6_FW2652_with_active_segment_and_no_mop_zone.json"),
    ),
    (
        "3790",
        include_str!("../../../maps/valetudo/converted_3790.json"),
    ),
    (
        "l10su",
        include_str!("../../../maps/valetudo/l10su_1121_new_path.json"),
    ),
];

/// A built-in map as map data: a flat (0.1 m cells) or a real home (5 cm).
pub fn suite_map(name: &str) -> Result<MapData, String> {
    if let Some((_, text)) = HOME_MAPS.iter().find(|(n, _)| *n == name) {
        return crate::io::valetudo::parse_valetudo(
            std::path::Path::new(name),
            text.as_bytes(),
            None,
        )
        .map_err(|e| e.to_string());
    }
    let (_, text) = SUITE_MAPS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| format!("no built-in map {name:?}"))?;
    crate::io::maps::parse_ascii(std::path::Path::new(name), text.as_bytes())
        .map(|mut m| {
            m.cell_m = Some(0.1);
            m
        })
        .map_err(|e| e.to_string())
}

/// One mission of the suite.
#[derive(Clone, Debug)]
pub struct SuiteCase {
    /// Map name.
    pub map: &'static str,
    /// Map mode.
    pub mode: MapMode,
    /// People.
    pub people: usize,
    /// Noise.
    pub noise: Noise,
    /// Seed.
    pub seed: u64,
}

/// The suite: `maps` × known/unknown × `people` × `noises` × `runs`
/// seeds (from `seed`).
pub fn suite_cases(
    runs: usize,
    seed: u64,
    maps: &[&'static str],
    people: &[usize],
    noises: &[Noise],
) -> Vec<SuiteCase> {
    let mut v = Vec::new();
    for &map in maps {
        for mode in [MapMode::Known, MapMode::Unknown] {
            for &people in people {
                for &noise in noises {
                    for k in 0..runs as u64 {
                        v.push(SuiteCase {
                            map,
                            mode,
                            people,
                            noise,
                            seed: seed + k,
                        });
                    }
                }
            }
        }
    }
    v
}

/// Runs the suite on a rayon pool of `threads` threads, with the maps'
/// own no-go zones and virtual walls when `map_zones`; `progress(done,
/// total)` after each mission. Results in case order.
pub fn run_suite(
    cases: &[SuiteCase],
    max_time_s: f64,
    threads: usize,
    map_zones: bool,
    local: robovac::mission::LocalPlanner,
    progress: impl Fn(usize, usize) + Sync,
) -> Vec<Result<MissionReport, String>> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let done = AtomicUsize::new(0);
    let run_one = |c: &SuiteCase| {
        let r = suite_map(c.map).and_then(|mut map| {
            if !map_zones {
                crate::sim::zones::drop_map_zones(&mut map);
            }
            let mut opts = MissionOptions::new(map, c.mode, c.people, c.noise, c.seed);
            opts.max_time_s = max_time_s;
            opts.local = local;
            run_mission(&opts, |_, _, _| {}).map(|(rep, _, _)| rep)
        });
        progress(done.fetch_add(1, Ordering::SeqCst) + 1, cases.len());
        r
    };
    match rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
    {
        Ok(pool) => pool.install(|| cases.par_iter().map(run_one).collect()),
        Err(e) => cases
            .iter()
            .map(|_| Err(format!("thread pool: {e}")))
            .collect(),
    }
}
