//! The edge pass's chords: a staircase along a slanted wall becomes a few
//! straight sub-paths that stay within the tolerance of every cell, a
//! line that is not clear is never taken, and a full chord is cut.

use robovac::nav::chord::{Chord, CHORD_CELLS};

/// Drives `pts` through a chord from `start`; the waypoints, the last one
/// flushed.
fn chords(
    start: (i32, i32),
    pts: &[(i32, i32)],
    tol: i64,
    clear: impl Fn((i32, i32), (i32, i32)) -> bool + Copy,
) -> Vec<(i32, i32)> {
    let mut c = Chord::new();
    c.reset(start);
    let mut out: Vec<_> = pts
        .iter()
        .filter_map(|&p| c.offer(p, tol, clear, clear))
        .collect();
    while let Some(w) = c.cut(clear) {
        out.push(w);
    }
    out
}

/// Distance of q from segment a–b, mm.
fn seg_dist(a: (i32, i32), b: (i32, i32), q: (i32, i32)) -> f64 {
    let (ax, ay, bx, by, qx, qy) = (
        a.0 as f64, a.1 as f64, b.0 as f64, b.1 as f64, q.0 as f64, q.1 as f64,
    );
    let (ux, uy) = (bx - ax, by - ay);
    let l2 = ux * ux + uy * uy;
    let t = if l2 == 0.0 {
        0.0
    } else {
        (((qx - ax) * ux + (qy - ay) * uy) / l2).clamp(0.0, 1.0)
    };
    (qx - ax - t * ux).hypot(qy - ay - t * uy)
}

#[test]
fn a_staircase_becomes_a_few_chords_within_the_tolerance() {
    // A wall at about 27°, as the edge pass walks it (8-connected 5 cm
    // cells): east, north-east, repeated.
    let mut pts = Vec::new();
    let (mut x, mut y) = (0, 0);
    for k in 0..30 {
        x += 50;
        y += 50 * (k % 2);
        pts.push((x, y));
    }
    let out = chords((0, 0), &pts, 40, |_, _| true);
    assert!(out.len() <= 3, "{out:?}");
    assert_eq!(*out.last().unwrap(), *pts.last().unwrap());
    // Every contour cell lies within 40 mm of the chord that passes it.
    let mut from = (0, 0);
    let mut i = 0;
    for &w in &out {
        while i < pts.len() && pts[i] != w {
            assert!(
                seg_dist(from, w, pts[i]) <= 40.0,
                "{:?} off {from:?}-{w:?}",
                pts[i]
            );
            i += 1;
        }
        i += 1;
        from = w;
    }
}

#[test]
fn a_line_that_is_not_clear_is_never_taken() {
    // Around a corner: east, then north; the diagonal cuts the corner.
    let pts: Vec<_> = (1..=5)
        .map(|k| (k * 50, 0))
        .chain((1..=5).map(|k| (250, k * 50)))
        .collect();
    let no_diagonal = |a: (i32, i32), b: (i32, i32)| a.0 == b.0 || a.1 == b.1;
    let out = chords((0, 0), &pts, 1000, no_diagonal);
    assert_eq!(out, vec![(250, 0), (250, 250)]);
}

#[test]
fn a_full_chord_is_cut() {
    let pts: Vec<_> = (1..=(3 * CHORD_CELLS as i32))
        .map(|k| (k * 50, 0))
        .collect();
    let out = chords((0, 0), &pts, 40, |_, _| true);
    assert_eq!(out.len(), 3, "{out:?}");
    assert_eq!(out[0], (CHORD_CELLS as i32 * 50, 0));
}

#[test]
fn an_empty_chord_flushes_nothing() {
    let mut c = Chord::new();
    c.reset((10, 10));
    assert_eq!(c.cut(|_, _| true), None);
}

#[test]
fn a_chord_the_body_cannot_sweep_is_cut_to_single_steps() {
    // The cells fit the cheap check, but the body's sweep refuses every
    // line longer than one step: the pass's own steps come out.
    let pts: Vec<_> = (1..=6).map(|k| (k * 50, 0)).collect();
    let mut c = Chord::new();
    c.reset((0, 0));
    let short = |a: (i32, i32), b: (i32, i32)| (a.0 - b.0).abs() <= 50;
    let mut out: Vec<_> = pts
        .iter()
        .filter_map(|&p| c.offer(p, 40, |_, _| true, short))
        .collect();
    while let Some(w) = c.cut(short) {
        out.push(w);
    }
    assert_eq!(out, pts);
}
