//! The command line as a user meets it: exit codes, messages, JSON.

mod cli_common;

use cli_common::{assert_refused, bin, json, repo};

#[test]
fn bad_input_exits_2_with_one_line() {
    let dir = test_support::temp_dir("cli");
    let trunc = dir.join("t.map");
    std::fs::write(&trunc, "type octile\nheight 9\nwidth 9\nmap\n.........\n").unwrap();
    let ascii = dir.join("a.txt");
    std::fs::write(&ascii, "....\n.##.\n....\n").unwrap();
    let t = trunc.to_str().unwrap();
    let a = ascii.to_str().unwrap();
    let cases: Vec<Vec<&str>> = vec![
        vec![
            "search",
            "--map",
            "/nonexistent/x.map",
            "--from",
            "0,0",
            "--to",
            "1,1",
        ],
        vec!["search", "--map", t, "--from", "0,0", "--to", "1,1"],
        vec!["search", "--map", a, "--from", "0,0", "--to", "1,1"],
        vec!["search", "--map", a, "--from", "0,0", "--to", "99,1"],
        vec!["search", "--map", a, "--from", "a,b", "--to", "1,1"],
        vec![
            "search", "--map", a, "--from", "0,0", "--to", "1,1", "--algo", "dijkstra",
        ],
        vec![
            "search", "--map", a, "--from", "0,0", "--to", "3,2", "--cell", "-1",
        ],
        vec!["scen", "/nonexistent.scen", "--map", a],
        vec!["bench", "table1", "--runs", "0"],
        vec!["bench", "table1", "--runs", "ten"],
        vec!["frobnicate"],
    ];
    for args in cases {
        let out = bin().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("backtrace"),
            "{args:?}: {err}"
        );
        assert!(!err.trim().is_empty());
    }
}

#[test]
fn table1_small_run_keeps_the_papers_order() {
    let j = json(&["bench", "table1", "--runs", "60", "--seed", "7", "--json"]);
    let a = &j["astar"];
    let o = &j["oha"];
    let t = &j["theta"];
    for r in [a, o, t] {
        for k in ["mean_time_us", "mean_cost", "mean_nodes"] {
            assert!(r[k].as_f64().unwrap() > 0.0, "{k}");
        }
    }
    let an = a["mean_nodes"].as_f64().unwrap();
    let on = o["mean_nodes"].as_f64().unwrap();
    assert!(on < 0.6 * an, "OHA* {on} vs A* {an}");
    // OHA*'s pruned cost is no higher than A*'s unpruned 8-connected cost.
    assert!(o["mean_cost"].as_f64().unwrap() <= a["mean_cost"].as_f64().unwrap());
}

