//! Fuzzes the LD06 parser with arbitrary byte streams: it must never panic,
//! and every frame it emits must carry a valid checksum and plausible
//! contents; its byte counter must match what was fed.
#![no_main]

use libfuzzer_sys::fuzz_target;
use robovac::robot::lidar::ld06::{crc8, encode, Ld06};
use robovac::robot::lidar::LidarProtocol;

fuzz_target!(|data: &[u8]| {
    let mut p = Ld06::new();
    for &b in data {
        if let Some(f) = p.feed(b) {
            let pts: [(u16, u8); 12] = core::array::from_fn(|i| (f.points[i].dist_mm, f.points[i].intensity));
            let bytes = encode(f.speed_dps, f.start_cdeg, f.end_cdeg, f.timestamp_ms, &pts);
            assert_eq!(crc8(&bytes[..46]), bytes[46]);
            assert!((360..=7200).contains(&f.speed_dps));
            assert!(f.start_cdeg < 36000 && f.end_cdeg < 36000 && f.timestamp_ms < 30000);
        }
    }
    assert_eq!(p.stats().bytes as usize, data.len());
});
