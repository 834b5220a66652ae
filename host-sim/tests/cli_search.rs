//! The command line's searches as a user meets them: `search`, `scen`,
//! `bench peers` and `bench replan`.

mod cli_common;

use cli_common::{assert_refused, bin, json, repo};

#[test]
fn search_json_has_the_fields() {
    let dir = test_support::temp_dir("cli-s");
    let ascii = dir.join("a.txt");
    std::fs::write(&ascii, "......\n.####.\n......\n").unwrap();
    for algo in ["astar", "oha", "theta"] {
        let j = json(&[
            "search",
            "--map",
            ascii.to_str().unwrap(),
            "--from",
            "0,1",
            "--to",
            "5,1",
            "--algo",
            algo,
            "--json",
        ]);
        assert_eq!(j["algo"], algo);
        assert!(j["nodes_expanded"].as_u64().unwrap() > 0);
        assert!(j["cost"].as_f64().unwrap() >= 5.0);
        assert!(j["pruned_length"].as_f64().unwrap() <= j["cost"].as_f64().unwrap() + 1e-9);
        assert_eq!(j["path"][0], serde_json::json!([0, 1]));
        assert!(j["time_us"].as_f64().is_some());
    }
}

/// MovingAI correctness: on our own maps (rooms, a maze of one-cell
/// corridors, an open area) and on the 512x512 8room benchmark map, with
/// optima computed independently by scripts/make_scen.py, A* has no
/// optimal mismatch and solves every problem.
#[test]
fn movingai_astar_is_optimal() {
    for m in ["rooms64", "maze49", "open96x72", "8room_001"] {
        let scen = format!("maps/movingai/{m}.map.scen");
        let map = format!("maps/movingai/{m}.map");
        let j = json(&["scen", &scen, "--map", &map, "--algo", "astar", "--json"]);
        assert_eq!(j["optimal_mismatches"], 0, "{m}: {j}");
        assert_eq!(j["solved"], j["problems"], "{m}");
        assert!(j["problems"].as_u64().unwrap() >= 200);
        assert!((j["mean_cost_ratio"].as_f64().unwrap() - 1.0).abs() < 1e-9);
        for key in ["algo", "mean_nodes_expanded", "median_query_us"] {
            assert!(!j[key].is_null(), "{key}");
        }
        // OHA* and Theta* solve everything too; OHA* never beats the optimum.
        let o = json(&["scen", &scen, "--map", &map, "--algo", "oha", "--json"]);
        assert_eq!(o["solved"], o["problems"]);
        assert!(o["mean_cost_ratio"].as_f64().unwrap() >= 1.0 - 1e-9);
        assert!(
            o["mean_nodes_expanded"].as_f64().unwrap() < j["mean_nodes_expanded"].as_f64().unwrap()
        );
        let t = json(&["scen", &scen, "--map", &map, "--algo", "theta", "--json"]);
        assert_eq!(t["solved"], t["problems"]);
        // A* with the octile heuristic: optimal too, fewer nodes.
        let q = json(&[
            "scen",
            &scen,
            "--map",
            &map,
            "--algo",
            "astar-octile",
            "--json",
        ]);
        assert_eq!(q["optimal_mismatches"], 0, "{m}: {q}");
        assert_eq!(q["solved"], q["problems"]);
        assert!(
            q["mean_nodes_expanded"].as_f64().unwrap()
                <= j["mean_nodes_expanded"].as_f64().unwrap()
        );
        // Jump point search: optimal, and only the jump points expanded.
        let p = json(&["scen", &scen, "--map", &map, "--algo", "jps", "--json"]);
        assert_eq!(p["optimal_mismatches"], 0, "{m}: {p}");
        assert_eq!(p["solved"], p["problems"]);
        assert!(
            p["mean_nodes_expanded"].as_f64().unwrap()
                < q["mean_nodes_expanded"].as_f64().unwrap() / 2.0,
            "{m}: {p}"
        );
    }
}

/// The baselines: breadth-first search solves every problem with paths
/// never shorter than the optimum; depth-first search solves every one.
#[test]
fn movingai_bfs_and_dfs_baselines() {
    for m in ["rooms64", "maze49"] {
        let scen = format!("maps/movingai/{m}.map.scen");
        let map = format!("maps/movingai/{m}.map");
        for algo in ["bfs", "dfs"] {
            let j = json(&["scen", &scen, "--map", &map, "--algo", algo, "--json"]);
            assert_eq!(j["solved"], j["problems"], "{m} {algo}");
            assert!(
                j["mean_cost_ratio"].as_f64().unwrap() >= 1.0 - 1e-9,
                "{m} {algo}: {j}"
            );
        }
    }
}

