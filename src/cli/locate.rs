//! `tactfab locate FILE --voltages V1,...,V9`: force and position from the electrode voltages,
//! through the calibration grid of `tactfab calibrate` (`--calibration DIR`) or one computed now.

use anyhow::{bail, Context};

use tactfab::analysis::calibration::{
    calibrate, Calibration, CalibrationPlan, Cost, Sample, SupportGroups,
};
use tactfab::analysis::inverse::Locator;
use tactfab::sensor::SensorGeometry;

use super::args::LocateArgs;
use super::output::f;
use super::{design, origin, Outcome};

pub fn run(args: &LocateArgs) -> anyhow::Result<Outcome> {
    let (loaded, design) = design(&args.process)?;
    super::warn_process_errors(&args.process, &design);
    let g = SensorGeometry::new(&design);
    let names: Vec<String> = g.electrodes.iter().map(|e| e.name.clone()).collect();
    if args.voltages.len() != names.len() {
        bail!(
            "--voltages: expected {} values in the order {}, got {}",
            names.len(),
            names.join(","),
            args.voltages.len()
        );
    }
    let cal = match &args.calibration {
        Some(dir) => {
            same_design(dir, &origin(&args.process, &loaded))?;
            read_grid(&dir.join("grid.csv"), &names)?
        }
        None => {
            let cp = CalibrationPlan::new(
                &g,
                args.grid.x_step_mm * 1e3,
                args.grid.y_step_mm * 1e3,
                0,
                args.grid.contact_radius_mm * 1e3,
                args.accuracy.into(),
            );
            let mut cp = cp;
            cp.force_table_n = vec![1.0];
            cp.x_sweep_um.clear();
            cp.y_sweep_um.clear();
            calibrate(&g, &cp).context("calibration grid")?
        }
    };
    let loc = Locator::new(&cal, SupportGroups::of(&g)?)?;
    let e = loc.locate(&args.voltages)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(
                &serde_json::json!({ "estimate": e, "electrodes": names })
            )?
        );
    } else {
        println!(
            "force {} N at x {} mm, y {} mm ({} iterations{}); residual {} mV RMS",
            f(e.force_n, 4),
            f(e.x_um / 1e3, 3),
            f(e.y_um / 1e3, 3),
            e.iterations,
            if e.clamped_y {
                "; y clamped: the load is over a support or outside the grid"
            } else if e.clamped_x {
                "; x clamped: outside the calibrated x range"
            } else {
                ""
            },
            f(e.residual_mv, 3)
        );
    }
    Ok(Outcome::Ok)
}

/// Refuses a calibration directory made for another design (other process bytes or `--set`
/// overrides) or without its identity file.
fn same_design(dir: &std::path::Path, now: &tactfab::report::Origin) -> anyhow::Result<()> {
    use tactfab::report::calibration::{CalibrationMeta, META};
    let path = dir.join(META);
    let bytes = std::fs::read(&path).with_context(|| {
        format!(
            "cannot read {}: a calibration directory carries it (regenerate it with `tactfab \
             calibrate FILE -o DIR`)",
            path.display()
        )
    })?;
    let meta = CalibrationMeta::parse(&bytes)
        .with_context(|| format!("{} is not a calibration identity file", path.display()))?;
    if let Some(why) = meta.origin.design_mismatch(now) {
        bail!(
            "--calibration {}: made for another design: {why}\n  hint: calibrate this design \
             (`tactfab calibrate` with the same file and --set), or run locate without \
             --calibration to solve its grid now",
            dir.display()
        );
    }
    Ok(())
}

/// Reads `grid.csv` as written by `tactfab calibrate`: x_um,y_um,force_n,<electrode>_voltage_mv...
fn read_grid(path: &std::path::Path, names: &[String]) -> anyhow::Result<Calibration> {
    let text = std::fs::read_to_string(path).with_context(|| {
        format!(
            "cannot read {} (run `tactfab calibrate FILE -o DIR` first)",
            path.display()
        )
    })?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let want: Vec<String> = ["x_um", "y_um", "force_n"]
        .iter()
        .map(|s| s.to_string())
        .chain(names.iter().map(|n| format!("{n}_voltage_mv")))
        .collect();
    if head != want {
        bail!(
            "{}: header must be `{}` (electrodes of this process file); regenerate it with \
             `tactfab calibrate`",
            path.display(),
            want.join(",")
        );
    }
    let mut samples = Vec::new();
    for (k, line) in lines.enumerate() {
        let v: Vec<f64> = line
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| {
                format!(
                    "{}:{}: expected {} numbers",
                    path.display(),
                    k + 2,
                    want.len()
                )
            })?;
        if v.len() != want.len() || v[2] == 0.0 {
            bail!(
                "{}:{}: expected {} numbers with a non-zero force",
                path.display(),
                k + 2,
                want.len()
            );
        }
        samples.push(Sample {
            x_um: v[0],
            y_um: v[1],
            force_n: v[2],
            voltage_mv: v[3..].to_vec(),
            model: None,
            error_estimate: None,
        });
    }
    let mut xs: Vec<f64> = samples.iter().map(|s| s.x_um).collect();
    let mut ys: Vec<f64> = samples.iter().map(|s| s.y_um).collect();
    for v in [&mut xs, &mut ys] {
        v.sort_by(f64::total_cmp);
        v.dedup();
    }
    if xs.len() * ys.len() != samples.len() {
        bail!(
            "{}: the rows do not form a complete x-y grid ({} x, {} y, {} rows)",
            path.display(),
            xs.len(),
            ys.len(),
            samples.len()
        );
    }
    let mut grid = vec![Vec::new(); ys.len()];
    samples.sort_by(|a, b| a.y_um.total_cmp(&b.y_um).then(a.x_um.total_cmp(&b.x_um)));
    for (k, s) in samples.into_iter().enumerate() {
        grid[k / xs.len()].push(s);
    }
    Ok(Calibration {
        electrodes: names.to_vec(),
        force_table: vec![],
        linearity_deviation: f64::NAN,
        force_table_ladder: vec![],
        linearity_by_electrode: vec![],
        y_sweep: vec![],
        x_sweep: vec![],
        grid_x_um: xs,
        grid_y_um: ys,
        grid,
        held_out: vec![],
        cost: Cost {
            scenes: 0,
            wall_ms: 0.0,
            dofs: 0,
            levels: 0,
            max_error_estimate: None,
        },
    })
}
