//! Every map format, its free/blocked rule, resampling, and bad files.

use std::path::{Path, PathBuf};

use host_sim::capacity::new_grid;
use host_sim::io::maps::{load_map, LoadOptions, MapData};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("robovac-loaders-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = tmp(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn load(p: &Path) -> Result<MapData, String> {
    load_map(p, LoadOptions::default()).map_err(|e| e.to_string())
}

fn png(
    name: &str,
    w: u32,
    h: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) -> PathBuf {
    let p = tmp(name);
    let f = std::fs::File::create(&p).unwrap();
    let mut e = png::Encoder::new(std::io::BufWriter::new(f), w, h);
    e.set_color(color);
    e.set_depth(depth);
    let mut wr = e.write_header().unwrap();
    wr.write_image_data(data).unwrap();
    drop(wr);
    p
}

#[test]
fn ascii_and_movingai() {
    let p = write("a.txt", b"#..\n.#.\r\n");
    let m = load(&p).unwrap();
    assert_eq!((m.width, m.height), (3, 2));
    assert_eq!(m.blocked, vec![true, false, false, false, true, false]);
    assert_eq!(m.to_ascii(), "#..\n.#.\n");
    let p = write(
        "m.map",
        b"type octile\nheight 2\nwidth 4\nmap\n.G@T\nSW..\n",
    );
    let m = load(&p).unwrap();
    assert_eq!(
        m.blocked,
        vec![false, false, true, true, true, true, false, false]
    );
    let mut g = new_grid();
    m.to_grid(&mut *g).unwrap();
    assert!(g.is_blocked(2, 0) && g.is_free(1, 0));
}

#[test]
fn png_rule_grey_alpha_rgb_rgba() {
    use png::{BitDepth::*, ColorType::*};
    // grey: 255 and 254 free, 250 free, 249 and 205 blocked, 0 blocked
    let p = png(
        "g.png",
        6,
        1,
        Grayscale,
        Eight,
        &[255, 254, 250, 249, 205, 0],
    );
    assert_eq!(
        load(&p).unwrap().blocked,
        vec![false, false, false, true, true, true]
    );
    // grey + alpha: translucent white is blocked
    let p = png("ga.png", 2, 1, GrayscaleAlpha, Eight, &[255, 255, 255, 128]);
    assert_eq!(load(&p).unwrap().blocked, vec![false, true]);
    // RGB: white free, light grey (200,200,200) blocked, red blocked
    let p = png(
        "rgb.png",
        3,
        1,
        Rgb,
        Eight,
        &[255, 255, 255, 200, 200, 200, 255, 0, 0],
    );
    assert_eq!(load(&p).unwrap().blocked, vec![false, true, true]);
    // RGBA: opaque white free, transparent white blocked
    let p = png(
        "rgba.png",
        2,
        1,
        Rgba,
        Eight,
        &[254, 254, 254, 255, 255, 255, 255, 0],
    );
    assert_eq!(load(&p).unwrap().blocked, vec![false, true]);
    // 16-bit grey
    let p = png(
        "g16.png",
        2,
        1,
        Grayscale,
        Sixteen,
        &[0xFF, 0xFF, 0x10, 0x00],
    );
    assert_eq!(load(&p).unwrap().blocked, vec![false, true]);
}

#[test]
fn resampling_needs_every_pixel_free() {
    use png::{BitDepth::*, ColorType::*};
    // 4x2 pixels at 0.05 m; cells of 0.1 m = 2x2 pixels; one dark pixel in
    // the right block blocks that whole cell.
    let p = png(
        "rs.png",
        4,
        2,
        Grayscale,
        Eight,
        &[255, 255, 255, 255, 255, 255, 255, 0],
    );
    let m = load_cells(&p, 0.1);
    assert_eq!(
        (m.width, m.height, m.blocked.clone()),
        (2, 1, vec![false, true])
    );
    assert_eq!(m.cell_m, Some(0.1));
    // a partial block at the edge counts its missing pixels as blocked
    let p = png("rs3.png", 3, 2, Grayscale, Eight, &[255; 6]);
    let m = load_cells(&p, 0.1);
    assert_eq!(m.blocked, vec![false, true]);
    // a cell smaller than a pixel is refused
    assert!(load_map(
        &p,
        LoadOptions {
            cell_m: Some(0.01),
            png_resolution_m: None
        }
    )
    .is_err());
}

