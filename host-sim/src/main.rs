//! `host-sim`: parses the command line and dispatches to [`cli`]; a bad
//! input is one line on stderr and exit code 2.

mod cli;

use std::process::ExitCode;

use clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand as MissingCommand;
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
    let args = match Cli::try_parse() {
        Ok(args) => args,
        // Help and version are printed whole (exit 0), and so is the help
        // asked for by giving no command (exit 2).
        Err(e) if !e.use_stderr() || e.kind() == MissingCommand => e.exit(),
        // A usage error: its first line only ("error: ..."), exit code 2,
        // as for every other bad input.
        Err(e) => {
            let text = e.to_string();
            eprintln!("{}", text.lines().next().unwrap_or("error: bad arguments"));
            return ExitCode::from(2);
        }
    };
    match cli::run(args.cmd) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}
