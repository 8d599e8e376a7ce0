//! Every clap type of the command line. Shared option groups (the process file, accuracy, the
//! calibration grid, the output date) are flattened into the subcommands that need them, and
//! every value is checked by a value parser, so a subcommand receives only values it can use:
//! a bad flag is exit 2 naming the flag, before any work starts.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use super::parse;

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
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
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
    /// The nine channels in time through the read-out electronics (charge amplifier or voltage
    /// input, from the process file) for a force history at one point: CSV + SVG in DIR.
    Readout(ReadoutArgs),
    /// Contact pressure a hidden lump or void puts on the sensor face (paper 002 Figs. 8-9):
    /// tissue.csv and tissue.svg with P / P0.
    Tissue(TissueArgs),
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

/// How accurate an FE answer must be; shared by every subcommand that solves. The defaults are
/// those of `fe`, `build` and `traveler`; the studies (many scattered loads on one mesh) set
/// their own (tol 0.05, 3 levels) and say so in `--help`.
#[derive(Debug, Clone, Copy, Args)]
pub struct AccuracyArgs {
    /// Relative error the answer must be under (estimated from three meshes), in (0, 1).
    #[arg(long, value_parser = parse::tolerance, default_value = "0.01")]
    pub tol: f64,
    /// Most mesh levels to try, 1-10 (level k splits the 2 mm coarse mesh 1, 2, 3, 4, 6, 8, 12,
    /// 16, 24 or 32 times; three are needed for an error estimate). The bundled design's
    /// tooth-base stress needs 6 for 1 % at 1 N, and 8 at 4 N with `support_model: solid_section`.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=10), default_value = "9")]
    pub max_levels: u8,
    /// Model rung: auto (the cheapest meeting --tol: strip, linear plate, large-deflection
    /// plate), or force beam, plate or large-deflection; `fe` also takes solid (the 3D rung, at
    /// most 3 levels unless --solid-levels, nonlinear where auto picks the large-deflection
    /// plate, each quantity compared with the plate rung auto picks).
    #[arg(long, value_enum, default_value = "auto")]
    pub model: ModelArg,
    /// In-plane support condition of the large-deflection plate: immovable (the supports hold
    /// the plate) or sliding (it may pull in across them).
    #[arg(long, value_enum, default_value = "immovable")]
    pub in_plane: InPlaneArg,
}

impl From<AccuracyArgs> for tactfab::sensor::Accuracy {
    fn from(a: AccuracyArgs) -> Self {
        tactfab::sensor::Accuracy {
            tol_rel: a.tol,
            max_levels: usize::from(a.max_levels),
            model: a.model.into(),
            in_plane: a.in_plane.into(),
        }
    }
}

/// Dates written into the GDS header: `SOURCE_DATE_EPOCH` (reproducible builds) or zero.
#[derive(Debug, Clone, Copy, Args)]
pub struct DateArgs {
    /// GDS modification/access date in seconds since 1970 (years 1970-9999); without it the dates
    /// are zero, so the same input gives the same bytes.
    #[arg(
        long = "source-date-epoch",
        env = "SOURCE_DATE_EPOCH",
        value_name = "SECONDS",
        value_parser = parse::source_date_epoch,
        hide_env_values = true
    )]
    pub epoch_s: Option<i64>,
}

/// Permission to replace an output directory that holds files tactfab did not write.
#[derive(Debug, Clone, Copy, Args)]
pub struct OverwriteArgs {
    /// Replace the output directory even if it holds files tactfab did not write or that changed
    /// since (by default such a directory is refused; the input file is never replaced).
    #[arg(long)]
    pub overwrite: bool,
}

/// Where the calibration grid's point loads go; shared by `calibrate` and `locate`.
#[derive(Debug, Clone, Copy, Args)]
pub struct GridArgs {
    /// Spacing of the x sweep and of the inverse grid's x nodes (0.1-30 mm).
    #[arg(long, default_value = "2", value_parser = parse::grid_step_mm)]
    pub x_step_mm: f64,
    /// Spacing of the y sweep (support to support) and of the inverse grid's y nodes (0.1-30 mm).
    #[arg(long, default_value = "1.25", value_parser = parse::grid_step_mm)]
    pub y_step_mm: f64,
    /// Contact radius of the point loads (0.01-5 mm; the stress under a point is singular).
    #[arg(long, default_value = "0.25", value_parser = parse::contact_radius_mm)]
    pub contact_radius_mm: f64,
}

