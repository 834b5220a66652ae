//! The path follower: sub-path merging, rotate-then-drive, convergence.

use robovac::nav::follow::{follow, track_errors, FollowCmd, SubPath, SubPaths, DEFAULT_FOLLOW};
use robovac::robot::odometry::Pose;

#[test]
fn waypoints_merge_into_straight_sub_paths() {
    let mut q: SubPaths<8> = SubPaths::new();
    q.reset((0, 0));
    // east ×3, north ×2, a transit diagonal, east
    for (p, c) in [
        ((300, 0), true),
        ((600, 0), true),
        ((900, 0), true),
        ((900, 300), true),
        ((900, 600), true),
        ((1500, 1200), false),
        ((1800, 1200), true),
    ] {
        assert!(q.push(p, c));
    }
    // The first sub-path is being driven and is never extended; later ones merge.
    let mut got = Vec::new();
    while let Some((s, c)) = q.front() {
        got.push((s.from, s.to, c));
        q.pop();
    }
    assert_eq!(
        got,
        vec![
            ((0, 0), (300, 0), true),
            ((300, 0), (900, 0), true),
            ((900, 0), (900, 600), true),
            ((900, 600), (1500, 1200), false),
            ((1500, 1200), (1800, 1200), true)
        ]
    );
    let mut full: SubPaths<2> = SubPaths::new();
    full.reset((0, 0));
    assert!(full.push((0, 100), true) && full.push((100, 100), true));
    assert!(!full.push((100, 0), true), "a full queue refuses");
}

#[test]
fn errors_and_commands() {
    let seg = SubPath {
        from: (0, 0),
        to: (1000, 0),
    };
    assert_eq!(track_errors(&seg, 200, 50), (50, 800));
    let at = |x_mm, y_mm, theta_mrad| {
        follow(
            &DEFAULT_FOLLOW,
            &seg,
            &Pose {
                x_mm,
                y_mm,
                theta_mrad,
            },
        )
    };
    // Facing away: turn in place first.
    match at(0, 0, 3000) {
        FollowCmd::Drive { v_mm_s, w_mrad_s } => assert!(v_mm_s == 0 && w_mrad_s != 0),
        c => panic!("{c:?}"),
    }
    // On the line, facing along: drive straight at cruise speed.
    assert_eq!(
        at(100, 0, 0),
        FollowCmd::Drive {
            v_mm_s: 300,
            w_mrad_s: 0
        }
    );
    // Left of the line: steer right (negative ω) while driving.
    match at(100, 60, 0) {
        FollowCmd::Drive { v_mm_s, w_mrad_s } => assert!(v_mm_s > 0 && w_mrad_s < 0),
        c => panic!("{c:?}"),
    }
    assert_eq!(at(990, 5, 0), FollowCmd::Arrived);
}

/// An ideal unicycle following a zig-zag converges onto each line and
/// arrives at every corner.
#[test]
fn ideal_robot_follows_a_path() {
    let pts = [
        (0, 0),
        (2000, 0),
        (2000, 300),
        (0, 300),
        (0, 600),
        (1500, 1500),
    ];
    let (mut x, mut y, mut th) = (0.0f64, -80.0f64, 0.3f64);
    let mut max_cross: f64 = 0.0;
    for w in pts.windows(2) {
        let seg = SubPath {
            from: w[0],
            to: w[1],
        };
        let mut arrived = false;
        for _ in 0..3000 {
            let pose = Pose {
                x_mm: x as i32,
                y_mm: y as i32,
                theta_mrad: (th * 1000.0) as i32,
            };
            match follow(&DEFAULT_FOLLOW, &seg, &pose) {
                FollowCmd::Arrived => {
                    arrived = true;
                    break;
                }
                FollowCmd::Drive { v_mm_s, w_mrad_s } => {
                    th += w_mrad_s as f64 / 1000.0 * 0.01;
                    x += v_mm_s as f64 * 0.01 * th.cos();
                    y += v_mm_s as f64 * 0.01 * th.sin();
                    let (c, rem) = track_errors(&seg, x as i32, y as i32);
                    if rem < ((w[1].0 - w[0].0) as f64).hypot((w[1].1 - w[0].1) as f64) as i64 - 300
                    {
                        max_cross = max_cross.max(c.abs() as f64);
                    }
                }
            }
        }
        assert!(arrived, "did not reach {:?}", w[1]);
    }
    assert!(
        max_cross < 40.0,
        "cross-track {max_cross} mm after settling"
    );
}
