//! The sim link's frames: round trips, and what bad bytes cost.
#![cfg(feature = "link")]

use robovac::link::msg::{pack_row, unpack_cell, Down, Hello, Tick, Up};
use robovac::link::{encode, FrameReader, LinkError, MAX_FRAME};
use robovac::mission::{MapMode, MissionConfig, MotorCmd, State};
use robovac::robot::lidar_map::{CellState, LidarMount};
use robovac::robot::odometry::{DriveGeometry, Pose};
use robovac::robot::wheel_control::WheelGains;

fn hello() -> Down {
    let geo = DriveGeometry {
        ticks_per_rev: 1440,
        wheel_diameter_um: 70_000,
        wheelbase_um: 230_000,
    };
    let gains = WheelGains {
        kff_q8: 300,
        kp_q8: 200,
        ki_q8: 50,
        max_duty_pm: 1000,
        stall_duty_pm: 600,
        stall_ms: 800,
    };
    let cfg = MissionConfig::new(MapMode::Unknown, geo, gains, LidarMount::ld06_centred(true));
    Down::Hello(Hello {
        cfg,
        dock: Pose {
            x_mm: 1200,
            y_mm: -40,
            theta_mrad: 3141,
        },
        map_w: 240,
        map_h: 200,
        res_mm: 50,
    })
}

fn frames(msgs: &[Down]) -> Vec<u8> {
    let mut wire = Vec::new();
    for m in msgs {
        let mut buf = [0u8; MAX_FRAME];
        let n = encode(m, &mut buf).unwrap();
        assert_eq!(buf[n - 1], 0);
        assert!(
            !buf[..n - 1].contains(&0),
            "COBS leaves no zero inside a frame"
        );
        wire.extend_from_slice(&buf[..n]);
    }
    wire
}

fn read_all(wire: &[u8]) -> (Vec<Down>, Vec<LinkError>, FrameReader<MAX_FRAME>) {
    let mut r = FrameReader::<MAX_FRAME>::new();
    let (mut ok, mut bad) = (Vec::new(), Vec::new());
    for &b in wire {
        match r.push::<Down>(b) {
            Some(Ok(m)) => ok.push(m),
            Some(Err(e)) => bad.push(e),
            None => {}
        }
    }
    (ok, bad, r)
}

fn sample() -> Vec<Down> {
    let row = pack_row((0..240).map(|x| match x % 3 {
        0 => CellState::Unknown,
        1 => CellState::Free,
        _ => CellState::Occupied,
    }))
    .unwrap();
    vec![
        hello(),
        Down::MapRow { row: 7, cells: row },
        Down::Start,
        Down::Tick(Tick {
            t_us: 10_000,
            enc: (65_535, 3),
            bumper: robovac::robot::hal::Bumper {
                left: true,
                right: false,
            },
            lidar_bytes: 94,
        }),
        Down::End,
    ]
}

#[test]
fn every_message_comes_through_unchanged() {
    let msgs = sample();
    let (got, bad, r) = read_all(&frames(&msgs));
    assert_eq!(got, msgs);
    assert!(bad.is_empty());
    assert_eq!(r.stats().frames, msgs.len() as u32);
    // The packed row reads back cell by cell.
    let Down::MapRow { cells, .. } = &got[1] else {
        panic!("not a row")
    };
    for x in 0..240 {
        let want = [CellState::Unknown, CellState::Free, CellState::Occupied][x % 3];
        assert_eq!(unpack_cell(cells, x), want, "cell {x}");
    }
    assert_eq!(unpack_cell(cells, 999), CellState::Unknown);
}

#[test]
fn a_flipped_bit_costs_one_frame_and_is_counted() {
    let msgs = sample();
    let mut wire = frames(&msgs);
    // Flip a bit inside the Tick's frame (not its zero).
    let ends: Vec<usize> = (0..wire.len()).filter(|&i| wire[i] == 0).collect();
    let i = ends[2] + 3;
    wire[i] ^= 0x10;
    let (got, bad, r) = read_all(&wire);
    assert_eq!(got.len(), msgs.len() - 1);
    assert!(!got.iter().any(|m| matches!(m, Down::Tick(_))));
    assert_eq!(bad.len(), 1);
    assert_eq!(
        r.stats().frames + r.stats().crc + r.stats().framing + r.stats().decode,
        5
    );
}

#[test]
fn garbage_and_overlong_frames_are_dropped_and_the_reader_resynchronises() {
    let msgs = sample();
    let mut wire: Vec<u8> = (0..3000u32).map(|i| (i * 37 % 251) as u8 | 1).collect();
    wire.push(0); // ends the overlong garbage "frame"
    wire.extend((0..200u32).map(|i| (i * 101 % 256) as u8)); // short garbage with zeros
    wire.push(0);
    wire.extend(frames(&msgs));
    let (got, bad, r) = read_all(&wire);
    assert_eq!(got, msgs, "every frame after the garbage arrives");
    assert!(bad.contains(&LinkError::TooLong));
    assert_eq!(r.stats().too_long, 1);
    let s = r.stats();
    assert_eq!(s.framing + s.crc + s.decode + s.too_long, bad.len() as u32);
}

#[test]
fn up_messages_round_trip_and_overlong_messages_are_refused() {
    let step = Up::Step(robovac::link::msg::StepMsg {
        cmd: MotorCmd::Duty(-300, 450),
        state: State::Cover,
        pose: Pose::default(),
        lost: false,
        avoidance_events: 3,
        finished: false,
    });
    let mut buf = [0u8; MAX_FRAME];
    let n = encode(&step, &mut buf).unwrap();
    let mut r = FrameReader::<MAX_FRAME>::new();
    let got: Vec<Up> = buf[..n]
        .iter()
        .filter_map(|&b| r.push(b))
        .map(|x| x.unwrap())
        .collect();
    assert_eq!(got, vec![step]);
    // A frame buffer too small is an error, not a panic.
    let mut small = [0u8; 4];
    assert_eq!(encode(&hello(), &mut small), Err(LinkError::TooLong));
}
