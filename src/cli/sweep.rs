//! `tactfab sweep FILE -o DIR [--shard i/n]` and `tactfab sweep --merge DIR`: the design sweep of
//! paper 001 (sec. 4.1, Fig. 15). Writes `DIR/sweep.csv` (or `DIR/sweep-i-of-n.csv`) and, for a
//! whole or merged sweep, `DIR/family.svg`. The terminal summary includes wall-clock times (not in
//! files).

use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Context};
use indicatif::{ProgressBar, ProgressStyle};
use tactfab::export::file::{self, Proof};
use tactfab::sweep::{
    estimate_error, run::corner_designs, shard, Design, DesignModel, Grid, Matching, Mode, Range,
    Row, Shard,
};

use super::args::{ProcessArgs, SweepArgs};
use super::{check_out, load, write_dir, Outcome};

/// The family's plot, in a whole sweep's directory and beside merged shards.
const FAMILY_SVG: &str = "family.svg";
/// How a sweep's CSV (whole, merged or a shard's) shows it is tactfab's.
const SWEEP_CSV: Proof = Proof::CsvHeader(shard::HEADER);
/// How the prototype's CSV shows it is tactfab's.
const PROTOTYPE_CSV: Proof = Proof::CsvHeader(shard::PROTOTYPE_HEADER);

/// The family plot, stamped: a merge may replace it, and a merged sweep's plot is the whole
/// sweep's, byte for byte.
fn family_svg(family: &[Design], tol: f64, proto: Option<&Design>) -> String {
    file::stamp_svg(tactfab::sweep::plot::family_svg(family, Some(tol), proto))
}

/// A flag's range as the sweep's axis.
fn axis(r: &super::parse::Range) -> Range {
    Range {
        lo: r.lo,
        hi: r.hi,
        steps: r.n,
    }
}

fn ensure_dir(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))
}

/// `tactfab sweep`: merge shards, or run the whole sweep or one shard and print its summary.
pub fn run(a: &SweepArgs) -> anyhow::Result<Outcome> {
    if let Some(dir) = &a.merge {
        return merge(dir, a.tol);
    }
    let (Some(process), Some(out)) = (&a.process, &a.out) else {
        bail!("sweep needs FILE and -o DIR (or --merge DIR)")
    };
    let grid = Grid {
        length_um: axis(&a.length_um),
        width_um: axis(&a.width_um),
        thickness_um: axis(&a.thickness_um),
    };
    grid.check()?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let loaded = load(process)?;
    let p = &loaded.process;
    let contact_radius_um = a.contact_radius_mm * 1e3;
    let model = DesignModel::from_process(p, a.force_n, contact_radius_um);
    let proto = prototype(p);
    let si = &p.materials.silicon;
    let matching = Matching::new(
        proto,
        &model,
        a.tol,
        si.fracture_strength_mpa / si.safety_factor,
    )?;
    let range = shard.map_or(0..grid.len(), |s| s.range(grid.len()));
    // Before the sweep: a whole sweep's directory as every -o DIR, a shard's own two files.
    match shard {
        None => check_out(out, a.replace, process)?,
        Some(s) => {
            ensure_dir(out)?;
            let inputs = [process.file.as_path()];
            file::check(&out.join(s.file_name()), SWEEP_CSV, &inputs).context("-o")?;
            file::check(&out.join(shard::PROTOTYPE), PROTOTYPE_CSV, &inputs).context("-o")?;
        }
    }

    let bar = progress_bar(range.len());
    let t = Instant::now();
    let mode = if a.direct {
        Mode::Direct
    } else {
        Mode::ScaledThickness
    };
    let rows = tactfab::sweep::run_range(&grid, &model, &matching, range.clone(), mode, &|n| {
        bar.inc(n)
    })?;
    bar.finish_and_clear();
    let secs = t.elapsed().as_secs_f64();

    let family = shard::family(&rows);
    write_rows(a, out, process, shard, &rows, &family, &proto)?;
    print_prototype(a, &matching, contact_radius_um);
    println!(
        "designs {}..{} of {}: {} in the family (elongation within {} %), {} within strength; {} \
         in {:.1} s",
        range.start,
        range.end,
        grid.len(),
        family.len(),
        100.0 * a.tol,
        rows.iter().filter(|r| r.within_strength).count(),
        out.join(shard.map_or(shard::UNSHARDED.to_string(), |s| s.file_name()))
            .display(),
        secs
    );
    if !a.no_error_estimate {
        print_error_estimate(&model, &grid, proto)?;
    }
    Ok(Outcome::Ok)
}

