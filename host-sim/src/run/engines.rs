//! Every point-to-point search behind one call, for `search` and `scen`:
//! the best-first searches of the core's loop, D* Lite (one plan) and the
//! artificial potential field (a walk that may end at a local minimum).

use robovac::search::apf::{descend, ApfEnd, APF_DEFAULT};
use robovac::search::SearchError;
use robovac::{Algo, Cell};

use crate::capacity::{new_search, HostGrid, HostSearch};
use crate::io::scen::algo_name;
use crate::run::replan::{new_dstar, HostDStar};

/// A point-to-point search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    /// A* (either heuristic), OHA*, Theta*, BFS or DFS.
    BestFirst(Algo),
    /// D* Lite's first plan.
    DStarLite,
    /// The artificial potential field.
    Apf,
}

impl Engine {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Engine::BestFirst(a) => algo_name(a),
            Engine::DStarLite => "dstar-lite",
            Engine::Apf => "apf",
        }
    }
}

/// One plan: the path's cells, the nodes expanded (for the field, the cells
/// walked), and where a field walk was held when it did not reach the goal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Planned {
    /// Cells on the path written out, start included.
    pub cells: usize,
    /// Nodes expanded (the field: cells walked).
    pub nodes: u32,
    /// The field's local minimum, when the walk ended there.
    pub local_minimum: Option<Cell>,
}

/// The engines' states, made once and reused query after query (D* Lite's
/// on first use).
pub struct Engines {
    search: Box<HostSearch>,
    dstar: Option<Box<HostDStar>>,
}

impl Default for Engines {
    fn default() -> Self {
        Self::new()
    }
}

impl Engines {
    /// Fresh states.
    pub fn new() -> Self {
        Self {
            search: new_search(),
            dstar: None,
        }
    }

    /// Plans from `from` to `to` with `engine`, writing the path into `path`.
    pub fn plan(
        &mut self,
        engine: Engine,
        grid: &HostGrid,
        from: Cell,
        to: Cell,
        path: &mut [Cell],
    ) -> Result<Planned, SearchError> {
        let plain = |cells, nodes| Planned {
            cells,
            nodes,
            local_minimum: None,
        };
        match engine {
            Engine::BestFirst(algo) => {
                let stats = self.search.search(grid, from, &[to], algo)?;
                Ok(plain(self.search.write_path(path)?, stats.nodes_expanded))
            }
            Engine::DStarLite => {
                let d = self.dstar.get_or_insert_with(new_dstar);
                d.begin(grid, from, to)?;
                let r = d.compute(grid)?;
                Ok(plain(d.write_path(grid, path)?, r.nodes_expanded))
            }
            Engine::Apf => {
                let w = descend(grid, from, to, APF_DEFAULT, path)?;
                Ok(Planned {
                    local_minimum: (w.end == ApfEnd::LocalMinimum).then_some(w.at),
                    ..plain(w.cells, w.cells as u32)
                })
            }
        }
    }
}
