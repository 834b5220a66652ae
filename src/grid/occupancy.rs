//! The occupancy grid: bit-packed layers over a run-time-sized map.
//!
//! One bit per cell per layer ([`Layer`]): obstacle, covered, known. The
//! capacity is fixed at compile time by `NW` (words of 32 cells, see
//! [`crate::math::bits::words_for`]); the actual width and height are chosen at run
//! time up to that capacity. Cells are addressed (x, y), x the column and y
//! the row counted from the top, as in MovingAI scenarios.
//!
//! Reading off the map never panics: a cell outside reads as blocked, not
//! covered and not known. Writing off the map is an error.

use crate::math::bits::Bits;

/// A cell coordinate: `x` the column, `y` the row from the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Cell {
    /// Column.
    pub x: u16,
    /// Row, counted from the top.
    pub y: u16,
}

impl Cell {
    /// A cell at (x, y).
    pub const fn new(x: u16, y: u16) -> Self {
        Self { x, y }
    }

    /// The coordinates as signed integers, for arithmetic.
    #[inline]
    pub const fn xy(self) -> (i32, i32) {
        (self.x as i32, self.y as i32)
    }

    /// The cell at signed coordinates, if both are representable.
    #[inline]
    pub fn from_xy(x: i32, y: i32) -> Option<Self> {
        Some(Self {
            x: u16::try_from(x).ok()?,
            y: u16::try_from(y).ok()?,
        })
    }
}

/// The grid's bit layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Layer {
    /// The cell is blocked (wall, furniture, or unreachable for the robot).
    Obstacle,
    /// The robot has cleaned the cell.
    Covered,
    /// The cell has been observed (for exploring unknown maps).
    Known,
}

/// Errors from grid construction and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GridError {
    /// width × height exceeds the compile-time capacity, or a side is 0.
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Capacity in cells.
        capacity: u32,
    },
    /// A side of zero cells.
    Empty,
    /// A write addressed a cell outside the map.
    OffMap {
        /// Column.
        x: i32,
        /// Row.
        y: i32,
    },
    /// An ASCII map had rows of different lengths.
    RaggedRows {
        /// Zero-based row index.
        row: u32,
    },
    /// An ASCII map had a character other than `#` and `.`.
    BadChar {
        /// Zero-based row index.
        row: u32,
        /// Zero-based column index.
        col: u32,
    },
}

impl core::fmt::Display for GridError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            GridError::TooLarge {
                width,
                height,
                capacity,
            } => write!(
                f,
                "map of {width}x{height} cells exceeds the capacity of {capacity} cells"
            ),
            GridError::Empty => write!(f, "map has no cells"),
            GridError::OffMap { x, y } => write!(f, "cell ({x},{y}) is off the map"),
            GridError::RaggedRows { row } => {
                write!(f, "row {row} has a different length from row 0")
            }
            GridError::BadChar { row, col } => {
                write!(f, "unexpected character at row {row}, column {col}")
            }
        }
    }
}

/// A bit-packed grid of up to `NW * 32` cells.
#[derive(Clone)]
pub struct Grid<const NW: usize> {
    width: u16,
    height: u16,
    obstacle: Bits<NW>,
    covered: Bits<NW>,
    known: Bits<NW>,
}

impl<const NW: usize> Default for Grid<NW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NW: usize> Grid<NW> {
    /// Capacity in cells.
    pub const CAPACITY: usize = NW * 32;

    /// An empty 0×0 grid (every read is off the map). Call [`Grid::reset`].
    pub const fn new() -> Self {
        Self {
            width: 0,
            height: 0,
            obstacle: Bits::new(),
            covered: Bits::new(),
            known: Bits::new(),
        }
    }

    /// [`Grid::reset`], but the covered layer is kept when the size is
    /// unchanged: a grid rebuilt from a changed map keeps what the robot
    /// has done on it.
    pub fn reset_keeping_covered(&mut self, width: u32, height: u32) -> Result<(), GridError> {
        if (width, height) != (self.width(), self.height()) {
            return self.reset(width, height);
        }
        self.obstacle.clear_all();
        self.known.clear_all();
        Ok(())
    }

