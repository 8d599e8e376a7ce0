//! Runs the built `tactfab` binary from the crate root and captures what it prints.

use std::path::{Path, PathBuf};
use std::process::Command;

pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    #[track_caller]
    pub fn expect_code(&self, code: i32) -> &Self {
        assert_eq!(
            self.code, code,
            "exit code\n--- stdout\n{}\n--- stderr\n{}",
            self.stdout, self.stderr
        );
        self
    }
}

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `tactfab ARGS...` run in the crate root, with SOURCE_DATE_EPOCH cleared.
pub fn tactfab(args: &[&str]) -> Run {
    tactfab_in(&root(), args)
}

pub fn tactfab_in(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_tactfab"))
        .args(args)
        .current_dir(dir)
        .env_remove("SOURCE_DATE_EPOCH")
        .output()
        .expect("run tactfab");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

pub const REFERENCE: &str = "process/mis-grasper.yaml";

/// `tactfab ARGS` in the crate root with extra environment variables, as (code, stdout, stderr).
pub fn run_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tactfab"));
    c.args(args)
        .current_dir(root())
        .env_remove("SOURCE_DATE_EPOCH");
    for (k, v) in env {
        c.env(k, v);
    }
    let out = c.output().expect("the tactfab binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `tactfab ARGS` in the crate root, as (code, stdout, stderr).
pub fn run(args: &[&str]) -> (i32, String, String) {
    run_env(args, &[])
}

/// A `tactfab ARGS` command run in the crate root with SOURCE_DATE_EPOCH cleared, not yet
/// started (for tests that spawn, time or kill the process themselves).
pub fn command(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tactfab"));
    c.args(args)
        .current_dir(root())
        .env_remove("SOURCE_DATE_EPOCH");
    c
}

/// The SHA-256 of `bytes` as lowercase hex, as `sha256sum` prints it.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every SVG in `dir` keeps its text on its canvas ([`tactfab::plot::text_outside_canvas`]).
#[track_caller]
pub fn assert_svgs_fit(dir: &std::path::Path) {
    let mut seen = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "svg") {
            let svg = std::fs::read_to_string(&path).unwrap();
            let bad = tactfab::plot::text_outside_canvas(&svg);
            assert!(bad.is_empty(), "{}: {bad:?}", path.display());
            seen += 1;
        }
    }
    assert!(seen > 0, "no SVG in {}", dir.display());
}
