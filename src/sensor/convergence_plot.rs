//! The convergence plot of `tactfab fe --convergence`: error against dofs and against time.

use crate::fe::richardson_ratios;
use crate::plot::{side_by_side, xy_svg, Axis, Series, Style, XyPlot};

use super::evaluate::SceneReport;

/// Two charts side by side, one series pair per scene: the deflection at the load of every level
/// against the Richardson value of the three finest levels (|f_k - f_ext| / |f_ext|, lines), and
/// the estimate each level reported (markers). Left against dofs, right against cumulative solve
/// time. Scenes answered without a plate (over a support) have nothing to plot and are left out.
pub fn convergence_svg(reports: &[SceneReport]) -> String {
    let mut by_dofs = Vec::new();
    let mut by_time = Vec::new();
    for r in reports.iter().filter(|r| r.model.kind.is_plate()) {
        let levels = &r.convergence;
        let mut t_ms = 0.0;
        let cumulative: Vec<f64> = levels
            .iter()
            .map(|l| {
                t_ms += l.time_ms;
                t_ms
            })
            .collect();
        let n = levels.len();
        if n >= 3 {
            let w = |k: usize| levels[k].deflection_at_load_um;
            let h = |k: usize| levels[k].max_element_um;
            let ext = richardson_ratios(
                w(n - 3),
                w(n - 2),
                w(n - 1),
                h(n - 3) / h(n - 2),
                h(n - 2) / h(n - 1),
            )
            .extrapolated;
            if ext != 0.0 {
                let err: Vec<f64> = (0..n).map(|k| ((w(k) - ext) / ext).abs()).collect();
                let name = format!("{}: deflection vs extrapolated", r.scene);
                by_dofs.push(Series {
                    name: name.clone(),
                    points: levels
                        .iter()
                        .zip(&err)
                        .map(|(l, e)| (l.dofs as f64, *e))
                        .collect(),
                    style: Style::LineAndMarkers,
                });
                by_time.push(Series {
                    name,
                    points: cumulative.iter().zip(&err).map(|(t, e)| (*t, *e)).collect(),
                    style: Style::LineAndMarkers,
                });
            }
        }
        let est: Vec<(usize, f64)> = levels
            .iter()
            .enumerate()
            .filter_map(|(k, l)| l.error_estimate.map(|e| (k, e)))
            .collect();
        if !est.is_empty() {
            let name = format!("{}: estimate", r.scene);
            by_dofs.push(Series {
                name: name.clone(),
                points: est
                    .iter()
                    .map(|&(k, e)| (levels[k].dofs as f64, e))
                    .collect(),
                style: Style::Markers,
            });
            by_time.push(Series {
                name,
                points: est.iter().map(|&(k, e)| (cumulative[k], e)).collect(),
                style: Style::Markers,
            });
        }
    }
    let chart = |title: &str, x: Axis, series| XyPlot {
        title: title.into(),
        x,
        y: Axis::log("relative error"),
        series,
    };
    side_by_side(&[
        xy_svg(
            &chart("error against dofs", Axis::log("dofs"), by_dofs),
            640,
            420,
        ),
        xy_svg(
            &chart(
                "error against time",
                Axis::log("cumulative solve time (ms)"),
                by_time,
            ),
            640,
            420,
        ),
    ])
}
