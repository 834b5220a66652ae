//! Helpers shared by the core's tests (`tests/`) and host-sim's tests:
//! random maps from a seed, temporary directories, JSON files and process
//! outcomes. A dev-dependency only; nothing here ships.

use std::path::{Path, PathBuf};
use std::process::Output;

use robovac::grid::maps::{random_obstacles, RandomMap, SplitMix64};
use robovac::Grid;

/// A `w` × `h` map with rectangles of 1–3 cells until `density` percent
/// is blocked, from `seed` (the core's own generator).
pub fn random_grid<const NW: usize>(w: u32, h: u32, density: u32, seed: u64) -> Box<Grid<NW>> {
    random_grid_with(w, h, density, &mut SplitMix64::new(seed))
}

/// [`random_grid`] drawing from `rng`, which the caller may go on using.
pub fn random_grid_with<const NW: usize>(
    w: u32,
    h: u32,
    density: u32,
    rng: &mut SplitMix64,
) -> Box<Grid<NW>> {
    let mut g = Box::new(Grid::new());
    let spec = RandomMap {
        width: w,
        height: h,
        density_pct: density,
        max_side: 3,
    };
    random_obstacles(&mut *g, spec, rng).expect("random map fits the grid");
    g
}

/// A fresh directory for this test process, named with `tag`.
pub fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("robovac-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The JSON in a file.
pub fn read_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Asserts that a process succeeded, showing its stderr when not.
pub fn assert_ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
