//! The softness curve (paper 001 Fig. 24): middle-electrode voltage against the tissue modulus, per
//! force, FE and composite beam.

use crate::plot::{xy_svg, Axis, Series, Style, XyPlot};

/// One curve: name, (E_t Pa, voltage mV) points, and whether it is FE (markers) or the beam (line).
pub type Curve = (String, Vec<(f64, f64)>, bool);

/// The chart of all curves.
pub fn softness_svg(curves: &[Curve]) -> String {
    let series = curves
        .iter()
        .map(|(name, pts, fe)| Series {
            name: name.clone(),
            points: pts.clone(),
            style: if *fe {
                Style::LineAndMarkers
            } else {
                Style::Line
            },
        })
        .collect();
    xy_svg(
        &XyPlot {
            title: "Middle electrode voltage vs tissue modulus (FE: markers; composite beam: \
                    lines)"
                .into(),
            x: Axis::log("tissue modulus E_t (Pa)"),
            y: Axis::linear("voltage (mV)"),
            series,
        },
        860,
        560,
    )
}
