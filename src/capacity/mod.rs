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

mod home;
pub use home::{home12, home16, FW_EXECUTIVE_BYTES, FW_FINE_PATH, FW_WINDOW_SIDE};

// The robot's capacity: 12 × 12 m on the F411 (128 KiB), or 16 × 16 m on
// an F405/F407 (192 KiB: 128 KiB of SRAM and 64 KiB of core-coupled RAM)
// with the `home16` feature.
#[cfg(not(feature = "home16"))]
pub use home12::*;
#[cfg(feature = "home16")]
pub use home16::*;
