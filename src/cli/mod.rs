//! Command-line types and dispatch; each subcommand lives in its own file.

mod build;
mod calibrate;
mod check;
mod etch;
mod fe;
mod locate;
mod masks;
mod orient;
mod output;
mod softness;
mod sweep;
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
#[command(
    name = "tactfab",
    version,
    about = "From one process file to etch plan, masks, FE sensitivity and traveler for PVDF \
             tactile sensors"
)]
#[command(
    after_help = "Exit codes: 0 ok, 1 a check of the process failed, 2 bad input or I/O error."
)]
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
    /// Everything for one process file into DIR: etch plan, masks, DRC, FE checks, traveler,
    /// build.json.
    Build(BuildArgs),
    /// The process traveler (run sheet) as Markdown and a self-contained HTML page.
    Traveler(TravelerArgs),
    /// Design sweep (paper 001 sec. 4.1): 15,000 plates, the family matching the prototype;
    /// sharded or merged.
    Sweep(SweepArgs),
    /// Softness (paper 001 Fig. 24): middle-electrode voltage vs tissue modulus, composite beam
    /// and FE; the inverse.
    Softness(SoftnessArgs),
    /// Calibration tables (force, y, x sweeps), the load inverse's error on held-out loads and
    /// under noise: CSV + SVG in DIR.
    Calibrate(CalibrateArgs),
    /// Force and position of a load from the electrode voltages (through the calibration grid).
    Locate(LocateArgs),
    /// Probe-orientation study (paper 000): charge against angle, fits, inverse angle, bivariate
    /// function.
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
    /// Ad-hoc point load in die coordinates: X_MM,Y_MM,FORCE_N[,RADIUS_MM] (radius default 0.25
    /// mm).
    #[arg(long, value_name = "X_MM,Y_MM,FORCE_N[,RADIUS_MM]")]
    pub point: Vec<String>,
    /// Ad-hoc uniform pressure over the plate, by total force.
    #[arg(long, value_name = "FORCE_N", allow_hyphen_values = true)]
    pub pressure: Vec<f64>,
    /// Relative error the answer must be under (estimated from three meshes).
    #[arg(long, default_value_t = 0.01)]
    pub tol: f64,
    /// Most mesh levels to try (level k splits the 2 mm coarse mesh 1, 2, 3, 4, 6, 8, 12, 16, 24
    /// or 32 times; at most 10).
    #[arg(long, default_value_t = 8)]
    pub max_levels: usize,
    /// Print JSON (`{"scenes": [...]}`, stable contract) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Solve the whole plate even when the teeth and every scene are mirror-symmetric (by default
    /// such scenes solve half or a quarter of it; this is the cross-check).
    #[arg(long)]
    pub no_symmetry: bool,
    /// Grade the coarsest mesh geometrically towards the load patches and tooth edges (by default
    /// only feature lines: on the bundled design grading cost 2.7x at 1 % and paid only for a
    /// centre load at 0.5 %).
    #[arg(long)]
    pub graded: bool,
    /// Print the per-level convergence table (mesh, elements, dofs, time, value, estimate, order)
    /// and write the plot of error against dofs and time (see --plot).
    #[arg(long)]
    pub convergence: bool,
    /// Where --convergence writes its SVG plot.
    #[arg(
        long,
        value_name = "SVG",
        default_value = "fe-convergence.svg",
        requires = "convergence"
    )]
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
    /// Most mesh levels to try (level k splits the 2 mm coarse mesh 1, 2, 3, 4, 6, 8, 12, 16, 24
    /// or 32 times; at most 10).
    #[arg(long, default_value_t = 8)]
    pub max_levels: usize,
}

/// FE accuracy options shared by the studies.
#[derive(Debug, Args)]
pub struct StudyFe {
    /// Relative error the FE answer should be under (three-mesh estimate; many scattered loads
    /// share one mesh).
    #[arg(long, default_value_t = 0.05)]
    pub tol: f64,
    /// Most mesh levels (level k splits the 2 mm coarse mesh 1, 2, 3, 4, 6, ... times); 3 are
    /// needed for an error estimate.
    #[arg(long, default_value_t = 3)]
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

#[derive(Debug, Args)]
pub struct SoftnessArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Tissue thickness (um) [choice: paper 001 gives none].
    #[arg(long, default_value_t = tactfab::softness::TISSUE_THICKNESS_UM)]
    pub tissue_thickness_um: f64,
    /// Tissue Poisson's ratio [paper 001 sec. 4.3.2: 0.49].
    #[arg(long, default_value_t = tactfab::softness::TISSUE_NU)]
    pub tissue_nu: f64,
    /// Distributed loads (N) [paper 001 Fig. 24: 1-5 N].
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5")]
    pub forces_n: Vec<f64>,
    /// Tissue modulus range LO,HI,POINTS (Pa, log spaced) [paper 001: 1e4-1e8 Pa].
    #[arg(long, default_value = "1e4,1e8,17", value_name = "LO,HI,POINTS")]
    pub e_range_pa: String,
    /// E_t from a measured middle-electrode voltage and force: VOLTAGE_MV,FORCE_N.
    #[arg(long, value_name = "VOLTAGE_MV,FORCE_N", allow_hyphen_values = true)]
    pub invert: Option<String>,
    /// Write softness.csv and softness.svg into DIR.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: Option<std::path::PathBuf>,
}

