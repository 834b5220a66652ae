//! `host-sim demo`: the product at work.

use std::io::{IsTerminal, Write};
use std::path::Path;

use super::args::write_file;
use super::progress;

/// Runs the command.
pub fn run() -> Result<(), String> {
    cmd_demo()
}

/// `host-sim demo`: the product at work.
fn cmd_demo() -> Result<(), String> {
    use host_sim::report::mission::{mission_svg, summary};
    use host_sim::run::mission::{run_mission, MissionOptions};
    use host_sim::run::suite::suite_map;
    let map = suite_map("home")?;
    let opts = MissionOptions::new(
        map,
        robovac::mission::MapMode::Known,
        2,
        host_sim::sim::robot::Noise::None,
        1,
    );
    println!(
        "robovac demo: the firmware's mission executive cleans a 9.6 m × 7.2 m furnished flat"
    );
    println!(
        "(living room, kitchen, hallway, two bedrooms, bathroom) while two people walk about."
    );
    let tty = std::io::stdout().is_terminal();
    let pb = progress::status();
    let (rep, trace, floor) = run_mission(&opts, |t, state, cov| {
        if tty {
            pb.set_message(format!(
                "{t:>6.0} s simulated · {state:?} · {:.1} % of the floor swept",
                100.0 * cov
            ));
        } else if (t as u64).is_multiple_of(300) {
            println!(
                "  {t:>6.0} s simulated · {state:?} · {:.1} % of the floor swept",
                100.0 * cov
            );
        }
        let _ = std::io::stdout().flush();
    })?;
    pb.finish_and_clear();
    println!("  {}", summary(&rep));
    let svg = mission_svg(
        &opts.map,
        opts.cell_m,
        &floor,
        &trace,
        &rep,
        "robovac demo: known map, two people walking, ideal sensors",
    );
    write_file(Path::new("demo.svg"), &svg)?;
    println!(
        "  picture: demo.svg (swept floor green, missed red, the robot's path blue, people orange)"
    );
    Ok(())
}