#[derive(Debug, Args)]
pub struct EtchArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Print the plan as JSON (stable contract) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Simulate the front etch of one tooth's symmetry cell from the drawn mask (2.5-D level
    /// set, the recipe's time): corner deviation, undercut, compensator, floor, facets (JSON
    /// `simulation`); and the back mask's support corner: channel floor edge, wall run-out,
    /// support corners (JSON `simulation.back`); a few seconds at 5 um (release build).
    #[arg(long)]
    pub simulate: bool,
    /// Grid step of the simulation (1-50 um).
    #[arg(long, default_value = "5", value_parser = parse::sim_grid_um, requires = "simulate")]
    pub grid_um: f64,
    /// Also sweep the {311} and {411} rates over their stated bands (five more runs; JSON
    /// `simulation.sensitivity`).
    #[arg(long, requires = "simulate")]
    pub sensitivity: bool,
    /// Write the plan view of the simulated tooth (contours at several times) to this SVG file,
    /// and the back corner's beside it (`<stem>-back.svg`). An existing file is replaced only
    /// if it is an unedited plot of tactfab's (never the process file).
    #[arg(long, value_name = "FILE", requires = "simulate")]
    pub svg: Option<std::path::PathBuf>,
    /// Size the compensators by simulation: for each geometry the layout draws, the a (ratio
    /// h / a) that brings the corner within etchants.etched_corner_tolerance_um, by bisection on
    /// the corner (about 20 simulations on --grid-um and its double; JSON `sizing`).
    #[arg(long, requires = "simulate")]
    pub size_compensation: bool,
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("json_out").args(["json", "json_file"])))]
pub struct FeArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Run only this scene of checks.scenes.
    #[arg(long)]
    pub scene: Option<String>,
    /// Ad-hoc point load in die coordinates: X_MM,Y_MM,FORCE_N[,RADIUS_MM] (FORCE_N non-zero,
    /// |F| <= 1000, negative pulls; contact radius default 0.25 mm).
    #[arg(long, value_name = "X_MM,Y_MM,FORCE_N[,RADIUS_MM]", value_parser = parse::point_load)]
    pub point: Vec<parse::PointLoad>,
    /// Ad-hoc uniform pressure over the plate, by total force (N, non-zero, |F| <= 1000).
    #[arg(long, value_name = "FORCE_N", allow_hyphen_values = true, value_parser = parse::force_n)]
    pub pressure: Vec<f64>,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
    /// Print JSON (`{"scenes": [...]}`, stable contract: the same input gives the same bytes)
    /// instead of text.
    #[arg(long, conflicts_with = "json_file")]
    pub json: bool,
    /// Write the JSON that --json prints to FILE, and the text to stdout: one solve gives both
    /// (a solid run takes minutes). The file ends with one more key, `tactfab_sha256`, the
    /// SHA-256 of the bytes before it; an existing file is replaced only if it is such an
    /// unedited JSON of tactfab's (never the process file).
    #[arg(long, value_name = "FILE")]
    pub json_file: Option<PathBuf>,
    /// Add the wall-clock fields to the JSON (`solve_ms` per scene, `time_ms` per mesh level);
    /// they vary run to run, so they are left out by default.
    #[arg(long, requires = "json_out")]
    pub timings: bool,
    /// Solve the whole plate even when the teeth and every scene are mirror-symmetric (by default
    /// such scenes solve half or a quarter of it; this is the cross-check).
    #[arg(long)]
    pub no_symmetry: bool,
    /// Grade the coarsest mesh geometrically towards the load patches and tooth edges (by default
    /// only feature lines: on the bundled design grading cost 2.7x at 1 % and paid only for a
    /// centre load at 0.5 %). With `--model solid` or `--verify-solid` every solid level is also
    /// graded at every tooth's base edges, not only at the teeth the plate finds hottest (the
    /// worst edge where the plate ranks it, README), as `--solid-grading` says (by lines at 0.5
    /// and 2 plate thicknesses either side: about 4x the solid's dofs and memory).
    #[arg(long)]
    pub graded: bool,
    /// With --model solid or --verify-solid: the plain 27-node bricks (transverse shears from
    /// the displacements), as the solid rung was before 2026-11-28. By default it ties them (the
    /// MITC9 sampling on parallelepiped bricks), so the 100 um plate on bricks of several
    /// thicknesses does not lock: on the bundled design's centre load the three-level estimates
    /// are about 3x smaller at the same dofs (deflection 1.25 % against 4.2 %; README).
    #[arg(long)]
    pub plain_shear: bool,
    /// With --model solid or --verify-solid: how the solid's levels are graded at the hot teeth.
    /// `local`: the cells beside their base edges (and beside the channel walls) bisected toward
    /// them down to half a plate thickness, merged back away from the teeth, hanging nodes
    /// between; `lines`: lines at 0.5 and 2 plate thicknesses either side of each edge, across
    /// the whole die (the only grading before 2026-11-30); `auto` (the default): whichever gives
    /// the finest level the smaller factor, which on the bundled design is local for the centre
    /// load and lines for the line load (README, "Local refinement"); `uniform`: no tooth graded,
    /// the feature lines only (the cheapest look; it can miss the worst tooth base beyond its
    /// estimate, and says so).
    #[arg(long, value_enum, value_name = "GRADING")]
    pub solid_grading: Option<GradingArg>,
    /// With --model solid or --verify-solid: the solid's mesh levels, 1-5 (1000, 707, 500, 354,
    /// 250 um in plane, half that across the span; three give an error estimate). By default 3
    /// for --model solid, 2 for --verify-solid, or --max-levels if lower. Three put every reading
    /// of the bundled centre load under 1 % (the tooth base and vertex stresses with the 2-4-8
    /// bricks' correction through the thickness) but the peak principal stress, which is
    /// reported but not required to converge (README, "Eight bricks where the edges are read").
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=5))]
    pub solid_levels: Option<u8>,
    /// Print the per-level convergence table (mesh, elements, dofs, time, value, estimate, order)
    /// and write the plot of error against dofs and time (see --plot). The plate rungs only:
    /// with --model solid, --json --timings gives the solid's levels and their times.
    #[arg(long)]
    pub convergence: bool,
    /// Also solve each scene on the 3D solid rung (2 levels, or --max-levels if lower; the
    /// bundled design's four scenes take about half an hour and 12 GB) and take the plate
    /// answer's model error from it: each quantity's `model` part becomes its difference from the
    /// solid plus the solid's own estimate (or stays, if larger). Not with --model solid.
    #[arg(long)]
    pub verify_solid: bool,
    /// Where --convergence writes its SVG plot. An existing file is replaced only if it is an
    /// unedited plot of tactfab's (never the process file).
    #[arg(
        long,
        value_name = "SVG",
        default_value = "fe-convergence.svg",
        requires = "convergence"
    )]
    pub plot: PathBuf,
}

