//! The whole mission on the chip (issue 11 §3): the buffers of a home
//! whose bounding box is up to `side` × `side` evidence cells of 5 cm,
//! planned on 0.3 m cells, at two settings written once by
//! [`home_capacity`]:
//! - [`home12`]: 12 × 12 m (about 100 m² of floor) on the F411's 128 KiB;
//! - [`home16`]: 16 × 16 m (256 m² of bounding box) on an F405/F407's
//!   192 KiB, which is 128 KiB of SRAM and 64 KiB of core-coupled RAM
//!   (CCM): the robot image puts the evidence map in the CCM
//!   (`memory-f407.x`).
//!
//! Every structure's bytes are asserted at compile time, per setting, so
//! that nothing grows unnoticed; the stack left is measured by the size
//! report and the processor-in-the-loop run (its high-water mark).

/// Side of the fine searches' window, cells (2.4 m at 5 cm).
pub const FW_WINDOW_SIDE: usize = 48;
/// The fine path buffer (detours, edge transits, the way home's legs).
/// 512 cells is 25 m of path at 5 cm, and a leg is bounded by the 2.4 m
/// window; it also lends the room split its wavefront queue.
pub const FW_FINE_PATH: usize = 512;
/// Bytes of the executive itself (lidar ring and revolution, queues,
/// events, localisation state): the same at every capacity.
pub const FW_EXECUTIVE_BYTES: usize = core::mem::size_of::<crate::mission::Mission>();
const _: () = assert!(FW_EXECUTIVE_BYTES <= 20_776);

