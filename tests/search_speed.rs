//! The search's fast machinery (issue 13, search speed), each piece checked
//! against a plain model: the dial order of the open list, division by a
//! map's width without a divide, and the 3 × 3 free-neighbour read.

mod common;

use common::*;
use proptest::prelude::*;
use robovac::math::bits::Bits;
use robovac::math::divide::{RowDivider, EXACT_BELOW};
use robovac::search::open_list::{Entry, Full, OpenList, Order};
use robovac::search::NEIGHBOURS;

fn entry(f: u32, idx: u32) -> Entry {
    Entry { f, g: 7, idx }
}

proptest! {
    /// Keys that never fall below the last popped (what A* with a
    /// consistent heuristic pushes) come out smallest first, each pushed
    /// entry exactly once, however pushes and pops interleave.
    #[test]
    fn dial_order_pops_the_least_key(ops in proptest::collection::vec((any::<bool>(), 0u32..=robovac::search::open_list::dial::SPREAD, 0u32..1000), 1..600)) {
        let mut q: OpenList<1024> = OpenList::new();
        q.clear_for(Order::Monotone);
        let mut model: Vec<(u32, u32)> = Vec::new();
        let mut last = 0u32;
        let mut pushed = false;
        for (push, delta, idx) in ops {
            if push {
                let f = last + delta;
                if !pushed {
                    last = f; // the first key since the clear sets the floor
                    pushed = true;
                }
                q.push(entry(f, idx)).unwrap();
                model.push((f, idx));
            } else {
                let least = model.iter().map(|e| e.0).min();
                let got = q.pop();
                prop_assert_eq!(got.map(|e| e.f), least);
                if let Some(e) = got {
                    prop_assert_eq!(e.g, 0);
                    let at = model.iter().position(|&m| m == (e.f, e.idx));
                    prop_assert!(at.is_some(), "popped {:?} was never pushed", e);
                    model.swap_remove(at.unwrap());
                    last = e.f;
                }
            }
            prop_assert_eq!(q.len(), model.len());
        }
    }
}

/// The documented tie rule: equal keys come out last in first out,
/// except a bucket that held several keys, whose entries of the least key
/// come out oldest first once it is split.
#[test]
fn dial_ties_follow_the_documented_rule() {
    let mut q: OpenList<16> = OpenList::new();
    q.clear_for(Order::Monotone);
    q.push(entry(10, 9)).unwrap(); // the first push sets the floor
    for idx in 0..3 {
        q.push(entry(40, idx)).unwrap();
    }
    assert_eq!(q.pop().map(|e| (e.f, e.idx)), Some((10, 9)));
    assert_eq!(q.pop().map(|e| (e.f, e.idx)), Some((40, 2)), "newest first");
    q.push(entry(40, 5)).unwrap();
    q.push(entry(40, 6)).unwrap();
    let order: Vec<(u32, u32)> = std::iter::from_fn(|| q.pop().map(|e| (e.f, e.idx))).collect();
    assert_eq!(order, [(40, 6), (40, 5), (40, 1), (40, 0)]);
    // Keys 40 and 41 share a bucket: it is split when opened.
    q.clear_for(Order::Monotone);
    for (f, idx) in [(10, 9), (41, 1), (40, 2), (41, 3), (40, 4)] {
        q.push(entry(f, idx)).unwrap();
    }
    let order: Vec<(u32, u32)> = std::iter::from_fn(|| q.pop().map(|e| (e.f, e.idx))).collect();
    assert_eq!(order, [(10, 9), (40, 2), (40, 4), (41, 1), (41, 3)]);
}

/// A key beyond the span a consistent heuristic can push is lowered to its
/// bound: popped in its turn there, not lost.
#[test]
fn dial_lowers_a_key_beyond_its_span() {
    use robovac::search::open_list::dial::SPREAD;
    let mut q: OpenList<8> = OpenList::new();
    q.clear_for(Order::Monotone);
    q.push(entry(100, 1)).unwrap();
    q.push(entry(100 + SPREAD + 5_000, 2)).unwrap();
    q.push(entry(100 + SPREAD - 1, 3)).unwrap();
    let order: Vec<(u32, u32)> = std::iter::from_fn(|| q.pop().map(|e| (e.f, e.idx))).collect();
    assert_eq!(order, [(100, 1), (100 + SPREAD - 1, 3), (100 + SPREAD, 2)]);
}

/// A key below the last popped (which a consistent heuristic never
/// gives) is raised to it: popped next, not lost.
#[test]
fn dial_raises_a_falling_key() {
    let mut q: OpenList<8> = OpenList::new();
    q.clear_for(Order::Monotone);
    q.push(entry(100, 1)).unwrap();
    q.push(entry(500, 2)).unwrap();
    assert_eq!(q.pop().map(|e| e.f), Some(100));
    q.push(entry(3, 3)).unwrap();
    assert_eq!(q.pop().map(|e| (e.f, e.idx)), Some((100, 3)));
    assert_eq!(q.pop().map(|e| (e.f, e.idx)), Some((500, 2)));
    assert_eq!(q.pop(), None);
}

