//! Every compile-time capacity of the firmware, in one place.
//!
//! The search state costs 8 bytes per cell (u32 g-score and u32 parent; the
//! parent must be a full index because Theta* parents can be any cell), two
//! bits per cell of bitsets, and 12 bytes per open-list entry. The STM32F411
//! has 128 KiB of RAM, so the firmware plans on maps of up to 64 × 64 cells
//! (19.2 m square at 0.3 m cells): 45 KiB of search state. A 128 × 128 map
//! needs 184 KiB and an STM32F4 with more RAM; its size is asserted below so
//! that any growth of the state is caught at compile time.

use crate::grid::Grid;
use crate::math::bits::words_for;
use crate::search::SearchState;

/// Largest firmware map side, in cells.
pub const FW_SIDE: usize = 64;
/// Largest firmware map, in cells.
pub const FW_CELLS: usize = FW_SIDE * FW_SIDE;
/// Bitset words for the firmware map.
pub const FW_WORDS: usize = words_for(FW_CELLS);
/// Firmware open-list capacity (entries).
pub const FW_OPEN: usize = 1024;

/// The firmware's grid.
pub type FwGrid = Grid<FW_WORDS>;
/// The firmware's search state.
pub type FwSearch = SearchState<FW_CELLS, FW_WORDS, FW_OPEN>;

/// Cells of the 100 × 50 benchmark map of seed 000's Table 1.
pub const BENCH_CELLS: usize = 100 * 50;
/// Bitset words for the 100 × 50 map.
pub const BENCH_WORDS: usize = words_for(BENCH_CELLS);
/// Open-list capacity for the 100 × 50 map.
pub const BENCH_OPEN: usize = 2048;
/// A grid for the 100 × 50 benchmark (used by the emulated run).
pub type BenchGrid = Grid<BENCH_WORDS>;
/// A search state for the 100 × 50 benchmark (used by the emulated run).
pub type BenchSearch = SearchState<BENCH_CELLS, BENCH_WORDS, BENCH_OPEN>;

/// Cells at the reference 128 × 128 capacity.
pub const REF128_CELLS: usize = 128 * 128;
/// Bitset words at 128 × 128.
pub const REF128_WORDS: usize = words_for(REF128_CELLS);
/// Open-list capacity at 128 × 128.
pub const REF128_OPEN: usize = 4096;
/// The search state at the reference 128 × 128 capacity.
pub type Search128 = SearchState<REF128_CELLS, REF128_WORDS, REF128_OPEN>;
/// The grid at the reference 128 × 128 capacity.
pub type Grid128 = Grid<REF128_WORDS>;

/// Bytes of search state per the layout above, without the small fixed part.
pub const fn search_state_bytes(cells: usize, open: usize) -> usize {
    cells * 8 + 2 * words_for(cells) * 4 + open * 12
}

/// Fixed part of the search state: goal list (64 cells), query fields,
/// the neighbour index steps (32 bytes), and the open list's dial (288
/// bytes, [`crate::search::open_list::dial`])
/// with its order and the row divider.
pub const SEARCH_FIXED_BYTES_MAX: usize = 64 * 4 + 64 + 320;

/// 128 × 128: 131 072 (g, parent) + 4 096 (bitsets) + 49 152 (open list)
/// = 184 320 bytes plus at most 480 fixed.
pub const SEARCH128_BYTES: usize = core::mem::size_of::<Search128>();
const _: () = assert!(SEARCH128_BYTES >= search_state_bytes(REF128_CELLS, REF128_OPEN));
const _: () = assert!(
    SEARCH128_BYTES <= search_state_bytes(REF128_CELLS, REF128_OPEN) + SEARCH_FIXED_BYTES_MAX
);
const _: () = assert!(SEARCH128_BYTES <= 184_960);

/// The grid at 128 × 128: three 2 KiB layers plus the size.
pub const GRID128_BYTES: usize = core::mem::size_of::<Grid128>();
const _: () = assert!(GRID128_BYTES <= 3 * 2048 + 8);

/// The firmware's search state fits comfortably in the F411's 128 KiB.
pub const FW_SEARCH_BYTES: usize = core::mem::size_of::<FwSearch>();
const _: () = assert!(FW_SEARCH_BYTES <= 46 * 1024);

/// Backtracking-list capacity at 128 × 128 (points; overflow is handled by
/// the rescan policy of [`crate::coverage`]).
pub const REF128_LCAP: usize = 1024;
/// Transit path buffer at 128 × 128 (cells of one unpruned search path).
pub const REF128_PCAP: usize = 2048;
/// The coverage planner at the reference 128 × 128 capacity.
pub type Coverage128 =
    crate::coverage::Coverage<REF128_CELLS, REF128_WORDS, REF128_OPEN, REF128_LCAP, REF128_PCAP>;

