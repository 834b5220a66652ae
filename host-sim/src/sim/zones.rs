//! The owner's no-go zones and virtual walls in the twin: where they come
//! from (the ValetudoMap file, the command line), and how far the true
//! body reaches into one, which the mission measures.

use robovac::grid::Zone;

use crate::io::maps::MapData;

/// Metres to the core's millimetres.
fn mm(v: f64) -> i32 {
    (v * 1000.0).round().clamp(i32::MIN as f64, i32::MAX as f64) as i32
}

/// A no-go rectangle with corners (x0, y0) and (x1, y1), metres.
pub fn no_go_m(x0: f64, y0: f64, x1: f64, y1: f64) -> Zone {
    Zone::NoGo {
        x0_mm: mm(x0),
        y0_mm: mm(y0),
        x1_mm: mm(x1),
        y1_mm: mm(y1),
    }
}

/// A virtual wall from (x0, y0) to (x1, y1), metres.
pub fn wall_m(x0: f64, y0: f64, x1: f64, y1: f64) -> Zone {
    Zone::Wall {
        ax_mm: mm(x0),
        ay_mm: mm(y0),
        bx_mm: mm(x1),
        by_mm: mm(y1),
    }
}

/// The map's own zones: a ValetudoMap's `no_go_area`s (each as its
/// bounding box: Valetudo draws them as axis-aligned rectangles; a
/// rotated one is kept out of whole) and `virtual_wall`s. Its
/// `no_mop_area`s do not concern a vacuum and are left out.
pub fn map_zones(map: &MapData) -> Vec<Zone> {
    let Some(x) = map.extras.as_deref() else {
        return Vec::new();
    };
    let boxes = x.no_go.iter().filter(|p| !p.is_empty()).map(|poly| {
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for &(px, py) in poly {
            (x0, y0, x1, y1) = (x0.min(px), y0.min(py), x1.max(px), y1.max(py));
        }
        no_go_m(x0, y0, x1, y1)
    });
    let walls = x
        .virtual_walls
        .iter()
        .map(|&((ax, ay), (bx, by))| wall_m(ax, ay, bx, by));
    boxes.chain(walls).collect()
}

/// Leaves a map's own no-go areas and virtual walls out (they are then
/// neither kept to nor drawn), for comparison with the whole home.
pub fn drop_map_zones(map: &mut MapData) {
    if let Some(x) = map.extras.as_deref_mut() {
        x.no_go.clear();
        x.virtual_walls.clear();
    }
}

/// How far (m) a disc of radius `r` at (x, y) reaches into `z`: its
/// radius less its centre's distance to the zone (a rectangle's inside
/// counts as distance 0). At most 0 when the body is clear of it.
pub fn intrusion_m(z: &Zone, x: f64, y: f64, r: f64) -> f64 {
    let f = |v: i32| v as f64 / 1000.0;
    let d = match *z {
        Zone::NoGo {
            x0_mm,
            y0_mm,
            x1_mm,
            y1_mm,
        } => rect_distance_m((f(x0_mm), f(y0_mm)), (f(x1_mm), f(y1_mm)), (x, y)),
        Zone::Wall {
            ax_mm,
            ay_mm,
            bx_mm,
            by_mm,
        } => segment_distance_m((f(ax_mm), f(ay_mm)), (f(bx_mm), f(by_mm)), (x, y)),
    };
    r - d
}

/// Distance (m) from `p` to the rectangle with opposite corners `a`, `b`
/// (0 inside).
pub fn rect_distance_m(a: (f64, f64), b: (f64, f64), p: (f64, f64)) -> f64 {
    let (xa, xb) = (a.0.min(b.0), a.0.max(b.0));
    let (ya, yb) = (a.1.min(b.1), a.1.max(b.1));
    let dx = (xa - p.0).max(0.0).max(p.0 - xb);
    let dy = (ya - p.1).max(0.0).max(p.1 - yb);
    dx.hypot(dy)
}

/// Distance (m) from `p` to the segment from `a` to `b`.
pub fn segment_distance_m(a: (f64, f64), b: (f64, f64), p: (f64, f64)) -> f64 {
    let (ux, uy) = (b.0 - a.0, b.1 - a.1);
    let len2 = ux * ux + uy * uy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * ux + (p.1 - a.1) * uy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a.0 + t * ux - p.0).hypot(a.1 + t * uy - p.1)
}

/// The deepest a disc of radius `r` at (x, y) reaches into any of
/// `zones` (m); `None` when there are none.
pub fn deepest_m(zones: &[Zone], x: f64, y: f64, r: f64) -> Option<f64> {
    zones
        .iter()
        .map(|z| intrusion_m(z, x, y, r))
        .max_by(f64::total_cmp)
}

/// Parses `X0,Y0,X1,Y1` (metres, non-negative) for `--no-go` and
/// `--virtual-wall`.
pub fn parse_corners(s: &str) -> Result<(f64, f64, f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|f| f.is_finite() && *f >= 0.0)
        })
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{s:?} is not X0,Y0,X1,Y1 in metres"))?;
    match v[..] {
        [x0, y0, x1, y1] => Ok((x0, y0, x1, y1)),
        _ => Err(format!("{s:?} is not X0,Y0,X1,Y1 in metres")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intrusion_is_radius_less_distance() {
        let z = no_go_m(1.0, 1.0, 2.0, 2.0);
        assert!((intrusion_m(&z, 0.5, 1.5, 0.2) + 0.3).abs() < 1e-9);
        assert!((intrusion_m(&z, 1.5, 1.5, 0.2) - 0.2).abs() < 1e-9);
        let w = wall_m(0.0, 0.0, 2.0, 0.0);
        assert!((intrusion_m(&w, 1.0, 0.1, 0.2) - 0.1).abs() < 1e-9);
        assert!((intrusion_m(&w, 3.0, 0.0, 0.2) + 0.8).abs() < 1e-9);
    }

    #[test]
    fn corners_parse_or_say_why_not() {
        assert_eq!(parse_corners("1,2,3.5,4"), Ok((1.0, 2.0, 3.5, 4.0)));
        for bad in ["1,2,3", "1,2,3,4,5", "a,2,3,4", "-1,2,3,4", "", "1,2,inf,4"] {
            assert!(parse_corners(bad).is_err(), "{bad}");
        }
    }
}
