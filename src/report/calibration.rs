//! The files of `tactfab calibrate`: one CSV per table (units in every header) and one SVG per
//! plot, rendered from a [`CalibrationStudy`].

use std::fmt::Write as _;

use crate::analysis::calibration::{Calibration, Sample, SupportGroups};
use crate::analysis::inverse::NoiseRow;
use crate::analysis::study::CalibrationStudy;
use crate::plot::{side_by_side, xy_svg, Axis, Series, Style, XyPlot};
use crate::report::Origin;
use crate::sensor::Accuracy;
use crate::units::fixed as f;

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

/// The calibration's identity file: which design (process bytes, overrides) and accuracy it was
/// made for, so `locate --calibration` can refuse another design's.
pub const META: &str = "calibration.json";

/// What [`META`] holds.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CalibrationMeta {
    #[serde(flatten)]
    pub origin: Origin,
    /// The study's accuracy (model rung, tolerance, levels, in-plane condition), as asked.
    pub accuracy: serde_json::Value,
    /// Electrode order of the voltage columns.
    pub electrodes: Vec<String>,
}

impl CalibrationMeta {
    /// Reads [`META`]'s bytes.
    pub fn parse(bytes: &[u8]) -> Result<Self, serde_json::Error> {
        serde_json::from_slice(bytes)
    }
}

/// Every file of the calibration directory: [`META`], the CSV tables and the SVG plots.
pub fn files(
    study: &CalibrationStudy,
    origin: &Origin,
    accuracy: Accuracy,
) -> Vec<(String, Vec<u8>)> {
    let (cal, gr) = (&study.calibration, &study.groups);
    let (held, noise) = (&study.held_out, &study.noise);
    let mut out = Vec::new();
    let meta = CalibrationMeta {
        origin: origin.clone(),
        accuracy: serde_json::to_value(accuracy).unwrap_or(serde_json::Value::Null),
        electrodes: cal.electrodes.clone(),
    };
    let json = serde_json::to_string_pretty(&meta).unwrap_or_default() + "\n";
    out.push((META.to_string(), json.into_bytes()));
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
    for (name, plot) in plots(cal, gr) {
        out.push((name, xy_svg(&plot, 720, 460).into_bytes()));
    }
    if let Some(svg) = noise_svg(noise) {
        out.push(("noise.svg".to_string(), svg.into_bytes()));
    }
    out
}

/// A named error of the noise table.
type NoiseCurve = (&'static str, fn(&NoiseRow) -> f64);

/// The inverse's error against voltage noise: position (um) and force (%) on charts of their
/// own, noise on a log axis, the noise-free error (sigma = 0, which a log axis cannot show) as a
/// dashed level across each.
fn noise_svg(noise: &[NoiseRow]) -> Option<String> {
    let noisy: Vec<&NoiseRow> = noise.iter().filter(|r| r.sigma_mv > 0.0).collect();
    if noisy.is_empty() {
        return None;
    }
    let (lo, hi) = noisy.iter().fold((f64::INFINITY, 0f64), |(a, b), r| {
        (a.min(r.sigma_mv), b.max(r.sigma_mv))
    });
    let quiet = noise.iter().find(|r| r.sigma_mv == 0.0);
    let chart = |title: &str, y: &str, what: &[NoiseCurve]| {
        let mut series: Vec<Series> = what
            .iter()
            .map(|(name, g)| {
                series(
                    name,
                    noisy.iter().map(|r| (r.sigma_mv, g(r))).collect(),
                    Style::LineAndMarkers,
                )
            })
            .collect();
        if let Some(q) = quiet {
            for (name, g) in what {
                series.push(self::series(
                    &format!("{name}, no noise"),
                    vec![(lo, g(q)), (hi, g(q))],
                    Style::Dashed,
                ));
            }
        }
        xy_svg(
            &XyPlot {
                title: title.into(),
                x: Axis::log("noise sigma (mV)"),
                y: Axis::log(y),
                series,
            },
            520,
            420,
        )
    };
    Some(side_by_side(&[
        chart(
            "position error against noise (1 N)",
            "RMS error (um)",
            &[("x", |r| r.rms_error_x_um), ("y", |r| r.rms_error_y_um)],
        ),
        chart(
            "force error against noise (1 N)",
            "RMS error (%)",
            &[("force", |r| 100.0 * r.rms_error_force_rel)],
        ),
    ]))
}

fn series(name: &str, points: Vec<(f64, f64)>, style: Style) -> Series {
    Series {
        name: name.to_string(),
        points,
        style,
    }
}

fn plots(cal: &Calibration, gr: &SupportGroups) -> Vec<(String, XyPlot)> {
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
    out
}