#[test]
fn ros_yaml_pgm() {
    // P5 3x1: 254 free, 205 unknown (blocked), 0 occupied
    let pgm = tmp("room.pgm");
    std::fs::write(&pgm, b"P5\n# comment\n3 1\n255\n\xfe\xcd\x00").unwrap();
    let y = write("room.yaml", b"image: room.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
    let m = load(&y).unwrap();
    assert_eq!(m.blocked, vec![false, true, true]);
    assert_eq!(m.cell_m, Some(0.05));
    // negate flips the meaning: 0 becomes free
    let y = write("neg.yaml", b"image: room.pgm\nresolution: 0.05\nnegate: 1\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
    assert_eq!(load(&y).unwrap().blocked, vec![true, true, false]);
    // P2 (ASCII) PGM
    std::fs::write(tmp("p2.pgm"), b"P2\n2 2\n255\n255 0\n254 100\n").unwrap();
    let y = write("p2.yaml", b"image: \"p2.pgm\"\nresolution: 0.1\n");
    assert_eq!(load(&y).unwrap().blocked, vec![false, true, false, true]);
}

#[test]
fn bad_files_are_clear_errors() {
    let cases: Vec<(PathBuf, &str)> = vec![
        (tmp("missing.map"), "cannot read"),
        (
            write("t.map", b"type octile\nheight 3\nwidth 3\nmap\n...\n"),
            "truncated",
        ),
        (
            write("h.map", b"type octile\nheight x\nwidth 3\nmap\n"),
            "not a number",
        ),
        (write("w.map", b"hello\n"), "unexpected MovingAI header"),
        (
            write("nomap.map", b"type octile\nheight 1\nwidth 1\n"),
            "header ends",
        ),
        (write("bad.txt", b"..x\n"), "unexpected"),
        (write("rag.txt", b"...\n..\n"), "row 2"),
        (write("empty.txt", b""), "empty"),
        (write("bad.png", b"\x89PNG\r\n\x1a\nxxxx"), "PNG"),
        (write("bad.pgm", b"P5\n3 1\n255\n\x00"), "truncated PGM"),
        (write("bad2.pgm", b"P6\n3 1\n255\n"), "not a PGM"),
        (write("nokey.yaml", b"resolution: 0.05\n"), "image"),
        (
            write("badres.yaml", b"image: x.pgm\nresolution: abc\n"),
            "not a number",
        ),
        (
            write("noimg.yaml", b"image: nothere.pgm\nresolution: 0.05\n"),
            "cannot read map image",
        ),
    ];
    for (p, want) in cases {
        let e = load(&p).expect_err(&p.display().to_string());
        assert!(e.contains(want), "{}: {e:?} lacks {want:?}", p.display());
        assert!(!e.contains('\n'), "one line: {e:?}");
    }
    // truncated real PNG: cut a valid file in half
    let good = png(
        "cut.png",
        64,
        64,
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        &[255; 64 * 64],
    );
    let bytes = std::fs::read(&good).unwrap();
    let p = write("cut2.png", &bytes[..bytes.len() / 2]);
    assert!(load(&p).is_err());
    // too large for the host capacity: 2048 x 1024 cells
    let mut big = b"type octile\nheight 1024\nwidth 2048\nmap\n".to_vec();
    for _ in 0..1024 {
        big.extend(std::iter::repeat_n(b'.', 2048));
        big.push(b'\n');
    }
    let m = load(&write("big.map", &big)).unwrap();
    let mut g = new_grid();
    let e = m.to_grid(&mut *g).unwrap_err().to_string();
    assert!(e.contains("exceeds the capacity"), "{e}");
}

/// Loads an image map resampled to `cell_m` cells.
fn load_cells(p: &std::path::Path, cell_m: f64) -> MapData {
    load_map(
        p,
        LoadOptions {
            cell_m: Some(cell_m),
            png_resolution_m: None,
        },
    )
    .unwrap()
}

/// The six real homes load: floor area, rooms and a dock, as their README
/// lists them.
#[test]
fn valetudo_homes_load() {
    let expect = [
        ("S8_FW1286_with_obstacles.json", 36.5, 6),
        ("z10_1056_paths.json", 40.9, 7),
        ("1c_1096_virtualwall_and_forbidden_zone.json", 29.3, 3),
        (
            "S6_FW2652_with_active_segment_and_no_mop_zone.json",
            46.0,
            6,
        ),
        ("converted_3790.json", 51.8, 7),
        ("l10su_1121_new_path.json", 37.3, 5),
    ];
    for (f, m2, rooms) in expect {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../maps/valetudo")
            .join(f);
        let m = host_sim::io::maps::load_map(&p, Default::default()).unwrap();
        let free = m.blocked.iter().filter(|b| !**b).count() as f64 * 0.05 * 0.05;
        assert!((free - m2).abs() < 0.05 * m2, "{f}: {free:.1} m² vs {m2}");
        let x = m.extras.as_ref().unwrap();
        assert_eq!(x.rooms.len(), rooms, "{f}");
        assert!(m.dock.is_some(), "{f}");
    }
}

/// Malformed ValetudoMap files: a one-line error each, never a panic.
#[test]
fn bad_valetudo_files_are_refused() {
    let dir = test_support::temp_dir("valetudo-bad");
    let cases = [
        ("not json", "not ValetudoMap JSON"),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":1},"pixelSize":5,"layers":[]}"#,
            "version",
        ),
        (
            r#"{"__class":"Other","metaData":{"version":2}}"#,
            "not a ValetudoMap",
        ),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":2},"pixelSize":5}"#,
            "no layers",
        ),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":2},"pixelSize":5,"layers":[]}"#,
            "no floor",
        ),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":2},"pixelSize":9999,"layers":[]}"#,
            "absurd",
        ),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":2},"pixelSize":5,"layers":[{"type":"floor","pixels":[-3,4]}]}"#,
            "out of range",
        ),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":2},"pixelSize":5,"layers":[{"type":"floor","compressedPixels":[1,2]}]}"#,
            "wrong length",
        ),
        (
            r#"{"__class":"ValetudoMap","metaData":{"version":2},"pixelSize":5,"layers":[{"type":"floor","pixels":[0,0,90000,90000]}]}"#,
            "spans",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let p = dir.join(format!("bad{i}.json"));
        std::fs::write(&p, text).unwrap();
        let e = host_sim::io::maps::load_map(&p, Default::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && !e.contains('\n'), "case {i}: {e}");
    }
}
