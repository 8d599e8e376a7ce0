//! The matching family as an SVG scatter (Fig. 15 of paper 001 seen from the side): thickness
//! against length, one series per width band.

use crate::plot::{xy_svg, Axis, Series, Style, XyPlot};
use crate::sweep::design::Design;

/// Scatter of the family: x = length (mm), y = thickness (um), one series per fifth of the width
/// range, and the prototype they match as a series of its own.
pub fn family_svg(family: &[Design], tol: Option<f64>, prototype: Option<&Design>) -> String {
    let (lo, hi) = family
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), d| {
            (a.min(d.width_um), b.max(d.width_um))
        });
    let bands = 5usize;
    let band = |w: f64| {
        if hi > lo {
            (((w - lo) / (hi - lo)) * bands as f64)
                .floor()
                .min(bands as f64 - 1.0) as usize
        } else {
            0
        }
    };
    let mut series: Vec<Series> = (0..bands)
        .map(|b| {
            let (a, z) = (
                lo + (hi - lo) * b as f64 / bands as f64,
                lo + (hi - lo) * (b + 1) as f64 / bands as f64,
            );
            Series {
                name: format!("width {:.1}-{:.1} mm", a / 1000.0, z / 1000.0),
                points: Vec::new(),
                style: Style::Markers,
            }
        })
        .collect();
    for d in family {
        series[band(d.width_um)]
            .points
            .push((d.length_um / 1000.0, d.thickness_um));
    }
    series.retain(|s| !s.points.is_empty());
    if let Some(p) = prototype {
        series.push(Series {
            name: format!(
                "prototype {:.1} x {:.1} mm, {:.0} um",
                p.length_um / 1000.0,
                p.width_um / 1000.0,
                p.thickness_um
            ),
            points: vec![(p.length_um / 1000.0, p.thickness_um)],
            style: Style::Markers,
        });
    }
    let title = match tol {
        Some(t) => format!(
            "Designs with the prototype's elongation (+/- {:.1} %): {}",
            100.0 * t,
            family.len()
        ),
        None => format!("Designs with the prototype's elongation: {}", family.len()),
    };
    xy_svg(
        &XyPlot {
            title,
            x: Axis::linear("length (mm)"),
            y: Axis::linear("thickness (um)"),
            series,
        },
        800,
        560,
    )
}