/// Mask output formats; the .lyp goes with the GDS.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Gds,
    Svg,
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
    pub format: Vec<Format>,
    #[command(flatten)]
    pub date: DateArgs,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

#[derive(Debug, Args)]
pub struct BuildArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory, written as one unit; an existing one is replaced only if it is empty or
    /// holds exactly a previous output (its `tactfab.sha256` manifest proves it).
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
    #[command(flatten)]
    pub date: DateArgs,
    #[command(flatten)]
    pub replace: OverwriteArgs,
    #[command(flatten)]
    pub gate: GateArgs,
    /// Also solve each declared scene on the 3D solid rung (2 levels, or --max-levels if lower;
    /// the bundled design's four scenes take about half an hour and 12 GB) and fail where the
    /// plate rung the ladder picks differs from it by more than --tol; writes
    /// `<device>-solid-check.json`.
    #[arg(long)]
    pub verify_solid: bool,
    /// With --verify-solid: grade every solid level at every tooth's base edges, not only the
    /// hot teeth's, as `fe --verify-solid --graded` does (by lines at 0.5 and 2 plate
    /// thicknesses either side of each: about 4x the solid's dofs and memory).
    #[arg(long, requires = "verify_solid")]
    pub graded: bool,
    /// With --verify-solid: the plain bricks for the solid, as `fe --plain-shear` (by default
    /// their transverse shears are tied, so the plate's bricks do not lock).
    #[arg(long, requires = "verify_solid")]
    pub plain_shear: bool,
    /// With --verify-solid: how the solid's levels are graded at the hot teeth, as `fe
    /// --solid-grading` (by default `auto`: the grading with the smaller factor; `uniform`
    /// grades no tooth).
    #[arg(long, value_enum, value_name = "GRADING", requires = "verify_solid")]
    pub solid_grading: Option<GradingArg>,
    /// With --verify-solid: the solid's mesh levels, 1-5 (by default 2, or --max-levels if
    /// lower). Three or more give the solid its own estimate, and the check then fails where the
    /// difference plus that estimate exceeds --tol.
    #[arg(long, requires = "verify_solid", value_parser = clap::value_parser!(u8).range(1..=5))]
    pub solid_levels: Option<u8>,
}

