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

/// Chromium (or Chrome) on PATH, if any.
pub fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let ok = Command::new(name)
                .arg("--version")
                .output()
                .map(|o| o.status.success())
                .unwrap_or(false);
            ok.then(|| PathBuf::from(name))
        })
}

/// Headless `chrome` with the flags every test run shares and its own profile directory.
pub fn headless(chrome: &Path, profile: &Path) -> Command {
    let mut c = Command::new(chrome);
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
    ])
    .arg(format!("--user-data-dir={}", profile.display()));
    c
}

/// Every SVG in `dir` keeps its text on its canvas: estimated from the SVG
/// ([`tactfab::plot::text_outside_canvas`]) and, where Chromium is installed (always in CI),
/// as the browser lays it out ([`rendered_text_outside`]).
#[track_caller]
pub fn assert_svgs_fit(dir: &Path) {
    let mut svgs = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "svg") {
            let svg = std::fs::read_to_string(&path).unwrap();
            let bad = tactfab::plot::text_outside_canvas(&svg);
            assert!(bad.is_empty(), "{}: {bad:?}", path.display());
            svgs.push((path.display().to_string(), svg));
        }
    }
    assert!(!svgs.is_empty(), "no SVG in {}", dir.display());
    let bad = rendered_text_outside(&svgs);
    assert!(
        bad.is_empty(),
        "text outside its canvas in Chromium: {bad:#?}"
    );
}

/// Lays the SVGs out in headless Chromium and lists every `<text>` whose rendered box leaves the
/// box of the `<svg>` holding it (1 px slack), as "file: text (left, right, top, bottom margins)".
/// Empty, with a note, when Chromium is missing outside CI.
pub fn rendered_text_outside(svgs: &[(String, String)]) -> Vec<String> {
    let Some(chrome) = chromium() else {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("chromium is not installed: `.ci/run` installs the Debian package `chromium`");
        }
        eprintln!("SKIPPED the rendered SVG check: chromium is not on PATH");
        return Vec::new();
    };
    let work = tempfile::tempdir().unwrap();
    let charts: String = svgs
        .iter()
        .map(|(_, s)| format!("<div class=\"chart\">{s}</div>\n"))
        .collect();
    let names = serde_json::to_string(&svgs.iter().map(|(n, _)| n).collect::<Vec<_>>()).unwrap();
    let html = format!(
        "<!DOCTYPE html><html><body>{charts}<pre id=\"result\"></pre><script>\n\
         const names = {names}; const out = [];\n\
         document.querySelectorAll('div.chart > svg').forEach((svg, i) => {{\n\
           svg.querySelectorAll('text').forEach(t => {{\n\
             const c = t.closest('svg').getBoundingClientRect();\n\
             const b = t.getBoundingClientRect();\n\
             const m = [b.left - c.left, c.right - b.right, b.top - c.top, c.bottom - b.bottom];\n\
             if (b.width > 0 && m.some(v => v < -1))\n\
               out.push(names[i] + ': ' + JSON.stringify(t.textContent.trim()) + ' ' +\n\
                        m.map(v => v.toFixed(1)).join(','));\n\
           }});\n\
         }});\n\
         document.getElementById('result').textContent = 'CHECKED ' + names.length + '\\n' +\n\
           out.join('\\n');\n\
         </script></body></html>\n"
    );
    let page = work.path().join("charts.html");
    std::fs::write(&page, html).unwrap();
    let out = headless(&chrome, &work.path().join("profile"))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    let start = dom
        .find(&format!("CHECKED {}", svgs.len()))
        .unwrap_or_else(|| panic!("Chromium did not run the check:\n{dom}"));
    dom[start..]
        .split("</pre>")
        .next()
        .unwrap_or("")
        .lines()
        .skip(1)
        .map(str::to_string)
        .collect()
}
