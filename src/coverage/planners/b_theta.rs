//! B-Theta* (Choi, Lee, Viet and Chung, JIRS 2017), the second baseline of
//! seed 000 (ALGORITHMS.md §1): BA*'s boustrophedon motion and backtracking
//! list ([`super::ba_star`]), with the path to the backtracking points
//! planned by multi-goal Theta* (any-angle, [`crate::search::theta`]) toward
//! the [`MAX_GOALS`] nearest points. Theta* paths are already any-angle, so
//! they are followed as found, without pruning.

use super::ba_star;
use crate::coverage::rules::Rules;
use crate::search::{Algo, MAX_GOALS};

/// BA*'s rules with multi-goal Theta* transits, followed unpruned.
pub const RULES: Rules = Rules {
    transit_goals: MAX_GOALS,
    transit: Algo::Theta,
    prune_transit: false,
    ..ba_star::RULES
};
