//! The integer DWA against a floating-point reference of the same
//! formulation (Fox, Burgard and Thrun) on thousands of random situations.

use robovac::nav::dwa::{plan, window, DwaParams, DwaResult, DEFAULT_PARAMS, V_SAMPLES, W_SAMPLES};

#[derive(Clone, Copy, Debug)]
struct FSample {
    v: f64,
    ok: bool,
    heading: f64,
    clearance: f64,
}

/// The same rollout, admissibility and score in f64 (m, rad, s).
fn f_evaluate(p: &DwaParams, v: f64, w: f64, goal: (f64, f64), obs: &[(f64, f64)]) -> FSample {
    let dt = p.step_ms as f64 / 1000.0;
    let steps = (p.horizon_ms / p.step_ms).max(1);
    let r = p.radius_mm as f64 / 1000.0;
    let (mut x, mut y, mut th) = (0.0f64, 0.0f64, 0.0f64);
    let (mut min_d, mut travelled, mut hit) = (f64::INFINITY, 0.0f64, None);
    for _ in 0..steps {
        let mid = th + w * dt / 2.0;
        x += v * dt * mid.cos();
        y += v * dt * mid.sin();
        th += w * dt;
        travelled += (v * dt).abs();
        for &(ox, oy) in obs {
            let d = (ox - x).hypot(oy - y);
            min_d = min_d.min(d);
            if d <= r && hit.is_none() {
                hit = Some(travelled);
            }
        }
    }
    let cap = p.clearance_cap_mm as f64 / 1000.0;
    let clearance = if min_d.is_finite() {
        (min_d - r).clamp(0.0, cap)
    } else {
        cap
    };
    let ok = match hit {
        None => true,
        Some(_) if v == 0.0 => true,
        Some(h) => {
            let dist = (h - (v * dt).abs()).max(0.0);
            let a = p.acc_mm_s2 as f64 / 1000.0;
            let wa = p.w_acc_mrad_s2 as f64 / 1000.0;
            v * v <= 2.0 * dist * a + 1e-12 && w * w <= 2.0 * (dist / r) * wa + 1e-12
        }
    };
    let to_goal = (goal.1 - y).atan2(goal.0 - x);
    let mut err = (to_goal - th).rem_euclid(2.0 * std::f64::consts::PI);
    if err > std::f64::consts::PI {
        err = 2.0 * std::f64::consts::PI - err;
    }
    FSample {
        v,
        ok,
        heading: std::f64::consts::PI - err,
        clearance,
    }
}

fn f_scores(p: &DwaParams, s: &[FSample]) -> Vec<Option<f64>> {
    let ok = s.iter().filter(|x| x.ok);
    let hm = ok.clone().map(|x| x.heading).fold(0.0, f64::max);
    let cm = ok.clone().map(|x| x.clearance).fold(0.0, f64::max);
    let vm = ok.map(|x| x.v.abs()).fold(0.0, f64::max);
    let n = |x: f64, m: f64| if m > 0.0 { x / m } else { 0.0 };
    s.iter()
        .map(|x| {
            x.ok.then(|| {
                p.alpha as f64 * n(x.heading, hm)
                    + p.beta as f64 * n(x.clearance, cm)
                    + p.gamma as f64 * n(x.v.abs(), vm)
            })
        })
        .collect()
}

#[test]
fn integer_dwa_agrees_with_float() {
    let p = DEFAULT_PARAMS;
    let mut rng = robovac::grid::maps::SplitMix64::new(2026);
    let (mut n, mut same, mut close, mut both_none, mut worst) = (0, 0, 0, 0, 0.0f64);
    let mut disagree_admissible = 0;
    for _ in 0..3000 {
        let v0 = rng.below(501) as i32;
        let w0 = rng.below(2001) as i32 - 1000;
        let goal = (rng.below(8000) as i32 - 2000, rng.below(8000) as i32 - 4000);
        let k = rng.below(30) as usize;
        let obs: Vec<(i32, i32)> = (0..k)
            .map(|_| (rng.below(3000) as i32 - 500, rng.below(3000) as i32 - 1500))
            .collect();
        let int = plan(&p, v0, w0, goal, &obs);
        let (vs, ws) = window(&p, v0, w0);
        let fs: Vec<FSample> = (0..V_SAMPLES * W_SAMPLES)
            .map(|k| {
                let (v, w) = (
                    vs[k / W_SAMPLES] as f64 / 1000.0,
                    ws[k % W_SAMPLES] as f64 / 1000.0,
                );
                let fo: Vec<(f64, f64)> = obs
                    .iter()
                    .map(|&(x, y)| (x as f64 / 1000.0, y as f64 / 1000.0))
                    .collect();
                f_evaluate(
                    &p,
                    v,
                    w,
                    (goal.0 as f64 / 1000.0, goal.1 as f64 / 1000.0),
                    &fo,
                )
            })
            .collect();
        let sc = f_scores(&p, &fs);
        let best = sc
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.map(|s| (i, s)))
            .fold(None::<(usize, f64)>, |b, (i, s)| match b {
                Some((_, bs)) if bs >= s => b,
                _ => Some((i, s)),
            });
        n += 1;
        match (int, best) {
            (DwaResult::NoAdmissible, None) => {
                both_none += 1;
                same += 1;
                close += 1;
            }
            (
                DwaResult::Command {
                    v_mm_s, w_mrad_s, ..
                },
                Some((bi, bs)),
            ) => {
                let k = (0..fs.len())
                    .find(|&k| vs[k / W_SAMPLES] == v_mm_s && ws[k % W_SAMPLES] == w_mrad_s)
                    .unwrap();
                if k == bi {
                    same += 1;
                    close += 1;
                } else if let Some(s) = sc[k] {
                    // the float score of the integer choice, against the best
                    let gap = (bs - s) / 1000.0;
                    worst = worst.max(gap);
                    if gap <= 0.01 {
                        close += 1;
                    }
                } else {
                    disagree_admissible += 1;
                }
            }
            _ => disagree_admissible += 1,
        }
    }
    let rate = same as f64 / n as f64;
    println!(
        "DWA integer vs float over {n} situations: same command {:.2} %, within 1 % of the float optimum {:.2} %, both without admissible motion {both_none}, admissibility disagreements {disagree_admissible}, worst score gap {:.4}",
        100.0 * rate,
        100.0 * close as f64 / n as f64,
        worst
    );
    assert!(close as f64 >= 0.995 * n as f64, "{close}/{n}");
    assert!(rate >= 0.9, "{rate}");
}

