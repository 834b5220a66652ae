//! Twin scans for the matcher's tests and benchmarks: one revolution of
//! the twin's lidar taken at a standstill at a true pose, as robot-frame
//! points placed half an evidence cell beyond the range (as the core's
//! [`robovac::localize::points::ScanPoints::load`] places them).

use robovac::grid::maps::SplitMix64;
use robovac::robot::lidar_map::{CellState, EvidenceMap};

use crate::sim::world::World;

/// A revolution of `samples` bearings from the true pose (m, m, rad):
/// range noise `noise_m` (1 σ) and a share `dropout` of lost returns.
pub fn twin_scan(
    world: &World,
    pose: (f64, f64, f64),
    samples: usize,
    noise_m: f64,
    dropout: f64,
    past_hit_mm: f64,
    rng: &mut SplitMix64,
) -> Vec<(i32, i32)> {
    let mut out = Vec::new();
    for i in 0..samples {
        let b = i as f64 / samples as f64 * std::f64::consts::TAU;
        let Some(mut d) = world.ray(pose.0, pose.1, pose.2 + b, 12.0) else {
            continue;
        };
        if uniform(rng) < dropout {
            continue;
        }
        d += noise_m * crate::sim::robot::gauss(rng);
        let r = d * 1000.0 + past_hit_mm;
        out.push(((r * b.cos()).round() as i32, (r * b.sin()).round() as i32));
    }
    out
}

fn uniform(rng: &mut SplitMix64) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

/// Sizes `map` to the world at `res_mm` and fills it with the floor plan
/// (the known mode's prior; the caller freezes it). What the lidar cannot
/// see under or over its plane is not on it: the prior is the floor plan
/// a lidar would map.
pub fn fill_prior<const N: usize>(
    map: &mut EvidenceMap<N>,
    world: &World,
    res_mm: u32,
    known: bool,
) -> Result<(), String> {
    let (wm, hm) = world.size_m();
    let (ew, eh) = (
        ((wm * 1000.0).round() as u32).div_ceil(res_mm),
        ((hm * 1000.0).round() as u32).div_ceil(res_mm),
    );
    map.reset(ew, eh, res_mm)
        .map_err(|e| format!("map too large for the evidence map: {e}"))?;
    if !known {
        return Ok(());
    }
    let res = res_mm as f64 / 1000.0;
    for cy in 0..eh as i32 {
        for cx in 0..ew as i32 {
            let (x, y) = ((cx as f64 + 0.5) * res, (eh as f64 - cy as f64 - 0.5) * res);
            let st = if world.blocked_at(x, y) && !world.low_at(x, y) {
                CellState::Occupied
            } else {
                CellState::Free
            };
            map.set_state(cx, cy, st);
        }
    }
    Ok(())
}