#[test]
fn demo_runs_a_whole_mission_and_writes_its_picture() {
    let dir = test_support::temp_dir("cli-demo");
    let out = bin().arg("demo").current_dir(&dir).output().unwrap();
    test_support::assert_ok(&out);
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(
        s.contains("finished true") && s.contains("back at start true"),
        "{s}"
    );
    assert!(s.contains("collisions 0"), "{s}");
    let svg = std::fs::read_to_string(dir.join("demo.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("coverage") && svg.contains("polyline"));
}

#[test]
fn mission_reports_json_and_rejects_bad_input() {
    let dir = test_support::temp_dir("cli-m");
    let map = repo().join("maps/flat/studio.txt");
    let (j, svg) = (dir.join("m.json"), dir.join("m.svg"));
    let out = bin()
        .args(["mission", "--map"])
        .arg(&map)
        .args(["--mode", "known", "--people", "1", "--seed", "4", "--json"])
        .arg(&j)
        .arg("--svg")
        .arg(&svg)
        .output()
        .unwrap();
    test_support::assert_ok(&out);
    let v: serde_json::Value = test_support::read_json(&j);
    for k in [
        "finished",
        "returned_to_start",
        "coverage",
        "repetition",
        "collisions",
        "min_clearance_m",
        "distance_m",
        "avoidance_events",
        "sim_time_s",
        "wall_time_s",
        "faults",
    ] {
        assert!(v.get(k).is_some(), "JSON lacks {k}");
    }
    assert_eq!(v["collisions"], 0);
    assert!(std::fs::read_to_string(&svg).unwrap().contains("people"));
    for args in [
        vec!["mission", "--map", "no/such/map.txt"],
        vec!["mission", "--map", map.to_str().unwrap(), "--start", "a,b"],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--start",
            "0.05,0.05",
        ],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--max-time",
            "-3",
        ],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--planner",
            "zigzag",
        ],
        vec!["bench", "missions", "--runs", "0"],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--no-go",
            "1,2,3",
        ],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--virtual-wall",
            "a,1,2,3",
        ],
        // A no-go zone over the dock.
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--start",
            "3.0,2.25",
            "--no-go",
            "2.5,2.0,3.5,2.5",
        ],
        // Things the lidar cannot see: malformed, off the map, too small,
        // over the dock.
        vec!["mission", "--map", map.to_str().unwrap(), "--sofa", "1,2,3"],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--cable",
            "1,1,90,1",
        ],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--crossbar",
            "1,1,1.01,1",
        ],
        vec![
            "mission",
            "--map",
            map.to_str().unwrap(),
            "--start",
            "3.0,2.25",
            "--sofa",
            "2.5,2.0,3.5,2.5",
        ],
        // More zones than the map holds.
        ["mission", "--map", map.to_str().unwrap()]
            .into_iter()
            .chain((0..9).flat_map(|_| ["--no-go", "0.2,0.2,0.4,0.4"]))
            .collect(),
    ] {
        let out = bin().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn plan_writes_json_and_svg() {
    let dir = test_support::temp_dir("cli-p");
    for planner in ["b-oha", "ba", "b-theta", "b-oha-pc"] {
        let (j, s) = (
            dir.join(format!("{planner}.json")),
            dir.join(format!("{planner}.svg")),
        );
        let out = bin()
            .args([
                "plan",
                "--map",
                "maps/movingai/rooms64.map",
                "--planner",
                planner,
                "--json",
            ])
            .arg(&j)
            .arg("--svg")
            .arg(&s)
            .current_dir(repo())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = test_support::read_json(&j);
        assert_eq!(v["map"]["width"], 64);
        assert_eq!(v["grid"].as_array().unwrap().len(), 64);
        assert_eq!(v["start"], serde_json::json!([1, 1]));
        let wp = v["waypoints"].as_array().unwrap();
        assert!(wp.len() > 10);
        let segs = v["segments"].as_array().unwrap();
        assert!(segs
            .iter()
            .all(|s| s["kind"] == "cover" || s["kind"] == "transit"));
        assert_eq!(
            segs.last().unwrap()["to"].as_u64().unwrap() as usize,
            wp.len() - 1
        );
        let m = &v["metrics"];
        assert_eq!(m["coverage"], 1.0);
        for k in [
            "reachable_cells",
            "covered_cells",
            "repeated_cells",
            "repetition",
            "coverage_path_length",
            "backtrack_path_length",
            "total_path_length",
            "turns",
            "rotation_deg",
            "segments",
            "backtrack_points_total",
            "nodes_expanded",
            "time_us",
        ] {
            assert!(m[k].is_number(), "{k}");
        }
        let svg = std::fs::read_to_string(&s).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("polyline") && svg.contains("coverage 1.0000")
        );
        assert!(svg.contains("stroke-dasharray"), "transits are dashed");
    }
    // Bad planner and bad start: exit 2, one line.
    for args in [
        vec![
            "plan",
            "--map",
            "maps/movingai/rooms64.map",
            "--planner",
            "zigzag",
        ],
        vec![
            "plan",
            "--map",
            "maps/movingai/rooms64.map",
            "--start",
            "0,0",
        ],
        vec![
            "plan",
            "--map",
            "maps/movingai/rooms64.map",
            "--start",
            "900,900",
        ],
    ] {
        let out = bin().args(&args).current_dir(repo()).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr).trim().lines().count(),
            1
        );
    }
}

#[test]
fn table2_json_and_pictures() {
    let dir = test_support::temp_dir("cli-t2");
    let j = dir.join("t2.json");
    let out = bin()
        .args(["bench", "table2", "--runs", "4", "--seed", "3", "--json"])
        .arg(&j)
        .arg("--svg-dir")
        .arg(dir.join("svg"))
        .output()
        .unwrap();
    test_support::assert_ok(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("1200.01") && text.contains("ratios against our BA*"));
    let v: serde_json::Value = test_support::read_json(&j);
    for size in ["50x30", "30x50"] {
        for p in ["ba", "b-theta", "b-oha", "b-oha-pc"] {
            let r = &v[size][p];
            assert_eq!(r["min_coverage"], 1.0, "{size} {p}");
            let positive = "coverage_path_length segments turns backtrack_path_length";
            for k in positive
                .split(' ')
                .chain(["backtrack_points_total", "time_us"])
            {
                assert!(r[k].as_f64().unwrap() > 0.0, "{size} {p} {k}");
            }
        }
    }
    assert!(std::fs::read_dir(dir.join("svg")).unwrap().count() >= 8);
}

