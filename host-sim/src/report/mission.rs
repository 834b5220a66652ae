//! A mission reported: its one-line summary, its events as JSON, and its
//! picture (on the shared [`super::svg::Canvas`]).

use super::svg::Canvas;
use crate::io::maps::MapData;
use crate::run::mission::{MissionReport, MissionTrace};
use crate::sim::floor::Floor;

/// The executive's events as JSON: time (s) and what happened.
pub fn events_json(events: &[robovac::mission::Event]) -> serde_json::Value {
    let list: Vec<_> = events
        .iter()
        .map(
            |e| serde_json::json!({"t_s": e.at_us as f64 * 1e-6, "event": format!("{:?}", e.kind)}),
        )
        .collect();
    serde_json::Value::Array(list)
}

/// One line of summary.
pub fn summary(rep: &MissionReport) -> String {
    let zones = rep.zones.map_or(String::new(), |z| {
        format!(
            " · {} no-go zones/virtual walls: entered {} times, closest {:.0} mm",
            z.count, z.entries, z.min_gap_mm
        )
    });
    let charges = match rep.charges {
        0 => String::new(),
        n => format!(
            " · {n} charges ({:.0} min on the dock)",
            rep.charging_time_s / 60.0
        ),
    };
    let scrolls = rep
        .map_scrolls
        .map_or(String::new(), |n| format!(" · map scrolled {n} times"));
    let missing = match rep.people_missing {
        0 => String::new(),
        n => format!(" · {n} people asked for found no loop to walk and were left out"),
    };
    let objects = rep.objects.map_or(String::new(), |o| {
        format!(
            " · {} unseen objects: {} contacts, {} wheel snags, {:.1} % of the floor near them swept",
            o.objects,
            o.contacts,
            o.snags,
            100.0 * o.near_coverage
        )
    });
    format!(
        "finished {} · back at start {} · coverage {:.2} % · repetition {:.2} · collisions {} (people into robot {}) · min clearance {:.3} m · {:.1} m in {:.0} s of cleaning (ideal {:.0} s, ×{:.2}; time ÷ area-ideal {:.2}) · avoidances {} · {:.0}× real time",
        rep.finished,
        rep.returned_to_start,
        100.0 * rep.coverage,
        rep.repetition,
        rep.collisions,
        rep.person_contacts,
        rep.min_clearance_m,
        rep.distance_m,
        rep.cleaning_time_s,
        rep.ideal_time_s,
        rep.cleaning_time_s / rep.ideal_time_s.max(1e-9),
        rep.cleaning_time_s / rep.floor_time_s.max(1e-9),
        rep.avoidance_events,
        rep.sim_time_s / rep.wall_time_s.max(1e-9),
    ) + &charges
        + &scrolls
        + &zones
        + &objects
        + &missing
}

/// Things the lidar cannot see: sofas brown and hatched, crossbars brown
/// lines, cables purple dashes; where a wheel snagged, purple dots.
fn objects_svg(c: &mut Canvas, objects: &[crate::sim::objects::LowObject], snags: &[(f64, f64)]) {
    use crate::sim::objects::LowKind;
    for o in objects {
        let (a, b) = (c.px(o.a), c.px(o.b));
        let shape = match o.kind {
            LowKind::Sofa => format!(
                "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#8c564b\" fill-opacity=\"0.35\" stroke=\"#8c564b\" stroke-dasharray=\"4,2\"/>\n",
                a.0.min(b.0), a.1.min(b.1), (a.0 - b.0).abs(), (a.1 - b.1).abs()
            ),
            LowKind::Crossbar => format!(
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#8c564b\" stroke-width=\"3\"/>\n",
                a.0, a.1, b.0, b.1
            ),
            LowKind::Cable => format!(
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#9467bd\" stroke-width=\"3\" stroke-dasharray=\"5,3\"/>\n",
                a.0, a.1, b.0, b.1
            ),
        };
        c.raw(&shape);
    }
    for &p in snags {
        let (x, y) = c.px(p);
        c.raw(&format!(
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"4\" fill=\"#9467bd\"/>\n"
        ));
    }
}

