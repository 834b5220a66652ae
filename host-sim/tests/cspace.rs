//! The fine configuration space (`robovac::nav::cspace::build_fine`)
//! against the plain definition: a cell is blocked when a disc of the
//! radius at its centre overlaps a blocking evidence cell (or the map's
//! edge). Random maps of walls, blobs and unknown cells, several radii and
//! resolutions, both unknown policies.

use proptest::prelude::*;
use robovac::nav::cspace::{build_fine, cell_blocks, square_dist2, stamp_cell, MAX_STAMP_REACH};
use robovac::robot::lidar_map::{CellState, EvidenceMap};
use robovac::Grid;

type Map = EvidenceMap<{ 64 * 64 }>;
type Fine = Grid<{ 64 * 64 / 32 }>;

/// The definition, cell by cell (the former stamping loop's result).
fn reference(map: &Map, r: i64, unknown_blocks: bool, x: i32, y: i32) -> bool {
    let res = map.res_mm() as i64;
    let (px, py) = (x as i64 * res + res / 2, y as i64 * res + res / 2);
    let reach = (r / res + 2) as i32;
    (y - reach..=y + reach).any(|cy| {
        (x - reach..=x + reach).any(|cx| {
            let ring =
                cx >= -1 && cy >= -1 && cx <= map.width() as i32 && cy <= map.height() as i32;
            ring && cell_blocks(map, cx, cy, unknown_blocks)
                && square_dist2(px, py, cx as i64, cy as i64, res) < r * r
        })
    })
}

fn random_map(w: u32, h: u32, res: u32, cells: &[(u8, u8, u8)]) -> Map {
    random_map_with(w, h, res, cells, &[])
}

/// Blobs and wall pieces from `cells`, and solid blocks (thick walls,
/// furniture) from `rects` (x, y, width, height, unknown?).
fn random_map_with(
    w: u32,
    h: u32,
    res: u32,
    cells: &[(u8, u8, u8)],
    rects: &[(u8, u8, u8, u8, bool)],
) -> Map {
    let mut map = Map::new();
    map.reset(w, h, res).unwrap();
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            map.set_state(x, y, CellState::Free);
        }
    }
    for &(x, y, kind) in cells {
        let (x, y) = (x as i32 % w as i32, y as i32 % h as i32);
        let st = if kind % 3 == 0 {
            CellState::Unknown
        } else {
            CellState::Occupied
        };
        // Blobs and wall pieces: a 1-3 cell run.
        for k in 0..=(kind as i32 % 3) {
            let (cx, cy) = if kind % 2 == 0 {
                (x + k, y)
            } else {
                (x, y + k)
            };
            if cx < w as i32 && cy < h as i32 {
                map.set_state(cx, cy, st);
            }
        }
    }
    for &(x, y, rw, rh, unknown) in rects {
        let st = if unknown {
            CellState::Unknown
        } else {
            CellState::Occupied
        };
        for cy in y as i32..(y as i32 + rh as i32).min(h as i32) {
            for cx in x as i32..(x as i32 + rw as i32).min(w as i32) {
                map.set_state(cx, cy, st);
            }
        }
    }
    map
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn fine_space_matches_the_definition(
        w in 1u32..64, h in 1u32..64,
        res in prop::sample::select(vec![20u32, 50, 100]),
        r in 0u32..400,
        unknown_blocks: bool,
        cells in prop::collection::vec((0u8..64, 0u8..64, any::<u8>()), 0..120),
        rects in prop::collection::vec((0u8..64, 0u8..64, 1u8..24, 1u8..24, any::<bool>()), 0..6),
    ) {
        let map = random_map_with(w, h, res, &cells, &rects);
        let mut fine = Fine::new();
        build_fine(&map, &mut fine, r, unknown_blocks).unwrap();
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                prop_assert_eq!(
                    fine.is_blocked(x, y),
                    reference(&map, r as i64, unknown_blocks, x, y),
                    "cell ({}, {}), radius {} mm, {} mm cells", x, y, r, res
                );
            }
        }
    }
}

#[test]
fn a_reach_beyond_the_stamp_is_refused() {
    let map = random_map(8, 8, 10, &[]);
    let mut fine = Fine::new();
    let r = (MAX_STAMP_REACH as u32 - 2) * 10;
    assert!(build_fine(&map, &mut fine, r, false).is_ok());
    assert!(build_fine(&map, &mut fine, r + 10, false).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]
    /// A bump's mark stamped into a built grid ([`stamp_cell`]) gives the
    /// grid built after the mark: the edge pass keeps its grid and stamps.
    #[test]
    fn a_stamped_mark_matches_a_rebuild(
        w in 4u32..48, h in 4u32..48,
        r in 0u32..300,
        cells in prop::collection::vec((0u8..48, 0u8..48, any::<u8>()), 0..60),
        mark in (0u8..48, 0u8..48),
    ) {
        let mut map = random_map(w, h, 50, &cells);
        let mut stamped = Fine::new();
        build_fine(&map, &mut stamped, r, false).unwrap();
        let (mx, my) = (mark.0 as i32 % w as i32, mark.1 as i32 % h as i32);
        let (x_mm, y_mm) = (mx * 50 + 25, (h as i32 - 1 - my) * 50 + 25);
        map.mark_contact(x_mm, y_mm);
        prop_assert_eq!(map.cell_of(x_mm, y_mm), (mx, my));
        prop_assert!(stamp_cell(&mut stamped, 50, r, (mx, my)));
        let mut rebuilt = Fine::new();
        build_fine(&map, &mut rebuilt, r, false).unwrap();
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                prop_assert_eq!(stamped.is_blocked(x, y), rebuilt.is_blocked(x, y), "({}, {})", x, y);
            }
        }
    }
}

