//! Navigation: the configuration space from the evidence map, the path
//! follower, the speed guard, DWA and the potential field, the edge pass and the geometry they
//! share. Uses `math`, `grid`, `search` and `robot`.

pub mod apf;
pub mod chord;
pub mod cspace;
pub mod dwa;
pub mod edge;
pub mod follow;
pub mod geometry;
pub mod guard;
pub mod keep_off;
