//! The `tactfab` binary: parse arguments, dispatch, map the outcome to an exit code.

use std::process::ExitCode;

fn main() -> ExitCode {
    match tactfab_cli::run() {
        Ok(code) => code.into(),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

#[path = "cli/mod.rs"]
mod tactfab_cli;