/// A bump's mark is a fixed wall: beams through it (a glass pane lets
/// them pass) do not wipe it, as they would an ordinary wall's evidence.
#[test]
fn a_bump_mark_survives_beams_through_it() {
    let mut map = random_map(20, 20, 50, &[]);
    let (x, y) = (525, 525);
    assert!(map.mark_contact(x, y));
    assert!(!map.mark_contact(x, y), "marked once");
    assert!(map.take_changed().is_some());
    for _ in 0..50 {
        map.trace(25, 525, 975, 525, true);
    }
    let (cx, cy) = map.cell_of(x, y);
    assert_eq!(map.state(cx, cy), CellState::Occupied);
}

/// Forgetting the marks near a robot shut in by them frees those within
/// the square only, notes the change, and leaves marks elsewhere (a glass
/// pane across the room stays marked) and the lidar's own walls alone.
#[test]
fn marks_are_forgotten_near_a_point_only() {
    let mut map = random_map(20, 20, 50, &[]);
    for _ in 0..10 {
        map.trace(25, 325, 975, 325, true);
    }
    let wall = map.cell_of(975, 325);
    assert_eq!(map.state(wall.0, wall.1), CellState::Occupied);
    assert!(map.mark_contact(525, 525) && map.mark_contact(575, 525));
    assert!(map.mark_contact(125, 925));
    let _ = map.take_changed();
    let (cx, cy) = map.cell_of(525, 525);
    assert_eq!(map.forget_contacts_near(cx, cy, 3), 2);
    let changed = map.take_changed().expect("the change is noted");
    assert!(changed.0 <= cx && changed.2 > cx && changed.1 <= cy && changed.3 >= cy);
    assert_ne!(map.state(cx, cy), CellState::Occupied);
    let far = map.cell_of(125, 925);
    assert_eq!(
        map.state(far.0, far.1),
        CellState::Occupied,
        "a far mark stays"
    );
    assert_eq!(
        map.state(wall.0, wall.1),
        CellState::Occupied,
        "a wall stays"
    );
    assert_eq!(map.forget_contacts_near(cx, cy, 3), 0);
    assert_eq!(map.forget_contacts_near(-100, -100, 5), 0, "off the map");
}

