//! `tactfab traveler FILE -o PATH`: the run sheet as PATH.md and PATH.html.

use std::path::PathBuf;

use anyhow::Context;

use tactfab::export::write_atomic;
use tactfab::report::{build, Options};

use super::args::TravelerArgs;
use super::{design, Outcome, Progress};

pub fn run(args: &TravelerArgs) -> anyhow::Result<Outcome> {
    let (loaded, design) = design(&args.process)?;
    let opts = Options {
        process_file: args.process.file.display().to_string(),
        fe: (!args.no_fe).then(|| args.accuracy.into()),
        gds_epoch_s: args.date.epoch_s,
    };
    let built = {
        let progress = Progress::new();
        build(&loaded, &design, &opts, &mut |s| progress.stage(s))?
    };
    let (md, html) = paths(&args.out);
    if let Some(dir) = md.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    write_atomic(&md, built.markdown.as_bytes())?;
    write_atomic(&html, built.html.as_bytes())?;
    println!("wrote {} and {}", md.display(), html.display());
    let failures = built.failures();
    for f in &failures {
        println!("  FAIL: {f}");
    }
    Ok(if failures.is_empty() {
        Outcome::Ok
    } else {
        Outcome::CheckFailed
    })
}

/// PATH.md and PATH.html, with a given `.md`/`.html` extension replaced.
fn paths(out: &std::path::Path) -> (PathBuf, PathBuf) {
    let base = match out.extension().and_then(|e| e.to_str()) {
        Some("md") | Some("html") => out.with_extension(""),
        _ => out.to_path_buf(),
    };
    let with = |ext: &str| {
        let mut s = base.clone().into_os_string();
        s.push(ext);
        PathBuf::from(s)
    };
    (with(".md"), with(".html"))
}
