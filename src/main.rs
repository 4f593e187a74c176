//! `refract`: the thin binary. Parses the command line and hands it to the
//! library; errors are printed as one line and exit with status 1. A bad
//! command line gets clap's whole message (the reason, a suggestion or the
//! possible values, the usage and the `--help` hint) and status 2.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = refract::cli::Cli::parse();
    match refract::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("refract: error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
