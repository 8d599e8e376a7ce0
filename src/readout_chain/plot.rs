//! The read-out record as a picture: the force history beside the channels' voltages.

use crate::plot::{side_by_side, xy_svg, Axis, Series, Style, XyPlot};

use super::study::ReadoutStudy;

/// Most points drawn per curve; the CSV has every sample.
const MAX_PLOTTED: usize = 1500;

/// Every k-th sample (and the last) so a curve has at most [`MAX_PLOTTED`] points.
fn thin(t: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    let step = t.len().div_ceil(MAX_PLOTTED).max(1);
    let mut pts: Vec<(f64, f64)> = t
        .iter()
        .zip(v)
        .step_by(step)
        .map(|(a, b)| (*a, *b))
        .collect();
    if let (Some(&lt), Some(&lv)) = (t.last(), v.last()) {
        if pts.last().is_some_and(|p| p.0 != lt) {
            pts.push((lt, lv));
        }
    }
    pts
}

/// Force (left) and the voltages of every channel (right), both against time.
pub fn readout_svg(s: &ReadoutStudy) -> String {
    let force = XyPlot {
        title: format!("force: {}", history_name(s)),
        x: Axis::linear("time (s)"),
        y: Axis::linear("force (N)"),
        series: vec![Series {
            name: "F".into(),
            points: thin(&s.t_s, &s.force_n),
            style: Style::Line,
        }],
    };
    let volts = XyPlot {
        title: format!(
            "{} output (tau {:.3e} s, corner {:.3e} Hz)",
            s.amplifier.name(),
            s.channels.first().map_or(0.0, |c| c.tau_s),
            s.channels.first().map_or(0.0, |c| c.corner_hz)
        ),
        x: Axis::linear("time (s)"),
        y: Axis::linear("voltage (V)"),
        series: s
            .channels
            .iter()
            .map(|c| Series {
                name: c.name.clone(),
                points: thin(&s.t_s, &c.voltage_v),
                style: Style::Line,
            })
            .collect(),
    };
    side_by_side(&[xy_svg(&force, 480, 400), xy_svg(&volts, 760, 400)])
}

fn history_name(s: &ReadoutStudy) -> String {
    match s.spec.history {
        super::HistoryKind::HalfSine => "half-sine grasp, held".into(),
        super::HistoryKind::Sine5Hz => "5 Hz sine".into(),
        super::HistoryKind::Pulse => "1 Hz pulses on a held grasp".into(),
    }
}
