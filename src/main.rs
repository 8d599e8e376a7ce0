//! The `tactfab` binary: `main -> cli::run -> dispatch`, the outcome mapped to an exit code
//! (0 ok, 1 a check failed, 2 bad input or error).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    restore_sigpipe();
    match cli::run() {
        Ok(code) => code.into(),
        Err(e) => {
            eprintln!("error: {}", chain(&e));
            ExitCode::from(2)
        }
    }
}

/// A reader that stops early (`tactfab fe FILE | head -1`) ends tactfab as it ends `cat`, by
/// SIGPIPE: Rust's runtime ignores the signal, so each print to the closed pipe would instead
/// panic with a backtrace.
fn restore_sigpipe() {
    #[cfg(target_os = "linux")]
    // SAFETY: first thing in main, before any thread starts; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// The error and its causes, each once: a cause whose text the message above it already quotes
/// (thiserror's `{0}` of a `#[from]` source) is not repeated.
fn chain(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.contains(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}
