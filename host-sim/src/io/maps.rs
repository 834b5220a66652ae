//! Map loaders: MovingAI `.map`, ROS map_server YAML + PGM, PNG, ASCII.
//!
//! Every loader returns a [`MapError`] with a one-line message on bad input
//! (missing, truncated, wrong header, non-numeric sizes, too large); none
//! panics. Image maps (PNG, PGM) can be resampled to robot-sized cells: a
//! cell is free only if every pixel in it is free.

use std::fmt;
use std::path::Path;

use robovac::{Cell, Grid};

/// A loaded map: free/blocked cells, row-major, y from the top.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MapData {
    /// Width in cells.
    pub width: u32,
    /// Height in cells.
    pub height: u32,
    /// `true` where blocked, row-major.
    pub blocked: Vec<bool>,
    /// Cell side in metres, when known.
    pub cell_m: Option<f64>,
    /// The dock: x, y (m) and the heading a docked robot leaves with (rad),
    /// when the map gives one.
    pub dock: Option<(f64, f64, f64)>,
    /// Rooms, no-go areas, virtual walls, paths (ValetudoMap).
    pub extras: Option<Box<super::valetudo::MapExtras>>,
}

/// A map that could not be loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct MapError(pub String);

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MapError {}

fn err<T>(path: &Path, msg: impl fmt::Display) -> Result<T, MapError> {
    Err(MapError(format!("{}: {msg}", path.display())))
}

/// Options for image maps.
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadOptions {
    /// Resample to cells of this side (metres). Image maps only; ASCII and
    /// MovingAI maps take it as the size of their cells.
    pub cell_m: Option<f64>,
    /// Metres per pixel of a PNG (PNG files carry none); default 0.05.
    pub png_resolution_m: Option<f64>,
}

/// Default metres per pixel for PNG maps (the ipa maps' resolution).
pub const DEFAULT_PNG_RESOLUTION_M: f64 = 0.05;

/// Loads any supported map, by file extension: `.map` (MovingAI), `.yaml`
/// / `.yml` (ROS map_server), `.json` (ValetudoMap), `.png`, `.pgm` (ROS
/// thresholds, defaults),
/// anything else as ASCII (`#` blocked, `.` free).
pub fn load_map(path: &Path, opts: LoadOptions) -> Result<MapData, MapError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if let Some(c) = opts.cell_m {
        if !(c.is_finite() && c > 0.0) {
            return err(path, "--cell must be a positive number of metres");
        }
    }
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => return err(path, format!("cannot read: {e}")),
    };
    let mut map = match ext.as_str() {
        "map" => parse_movingai(path, &bytes)?,
        "json" => super::valetudo::parse_valetudo(path, &bytes, opts.cell_m)?,
        "yaml" | "yml" => load_ros_yaml(path, &bytes, opts)?,
        "png" => {
            let res = opts.png_resolution_m.unwrap_or(DEFAULT_PNG_RESOLUTION_M);
            let img = decode_png(path, &bytes)?;
            resample(path, img, res, opts.cell_m)?
        }
        "pgm" => {
            let img = decode_pgm(path, &bytes, &RosThresholds::default())?;
            let res = opts.png_resolution_m.unwrap_or(DEFAULT_PNG_RESOLUTION_M);
            resample(path, img, res, opts.cell_m)?
        }
        _ => parse_ascii(path, &bytes)?,
    };
    if matches!(ext.as_str(), "map" | "txt" | "ascii" | "") || map.cell_m.is_none() {
        if let Some(c) = opts.cell_m {
            map.cell_m = Some(c);
        }
    }
    Ok(map)
}

impl MapData {
    /// Copies the map into a grid (which checks the capacity).
    pub fn to_grid<const NW: usize>(&self, grid: &mut Grid<NW>) -> Result<(), MapError> {
        grid.reset(self.width, self.height)
            .map_err(|e| MapError(format!("map does not fit: {e}")))?;
        for y in 0..self.height {
            for x in 0..self.width {
                if self.is_blocked(x as i32, y as i32) {
                    grid.set_obstacle(x as i32, y as i32, true)
                        .map_err(|e| MapError(e.to_string()))?;
                }
            }
        }
        Ok(())
    }

    /// True when (x, y) is blocked or off the map.
    pub fn is_blocked(&self, x: i32, y: i32) -> bool {
        if x < 0 || y < 0 || x >= self.width as i32 || y >= self.height as i32 {
            return true;
        }
        self.blocked
            .get(y as usize * self.width as usize + x as usize)
            .copied()
            .unwrap_or(true)
    }

    /// The first free cell in reading order.
    pub fn first_free(&self) -> Option<Cell> {
        let i = self.blocked.iter().position(|b| !b)?;
        Cell::from_xy(
            (i % self.width as usize) as i32,
            (i / self.width as usize) as i32,
        )
    }