/// Planner state at 128 × 128: the search state, the list (4 bytes a
/// point), the path buffer (4 bytes a cell), two bitsets (in-list,
/// abandoned) and a few fields (the list's own counters among them).
pub const COVERAGE128_BYTES: usize = core::mem::size_of::<Coverage128>();
const _: () = assert!(
    COVERAGE128_BYTES
        <= SEARCH128_BYTES
            + REF128_LCAP * 4
            + REF128_PCAP * 4
            + 2 * REF128_WORDS * 4
            + 64 * 4
            + 160
);
const _: () = assert!(COVERAGE128_BYTES <= 210_000);
/// Grid plus planner at 128 × 128.
pub const PLANNER128_TOTAL_BYTES: usize = COVERAGE128_BYTES + GRID128_BYTES;

/// Firmware backtracking-list capacity.
pub const FW_LCAP: usize = 512;
/// Firmware transit path buffer.
pub const FW_PCAP: usize = 1024;
/// The firmware's coverage planner.
pub type FwCoverage = crate::coverage::Coverage<FW_CELLS, FW_WORDS, FW_OPEN, FW_LCAP, FW_PCAP>;

/// Backtracking list of the emulated run's planner.
pub const BENCH_LCAP: usize = 512;
/// Transit path buffer of the emulated run's planner.
pub const BENCH_PCAP: usize = 1024;
/// Cells of the emulated run's per-cell field: its coverage maps (40 × 20
/// and 50 × 30), 3,200 bytes.
pub const BENCH_FIELD: usize = 1600;
/// The emulated run's coverage planner (maps up to 100 × 50; the
/// wavefront, STC, BCD and regions up to [`BENCH_FIELD`] cells), so every planner is
/// measured on the M4.
pub type BenchCoverage = crate::coverage::Coverage<
    BENCH_CELLS,
    BENCH_WORDS,
    BENCH_OPEN,
    BENCH_LCAP,
    BENCH_PCAP,
    BENCH_FIELD,
>;

/// The firmware's home: 12 × 12 m at 5 cm evidence cells.
pub const FW_HOME_SIDE: usize = 240;
/// Words of the scan matcher's coarse levels for that home.
pub const FW_MATCH_WORDS: usize = crate::localize::matcher_words(FW_HOME_SIDE, FW_HOME_SIDE);
/// The firmware's scan matcher.
pub type FwMatcher = crate::localize::ScanMatcher<FW_MATCH_WORDS>;
/// Its RAM: the coarse levels (4 bits a block at 10, 20, 40 cm: 9 450
/// bytes) and the points (224 × 8 bytes), beyond the evidence map; the
/// issue's budget is 16 KiB. The searches' candidates live on the stack
/// (12 candidates, about 1 KiB).
pub const FW_MATCHER_BYTES: usize = core::mem::size_of::<FwMatcher>();
const _: () = assert!(FW_MATCHER_BYTES <= 16 * 1024);
const _: () = assert!(FW_MATCH_WORDS * 4 == 9_452);

// ---------------------------------------------------------------------
// The whole mission on the chip (issue 11 §3): a home whose bounding box
// is up to 12 × 12 m, at 5 cm evidence cells and 0.3 m planning cells.
// ---------------------------------------------------------------------

/// Evidence (fine) cells of the firmware's home: 240 × 240.
pub const FW_FINE_CELLS: usize = FW_HOME_SIDE * FW_HOME_SIDE;
/// Bitset words of the fine configuration space.
pub const FW_FINE_WORDS: usize = words_for(FW_FINE_CELLS);
/// Planning cells: 12 m at 0.3 m, plus one for a partial cell: 41 × 41.
pub const FW_PLAN_SIDE: usize = 41;
/// Planning cells of the firmware's home.
pub const FW_PLAN_CELLS: usize = FW_PLAN_SIDE * FW_PLAN_SIDE;
/// Side of the fine searches' window, cells (2.4 m at 5 cm).
pub const FW_WINDOW_SIDE: usize = 48;
/// Cells of the fine searches' window.
pub const FW_WINDOW_CELLS: usize = FW_WINDOW_SIDE * FW_WINDOW_SIDE;
/// Cells of the one search state, shared in time by the planner (on the
/// planning cells) and the fine searches (on the window): the larger of
/// the two.
pub const FW_SEARCH_CELLS: usize = if FW_PLAN_CELLS > FW_WINDOW_CELLS {
    FW_PLAN_CELLS
} else {
    FW_WINDOW_CELLS
};
/// Bitset words of the shared search state (and of the planning grid and
/// the window's copy of the obstacles, which share its `NW`).
pub const FW_SEARCH_WORDS: usize = words_for(FW_SEARCH_CELLS);
/// The shared search state's open list.
pub const FW_SEARCH_OPEN: usize = 512;
/// The planner's backtracking list.
pub const FW_PLAN_LCAP: usize = 512;
/// The planner's transit path buffer.
pub const FW_PLAN_PCAP: usize = 512;
/// The fine path buffer (detours, edge transits, the way home's legs).
/// 512 cells is 25 m of path at 5 cm, and a leg is bounded by the 2.4 m
/// window; it also lends the room split its wavefront queue.
pub const FW_FINE_PATH: usize = 512;

