//! Grid search: A*, OHA* and Theta* behind one resumable best-first loop,
//! multi-goal, with path pruning; D* Lite ([`dstar_lite`]), which keeps one
//! path up to date as cells change; and the artificial potential field
//! ([`apf`]), a local planner with its local minima. Uses `grid` and `math` only.
//!
//! The files point one way, toward the leaves: [`state`] (the state, its
//! errors and statistics: a leaf), [`heuristics`], [`theta`] (Theta*'s
//! parent update), [`open_list`] (with its bucket order, [`open_list::dial`]) and
//! [`prune`] serve [`run`], the loop.

pub mod apf;
pub mod blocks;
pub mod dstar_lite;
pub mod heuristics;
pub mod jps;
pub mod open_list;
pub mod prune;
pub mod run;
pub mod state;
pub mod theta;
pub mod window;

pub use state::{Algo, Progress, SearchError, SearchState, SearchStats, MAX_GOALS, NEIGHBOURS};
pub use window::WindowSearch;
