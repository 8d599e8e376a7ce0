//! The files of `tactfab orient -o DIR`: `orientation.csv` (charge against angle per force and
//! electrode) and one SVG per electrode with the FE points and both fits.

use std::fmt::Write as _;

use crate::analysis::orientation::Orientation;
use crate::plot::{xy_svg, Axis, Series, Style, XyPlot};
use crate::units::fixed as f;

/// The CSV and the plots.
pub fn files(o: &Orientation) -> Vec<(String, Vec<u8>)> {
    let mut csv = String::from("force_n,angle_deg");
    for e in &o.electrodes {
        let _ = write!(csv, ",{e}_charge_pc");
    }
    csv.push('\n');
    for (fi, force) in o.plan.forces_n.iter().enumerate() {
        for (ai, a) in o.plan.angles_deg.iter().enumerate() {
            let _ = write!(csv, "{force},{a}");
            for c in &o.charge_pc[fi][ai] {
                let _ = write!(csv, ",{}", f(*c, 6));
            }
            csv.push('\n');
        }
    }
    let mut out = vec![("orientation.csv".to_string(), csv.into_bytes())];
    let fine: Vec<f64> = (0..=360)
        .map(|k| k as f64 * 0.5)
        .filter(|a| *a >= o.plan.angles_deg[0] && *a <= *o.plan.angles_deg.last().unwrap_or(&180.0))
        .collect();
    let iref = o
        .plan
        .forces_n
        .iter()
        .position(|x| (*x - o.plan.reference_force_n).abs() < 1e-12)
        .unwrap_or(0);
    for (e, fits) in o.fits.iter().enumerate() {
        let mut series = Vec::new();
        for (fi, force) in o.plan.forces_n.iter().enumerate() {
            series.push(Series {
                name: format!("FE {force} N"),
                points: o
                    .plan
                    .angles_deg
                    .iter()
                    .zip(&o.charge_pc[fi])
                    .map(|(a, r)| (*a, r[e]))
                    .collect(),
                style: Style::Markers,
            });
        }
        series.push(Series {
            name: format!(
                "Chebyshev deg {} ({} N)",
                fits.chebyshev.basis.degree, o.plan.forces_n[iref]
            ),
            points: fine.iter().map(|&a| (a, fits.chebyshev.eval(a))).collect(),
            style: Style::Line,
        });
        series.push(Series {
            name: format!("Fourier 2theta, {} harmonics", fits.fourier.basis.degree),
            points: fine.iter().map(|&a| (a, fits.fourier.eval(a))).collect(),
            style: Style::Line,
        });
        let plot = XyPlot {
            title: format!("{}: charge against probe angle", fits.electrode),
            x: Axis::linear("angle (deg)"),
            y: Axis::linear("charge (pC)"),
            series,
        };
        out.push((
            format!("orientation-{}.svg", fits.electrode),
            xy_svg(&plot, 720, 460).into_bytes(),
        ));
    }
    out
}