#[test]
fn dwa_behaves() {
    let p = DEFAULT_PARAMS;
    // Free space, goal straight ahead: full speed ahead, no turning.
    match plan(&p, 400, 0, (3000, 0), &[]) {
        DwaResult::Command {
            v_mm_s, w_mrad_s, ..
        } => assert!(v_mm_s >= 400 && w_mrad_s == 0),
        r => panic!("{r:?}"),
    }
    // Closed loop toward a wall between the robot and its goal: cycle after
    // cycle (commands applied for 100 ms), it never touches the wall.
    let wall_world: Vec<(f64, f64)> = (-40..=40).map(|k| (1.0, k as f64 * 0.025)).collect();
    let (mut x, mut y, mut th, mut v, mut w) = (0.0f64, 0.0f64, 0.0f64, 300, 0);
    let mut min_clear = f64::INFINITY;
    for _ in 0..100 {
        let rel: Vec<(i32, i32)> = wall_world
            .iter()
            .map(|&(wx, wy)| {
                let (dx, dy) = (wx - x, wy - y);
                (
                    ((dx * th.cos() + dy * th.sin()) * 1000.0) as i32,
                    ((-dx * th.sin() + dy * th.cos()) * 1000.0) as i32,
                )
            })
            .collect();
        let (gx, gy) = (3.0 - x, 0.0 - y);
        let goal = (
            ((gx * th.cos() + gy * th.sin()) * 1000.0) as i32,
            ((-gx * th.sin() + gy * th.cos()) * 1000.0) as i32,
        );
        (v, w) = match plan(&p, v, w, goal, &rel) {
            DwaResult::Command {
                v_mm_s, w_mrad_s, ..
            } => (v_mm_s, w_mrad_s),
            DwaResult::NoAdmissible => (0, 0),
        };
        for _ in 0..10 {
            th += w as f64 / 1000.0 * 0.01;
            x += v as f64 / 1000.0 * 0.01 * th.cos();
            y += v as f64 / 1000.0 * 0.01 * th.sin();
            let c = wall_world
                .iter()
                .map(|&(wx, wy)| (wx - x).hypot(wy - y))
                .fold(f64::INFINITY, f64::min);
            min_clear = min_clear.min(c);
        }
    }
    assert!(
        min_clear > 0.165,
        "the body (radius 0.165 m) touched the wall: {min_clear}"
    );
    // Boxed in at 0.25 m on every side while moving: only stopping remains,
    // and turning on the spot is always admissible.
    let ring: Vec<(i32, i32)> = (0..36)
        .map(|k| {
            let a = k as f64 * 10f64.to_radians();
            ((250.0 * a.cos()) as i32, (250.0 * a.sin()) as i32)
        })
        .collect();
    match plan(&p, 0, 0, (3000, 0), &ring) {
        DwaResult::Command { v_mm_s, .. } => assert_eq!(v_mm_s, 0),
        r => panic!("{r:?}"),
    }
    // Goal behind: it turns.
    match plan(&p, 0, 0, (-2000, 100), &[]) {
        DwaResult::Command { w_mrad_s, .. } => assert!(w_mrad_s > 0),
        r => panic!("{r:?}"),
    }
}

#[test]
fn recorded_situation_at_full_capacity() {
    use robovac::nav::dwa::{recorded_full, RECORDED_GOAL, RECORDED_VELOCITY};
    let r = plan(
        &DEFAULT_PARAMS,
        RECORDED_VELOCITY.0,
        RECORDED_VELOCITY.1,
        RECORDED_GOAL,
        &recorded_full(),
    );
    println!("recorded situation, 64 points: {r:?}");
    // The emulated run must reach this command too (its golden line).
    match r {
        DwaResult::Command {
            v_mm_s, w_mrad_s, ..
        } => assert_eq!((v_mm_s, w_mrad_s), robovac::nav::dwa::RECORDED_FULL_COMMAND),
        DwaResult::NoAdmissible => panic!("no admissible motion"),
    }
}

