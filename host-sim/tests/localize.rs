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
    let world = World::new(suite_map(name).unwrap(), 0.1);
    let mut map = Box::new(EvidenceMap::<EV>::new());
    fill_prior(&mut map, &world, 50, true).unwrap();
    map.freeze_prior();
    let mut m = Box::new(ScanMatcher::<MW>::new());
    assert!(m.pyramid.build(&map, true));
    Bench { world, map, m }
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
    let t = true_pose(&b.world, &mut rng);
    let pts = twin_scan(&b.world, t, 450, 0.01, 0.02, 0.0, &mut rng);
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
        let t = true_pose(&b.world, &mut rng);
        let pts = twin_scan(&b.world, t, 450, 0.01, 0.02, 0.0, &mut rng);
        b.m.points.set(guess(t, 30, -25, 20_000), &pts);
        let (mt, _) = fusion::track(&b.m, &b.map, true).unwrap();
        let (d, dt) = error(mt.pose, t);
        assert!(d <= 10.0 && dt <= 8_727, "{t:?}: {d:.1} mm {dt} µrad");
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

/// A kidnap: the scan matched over the whole map from no guess at all.
#[test]
fn global_relocalisation_finds_the_robot() {
    let mut ok = 0;
    for (i, map) in ["studio", "home", "office"]
        .iter()
        .cycle()
        .take(12)
        .enumerate()
    {
        let mut b = bench(map);
        let mut rng = SplitMix64::new(100 + i as u64);
        let t = true_pose(&b.world, &mut rng);
        let pts = twin_scan(&b.world, t, 450, 0.01, 0.02, 0.0, &mut rng);
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

/// People (unmapped points) do not pull the pose: a scan with a third of
/// its points on a crowd in the room still matches the truth.
#[test]
fn unmapped_points_do_not_pull() {
    let mut b = bench("home");
    let mut rng = SplitMix64::new(3);
    let mut worst = 0.0f64;
    for _ in 0..10 {
        let t = true_pose(&b.world, &mut rng);
        let mut pts = twin_scan(&b.world, t, 450, 0.01, 0.02, 0.0, &mut rng);
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
    let blocked = (0..h)
        .flat_map(|r| (0..w).map(move |c| r == 0 || r == h - 1 || c == 0 || c == w - 1))
        .collect();
    let map = host_sim::io::maps::MapData {
        width: w,
        height: h,
        blocked,
        cell_m: Some(0.1),
        ..Default::default()
    };
    let world = World::new(map, 0.1);
    let mut ev = Box::new(EvidenceMap::<EV>::new());
    fill_prior(&mut ev, &world, 50, true).unwrap();
    ev.freeze_prior();
    let mut m = Box::new(ScanMatcher::<MW>::new());
    assert!(m.pyramid.build(&ev, true));
    let mut rng = SplitMix64::new(5);
    let truth = (16.0, 0.6, 0.0);
    let pts = twin_scan(&world, truth, 450, 0.01, 0.02, 0.0, &mut rng);
    m.points.set(guess(truth, 60, 25, 0), &pts);
    let mut f = Fusion::new();
    let (dx, dy, _) = f.track(&m, &ev, true).unwrap();
    assert_eq!(f.stats.partial, 1, "{:?}", f.stats);
    assert!(dx.abs() <= 2, "along the corridor: {dx} mm");
    assert!((dy + 25).abs() <= 6, "across: {dy} mm");
}
