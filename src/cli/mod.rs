//! Command-line types and dispatch; each subcommand lives in its own file.

mod build;
mod check;
mod etch;
mod fe;
mod masks;
mod output;
mod traveler;

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

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

#[derive(Debug, Parser)]
#[command(name = "tactfab", version, about = "From one process file to etch plan, masks, FE sensitivity and traveler for PVDF tactile sensors")]
#[command(after_help = "Exit codes: 0 ok, 1 a check of the process failed, 2 bad input or I/O error.")]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Validate a process file: summary, defaults used and their sources, all warnings.
    Check(ProcessArgs),
    /// Compute the etch plan: rates, times, sidewalls, compensation, oxide budget.
    Etch(EtchArgs),
    /// Finite-element sensitivity: charge and voltage of every electrode under each scene.
    Fe(FeArgs),
    /// Generate the mask set (GDS, SVG per mask, KLayout .lyp), print the inventory and run DRC.
    Masks(MasksArgs),
    /// Everything for one process file into DIR: etch plan, masks, DRC, FE checks, traveler, build.json.
    Build(BuildArgs),
    /// The process traveler (run sheet) as Markdown and a self-contained HTML page.
    Traveler(TravelerArgs),
}

/// The process file and what-if overrides, shared by every subcommand.
#[derive(Debug, Args)]
pub struct ProcessArgs {
    /// Process file (YAML), e.g. process/mis-grasper.yaml.
    pub file: PathBuf,
    /// Override a field: `--set steps.tmah-etch.temp_c=85`, `--set geometry.teeth.pattern=matrix`
    /// (repeatable; steps may be named or indexed as steps[10]).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<String>,
}

#[derive(Debug, Args)]
pub struct EtchArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Print the plan as JSON (stable contract) instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct FeArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Run only this scene of checks.scenes.
    #[arg(long)]
    pub scene: Option<String>,
    /// Ad-hoc point load in die coordinates: X_MM,Y_MM,FORCE_N[,RADIUS_MM] (radius default 0.25 mm).
    #[arg(long, value_name = "X_MM,Y_MM,FORCE_N[,RADIUS_MM]")]
    pub point: Vec<String>,
    /// Ad-hoc uniform pressure over the plate, by total force.
    #[arg(long, value_name = "FORCE_N", allow_hyphen_values = true)]
    pub pressure: Vec<f64>,
    /// Relative error the answer must be under (estimated from three meshes).
    #[arg(long, default_value_t = 0.01)]
    pub tol: f64,
    /// Most mesh levels to try (each halves the element size, starting at 2 mm).
    #[arg(long, default_value_t = 6)]
    pub max_levels: usize,
    /// Print JSON (`{"scenes": [...]}`, stable contract) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Print the per-level convergence table (mesh, elements, dofs, time, value, estimate, order)
    /// and write the plot of error against dofs and time (see --plot).
    #[arg(long)]
    pub convergence: bool,
    /// Where --convergence writes its SVG plot.
    #[arg(long, value_name = "SVG", default_value = "fe-convergence.svg", requires = "convergence")]
    pub plot: PathBuf,
}

#[derive(Debug, Args)]
pub struct MasksArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory; files are `<device>.gds`, `<device>.lyp`, `<device>-<mask>.svg`.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Formats to write (comma-separated); the .lyp comes with gds.
    #[arg(long, value_delimiter = ',', default_value = "gds,svg")]
    pub format: Vec<masks::Format>,
}

/// FE settings shared by `build` and `traveler`.
#[derive(Debug, Args)]
pub struct FeSettings {
    /// Relative error each declared scene is refined to (estimated from three meshes).
    #[arg(long, default_value_t = 0.01)]
    pub tol: f64,
    /// Most mesh levels to try (each halves the element size, starting at 1 mm).
    #[arg(long, default_value_t = 6)]
    pub max_levels: usize,
}

#[derive(Debug, Args)]
pub struct BuildArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory, written atomically; an existing one is replaced only if it holds a
    /// previous build (`build.json`) or is empty.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub fe: FeSettings,
}

#[derive(Debug, Args)]
pub struct TravelerArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output path: writes PATH.md and PATH.html (a `.md` or `.html` extension is replaced).
    #[arg(short = 'o', long = "out", value_name = "PATH")]
    pub out: PathBuf,
    /// Skip the FE solves: the traveler says the sensitivity was not computed.
    #[arg(long)]
    pub no_fe: bool,
    #[command(flatten)]
    pub fe: FeSettings,
}

/// Parses the command line and runs the subcommand.
pub fn run() -> anyhow::Result<Outcome> {
    let cli = Cli::parse();
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
    }
}

/// Loads the process file with overrides; every problem becomes one error (exit 2).
pub fn load(args: &ProcessArgs) -> anyhow::Result<tactfab::process::Loaded> {
    tactfab::process::load(&args.file, &args.set).map_err(anyhow::Error::new)
}

/// The electrode rectangles the FE model reads: those of the PVDF mask.
pub fn electrodes(p: &tactfab::process::Process, plan: &tactfab::etch::EtchPlan) -> anyhow::Result<Vec<tactfab::sensor::ElectrodeArea>> {
    let masks = tactfab::layout::build(p, plan).map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(tactfab::sensor::SensorGeometry::electrodes_from_masks(&masks))
}

/// SOURCE_DATE_EPOCH for GDS dates, if set (reproducible builds); an unparsable value is an error.
pub fn source_date_epoch() -> anyhow::Result<Option<i64>> {
    use anyhow::Context;
    match std::env::var("SOURCE_DATE_EPOCH") {
        Ok(s) if !s.trim().is_empty() => {
            Ok(Some(s.trim().parse::<i64>().with_context(|| format!("SOURCE_DATE_EPOCH=`{s}` is not an integer number of seconds"))?))
        }
        _ => Ok(None),
    }
}

/// Validates FE settings given on the command line.
pub fn fe_options(s: &FeSettings) -> anyhow::Result<tactfab::report::FeOptions> {
    if !(s.tol > 0.0 && s.tol < 1.0) {
        anyhow::bail!("--tol {}: expected a relative error between 0 and 1, e.g. 0.01", s.tol);
    }
    if s.max_levels == 0 {
        anyhow::bail!("--max-levels 0: expected at least 1 mesh level");
    }
    Ok(tactfab::report::FeOptions { tol_rel: s.tol, max_levels: s.max_levels })
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
        if let Some(b) = &self.0 {
            b.set_message(s.label());
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