/// `bench peers`: ours and the `pathfinding` crate's A* on the same
/// queries, every engine optimal on every one, and the ratio printed.
#[test]
fn bench_peers_runs_both_engines_on_the_same_queries() {
    let j = json(&[
        "bench",
        "peers",
        "--scen",
        "maps/movingai/maze49.map.scen",
        "--map",
        "maps/movingai/maze49.map",
        "--json",
    ]);
    let engines = j["engines"].as_array().unwrap();
    assert_eq!(engines.len(), 4);
    for e in engines {
        assert_eq!(e["solved"], j["problems"], "{e}");
        assert_eq!(e["optimal_mismatches"], 0, "{e}");
        assert!(e["median_us"].as_f64().unwrap() > 0.0);
    }
    assert!(j["ratio"].as_f64().unwrap() > 0.0);
    assert!(j["jps_ratio"].as_f64().unwrap() > 0.0);
    let out = bin()
        .args([
            "bench",
            "peers",
            "--scen",
            "nope.scen",
            "--map",
            "maps/movingai/maze49.map",
        ])
        .current_dir(repo())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// `search` on rooms64 from (55,45) to (11,43) with `algo`, as JSON.
fn rooms64_search(algo: &str) -> serde_json::Value {
    json(&[
        "search",
        "--map",
        "maps/movingai/rooms64.map",
        "--from",
        "55,45",
        "--to",
        "11,43",
        "--algo",
        algo,
        "--json",
    ])
}

/// D* Lite on the command line: `search --algo dstar-lite` finds A*
/// octile's cost and `scen` solves every problem optimally; `bench replan`
/// repairs as many plans as A* searches again with no cost mismatch and
/// fewer nodes; its refusals are one line and exit code 2.
#[test]
fn dstar_lite_plans_and_repairs() {
    let (d, a) = (rooms64_search("dstar-lite"), rooms64_search("astar-octile"));
    assert_eq!(d["algo"], "dstar-lite");
    assert!((d["cost"].as_f64().unwrap() - a["cost"].as_f64().unwrap()).abs() < 1e-9);
    let replan = |flag: &'static str, value: &'static str| {
        vec![
            "bench",
            "replan",
            "--scen",
            "maps/movingai/rooms64.map.scen",
            "--map",
            "maps/movingai/rooms64.map",
            flag,
            value,
        ]
    };
    let mut args = replan("--problems", "12");
    args.push("--json");
    let j = json(&args);
    assert_eq!(j["mismatches"], 0, "{j}");
    let (first, repair, astar) = (&j["engines"][0], &j["engines"][1], &j["engines"][2]);
    assert_eq!(first["replans"], 12, "{j}");
    assert_eq!(repair["replans"], astar["replans"], "{j}");
    assert!(repair["replans"].as_u64().unwrap() > 0, "{j}");
    assert!(
        repair["mean_nodes"].as_f64() < astar["mean_nodes"].as_f64(),
        "{j}"
    );
    let ended = ["at_goal", "cut_off", "all_changes"].map(|k| j[k].as_u64().unwrap());
    assert_eq!(ended.iter().sum::<u64>(), 12, "{j}");
    for args in [replan("--side", "2"), replan("--every", "0")] {
        assert_refused(&args);
    }
}

/// `bench replan --to-dock`: ways home to a real home's charger on its
/// configuration space, D* Lite and A* agreeing on every replan's cost; a
/// map with no charger, or both a scenario and `--to-dock`, is refused with
/// one line and exit code 2.
#[test]
fn replan_measures_ways_home_on_a_real_home() {
    let home = "maps/valetudo/S8_FW1286_with_obstacles.json";
    let args = [
        "bench",
        "replan",
        "--to-dock",
        "--map",
        home,
        "--problems",
        "10",
        "--every",
        "20",
        "--ahead",
        "10",
        "--side",
        "9",
        "--json",
    ];
    let j = json(&args);
    assert_eq!(j["mismatches"], 0, "{j}");
    let (first, repair, astar) = (&j["engines"][0], &j["engines"][1], &j["engines"][2]);
    assert_eq!(first["replans"], 10, "{j}");
    assert_eq!(repair["replans"], astar["replans"], "{j}");
    assert!(repair["replans"].as_u64().unwrap() > 0, "{j}");
    let no_dock = [
        "bench",
        "replan",
        "--to-dock",
        "--map",
        "maps/movingai/rooms64.map",
    ];
    let both = [
        "bench",
        "replan",
        "--to-dock",
        "--scen",
        "maps/movingai/rooms64.map.scen",
        "--map",
        "maps/movingai/rooms64.map",
    ];
    for args in [&no_dock[..], &both[..]] {
        assert_refused(args);
    }
}

/// The potential field on the command line: on rooms64 some problems end
/// at a local minimum, shown in `scen`'s report and in `search`'s JSON;
/// D* Lite solves every one optimally.
#[test]
fn scen_runs_dstar_lite_and_shows_the_fields_local_minima() {
    let scen = |algo: &str| {
        json(&[
            "scen",
            "maps/movingai/rooms64.map.scen",
            "--map",
            "maps/movingai/rooms64.map",
            "--algo",
            algo,
            "--json",
        ])
    };
    let d = scen("dstar-lite");
    assert_eq!(d["solved"], d["problems"], "{d}");
    assert_eq!(d["optimal_mismatches"], 0, "{d}");
    let a = scen("apf");
    let solved = a["solved"].as_u64().unwrap();
    assert!(
        solved > 0 && solved < a["problems"].as_u64().unwrap(),
        "{a}"
    );
    assert!(
        a["mismatch_examples"].to_string().contains("local minimum"),
        "{a}"
    );
    let s = rooms64_search("apf");
    assert_eq!(s["reached"], false, "{s}");
    assert_eq!(s["local_minimum"], serde_json::json!([49, 43]), "{s}");
}
