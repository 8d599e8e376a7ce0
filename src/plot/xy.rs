//! An x-y chart: lines and/or markers, linear or log axes, a legend.

use plotters::prelude::*;

/// Axis scale and label.
#[derive(Debug, Clone)]
pub struct Axis {
    pub label: String,
    pub log: bool,
}

impl Axis {
    pub fn linear(label: impl Into<String>) -> Self {
        Axis {
            label: label.into(),
            log: false,
        }
    }
    pub fn log(label: impl Into<String>) -> Self {
        Axis {
            label: label.into(),
            log: true,
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Line,
    Markers,
    LineAndMarkers,
}

/// One named data series.
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

/// A chart: title, axes and series.
#[derive(Debug, Clone)]
pub struct XyPlot {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
}

/// Colour-blind-safe palette (Okabe-Ito), cycled per series.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];

/// Data range of one axis over all finite points (positive only on a log axis), padded.
fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (l, h) = (lo.log10().floor(), hi.log10().ceil());
        let h = if h <= l { l + 1.0 } else { h };
        (10f64.powf(l), 10f64.powf(h))
    } else {
        let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
        (lo - 0.05 * span, hi + 0.05 * span)
    }
}

/// The corner whose legend box (`box_w` x `box_h`, fractions of the plot area) covers the fewest
/// data points, so the legend hides as little as it can.
fn emptiest_corner<'a>(
    points: impl Iterator<Item = &'a (f64, f64)>,
    x: (f64, f64, bool),
    y: (f64, f64, bool),
    box_w: f64,
    box_h: f64,
) -> SeriesLabelPosition {
    let unit = |v: f64, (lo, hi, log): (f64, f64, bool)| {
        if log {
            (v / lo).ln() / (hi / lo).ln()
        } else {
            (v - lo) / (hi - lo)
        }
    };
    // upper right, upper left, lower right, lower left
    let mut count = [0usize; 4];
    for (u, v) in points.map(|p| (unit(p.0, x), unit(p.1, y))) {
        let (right, left, upper, lower) =
            (u >= 1.0 - box_w, u <= box_w, v >= 1.0 - box_h, v <= box_h);
        for (i, inside) in [right && upper, left && upper, right && lower, left && lower]
            .into_iter()
            .enumerate()
        {
            count[i] += inside as usize;
        }
    }
    let corners = [
        SeriesLabelPosition::UpperRight,
        SeriesLabelPosition::UpperLeft,
        SeriesLabelPosition::LowerRight,
        SeriesLabelPosition::LowerLeft,
    ];
    let best = (0..4).min_by_key(|&i| count[i]).unwrap_or(0);
    corners[best].clone()
}

