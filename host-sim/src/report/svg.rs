//! SVG pictures of coverage plans, in the manner of seed 000's figures:
//! obstacles, cover runs coloured by segment, transit paths dashed,
//! backtracking and critical points marked, metrics in a caption; and
//! the [`Canvas`] the drive and mission pictures draw on.

use std::fmt::Write;

use robovac::verify::metrics::SegmentKind;

use crate::io::maps::MapData;
use crate::run::plan::Plan;

/// Renders a plan on its map.
pub fn plan_svg(map: &MapData, p: &Plan, title: &str) -> String {
    let cs = (900.0 / map.width.max(map.height) as f64).clamp(4.0, 24.0);
    let (w, h) = (map.width as f64 * cs, map.height as f64 * cs);
    let caption_h = 78.0;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {:.0} {:.0}" font-family="sans-serif">"#,
        w + 20.0,
        h + caption_h + 20.0,
        w + 20.0,
        h + caption_h + 20.0
    );
    let _ = writeln!(
        s,
        r##"<rect width="100%" height="100%" fill="#ffffff"/><g transform="translate(10,10)">"##
    );
    let _ = writeln!(
        s,
        r##"<rect width="{w:.1}" height="{h:.1}" fill="#f7f7f2" stroke="#999"/>"##
    );
    plan_obstacles(&mut s, map, cs);
    plan_segments(&mut s, p, cs);
    plan_markers(&mut s, p, cs);
    let m = &p.metrics;
    let cells = |c: u64| c as f64 / robovac::math::cost::COST_PER_CELL as f64;
    let lines = [
        format!("{title} — planner {}, {}x{} cells", p.kind.name(), map.width, map.height),
        format!(
            "coverage {:.4} ({} of {} reachable)  repetition {:.4}  segments {}  turns {}  rotation {:.0}°",
            p.coverage(),
            m.covered_cells,
            m.reachable_cells,
            p.repetition(),
            m.segments,
            m.turns,
            m.rotation_urad as f64 * 1e-6 * 180.0 / std::f64::consts::PI
        ),
        format!(
            "coverage path {:.1}  backtracking path {:.1}  total {:.1} cells  backtracking points {}  nodes {}  {:.0} µs",
            cells(m.coverage_path_cost),
            cells(m.backtrack_path_cost),
            cells(m.coverage_path_cost + m.backtrack_path_cost),
            m.backtrack_points_total,
            m.nodes_expanded,
            p.time_us
        ),
        "green ● start · coloured lines: cover runs · dashed: transit · red ×: critical points · blue ◆: backtracking points reached".to_string(),
    ];
    for (k, line) in lines.iter().enumerate() {
        let _ = writeln!(
            s,
            r##"<text x="0" y="{:.1}" font-size="{}" fill="#222">{}</text>"##,
            h + 18.0 + 17.0 * k as f64,
            if k == 0 { 14 } else { 12 },
            xml(line)
        );
    }
    s.push_str("</g></svg>\n");
    s
}

/// A picture of the world in metres (y up), drawn onto by the drive and
/// mission pictures: the shared scaffold (header, scale, blocked cells,
/// polylines, caption, footer), written once.
pub struct Canvas {
    out: String,
    /// Pixels per metre.
    pub s: f64,
    /// The world's height, m (y is flipped with it).
    pub h_m: f64,
    /// The drawing's height, px (the caption goes below it).
    pub h_px: f64,
}

impl Canvas {
    /// A canvas for a `w_m` × `h_m` world, at most 900 px across, with
    /// `caption_px` below the drawing.
    pub fn world(w_m: f64, h_m: f64, caption_px: f64) -> Self {
        let s = (900.0 / w_m.max(h_m)).min(200.0);
        let (w, h) = (w_m * s, h_m * s);
        let mut out = String::new();
        let _ = writeln!(
            out,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" font-family="sans-serif"><rect width="100%" height="100%" fill="#fff"/><g transform="translate(10,10)">"##,
            w + 20.0,
            h + caption_px
        );
        Self {
            out,
            s,
            h_m,
            h_px: h,
        }
    }

    /// A canvas for `map` of `cell_m` cells.
    pub fn for_map(map: &MapData, cell_m: f64, caption_px: f64) -> Self {
        let (w_m, h_m) = (map.width as f64 * cell_m, map.height as f64 * cell_m);
        Self::world(w_m, h_m, caption_px)
    }

    /// A world point (m) in pixels.
    pub fn px(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (x * self.s, (self.h_m - y) * self.s)
    }

    /// Appends raw SVG.
    pub fn raw(&mut self, svg: &str) {
        self.out.push_str(svg);
    }

    /// A crisp rectangle in pixels.
    pub fn rect_px(&mut self, (x, y, w, h): (f64, f64, f64, f64), fill: &str, extra: &str) {
        let _ = writeln!(
            self.out,
            r##"<rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" fill="{fill}"{extra} shape-rendering="crispEdges"/>"##,
        );
    }

