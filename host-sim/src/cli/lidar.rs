//! `host-sim lidar-decode`: a captured lidar byte stream decoded.

use std::path::{Path, PathBuf};

use serde_json::json;

#[derive(clap::Args)]
pub struct Args {
    /// The capture file.
    pub file: PathBuf,
    /// Wire protocol.
    #[arg(long, default_value = "ld06")]
    pub protocol: String,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(a: Args) -> Result<(), String> {
    cmd_lidar_decode(&a.file, &a.protocol, a.json)
}

fn cmd_lidar_decode(file: &Path, protocol: &str, json: bool) -> Result<(), String> {
    use robovac::robot::lidar::LidarProtocol;
    if protocol != "ld06" {
        return Err(format!("unknown protocol {protocol:?} (supported: ld06)"));
    }
    let bytes = std::fs::read(file).map_err(|e| format!("{}: cannot read: {e}", file.display()))?;
    let mut p = robovac::robot::lidar::ld06::Ld06::new();
    let (mut points, mut valid, mut speed_sum) = (0u64, 0u64, 0u64);
    for &b in &bytes {
        if let Some(f) = p.feed(b) {
            points += f.count as u64;
            valid += f.points().iter().filter(|q| q.dist_mm > 0).count() as u64;
            speed_sum += f.speed_dps as u64;
        }
    }
    let s = p.stats();
    let mean_speed = if s.frames > 0 {
        speed_sum as f64 / s.frames as f64
    } else {
        0.0
    };
    if json {
        println!(
            "{}",
            json!({
                "protocol": protocol, "bytes": s.bytes, "frames": s.frames, "crc_failures": s.crc_failures,
                "rejected": s.rejected, "rejected_speed": s.rejected_speed, "rejected_span": s.rejected_span,
                "rejected_timestamp": s.rejected_timestamp, "bytes_skipped": s.bytes_skipped,
                "points": points, "points_with_return": valid, "mean_speed_dps": mean_speed,
            })
        );
    } else {
        println!("{}: {} bytes, {} frames, {} CRC failures, {} rejected, {} skipped bytes, {} points ({} with a return), mean speed {:.1} deg/s",
            file.display(), s.bytes, s.frames, s.crc_failures, s.rejected, s.bytes_skipped, points, valid, mean_speed);
    }
    Ok(())
}