/// What a ValetudoMap adds: the vendor robot's own paths (grey).
fn map_extras(c: &mut Canvas, map: &MapData) {
    let Some(x) = map.extras.as_ref() else {
        return;
    };
    for p in &x.paths {
        c.polyline(p, 1, r##"stroke="#888" stroke-width="0.8" opacity="0.6""##);
    }
}

/// The owner's zones (the map's and the command line's): no-go areas red
/// and translucent, virtual walls as red lines.
fn zones_svg(c: &mut Canvas, zones: &[robovac::grid::Zone]) {
    use robovac::grid::Zone;
    let m = |v: i32| v as f64 / 1000.0;
    for z in zones {
        match *z {
            Zone::NoGo {
                x0_mm,
                y0_mm,
                x1_mm,
                y1_mm,
            } => {
                let (a, b) = (c.px((m(x0_mm), m(y0_mm))), c.px((m(x1_mm), m(y1_mm))));
                c.raw(&format!(
                    "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#d62728\" fill-opacity=\"0.25\" stroke=\"#d62728\"/>\n",
                    a.0.min(b.0), a.1.min(b.1), (a.0 - b.0).abs(), (a.1 - b.1).abs()
                ));
            }
            Zone::Wall {
                ax_mm,
                ay_mm,
                bx_mm,
                by_mm,
            } => {
                let (a, b) = (c.px((m(ax_mm), m(ay_mm))), c.px((m(bx_mm), m(by_mm))));
                c.raw(&format!(
                    "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#d62728\" stroke-width=\"3\"/>\n",
                    a.0, a.1, b.0, b.1
                ));
            }
        }
    }
}

/// The rooms tinted, one hue each, over the swept floor; runs of one
/// room in a row of planning cells, one rectangle each.
fn rooms_svg(c: &mut Canvas, rooms: &crate::run::rooms::RoomView) {
    let (s, k) = (c.s, rooms.cell_m * c.s);
    let dy = rooms.map_h_m - c.h_m;
    let (w, h) = (rooms.size.0 as usize, rooms.size.1 as usize);
    for (y, row) in rooms.labels.chunks(w.max(1)).take(h).enumerate() {
        let mut x = 0;
        while x < row.len() {
            let id = row[x];
            let run = row[x..].iter().take_while(|&&l| l == id).count();
            if id != 0 {
                let hue = (id as u32 * 137) % 360;
                let px = (x as f64 * k, y as f64 * k - dy * s, run as f64 * k, k);
                c.rect_px(px, &format!("hsl({hue},70%,55%)"), r#" opacity="0.3""#);
            }
            x += run;
        }
    }
}

/// The potential field's local minima (`--local apf`), as black diamonds
/// where the robot believed it was; returns how many.
fn local_minima_svg(c: &mut Canvas, events: &[robovac::mission::Event]) -> usize {
    let mut n = 0;
    for e in events {
        if let robovac::mission::EventKind::LocalMinimum { x_mm, y_mm } = e.kind {
            let (x, y) = c.px((x_mm as f64 / 1000.0, y_mm as f64 / 1000.0));
            c.raw(&format!(
                "<path d=\"M{x:.1},{:.1} l7,7 l-7,7 l-7,-7 z\" fill=\"#000\"/>\n",
                y - 7.0
            ));
            n += 1;
        }
    }
    n
}

/// The mission as an SVG: the ground truth, the swept floor shaded (missed
/// reachable floor in red), the trajectory, people's tracks, avoidances
/// (blue rings) and collisions (red crosses: the robot's; orange: a person
/// walked into it), the robot's own estimate beside the truth, and a
/// ValetudoMap's paths, no-go areas and virtual walls, with the metrics as
/// a caption.
pub fn mission_svg(
    map: &MapData,
    cell_m: f64,
    floor: &Floor,
    t: &MissionTrace,
    rep: &MissionReport,
    title: &str,
) -> String {
    let mut c = Canvas::for_map(map, cell_m, 120.0);
    let (s, hm) = (c.s, c.h_m);
    // Swept / missed floor: runs of equal state in a row, one rectangle each.
    let (res, fw, fh) = floor.dims();
    for y in 0..fh {
        let mut x = 0;
        while x < fw {
            let st = floor.state(x, y);
            let mut x1 = x + 1;
            while x1 < fw && floor.state(x1, y) == st {
                x1 += 1;
            }
            if let Some(swept) = st {
                let colour = if swept { "#c7e9c0" } else { "#f4a6a6" };
                let px = (x as f64 * res * s, (hm - (y + 1) as f64 * res) * s);
                c.rect_px((px.0, px.1, (x1 - x) as f64 * res * s, res * s), colour, "");
            }
            x = x1;
        }
    }
    if let Some(rooms) = &t.rooms {
        rooms_svg(&mut c, rooms);
    }
    c.blocked(map, cell_m, "#555");
    for track in &t.people {
        c.polyline(
            track,
            1,
            r##"stroke="#ff7f0e" stroke-width="1" opacity="0.5""##,
        );
    }
    map_extras(&mut c, map);
    zones_svg(&mut c, &t.zones);
    objects_svg(&mut c, &t.objects, &t.snags);
    c.polyline(
        &t.truth,
        5,
        r##"stroke="#1f3f9f" stroke-width="1.2" opacity="0.8""##,
    );
    c.polyline(
        &t.estimate,
        1,
        r##"stroke="#e377c2" stroke-width="1" stroke-dasharray="3,3" opacity="0.9""##,
    );
    for &p in &t.avoidances {
        let (x, y) = c.px(p);
        c.raw(&format!(
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"6\" fill=\"none\" stroke=\"#1f77b4\" stroke-width=\"2\"/>\n"
        ));
    }
    for &(p, by_person) in &t.collisions {
        let colour = if by_person { "#ff7f0e" } else { "#d62728" };
        let (x, y) = c.px(p);
        c.raw(&format!(
            "<path d=\"M{:.1},{:.1} l12,12 m0,-12 l-12,12\" stroke=\"{colour}\" stroke-width=\"3\"/>\n",
            x - 6.0,
            y - 6.0
        ));
    }
    let minima = local_minima_svg(&mut c, &t.events);
    if let Some((_, (x, y, _))) = t.kidnap {
        let (x, y) = c.px((x, y));
        c.raw(&format!(
            "<path d=\"M{x:.1},{:.1} l8,14 l-16,0 z\" fill=\"#9467bd\" stroke=\"#000\"/>\n",
            y - 9.0
        ));
    }
    let (x, y) = c.px(t.start);
    c.raw(&format!(
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"12\" height=\"12\" fill=\"#2ca02c\" stroke=\"#000\"/>\n",
        x - 6.0,
        y - 6.0
    ));
    let lines = [
        title.to_string(),
        format!(
            "coverage {:.2} % of {:.1} m² reachable floor · repetition {:.2} · finished {} · back at the dock {}",
            100.0 * rep.coverage,
            rep.floor_m2,
            rep.repetition,
            rep.finished,
            rep.returned_to_start
        ),
        format!(
            "collisions {} (people walking into the robot {}) · min clearance {:.3} m · avoidances {} · {:.1} m in {:.0} s (path ÷ speed {:.0} s)",
            rep.collisions,
            rep.person_contacts,
            rep.min_clearance_m,
            rep.avoidance_events,
            rep.distance_m,
            rep.sim_time_s,
            rep.ideal_time_s
        ),
        format!(
            "pose error vs truth: RMS {:.1} mm, max {:.1} mm; heading RMS {:.1} mrad, max {:.1} mrad · docked {} ({:.0} mm, {:.0} mrad)",
            rep.pose_error_rms_mm,
            rep.pose_error_max_mm,
            rep.heading_error_rms_mrad,
            rep.heading_error_max_mrad,
            rep.docked,
            rep.dock_error_mm,
            rep.dock_heading_error_mrad
        ),
        "green: swept · red: reachable floor missed · blue line: robot (truth) · pink dashes: its own estimate · orange: people · rings: avoidances · crosses: collisions · square: dock · grey: the vendor robot's paths · red hatched: no-go areas, red lines: virtual walls · brown: sofas and crossbars, purple dashes: cables (dots: wheel snags)".to_string()
            + if minima > 0 { " · black diamonds: the potential field's local minima" } else { "" }
            + &t.kidnap.map_or(String::new(), |(at, _)| format!(" · purple triangle: put down there by the kidnap at {at:.0} s")),
    ];
    c.finish(&lines)
}