    /// The map as rows of `#` and `.`.
    pub fn to_ascii(&self) -> String {
        let mut s = String::with_capacity((self.width as usize + 1) * self.height as usize);
        for y in 0..self.height as i32 {
            for x in 0..self.width as i32 {
                s.push(if self.is_blocked(x, y) { '#' } else { '.' });
            }
            s.push('\n');
        }
        s
    }
}

fn text<'a>(path: &Path, bytes: &'a [u8]) -> Result<&'a str, MapError> {
    std::str::from_utf8(bytes).or_else(|_| err(path, "not a text file (invalid UTF-8)"))
}

/// Parses an ASCII map: `#` blocked, `.` free, one line per row.
pub fn parse_ascii(path: &Path, bytes: &[u8]) -> Result<MapData, MapError> {
    let t = text(path, bytes)?;
    let rows: Vec<&str> = t
        .lines()
        .map(|l| l.trim_end_matches('\r'))
        .filter(|l| !l.is_empty())
        .collect();
    let Some(first) = rows.first() else {
        return err(path, "empty ASCII map");
    };
    let width = first.chars().count();
    let mut blocked = Vec::with_capacity(width * rows.len());
    for (y, row) in rows.iter().enumerate() {
        if row.chars().count() != width {
            return err(
                path,
                format!(
                    "ASCII map row {} has {} cells, row 1 has {width}",
                    y + 1,
                    row.chars().count()
                ),
            );
        }
        for (x, c) in row.chars().enumerate() {
            match c {
                '#' => blocked.push(true),
                '.' => blocked.push(false),
                _ => {
                    return err(
                        path,
                        format!(
                            "ASCII map: unexpected {c:?} at row {}, column {} (use # and .)",
                            y + 1,
                            x + 1
                        ),
                    )
                }
            }
        }
    }
    Ok(MapData {
        width: width as u32,
        height: rows.len() as u32,
        blocked,
        cell_m: None,
        ..Default::default()
    })
}

/// Parses a MovingAI grid benchmark map (`type octile`, `height`, `width`,
/// `map`); `.` and `G` are passable, everything else blocked.
pub fn parse_movingai(path: &Path, bytes: &[u8]) -> Result<MapData, MapError> {
    let t = text(path, bytes)?;
    let mut lines = t.lines().map(|l| l.trim_end_matches('\r'));
    let mut height: Option<u32> = None;
    let mut width: Option<u32> = None;
    let mut saw_type = false;
    loop {
        let Some(line) = lines.next() else {
            return err(path, "MovingAI header ends before the 'map' line");
        };
        let mut it = line.split_whitespace();
        match (it.next(), it.next()) {
            (Some("type"), Some(_)) => saw_type = true,
            (Some("height"), Some(v)) => {
                height = Some(
                    v.parse()
                        .or_else(|_| err(path, format!("height {v:?} is not a number")))?,
                )
            }
            (Some("width"), Some(v)) => {
                width = Some(
                    v.parse()
                        .or_else(|_| err(path, format!("width {v:?} is not a number")))?,
                )
            }
            (Some("map"), None) => break,
            (None, _) => {}
            _ => return err(path, format!("unexpected MovingAI header line {line:?}")),
        }
    }
    if !saw_type {
        return err(path, "MovingAI header has no 'type' line");
    }
    let (Some(h), Some(w)) = (height, width) else {
        return err(path, "MovingAI header lacks width or height");
    };
    if w == 0 || h == 0 {
        return err(path, "MovingAI map has a zero side");
    }
    if (w as u64) * (h as u64) > 1 << 28 {
        return err(path, format!("MovingAI map {w}x{h} is too large"));
    }
    let mut blocked = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h {
        let Some(row) = lines.next() else {
            return err(path, format!("truncated: {h} rows declared, {y} found"));
        };
        let row = row.as_bytes();
        if row.len() < w as usize {
            return err(
                path,
                format!(
                    "truncated: row {} has {} cells, width is {w}",
                    y + 1,
                    row.len()
                ),
            );
        }
        blocked.extend(
            row.iter()
                .take(w as usize)
                .map(|&c| !(c == b'.' || c == b'G')),
        );
    }
    Ok(MapData {
        width: w,
        height: h,
        blocked,
        cell_m: None,
        ..Default::default()
    })
}

/// A grey (0–255) image with an opacity flag per pixel.
pub struct GreyImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `true` where the pixel is free.
    pub free: Vec<bool>,
}