/// The firmware mission's coverage planner, owner of the shared search
/// state.
pub type FwPlanner = crate::coverage::Coverage<
    FW_SEARCH_CELLS,
    FW_SEARCH_WORDS,
    FW_SEARCH_OPEN,
    FW_PLAN_LCAP,
    FW_PLAN_PCAP,
>;
/// The firmware mission's fine searches (the window and its goals; they
/// run on the planner's search state).
pub type FwWindow = crate::search::WindowSearch<FW_SEARCH_CELLS, FW_SEARCH_WORDS>;
/// The firmware mission's planning grid.
pub type FwPlanGrid = Grid<FW_SEARCH_WORDS>;
/// The firmware mission's fine configuration space.
pub type FwFineGrid = Grid<FW_FINE_WORDS>;
/// The firmware mission's evidence map.
pub type FwEvidence = crate::robot::lidar_map::EvidenceMap<FW_EVIDENCE_CELL_BYTES>;
/// Bytes of the evidence map's cells (4 bits a cell).
pub const FW_EVIDENCE_CELL_BYTES: usize = crate::robot::lidar_map::evidence_bytes(FW_FINE_CELLS);
/// The firmware mission's buffers, lent to the executive.
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

/// Bytes of the firmware mission's planner (planning grid search state,
/// open list, backtracking list, transit path).
pub const FW_PLANNER_BYTES: usize = core::mem::size_of::<FwPlanner>();
const _: () = assert!(FW_PLANNER_BYTES <= 30_868);
/// Bytes of the fine searches' window (search state, open list, the
/// window's copy of the obstacles).
pub const FW_WINDOW_BYTES: usize = core::mem::size_of::<FwWindow>();
const _: () = assert!(FW_WINDOW_BYTES <= 1_200);
/// Bytes of the planning grid (three bit layers of 41 × 41).
pub const FW_PLAN_GRID_BYTES: usize = core::mem::size_of::<FwPlanGrid>();
const _: () = assert!(FW_PLAN_GRID_BYTES <= 900);
/// Bytes of the fine configuration space (three bit layers of 240 × 240).
pub const FW_FINE_GRID_BYTES: usize = core::mem::size_of::<FwFineGrid>();
const _: () = assert!(FW_FINE_GRID_BYTES <= 21_700);
/// Bytes of the evidence map (two cells a byte).
pub const FW_EVIDENCE_BYTES: usize = core::mem::size_of::<FwEvidence>();
const _: () = assert!(FW_EVIDENCE_BYTES <= 29_060);
/// Bytes of the executive itself (lidar ring and revolution, queues,
/// events, localisation state).
pub const FW_EXECUTIVE_BYTES: usize = core::mem::size_of::<crate::mission::Mission>();
const _: () = assert!(FW_EXECUTIVE_BYTES <= 20_640);
/// Every buffer of the firmware mission at 12 × 12 m, stack excluded.
///
/// About 118,800 bytes as laid out on the host (a little less on
/// thumbv7em, where `usize` is 4 bytes), of the F411's 131,072: one search state
/// shared in time by the planner and the fine searches (167,136 with two)
/// and evidence cells of 4 bits (147,196 with bytes). The rooms' labels
/// (1,681 bytes, [`crate::grid::rooms`]) were paid for by halving the fine
/// path (2,048 bytes); the edge pass's chord ([`crate::nav::chord`]) is
/// about 200 bytes of the executive; the open list's dial
/// ([`crate::search::open_list::dial`]) 296 bytes of the planner and the
/// neighbour steps 32; the potential field's parameters and state (the
/// local planner beside DWA, [`crate::nav::apf`]) 56 of the executive, and
/// the counter of legs planned again when the map came to block them 8;
/// the walls the control loop keeps off ([`crate::nav::keep_off`]) and
/// the time a person was last beside the body 72; the cleaning goals the
/// fine search found no way to ([`crate::mission::SKIPPED_GOALS`]) 72;
/// a boxed-in search's wait ([`crate::mission::BOXED_NODES`] and
/// [`crate::mission::BOXED_PLAN_NODES`]) 32.
/// The stack left is measured by the size report and the
/// processor-in-the-loop run (its high-water mark). This bound is
/// asserted so that nothing grows unnoticed.
pub const FW_MISSION_BYTES: usize = FW_PLANNER_BYTES
    + FW_WINDOW_BYTES
    + FW_PLAN_GRID_BYTES
    + FW_FINE_GRID_BYTES
    + FW_EVIDENCE_BYTES
    + FW_MATCHER_BYTES
    + FW_FINE_PATH * 4
    + FW_PLAN_CELLS
    + FW_EXECUTIVE_BYTES;
const _: () = assert!(FW_MISSION_BYTES <= 119_225);
