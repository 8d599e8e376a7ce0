//! Runs the built binary and returns (exit code, stdout, stderr).

use std::path::Path;
use std::process::Command;

/// Repository root (process files, masks/, tests/ scripts).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `tactfab ARGS` in the repository root with extra environment variables.
pub fn tactfab_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tactfab"));
    c.args(args).current_dir(root()).env_remove("SOURCE_DATE_EPOCH");
    for (k, v) in env {
        c.env(k, v);
    }
    let out = c.output().expect("the tactfab binary runs");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// `tactfab ARGS` in the repository root.
pub fn tactfab(args: &[&str]) -> (i32, String, String) {
    tactfab_env(args, &[])
}
