//! The command line: clap types in [`args`], value parsers in [`parse`], one file per
//! subcommand. Each subcommand parses nothing itself, makes one library call and prints; `run`
//! maps the outcome to the exit code.

mod args;
mod build;
mod calibrate;
mod check;
mod etch;
mod fe;
mod locate;
mod masks;
mod orient;
mod output;
mod parse;
mod readout;
mod softness;
mod sweep;
mod tissue;
mod traveler;

use clap::Parser;

use args::{Cli, Command, ProcessArgs};

/// Exit status: 0 ok, 1 a check failed, 2 bad input or error (the latter via `Err`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Ok,
    CheckFailed,
}

impl From<Outcome> for std::process::ExitCode {
    fn from(o: Outcome) -> Self {
        match o {
            Outcome::Ok => 0.into(),
            Outcome::CheckFailed => 1.into(),
        }
    }
}

/// Solid levels of `--verify-solid` (`fe` and `build`), fewer when `--max-levels` is lower: the
/// bundled design's four scenes take about half an hour on two (dev build, 2026-11-29).
const VERIFY_SOLID_LEVELS: usize = 2;

/// Solid levels of `fe --model solid`: three give the estimate.
const MODEL_SOLID_LEVELS: usize = 3;

/// The solid levels a run takes: `--solid-levels` as given, else `default` or `--max-levels` if
/// lower.
fn solid_levels(solid_levels: Option<u8>, default: usize, max_levels: usize) -> usize {
    solid_levels.map_or(default.min(max_levels), usize::from)
}

/// Parses the command line and runs the subcommand.
pub fn run() -> anyhow::Result<Outcome> {
    let cli = Cli::parse();
    // One thread per factorisation: on these plate meshes (up to ~60k dofs) faer's threaded
    // Cholesky ran 1.3-1.8x slower on 2 cores (benches/README.md); studies run their scenes
    // and designs in parallel with rayon instead.
    faer::set_global_parallelism(faer::Par::Seq);
    // A malformed memory limit is bad input whichever subcommand would meet it.
    tactfab::fe::memory::limit()?;
    dispatch(cli.command)
}

fn dispatch(command: Command) -> anyhow::Result<Outcome> {
    match command {
        Command::Check(a) => check::run(&a),
        Command::Etch(a) => etch::run(&a),
        Command::Fe(a) => fe::run(&a),
        Command::Masks(a) => masks::run(&a),
        Command::Build(a) => build::run(&a),
        Command::Traveler(a) => traveler::run(&a),
        Command::Sweep(a) => sweep::run(&a),
        Command::Softness(a) => softness::run(&a),
        Command::Calibrate(a) => calibrate::run(&a),
        Command::Locate(a) => locate::run(&a),
        Command::Orient(a) => orient::run(&a),
        Command::Readout(a) => readout::run(&a),
        Command::Tissue(a) => tissue::run(&a),
    }
}

/// Loads the process file with overrides; every problem becomes one error (exit 2).
pub fn load(args: &ProcessArgs) -> anyhow::Result<tactfab::process::Loaded> {
    tactfab::process::load(&args.file, &args.set).map_err(anyhow::Error::new)
}

/// Loads the process file and makes its design (plan and masks), once.
pub fn design(
    args: &ProcessArgs,
) -> anyhow::Result<(tactfab::process::Loaded, tactfab::design::Design)> {
    tactfab::design::Design::load(&args.file, &args.set).map_err(anyhow::Error::new)
}

/// The process's failed checks, on stderr, for the commands that analyse the design without
/// reporting them (`fe` and the studies): the model is the design as its recipe makes it, so
/// `--set geometry.plate_thickness_um=5` with a recipe that leaves 92 um answers for 92 um,
/// which the user must be told (until 2026-11-29 it was silent). Stdout stays the answer.
pub fn warn_process_errors(args: &ProcessArgs, design: &tactfab::design::Design) {
    let errors: Vec<tactfab::finding::Finding> = design
        .plan
        .warnings
        .iter()
        .filter(|w| w.is_error())
        .cloned()
        .collect();
    if errors.is_empty() {
        return;
    }
    eprint!(
        "warning: the process fails {} (`tactfab check {}` lists every finding); the answer is \
         for the design as its recipe makes it:\n{}",
        output::count(errors.len(), "check"),
        args.file.display(),
        output::checks(&errors)
    );
}

/// How outputs name the process file: its name and the SHA-256 of the bytes loaded, never the path
/// as typed (a relative and an absolute path must give the same bytes), with the overrides
/// applied.
pub fn origin(args: &ProcessArgs, loaded: &tactfab::process::Loaded) -> tactfab::report::Origin {
    let name = args.file.file_name().map_or_else(
        || args.file.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    tactfab::report::Origin::new(&name, &loaded.source_sha256, &loaded.overrides)
}

/// The refusals of [`write_dir`] for `out`, checked before a command's work so a refused
/// directory costs no solve (`build --verify-solid` takes half an hour).
pub fn check_out(
    out: &std::path::Path,
    replace: args::OverwriteArgs,
    process: &ProcessArgs,
) -> anyhow::Result<()> {
    let inputs = [process.file.as_path()];
    tactfab::export::dir::check_dir(out, &guard(replace, &inputs))?;
    Ok(())
}

/// Writes `files` as the whole directory `out`: replaces only a previous output of tactfab (or
/// anything, with `--overwrite`), never the directory holding the process file.
pub fn write_dir(
    out: &std::path::Path,
    files: &[(String, Vec<u8>)],
    replace: args::OverwriteArgs,
    process: &ProcessArgs,
) -> anyhow::Result<()> {
    let inputs = [process.file.as_path()];
    tactfab::export::dir::write_dir_atomic(out, files, &guard(replace, &inputs))?;
    Ok(())
}

/// What an output directory may replace: anything with `--overwrite`, never the process file.
fn guard<'a>(
    replace: args::OverwriteArgs,
    inputs: &'a [&'a std::path::Path],
) -> tactfab::export::dir::Guard<'a> {
    tactfab::export::dir::Guard {
        overwrite: replace.overwrite,
        flag: "--overwrite",
        inputs,
    }
}

/// A spinner on stderr when it is a terminal; nothing otherwise.
pub struct Progress(Option<indicatif::ProgressBar>);

impl Progress {
    pub fn new() -> Self {
        use std::io::IsTerminal;
        if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new_spinner();
            bar.enable_steady_tick(std::time::Duration::from_millis(120));
            Progress(Some(bar))
        } else {
            Progress(None)
        }
    }
    pub fn stage(&self, s: tactfab::report::Stage) {
        self.message(s.label());
    }
    pub fn message(&self, s: String) {
        if let Some(b) = &self.0 {
            b.set_message(s);
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(b) = &self.0 {
            b.finish_and_clear();
        }
    }
}