/// Whether an unconverged declared scene fails the build.
#[derive(Debug, Args)]
pub struct GateArgs {
    /// Do not fail when a declared scene's estimated error stays above --tol (the traveler and
    /// build.json still say which did not converge).
    #[arg(long)]
    pub allow_unconverged: bool,
}

#[derive(Debug, Args)]
pub struct TravelerArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory: `<device>-traveler.md` and `<device>-traveler.html`, written as one unit.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Skip the FE solves: the traveler says the sensitivity was not computed.
    #[arg(long)]
    pub no_fe: bool,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
    #[command(flatten)]
    pub date: DateArgs,
    #[command(flatten)]
    pub replace: OverwriteArgs,
    #[command(flatten)]
    pub gate: GateArgs,
}

#[derive(Debug, Args)]
pub struct SoftnessArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Tissue thickness (um) [choice: paper 001 gives none].
    #[arg(long, default_value_t = tactfab::softness::TISSUE_THICKNESS_UM,
          value_parser = parse::tissue_thickness_um)]
    pub tissue_thickness_um: f64,
    /// Tissue Poisson's ratio, 0-0.4999 [paper 001 sec. 4.3.2: 0.49].
    #[arg(long, default_value_t = tactfab::softness::TISSUE_NU, value_parser = parse::tissue_nu)]
    pub tissue_nu: f64,
    /// Distributed loads (N), each 0.001-1000 [paper 001 Fig. 24: 1-5 N].
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5",
          value_parser = parse::pressing_force_n)]
    pub forces_n: Vec<f64>,
    /// Tissue modulus range LO,HI,POINTS (Pa, log spaced, 2-200 points) [paper 001: 1e4-1e8 Pa].
    #[arg(long, default_value = "1e4,1e8,17", value_name = "LO,HI,POINTS",
          value_parser = parse::modulus_range_pa)]
    pub e_range_pa: parse::Range,
    /// E_t from a measured middle-electrode voltage and force: VOLTAGE_MV,FORCE_N.
    #[arg(long, value_name = "VOLTAGE_MV,FORCE_N", allow_hyphen_values = true,
          value_parser = parse::voltage_and_force)]
    pub invert: Option<(f64, f64)>,
    /// Write softness.csv and softness.svg into DIR.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

#[derive(Debug, Args)]
#[command(
    after_help = "Slurm job array (8 shards, then merge):\n  sbatch --array=1-8 --wrap 'tactfab \
                  sweep process/mis-grasper.yaml -o out --shard ${SLURM_ARRAY_TASK_ID}/8'\n  \
                  sbatch --dependency=afterok:<jobid> --wrap 'tactfab sweep --merge out'\n(give --merge \
                  the --tol the shards ran with)"
)]
pub struct SweepArgs {
    /// The process file (Si stiffness, die size of the prototype, fracture strength and safety
    /// factor) and overrides; not with --merge.
    #[command(flatten)]
    pub process: Option<ProcessArgs>,
    /// Output directory: sweep.csv (or sweep-i-of-n.csv) and family.svg.
    #[arg(
        short = 'o',
        long = "out",
        value_name = "DIR",
        required_unless_present = "merge"
    )]
    pub out: Option<PathBuf>,
    /// Run shard i of n (1-based, e.g. $SLURM_ARRAY_TASK_ID/8); writes DIR/sweep-i-of-n.csv
    /// (replacing only a shard's own CSV, so a failed shard can be rerun).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Merge DIR/sweep-i-of-n.csv into DIR/sweep.csv (same bytes as an unsharded run) and draw
    /// DIR/family.svg (replacing only a previous merge's files).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["file", "shard", "out"])]
    pub merge: Option<PathBuf>,
    /// Relative tolerance on the elongation for the family, in (0, 1) (paper 001 gives none).
    #[arg(long, default_value = "0.01", value_parser = parse::tolerance)]
    pub tol: f64,
    /// Centre load (N, non-zero, |F| <= 1000) [paper 001 sec. 4.1].
    #[arg(long, default_value = "4", value_parser = parse::force_n)]
    pub force_n: f64,
    /// Contact patch radius (0.01-5 mm): the stress under a point is singular [choice, as
    /// `tactfab fe --point`].
    #[arg(long, default_value = "0.25", value_parser = parse::contact_radius_mm)]
    pub contact_radius_mm: f64,
    /// Plate length range LO,HI,STEPS (um) [paper 001: 10-40 mm, 30 steps].
    #[arg(long, default_value = "10000,40000,30", value_name = "LO,HI,STEPS",
          value_parser = parse::sweep_range_um)]
    pub length_um: parse::Range,
    /// Plate width (clamped span) range LO,HI,STEPS (um) [paper 001: 7.5-20 mm, 25 steps].
    #[arg(long, default_value = "7500,20000,25", value_name = "LO,HI,STEPS",
          value_parser = parse::sweep_range_um)]
    pub width_um: parse::Range,
    /// Plate thickness range LO,HI,STEPS (um) [paper 001: 50-150 um, 20 steps].
    #[arg(long, default_value = "50,150,20", value_name = "LO,HI,STEPS",
          value_parser = parse::sweep_range_um)]
    pub thickness_um: parse::Range,
    /// Skip the three-mesh error estimate at the grid corners and the prototype.
    #[arg(long)]
    pub no_error_estimate: bool,
    /// Refactorise per design instead of scaling one solve per (length, width) by t^3 (same
    /// results to ~1e-9, ~20x slower).
    #[arg(long)]
    pub direct: bool,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

