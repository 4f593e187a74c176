//! `refract`: the thin binary. Parses the command line and hands it to the
//! library. Every error, the command line's too, is printed as one line
//! (`refract: error: ...`) and exits with status 1; help and version exit 0.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let (args, notes) = refract::cli::modern_args(std::env::args_os().collect());
    let cli = match refract::cli::Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) => return ExitCode::from(refract::cli::parse_failure(e, &args)),
    };
    for n in notes {
        eprintln!("note: {n}");
    }
    match refract::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("refract: error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
