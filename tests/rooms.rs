//! Room segmentation: every free cell in exactly one room, each room
//! connected, rooms split at doorways, the overflow policy and the errors;
//! checked by an independent flood fill.

mod common;

use common::*;
use proptest::prelude::*;
use robovac::grid::maps::{random_obstacles, RandomMap, SplitMix64};
use robovac::grid::rooms::{segment, RoomError, RoomParams, MAX_ROOMS, NONE};
use robovac::Cell;

fn split(g: &TGrid, p: RoomParams) -> Result<(Vec<u8>, u8), RoomError> {
    let mut labels = vec![0xAA; g.cells()];
    let mut queue = vec![Cell::default(); 512];
    segment(g, &mut labels, &mut queue, p).map(|r| (labels, r.count))
}

/// Independent check: blocked cells have no room, free cells one of
/// `1..=count`, every id is used, and each room is 4-connected.
fn check(g: &TGrid, labels: &[u8], count: u8) {
    let w = g.width() as i32;
    for (i, &l) in labels.iter().enumerate() {
        let (x, y) = (i as i32 % w, i as i32 / w);
        if free(g, x, y) {
            assert!(
                (1..=count).contains(&l),
                "cell ({x},{y}) label {l} of {count}"
            );
        } else {
            assert_eq!(l, NONE, "blocked ({x},{y})");
        }
    }
    for id in 1..=count {
        let cells: Vec<usize> = (0..labels.len()).filter(|&i| labels[i] == id).collect();
        assert!(!cells.is_empty(), "room {id} is empty");
        if id == MAX_ROOMS {
            continue; // shared by the overflow
        }
        let mut seen = vec![false; labels.len()];
        let mut stack = vec![cells[0]];
        seen[cells[0]] = true;
        let mut n = 0;
        while let Some(i) = stack.pop() {
            n += 1;
            let (x, y) = (i as i32 % w, i as i32 / w);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w || ny >= g.height() as i32 {
                    continue;
                }
                let j = (ny * w + nx) as usize;
                if labels[j] == id && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        assert_eq!(n, cells.len(), "room {id} is not connected");
    }
}

fn grid(text: &str) -> TGrid {
    let mut g = TGrid::new();
    g.load_ascii(text).unwrap();
    g
}

#[test]
fn two_rooms_split_at_their_doorway() {
    let g = grid(
        "\
##################
#.......#........#
#.......#........#
#.......#........#
#................#
#.......#........#
#.......#........#
##################
",
    );
    let (labels, count) = split(&g, RoomParams::DEFAULT).unwrap();
    check(&g, &labels, count);
    assert_eq!(count, 2);
    let at = |x: i32, y: i32| labels[(y * 18 + x) as usize];
    assert_ne!(at(2, 2), at(14, 2));
    assert_eq!(at(2, 2), at(6, 6));
    assert_eq!(at(14, 2), at(10, 6));
}

#[test]
fn one_open_room_is_one_room() {
    let g = grid("##########\n#........#\n#........#\n#........#\n#........#\n##########\n");
    let (labels, count) = split(&g, RoomParams::DEFAULT).unwrap();
    check(&g, &labels, count);
    assert_eq!(count, 1);
}

#[test]
fn the_built_in_flat_has_its_rooms() {
    let g = grid(robovac::grid::maps::FLAT_40X20);
    let (labels, count) = split(&g, RoomParams::DEFAULT).unwrap();
    check(&g, &labels, count);
    // Three rooms above, the hall, three below (some may merge).
    assert!((4..=8).contains(&count), "{count} rooms");
}

#[test]
fn past_the_last_id_pockets_share_it() {
    // 200 single free cells, each walled off: more pockets than ids.
    let mut text = String::new();
    for y in 0..21 {
        for x in 0..41 {
            text.push(if x % 2 == 1 && y % 2 == 1 { '.' } else { '#' });
        }
        text.push('\n');
    }
    let g = grid(&text);
    let (labels, count) = split(&g, RoomParams::DEFAULT).unwrap();
    assert_eq!(count, MAX_ROOMS);
    check(&g, &labels, count);
    assert!(labels.iter().filter(|&&l| l == MAX_ROOMS).count() > 1);
}

#[test]
fn small_buffers_are_errors_not_panics() {
    let g = grid(robovac::grid::maps::FLAT_40X20);
    let mut labels = vec![0; g.cells() - 1];
    let mut queue = vec![Cell::default(); 512];
    let p = RoomParams::DEFAULT;
    assert_eq!(
        segment(&g, &mut labels, &mut queue, p),
        Err(RoomError::LabelsTooSmall)
    );
    let mut labels = vec![0; g.cells()];
    let mut queue = vec![Cell::default(); 3];
    assert_eq!(
        segment(&g, &mut labels, &mut queue, p),
        Err(RoomError::QueueFull)
    );
    assert_eq!(
        segment(&g, &mut labels, &mut [], p),
        Err(RoomError::QueueFull)
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn every_free_cell_is_in_one_connected_room(seed in 0u64..10_000, density in 5u32..35) {
        let mut g = TGrid::new();
        let spec = RandomMap { width: 40, height: 30, density_pct: density, max_side: 6 };
        random_obstacles(&mut g, spec, &mut SplitMix64::new(seed)).unwrap();
        let (labels, count) = split(&g, RoomParams::DEFAULT).unwrap();
        check(&g, &labels, count);
    }
}

/// Lanes along the long axis: an L-shaped room counted on its own cells,
/// and a thin wall the planning cells do not show.
#[test]
fn lanes_count_runs_and_walls() {
    use robovac::grid::rooms::lanes;
    // A 12 × 3 bar with a 3 × 6 leg: bounding box 12 × 9 (higher than
    // wide, were it square), yet rows take fewer lanes.
    let g = grid(
        "\
##############
#............#
#............#
#............#
#...##########
#...##########
#...##########
#...##########
#...##########
#...##########
##############
",
    );
    // One room: every free cell.
    let labels: Vec<u8> = (0..g.cells())
        .map(|i| {
            let (x, y) = g.cell_at(i).xy();
            u8::from(g.is_free(x, y))
        })
        .collect();
    let joined = |_: (i32, i32), _: (i32, i32)| true;
    // Rows: 3 in the bar, 6 in the leg; columns: 3 in the leg and bar,
    // 9 more in the bar.
    assert_eq!(lanes(&g, &labels, 1, 5, joined), (9, 12));
    // A thin wall across the bar between x = 6 and 7 (not a blocked
    // cell): each of the bar's 3 rows meets it, 5 lanes each.
    let wall = |a: (i32, i32), b: (i32, i32)| !(a.1 <= 3 && a.0 == 6 && b.0 == 7);
    assert_eq!(lanes(&g, &labels, 1, 5, wall), (9 + 3 * 5, 12));
    // No room, no lanes.
    assert_eq!(lanes(&g, &labels, NONE, 5, joined), (0, 0));
    assert_eq!(lanes(&g, &labels, 2, 5, joined), (0, 0));
}
