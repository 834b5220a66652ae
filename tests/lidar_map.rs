//! The evidence map and the derived planner grid.

use robovac::grid::Grid;
use robovac::robot::lidar::scan::{Scan, ScanAssembler};
use robovac::robot::lidar::{LidarFrame, LidarPoint};
use robovac::robot::lidar_map::{evidence_bytes, CellState, EvidenceMap, LidarMount};
use robovac::robot::odometry::Pose;

const MOUNT: LidarMount = LidarMount::ld06_centred(false);

#[test]
fn beams_clear_and_hit() {
    let mut m: Box<EvidenceMap<{ evidence_bytes(100 * 100) }>> = Box::new(EvidenceMap::new());
    m.reset(100, 100, 50).unwrap();
    // Robot at (1 m, 1 m) looking east; a wall 2 m ahead.
    m.trace(1000, 1000, 3000, 1000, true);
    let (hx, hy) = m.cell_of(3000, 1000);
    assert_eq!(m.state(hx, hy), CellState::Occupied);
    let (fx, fy) = m.cell_of(2000, 1000);
    assert_eq!(m.state(fx, fy), CellState::Free);
    // Well-seen free cell: one bad return does not flip it.
    for _ in 0..25 {
        m.trace(1000, 1000, 3000, 1000, true);
    }
    m.trace(1000, 1000, 2000, 1000, true);
    assert_eq!(m.state(fx, fy), CellState::Free);
    // And a well-seen wall survives one beam through it.
    m.trace(1000, 1000, 4000, 1000, true);
    assert_eq!(m.state(hx, hy), CellState::Occupied);
}

#[test]
fn scans_assemble_and_map_a_room() {
    // A 4 m square room seen from its centre by an ideal lidar.
    let mut asm: ScanAssembler<64> = ScanAssembler::new();
    let mut scan: Box<Scan<64>> = Box::new(Scan::new());
    // The room's walls face x, y = 100 and 4100 mm; the map has a margin.
    let pose = Pose {
        x_mm: 2100,
        y_mm: 2100,
        theta_mrad: 0,
    };
    let mut got = false;
    for rev in 0..2 {
        for k in 0..38u32 {
            let start = (k * 36000 / 38) as u16;
            let mut f = LidarFrame {
                speed_dps: 3600,
                start_cdeg: start,
                end_cdeg: start + 900,
                timestamp_ms: 0,
                count: 12,
                ..Default::default()
            };
            for i in 0..12 {
                let a = (start as f64 + i as f64 * 900.0 / 11.0) / 100.0;
                let r = a.to_radians();
                // distance to the square's wall from the centre
                let d = 2000.0 / r.cos().abs().max(r.sin().abs());
                f.points[i] = LidarPoint {
                    angle_cdeg: (a * 100.0) as u16 % 36000,
                    dist_mm: d as u16,
                    intensity: 200,
                };
            }
            got |= asm.push(&f, pose, &mut scan) && rev == 1;
        }
    }
    assert!(got);
    assert!(scan.point_count() >= 38 * 12 - 12);
    let mut m: Box<EvidenceMap<{ evidence_bytes(100 * 100) }>> = Box::new(EvidenceMap::new());
    m.reset(84, 84, 50).unwrap();
    m.integrate_scan(&scan, &MOUNT);
    let c = |x, y| {
        let (cx, cy) = m.cell_of(x, y);
        m.state(cx, cy)
    };
    assert_eq!(c(2100, 2100), CellState::Free);
    assert_eq!(c(3100, 2600), CellState::Free);
    assert_eq!(c(4090, 2100), CellState::Free); // just before the face
    assert_eq!(c(4120, 2100), CellState::Occupied); // the wall
    assert_eq!(c(2100, 80), CellState::Occupied);
    // The planner grid: 0.3 m cells, robot radius 165 mm. Centre cells free,
    // cells within a radius of the walls blocked.
    let mut g: Box<Grid<{ robovac::math::bits::words_for(4096) }>> = Box::new(Grid::new());
    m.derive_grid(&mut *g, 300, 165, true).unwrap();
    assert_eq!((g.width(), g.height()), (14, 14));
    assert!(g.is_free(7, 7) && g.is_free(2, 7));
    assert!(g.is_blocked(0, 7) && g.is_blocked(7, 0) && g.is_blocked(13, 7));
}

#[test]
fn absurd_poses_do_not_panic() {
    let mut m: Box<EvidenceMap<{ evidence_bytes(10 * 10) }>> = Box::new(EvidenceMap::new());
    m.reset(10, 10, 1).unwrap(); // 1 mm cells: the worst case for overflow
    for &(a, b) in &[
        (i32::MIN, i32::MAX),
        (i32::MAX, i32::MIN),
        (0, i32::MIN),
        (i32::MAX, i32::MAX),
    ] {
        let _ = m.cell_of(a, b);
        // A far-away beam: the walk is bounded and touches nothing on the map.
        if a.unsigned_abs() < 1 << 28 && b.unsigned_abs() < 1 << 28 {
            m.trace(a, b, 100, 100, true);
        }
    }
    m.trace(100, 100, 100 + 5_000_000, 100, false);
}

