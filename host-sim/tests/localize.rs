//! The scan matcher on twin scans: a scan taken at a true pose, matched
//! from a wrong guess, must come back to the truth. Checked against the
//! twin's true pose, with random poses and errors (property tests).

use host_sim::run::suite::suite_map;
use host_sim::sim::scan::{fill_prior, twin_scan};
use host_sim::sim::world::World;
use proptest::prelude::*;
use robovac::grid::maps::SplitMix64;
use robovac::localize::{fusion, Fusion, PoseU, ScanMatcher};
use robovac::robot::lidar_map::EvidenceMap;

const EV: usize = robovac::robot::lidar_map::evidence_bytes(400 * 400);
const MW: usize = robovac::localize::matcher_words(400, 400);

struct Bench {
    world: World,
    map: Box<EvidenceMap<EV>>,
    m: Box<ScanMatcher<MW>>,
}

fn bench(name: &str) -> Bench {
    bench_of(World::new(suite_map(name).unwrap(), 0.1))
}

/// `world`'s walls as a frozen prior at 5 cm, and a matcher built on it.
fn bench_of(world: World) -> Bench {
    let mut map = Box::new(EvidenceMap::<EV>::new());
    fill_prior(&mut map, &world, 50, true).unwrap();
    map.freeze_prior();
    let mut m = Box::new(ScanMatcher::<MW>::new());
    assert!(m.pyramid.build(&map, true));
    Bench { world, map, m }
}

/// A `w` × `h` world of 10 cm cells, blocked where `wall(row, column)`.
fn drawn_world(w: u32, h: u32, wall: impl Fn(u32, u32) -> bool) -> World {
    let blocked = (0..h)
        .flat_map(|r| (0..w).map(move |c| (r, c)))
        .map(|(r, c)| wall(r, c))
        .collect();
    let map = host_sim::io::maps::MapData {
        width: w,
        height: h,
        blocked,
        cell_m: Some(0.1),
        ..Default::default()
    };
    World::new(map, 0.1)
}

/// A free true pose drawn from the seed and the twin's scan there (450
/// returns, realistic range noise and dropouts), robot frame.
fn random_scan(w: &World, rng: &mut SplitMix64) -> ((f64, f64, f64), Vec<(i32, i32)>) {
    let t = true_pose(w, rng);
    (t, twin_scan(w, t, 450, 0.01, 0.02, 0.0, rng))
}

/// A free true pose drawn from the seed (clear of walls by 0.3 m).
fn true_pose(w: &World, rng: &mut SplitMix64) -> (f64, f64, f64) {
    let (wm, hm) = w.size_m();
    loop {
        let x = 0.3 + (rng.next_u64() % 10_000) as f64 / 10_000.0 * (wm - 0.6);
        let y = 0.3 + (rng.next_u64() % 10_000) as f64 / 10_000.0 * (hm - 0.6);
        if !w.disc_hits_wall(x, y, 0.3) {
            let th = (rng.next_u64() % 6283) as f64 / 1000.0 - std::f64::consts::PI;
            return (x, y, th);
        }
    }
}

fn guess(t: (f64, f64, f64), dx_mm: i32, dy_mm: i32, dt_urad: i64) -> PoseU {
    PoseU {
        x_mm: (t.0 * 1000.0).round() as i32 + dx_mm,
        y_mm: (t.1 * 1000.0).round() as i32 + dy_mm,
        theta_urad: (t.2 * 1e6).round() as i64 + dt_urad,
    }
}

/// (position error mm, heading error µrad) of `p` against the truth.
fn error(p: PoseU, t: (f64, f64, f64)) -> (f64, i64) {
    let d = (p.x_mm as f64 - t.0 * 1000.0).hypot(p.y_mm as f64 - t.1 * 1000.0);
    let dt = fusion_wrap(p.theta_urad - (t.2 * 1e6).round() as i64);
    (d, dt.abs())
}

fn fusion_wrap(t: i64) -> i64 {
    robovac::localize::correlative::wrap_urad(t)
}

fn relocalise_case(name: &str, seed: u64, err: (i32, i32, i64)) -> (f64, i64) {
    let mut b = bench(name);
    let mut rng = SplitMix64::new(seed);
    let (t, pts) = random_scan(&b.world, &mut rng);
    b.m.points.set(guess(t, err.0, err.1, err.2), &pts);
    let mut f = Fusion::new();
    let p = f
        .relocalise(&b.m, &b.map, true, false)
        .unwrap_or_else(|e| panic!("{name} seed {seed}: {e:?}"));
    error(p, t)
}

