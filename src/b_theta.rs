//! B-Theta* (Choi, Lee, Viet and Chung, JIRS 2017), the second baseline of
//! seed 000 (ALGORITHMS.md §1): BA*'s boustrophedon motion and backtracking
//! list ([`crate::ba_star`]), with the path to the backtracking points
//! planned by multi-goal Theta* (any-angle, [`crate::theta_star`]) toward
//! the [`MAX_GOALS`] nearest points. Theta* paths are already any-angle, so
//! they are followed as found, without pruning.

use crate::search::{Algo, MAX_GOALS};

/// Goals per transit and the search used.
pub const TRANSIT: (usize, Algo) = (MAX_GOALS, Algo::Theta);
