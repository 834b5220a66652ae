//! The potential field as a local planner (`nav::apf`): it drives a clear
//! way straight, steers around a post, and reports the local minima of a
//! wall square across the way and of a pocket instead of hiding them.
//! The closed-loop checks drive a unicycle in f64 (an independent model,
//! not the core's) and measure clearance on the true geometry.

use proptest::prelude::*;
use robovac::nav::apf::{force, plan, ApfResult, DEFAULT_APF};

/// Points every 20 mm from `a` to `b` (world mm).
fn wall(a: (f64, f64), b: (f64, f64)) -> Vec<(f64, f64)> {
    let n = ((b.0 - a.0).hypot(b.1 - a.1) / 20.0).ceil() as usize;
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        })
        .collect()
}

/// How a closed-loop drive ended.
#[derive(Debug, PartialEq)]
enum End {
    Goal,
    Minimum { at: (f64, f64) },
    Timeout,
}

/// Drives from the origin (heading +x) toward `goal` among `points` for
/// at most `secs`, 10 Hz, with the field's command; returns how it ended
/// and the least clearance of the 165 mm body to any point.
fn drive(goal: (f64, f64), points: &[(f64, f64)], secs: f64) -> (End, f64) {
    let (mut x, mut y, mut th) = (0.0f64, 0.0f64, 0.0f64);
    let mut clear = f64::INFINITY;
    for _ in 0..(secs * 10.0) as usize {
        let to_robot = |p: (f64, f64)| {
            let (dx, dy) = (p.0 - x, p.1 - y);
            let (s, c) = th.sin_cos();
            ((c * dx + s * dy) as i32, (-s * dx + c * dy) as i32)
        };
        let obs: Vec<(i32, i32)> = points.iter().map(|&p| to_robot(p)).collect();
        if (goal.0 - x).hypot(goal.1 - y) < 100.0 {
            return (End::Goal, clear);
        }
        match plan(&DEFAULT_APF, to_robot(goal), &obs) {
            ApfResult::LocalMinimum { .. } => return (End::Minimum { at: (x, y) }, clear),
            ApfResult::Command {
                v_mm_s, w_mrad_s, ..
            } => {
                th += w_mrad_s as f64 / 1000.0 * 0.1;
                x += v_mm_s as f64 * 0.1 * th.cos();
                y += v_mm_s as f64 * 0.1 * th.sin();
            }
        }
        for p in points {
            clear = clear.min((p.0 - x).hypot(p.1 - y) - 165.0);
        }
    }
    (End::Timeout, clear)
}

#[test]
fn clear_way_is_driven_straight_at_full_speed() {
    let r = plan(&DEFAULT_APF, (2000, 0), &[]);
    assert_eq!(
        r,
        ApfResult::Command {
            v_mm_s: 300,
            w_mrad_s: 0,
            force_pm: 1000
        }
    );
    // A goal to the left: turn in place toward it first.
    let ApfResult::Command {
        v_mm_s, w_mrad_s, ..
    } = plan(&DEFAULT_APF, (0, 2000), &[])
    else {
        panic!("a clear way is no minimum");
    };
    assert_eq!(v_mm_s, 0);
    assert_eq!(w_mrad_s, DEFAULT_APF.w_max_mrad_s);
}

#[test]
fn a_wall_ahead_pushes_back_and_sideways_obstacles_push_aside() {
    let ahead: Vec<(i32, i32)> = (-5..=5).map(|i| (300, i * 20)).collect();
    let (fx, _) = force(&DEFAULT_APF, (2000, 0), &ahead);
    assert!(fx < 1000, "a wall ahead must take from the pull: {fx}");
    let left: Vec<(i32, i32)> = (-5..=5).map(|i| (i * 20, 300)).collect();
    let (_, fy) = force(&DEFAULT_APF, (2000, 0), &left);
    assert!(fy < 0, "a wall on the left pushes right: {fy}");
}

#[test]
fn steers_round_a_post_to_the_goal_without_touching_it() {
    let post: Vec<(f64, f64)> = (0..16)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 16.0;
            (1000.0 + 60.0 * a.cos(), 120.0 + 60.0 * a.sin())
        })
        .collect();
    let (end, clear) = drive((2500.0, 0.0), &post, 60.0);
    assert_eq!(end, End::Goal);
    assert!(clear > 0.0, "touched the post: clearance {clear:.0} mm");
}

#[test]
fn a_wall_square_across_the_way_is_reported_as_a_local_minimum() {
    let w = wall((800.0, -1000.0), (800.0, 1000.0));
    let (end, clear) = drive((2000.0, 0.0), &w, 60.0);
    let End::Minimum { at } = end else {
        panic!("expected a local minimum, got {end:?}");
    };
    assert!(
        clear > 0.0,
        "touched the wall before stopping: {clear:.0} mm"
    );
    assert!(at.0 < 800.0 - 165.0 && at.1.abs() < 50.0, "held at {at:?}");
}

#[test]
fn a_pocket_is_reported_as_a_local_minimum() {
    // A U open toward the robot, the goal behind its bottom.
    let mut u = wall((1000.0, -450.0), (1000.0, 450.0));
    u.extend(wall((300.0, 450.0), (1000.0, 450.0)));
    u.extend(wall((300.0, -450.0), (1000.0, -450.0)));
    let (end, clear) = drive((2500.0, 0.0), &u, 120.0);
    assert!(matches!(end, End::Minimum { .. }), "got {end:?}");
    assert!(clear > 0.0, "touched the pocket: {clear:.0} mm");
}

proptest! {
    /// Any goal and any points (the whole i32 range): no panic, and the
    /// command within the limits.
    #[test]
    fn commands_stay_within_limits(
        goal in (any::<i32>(), any::<i32>()),
        pts in proptest::collection::vec((any::<i32>(), any::<i32>()), 0..64),
        near in proptest::collection::vec((-600i32..600, -600i32..600), 0..64),
    ) {
        let pts: Vec<(i32, i32)> = pts.into_iter().chain(near).collect();
        if let ApfResult::Command { v_mm_s, w_mrad_s, force_pm } = plan(&DEFAULT_APF, goal, &pts) {
            prop_assert!((0..=DEFAULT_APF.v_max_mm_s).contains(&v_mm_s));
            prop_assert!(w_mrad_s.abs() <= DEFAULT_APF.w_max_mrad_s);
            prop_assert!(force_pm >= 0);
        }
    }
}