/// The dial has the heap's capacity: full at `CAP` entries, and a
/// popped slot is used again.
#[test]
fn dial_capacity_and_reuse() {
    let mut q: OpenList<4> = OpenList::new();
    q.clear_for(Order::Monotone);
    for k in 0..4 {
        q.push(entry(k * 10, k)).unwrap();
    }
    assert_eq!(q.push(entry(99, 9)), Err(Full));
    assert_eq!(q.pop().map(|e| e.idx), Some(0));
    q.push(entry(99, 9)).unwrap();
    assert_eq!(q.peak(), 4);
    let idx: Vec<u32> = std::iter::from_fn(|| q.pop().map(|e| e.idx)).collect();
    assert_eq!(idx, [1, 2, 3, 9]);
    // A clear gives every slot back and the heap order again.
    q.clear();
    for k in (0..4).rev() {
        q.push(Entry { f: 5, g: k, idx: k }).unwrap();
    }
    assert_eq!(
        q.pop().map(|e| e.g),
        Some(3),
        "the heap keeps g and its order"
    );
}

/// The row divider equals integer division for every width, at indices
/// around every multiple of the width near the ends of its range, and
/// exhaustively for small widths.
#[test]
fn row_divider_is_exact() {
    for w in 1u32..=65_535 {
        let d = RowDivider::new(w as u16);
        let top = (EXACT_BELOW as u32 - 1) / w * w;
        for base in [0, w, 2 * w, top.saturating_sub(w), top] {
            for i in [base.saturating_sub(1), base, base + 1, base + w - 1] {
                if (i as usize) < EXACT_BELOW {
                    assert_eq!(d.div(i), i / w, "{i} / {w}");
                }
            }
        }
    }
    for w in 1u32..=70 {
        let d = RowDivider::new(w as u16);
        for i in 0..(1 << 16) {
            assert_eq!(d.div(i), i / w, "{i} / {w}");
        }
    }
    assert_eq!(RowDivider::new(0).div(12), 12, "width 0 is taken as 1");
}

proptest! {
    /// The 3 × 3 read of the free neighbours equals eight plain reads, on
    /// the map's edges and corners too, for maps down to one cell wide.
    #[test]
    fn free_neighbours_match_plain_reads(seed in any::<u64>(), w in 1u32..40, h in 1u32..40, density in 0u32..60) {
        let g = random_grid(w, h, density, seed);
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                let mut want = 0u32;
                for (k, (dx, dy)) in NEIGHBOURS.iter().enumerate() {
                    if free(&g, x + dx, y + dy) {
                        want |= 1 << k;
                    }
                }
                prop_assert_eq!(g.free_neighbours(x, y), want, "({}, {})", x, y);
            }
        }
    }
}

proptest! {
    /// The ring read of any bit raster (the search's closed cells) equals
    /// eight plain reads wherever all eight neighbours lie on the raster,
    /// and the close's test-and-set reports the bit as it was.
    #[test]
    fn ring_and_test_and_set_match_plain_reads(bits in proptest::collection::vec(any::<bool>(), 0..600), w in 1usize..40) {
        let mut b: Bits<{ 640 / 32 }> = Bits::new();
        for (i, &v) in bits.iter().enumerate() {
            b.put(i, v);
        }
        let h = bits.len() / w;
        for y in 1..h.saturating_sub(1) {
            for x in 1..w.saturating_sub(1) {
                let i = y * w + x;
                let mut want = 0u32;
                for (k, (dx, dy)) in NEIGHBOURS.iter().enumerate() {
                    let j = (i as i64 + *dy as i64 * w as i64 + *dx as i64) as usize;
                    if bits[j] {
                        want |= 1 << k;
                    }
                }
                prop_assert_eq!(b.ring(i, w, false), want, "({}, {})", x, y);
            }
        }
        for (i, &v) in bits.iter().enumerate() {
            prop_assert_eq!(b.test_and_set(i), v);
            prop_assert!(b.get(i));
        }
        prop_assert!(b.test_and_set(640 + 5), "beyond the capacity reads as set");
    }
}

proptest! {
    /// Jump point search's 32-bit window read equals 32 plain reads from
    /// any start, below 0 and beyond the capacity included (both read 0).
    #[test]
    fn window_matches_plain_reads(bits in proptest::collection::vec(any::<bool>(), 0..640), at in -40isize..680) {
        let mut b: Bits<{ 640 / 32 }> = Bits::new();
        for (i, &v) in bits.iter().enumerate() {
            b.put(i, v);
        }
        let mut want = 0u32;
        for j in 0..32isize {
            let i = at + j;
            if i >= 0 && b.get(i as usize) {
                want |= 1 << j;
            }
        }
        prop_assert_eq!(b.window(at), want);
    }
}