/// Squared distance (mm²) from point p to segment a–b, in floating point
/// (independent of the core's integer version).
fn seg_dist2_f(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (ux, uy) = (b.0 - a.0, b.1 - a.1);
    let len2 = ux * ux + uy * uy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * ux + (p.1 - a.1) * uy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a.0 + t * ux - p.0).powi(2) + (a.1 + t * uy - p.1).powi(2)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]
    /// No-go zones and virtual walls: no free cell of the fine space puts
    /// the body (radius r) within the margin of a zone, in world mm, on
    /// random maps with random rectangles and segments (some reaching
    /// past the map).
    #[test]
    fn the_free_space_keeps_the_body_out_of_zones(
        w in 4u32..48, h in 4u32..48,
        r in 1u32..300,
        margin in 0u32..120,
        cells in prop::collection::vec((0u8..48, 0u8..48, any::<u8>()), 0..40),
        zones in prop::collection::vec(
            (any::<bool>(), -200i32..2600, -200i32..2600, -200i32..2600, -200i32..2600), 1..=robovac::grid::zones::MAX_ZONES),
    ) {
        use robovac::grid::Zone;
        let mut map = random_map(w, h, 50, &cells);
        let zones: Vec<Zone> = zones.iter().map(|&(rect, a, b, c, d)| if rect {
            Zone::NoGo { x0_mm: a, y0_mm: b, x1_mm: c, y1_mm: d }
        } else {
            Zone::Wall { ax_mm: a, ay_mm: b, bx_mm: c, by_mm: d }
        }).collect();
        map.set_zones(&zones, margin).unwrap();
        let mut fine = Fine::new();
        build_fine(&map, &mut fine, r, false).unwrap();
        let keep = (r + margin) as f64;
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                if fine.is_blocked(x, y) {
                    continue;
                }
                // The cell's centre in world mm (y up).
                let p = (x as f64 * 50.0 + 25.0, (h as i32 - 1 - y) as f64 * 50.0 + 25.0);
                for z in &zones {
                    let d2 = match *z {
                        Zone::NoGo { x0_mm, y0_mm, x1_mm, y1_mm } => {
                            let dx = (x0_mm.min(x1_mm) as f64 - p.0).max(0.0).max(p.0 - x0_mm.max(x1_mm) as f64);
                            let dy = (y0_mm.min(y1_mm) as f64 - p.1).max(0.0).max(p.1 - y0_mm.max(y1_mm) as f64);
                            dx * dx + dy * dy
                        }
                        Zone::Wall { ax_mm, ay_mm, bx_mm, by_mm } => seg_dist2_f(
                            p, (ax_mm as f64, ay_mm as f64), (bx_mm as f64, by_mm as f64)),
                    };
                    prop_assert!(d2 >= keep * keep - 1.0,
                        "free cell ({}, {}) is {:.0} mm from {:?}, keep {} mm", x, y, d2.sqrt(), z, keep);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// The leg check's geometry (`foot_on_segment`, `toward`) against
    /// floating point: within 1 mm of the exact foot and point, on the
    /// segment, any coordinates a pose can hold.
    #[test]
    fn foot_and_point_along_a_segment_are_exact_to_a_millimetre(
        a in (-30_000i32..30_000, -30_000i32..30_000),
        b in (-30_000i32..30_000, -30_000i32..30_000),
        p in (-40_000i32..40_000, -40_000i32..40_000),
        d in 0i64..50_000,
    ) {
        use robovac::nav::geometry::{foot_on_segment, toward};
        let f = |q: (i32, i32)| (q.0 as f64, q.1 as f64);
        let ((ax, ay), (bx, by), (px, py)) = (f(a), f(b), f(p));
        let (ux, uy) = (bx - ax, by - ay);
        let len2 = ux * ux + uy * uy;
        let t = if len2 == 0.0 { 0.0 } else { (((px - ax) * ux + (py - ay) * uy) / len2).clamp(0.0, 1.0) };
        let got = foot_on_segment(a, b, p);
        prop_assert!((got.0 as f64 - (ax + t * ux)).abs() <= 1.0 && (got.1 as f64 - (ay + t * uy)).abs() <= 1.0, "{got:?}");
        let len = len2.sqrt();
        let s = if len <= d as f64 { 1.0 } else { d as f64 / len };
        let got = toward(a, b, d);
        prop_assert!((got.0 as f64 - (ax + s * ux)).abs() <= 1.5 && (got.1 as f64 - (ay + s * uy)).abs() <= 1.5, "{got:?}");
    }
}

/// The extremes: no overflow, and a zero-length segment is its own foot.
#[test]
fn foot_on_a_segment_at_the_extremes() {
    use robovac::nav::geometry::{foot_on_segment, toward};
    let (lo, hi) = (i32::MIN, i32::MAX);
    assert_eq!(foot_on_segment((5, 5), (5, 5), (hi, lo)), (5, 5));
    assert_eq!(foot_on_segment((lo, lo), (hi, hi), (lo, lo)), (lo, lo));
    assert_eq!(foot_on_segment((lo, lo), (hi, hi), (hi, hi)), (hi, hi));
    let _ = toward((0, 0), (100, 0), i64::MAX);
    assert_eq!(toward((0, 0), (100, 0), 40), (40, 0));
}

/// A free cell walled in on all sides (an island the corner berths can
/// leave) is a pocket; the open floor beside it is not. The nearest free
/// cell a search starts from skips the pocket, so a robot parked on one
/// searches from the open floor instead of failing for ever.
#[test]
fn a_pocket_is_skipped_as_a_search_start() {
    use robovac::nav::geometry::{in_pocket, search_start_fine, POCKET_CELLS};
    let mut fine = Fine::new();
    fine.load_ascii(
        "##########\n\
         #.#......#\n\
         ###......#\n\
         #........#\n\
         ##########\n",
    )
    .unwrap();
    assert!(in_pocket(&fine, 1, 1));
    assert!(!in_pocket(&fine, 4, 2));
    const { assert!(POCKET_CELLS <= 20, "the open room has 20 free cells") };
    let mut map = Map::new();
    map.reset(10, 5, 50).unwrap();
    let (x, y) = robovac::nav::cspace::fine_centre_mm(&map, 1, 1);
    let start = search_start_fine(&map, &fine, (x, y), 3).unwrap();
    assert!(
        !in_pocket(&fine, start.x as i32, start.y as i32),
        "{start:?}"
    );
    assert!(fine.is_free(start.x as i32, start.y as i32));
    // A pocket exactly one cell short of open, and one exactly open.
    let row = |n: usize| format!("#{}{}#\n", ".".repeat(n), "#".repeat(20 - n));
    for (n, pocket) in [(POCKET_CELLS - 1, true), (POCKET_CELLS, false)] {
        let text = format!(
            "{}{}{}",
            "#".repeat(22) + "\n",
            row(n),
            "#".repeat(22) + "\n"
        );
        fine.load_ascii(&text).unwrap();
        assert_eq!(in_pocket(&fine, 1, 1), pocket, "{n} cells");
    }
}
