//! The real floor maps in ../shared/maps (kept out of the repository for
//! their licence): each loads, resampled to 0.3 m robot cells and at full
//! resolution, and A* finds an optimal path across its largest free area.
//! Skipped, with a message, where shared/ is not beside the repository.

use std::path::PathBuf;

use host_sim::capacity::{new_grid, new_search};
use host_sim::io::maps::{load_map, LoadOptions};
use host_sim::report::metrics::check_polyline;
use robovac::{Algo, Cell};

fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/maps");
    p.is_dir().then_some(p)
}

/// The two free cells farthest apart (by BFS) in the largest component.
fn far_pair(m: &host_sim::io::maps::MapData) -> Option<(Cell, Cell)> {
    let (w, h) = (m.width as i32, m.height as i32);
    let mut comp = vec![u32::MAX; (w * h) as usize];
    let mut best: (usize, usize) = (0, 0);
    let mut id = 0u32;
    for start in 0..(w * h) as usize {
        if m.blocked[start] || comp[start] != u32::MAX {
            continue;
        }
        let mut q = std::collections::VecDeque::from([start]);
        comp[start] = id;
        let mut n = 0;
        while let Some(i) = q.pop_front() {
            n += 1;
            let (x, y) = ((i as i32) % w, (i as i32) / w);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                if !m.is_blocked(x + dx, y + dy) {
                    let j = ((y + dy) * w + x + dx) as usize;
                    if comp[j] == u32::MAX {
                        comp[j] = id;
                        q.push_back(j);
                    }
                }
            }
        }
        if n > best.1 {
            best = (start, n);
        }
        id += 1;
    }
    let c = comp[best.0];
    let cells: Vec<usize> = (0..(w * h) as usize).filter(|&i| comp[i] == c).collect();
    let a = *cells.first()?;
    let b = *cells.last()?;
    Some((
        Cell::new((a as i32 % w) as u16, (a as i32 / w) as u16),
        Cell::new((b as i32 % w) as u16, (b as i32 / w) as u16),
    ))
}

#[test]
fn real_maps_load_and_plan() {
    let Some(dir) = shared() else {
        eprintln!("../shared/maps not found: real-map test skipped");
        return;
    };
    let mut grid = new_grid();
    let mut st = new_search();
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !matches!(ext, "png" | "map" | "yaml" | "pgm") {
            continue;
        }
        for cell in [None, Some(0.3)] {
            if ext == "map" && cell.is_some() {
                continue;
            }
            let m = load_map(
                &p,
                LoadOptions {
                    cell_m: cell,
                    png_resolution_m: None,
                },
            )
            .unwrap_or_else(|e| panic!("{e}"));
            let free = m.blocked.iter().filter(|b| !**b).count();
            assert!(free > 0, "{}: no free cell", p.display());
            if let Err(e) = m.to_grid(&mut *grid) {
                // Full-resolution scans may exceed the host's 1024x1024 cells:
                // that is a clear error, and resampled they must fit.
                assert!(
                    cell.is_none() && e.to_string().contains("exceeds the capacity"),
                    "{e}"
                );
                eprintln!("{}: {e}", p.display());
                continue;
            }
            let (s, t) = far_pair(&m).unwrap();
            let stats = st
                .search(&*grid, s, &[t], Algo::AStar)
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            let mut path = vec![Cell::default(); grid.cells()];
            let n = st.write_path(&mut path).unwrap();
            check_polyline(&m, &path[..n]).unwrap();
            eprintln!(
                "{} cell {:?}: {}x{}, {} free, A* {:.1} cells, {} nodes",
                p.file_name().unwrap().to_string_lossy(),
                m.cell_m,
                m.width,
                m.height,
                free,
                stats.cost as f64 / 5741.0,
                stats.nodes_expanded
            );
            seen += 1;
            if cell.is_some() {
                for kind in host_sim::run::plan::ALL_PLANNERS {
                    let p = host_sim::run::plan::plan(&m, kind, Some(s))
                        .unwrap_or_else(|e| panic!("{e}"));
                    let mut ck: Box<
                        robovac::verify::check::Checker<{ host_sim::capacity::HOST_WORDS }>,
                    > = Box::new(robovac::verify::check::Checker::new());
                    ck.start(&*grid, s).unwrap();
                    for w in &p.moves {
                        ck.push(&*grid, w.to, w.kind, w.starts_segment)
                            .unwrap_or_else(|e| panic!("{}: {e:?}", p.kind.name()));
                    }
                    let c = ck.finish(&*grid);
                    assert_eq!(c.missed_cells, 0, "{}", kind.name());
                    eprintln!(
                        "  {}: coverage {:.4}, backtracking {:.1} cells, {} segments",
                        kind.name(),
                        p.coverage(),
                        p.metrics.backtrack_path_cost as f64 / 5741.0,
                        p.metrics.segments
                    );
                }
            }
        }
    }
    assert!(seen >= 6, "expected the shared maps, found {seen}");
}