/// Writes one capacity setting: its sizes, its types and `Parts`, and
/// the compile-time bounds on each structure's bytes.
macro_rules! home_capacity {
    (
        $(#[$doc:meta])*
        $name:ident {
            side: $side:expr,
            plan_side: $plan_side:expr,
            bytes: {
                planner: $planner:expr,
                window: $window:expr,
                plan_grid: $plan_grid:expr,
                fine_grid: $fine_grid:expr,
                evidence: $evidence:expr,
                matcher: $matcher:expr,
                mission: $mission:expr $(,)?
            } $(,)?
        }
    ) => {
        $(#[$doc])*
        pub mod $name {
            use crate::grid::Grid;
            use crate::math::bits::words_for;
            pub use super::{FW_EXECUTIVE_BYTES, FW_FINE_PATH, FW_WINDOW_SIDE};

            /// The home's side in 5 cm evidence cells.
            pub const FW_HOME_SIDE: usize = $side;
            /// Words of the scan matcher's coarse levels for that home.
            pub const FW_MATCH_WORDS: usize =
                crate::localize::matcher_words(FW_HOME_SIDE, FW_HOME_SIDE);
            /// The scan matcher: the coarse levels (4 bits a block at 10,
            /// 20, 40 cm) and the points (224 × 8 bytes), beyond the
            /// evidence map. The searches' candidates live on the stack
            /// (12 candidates, about 1 KiB).
            pub type FwMatcher = crate::localize::ScanMatcher<FW_MATCH_WORDS>;
            /// Evidence (fine) cells of the home.
            pub const FW_FINE_CELLS: usize = FW_HOME_SIDE * FW_HOME_SIDE;
            /// Bitset words of the fine configuration space.
            pub const FW_FINE_WORDS: usize = words_for(FW_FINE_CELLS);
            /// Planning cells a side: the home at 0.3 m, plus one for a
            /// partial cell.
            pub const FW_PLAN_SIDE: usize = $plan_side;
            const _: () = assert!(FW_PLAN_SIDE * 300 >= FW_HOME_SIDE * 50);
            /// Planning cells of the home.
            pub const FW_PLAN_CELLS: usize = FW_PLAN_SIDE * FW_PLAN_SIDE;
            /// Cells of the fine searches' window.
            pub const FW_WINDOW_CELLS: usize = FW_WINDOW_SIDE * FW_WINDOW_SIDE;
            /// Cells of the one search state, shared in time by the
            /// planner (on the planning cells) and the fine searches (on
            /// the window): the larger of the two.
            pub const FW_SEARCH_CELLS: usize = if FW_PLAN_CELLS > FW_WINDOW_CELLS {
                FW_PLAN_CELLS
            } else {
                FW_WINDOW_CELLS
            };
            /// Bitset words of the shared search state (and of the
            /// planning grid and the window's copy of the obstacles, which
            /// share its `NW`).
            pub const FW_SEARCH_WORDS: usize = words_for(FW_SEARCH_CELLS);
            /// The shared search state's open list.
            pub const FW_SEARCH_OPEN: usize = 512;
            /// The planner's backtracking list.
            pub const FW_PLAN_LCAP: usize = 512;
            /// The planner's transit path buffer.
            pub const FW_PLAN_PCAP: usize = 512;

            /// The mission's coverage planner, owner of the shared search
            /// state.
            pub type FwPlanner = crate::coverage::Coverage<
                FW_SEARCH_CELLS,
                FW_SEARCH_WORDS,
                FW_SEARCH_OPEN,
                FW_PLAN_LCAP,
                FW_PLAN_PCAP,
            >;
            /// The mission's fine searches (the window and its goals; they
            /// run on the planner's search state).
            pub type FwWindow = crate::search::WindowSearch<FW_SEARCH_CELLS, FW_SEARCH_WORDS>;
            /// The mission's planning grid.
            pub type FwPlanGrid = Grid<FW_SEARCH_WORDS>;
            /// The mission's fine configuration space.
            pub type FwFineGrid = Grid<FW_FINE_WORDS>;
            /// Bytes of the evidence map's cells (4 bits a cell).
            pub const FW_EVIDENCE_CELL_BYTES: usize =
                crate::robot::lidar_map::evidence_bytes(FW_FINE_CELLS);
            /// The mission's evidence map.
            pub type FwEvidence = crate::robot::lidar_map::EvidenceMap<FW_EVIDENCE_CELL_BYTES>;
            /// The mission's buffers, lent to the executive.
            pub type FwParts<'a> = crate::mission::Parts<
                'a,
                FW_SEARCH_CELLS,
                FW_SEARCH_WORDS,
                FW_SEARCH_OPEN,
                FW_PLAN_LCAP,
                FW_PLAN_PCAP,
                FW_FINE_WORDS,
                FW_EVIDENCE_CELL_BYTES,
                FW_MATCH_WORDS,
                0,
            >;

            /// Bytes of the planner (planning grid search state, open
            /// list, backtracking list, transit path).
            pub const FW_PLANNER_BYTES: usize = core::mem::size_of::<FwPlanner>();
            const _: () = assert!(FW_PLANNER_BYTES <= $planner);
            /// Bytes of the fine searches' window (search state, open
            /// list, the window's copy of the obstacles).
            pub const FW_WINDOW_BYTES: usize = core::mem::size_of::<FwWindow>();
            const _: () = assert!(FW_WINDOW_BYTES <= $window);
            /// Bytes of the planning grid (three bit layers).
            pub const FW_PLAN_GRID_BYTES: usize = core::mem::size_of::<FwPlanGrid>();
            const _: () = assert!(FW_PLAN_GRID_BYTES <= $plan_grid);
            /// Bytes of the fine configuration space (three bit layers).
            pub const FW_FINE_GRID_BYTES: usize = core::mem::size_of::<FwFineGrid>();
            const _: () = assert!(FW_FINE_GRID_BYTES <= $fine_grid);
            /// Bytes of the evidence map (two cells a byte).
            pub const FW_EVIDENCE_BYTES: usize = core::mem::size_of::<FwEvidence>();
            const _: () = assert!(FW_EVIDENCE_BYTES <= $evidence);
            /// Bytes of the scan matcher.
            pub const FW_MATCHER_BYTES: usize = core::mem::size_of::<FwMatcher>();
            const _: () = assert!(FW_MATCHER_BYTES <= $matcher);
            /// Every buffer of the mission, stack excluded.
            pub const FW_MISSION_BYTES: usize = FW_PLANNER_BYTES
                + FW_WINDOW_BYTES
                + FW_PLAN_GRID_BYTES
                + FW_FINE_GRID_BYTES
                + FW_EVIDENCE_BYTES
                + FW_MATCHER_BYTES
                + FW_FINE_PATH * 4
                + FW_PLAN_CELLS
                + FW_EXECUTIVE_BYTES;
            const _: () = assert!(FW_MISSION_BYTES <= $mission);
        }
    };
}

home_capacity! {
    /// The F411's capacity: a home whose bounding box is up to 12 × 12 m
    /// (about 100 m² of floor; every home in `../shared/maps/valetudo`).
    ///
    /// Its buffers come to about 118,800 bytes as laid out on the host (a
    /// little less on thumbv7em, where `usize` is 4 bytes), of the F411's
    /// 131,072: one search state shared in time by the planner and the
    /// fine searches (167,136 with two) and evidence cells of 4 bits
    /// (147,196 with bytes). The rooms' labels (1,681 bytes,
    /// [`crate::grid::rooms`]) were paid for by halving the fine path
    /// (2,048 bytes); the edge pass's chord ([`crate::nav::chord`]) is
    /// about 200 bytes of the executive; the open list's dial
    /// ([`crate::search::open_list::dial`]) 296 bytes of the planner and
    /// the neighbour steps 32; the potential field's parameters and state
    /// (the local planner beside DWA, [`crate::nav::apf`]) 56 of the
    /// executive, and the counter of legs planned again when the map came
    /// to block them 8; the walls the control loop keeps off
    /// ([`crate::nav::keep_off`]) and the time a person was last beside
    /// the body 72, and the transits' own keep-off 16; the cleaning goals
    /// the fine search found no way to ([`crate::mission::SKIPPED_GOALS`])
    /// 72; a boxed-in search's wait ([`crate::mission::BOXED_NODES`] and
    /// [`crate::mission::BOXED_PLAN_NODES`]) 32; where the edge pass last
    /// rejoined its dropped queue 8; the places bumped last and their
    /// counts (`BUMP_PLACES` in `src/mission/bump.rs`) 48, and the two
    /// places where the edge pass gave sub-paths up lately 24. The matcher stays
    /// within the 16 KiB beyond the evidence map (9,452 bytes of
    /// levels).
    home12 {
        side: 240,
        plan_side: 41,
        bytes: {
            planner: 30_868,
            window: 1_200,
            plan_grid: 900,
            fine_grid: 21_700,
            evidence: 29_060,
            matcher: 16 * 1024,
            mission: 118_593,
        },
    }
}

home_capacity! {
    /// The F405/F407's capacity (feature `home16`): a home whose bounding
    /// box is up to 16 × 16 m, 256 m². A 250 m² home fits when its
    /// bounding box does; a sprawling one (the 12 m setting's ratio of
    /// floor to box would ask 19 × 19 m) needs about 240 KiB with these
    /// structures, more than the chip has.
    ///
    /// Its buffers come to about 185,000 bytes: the robot image puts the
    /// evidence map (51,200 bytes of cells) in the 64 KiB CCM and the rest
    /// in the 128 KiB SRAM with the stack.
    home16 {
        side: 320,
        plan_side: 54,
        bytes: {
            planner: 60_000,
            window: 2_000,
            plan_grid: 2_000,
            fine_grid: 40_000,
            evidence: 52_000,
            matcher: 20_000,
            mission: 200_000,
        },
    }
}