/// The studies' accuracy: many scattered loads share one mesh, so a coarser default than `fe`.
#[derive(Debug, Clone, Copy, Args)]
pub struct StudyAccuracyArgs {
    /// Relative error the FE answer should be under (three-mesh estimate), in (0, 1).
    #[arg(long, value_parser = parse::tolerance, default_value = "0.05")]
    pub tol: f64,
    /// Most mesh levels, 1-10 (level k splits the 2 mm coarse mesh 1, 2, 3, 4, 6, ... times); 3
    /// are needed for an error estimate.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=10), default_value = "3")]
    pub max_levels: u8,
    /// Model rung: auto lets each load climb to the large-deflection plate where the linear one
    /// misses --tol (the sensor is not linear in force: ~15x the time of `--model plate`, which
    /// answers fast and reports its model error instead).
    #[arg(long, value_enum, default_value = "auto")]
    pub model: ModelArg,
    /// In-plane support condition of the large-deflection plate: immovable or sliding.
    #[arg(long, value_enum, default_value = "immovable")]
    pub in_plane: InPlaneArg,
}

/// `--model`: the rung of the fidelity ladder.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ModelArg {
    Auto,
    Beam,
    Plate,
    LargeDeflection,
    /// The 3D solid (`fe` only): at most 3 levels unless --solid-levels, nonlinear where auto
    /// picks the large-deflection plate (and compared with it), else linear against the linear
    /// plate.
    Solid,
}

impl From<ModelArg> for tactfab::sensor::ModelChoice {
    fn from(m: ModelArg) -> Self {
        use tactfab::sensor::ModelChoice as C;
        match m {
            ModelArg::Auto => C::Auto,
            ModelArg::Beam => C::Beam,
            ModelArg::Plate => C::Plate,
            ModelArg::LargeDeflection => C::LargeDeflection,
            ModelArg::Solid => C::Solid,
        }
    }
}

/// `--solid-grading`: how the solid's levels are graded at the hot teeth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum GradingArg {
    Auto,
    Local,
    Lines,
    Uniform,
}

impl GradingArg {
    /// The library's grading; none given is auto.
    pub fn or_auto(g: Option<GradingArg>) -> tactfab::sensor::solid::SolidGrading {
        use tactfab::sensor::solid::SolidGrading as G;
        match g {
            None | Some(GradingArg::Auto) => G::Auto,
            Some(GradingArg::Local) => G::Local,
            Some(GradingArg::Lines) => G::Lines,
            Some(GradingArg::Uniform) => G::Uniform,
        }
    }
}

/// `--in-plane`: what the supports do in the plate's plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum InPlaneArg {
    Immovable,
    Sliding,
}

impl From<InPlaneArg> for tactfab::fe::InPlane {
    fn from(m: InPlaneArg) -> Self {
        match m {
            InPlaneArg::Immovable => tactfab::fe::InPlane::Immovable,
            InPlaneArg::Sliding => tactfab::fe::InPlane::Sliding,
        }
    }
}

