//! The command line: one file per command, each with its arguments and
//! its `run`; [`args`] holds what they share. The business logic lives in
//! the library (`host_sim::…`).

pub mod args;
pub mod bench;
pub mod bench_coverage;
pub mod bench_missions;
pub mod bench_peers;
pub mod bench_replan;
pub mod bench_seeds;
pub mod demo;
pub mod drive;
pub mod lidar;
pub mod mission;
pub mod plan;
pub mod power_loss;
pub mod progress;
pub mod scen;
pub mod search;

/// The commands.
#[derive(clap::Subcommand)]
pub enum Cmd {
    /// A whole cleaning mission on the built-in furnished flat with two people walking; writes demo.svg.
    Demo,
    /// Search one path.
    Search(search::Args),
    /// Run every problem of a MovingAI scenario file.
    Scen(scen::Args),
    /// Plan a complete coverage of a map.
    Plan(plan::Args),
    /// Decode a captured lidar byte stream.
    LidarDecode(lidar::Args),
    /// Drive a route with the real wheel controllers and odometry while the lidar maps.
    Drive(drive::Args),
    /// Run a whole cleaning mission: the core's executive in closed loop with the physics.
    Mission(Box<mission::Args>),
    /// Benchmarks reproducing the papers' tables.
    Bench {
        #[command(subcommand)]
        which: bench::BenchCmd,
    },
}

/// Runs a command.
pub fn run(cmd: Cmd) -> Result<(), String> {
    match cmd {
        Cmd::Demo => demo::run(),
        Cmd::Search(a) => search::run(a),
        Cmd::Scen(a) => scen::run(a),
        Cmd::Plan(a) => plan::run(a),
        Cmd::LidarDecode(a) => lidar::run(a),
        Cmd::Drive(a) => drive::run(a),
        Cmd::Mission(a) => mission::run(*a),
        Cmd::Bench { which } => bench::run(which),
    }
}
