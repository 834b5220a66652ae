//! Odometry, angles, wheel control and the evidence map.

use proptest::prelude::*;
use robovac::math::angle::sin_cos_q30;
use robovac::robot::odometry::{DriveGeometry, Odometry};
use robovac::robot::wheel_control::{wheel_setpoints, WheelControl, WheelFault, WheelGains};

const GEOM: DriveGeometry = DriveGeometry {
    ticks_per_rev: 1000,
    wheel_diameter_um: 72_000,
    wheelbase_um: 235_000,
};

proptest! {
    #[test]
    fn sin_cos_accurate(t in -20_000_000i64..20_000_000) {
        let (s, c) = sin_cos_q30(t);
        let a = t as f64 * 1e-6;
        prop_assert!((s as f64 / (1u64 << 30) as f64 - a.sin()).abs() < 1.2e-8);
        prop_assert!((c as f64 / (1u64 << 30) as f64 - a.cos()).abs() < 1.2e-8);
    }
}

#[test]
fn straight_and_spin_are_exact() {
    let mut o = Odometry::new(GEOM);
    o.update(65000, 100); // first reading: reference only, counters near wrap
                          // 10 wheel turns forward, crossing the 16-bit wrap on the left wheel.
    let (mut l, mut r) = (65000u16, 100u16);
    for _ in 0..1000 {
        l = l.wrapping_add(10);
        r = r.wrapping_add(10);
        o.update(l, r);
    }
    let p = o.pose();
    let expect_mm = 10.0 * 72.0 * std::f64::consts::PI;
    assert!((p.x_mm as f64 - expect_mm).abs() <= 1.0, "{p:?}");
    assert_eq!((p.y_mm, p.theta_mrad), (0, 0));
    // Spin in place one full turn: wheel arc = π·B.
    let ticks = (235.0 / 72.0 * 1000.0f64).round() as i32;
    for _ in 0..ticks {
        l = l.wrapping_sub(1);
        r = r.wrapping_add(1);
        o.update(l, r);
    }
    let q = o.pose();
    assert!((q.x_mm - p.x_mm).abs() <= 1 && q.y_mm.abs() <= 1, "{q:?}");
    assert!(q.theta_mrad.abs() <= 2, "{q:?}");
}

/// An hour of simulated driving at 100 Hz with varied wheel speeds: the
/// integer odometry stays within 0.1 mm of a float implementation of the
/// same scheme (no drift from rounding).
#[test]
fn an_hour_without_rounding_drift() {
    let mut o = Odometry::new(GEOM);
    let (mut l, mut r) = (0u16, 0u16);
    o.update(l, r);
    let circ = 72.0e-3 * std::f64::consts::PI;
    let (mut x, mut y, mut tl, mut tr) = (0.0f64, 0.0f64, 0i64, 0i64);
    let mut rng = robovac::grid::maps::SplitMix64::new(42);
    let (mut vl, mut vr) = (0i32, 0i32);
    for k in 0..360_000u32 {
        if k % 300 == 0 {
            vl = rng.below(41) as i32 - 20; // ticks per 10 ms: up to ±0.45 m/s
            vr = rng.below(41) as i32 - 20;
        }
        l = l.wrapping_add(vl as u16);
        r = r.wrapping_add(vr as u16);
        let th0 = (tr - tl) as f64 * circ / 1000.0 / 0.235;
        tl += vl as i64;
        tr += vr as i64;
        let th1 = (tr - tl) as f64 * circ / 1000.0 / 0.235;
        let d = (vl + vr) as f64 / 2.0 * circ / 1000.0;
        let mid = 0.5 * (th0 + th1);
        x += d * mid.cos();
        y += d * mid.sin();
        o.update(l, r);
    }
    let (xn, yn, _) = o.pose_fine();
    let (ex, ey) = (xn as f64 * 1e-9 - x, yn as f64 * 1e-9 - y);
    println!(
        "after an hour: |x| {:.1} m, error vs float {:.3} mm, {:.3} mm",
        x.abs(),
        ex * 1e3,
        ey * 1e3
    );
    assert!(ex.abs() < 1e-4 && ey.abs() < 1e-4, "drift {ex} {ey} m");
}

const GAINS: WheelGains = WheelGains {
    kff_q8: 512,
    kp_q8: 400,
    ki_q8: 3000,
    max_duty_pm: 1000,
    stall_duty_pm: 500,
    stall_ms: 500,
};

#[test]
fn setpoints_and_stall() {
    assert_eq!(wheel_setpoints(300, 0, 235), (300, 300));
    assert_eq!(wheel_setpoints(0, 1000, 236), (-118, 118));
    let mut c = WheelControl::new(GAINS, 235);
    // A blocked left wheel: high duty, no ticks, for 0.5 s → stall.
    let mut fault_at = None;
    for k in 0..100 {
        let (dl, dr) = c.step(300, 0, 0, 300, false, true, 10_000);
        if c.fault().is_some() {
            fault_at = Some(k);
            assert_eq!((dl, dr), (0, 0));
            break;
        }
    }
    assert_eq!(c.fault(), Some(WheelFault::LeftStall));
    assert!(
        fault_at.is_some_and(|k| (45..=60).contains(&k)),
        "{fault_at:?}"
    );
    c.clear_fault();
    assert_eq!(c.fault(), None);
}

#[test]
fn anti_windup_limits_the_integral() {
    let mut c = WheelControl::new(GAINS, 235);
    // Saturated for 5 s against a wheel that cannot keep up (but ticks).
    for _ in 0..500 {
        let (d, _) = c.step(3000, 0, 100, 100, true, true, 10_000);
        assert!(d <= 1000);
    }
    // The moment the speed is reached, the duty falls back near the
    // feed-forward instead of staying pinned by a wound-up integral.
    let (d, _) = c.step(300, 0, 300, 300, true, true, 10_000);
    assert!(d < 1000, "duty {d} stayed saturated");
}
