//! The coverage planners by name: the one `match` on the planner kind,
//! which names each planner's [`Rules`]. Uses the planner files.

use super::planners::{
    b_oha, b_oha_pc, b_theta, ba_star, bcd, binn, mark_backtrack, regions, stc, template, wavefront,
};
use super::rules::Rules;

/// The coverage planners.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PlannerKind {
    /// B-OHA*, seed 000 (ALGORITHMS.md §1).
    BOha = 0,
    /// BA* (Viet et al. 2013), the paper's first baseline.
    BaStar,
    /// B-Theta* (Choi et al. 2017), the paper's second baseline.
    BTheta,
    /// B-OHA*-PC: our variant of B-OHA* (see [`crate::coverage::planners::b_oha_pc`]).
    BOhaPc,
    /// The efficient template method, seed 002 (ALGORITHMS.md §3).
    Template,
    /// Mark backtracking with closed areas, seed 001 (ALGORITHMS.md §2).
    MarkBacktrack,
    /// The bio-inspired neural network, seed 004 (ALGORITHMS.md §5).
    Binn,
    /// Wavefront coverage, seed 004 (ALGORITHMS.md §5).
    Wavefront,
    /// Spanning-tree coverage, seed 004 (ALGORITHMS.md §5).
    Stc,
    /// Boustrophedon cell decomposition, seed 004 (ALGORITHMS.md §5).
    Bcd,
    /// Region decomposition with spiral and comb, seed 003 (ALGORITHMS.md
    /// §4).
    Regions,
}

impl PlannerKind {
    /// Every coverage planner: seed 000's (baselines first), then seeds
    /// 001, 002 and 004's.
    pub const ALL: [PlannerKind; 11] = [
        PlannerKind::BaStar,
        PlannerKind::BTheta,
        PlannerKind::BOha,
        PlannerKind::BOhaPc,
        PlannerKind::MarkBacktrack,
        PlannerKind::Template,
        PlannerKind::Binn,
        PlannerKind::Wavefront,
        PlannerKind::Stc,
        PlannerKind::Bcd,
        PlannerKind::Regions,
    ];

    /// The name used on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            PlannerKind::BOha => "b-oha",
            PlannerKind::BaStar => "ba",
            PlannerKind::BTheta => "b-theta",
            PlannerKind::BOhaPc => "b-oha-pc",
            PlannerKind::Template => "template",
            PlannerKind::MarkBacktrack => "mark-backtrack",
            PlannerKind::Binn => "binn",
            PlannerKind::Wavefront => "wavefront",
            PlannerKind::Stc => "stc",
            PlannerKind::Bcd => "bcd",
            PlannerKind::Regions => "regions",
        }
    }

    /// The planner's rules: the one `match` on the kind.
    pub const fn rules(self) -> Rules {
        match self {
            PlannerKind::BOha => b_oha::RULES,
            PlannerKind::BaStar => ba_star::RULES,
            PlannerKind::BTheta => b_theta::RULES,
            PlannerKind::BOhaPc => b_oha_pc::RULES,
            PlannerKind::Template => template::RULES,
            PlannerKind::MarkBacktrack => mark_backtrack::RULES,
            PlannerKind::Binn => binn::RULES,
            PlannerKind::Wavefront => wavefront::RULES,
            PlannerKind::Stc => stc::RULES,
            PlannerKind::Bcd => bcd::RULES,
            PlannerKind::Regions => regions::RULES,
        }
    }
}
