//! The `tactfab` binary: `main -> cli::run -> dispatch`, the outcome mapped to an exit code
//! (0 ok, 1 a check failed, 2 bad input or error).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    match cli::run() {
        Ok(code) => code.into(),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
