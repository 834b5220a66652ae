//! ValetudoMap JSON (version 2), the format cloud-free robot vacuum owners
//! export (Valetudo, `backend/lib/entities/map/ValetudoMap.js`): layers of
//! map pixels (`floor`, `segment` = a room, `wall`), entities in
//! centimetres (`charger_location`, `path`, `virtual_wall`,
//! `no_go_area`, …). `../shared/maps/valetudo/README.md` describes what
//! these files hold.
//!
//! The floor is the union of the floor and segment layers; walls and
//! everything never seen are blocked. The image is cropped to the pixels
//! the file uses plus a border, padded to a multiple of 24 pixels so that
//! every resampling the loaders offer (cells of 1, 2, 3, 4, 6 or 8 pixels)
//! keeps the same world frame. Map pixels have y down; the world frame is
//! x east, y north from the bottom-left corner, metres.

use std::path::Path;

use serde::Deserialize;

use super::maps::{GreyImage, MapData, MapError};

/// A room: its id, its name when given, its pixels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Room {
    /// Segment id.
    pub id: u32,
    /// Name, when the file gives one.
    pub name: Option<String>,
    /// The centres of its pixels, world metres.
    pub points_m: Vec<(f64, f64)>,
}

/// What a ValetudoMap adds to the floor plan (metres, in the map's world
/// frame: x east, y north, origin at the bottom-left corner).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MapExtras {
    /// Rooms.
    pub rooms: Vec<Room>,
    /// No-go areas (polygons).
    pub no_go: Vec<Vec<(f64, f64)>>,
    /// Virtual walls (segments).
    pub virtual_walls: Vec<((f64, f64), (f64, f64))>,
    /// The vendor robot's own paths (polylines).
    pub paths: Vec<Vec<(f64, f64)>>,
}

/// Pixels of border kept around the used area.
const BORDER_PX: i64 = 8;
/// Largest cropped side accepted, pixels (at 5 cm: 150 m).
const MAX_SIDE_PX: i64 = 3000;

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Raw {
    #[serde(rename = "__class")]
    class: Option<String>,
    meta_data: Option<RawMeta>,
    pixel_size: Option<f64>,
    layers: Option<Vec<RawLayer>>,
    #[serde(default)]
    entities: Vec<RawEntity>,
}

