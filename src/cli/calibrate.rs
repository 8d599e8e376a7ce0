//! `tactfab calibrate FILE -o DIR`: calibration tables, the inverse's error on held-out loads and
//! under voltage noise, as CSV (unit-bearing headers) and SVG plots, written atomically.

use std::fmt::Write as _;

use anyhow::Context;

use tactfab::analysis::calibration::{
    calibrate, Calibration, CalibrationPlan, Sample, SupportGroups,
};
use tactfab::analysis::inverse::{held_out_errors, noise_study, HeldOutError, Locator, NoiseRow};
use tactfab::export::dir::write_dir_atomic;
use tactfab::plot::{xy_svg, Axis, Series, Style, XyPlot};
use tactfab::sensor::SensorGeometry;

use super::args::CalibrateArgs;
use super::output::f;
use super::{design, Outcome};

pub fn run(args: &CalibrateArgs) -> anyhow::Result<Outcome> {
    let (_, design) = design(&args.process)?;
    let g = SensorGeometry::new(&design);
    let cp = CalibrationPlan::new(
        &g,
        args.grid.x_step_mm * 1e3,
        args.grid.y_step_mm * 1e3,
        usize::from(args.held_out),
        args.grid.contact_radius_mm * 1e3,
        args.accuracy.into(),
    );
    let cal = calibrate(&g, &cp).context("calibration")?;
    let loc = Locator::new(&cal, SupportGroups::of(&g)?)?;
    let held = held_out_errors(&loc, &cal.held_out)?;
    let noise = noise_study(
        &loc,
        &cal.held_out,
        1.0,
        &args.noise_mv,
        usize::from(args.trials),
        args.seed,
    )?;
    let groups = SupportGroups::of(&g)?;
    let files = files(&cal, &groups, &held, &noise);
    write_dir_atomic(&args.out, &files, "grid.csv")?;
    print!("{}", summary(&cal, &loc, &held, &noise, &args.out));
    Ok(Outcome::Ok)
}

/// Voltage columns `<electrode>_voltage_mv` in the sensor's electrode order.
fn header(cal: &Calibration, lead: &str) -> String {
    let mut h = lead.to_string();
    for e in &cal.electrodes {
        let _ = write!(h, ",{e}_voltage_mv");
    }
    h
}

fn volts(s: &Sample) -> String {
    s.voltage_mv
        .iter()
        .map(|v| format!(",{}", f(*v, 6)))
        .collect()
}

fn model(s: &Sample) -> String {
    s.model.map(|m| m.to_string()).unwrap_or_default()
}

fn est(e: Option<f64>) -> String {
    e.map(|e| format!("{e:.3e}")).unwrap_or_default()
}

fn files(
    cal: &Calibration,
    gr: &SupportGroups,
    held: &[HeldOutError],
    noise: &[NoiseRow],
) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut csv = header(cal, "force_n,x_um,y_um") + ",model,error_estimate\n";
    for s in &cal.force_table {
        let _ = writeln!(
            csv,
            "{},{},{}{},{},{}",
            s.force_n,
            f(s.x_um, 1),
            f(s.y_um, 1),
            volts(s),
            model(s),
            est(s.error_estimate)
        );
    }
    out.push(("force.csv".to_string(), csv.into_bytes()));
    let mut csv = header(cal, "y_um,x_um,force_n") + ",u_y,model,error_estimate\n";
    for s in &cal.y_sweep {
        let _ = writeln!(
            csv,
            "{},{},{}{},{},{},{}",
            f(s.y_um, 1),
            f(s.x_um, 1),
            s.force_n,
            volts(s),
            f(gr.u_y(&s.voltage_mv), 6),
            model(s),
            est(s.error_estimate)
        );
    }
    out.push(("y-sweep.csv".to_string(), csv.into_bytes()));
    let mut csv = header(cal, "x_um,y_um,force_n") + ",vs1_mv,vs2_mv,u_x,model,error_estimate\n";
    for s in &cal.x_sweep {
        let v = &s.voltage_mv;
        let _ = writeln!(
            csv,
            "{},{},{}{},{},{},{},{},{}",
            f(s.x_um, 1),
            f(s.y_um, 1),
            s.force_n,
            volts(s),
            f(gr.vs1(v), 6),
            f(gr.vs2(v), 6),
            f(gr.u_x(v), 6),
            model(s),
            est(s.error_estimate)
        );
    }
    out.push(("x-sweep.csv".to_string(), csv.into_bytes()));
    let mut csv = header(cal, "x_um,y_um,force_n") + "\n";
    for s in cal.grid.iter().flatten() {
        let _ = writeln!(
            csv,
            "{},{},{}{}",
            f(s.x_um, 3),
            f(s.y_um, 3),
            s.force_n,
            volts(s)
        );
    }
    out.push(("grid.csv".to_string(), csv.into_bytes()));
    let mut csv = String::from(
        "x_um,y_um,force_n,estimated_x_um,estimated_y_um,estimated_force_n,error_x_um,error_y_um,\
         error_force_pct,iterations,clamped\n",
    );
    for h in held {
        let e = &h.estimate;
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{}",
            f(h.x_um, 1),
            f(h.y_um, 1),
            h.force_n,
            f(e.x_um, 3),
            f(e.y_um, 3),
            f(e.force_n, 6),
            f(h.error_x_um, 3),
            f(h.error_y_um, 3),
            f(100.0 * h.error_force_rel, 4),
            e.iterations,
            e.clamped_x || e.clamped_y
        );
    }
    out.push(("held-out.csv".to_string(), csv.into_bytes()));
    let mut csv = String::from(
        "sigma_mv,trials,rms_error_x_um,max_error_x_um,rms_error_y_um,max_error_y_um,\
         rms_error_force_pct,max_error_force_pct\n",
    );
    for r in noise {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{}",
            r.sigma_mv,
            r.trials,
            f(r.rms_error_x_um, 3),
            f(r.max_error_x_um, 3),
            f(r.rms_error_y_um, 3),
            f(r.max_error_y_um, 3),
            f(100.0 * r.rms_error_force_rel, 4),
            f(100.0 * r.max_error_force_rel, 4)
        );
    }
    out.push(("noise.csv".to_string(), csv.into_bytes()));
    for (name, plot) in plots(cal, gr, noise) {
        out.push((name, xy_svg(&plot, 720, 460).into_bytes()));
    }
    out
}