/// Draw `plot` at `width` x `height` pixels and return the SVG text.
///
/// Points that cannot be drawn (NaN, or <= 0 on a log axis) are skipped, never an error: a plot
/// is a view of results that were already checked.
pub fn xy_svg(plot: &XyPlot, width: u32, height: u32) -> String {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        // Errors from the SVG backend writing to a String cannot happen; keep going regardless.
        let _ = root.fill(&WHITE);
        let drawable = |p: &(f64, f64)| {
            p.0.is_finite()
                && p.1.is_finite()
                && (!plot.x.log || p.0 > 0.0)
                && (!plot.y.log || p.1 > 0.0)
        };
        let all = || {
            plot.series
                .iter()
                .flat_map(|s| s.points.iter())
                .filter(|p| drawable(p))
        };
        let (x0, x1) = range(all().map(|p| p.0), plot.x.log);
        let (y0, y1) = range(all().map(|p| p.1), plot.y.log);
        // Legend box size as plotters lays it out (about 6 px per character, 15 px per row).
        let longest = plot
            .series
            .iter()
            .map(|s| s.name.chars().count())
            .max()
            .unwrap_or(0) as f64;
        let box_w = ((longest * 6.5 + 60.0) / (width as f64 - 76.0)).min(1.0);
        let box_h = ((plot.series.len() as f64 * 15.0 + 15.0) / (height as f64 - 80.0)).min(1.0);
        // Lines count too: a few points along every drawn segment.
        let mut samples: Vec<(f64, f64)> = all().copied().collect();
        for s in plot.series.iter().filter(|s| s.style != Style::Markers) {
            let pts: Vec<&(f64, f64)> = s.points.iter().filter(|p| drawable(p)).collect();
            for w in pts.windows(2) {
                let lerp = |a: f64, b: f64, t: f64, log: bool| {
                    if log {
                        a * (b / a).powf(t)
                    } else {
                        a + (b - a) * t
                    }
                };
                samples.extend((1..8).map(|k| {
                    let t = k as f64 / 8.0;
                    (
                        lerp(w[0].0, w[1].0, t, plot.x.log),
                        lerp(w[0].1, w[1].1, t, plot.y.log),
                    )
                }));
            }
        }
        let legend_corner = emptiest_corner(
            samples.iter(),
            (x0, x1, plot.x.log),
            (y0, y1, plot.y.log),
            box_w,
            box_h,
        );
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&plot.title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(42)
            .y_label_area_size(64);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                let _ = chart
                    .configure_mesh()
                    .x_desc(&plot.x.label)
                    .y_desc(&plot.y.label)
                    .draw();
                for (i, s) in plot.series.iter().enumerate() {
                    let colour = PALETTE[i % PALETTE.len()];
                    let pts: Vec<(f64, f64)> =
                        s.points.iter().copied().filter(|p| drawable(p)).collect();
                    if matches!(s.style, Style::Line | Style::LineAndMarkers) {
                        if let Ok(a) =
                            chart.draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                        {
                            a.label(&s.name).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                            });
                        }
                    }
                    if matches!(s.style, Style::Markers | Style::LineAndMarkers) {
                        let marks = pts.iter().map(|&p| Circle::new(p, 3, colour.filled()));
                        if let Ok(a) = chart.draw_series(marks) {
                            if s.style == Style::Markers {
                                a.label(&s.name).legend(move |(x, y)| {
                                    Circle::new((x + 9, y), 3, colour.filled())
                                });
                            }
                        }
                    }
                }
                if plot.series.len() > 1 {
                    let _ = chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.85))
                        .border_style(BLACK.mix(0.4))
                        .position(legend_corner)
                        .draw();
                }
            }};
        }
        match (plot.x.log, plot.y.log) {
            (false, false) => {
                if let Ok(c) = builder.build_cartesian_2d(x0..x1, y0..y1) {
                    draw!(c)
                }
            }
            (true, false) => {
                if let Ok(c) = builder.build_cartesian_2d((x0..x1).log_scale(), y0..y1) {
                    draw!(c)
                }
            }
            (false, true) => {
                if let Ok(c) = builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale()) {
                    draw!(c)
                }
            }
            (true, true) => {
                if let Ok(c) =
                    builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                {
                    draw!(c)
                }
            }
        }
        let _ = root.present();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> XyPlot {
        XyPlot {
            title: "error against dofs".into(),
            x: Axis::log("dofs"),
            y: Axis::log("estimated error"),
            series: vec![
                Series {
                    name: "sensor".into(),
                    points: vec![(1e3, 1e-2), (4e3, 3e-3), (1.6e4, 8e-4)],
                    style: Style::LineAndMarkers,
                },
                Series {
                    name: "skip".into(),
                    points: vec![(f64::NAN, 1.0), (10.0, 0.0)],
                    style: Style::Markers,
                },
            ],
        }
    }

    #[test]
    fn draws_every_drawable_point_and_is_deterministic() {
        let a = xy_svg(&sample(), 640, 400);
        assert_eq!(a, xy_svg(&sample(), 640, 400));
        assert!(a.starts_with("<svg"));
        assert!(a.contains("error against dofs") && a.contains("sensor"));
        // Three markers for the first series, none for the second (NaN, and 0 on a log axis), plus
        // the legend marker of the markers-only series.
        assert_eq!(a.matches("<circle").count(), 3 + 1);
    }
}