#[test]
fn four_bit_cells_hold_their_values_apart() {
    use robovac::robot::lidar_map::{FREE_LIMIT, LIMIT};
    // 7 × 5 = 35 cells in 18 bytes: an odd count, so the last byte is half used.
    let mut m: Box<EvidenceMap<{ evidence_bytes(7 * 5) }>> = Box::new(EvidenceMap::new());
    // Size, resolution, the box of changed cells (16 bytes), the owner's
    // zones and the cells.
    let zones = core::mem::size_of::<robovac::grid::Zones>();
    assert_eq!(
        core::mem::size_of_val(&*m),
        (12 + 16 + zones + 18_usize).next_multiple_of(4)
    );
    m.reset(7, 5, 50).unwrap();
    let want = |x: i32, y: i32| match (x * 3 + y) % 3 {
        0 => CellState::Occupied,
        1 => CellState::Free,
        _ => CellState::Unknown,
    };
    for y in 0..5 {
        for x in 0..7 {
            m.set_state(x, y, want(x, y));
        }
    }
    for y in 0..5 {
        for x in 0..7 {
            let e = match want(x, y) {
                CellState::Occupied => LIMIT,
                CellState::Free => FREE_LIMIT,
                CellState::Unknown => 0,
            };
            assert_eq!(
                (m.evidence(x, y), m.state(x, y)),
                (e, want(x, y)),
                "({x}, {y})"
            );
        }
    }
    // Off the map: unknown; and the map holds no more cells than its bytes.
    assert_eq!(m.evidence(7, 0), 0);
    assert!(m.reset(6, 6, 50).is_ok()); // 36 cells = 18 bytes
    assert!(m.reset(37, 1, 50).is_err());
}

#[test]
fn evidence_steps_of_four_bit_cells() {
    // Cells of 100 mm; beams along the row y = 50 mm, from x = 50 mm.
    let mut m: Box<EvidenceMap<{ evidence_bytes(20) }>> = Box::new(EvidenceMap::new());
    m.reset(20, 1, 100).unwrap();
    let (fx, fy) = m.cell_of(1050, 50);
    // A well-seen free cell: three returns in it leave it not yet occupied,
    // the fourth makes it occupied (a person stepping in).
    m.set_state(fx, fy, CellState::Free);
    for k in 1..=4 {
        m.trace(50, 50, 1050, 50, true);
        assert_eq!(m.state(fx, fy) == CellState::Occupied, k == 4, "hit {k}");
    }
    // A well-seen wall survives six beams through it; the seventh frees it.
    for _ in 0..4 {
        m.trace(50, 50, 1050, 50, true);
    }
    assert_eq!(m.evidence(fx, fy), robovac::robot::lidar_map::LIMIT);
    for k in 1..=7 {
        m.trace(50, 50, 1850, 50, true);
        let free = m.state(fx, fy) == CellState::Free;
        assert_eq!(free, k == 7, "miss {k}");
    }
    // A prior wall never changes.
    let (wx, wy) = m.cell_of(1550, 50);
    m.set_state(wx, wy, CellState::Occupied);
    assert_eq!(m.freeze_prior(), 2); // the wall and the beam's last hit cell
    for _ in 0..30 {
        m.trace(50, 50, 1950, 50, true);
    }
    assert!(m.is_wall(wx, wy, true));
}

mod partial_refresh {
    //! The planning cells derived again only around the map's changed
    //! cells (`take_changed`, `coarse_box_of`, `update_coarse_in`) equal
    //! the cells derived all over again: the mission's refresh after a
    //! revolution relies on it.
    use super::*;
    use proptest::prelude::*;
    use robovac::nav::cspace::{coarse_box_of, update_coarse, update_coarse_in};

    const W: u32 = 60;
    const H: u32 = 48;
    type Map = EvidenceMap<{ evidence_bytes(60 * 48) }>;
    type Coarse = Grid<{ robovac::math::bits::words_for(20 * 16) }>;

    fn coarse_of(map: &Map, cell_mm: u32, r: u32) -> Box<Coarse> {
        let mut g: Box<Coarse> = Box::new(Grid::new());
        g.reset(W * 50 / cell_mm, H * 50 / cell_mm).unwrap();
        update_coarse(map, &mut g, cell_mm, r, false).unwrap();
        g
    }

