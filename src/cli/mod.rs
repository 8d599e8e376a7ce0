//! Command-line types and dispatch; each subcommand lives in its own file.

mod calibrate;
mod check;
mod etch;
mod fe;
mod locate;
mod masks;
mod orient;
mod output;

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
    /// Calibration tables (force, y, x sweeps), the load inverse's error on held-out loads and under noise: CSV + SVG in DIR.
    Calibrate(CalibrateArgs),
    /// Force and position of a load from the electrode voltages (through the calibration grid).
    Locate(LocateArgs),
    /// Probe-orientation study (paper 000): charge against angle, fits, inverse angle, bivariate function.
    Orient(OrientArgs),
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
    /// Most mesh levels to try (each halves the element size, starting at 1 mm).
    #[arg(long, default_value_t = 6)]
    pub max_levels: usize,
    /// Print JSON (`{"scenes": [...]}`, stable contract) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Print the per-level convergence table (mesh, elements, dofs, time, value, estimate, order).
    #[arg(long)]
    pub convergence: bool,
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

/// FE accuracy options shared by the studies.
#[derive(Debug, Args)]
pub struct StudyFe {
    /// Relative error the FE answer should be under (three-mesh estimate; many scattered loads share one mesh).
    #[arg(long, default_value_t = 0.05)]
    pub tol: f64,
    /// Most mesh levels (each halves the element size from 1 mm); 3 are needed for an error estimate.
    #[arg(long, default_value_t = 3)]
    pub max_levels: usize,
}

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory: force.csv, y-sweep.csv, x-sweep.csv, grid.csv, held-out.csv, noise.csv and SVG plots.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Spacing of the x sweep and of the inverse grid's x nodes.
    #[arg(long, default_value_t = 2.0)]
    pub x_step_mm: f64,
    /// Spacing of the y sweep (support to support) and of the inverse grid's y nodes.
    #[arg(long, default_value_t = 1.25)]
    pub y_step_mm: f64,
    /// Held-out loads (cell centres, forces 0.05/0.3/1.7/4.2 N) for the inverse's error table.
    #[arg(long, default_value_t = 8)]
    pub held_out: usize,
    /// Contact radius of the point loads.
    #[arg(long, default_value_t = 0.25)]
    pub radius_mm: f64,
    /// Gaussian noise levels (standard deviation, mV) added to every voltage in the noise study.
    #[arg(long, value_delimiter = ',', default_value = "0,0.1,0.3,1,3,10")]
    pub noise_mv: Vec<f64>,
    /// Noisy copies of each held-out load per noise level.
    #[arg(long, default_value_t = 50)]
    pub trials: usize,
    /// Seed of the noise generator (splitmix64 + Box-Muller): same seed, same numbers.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub fe: StudyFe,
}

#[derive(Debug, Args)]
pub struct LocateArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// One voltage (mV) per electrode in the model's order (S11,S12,S13,M1,M2,M3,S21,S22,S23 on mis-grasper).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, required = true)]
    pub voltages: Vec<f64>,
    /// Directory written by `tactfab calibrate` (reads its grid.csv); without it the grid is solved now.
    #[arg(long, value_name = "DIR")]
    pub calibration: Option<PathBuf>,
    #[arg(long, default_value_t = 2.0)]
    pub x_step_mm: f64,
    #[arg(long, default_value_t = 1.25)]
    pub y_step_mm: f64,
    #[arg(long, default_value_t = 0.25)]
    pub radius_mm: f64,
    #[command(flatten)]
    pub fe: StudyFe,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct OrientArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Angle step; must divide 180 (paper 000: 10).
    #[arg(long, default_value_t = 10.0)]
    pub step_deg: f64,
    /// Degree of the Chebyshev fit (paper 000: 10).
    #[arg(long, default_value_t = 10)]
    pub degree: usize,
    /// Harmonics of the Fourier-in-2-theta fit (2 k + 1 terms; at most 8 on 18 distinct angles).
    #[arg(long, default_value_t = 4)]
    pub fourier_degree: usize,
    /// Electrode for the inverse angle (default: the one whose charge varies most with angle).
    #[arg(long)]
    pub electrode: Option<String>,
    /// Also write orientation.csv and one SVG per electrode (FE points and both fits) here.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub fe: StudyFe,
    /// Print the whole study as JSON (the cost fields hold wall-clock ms and vary run to run).
    #[arg(long)]
    pub json: bool,
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
        Command::Calibrate(a) => calibrate::run(&a),
        Command::Locate(a) => locate::run(&a),
        Command::Orient(a) => orient::run(&a),
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
