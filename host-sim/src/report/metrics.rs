//! Path measurements shared by the CLI, the benchmarks and the tests.

use robovac::grid::los::supercover;
use robovac::Cell;

use crate::io::maps::MapData;

/// Euclidean length of a polyline, in cells (exact to f64).
pub fn polyline_length(path: &[Cell]) -> f64 {
    path.windows(2)
        .map(|w| {
            let dx = w[0].x as f64 - w[1].x as f64;
            let dy = w[0].y as f64 - w[1].y as f64;
            (dx * dx + dy * dy).sqrt()
        })
        .sum()
}

/// Checks a polyline against a map independently of the planner: every
/// segment's supercover cells are on the map and free (so no obstacle is
/// entered and no corner is cut). Returns the first offending segment.
pub fn check_polyline(map: &MapData, path: &[Cell]) -> Result<(), String> {
    if let Some(c) = path.first() {
        if map.is_blocked(c.x as i32, c.y as i32) {
            return Err(format!("waypoint ({},{}) is blocked", c.x, c.y));
        }
    }
    for (k, w) in path.windows(2).enumerate() {
        let mut bad = None;
        supercover(w[0].xy(), w[1].xy(), |x, y| {
            if map.is_blocked(x, y) {
                bad = Some((x, y));
                false
            } else {
                true
            }
        });
        if let Some((x, y)) = bad {
            return Err(format!(
                "segment {k} ({},{})->({},{}) touches blocked cell ({x},{y})",
                w[0].x, w[0].y, w[1].x, w[1].y
            ));
        }
    }
    Ok(())
}

/// Median of a list (0 for an empty one).
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Mean of a list (0 for an empty one).
pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}
