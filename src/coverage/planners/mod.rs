//! One file per coverage planner, each naming its [`super::rules::Rules`]
//! and holding its own list and move rules. Uses the coverage layer's
//! leaves (`cells`, `list`, `rules`), `grid` and `search`; never the loop.

pub mod b_oha;
pub mod b_oha_pc;
pub mod b_theta;
pub mod ba_star;
pub mod bcd;
pub mod binn;
pub mod mark_backtrack;
pub mod regions;
pub mod stc;
pub mod template;
pub mod wavefront;