#[test]
fn drive_and_lidar_decode() {
    let dir = test_support::temp_dir("cli-d");
    let (j, cap, svg) = (dir.join("d.json"), dir.join("cap.ld06"), dir.join("d.svg"));
    let out = bin()
        .args([
            "drive",
            "--map",
            "maps/flat/studio.txt",
            "--cell",
            "0.1",
            "--route",
            "maps/flat/studio_tour.txt",
            "--seed",
            "3",
            "--json",
        ])
        .arg(&j)
        .arg("--capture")
        .arg(&cap)
        .arg("--svg")
        .arg(&svg)
        .current_dir(repo())
        .output()
        .unwrap();
    test_support::assert_ok(&out);
    let v: serde_json::Value = test_support::read_json(&j);
    assert_eq!(v["completed"], true);
    assert!(v["odometry"]["final_position_error_mm"].as_f64().unwrap() < 5.0);
    assert!(v["map"]["correct_share"].as_f64().unwrap() > 0.98);
    assert!(std::fs::read_to_string(&svg)
        .unwrap()
        .contains("odometry error"));
    let d = json(&[
        "lidar-decode",
        "--protocol",
        "ld06",
        cap.to_str().unwrap(),
        "--json",
    ]);
    // The capture also holds what was still on the wire when the drive ended.
    let (cf, df) = (
        d["frames"].as_u64().unwrap(),
        v["lidar"]["frames"].as_u64().unwrap(),
    );
    assert!(cf >= df && cf <= df + 2, "{cf} vs {df}");
    assert_eq!(d["crc_failures"], 0);
    assert_eq!(d["mean_speed_dps"], 3600.0);
    assert!(d["points"].as_u64().unwrap() > 0 && !d["rejected"].is_null());
    // errors: a bad route, an unknown protocol, a missing capture
    let route = dir.join("bad.txt");
    std::fs::write(&route, "1 2\nthree 4\n").unwrap();
    for args in [
        vec![
            "drive",
            "--map",
            "maps/flat/studio.txt",
            "--route",
            route.to_str().unwrap(),
        ],
        vec!["lidar-decode", "--protocol", "xv11", cap.to_str().unwrap()],
        vec!["lidar-decode", "/nonexistent.bin"],
    ] {
        let out = bin().args(&args).current_dir(repo()).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
    }
}

#[test]
fn bench_coverage_runs_every_planner_and_checks_each_plan() {
    let dir = test_support::temp_dir("bench_coverage");
    let json_path = dir.join("cov.json");
    let svg_dir = dir.join("svg");
    let out = bin()
        .args([
            "bench",
            "coverage",
            "--maps",
            "maps/flat/studio.txt,maps/movingai/maze49.map",
        ])
        .args(["--json", json_path.to_str().unwrap()])
        .args(["--svg-dir", svg_dir.to_str().unwrap()])
        .current_dir(repo())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    let rows = doc["rows"].as_array().unwrap();
    let names = robovac::coverage::PlannerKind::ALL.map(|k| k.name());
    assert_eq!(rows.len(), 2 * names.len());
    for r in rows {
        // The independent checker found every move legal and no cell missed.
        assert_eq!(r["valid"], true, "{r}");
        assert_eq!(r["metrics"]["coverage"], 1.0, "{r}");
        let name = r["planner"].as_str().unwrap();
        assert!(names.contains(&name));
        let map = r["map"].as_str().unwrap().replace('/', "_");
        let svg = svg_dir.join(format!("{map}.{name}.svg"));
        assert!(std::fs::read_to_string(svg).unwrap().starts_with("<svg"));
    }
    // A table per map with the best marked, and the summary.
    assert_eq!(text.matches("complete").count(), 2 * names.len() + 1);
    assert!(text.contains("summary over 2 maps") && text.contains('*'));
    for bad in [
        vec![
            "bench",
            "coverage",
            "--maps",
            "maps/flat/studio.txt",
            "--planners",
            "nope",
        ],
        vec![
            "bench",
            "coverage",
            "--maps",
            "maps/flat/studio.txt",
            "--cell",
            "0",
        ],
        vec!["bench", "coverage", "--maps", "/nonexistent/x.map"],
    ] {
        assert_refused(&bad);
    }
}

#[test]
fn field_planners_are_refused_at_the_firmwares_capacity() {
    let out = bin()
        .args([
            "mission",
            "--map",
            "maps/flat/studio.txt",
            "--planner",
            "stc",
            "--capacity",
            "fw",
        ])
        .current_dir(repo())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("stc") && err.trim().lines().count() == 1,
        "{err}"
    );
}