    fn same(a: &Coarse, b: &Coarse) -> bool {
        (0..a.height() as i32)
            .all(|y| (0..a.width() as i32).all(|x| a.is_free(x, y) == b.is_free(x, y)))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        #[test]
        fn equals_a_full_refresh(
            walls in prop::collection::vec((0i32..60, 0i32..48, 0u8..3), 0..120),
            beams in prop::collection::vec((100i32..2900, 100i32..2300, 100i32..2900, 100i32..2300, any::<bool>()), 1..40),
            r in 120u32..260,
        ) {
            let cell_mm = 150;
            let mut map: Box<Map> = Box::new(EvidenceMap::new());
            map.reset(W, H, 50).unwrap();
            for &(x, y, s) in &walls {
                let st = [CellState::Free, CellState::Occupied, CellState::Unknown][s as usize];
                map.set_state(x, y, st);
            }
            let mut partial = coarse_of(&map, cell_mm, r);
            map.take_changed();
            for &(x0, y0, x1, y1, hit) in &beams {
                map.trace(x0, y0, x1, y1, hit);
            }
            if let Some(changed) = map.take_changed() {
                let b = coarse_box_of(50, cell_mm, r, changed);
                update_coarse_in(&map, &mut partial, cell_mm, r, false, b).unwrap();
            }
            prop_assert!(same(&partial, &coarse_of(&map, cell_mm, r)));
        }
    }
}

/// The bumper's marks are forgotten on request (unknown mode, boxed in):
/// each becomes a free cell that one lidar hit turns occupied again, the
/// lidar's own walls are left as they were, and the changed box covers
/// the map so the derived grids are rebuilt.
#[test]
fn contacts_are_forgotten_and_the_lidar_judges_them_again() {
    use robovac::robot::lidar_map::{FREE_AT, PRIOR_WALL};
    let mut m: Box<EvidenceMap<{ evidence_bytes(20 * 4) }>> = Box::new(EvidenceMap::new());
    m.reset(20, 4, 100).unwrap();
    m.set_state(3, 1, CellState::Occupied);
    assert!(m.mark_contact(550, 250));
    assert!(m.mark_contact(1050, 150));
    let _ = m.take_changed();
    let (a, b) = (m.cell_of(550, 250), m.cell_of(1050, 150));
    assert_eq!(
        (m.evidence(a.0, a.1), m.evidence(b.0, b.1)),
        (PRIOR_WALL, PRIOR_WALL)
    );
    assert_eq!(m.forget_contacts(), 2);
    assert_eq!(
        (m.evidence(a.0, a.1), m.evidence(b.0, b.1)),
        (FREE_AT, FREE_AT)
    );
    assert_eq!(m.state(3, 1), CellState::Occupied, "the lidar's wall stays");
    assert_eq!(m.take_changed(), Some((0, 0, 19, 3)));
    assert_eq!(m.forget_contacts(), 0);
    assert_eq!(m.take_changed(), None);
    // One return in a forgotten cell makes it occupied again.
    let (x, y) = (b.0 * 100 + 50, 4 * 100 - b.1 * 100 - 50);
    m.trace(50, y, x, y, true);
    assert_eq!(m.state(b.0, b.1), CellState::Occupied);
}

type JambMap = EvidenceMap<{ evidence_bytes(20 * 20) }>;

/// A 1 × 1 m map at 5 cm with one occupied cell: x 500..550 mm, y
/// 500..550 mm.
fn jamb_map() -> Box<JambMap> {
    let mut m: Box<JambMap> = Box::new(EvidenceMap::new());
    m.reset(20, 20, 50).unwrap();
    let (cx, cy) = m.cell_of(520, 520);
    m.set_state(cx, cy, CellState::Occupied);
    m
}

/// The wall point a mapped lidar hit stands for (the guard judges it at
/// full width instead of the hit): a point of the nearest occupied cell's
/// square, the one nearest the robot, whatever the range noise on the
/// hit, as long as the hit lies within the tolerance given (2.5 σ of the
/// range noise) of that square.
#[test]
fn a_mapped_hit_stands_for_the_nearest_wall_point_of_its_cell() {
    use robovac::nav::geometry::wall_offset;
    // One occupied cell: x 500..550 mm, y 500..550 mm (a door jamb's corner).
    let m = jamb_map();
    let snap = |q: (i32, i32), from: (i32, i32)| {
        wall_offset(&*m, q, from, 25, false).map(|[dx, dy]| (q.0 + dx as i32, q.1 + dy as i32))
    };
    // Hits on the west face, 10 mm short and 10 mm deep (range noise),
    // seen from the south-west: both stand for the corner (500, 500).
    for q in [(490, 510), (510, 520), (495, 545)] {
        assert_eq!(snap(q, (300, 300)), Some((500, 500)), "{q:?}");
    }
    // Seen from due west, the nearest point is on the west face.
    assert_eq!(snap((490, 510), (200, 530)), Some((500, 530)));
    // A robot standing inside the square (a bad pose) gets its own position.
    assert_eq!(snap((520, 520), (510, 540)), Some((510, 540)));
    // A hit 20 mm in front of the face is range noise; 40 mm in front,
    // it is something else (a person by the wall) and stands for itself.
    assert_eq!(snap((480, 520), (300, 300)), Some((500, 500)));
    assert_eq!(snap((460, 520), (300, 300)), None);
    // An ideal sensor (no tolerance): only a hit on the square stands for it.
    assert_eq!(
        wall_offset(&*m, (500, 520), (300, 300), 0, false),
        Some([0, -20])
    );
    assert_eq!(wall_offset(&*m, (499, 520), (300, 300), 0, false), None);
    // No occupied cell within one cell of the hit: nothing to stand for.
    assert_eq!(snap((390, 390), (300, 300)), None);
    assert_eq!(snap((700, 700), (300, 300)), None);
    // Off the map (a hit beyond its edge) reads unknown, never occupied.
    assert_eq!(snap((-60, 2000), (300, 300)), None);
}

