//! `host-sim`: parses the command line and dispatches to [`cli`]; a bad
//! input is one line on stderr and exit code 2.

mod cli;

use std::process::ExitCode;

use clap::Parser;

#[derive(Parser)]
#[command(
    name = "host-sim",
    version,
    about = "robovac host simulator: the firmware core on your PC"
)]
struct Cli {
    #[command(subcommand)]
    cmd: cli::Cmd,
}

fn main() -> ExitCode {
    match cli::run(Cli::parse().cmd) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}