#[test]
fn window_relocalisation_recovers_150mm_and_10deg() {
    for (i, map) in ["studio", "home", "office"].iter().enumerate() {
        let (d, dt) = relocalise_case(map, 40 + i as u64, (150, -150, 174_533));
        assert!(d <= 10.0 && dt <= 8_727, "{map}: {d:.1} mm, {dt} µrad");
    }
}

#[test]
fn tracking_corrects_a_small_error() {
    let mut b = bench("home");
    let mut rng = SplitMix64::new(7);
    for _ in 0..20 {
        let (t, pts) = random_scan(&b.world, &mut rng);
        b.m.points.set(guess(t, 30, -25, 20_000), &pts);
        let (mt, _) = fusion::track(&b.m, &b.map, true).unwrap();
        let (d, dt) = error(mt.pose, t);
        assert!(d <= 10.0 && dt <= 8_727, "{t:?}: {d:.1} mm {dt} µrad");
    }
}

/// `g` moved by a correction the fusion returned.
fn corrected(g: PoseU, (dx, dy, dt): (i32, i32, i64)) -> PoseU {
    PoseU {
        x_mm: g.x_mm + dx,
        y_mm: g.y_mm + dy,
        theta_urad: g.theta_urad + dt,
    }
}

/// A correction is applied at most `STEP_MM` per revolution (a match
/// pulled by a person moves the pose that much at most before the next
/// one disagrees), yet an error beyond it is worked off within a few
/// revolutions: each applied step is toward the truth, and the rest is
/// measured again.
#[test]
fn a_large_correction_glides_in_steps() {
    let mut b = bench("home");
    let mut rng = SplitMix64::new(11);
    for _ in 0..10 {
        let (t, pts) = random_scan(&b.world, &mut rng);
        let mut g = guess(t, fusion::STEP_MM + 20, -fusion::STEP_MM - 20, 0);
        let mut f = Fusion::new();
        for rev in 0..4 {
            b.m.points.set(g, &pts);
            let (dx, dy, dt) = f.track(&b.m, &b.map, true, false, true).unwrap();
            assert!(dx.abs() <= fusion::STEP_MM && dy.abs() <= fusion::STEP_MM);
            g = corrected(g, (dx, dy, dt));
            if rev == 0 {
                assert_eq!((dx, dy), (-fusion::STEP_MM, fusion::STEP_MM), "{t:?}");
            }
        }
        let (d, _) = error(g, t);
        assert!(d <= 10.0, "{t:?}: {d:.1} mm after 4 revolutions");
    }
}