    /// Resizes to `width × height`, all cells free, uncovered and unknown.
    pub fn reset(&mut self, width: u32, height: u32) -> Result<(), GridError> {
        if width == 0 || height == 0 {
            return Err(GridError::Empty);
        }
        let cells = (width as u64) * (height as u64);
        if cells > Self::CAPACITY as u64 || width > u16::MAX as u32 || height > u16::MAX as u32 {
            return Err(GridError::TooLarge {
                width,
                height,
                capacity: Self::CAPACITY.min(u32::MAX as usize) as u32,
            });
        }
        self.width = width as u16;
        self.height = height as u16;
        self.obstacle.clear_all();
        self.covered.clear_all();
        self.known.clear_all();
        Ok(())
    }

    /// Width in cells.
    #[inline]
    pub fn width(&self) -> u32 {
        self.width as u32
    }

    /// Height in cells.
    #[inline]
    pub fn height(&self) -> u32 {
        self.height as u32
    }

    /// Number of cells on the map (width × height).
    #[inline]
    pub fn cells(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// True when (x, y) is on the map.
    #[inline]
    pub fn contains(&self, x: i32, y: i32) -> bool {
        x >= 0 && y >= 0 && x < self.width as i32 && y < self.height as i32
    }

    /// Linear index of (x, y), row-major, or `None` off the map.
    #[inline]
    pub fn index(&self, x: i32, y: i32) -> Option<usize> {
        if self.contains(x, y) {
            Some(y as usize * self.width as usize + x as usize)
        } else {
            None
        }
    }

    /// The cell at a linear index (no bounds check beyond the arithmetic;
    /// only meaningful for indices from [`Grid::index`]).
    #[inline]
    pub fn cell_at(&self, i: usize) -> Cell {
        let w = (self.width as usize).max(1);
        Cell::new((i % w) as u16, (i / w) as u16)
    }

    fn layer(&self, layer: Layer) -> &Bits<NW> {
        match layer {
            Layer::Obstacle => &self.obstacle,
            Layer::Covered => &self.covered,
            Layer::Known => &self.known,
        }
    }

    fn layer_mut(&mut self, layer: Layer) -> &mut Bits<NW> {
        match layer {
            Layer::Obstacle => &mut self.obstacle,
            Layer::Covered => &mut self.covered,
            Layer::Known => &mut self.known,
        }
    }

    /// Reads a layer bit; off the map reads `true` for `Obstacle` and
    /// `false` for the others.
    #[inline]
    pub fn get(&self, layer: Layer, x: i32, y: i32) -> bool {
        match self.index(x, y) {
            Some(i) => self.layer(layer).get(i),
            None => layer == Layer::Obstacle,
        }
    }

    /// Writes a layer bit.
    pub fn set(&mut self, layer: Layer, x: i32, y: i32, v: bool) -> Result<(), GridError> {
        let i = self.index(x, y).ok_or(GridError::OffMap { x, y })?;
        self.layer_mut(layer).put(i, v);
        Ok(())
    }

    /// Moves one layer's bits `dx` columns right and `dy` rows down; the
    /// strip left behind reads false ([`super::shift::for_shift`]). The
    /// planning grid's covered layer under a scrolling map.
    pub fn shift_layer(&mut self, layer: Layer, dx: i32, dy: i32) {
        let (w, h) = (self.width(), self.height());
        let bits = self.layer_mut(layer);
        super::shift::for_shift(w, h, dx, dy, |d, s| {
            let v = s.is_some_and(|s| bits.get(s));
            bits.put(d, v);
        });
    }

    /// True when (x, y) is an obstacle or off the map.
    #[inline]
    pub fn is_blocked(&self, x: i32, y: i32) -> bool {
        self.get(Layer::Obstacle, x, y)
    }

    /// True when (x, y) is on the map and not an obstacle.
    #[inline]
    pub fn is_free(&self, x: i32, y: i32) -> bool {
        !self.is_blocked(x, y)
    }

    /// Obstacle bit by linear index (the search's hot path).
    #[inline]
    pub(crate) fn blocked_at(&self, i: usize) -> bool {
        self.obstacle.get(i)
    }

    /// The obstacle bits of cells x ..= x + 31 of rows y − 1, y and y + 1,
    /// as bits 0..32 of three words; cells off the map read blocked (1).
    /// Jump point search's row scan ([`crate::search::jps`]): 32 cells of
    /// a row and of the rows beside it in six word reads, the map's side
    /// edges worked out once for the three.
    #[inline]
    pub(crate) fn rows3(&self, x: i32, y: i32) -> [u32; 3] {
        let (w, h) = (self.width as isize, self.height as i32);
        let on_map = self.row_mask(x);
        let at = y as isize * w + x as isize;
        let read = |dy: i32, step: isize| {
            if (0..h).contains(&(y + dy)) {
                (self.obstacle.window(at + step) & on_map) | !on_map
            } else {
                u32::MAX
            }
        };
        [read(-1, -w), read(0, 0), read(1, w)]
    }

    /// A reader of the three columns x − 1, x, x + 1, row by row
    /// ([`Column3::read`]): jump point search's column scan, with the
    /// map's side edges worked out once per scan.
    #[inline]
    pub(crate) fn column3(&self, x: i32) -> Column3<'_, NW> {
        Column3 {
            grid: self,
            x0: x - 1,
            on_map: self.row_mask(x - 1) & 0b111,
            w: self.width as i32,
        }
    }