/// `--merge DIR`: the shards into `sweep.csv` (the unsharded bytes) and `family.svg`.
fn merge(dir: &Path, tol: f64) -> anyhow::Result<Outcome> {
    let merged = tactfab::sweep::merge_dir(dir, tol)?;
    let proto = shard::read_prototype(dir)?;
    let svg = family_svg(&merged.family, tol, proto.as_ref());
    file::check(&dir.join(shard::UNSHARDED), SWEEP_CSV, &[]).context("--merge")?;
    file::check(&dir.join(FAMILY_SVG), Proof::SvgStamp, &[]).context("--merge")?;
    file::write(
        &dir.join(shard::UNSHARDED),
        merged.csv.as_bytes(),
        SWEEP_CSV,
        &[],
    )?;
    file::write(&dir.join(FAMILY_SVG), svg.as_bytes(), Proof::SvgStamp, &[])?;
    println!(
        "merged {} designs into {}; family {} designs -> {}",
        merged.total,
        dir.join(shard::UNSHARDED).display(),
        merged.family.len(),
        dir.join(FAMILY_SVG).display()
    );
    Ok(Outcome::Ok)
}

/// The prototype: the process file's die (paper 001: 30 x 15 mm, 100 um).
fn prototype(p: &tactfab::process::Process) -> Design {
    let g = &p.geometry;
    Design {
        index: usize::MAX,
        length_um: g.die_length_um,
        width_um: g.die_width_um,
        thickness_um: g.plate_thickness_um,
    }
}

/// A progress bar on a terminal, hidden otherwise.
fn progress_bar(len: usize) -> ProgressBar {
    let bar = if std::io::stderr().is_terminal() {
        ProgressBar::new(len as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} designs, {per_sec}, eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// A shard writes one file into the directory its siblings share; a whole sweep writes
/// `sweep.csv` and `family.svg` as one directory.
fn write_rows(
    a: &SweepArgs,
    out: &Path,
    process: &ProcessArgs,
    shard: Option<Shard>,
    rows: &[Row],
    family: &[Design],
    proto: &Design,
) -> anyhow::Result<()> {
    let proto_csv = shard::prototype_csv(proto);
    match shard {
        Some(s) => {
            let inputs = [process.file.as_path()];
            let rows = shard::csv(rows);
            file::write(
                &out.join(s.file_name()),
                rows.as_bytes(),
                SWEEP_CSV,
                &inputs,
            )?;
            file::write(
                &out.join(shard::PROTOTYPE),
                proto_csv.as_bytes(),
                PROTOTYPE_CSV,
                &inputs,
            )?;
        }
        None => {
            let files = [
                (shard::UNSHARDED.to_string(), shard::csv(rows).into_bytes()),
                (shard::PROTOTYPE.to_string(), proto_csv.into_bytes()),
                (
                    FAMILY_SVG.to_string(),
                    family_svg(family, a.tol, Some(proto)).into_bytes(),
                ),
            ];
            write_dir(out, &files, a.replace, process)?;
        }
    }
    Ok(())
}

/// The prototype's response, and a note when its deflection leaves the linear plate model.
fn print_prototype(a: &SweepArgs, matching: &Matching, contact_radius_um: f64) {
    let proto = &matching.prototype;
    let pr = &matching.prototype_response;
    println!(
        "prototype {} x {} mm, {} um, {} N over r = {} um: deflection {:.3} um, elongation {:.4} \
         um, max stress {:.1} MPa (allowed {:.1})",
        proto.length_um / 1000.0,
        proto.width_um / 1000.0,
        proto.thickness_um,
        a.force_n,
        contact_radius_um,
        pr.deflection_um,
        pr.elongation_um,
        pr.max_stress_mpa,
        matching.allowed_stress_mpa
    );
    if pr.deflection_um > 0.2 * proto.thickness_um {
        println!(
            "note: deflection {:.1} x the thickness: the linear plate model is outside its range \
             (membrane stiffening), as in the paper's linear analysis",
            pr.deflection_um / proto.thickness_um
        );
    }
}

/// The sweep mesh's worst estimated error over the grid corners and the prototype (3 nested
/// meshes).
fn print_error_estimate(model: &DesignModel, grid: &Grid, proto: Design) -> anyhow::Result<()> {
    let mut sample = corner_designs(grid);
    sample.push(proto);
    let errs = estimate_error(model, &sample)?;
    let worst = |f: fn(&tactfab::sweep::DesignError) -> f64| errs.iter().map(f).fold(0.0, f64::max);
    println!(
        "estimated error of the sweep mesh (grid corners + prototype, 3 nested meshes): \
         deflection {:.3} %, elongation {:.3} %, max stress {:.3} %",
        100.0 * worst(|e| e.deflection_rel),
        100.0 * worst(|e| e.elongation_rel),
        100.0 * worst(|e| e.max_stress_rel)
    );
    Ok(())
}