/// A pose turned 12° (a slip burst on a harsh floor) is beyond the
/// narrow heading search; the poor fit makes the next revolution search
/// wide, and the pose glides back to the truth. Meanwhile the pose is in
/// doubt and the revolutions are not to be mapped; once settled, they are.
#[test]
fn a_turned_pose_is_found_by_the_wide_search_and_not_mapped_meanwhile() {
    let mut b = bench("home");
    let mut rng = SplitMix64::new(13);
    for _ in 0..10 {
        let (t, pts) = random_scan(&b.world, &mut rng);
        let mut g = guess(t, 30, -25, -209_440);
        let mut f = Fusion::new();
        let mut doubtful = 0;
        for _ in 0..12 {
            b.m.points.set(g, &pts);
            if let Ok(c) = f.track(&b.m, &b.map, true, false, true) {
                g = corrected(g, c);
            }
            doubtful += usize::from(!f.mappable());
        }
        let (d, dt) = error(g, t);
        assert!(d <= 10.0 && dt <= 8_727, "{t:?}: {d:.1} mm {dt} µrad");
        assert!(f.mappable(), "{t:?}: settled but still in doubt");
        // 12° in steps of at most 5° (SURE_STEP_URAD): at least 2
        // revolutions in doubt.
        assert!(doubtful >= 2, "{t:?}: only {doubtful} revolutions in doubt");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Random true poses on the three flats, random errors up to ±150 mm
    /// and ±10°: recovered within 10 mm and 0.5°.
    #[test]
    fn relocalisation_property(seed in 0u64..10_000, m in 0usize..3,
                               dx in -150i32..=150, dy in -150i32..=150,
                               dt in -174_533i64..=174_533) {
        let map = ["studio", "home", "office"][m];
        let (d, e) = relocalise_case(map, seed, (dx, dy, dt));
        prop_assert!(d <= 10.0 && e <= 8_727, "{map} seed {seed}: {d:.1} mm {e} µrad");
    }
}

/// The three flats in turn, `n` cases numbered from 0.
fn flats(n: usize) -> impl Iterator<Item = (usize, &'static str)> {
    ["studio", "home", "office"]
        .into_iter()
        .cycle()
        .take(n)
        .enumerate()
}

/// A kidnap: the scan matched over the whole map from no guess at all.
#[test]
fn global_relocalisation_finds_the_robot() {
    let mut ok = 0;
    for (i, map) in flats(12) {
        let mut b = bench(map);
        let mut rng = SplitMix64::new(100 + i as u64);
        let (t, pts) = random_scan(&b.world, &mut rng);
        b.m.points.set(PoseU::default(), &pts);
        let mut f = Fusion::new();
        match f.relocalise(&b.m, &b.map, true, true) {
            Ok(p) => {
                let (d, dt) = error(p, t);
                // Success must be right; ambiguity may refuse.
                assert!(d <= 10.0 && dt <= 8_727, "{map} {i}: {d:.1} mm {dt} µrad");
                ok += 1;
            }
            Err(e) => eprintln!("{map} {i}: refused ({e:?})"),
        }
    }
    assert!(ok >= 10, "only {ok} of 12 relocalised");
}

/// A false alarm: people in front of the walls hide most of them, so the
/// revolution fits poorly where the robot truly is; the search over the
/// whole map must not move it elsewhere (it once moved a studio mission
/// 2–4 m, 41 times). And a true kidnap from another free place of the same
/// home still relocalises to the truth.
#[test]
fn a_hidden_wall_is_not_a_kidnap_and_a_kidnap_still_relocalises() {
    let (mut kept, mut found) = (0, 0);
    for (i, map) in flats(9) {
        let mut b = bench(map);
        let mut rng = SplitMix64::new(500 + i as u64);
        let (t, pts) = random_scan(&b.world, &mut rng);
        b.m.points.set(guess(t, 0, 0, 0), &hidden(&pts));
        if let Ok(p) = Fusion::new().relocalise(&b.m, &b.map, true, true) {
            let (d, dt) = error(p, t);
            assert!(
                d <= 15.0 && dt <= 8_727,
                "{map} {i}: moved {d:.1} mm {dt} µrad"
            );
            kept += 1;
        }
        // Kidnapped: the odometry believes another free place.
        let (t2, pts2) = random_scan(&b.world, &mut rng);
        b.m.points.set(guess(t, 0, 0, 0), &pts2);
        match Fusion::new().relocalise(&b.m, &b.map, true, true) {
            Ok(p) => {
                let (d, dt) = error(p, t2);
                assert!(
                    d <= 10.0 && dt <= 8_727,
                    "{map} {i}: kidnap {d:.1} mm {dt} µrad"
                );
                found += 1;
            }
            Err(e) => eprintln!("{map} {i}: kidnap refused ({e:?})"),
        }
    }
    eprintln!("false alarms kept {kept} of 9, kidnaps found {found} of 9");
    assert!(kept >= 8, "only {kept} of 9 false alarms kept the pose");
    assert!(found >= 7, "only {found} of 9 kidnaps relocalised");
}

/// `pts` with three returns in five moved onto people 0.4–0.8 m away.
fn hidden(pts: &[(i32, i32)]) -> Vec<(i32, i32)> {
    let mut out = pts.to_vec();
    for (k, p) in out.iter_mut().enumerate().filter(|(k, _)| k % 5 < 3) {
        let a = f64::from(p.1).atan2(f64::from(p.0));
        let r = 400.0 + (k % 5) as f64 * 100.0;
        *p = ((r * a.cos()) as i32, (r * a.sin()) as i32);
    }
    out
}

/// `n` revolutions of `scan` tracked from `at`.
fn revs(b: &mut Bench, f: &mut Fusion, at: PoseU, scan: &[(i32, i32)], n: usize) {
    for _ in 0..n {
        b.m.points.set(at, scan);
        let _ = f.track(&b.m, &b.map, true, false, true);
    }
}

/// A robot whose walls stay hidden where its pose is right (dark furniture
/// and glass about it) is kept where it is each time the whole map agrees,
/// and its poor fits stop raising the alarm until a good fit, or until
/// `KEEP_AGAIN_AFTER` revolutions pass: the S8 home on harsh floors once
/// stood braked there until `Failed(Lost)`.
#[test]
fn a_robot_hemmed_in_where_it_is_right_is_kept_and_not_braked_again() {
    let lost_after = fusion::LOST_AFTER as usize;
    let mut ok = 0;
    for (i, map) in flats(9) {
        let mut b = bench(map);
        let mut rng = SplitMix64::new(700 + i as u64);
        let (t, pts) = random_scan(&b.world, &mut rng);
        let (dim, at) = (hidden(&pts), guess(t, 0, 0, 0));
        let mut f = Fusion::new();
        revs(&mut b, &mut f, at, &pts, 1);
        revs(&mut b, &mut f, at, &dim, lost_after);
        let mut good = f.lost;
        for _ in 0..2 {
            b.m.points.set(at, &dim);
            let kept = f.relocalise(&b.m, &b.map, true, true);
            good &= kept.is_ok_and(|p| error(p, t).0 <= 15.0) && !f.lost;
            revs(&mut b, &mut f, at, &dim, 50);
            good &= !f.lost;
            // A good fit ends the quiet; hidden again, the alarm returns.
            revs(&mut b, &mut f, at, &pts, 1);
            revs(&mut b, &mut f, at, &dim, lost_after);
            good &= f.lost;
        }
        // Quiet for no longer than KEEP_AGAIN_AFTER revolutions.
        b.m.points.set(at, &dim);
        good &= f.relocalise(&b.m, &b.map, true, true).is_ok();
        let quiet = fusion::KEEP_AGAIN_AFTER as usize + 1;
        revs(&mut b, &mut f, at, &dim, quiet);
        if good && f.lost {
            ok += 1;
        } else {
            eprintln!("{map} {i}: not kept each time, or quiet for good");
        }
    }
    assert!(ok >= 8, "only {ok} of 9 hemmed-in robots kept and re-armed");
}

/// A scan that fits another place better, but not as a kidnap's place
/// does: three returns in five from another free place `other` (robot
/// frame), the rest from the truth. Glass and dark furniture left the
/// S8 home's true pose fitting 29 % of its scan (known mode, harsh,
/// seed 4, 689 s) and a place 9.3 m away fitting 50 %, and the robot was
/// moved there.
fn mixed(truth: &[(i32, i32)], other: &[(i32, i32)]) -> Vec<(i32, i32)> {
    let pick = |k: usize| if k % 5 < 3 { other[k] } else { truth[k] };
    (0..truth.len().min(other.len())).map(pick).collect()
}

/// Whole-map relocalisation of an ambiguous scan never moves the robot
/// elsewhere: kept or refused, its pose stays within 15 mm of the truth.
#[test]
fn an_ambiguous_scan_does_not_move_the_robot_elsewhere() {
    let mut moved = Vec::new();
    for (i, map) in flats(12) {
        let mut b = bench(map);
        let mut rng = SplitMix64::new(900 + i as u64);
        let (t, pts) = random_scan(&b.world, &mut rng);
        let (_, other) = random_scan(&b.world, &mut rng);
        b.m.points.set(guess(t, 0, 0, 0), &mixed(&pts, &other));
        let mut f = Fusion::new();
        let r = f.relocalise(&b.m, &b.map, true, true);
        eprintln!("{map} {i}: fits {:?} % {r:?}", f.stats.last_reloc_pct);
        if let Ok(p) = r {
            let (d, _) = error(p, t);
            if d > 15.0 {
                moved.push((map, i, d as i32, f.stats.last_reloc_pct));
            }
        }
    }
    assert!(moved.is_empty(), "moved elsewhere: {moved:?}");
}

/// People (unmapped points) do not pull the pose: a scan with a third of
/// its points on a crowd in the room still matches the truth.
#[test]
fn unmapped_points_do_not_pull() {
    let mut b = bench("home");
    let mut rng = SplitMix64::new(3);
    let mut worst = 0.0f64;
    for _ in 0..10 {
        let (t, mut pts) = random_scan(&b.world, &mut rng);
        // Replace every third return by a point 0.6–1.0 m away (a person).
        for (i, p) in pts.iter_mut().enumerate().filter(|(i, _)| i % 3 == 0) {
            let a = f64::from(p.1).atan2(f64::from(p.0));
            let r = 600.0 + (i % 5) as f64 * 100.0;
            *p = ((r * a.cos()) as i32, (r * a.sin()) as i32);
        }
        b.m.points.set(guess(t, 20, 20, 10_000), &pts);
        let (mt, _) = fusion::track(&b.m, &b.map, true).unwrap();
        let (d, dt) = error(mt.pose, t);
        worst = worst.max(d);
        assert!(d <= 15.0 && dt <= 8_727, "{d:.1} mm {dt} µrad");
    }
    eprintln!("worst with a crowd: {worst:.1} mm");
}

/// The recorded revolution the emulated Cortex-M4 run matches
/// (`tests/golden/scan_home.txt`, read by `examples/emu_localize.rs`): one
/// revolution of the twin's lidar in the home flat at a known true pose.
/// This test regenerates it and checks the file is the twin's; set
/// `ROBOVAC_RECORD=1` to write it.
#[test]
fn recorded_revolution_is_the_twins() {
    let world = World::new(suite_map("home").unwrap(), 0.1);
    let mut rng = SplitMix64::new(2026);
    let truth = (4.5, 3.4, 0.5);
    let pts = twin_scan(&world, truth, 450, 0.01, 0.02, 0.0, &mut rng);
    let mut text = format!(
        "# one twin revolution in maps/flat/home.txt: true pose x_mm y_mm theta_urad, then points (robot frame, mm)\n{} {} {}\n",
        4500, 3400, 500_000
    );
    for (x, y) in &pts {
        text.push_str(&format!("{x} {y}\n"));
    }
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/golden/scan_home.txt");
    if std::env::var_os("ROBOVAC_RECORD").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    // And the host matches it as the target must.
    let mut b = bench("home");
    b.m.points.set(guess(truth, 150, -150, 174_533), &pts);
    let p = Fusion::new().relocalise(&b.m, &b.map, true, false).unwrap();
    let (d, dt) = error(p, truth);
    assert!(d <= 10.0 && dt <= 8_727, "{d:.1} mm {dt} µrad");
}

/// A corridor longer than the lidar's range constrains only the axis
/// across it: the fusion corrects across and leaves the along-axis to the
/// odometry (a partial correction), instead of trusting a match that
/// cannot know where along the corridor the robot is.
#[test]
fn a_long_corridor_corrects_across_only() {
    let (w, h) = (320u32, 12u32);
    let Bench {
        world,
        map: ev,
        mut m,
    } = bench_of(drawn_world(w, h, |r, c| {
        r == 0 || r == h - 1 || c == 0 || c == w - 1
    }));
    let mut rng = SplitMix64::new(5);
    let truth = (16.0, 0.6, 0.0);
    let pts = twin_scan(&world, truth, 450, 0.01, 0.02, 0.0, &mut rng);
    // 12 mm across: within one revolution's step (`STEP_MM`).
    m.points.set(guess(truth, 60, 12, 0), &pts);
    let mut f = Fusion::new();
    let (dx, dy, _) = f.track(&m, &ev, true, false, true).unwrap();
    assert_eq!(f.stats.partial, 1, "{:?}", f.stats);
    assert!(dx.abs() <= 2, "along the corridor: {dx} mm");
    assert!((dy + 12).abs() <= 6, "across: {dy} mm");
}

/// Robot-frame returns of `pts` with a free-standing disc (a person, 150
/// mm radius) put in front of them at `(d_mm, bearing)`; returns the
/// points and which of them the disc gave.
fn with_person(pts: &[(i32, i32)], d_mm: f64, bearing: f64) -> (Vec<(i32, i32)>, Vec<bool>) {
    let (cx, cy, r) = (d_mm * bearing.cos(), d_mm * bearing.sin(), 150.0);
    pts.iter()
        .map(|&(x, y)| {
            let (ux, uy) = {
                let n = f64::from(x).hypot(f64::from(y)).max(1.0);
                (f64::from(x) / n, f64::from(y) / n)
            };
            // Ray–circle: t² − 2t(u·c) + |c|² − r² = 0, nearest root.
            let b = ux * cx + uy * cy;
            let disc = b * b - (cx * cx + cy * cy - r * r);
            let wall = f64::from(x).hypot(f64::from(y));
            match disc >= 0.0 && b - disc.sqrt() > 0.0 && b - disc.sqrt() < wall {
                true => {
                    let t = b - disc.sqrt();
                    (((ux * t).round() as i32, (uy * t).round() as i32), true)
                }
                false => ((x, y), false),
            }
        })
        .unzip()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A person standing free in front of the walls (0.4–2 m away, at
    /// least 0.4 m before the wall behind them, a wall not seen edge-on) loses every return to
    /// `drop_foreground` but one at each edge of their outline, and the walls left still put the match on the
    /// truth from a guess 40 mm and 1° off. Without the person, a room's
    /// walls lose nothing but free-standing furniture.
    #[test]
    fn a_person_standing_free_is_dropped_from_the_match(
        seed in 0u64..10_000, map_i in 0usize..3, d in 400.0f64..2000.0, bearing in -3.1f64..3.1
    ) {
        let map = ["studio", "home", "office"][map_i];
        let mut b = bench(map);
        let mut rng = SplitMix64::new(seed);
        let t = true_pose(&b.world, &mut rng);
        // Every return of the twin: 224 of them, as `load` keeps.
        let walls = twin_scan(&b.world, t, 224, 0.01, 0.0, 0.0, &mut rng);
        let (pts, person) = with_person(&walls, d, bearing);
        // The person stands free: every wall return within three steps
        // of theirs is at least 0.4 m behind their far side.
        let n = walls.len();
        let near_person = |i: usize| (0..7).any(|k| person[(i + n + k - 3) % n]);
        let behind = (0..n).filter(|&i| near_person(i))
            .map(|i| f64::from(walls[i].0).hypot(f64::from(walls[i].1))).fold(f64::MAX, f64::min);
        prop_assume!(n == 224 && person.iter().filter(|&&p| p).count() >= 3 && behind > d + 150.0 + 400.0);
        // ... and the walls beside them are not seen edge-on (within 30°),
        // where `drop_foreground` cannot tell a person from a wall's end.
        let edges = (0..n).filter(|&i| person[i] != person[(i + 1) % n]);
        for i in edges {
            let (wall, step) = if person[i] { ((i + 1) % n, 1) } else { (i, n - 1) };
            let (a, b) = (walls[wall], walls[(wall + step) % n]);
            let (ux, uy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
            let (rx, ry) = (f64::from(a.0), f64::from(a.1));
            let sin = (ux * ry - uy * rx).abs() / (ux.hypot(uy) * rx.hypot(ry)).max(1.0);
            prop_assume!(sin >= 0.5);
        }
        b.m.points.set(guess(t, 30, -25, 17_453), &pts);
        let before = b.m.points.as_slice().to_vec();
        let dropped = b.m.points.drop_foreground() as usize;
        let kept = b.m.points.as_slice();
        // A return at the person's very outline meets the disc edge-on and
        // may be cut off as a run of its own: at most one a side is kept.
        let left: Vec<_> = pts.iter().zip(&person).filter(|(p, &is)| is && kept.contains(&(p.0 as i16, p.1 as i16))).collect();
        prop_assert!(left.len() <= 2, "a person's returns were kept: {:?}", left);
        prop_assert_eq!(before.len() - dropped, kept.len());
        let (mt, _) = fusion::track(&b.m, &b.map, true).unwrap();
        let (e, et) = error(mt.pose, t);
        prop_assert!(e <= 10.0 && et <= 8_727, "{} mm {} µrad after dropping {}", e, et, dropped);
    }
}

/// A plain room with a doorway (walls only, no furniture) loses few
/// returns, from anywhere in it: walls seen from inside are never in
/// front of both neighbours. The doorway's jambs, seen edge-on or end-on,
/// are what could be mistaken for a person.
#[test]
fn walls_alone_lose_few_returns() {
    let (w, h) = (70u32, 50u32);
    let world = drawn_world(w, h, |r, c| {
        r == 0 || r == h - 1 || c == 0 || c == w - 1 || (c == 30 && !(20..30).contains(&r))
    });
    let mut rng = SplitMix64::new(11);
    let mut m = Box::new(ScanMatcher::<MW>::new());
    let (mut total, mut worst, mut scans_with_loss) = (0, 0, 0);
    for _ in 0..200 {
        let t = true_pose(&world, &mut rng);
        let pts = twin_scan(&world, t, 224, 0.01, 0.02, 0.0, &mut rng);
        m.points.set(guess(t, 0, 0, 0), &pts);
        let n = m.points.drop_foreground();
        total += n;
        worst = worst.max(n);
        scans_with_loss += u32::from(n > 0);
    }
    eprintln!("walls alone: {total} returns dropped in 200 scans, {scans_with_loss} scans, at most {worst}");
    assert!(
        worst <= 4 && scans_with_loss <= 10,
        "{total} {scans_with_loss} {worst}"
    );
}

/// A mission on the suite map `name` in unknown mode, realistic noise,
/// `people`, `seed`, cut at `max_time_s`: its report.
fn unknown_realistic(
    name: &str,
    people: usize,
    seed: u64,
    max_time_s: f64,
) -> host_sim::run::mission::MissionReport {
    use host_sim::run::mission::{run_mission, MissionOptions};
    use host_sim::sim::robot::Noise;
    use robovac::mission::MapMode;
    let map = suite_map(name).unwrap();
    let mut o = MissionOptions::new(map, MapMode::Unknown, people, Noise::Realistic, seed);
    o.max_time_s = max_time_s;
    run_mission(&o, |_, _, _| {}).unwrap().0
}

/// A person walking beside the robot in unknown mode no longer drags the
/// pose (issue 10 §2). The real S6 home, 1 person, realistic noise, seed
/// 1: before `drop_foreground`, a person beside the robot in a corridor
/// pulled the estimate 700 mm along it between 1,359 and 1,427 s, and the
/// robot never docked. Checked against the twin's true pose.
#[test]
fn a_person_beside_the_robot_does_not_drag_the_pose() {
    let rep = unknown_realistic("S6", 1, 1, 1_450.0);
    assert!(rep.pose_error_max_mm <= 100.0, "{rep:?}");
    assert!(rep.pose_error_rms_mm <= 30.0, "{rep:?}");
}

/// A person walking past a robot that waits no longer slides its pose
/// (`fusion::held_still`). The office flat, unknown mode, realistic
/// noise, 3 people, seed 9: at 2,310 s a person passed the robot waiting
/// beside the corridor's wall; in 5 s the matches slid the
/// estimate 50 mm along the wall, and the rest of the office was mapped in
/// that frame (pose RMS 37.3 mm, 134 mm at worst, for the whole mission).
/// Checked against the twin's true pose.
#[test]
fn a_person_passing_a_waiting_robot_does_not_slide_it() {
    let rep = unknown_realistic("office", 3, 9, 2_600.0);
    assert!(rep.pose_error_max_mm <= 40.0, "{rep:?}");
    assert!(rep.pose_error_rms_mm <= 15.0, "{rep:?}");
}

/// Someone following the robot along a corridor no longer holds the pose
/// back (`localize::track`: against the map being written, only points
/// beyond 0.3 m condition a match). The office flat, unknown mode,
/// realistic noise, 3 people, seed 9: at 2,672 s and again at 3,100 s a
/// person followed the robot 0.35 m behind along the 0.7 m corridor,
/// whose walls fix only the axis across it. The estimate was held 250,
/// then 450 mm behind the truth, the map was written in that frame, and
/// the robot never found its dock (95.85 % covered, pose RMS 227 mm).
/// Checked against the twin's true pose.
#[test]
fn a_follower_in_a_corridor_does_not_hold_the_pose_back() {
    let rep = unknown_realistic("office", 3, 9, 3_300.0);
    assert!(rep.pose_error_max_mm <= 60.0, "{rep:?}");
}

/// A robot turning in place in a doorway keeps its place (`localize::track`:
/// the far-point judgement applies only while the robot translates). The
/// real S6 home without its zones, unknown mode, harsh floors, 1 person,
/// seed 3: at 1,434 s the robot turned in place for 10 s in a doorway,
/// whose jambs, within 0.3 m, were what fixed the axis along the passage.
/// Judged by its far points alone every match there was partial, wheel
/// slip slid the estimate 58 mm, and the map was written in that frame
/// (the robot came back 58 mm from its dock, not docked). Checked against
/// the twin's true pose.
#[test]
fn a_robot_turning_in_a_doorway_keeps_its_place() {
    use host_sim::run::mission::{run_mission, MissionOptions};
    use host_sim::sim::robot::Noise;
    use robovac::mission::MapMode;
    let mut map = suite_map("S6").unwrap();
    host_sim::sim::zones::drop_map_zones(&mut map);
    let mut o = MissionOptions::new(map, MapMode::Unknown, 1, Noise::Harsh, 3);
    o.max_time_s = 1_460.0;
    let (rep, _, _) = run_mission(&o, |_, _, _| {}).unwrap();
    assert!(rep.pose_error_max_mm <= 30.0, "{rep:?}");
}

/// Someone following the robot on the floor it has just swept no longer
/// drags the pose (`localize::trail`). The studio, unknown mode, harsh
/// floors, 3 people, seed 3: a person stood 0.35 m behind the robot at
/// 136 s, was mapped, then followed it along the bottom wall. Every
/// revolution's match pulled the pose back toward where they had stood,
/// 522 mm off by 300 s (the robot was lost for good, 37 % covered).
/// Checked against the twin's true pose.
#[test]
fn someone_following_the_robot_does_not_hold_the_pose_back() {
    use host_sim::run::mission::{run_mission, MissionOptions};
    use host_sim::sim::robot::Noise;
    use robovac::mission::MapMode;
    let mut o = MissionOptions::new(
        suite_map("studio").unwrap(),
        MapMode::Unknown,
        3,
        Noise::Harsh,
        3,
    );
    o.max_time_s = 300.0;
    let (rep, _, _) = run_mission(&o, |_, _, _| {}).unwrap();
    assert!(rep.pose_error_max_mm <= 100.0, "{rep:?}");
}

/// A kidnap in a real home: twin scans at 50 random free places of each
/// of the six real homes (ValetudoMap exports, whose never-seen space
/// round the home the prior holds as solid wall), matched over the whole
/// map from no guess. Measured at 20 places each, with the whole-map
/// search counting every wall cell: 6, 4, 15, 13, 9 and 2 of 20 found;
/// with wall faces only ([`robovac::localize::pyramid::GLOBAL_LEVEL`]):
/// 17, 20, 20, 20, 20, 15. At 50 places each: 286 of 300 with 32 coarse
/// points and 12 candidates, 296 with faces beyond a block's edge, 64
/// points and 48 candidates (l10su 46 of 50, the others 50); none wrong.
#[test]
fn global_relocalisation_finds_the_robot_in_real_homes() {
    for name in ["S8", "z10", "1c", "S6", "3790", "l10su"] {
        let data = suite_map(name).unwrap();
        let cell_m = data.cell_m.unwrap_or(0.1);
        let Bench { world, map, mut m } = bench_of(World::new(data, cell_m));
        let mut rng = SplitMix64::new(11);
        let mut found = 0;
        for _ in 0..50 {
            let (t, pts) = random_scan(&world, &mut rng);
            m.points.set(PoseU::default(), &pts);
            if let Ok(p) = Fusion::new().relocalise(&m, &map, true, true) {
                let (d, dt) = error(p, t);
                // Success must be right; ambiguity may refuse.
                assert!(d <= 30.0 && dt <= 8_727, "{name}: {d:.1} mm {dt} µrad");
                found += 1;
            }
        }
        eprintln!("{name}: {found} of 50 found");
        assert!(found >= 45, "{name}: only {found} of 50 found");
    }
}

/// Where the S8 home's kidnap at 600 s put the robot down (known mode,
/// realistic, 1 person, seed 1: `Failed(Lost)` before the fix): beside a
/// wall whose face lies on a 40 cm block border of the whole-map search's
/// level, so every return off it fell in the free block before it (27 of
/// 32 coarse points hit at the true pose, clutter elsewhere 29–31). Found
/// at every heading now ([`robovac::localize::pyramid::GLOBAL_LEVEL`]'s
/// faces beyond a block's edge, [`robovac::localize::correlative::GLOBAL_TOP`]).
#[test]
fn global_relocalisation_finds_the_s8_kidnap_spot() {
    let data = suite_map("S8").unwrap();
    let cell_m = data.cell_m.unwrap_or(0.1);
    let Bench { world, map, mut m } = bench_of(World::new(data, cell_m));
    let mut rng = SplitMix64::new(7);
    for th in [-0.157f64, 0.5, 1.5, 3.0] {
        let t = (6.07, 5.74, th);
        let pts = twin_scan(&world, t, 450, 0.01, 0.02, 0.0, &mut rng);
        m.points.set(PoseU::default(), &pts);
        let p = Fusion::new().relocalise(&m, &map, true, true);
        let (d, dt) = error(p.unwrap(), t);
        assert!(d <= 30.0 && dt <= 8_727, "{t:?}: {d:.1} mm {dt} µrad");
    }
}