    /// The bits 0..32 of a row word from column `x` that lie on the map.
    #[inline]
    fn row_mask(&self, x: i32) -> u32 {
        let lo = (-x).clamp(0, 32) as u32;
        let hi = (self.width as i32 - x).clamp(0, 32) as u32;
        if lo >= hi {
            return 0;
        }
        ((1u64 << hi) - (1u64 << lo)) as u32
    }

    /// The free 8-neighbours of (x, y), which must be on the map: bit k is
    /// set when neighbour k is on the map and not an obstacle, k counting
    /// E, NE, N, NW, W, SW, S, SE (y grows downward; the order of
    /// `search::NEIGHBOURS`). Three reads of three bits, one per row, and
    /// the map's edges as a mask, instead of eight checked reads: the
    /// search's hot loop (issue 13).
    #[inline(always)]
    pub fn free_neighbours(&self, x: i32, y: i32) -> u32 {
        self.free_neighbours_at((y * self.width as i32 + x) as usize, x, y)
    }

    /// [`Grid::free_neighbours`] of the cell at linear index `i` = (x, y),
    /// for a caller that has the index already (the search).
    #[inline(always)]
    pub fn free_neighbours_at(&self, i: usize, x: i32, y: i32) -> u32 {
        let (w, h) = (self.width as i32, self.height as i32);
        let mut blocked = self.obstacle.ring(i, w as usize, x == 0);
        if x == 0 {
            blocked |= 0b0011_1000; // NW, W, SW
        }
        if x + 1 >= w {
            blocked |= 0b1000_0011; // E, NE, SE
        }
        if y == 0 {
            blocked |= 0b0000_1110; // NE, N, NW
        }
        if y + 1 >= h {
            blocked |= 0b1110_0000; // SW, S, SE
        }
        !blocked & 0xFF
    }

    /// The moves out of (x, y), which must be on the map, as a mask in the
    /// order of [`Grid::free_neighbours`]: every free straight neighbour,
    /// and a free diagonal one only when both straight cells beside it are
    /// free (no corner cutting: the search's graph, defined here once).
    #[inline(always)]
    pub fn moves(&self, x: i32, y: i32) -> u32 {
        self.moves_at((y * self.width as i32 + x) as usize, x, y)
    }

    /// [`Grid::moves`] of the cell at linear index `i` = (x, y).
    #[inline(always)]
    pub fn moves_at(&self, i: usize, x: i32, y: i32) -> u32 {
        Self::moves_of(self.free_neighbours_at(i, x, y))
    }