#[derive(Debug, Args)]
#[command(
    after_help = "Slurm job array (8 shards, then merge):\n  sbatch --array=1-8 --wrap 'tactfab \
                  sweep process/mis-grasper.yaml -o out --shard ${SLURM_ARRAY_TASK_ID}/8'\n  \
                  sbatch --dependency=afterok:<jobid> --wrap 'tactfab sweep --merge out'"
)]
pub struct SweepArgs {
    /// Process file (YAML): Si stiffness, die size (the prototype), fracture strength and safety
    /// factor.
    #[arg(required_unless_present = "merge")]
    pub file: Option<PathBuf>,
    /// Override a field of the process file (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<String>,
    /// Output directory: sweep.csv (or sweep-i-of-n.csv) and family.svg.
    #[arg(
        short = 'o',
        long = "out",
        value_name = "DIR",
        required_unless_present = "merge"
    )]
    pub out: Option<PathBuf>,
    /// Run shard i of n (1-based, e.g. $SLURM_ARRAY_TASK_ID/8); writes DIR/sweep-i-of-n.csv.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Merge DIR/sweep-i-of-n.csv into DIR/sweep.csv (same bytes as an unsharded run) and draw
    /// DIR/family.svg.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["file", "shard"])]
    pub merge: Option<PathBuf>,
    /// Relative tolerance on the elongation for the family (paper 001 gives none).
    #[arg(long, default_value_t = 0.01)]
    pub tol: f64,
    /// Centre load (N) [paper 001 sec. 4.1].
    #[arg(long, default_value_t = 4.0)]
    pub force_n: f64,
    /// Contact patch radius (um): the stress under a point is singular [choice, as `tactfab fe
    /// --point`].
    #[arg(long, default_value_t = 250.0)]
    pub contact_radius_um: f64,
    /// Plate length range LO,HI,STEPS (um) [paper 001: 10-40 mm, 30 steps].
    #[arg(long, default_value = "10000,40000,30", value_name = "LO,HI,STEPS")]
    pub length_um: String,
    /// Plate width (clamped span) range LO,HI,STEPS (um) [paper 001: 7.5-20 mm, 25 steps].
    #[arg(long, default_value = "7500,20000,25", value_name = "LO,HI,STEPS")]
    pub width_um: String,
    /// Plate thickness range LO,HI,STEPS (um) [paper 001: 50-150 um, 20 steps].
    #[arg(long, default_value = "50,150,20", value_name = "LO,HI,STEPS")]
    pub thickness_um: String,
    /// Skip the three-mesh error estimate at the grid corners and the prototype.
    #[arg(long)]
    pub no_error_estimate: bool,
    /// Refactorise per design instead of scaling one solve per (length, width) by t^3 (same
    /// results to ~1e-9, ~20x slower).
    #[arg(long)]
    pub direct: bool,
}

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory: force.csv, y-sweep.csv, x-sweep.csv, grid.csv, held-out.csv, noise.csv
    /// and SVG plots.
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
    /// One voltage (mV) per electrode in the model's order (S11,S12,S13,M1,M2,M3,S21,S22,S23 on
    /// mis-grasper).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    pub voltages: Vec<f64>,
    /// Directory written by `tactfab calibrate` (reads its grid.csv); without it the grid is
    /// solved now.
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
    // One thread per factorisation: on these plate meshes (up to ~60k dofs) faer's threaded
    // Cholesky ran 1.3-1.8x slower on 2 cores (benches/README.md); studies run their scenes
    // and designs in parallel with rayon instead.
    faer::set_global_parallelism(faer::Par::Seq);
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
    }
}

/// Loads the process file with overrides; every problem becomes one error (exit 2).
pub fn load(args: &ProcessArgs) -> anyhow::Result<tactfab::process::Loaded> {
    tactfab::process::load(&args.file, &args.set).map_err(anyhow::Error::new)
}

/// The electrode rectangles the FE model reads: those of the PVDF mask.
pub fn electrodes(
    p: &tactfab::process::Process,
    plan: &tactfab::etch::EtchPlan,
) -> anyhow::Result<Vec<tactfab::sensor::ElectrodeArea>> {
    let masks = tactfab::layout::build(p, plan).map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(tactfab::sensor::SensorGeometry::electrodes_from_masks(
        &masks,
    ))
}

/// SOURCE_DATE_EPOCH for GDS dates, if set (reproducible builds); an unparsable value is an error.
pub fn source_date_epoch() -> anyhow::Result<Option<i64>> {
    use anyhow::Context;
    match std::env::var("SOURCE_DATE_EPOCH") {
        Ok(s) if !s.trim().is_empty() => Ok(Some(s.trim().parse::<i64>().with_context(|| {
            format!("SOURCE_DATE_EPOCH=`{s}` is not an integer number of seconds")
        })?)),
        _ => Ok(None),
    }
}

/// Validates FE settings given on the command line.
pub fn fe_options(s: &FeSettings) -> anyhow::Result<tactfab::report::FeOptions> {
    if !(s.tol > 0.0 && s.tol < 1.0) {
        anyhow::bail!(
            "--tol {}: expected a relative error between 0 and 1, e.g. 0.01",
            s.tol
        );
    }
    if s.max_levels == 0 {
        anyhow::bail!("--max-levels 0: expected at least 1 mesh level");
    }
    Ok(tactfab::report::FeOptions {
        tol_rel: s.tol,
        max_levels: s.max_levels,
    })
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