/// Decodes a PNG (grey, grey+alpha, RGB, RGBA, palette; 8 or 16 bit). A
/// pixel is free when it is opaque and its grey level is ≥ 250 (real maps
/// use 254 and 255 for free; 205 is "unknown" and counts as blocked).
pub fn decode_png(path: &Path, bytes: &[u8]) -> Result<GreyImage, MapError> {
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = match dec.read_info() {
        Ok(r) => r,
        Err(e) => return err(path, format!("not a readable PNG: {e}")),
    };
    let Some(size) = reader.output_buffer_size() else {
        return err(path, "PNG too large");
    };
    let mut buf = vec![0u8; size];
    let info = match reader.next_frame(&mut buf) {
        Ok(i) => i,
        Err(e) => return err(path, format!("truncated or corrupt PNG: {e}")),
    };
    let (w, h) = (info.width, info.height);
    let ch = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return err(path, "palette PNG was not expanded"),
    };
    let stride = info.line_size;
    let mut free = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let o = y * stride + x * ch;
            let px = buf.get(o..o + ch).unwrap_or(&[]);
            let (grey, alpha) = match *px {
                [g] => (g as u32, 255),
                [g, a] => (g as u32, a),
                [r, g, b] => (grey_of(r, g, b), 255),
                [r, g, b, a] => (grey_of(r, g, b), a),
                _ => (0, 0),
            };
            free.push(alpha == 255 && grey >= 250);
        }
    }
    Ok(GreyImage {
        width: w,
        height: h,
        free,
    })
}

/// ITU-R BT.601 luma, rounded.
fn grey_of(r: u8, g: u8, b: u8) -> u32 {
    (299 * r as u32 + 587 * g as u32 + 114 * b as u32 + 500) / 1000
}

/// ROS map_server thresholds.
#[derive(Clone, Copy, Debug)]
pub struct RosThresholds {
    /// Invert the image's meaning.
    pub negate: bool,
    /// Occupancy probability above which a pixel is occupied.
    pub occupied_thresh: f64,
    /// Occupancy probability below which a pixel is free.
    pub free_thresh: f64,
}

impl Default for RosThresholds {
    fn default() -> Self {
        Self {
            negate: false,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
        }
    }
}