fn series(name: &str, points: Vec<(f64, f64)>, style: Style) -> Series {
    Series {
        name: name.to_string(),
        points,
        style,
    }
}

fn plots(cal: &Calibration, gr: &SupportGroups, noise: &[NoiseRow]) -> Vec<(String, XyPlot)> {
    let idx = |n: &str| cal.electrodes.iter().position(|e| e == n);
    let mut force = Vec::new();
    for (e, name) in cal.electrodes.iter().enumerate() {
        let pts = cal
            .force_table
            .iter()
            .map(|s| (s.force_n, s.voltage_mv[e].abs()))
            .collect();
        force.push(series(name, pts, Style::LineAndMarkers));
    }
    let along = |samples: &[Sample], key: fn(&Sample) -> f64, set: &[usize]| -> Vec<Series> {
        set.iter()
            .map(|&e| {
                series(
                    &cal.electrodes[e],
                    samples
                        .iter()
                        .map(|s| (key(s) / 1e3, s.voltage_mv[e]))
                        .collect(),
                    Style::LineAndMarkers,
                )
            })
            .collect()
    };
    let supports: Vec<usize> = gr.support1.iter().chain(&gr.support2).copied().collect();
    let mut ysw = along(&cal.y_sweep, |s| s.y_um, &supports);
    ysw.push(series(
        "u_y = (S1 - S2)/(S1 + S2) x 100 mV",
        cal.y_sweep
            .iter()
            .map(|s| (s.y_um / 1e3, 100.0 * gr.u_y(&s.voltage_mv)))
            .collect(),
        Style::Line,
    ));
    let mut xsw = vec![
        series(
            "VS1 = first unit pair",
            cal.x_sweep
                .iter()
                .map(|s| (s.x_um / 1e3, gr.vs1(&s.voltage_mv)))
                .collect(),
            Style::LineAndMarkers,
        ),
        series(
            "VS2 = last unit pair",
            cal.x_sweep
                .iter()
                .map(|s| (s.x_um / 1e3, gr.vs2(&s.voltage_mv)))
                .collect(),
            Style::LineAndMarkers,
        ),
    ];
    xsw.extend(along(&cal.x_sweep, |s| s.x_um, &supports));
    let mut out = vec![
        (
            "force.svg".to_string(),
            XyPlot {
                title: "voltage against force at the centre".into(),
                x: Axis::log("force (N)"),
                y: Axis::log("|voltage| (mV)"),
                series: force,
            },
        ),
        (
            "y-sweep.svg".to_string(),
            XyPlot {
                title: "support voltages against y (x = length/2, 1 N)".into(),
                x: Axis::linear("y (mm)"),
                y: Axis::linear("voltage (mV)"),
                series: ysw,
            },
        ),
        (
            "x-sweep.svg".to_string(),
            XyPlot {
                title: "support voltages against x (y = width/2, 1 N)".into(),
                x: Axis::linear("x (mm)"),
                y: Axis::linear("voltage (mV)"),
                series: xsw,
            },
        ),
    ];
    if let (Some(_), Some(_)) = (idx("S12"), idx("S22")) {
        // Paper 002 Fig. 23: the middle pair alone.
        let pair = along(
            &cal.y_sweep,
            |s| s.y_um,
            &[idx("S12").unwrap_or(0), idx("S22").unwrap_or(0)],
        );
        out.push((
            "pair-y.svg".to_string(),
            XyPlot {
                title: "V12 and V22 against y (paper 002 Fig. 23)".into(),
                x: Axis::linear("y (mm)"),
                y: Axis::linear("voltage (mV)"),
                series: pair,
            },
        ));
    }
    let noisy: Vec<&NoiseRow> = noise.iter().filter(|r| r.sigma_mv > 0.0).collect();
    if !noisy.is_empty() {
        let s = |name: &str, g: fn(&NoiseRow) -> f64| {
            series(
                name,
                noisy.iter().map(|r| (r.sigma_mv, g(r))).collect(),
                Style::LineAndMarkers,
            )
        };
        out.push((
            "noise.svg".to_string(),
            XyPlot {
                title: "inverse error against voltage noise (held-out positions, 1 N)".into(),
                x: Axis::log("noise sigma (mV)"),
                y: Axis::log("RMS error (um; force in 0.1 %)"),
                series: vec![
                    s("x (um)", |r| r.rms_error_x_um),
                    s("y (um)", |r| r.rms_error_y_um),
                    s("force (0.1 %)", |r| 1e3 * r.rms_error_force_rel),
                ],
            },
        ));
    }
    out
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
