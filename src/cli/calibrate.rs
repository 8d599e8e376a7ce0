//! `tactfab calibrate FILE -o DIR`: calibration tables, the inverse's error on held-out loads and
//! under voltage noise, as CSV (unit-bearing headers) and SVG plots, written atomically.

use std::fmt::Write as _;

use anyhow::Context;

use tactfab::analysis::calibration::{Calibration, CalibrationPlan};
use tactfab::analysis::inverse::{HeldOutError, Locator, NoiseRow};
use tactfab::analysis::study::{calibration_study, NoiseSpec};
use tactfab::report::calibration::files;
use tactfab::sensor::SensorGeometry;

use super::args::CalibrateArgs;
use super::output::f;
use super::{check_out, design, origin, write_dir, Outcome};

pub fn run(args: &CalibrateArgs) -> anyhow::Result<Outcome> {
    let (loaded, design) = design(&args.process)?;
    super::warn_process_errors(&args.process, &design);
    check_out(&args.out, args.replace, &args.process)?;
    let origin = origin(&args.process, &loaded);
    let g = SensorGeometry::new(&design);
    let cp = CalibrationPlan::new(
        &g,
        args.grid.x_step_mm * 1e3,
        args.grid.y_step_mm * 1e3,
        usize::from(args.held_out),
        args.grid.contact_radius_mm * 1e3,
        args.accuracy.into(),
    );
    let noise = NoiseSpec {
        sigmas_mv: args.noise_mv.clone(),
        trials: usize::from(args.trials),
        seed: args.seed,
        force_n: 1.0,
    };
    let s = calibration_study(&g, &cp, &noise).context("calibration")?;
    write_dir(
        &args.out,
        &files(&s, &origin, args.accuracy.into()),
        args.replace,
        &args.process,
    )?;
    print!(
        "{}",
        summary(&s.calibration, &s.locator, &s.held_out, &s.noise, &args.out)
    );
    Ok(Outcome::Ok)
}

fn summary(
    cal: &Calibration,
    loc: &Locator,
    held: &[HeldOutError],
    noise: &[NoiseRow],
    dir: &std::path::Path,
) -> String {
    let c = &cal.cost;
    let mut s = format!(
        "calibration: {} loads in one FE call, {} ms, {} dofs, {} levels, largest estimated error \
         {}\n",
        c.scenes,
        f(c.wall_ms, 0),
        c.dofs,
        c.levels,
        c.max_error_estimate
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "n/a (fewer than 3 levels)".into())
    );
    let _ = writeln!(
        s,
        "linearity 1 mN - 5 N at the centre: largest |V/F - V(1 N)| = {:.2e} of the largest \
         voltage",
        cal.linearity_deviation
    );
    if !cal.linearity_by_electrode.is_empty() {
        let models: Vec<String> = cal
            .force_table_ladder
            .iter()
            .map(|s| {
                format!(
                    "{} N {}",
                    s.force_n,
                    s.model.map_or_else(|| "?".to_string(), |m| m.to_string())
                )
            })
            .collect();
        let _ = writeln!(
            s,
            "the sensor's linearity over the force table on the fidelity ladder ({}):\n  \
             electrode  max |V/F - V(1 N)| / V(1 N)  V/F at the top force / V(1 N)",
            models.join(", ")
        );
        for e in &cal.linearity_by_electrode {
            let _ = writeln!(
                s,
                "  {:<9}  {:>27}  {:>30}",
                e.electrode,
                format!("{:.2} %", e.deviation * 100.0),
                f(e.top_over_unit, 3)
            );
        }
    }
    let (x0, x1, y0, y1) = loc.domain_um();
    let _ = writeln!(
        s,
        "inverse domain: x {} - {} mm, y {} - {} mm (monotone branches of u_x, u_y)",
        f(x0 / 1e3, 2),
        f(x1 / 1e3, 2),
        f(y0 / 1e3, 2),
        f(y1 / 1e3, 2)
    );
    let _ = writeln!(
        s,
        "held-out loads (between grid nodes, uncalibrated forces):\n    x_mm    y_mm  force_n   \
         err_x_um  err_y_um  err_force_%"
    );
    for h in held {
        let _ = writeln!(
            s,
            "  {:>6} {:>7} {:>8} {:>10} {:>9} {:>12}",
            f(h.x_um / 1e3, 2),
            f(h.y_um / 1e3, 2),
            h.force_n,
            f(h.error_x_um, 1),
            f(h.error_y_um, 1),
            f(100.0 * h.error_force_rel, 3)
        );
    }
    let _ = writeln!(
        s,
        "error against voltage noise at 1 N (held-out positions, voltages scaled to 1 N; RMS over \
         loads x trials):\n  sigma_mv  rms_x_um  rms_y_um  rms_force_%  max_force_%"
    );
    for r in noise {
        let _ = writeln!(
            s,
            "  {:>8} {:>9} {:>9} {:>12} {:>12}",
            r.sigma_mv,
            f(r.rms_error_x_um, 1),
            f(r.rms_error_y_um, 1),
            f(100.0 * r.rms_error_force_rel, 3),
            f(100.0 * r.max_error_force_rel, 3)
        );
    }
    let _ = writeln!(s, "wrote {}", dir.display());
    s
}