impl From<StudyAccuracyArgs> for tactfab::sensor::Accuracy {
    fn from(a: StudyAccuracyArgs) -> Self {
        tactfab::sensor::Accuracy {
            tol_rel: a.tol,
            max_levels: usize::from(a.max_levels),
            model: a.model.into(),
            in_plane: a.in_plane.into(),
        }
    }
}

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory: force.csv, y-sweep.csv, x-sweep.csv, grid.csv, held-out.csv, noise.csv
    /// and SVG plots.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Held-out loads (cell centres, forces 0.05/0.3/1.7/4.2 N) for the inverse's error table
    /// (0-1000).
    #[arg(long, default_value = "8", value_parser = clap::value_parser!(u16).range(0..=1000))]
    pub held_out: u16,
    /// Gaussian noise levels (standard deviation, mV, 0-1e4) added to every voltage in the noise
    /// study.
    #[arg(long, value_delimiter = ',', default_value = "0,0.1,0.3,1,3,10",
          value_parser = parse::noise_mv)]
    pub noise_mv: Vec<f64>,
    /// Noisy copies of each held-out load per noise level (1-10000).
    #[arg(long, default_value = "50", value_parser = clap::value_parser!(u16).range(1..=10000))]
    pub trials: u16,
    /// Seed of the noise generator (splitmix64 + Box-Muller): same seed, same numbers.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub accuracy: StudyAccuracyArgs,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

#[derive(Debug, Args)]
pub struct LocateArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// One voltage (mV) per electrode in the model's order (S11,S12,S13,M1,M2,M3,S21,S22,S23 on
    /// mis-grasper), each within +/- 1e6 mV.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, required = true,
          value_parser = parse::voltage_mv)]
    pub voltages: Vec<f64>,
    /// Directory written by `tactfab calibrate` (reads its grid.csv); without it the grid is
    /// solved now.
    #[arg(long, value_name = "DIR")]
    pub calibration: Option<PathBuf>,
    #[command(flatten)]
    pub grid: GridArgs,
    #[command(flatten)]
    pub accuracy: StudyAccuracyArgs,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct OrientArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Angle step, 1-90 deg; must divide 180 (paper 000: 10).
    #[arg(long, default_value = "10", value_parser = parse::angle_step_deg)]
    pub step_deg: f64,
    /// Degree of the Chebyshev fit, 0-30 (paper 000: 10).
    #[arg(long, default_value = "10", value_parser = clap::value_parser!(u8).range(0..=30))]
    pub degree: u8,
    /// Harmonics of the Fourier-in-2-theta fit, 0-30 (2 k + 1 terms; at most 8 on 18 distinct
    /// angles).
    #[arg(long, default_value = "4", value_parser = clap::value_parser!(u8).range(0..=30))]
    pub fourier_degree: u8,
    /// Electrode for the inverse angle (default: the one whose charge varies most with angle).
    #[arg(long)]
    pub electrode: Option<String>,
    /// Also write orientation.csv and one SVG per electrode (FE points and both fits) here.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub accuracy: StudyAccuracyArgs,
    /// Print the whole study as JSON (the cost fields hold wall-clock ms and vary run to run).
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

/// `--history`: the force the jaws apply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum HistoryArg {
    /// Closes along the rising half of a 1 s half sine [paper 002 sec. VII.A], then held.
    HalfSine,
    /// The papers' 5 Hz test sinusoid.
    #[value(name = "sine-5hz")]
    Sine5Hz,
    /// 1 Hz half-sine pulses of 10 % of the force on a held grasp (a pulsating vessel).
    Pulse,
}

impl From<HistoryArg> for tactfab::readout_chain::HistoryKind {
    fn from(h: HistoryArg) -> Self {
        use tactfab::readout_chain::HistoryKind as K;
        match h {
            HistoryArg::HalfSine => K::HalfSine,
            HistoryArg::Sine5Hz => K::Sine5Hz,
            HistoryArg::Pulse => K::Pulse,
        }
    }
}