/// Known mode (`fixed_only`): a hit stands for a fixed wall's square (the
/// prior, frozen; a bumper's mark) but not for a cell mapped beside the
/// prior (a person, mapped late and a cell coarse): that hit stands for
/// itself, so the guard sees where the person truly is.
#[test]
fn in_known_mode_only_fixed_walls_are_stood_for() {
    use robovac::nav::geometry::wall_offset;
    let mut m = jamb_map();
    m.freeze_prior();
    // A person mapped after the freeze, 0.3 m east of the wall cell.
    let (px, py) = m.cell_of(820, 520);
    m.set_state(px, py, CellState::Occupied);
    let at = |m: &JambMap, q: (i32, i32), fixed| wall_offset(m, q, (300, 300), 25, fixed);
    // The prior wall: stood for in both modes.
    assert_eq!(at(&m, (490, 510), true), Some([10, -10]));
    assert_eq!(at(&m, (490, 510), false), Some([10, -10]));
    // The person's cell: only when every occupied cell counts.
    assert!(at(&m, (790, 510), false).is_some());
    assert_eq!(at(&m, (790, 510), true), None);
    // A bumper's mark is fixed, as the prior is.
    m.mark_contact(820, 520);
    assert!(at(&m, (790, 510), true).is_some());
}

/// The edge pass's "sure to block" test counts the map's outside as
/// blocked, as every other clearance check does: a disc hanging over the
/// edge of a map whose border cells are free is not clear.
#[test]
fn the_maps_outside_is_surely_blocked() {
    use robovac::nav::cspace::{disc_blocked, disc_surely_blocked};
    let mut m: Box<EvidenceMap<{ evidence_bytes(20 * 20) }>> = Box::new(EvidenceMap::new());
    m.reset(20, 20, 50).unwrap();
    for cy in 0..20 {
        for cx in 0..20 {
            m.set_state(cx, cy, CellState::Free);
        }
    }
    // Index space (the checks' own): the centre 100 mm from the left
    // edge, radius 150 mm: the disc overlaps the outside.
    assert!(disc_blocked(&*m, 100, 500, 150, false));
    assert!(disc_surely_blocked(&*m, 100, 500, 150, 4));
    // Well inside, nothing blocks.
    assert!(!disc_blocked(&*m, 500, 500, 150, false));
    assert!(!disc_surely_blocked(&*m, 500, 500, 150, 4));
}

/// A map saved by a known-mode run holds its walls as `PRIOR_WALL`, like
/// bumper marks; loaded for an unknown-mode run they are thawed into
/// ordinary walls, so forgetting the marks later frees none of them.
#[test]
fn a_loaded_maps_frozen_walls_thaw_and_outlive_forgotten_marks() {
    use robovac::robot::lidar_map::{LIMIT, PRIOR_WALL};
    let mut m: Box<EvidenceMap<{ evidence_bytes(20 * 4) }>> = Box::new(EvidenceMap::new());
    m.reset(20, 4, 100).unwrap();
    for x in 0..20 {
        m.set_state(x, 0, CellState::Occupied);
    }
    assert_eq!(m.freeze_prior(), 20);
    assert_eq!(m.evidence(7, 0), PRIOR_WALL);
    assert_eq!(m.thaw_prior(), 20);
    assert_eq!(m.evidence(7, 0), LIMIT);
    assert!(m.mark_contact(550, 250));
    assert_eq!(m.forget_contacts(), 1, "only this run's mark");
    assert!((0..20).all(|x| m.state(x, 0) == CellState::Occupied));
    // Thawed, a wall is the lidar's again: beams through it clear it.
    for _ in 0..7 {
        m.trace(750, 50, 750, 395, false);
    }
    assert_eq!(m.state(7, 0), CellState::Free);
}