/// Decodes a PGM (P2 or P5, maxval up to 65535) with ROS semantics: the
/// occupancy probability is (max − v)/max (v/max when negated); a pixel is
/// free below `free_thresh`; occupied and unknown pixels are blocked.
pub fn decode_pgm(path: &Path, bytes: &[u8], th: &RosThresholds) -> Result<GreyImage, MapError> {
    // Header tokens, skipping comments.
    let mut pos = 0usize;
    let mut tokens: Vec<String> = Vec::new();
    while tokens.len() < 4 {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if pos >= bytes.len() {
            return err(path, "truncated PGM header");
        }
        if bytes[pos] == b'#' {
            while pos < bytes.len() && bytes[pos] != b'\n' {
                pos += 1;
            }
            continue;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        tokens.push(String::from_utf8_lossy(&bytes[start..pos]).into_owned());
    }
    let magic = tokens[0].as_str();
    if magic != "P5" && magic != "P2" {
        return err(
            path,
            format!("not a PGM (magic {magic:?}, expected P5 or P2)"),
        );
    }
    let num = |s: &str, what: &str| -> Result<u32, MapError> {
        s.parse::<u32>()
            .or_else(|_| err(path, format!("PGM {what} {s:?} is not a number")))
    };
    let w = num(&tokens[1], "width")?;
    let h = num(&tokens[2], "height")?;
    let maxval = num(&tokens[3], "maxval")?;
    if w == 0 || h == 0 || maxval == 0 || maxval > 65535 {
        return err(path, "PGM has a zero size or a bad maxval");
    }
    if (w as u64) * (h as u64) > 1 << 28 {
        return err(path, format!("PGM {w}x{h} is too large"));
    }
    let n = w as usize * h as usize;
    let mut values = Vec::with_capacity(n);
    if magic == "P5" {
        pos += 1; // the single whitespace after maxval
        let bpp = if maxval > 255 { 2 } else { 1 };
        let data = bytes.get(pos..).unwrap_or(&[]);
        if data.len() < n * bpp {
            return err(
                path,
                format!("truncated PGM: {} of {} data bytes", data.len(), n * bpp),
            );
        }
        for k in 0..n {
            values.push(if bpp == 2 {
                (data[2 * k] as u32) << 8 | data[2 * k + 1] as u32
            } else {
                data[k] as u32
            });
        }
    } else {
        let rest = std::str::from_utf8(bytes.get(pos..).unwrap_or(&[]))
            .or_else(|_| err(path, "P2 PGM data is not text"))?;
        for tok in rest.split_whitespace().take(n) {
            values.push(num(tok, "value")?);
        }
        if values.len() < n {
            return err(
                path,
                format!("truncated PGM: {} of {n} values", values.len()),
            );
        }
    }
    let free = values
        .iter()
        .map(|&v| {
            let v = v.min(maxval) as f64 / maxval as f64;
            let p = if th.negate { v } else { 1.0 - v };
            p < th.free_thresh
        })
        .collect();
    Ok(GreyImage {
        width: w,
        height: h,
        free,
    })
}

/// The keys of a ROS map_server YAML that the loader reads (others, such
/// as `origin` and `mode`, are ignored). Numbers are read as YAML values so
/// a bad one gets a message naming its key.
#[derive(serde::Deserialize)]
struct RosYaml {
    image: Option<String>,
    resolution: Option<serde_norway::Value>,
    negate: Option<serde_norway::Value>,
    occupied_thresh: Option<serde_norway::Value>,
    free_thresh: Option<serde_norway::Value>,
}

/// Loads a ROS map_server YAML and the PGM (or PNG) it names.
pub fn load_ros_yaml(path: &Path, bytes: &[u8], opts: LoadOptions) -> Result<MapData, MapError> {
    let t = text(path, bytes)?;
    let y: RosYaml = match serde_norway::from_str(t) {
        Ok(y) => y,
        Err(e) => {
            return err(
                path,
                format!("not a ROS map YAML: {}", one_line(&e.to_string())),
            )
        }
    };
    let num = |v: &Option<serde_norway::Value>, k: &str| -> Result<Option<f64>, MapError> {
        match v {
            None => Ok(None),
            Some(v) => v.as_f64().filter(|x| x.is_finite()).map_or_else(
                || err(path, format!("{k}: {v:?} is not a number")),
                |x| Ok(Some(x)),
            ),
        }
    };
    let resolution = num(&y.resolution, "resolution")?;
    let mut th = RosThresholds {
        negate: matches!(&y.negate, Some(v) if v.as_bool() == Some(true) || v.as_i64() == Some(1)),
        ..RosThresholds::default()
    };
    if let Some(v) = num(&y.occupied_thresh, "occupied_thresh")? {
        th.occupied_thresh = v;
    }
    if let Some(v) = num(&y.free_thresh, "free_thresh")? {
        th.free_thresh = v;
    }
    let image = y.image;
    let Some(image) = image else {
        return err(path, "ROS map YAML has no 'image' key");
    };
    let Some(res) = resolution.filter(|r| *r > 0.0) else {
        return err(path, "ROS map YAML has no positive 'resolution'");
    };
    let img_path = path.parent().unwrap_or(Path::new(".")).join(&image);
    let img_bytes = match std::fs::read(&img_path) {
        Ok(b) => b,
        Err(e) => return err(&img_path, format!("cannot read map image: {e}")),
    };
    let img = if image.to_ascii_lowercase().ends_with(".png") {
        decode_png(&img_path, &img_bytes)?
    } else {
        decode_pgm(&img_path, &img_bytes, &th)?
    };
    resample(path, img, res, opts.cell_m)
}

/// Resamples an image of `res_m` metres per pixel to cells of `cell_m`
/// metres (a cell is free only if every pixel in it is free; pixels past
/// the image edge count as blocked). Without `cell_m`, one cell per pixel.
pub fn resample(
    path: &Path,
    img: GreyImage,
    res_m: f64,
    cell_m: Option<f64>,
) -> Result<MapData, MapError> {
    let Some(cell) = cell_m else {
        return Ok(MapData {
            width: img.width,
            height: img.height,
            blocked: img.free.iter().map(|f| !f).collect(),
            cell_m: Some(res_m),
            ..Default::default()
        });
    };
    let k = (cell / res_m).round();
    if !(1.0..=4096.0).contains(&k) {
        return err(
            path,
            format!("--cell {cell} m is smaller than a pixel ({res_m} m)"),
        );
    }
    let k = k as u32;
    let w = img.width.div_ceil(k);
    let h = img.height.div_ceil(k);
    let mut blocked = Vec::with_capacity(w as usize * h as usize);
    for cy in 0..h {
        for cx in 0..w {
            let mut free = true;
            'px: for py in cy * k..(cy + 1) * k {
                for px in cx * k..(cx + 1) * k {
                    let ok = px < img.width
                        && py < img.height
                        && img
                            .free
                            .get(py as usize * img.width as usize + px as usize)
                            .copied()
                            .unwrap_or(false);
                    if !ok {
                        free = false;
                        break 'px;
                    }
                }
            }
            blocked.push(!free);
        }
    }
    Ok(MapData {
        width: w,
        height: h,
        blocked,
        cell_m: Some(k as f64 * res_m),
        ..Default::default()
    })
}

/// A message on one line (YAML errors span several).
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
