//! A reader that stops early (`tactfab fe FILE | head -1`) ends tactfab as it ends `cat`: by
//! SIGPIPE, quietly, not with a panic and a backtrace on every print to the closed pipe.

use std::os::unix::process::ExitStatusExt;
use std::process::Stdio;

use super::harness::{command, REFERENCE};

/// SIGPIPE's number on Linux.
const SIGPIPE: i32 = 13;

#[test]
fn a_closed_pipe_ends_tactfab_quietly() {
    for args in [
        &["etch", REFERENCE][..],
        &[
            "fe",
            REFERENCE,
            "--model",
            "plate",
            "--scene",
            "centre-1n",
            "--max-levels",
            "1",
        ][..],
    ] {
        let mut child = command(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("tactfab starts");
        // The reader is gone before tactfab has computed anything to print.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("tactfab ends");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(out.status.signal(), Some(SIGPIPE), "{args:?}: {stderr}");
    }
}
