//! `refract`: the thin binary. Parses the command line and hands it to the
//! library; errors are printed as one line and exit with status 1 (2 for a
//! bad command line).

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = match refract::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => {
            // clap's first line names the flag and the reason; the rest is a hint.
            let text = e.to_string();
            eprintln!("refract: {}", text.lines().next().unwrap_or("bad command line").trim_start_matches("error: "));
            return ExitCode::from(2);
        }
    };
    match refract::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("refract: error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