#[derive(Debug, Args)]
pub struct ReadoutArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory: readout.csv (t_s, F_n, V_<electrode>_v) and readout.svg.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// The force history.
    #[arg(long, value_enum, default_value = "half-sine")]
    pub history: HistoryArg,
    /// Load position along the die length (mm; default: the die centre).
    #[arg(long, value_parser = parse::position_mm)]
    pub x_mm: Option<f64>,
    /// Load position across the die width (mm; default: the die centre).
    #[arg(long, value_parser = parse::position_mm)]
    pub y_mm: Option<f64>,
    /// Peak grasp force or sine amplitude (N, non-zero, |F| <= 1000).
    #[arg(long, default_value = "1", allow_hyphen_values = true, value_parser = parse::force_n)]
    pub force_n: f64,
    /// Contact radius of the load (0.01-5 mm).
    #[arg(long, default_value = "0.25", value_parser = parse::contact_radius_mm)]
    pub contact_radius_mm: f64,
    /// Record length, 0.001-3600 s (default: 5 s half-sine, 1 s sine, 6 s pulse).
    #[arg(long, value_parser = parse::duration_s)]
    pub duration_s: Option<f64>,
    /// Sample step, 0.001-1000 ms (the force is linear between samples; the filter is exact
    /// for that).
    #[arg(long, default_value = "1", value_parser = parse::dt_ms)]
    pub dt_ms: f64,
    /// Relative error of the sensitivities (linear plate, three-mesh estimate), in (0, 1).
    #[arg(long, value_parser = parse::tolerance, default_value = "0.01")]
    pub tol: f64,
    /// Most mesh levels for the sensitivities, 1-10.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=10), default_value = "8")]
    pub max_levels: u8,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

/// `tissue`: which feature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FeatureArg {
    Lump,
    Void,
}