#[test]
fn recorded_situation() {
    use robovac::nav::dwa::{RECORDED_GOAL, RECORDED_OBSTACLES, RECORDED_VELOCITY};
    let r = plan(
        &DEFAULT_PARAMS,
        RECORDED_VELOCITY.0,
        RECORDED_VELOCITY.1,
        RECORDED_GOAL,
        &RECORDED_OBSTACLES,
    );
    println!("recorded situation: {r:?}");
    // The emulated Cortex-M4 run must reach exactly this command too.
    match r {
        DwaResult::Command {
            v_mm_s, w_mrad_s, ..
        } => {
            assert_eq!((v_mm_s, w_mrad_s), robovac::nav::dwa::RECORDED_COMMAND);
        }
        DwaResult::NoAdmissible => panic!("no admissible motion"),
    }
}

/// The rollout as first written (each obstacle converted to µm inside the
/// loop, the contact tested per point), kept as the exact reference for
/// the faster loop of `evaluate` (obstacles converted once, a per-step
/// nearest distance). Only the clearance's d² and the contact distance
/// come from this loop; the rest of a sample is shared code.
fn reference_rollout(p: &DwaParams, v: i32, w: i32, obs: &[(i32, i32)]) -> (i64, Option<i64>) {
    use robovac::math::angle::sin_cos_q30;
    let steps = (p.horizon_ms / p.step_ms.max(1)).max(1);
    let (mut x_um, mut y_um) = (0i64, 0i64);
    let r_um = p.radius_mm as i64 * 1000;
    let (step_um, dth) = (v as i64 * p.step_ms as i64, w as i64 * p.step_ms as i64);
    let (mut min_d2, mut travelled, mut hit) = (i64::MAX, 0i64, None);
    let (mut s, mut c) = sin_cos_q30(dth / 2);
    let (rs, rc) = sin_cos_q30(dth);
    for _ in 0..steps {
        x_um += (step_um * c) >> 30;
        y_um += (step_um * s) >> 30;
        (c, s) = ((c * rc - s * rs) >> 30, (s * rc + c * rs) >> 30);
        travelled += step_um.abs();
        let (xi, yi) = (
            x_um.clamp(-(1 << 30), 1 << 30) as i32,
            y_um.clamp(-(1 << 30), 1 << 30) as i32,
        );
        for &(ox, oy) in obs {
            let dx = (ox.clamp(-2_000_000, 2_000_000) * 1000).saturating_sub(xi) as i64;
            let dy = (oy.clamp(-2_000_000, 2_000_000) * 1000).saturating_sub(yi) as i64;
            let d2 = dx * dx + dy * dy;
            min_d2 = min_d2.min(d2);
            if d2 <= r_um * r_um && hit.is_none() {
                hit = Some(travelled);
            }
        }
    }
    (min_d2, hit)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(400))]
    /// The fast loop gives every sample exactly what the reference loop
    /// gives (clearance and admissibility from the same d² and contact),
    /// including far and clamped obstacles and more than MAX_OBSTACLES.
    #[test]
    fn fast_rollout_equals_the_reference(
        v in 0i32..=500,
        w in -1000i32..=1000,
        goal in (-5000i32..5000, -5000i32..5000),
        obs in proptest::collection::vec((-3_000_000i32..3_000_000, -3_000_000i32..3_000_000), 0..80),
        near in proptest::collection::vec((-1500i32..1500, -1500i32..1500), 0..80),
    ) {
        use robovac::nav::dwa::{evaluate, MAX_OBSTACLES};
        let p = DEFAULT_PARAMS;
        // Mostly near points (contacts and clearances), some far ones.
        let all: Vec<(i32, i32)> = near.iter().chain(obs.iter().take(8)).copied().collect();
        let used = &all[..all.len().min(MAX_OBSTACLES)];
        let got = evaluate(&p, v, w, goal, &all);
        let (min_d2, hit) = reference_rollout(&p, v, w, used);
        let cap = p.clearance_cap_mm as i64;
        let clearance = if min_d2 == i64::MAX {
            cap
        } else {
            (robovac::math::cost::isqrt_u64(min_d2 as u64) as i64 / 1000 - p.radius_mm as i64)
                .clamp(0, cap)
        };
        proptest::prop_assert_eq!(got.clearance_mm as i64, clearance);
        let step_um = (v as i64 * p.step_ms as i64).abs();
        let ok = match hit {
            None => true,
            Some(_) if v == 0 => true,
            Some(h) => {
                let dist = ((h - step_um) / 1000).max(0);
                let ang = dist * 1000 / p.radius_mm as i64;
                (v as i64).pow(2) <= 2 * dist * p.acc_mm_s2 as i64
                    && (w as i64).pow(2) <= 2 * ang * p.w_acc_mrad_s2 as i64
            }
        };
        proptest::prop_assert_eq!(got.ok, ok);
    }
}