    /// The map's blocked cells (`cell_m` each, row 0 at the top).
    pub fn blocked(&mut self, map: &MapData, cell_m: f64, fill: &str) {
        let c = cell_m * self.s;
        for y in 0..map.height as i32 {
            for x in 0..map.width as i32 {
                if map.is_blocked(x, y) {
                    self.rect_px((x as f64 * c, y as f64 * c, c, c), fill, "");
                }
            }
        }
    }

    /// A polyline through every `step`-th point (world m).
    pub fn polyline(&mut self, pts: &[(f64, f64)], step: usize, style: &str) {
        let p: Vec<String> = pts
            .iter()
            .step_by(step.max(1))
            .map(|&q| {
                let (x, y) = self.px(q);
                format!("{x:.1},{y:.1}")
            })
            .collect();
        let _ = write!(
            self.out,
            r#"<polyline points="{}" fill="none" {style}/>"#,
            p.join(" ")
        );
    }

    /// Caption lines under the drawing, and the footer.
    pub fn finish(mut self, lines: &[String]) -> String {
        for (k, l) in lines.iter().enumerate() {
            let _ = writeln!(
                self.out,
                r##"<text x="0" y="{:.0}" font-size="12" fill="#222">{}</text>"##,
                self.h_px + 18.0 + 16.0 * k as f64,
                l.replace('&', "&amp;").replace('<', "&lt;")
            );
        }
        self.out.push_str("</g></svg>\n");
        self.out
    }
}

/// Obstacles, one rect per horizontal run of blocked cells.
fn plan_obstacles(s: &mut String, map: &MapData, cs: f64) {
    for y in 0..map.height as i32 {
        let mut x = 0;
        while x < map.width as i32 {
            if map.is_blocked(x, y) {
                let x0 = x;
                while x < map.width as i32 && map.is_blocked(x, y) {
                    x += 1;
                }
                let _ = writeln!(
                    s,
                    r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="#3b3b3b" shape-rendering="crispEdges"/>"##,
                    x0 as f64 * cs,
                    y as f64 * cs,
                    (x - x0) as f64 * cs,
                    cs
                );
            } else {
                x += 1;
            }
        }
    }
}

/// Cover runs coloured by segment, transits dashed.
fn plan_segments(s: &mut String, p: &Plan, cs: f64) {
    let pt = |c: robovac::Cell| ((c.x as f64 + 0.5) * cs, (c.y as f64 + 0.5) * cs);
    let covers = p
        .segments
        .iter()
        .filter(|g| g.kind == SegmentKind::Cover)
        .count()
        .max(1);
    let mut ci = 0usize;
    for seg in &p.segments {
        let pts: Vec<String> = p.waypoints[seg.from..=seg.to]
            .iter()
            .map(|&c| {
                let (x, y) = pt(c);
                format!("{x:.1},{y:.1}")
            })
            .collect();
        match seg.kind {
            SegmentKind::Cover => {
                let hue = (ci * 360 / covers + (ci % 2) * 180 / covers.max(2)) % 360;
                ci += 1;
                let _ = writeln!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="hsl({hue},70%,45%)" stroke-width="{:.1}" stroke-linejoin="round" stroke-linecap="round" opacity="0.85"/>"#,
                    pts.join(" "),
                    (cs * 0.28).max(1.2)
                );
            }
            SegmentKind::Transit => {
                let _ = writeln!(
                    s,
                    r##"<polyline points="{}" fill="none" stroke="#111" stroke-width="{:.1}" stroke-dasharray="{:.1},{:.1}"/>"##,
                    pts.join(" "),
                    (cs * 0.16).max(1.0),
                    cs * 0.5,
                    cs * 0.3
                );
            }
        }
    }
}

/// Critical points (red ×), backtracking points reached (blue ◆), the
/// start (green ●).
fn plan_markers(s: &mut String, p: &Plan, cs: f64) {
    let pt = |c: robovac::Cell| ((c.x as f64 + 0.5) * cs, (c.y as f64 + 0.5) * cs);
    let r = (cs * 0.32).max(2.0);
    for &c in &p.critical_points {
        let (x, y) = pt(c);
        let _ = writeln!(
            s,
            r##"<path d="M{:.1},{:.1}L{:.1},{:.1}M{:.1},{:.1}L{:.1},{:.1}" stroke="#d62728" stroke-width="{:.1}"/>"##,
            x - r,
            y - r,
            x + r,
            y + r,
            x - r,
            y + r,
            x + r,
            y - r,
            (cs * 0.12).max(1.0)
        );
    }
    for &c in &p.backtrack_points {
        let (x, y) = pt(c);
        let _ = writeln!(
            s,
            r##"<path d="M{:.1},{:.1}L{:.1},{:.1}L{:.1},{:.1}L{:.1},{:.1}Z" fill="#1f77b4" stroke="#fff" stroke-width="0.8"/>"##,
            x,
            y - r,
            x + r,
            y,
            x,
            y + r,
            x - r,
            y
        );
    }
    let (sx, sy) = pt(p.start);
    let _ = writeln!(
        s,
        r##"<circle cx="{sx:.1}" cy="{sy:.1}" r="{:.1}" fill="#2ca02c" stroke="#fff"/>"##,
        r * 1.3
    );
}

fn xml(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