#[derive(Debug, Args)]
pub struct TissueArgs {
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Output directory: tissue.csv (x_mm, P_pa, P0_pa, P_over_P0) and tissue.svg.
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// The hidden feature: a stiffer disc or an empty one.
    #[arg(long, value_enum, default_value = "lump")]
    pub feature: FeatureArg,
    /// Slab length along the jaw and its thickness between the jaws (mm) [choice: paper 002
    /// gives no geometry].
    #[arg(long, default_value = "30", value_parser = parse::length_mm)]
    pub width_mm: f64,
    #[arg(long, default_value = "10", value_parser = parse::length_mm)]
    pub thickness_mm: f64,
    /// The disc: centre along the jaw (default: the middle), height above the sensor, radius (mm).
    #[arg(long, value_parser = parse::length_mm)]
    pub x_mm: Option<f64>,
    #[arg(long, default_value = "4", value_parser = parse::length_mm)]
    pub height_mm: f64,
    #[arg(long, default_value = "2", value_parser = parse::length_mm)]
    pub radius_mm: f64,
    /// Tissue and lump moduli (kPa; paper 002 sec. V.B: 20 and 200, nu 0.49 and 0.4).
    #[arg(long, default_value = "20", value_parser = parse::modulus_kpa)]
    pub tissue_e_kpa: f64,
    #[arg(long, default_value = "200", value_parser = parse::modulus_kpa)]
    pub lump_e_kpa: f64,
    /// How far the jaws squeeze the slab, as a fraction of its thickness.
    #[arg(long, default_value = "0.1", value_parser = parse::compression)]
    pub compression: f64,
    /// Q2/P1 elements along the jaw (1-400) and through the slab (1-200).
    #[arg(long, default_value = "120", value_parser = clap::value_parser!(u16).range(1..=400))]
    pub across: u16,
    #[arg(long, default_value = "40", value_parser = clap::value_parser!(u16).range(1..=200))]
    pub through: u16,
    /// The tissue model: 2d (the plane section above; through the sensor P0(x) the same at
    /// every y, the feature's disturbance from --shape) or 3d (a block --width-mm along the jaw x
    /// --jaw-width-mm across x --thickness-mm with free sides and the sphere at --x-mm, --y-mm:
    /// tissue-3d.csv and the plan-view heat map tissue-3d.svg; through the sensor the cells take
    /// its P0(x, y) and P(x, y); about 6 s on the default mesh).
    #[arg(long, value_enum, default_value = "2d")]
    pub slab: SlabArg,
    /// --slab 3d: the block's width across the jaw (mm) [choice: the die's width].
    #[arg(long, value_parser = parse::length_mm)]
    pub jaw_width_mm: Option<f64>,
    /// --slab 3d: brick size over the sphere and down to the face (mm) and the largest elsewhere
    /// (mm; graded by 1.3).
    #[arg(long, default_value = "0.6667", value_parser = parse::length_mm)]
    pub near_mm: f64,
    #[arg(long, default_value = "2.5", value_parser = parse::length_mm)]
    pub far_mm: f64,
    /// Load the sensor with the slab's pressure: the nine voltages with and without the
    /// feature (through-sensor.csv, face-pressure.csv, through-sensor.svg). --x-mm and --y-mm
    /// then place the feature on the die (x along the jaw, y across; default the die centre).
    #[arg(long)]
    pub through_sensor: bool,
    /// With --through-sensor: locate and classify the feature from the voltage difference plus
    /// seeded Gaussian noise of --noise-mv.
    #[arg(long)]
    pub locate: bool,
    /// With --through-sensor: the smallest detectable lump over --map-radii-mm x
    /// --map-heights-mm x --map-stiffness at --noise-mv (detectability.csv, detectability.svg).
    #[arg(long)]
    pub detectability: bool,
    /// The feature's centre across the jaw on the die (mm; default the die's middle).
    #[arg(long, value_parser = parse::length_mm)]
    pub y_mm: Option<f64>,
    /// The feature in plan: a sphere (its disturbance from the axisymmetric scene: the sphere on
    /// the axis of a tissue cylinder of radius half --width-mm), a cylinder lying across the jaw
    /// (the plane section's disc), or rotated-section (the plane section's disturbance rotated
    /// about the centre: the older approximation of a sphere).
    #[arg(long, value_enum, default_value = "sphere")]
    pub shape: ShapeArg,
    /// Side of the pressure cells on the die face (mm, 0.25-30) [choice: 1 mm].
    #[arg(long, default_value = "1", value_parser = parse::cell_mm)]
    pub cell_mm: f64,
    /// Noise per channel (mV rms, > 0) for --locate and --detectability [choice: 1 mV; no
    /// amplifier noise is modelled].
    #[arg(long, default_value = "1", value_parser = parse::positive_noise_mv)]
    pub noise_mv: f64,
    /// Matched-filter SNR a feature must reach to be reported [choice: 5].
    #[arg(long, default_value = "5", value_parser = parse::snr)]
    pub snr: f64,
    /// Seed of the noise of --locate.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Detectability map axes: lump radii, heights of the centre above the sensor (mm) and
    /// E_lump / E_tissue.
    #[arg(long, value_delimiter = ',', default_value = "0.5,0.75,1,1.25,1.5,2,2.5,3",
          value_parser = parse::length_mm)]
    pub map_radii_mm: Vec<f64>,
    #[arg(long, value_delimiter = ',', default_value = "1.5,2.5,3.5,4.5,5.5,6.5,7.5,8.5",
          value_parser = parse::length_mm)]
    pub map_heights_mm: Vec<f64>,
    #[arg(long, value_delimiter = ',', default_value = "3,10",
          value_parser = parse::stiffness_ratio)]
    pub map_stiffness: Vec<f64>,
    /// With --through-sensor: the void is a vessel pulsing at --pulse-hz between --mean-mmhg
    /// -/+ half of --pulse-mmhg (paper 002 Fig. 10): 20 instants of a cycle through the sensor,
    /// then the nine amplifier outputs over 5 cycles (vessel.csv, vessel-readout.csv,
    /// vessel.svg). Needs --feature void; --shape cylinder lays it across the jaw.
    #[arg(long)]
    pub vessel: bool,
    /// Pulse rate (Hz, 0.01-100) [choice: 1.2 Hz].
    #[arg(long, default_value = "1.2", value_parser = parse::pulse_hz)]
    pub pulse_hz: f64,
    /// Mean vessel pressure and pulse pressure (mmHg, 0-1000) [choice: 100 and 40, i.e. 120/80].
    #[arg(long, default_value = "100", value_parser = parse::mmhg)]
    pub mean_mmhg: f64,
    #[arg(long, default_value = "40", value_parser = parse::mmhg)]
    pub pulse_mmhg: f64,
    /// Relative error of the plate's unit responses, in (0, 1) (the studies' 0.05).
    #[arg(long, value_parser = parse::tolerance, default_value = "0.05")]
    pub tol: f64,
    /// Most plate mesh levels, 1-10 (the studies' 3).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=10), default_value = "3")]
    pub max_levels: u8,
    /// Plate rung of the two full grasp scenes (without and with the feature): auto (the
    /// cheapest meeting --tol, the large-deflection plate at the default grasp), plate or
    /// large-deflection. The cell superposition, the inverse, the map and the vessel use the
    /// linear plate whatever this says.
    #[arg(long, value_enum, default_value = "auto")]
    pub model: ModelArg,
    #[command(flatten)]
    pub replace: OverwriteArgs,
}

/// `tissue --slab`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SlabArg {
    #[value(name = "2d")]
    Plane,
    #[value(name = "3d")]
    Block,
}

/// `tissue --shape`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ShapeArg {
    Sphere,
    Cylinder,
    RotatedSection,
}
