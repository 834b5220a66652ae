//! `host-sim demo`: plans on the built-in flat and shows it in the terminal.

use robovac::maps::FLAT_40X20;
use robovac::prune::prune;
use robovac::{Algo, Cell};

use crate::metrics::polyline_length;
use crate::state::{new_grid, new_search};

/// Renders a map with a path: `#` obstacle, `*` path cell, `S`/`G` ends,
/// `o` pruned waypoints.
pub fn render(
    grid: &robovac::Grid<{ crate::state::HOST_WORDS }>,
    path: &[Cell],
    waypoints: &[Cell],
) -> String {
    let mut out = String::new();
    for y in 0..grid.height() as i32 {
        for x in 0..grid.width() as i32 {
            let c = Cell::from_xy(x, y);
            let ch = if path.first().copied() == c {
                'S'
            } else if path.last().copied() == c {
                'G'
            } else if c.is_some_and(|c| waypoints.contains(&c)) {
                'o'
            } else if c.is_some_and(|c| path.contains(&c)) {
                '*'
            } else if grid.is_blocked(x, y) {
                '#'
            } else {
                '.'
            };
            out.push(ch);
        }
        out.push('\n');
    }
    out
}

/// Runs the demo and returns the text it shows.
pub fn run() -> Result<String, String> {
    let mut grid = new_grid();
    grid.load_ascii(FLAT_40X20).map_err(|e| e.to_string())?;
    let mut state = new_search();
    let (start, goal) = (Cell::new(1, 1), Cell::new(38, 18));
    let stats = state
        .search(&*grid, start, &[goal], Algo::Oha)
        .map_err(|e| e.to_string())?;
    let mut path = vec![Cell::default(); grid.cells()];
    let n = state.write_path(&mut path).map_err(|e| e.to_string())?;
    let full: Vec<Cell> = path[..n].to_vec();
    let m = prune(&*grid, &mut path[..n]);
    let mut s = String::from("robovac demo: OHA* across the built-in 40x20 flat\n\n");
    s += &render(&grid, &full, &path[..m]);
    s += &format!(
        "\npath {} cells, cost {:.2} cells, {} waypoints after pruning ({:.2} cells), {} nodes expanded\n",
        n,
        polyline_length(&full),
        m,
        polyline_length(&path[..m]),
        stats.nodes_expanded
    );
    Ok(s)
}