#[derive(Deserialize)]
struct RawMeta {
    version: Option<i64>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct RawLayer {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    pixels: Vec<i64>,
    #[serde(default)]
    compressed_pixels: Vec<i64>,
    meta_data: Option<serde_json::Value>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct RawEntity {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    points: Vec<f64>,
    meta_data: Option<serde_json::Value>,
}

fn bad(path: &Path, msg: impl std::fmt::Display) -> MapError {
    MapError(format!("{}: {msg}", path.display()))
}

/// A layer's pixels, validated: (x, y) map pixels.
fn layer_pixels(path: &Path, l: &RawLayer) -> Result<Vec<(i64, i64)>, MapError> {
    if !l.pixels.len().is_multiple_of(2) || !l.compressed_pixels.len().is_multiple_of(3) {
        return Err(bad(
            path,
            format!("layer {}: pixel lists of the wrong length", l.kind),
        ));
    }
    let mut out: Vec<(i64, i64)> = l.pixels.chunks(2).map(|c| (c[0], c[1])).collect();
    for c in l.compressed_pixels.chunks(3) {
        let (x, y, run) = (c[0], c[1], c[2]);
        if !(0..=MAX_SIDE_PX * 4).contains(&run) {
            return Err(bad(path, format!("layer {}: run of {run} pixels", l.kind)));
        }
        out.extend((0..run).map(|i| (x + i, y)));
    }
    if let Some(&(x, y)) = out
        .iter()
        .find(|(x, y)| *x < 0 || *y < 0 || *x > 1 << 20 || *y > 1 << 20)
    {
        return Err(bad(
            path,
            format!("layer {}: pixel ({x}, {y}) out of range", l.kind),
        ));
    }
    Ok(out)
}

/// Parses a ValetudoMap file into a floor plan at its own resolution
/// (resampled to `cell_m` when given), with the dock, rooms, no-go areas,
/// virtual walls and the vendor robot's paths.
pub fn parse_valetudo(path: &Path, bytes: &[u8], cell_m: Option<f64>) -> Result<MapData, MapError> {
    let raw: Raw = serde_json::from_slice(bytes)
        .map_err(|e| bad(path, format!("not ValetudoMap JSON: {e}")))?;
    if raw.class.as_deref() != Some("ValetudoMap") {
        return Err(bad(
            path,
            "not a ValetudoMap (no \"__class\": \"ValetudoMap\")",
        ));
    }
    let version = raw.meta_data.and_then(|m| m.version);
    if version != Some(2) {
        return Err(bad(
            path,
            format!("ValetudoMap version {version:?}, only 2 is supported"),
        ));
    }
    let px_cm = raw.pixel_size.ok_or_else(|| bad(path, "no pixelSize"))?;
    if !(px_cm.is_finite() && (1.0..=50.0).contains(&px_cm)) {
        return Err(bad(
            path,
            format!("pixelSize {px_cm} cm is absurd (1 to 50)"),
        ));
    }
    let layers = raw.layers.ok_or_else(|| bad(path, "no layers"))?;
    let mut floor = Vec::new();
    let mut rooms_px = Vec::new();
    for l in &layers {
        let pts = layer_pixels(path, l)?;
        match l.kind.as_str() {
            "floor" => floor.extend(pts),
            "segment" => {
                floor.extend(pts.iter().copied());
                let meta = l.meta_data.as_ref();
                let id = meta
                    .and_then(|m| m.get("segmentId"))
                    .and_then(|v| v.as_str().and_then(|s| s.parse().ok()).or(v.as_u64()))
                    .unwrap_or(rooms_px.len() as u64 + 1) as u32;
                let name = meta
                    .and_then(|m| m.get("name"))
                    .and_then(|v| v.as_str())
                    .map(String::from);
                rooms_px.push((id, name, pts));
            }
            _ => {}
        }
    }
    if floor.is_empty() {
        return Err(bad(path, "no floor or segment layer with pixels"));
    }
    let frame = Frame::around(path, &floor, px_cm)?;
    let mut img = GreyImage {
        width: frame.w as u32,
        height: frame.h as u32,
        free: vec![false; (frame.w * frame.h) as usize],
    };
    for &(x, y) in &floor {
        if let Some(f) = frame.index(x, y).and_then(|i| img.free.get_mut(i)) {
            *f = true;
        }
    }
    let res_m = px_cm / 100.0;
    let mut map = super::maps::resample(path, img, res_m, cell_m)?;
    let extras = MapExtras {
        rooms: rooms_px
            .into_iter()
            .map(|(id, name, px)| Room {
                id,
                name,
                points_m: px
                    .iter()
                    .filter_map(|&(x, y)| frame.centre_m(x, y))
                    .collect(),
            })
            .collect(),
        ..entities(&raw.entities, &frame)
    };
    map.dock = raw
        .entities
        .iter()
        .find(|e| e.kind == "charger_location" && e.points.len() >= 2)
        .map(|e| {
            let (x, y) = frame.world(e.points[0], e.points[1]);
            let deg = e
                .meta_data
                .as_ref()
                .and_then(|m| m.get("angle"))
                .and_then(|a| a.as_f64())
                .unwrap_or(0.0);
            // Valetudo's angles run clockwise from north on its y-down
            // image; ours counter-clockwise from east.
            (x, y, (90.0 - deg).to_radians())
        });
    map.extras = Some(Box::new(extras));
    Ok(map)
}

/// The crop: which map pixels become the image, and the world frame.
struct Frame {
    x0: i64,
    y0: i64,
    w: i64,
    h: i64,
    px_cm: f64,
}

impl Frame {
    fn around(path: &Path, px: &[(i64, i64)], px_cm: f64) -> Result<Self, MapError> {
        let (mut x0, mut y0, mut x1, mut y1) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
        for &(x, y) in px {
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
        let pad = |n: i64| (n + 2 * BORDER_PX).div_euclid(24) * 24 + 24;
        let (w, h) = (pad(x1 - x0 + 1), pad(y1 - y0 + 1));
        if w > MAX_SIDE_PX || h > MAX_SIDE_PX {
            return Err(bad(
                path,
                format!("the floor spans {w} × {h} pixels (at most {MAX_SIDE_PX})"),
            ));
        }
        Ok(Self {
            x0: x0 - BORDER_PX,
            y0: y0 - BORDER_PX,
            w,
            h,
            px_cm,
        })
    }

    /// Image cell (column, row from the top) of a map pixel.
    fn cell(&self, x: i64, y: i64) -> Option<(u32, u32)> {
        let (c, r) = (x - self.x0, y - self.y0);
        (c >= 0 && r >= 0 && c < self.w && r < self.h).then_some((c as u32, r as u32))
    }

    /// World metres of a map pixel's centre, when inside the frame.
    fn centre_m(&self, x: i64, y: i64) -> Option<(f64, f64)> {
        let (c, r) = self.cell(x, y)?;
        let res = self.px_cm / 100.0;
        Some((
            (c as f64 + 0.5) * res,
            (self.h as f64 - r as f64 - 0.5) * res,
        ))
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        self.cell(x, y)
            .map(|(c, r)| r as usize * self.w as usize + c as usize)
    }

    /// World metres of a point given in centimetres.
    fn world(&self, x_cm: f64, y_cm: f64) -> (f64, f64) {
        let (px, py) = (x_cm / self.px_cm, y_cm / self.px_cm);
        let res = self.px_cm / 100.0;
        (
            (px - self.x0 as f64) * res,
            (self.h as f64 - (py - self.y0 as f64)) * res,
        )
    }
}

/// No-go areas, virtual walls and paths, in world metres.
fn entities(ents: &[RawEntity], f: &Frame) -> MapExtras {
    let poly = |e: &RawEntity| -> Vec<(f64, f64)> {
        e.points
            .chunks(2)
            .filter(|c| c.len() == 2)
            .map(|c| f.world(c[0], c[1]))
            .collect()
    };
    let mut x = MapExtras::default();
    for e in ents {
        match e.kind.as_str() {
            "no_go_area" => x.no_go.push(poly(e)),
            "virtual_wall" => {
                if let [a, b, ..] = poly(e)[..] {
                    x.virtual_walls.push((a, b));
                }
            }
            "path" => x.paths.push(poly(e)),
            _ => {}
        }
    }
    x
}