    /// The moves allowed by a mask of free neighbours
    /// ([`Grid::free_neighbours`]).
    #[inline(always)]
    pub fn moves_of(free: u32) -> u32 {
        // Straight moves are the even k; a diagonal k needs k - 1 and
        // k + 1 (mod 8) free.
        let straight = free & 0b0101_0101;
        let corners = (straight << 1) & ((straight >> 1) | (straight << 7));
        straight | (free & corners & 0b1010_1010)
    }

    /// Marks (x, y) as an obstacle or free.
    pub fn set_obstacle(&mut self, x: i32, y: i32, blocked: bool) -> Result<(), GridError> {
        self.set(Layer::Obstacle, x, y, blocked)
    }

    /// Marks cells `x0..=x1` of row `y` as obstacles, clipped to the map
    /// (a word at a time: the fine configuration space's stamping).
    pub fn block_run(&mut self, y: i32, x0: i32, x1: i32) {
        let (x0, x1) = (x0.max(0), x1.min(self.width as i32 - 1));
        if y < 0 || y >= self.height as i32 || x0 > x1 {
            return;
        }
        let row = y as usize * self.width as usize;
        self.obstacle
            .set_range(row + x0 as usize, row + x1 as usize + 1);
    }

    /// Number of free (non-obstacle) cells on the map.
    pub fn free_cells(&self) -> usize {
        self.cells() - self.obstacle.count_prefix(self.cells())
    }

    /// Number of cells with the given layer bit set.
    pub fn count(&self, layer: Layer) -> usize {
        self.layer(layer).count_prefix(self.cells())
    }

    /// Clears a whole layer.
    pub fn clear_layer(&mut self, layer: Layer) {
        self.layer_mut(layer).clear_all();
    }

    /// Loads an ASCII map: one line per row, `#` blocked, `.` free. Blank
    /// leading/trailing lines and trailing `\r` are ignored.
    pub fn load_ascii(&mut self, text: &str) -> Result<(), GridError> {
        // Bytes split on `\n` (the maps are ASCII): no `str` slicing, so
        // no bounds check that could panic is linked into the firmware.
        let rows = || {
            text.as_bytes()
                .split(|&b| b == b'\n')
                .map(trim_cr)
                .filter(|l| !l.is_empty())
        };
        let height = rows().count() as u32;
        let width = rows().next().map(|l| l.len() as u32).unwrap_or(0);
        self.reset(width, height)?;
        for (y, line) in rows().enumerate() {
            if line.len() as u32 != width {
                return Err(GridError::RaggedRows { row: y as u32 });
            }
            for (x, &b) in line.iter().enumerate() {
                match b {
                    b'#' => self.set_obstacle(x as i32, y as i32, true)?,
                    b'.' => {}
                    _ => {
                        return Err(GridError::BadChar {
                            row: y as u32,
                            col: x as u32,
                        })
                    }
                }
            }
        }
        Ok(())
    }
}

/// `line` without its trailing `\r`s.
fn trim_cr(mut line: &[u8]) -> &[u8] {
    while let [rest @ .., b'\r'] = line {
        line = rest;
    }
    line
}

/// Three adjacent columns of a grid's obstacle bits, read a row at a time
/// ([`Grid::column3`]).
pub(crate) struct Column3<'a, const NW: usize> {
    grid: &'a Grid<NW>,
    /// The first column (x − 1).
    x0: i32,
    /// Which of the three columns lie on the map.
    on_map: u32,
    w: i32,
}

impl<const NW: usize> Column3<'_, NW> {
    /// The obstacle bits of the three cells of row `y` as bits 0, 1, 2;
    /// cells off the map read blocked.
    #[inline(always)]
    pub(crate) fn read(&self, y: i32) -> u32 {
        if y < 0 || y >= self.grid.height as i32 {
            return 0b111;
        }
        let at = y as isize * self.w as isize + self.x0 as isize;
        (self.grid.obstacle.window(at) & self.on_map) | (0b111 & !self.on_map)
    }
}
