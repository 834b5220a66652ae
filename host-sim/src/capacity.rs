//! Every host size in one place: maps up to 1024 × 1024 cells (MovingAI
//! benchmark maps are 512 × 512; real floor plans resampled to robot cells
//! are far smaller), the planner's list and path, the evidence map and the
//! scan assembler. The firmware's own sizes are the core's
//! `robovac::capacity`.

use robovac::math::bits::words_for;
use robovac::search::WindowSearch;
use robovac::{Grid, SearchState};

/// Largest map the CLI takes, in cells.
pub const HOST_CELLS: usize = 1024 * 1024;
/// Bitset words for the host map.
pub const HOST_WORDS: usize = words_for(HOST_CELLS);
/// Open-list capacity on the host (one entry per cell: it never fills).
pub const HOST_OPEN: usize = HOST_CELLS;

/// Backtracking-list capacity on the host.
pub const HOST_LCAP: usize = HOST_CELLS;
/// Transit path buffer on the host.
pub const HOST_PCAP: usize = HOST_CELLS;
/// Bytes of the host's evidence cells (up to 75 m × 75 m at 5 cm, two
/// cells a byte).
pub const HOST_EVIDENCE: usize = robovac::robot::lidar_map::evidence_bytes(1500 * 1500);
/// Words of the scan matcher's coarse levels for the host evidence map.
pub const HOST_MATCH_WORDS: usize = robovac::localize::matcher_words(1500, 1500);
/// The host's scan matcher.
pub type HostMatcher = robovac::localize::ScanMatcher<HOST_MATCH_WORDS>;

/// Frames per revolution the scan assembler holds.
pub const SCAN_FRAMES: usize = 64;

/// The host grid.
pub type HostGrid = Grid<HOST_WORDS>;
/// The host search state (about 28 MB).
pub type HostSearch = SearchState<HOST_CELLS, HOST_WORDS, HOST_OPEN>;

/// A host grid on the heap.
pub fn new_grid() -> Box<HostGrid> {
    Box::new(HostGrid::new())
}

/// A host search state on the heap, without building it on the stack.
pub fn new_search() -> Box<HostSearch> {
    let b = Box::<HostSearch>::new_zeroed();
    // SAFETY: `SearchState` consists only of integers, arrays of integers,
    // `#[repr(u8)]` enums whose discriminant 0 is a variant (the algorithm,
    // the open list's order), and structs of those; its documentation
    // guarantees that all-zero bytes are a valid idle state that behaves
    // as `SearchState::new()`.
    unsafe { b.assume_init() }
}

/// The mission's fine searches on the host: the window is the whole map
/// (they run on the planner's search state, lent).
pub type HostWindow = WindowSearch<HOST_CELLS, HOST_WORDS>;

/// A host window search on the heap, without building it on the stack.
pub fn new_window() -> Box<HostWindow> {
    let b = Box::<HostWindow>::new_zeroed();
    // SAFETY: `WindowSearch` is a `Grid` (integers and arrays of them), a
    // window, goals and counters (integers); its
    // documentation guarantees that all-zero bytes are the idle state
    // `WindowSearch::new()`.
    unsafe { b.assume_init() }
}
