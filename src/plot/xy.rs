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
    /// A dashed line: a reference level, not data (e.g. the value without noise).
    Dashed,
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

/// Colour-blind-safe palette (Okabe-Ito, its yellow dropped: unreadable on white) and four of
/// Tol's muted colours: twelve distinct colours, enough for the nine electrodes and a reference;
/// cycled beyond.
pub const PALETTE: [RGBColor; 12] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(136, 34, 85),
    RGBColor(153, 153, 51),
    RGBColor(68, 170, 153),
    RGBColor(119, 119, 119),
    RGBColor(51, 34, 136),
];

/// The marker shape of series `i`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Cross,
}

fn marker(i: usize) -> Marker {
    [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ][i % 4]
}

/// A tick label: at most four significant digits, no trailing point or zeros, powers of ten as
/// 1e4 beyond 1e4 (plotters' own "10000." ran off the right edge).
pub fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { String::new() };
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.2e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        return format!("{m}e{e}");
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A tick at round-off distance from zero (plotters steps lo + k h: -1.4e-20 on a voltage axis
/// through zero) is zero; a log axis has no zero.
fn snap(v: f64, lo: f64, hi: f64, log: bool) -> f64 {
    if !log && v.abs() <= 1e-9 * (hi - lo).abs() {
        0.0
    } else {
        v
    }
}

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
/// data points, and how many it covers (0: the legend hides nothing there).
fn emptiest_corner<'a>(
    points: impl Iterator<Item = &'a (f64, f64)>,
    x: (f64, f64, bool),
    y: (f64, f64, bool),
    box_w: f64,
    box_h: f64,
) -> (SeriesLabelPosition, usize) {
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
    (corners[best].clone(), count[best])
}

/// Width (px) of the legend column beside the chart when no corner is free: the longest name at
/// ~7 px per character of 12 px sans-serif, the sample mark and margins.
fn legend_column_px(series: &[Series]) -> u32 {
    let longest = series
        .iter()
        .map(|s| s.name.chars().count())
        .max()
        .unwrap_or(0);
    (longest as u32 * 7 + 44).min(320)
}

/// Draw `plot` at `width` x `height` pixels and return the SVG text.
///
/// Points that cannot be drawn (NaN, or <= 0 on a log axis) are skipped, never an error: a plot
/// is a view of results that were already checked. The legend sits in the corner that hides no
/// data, or in a column beside the chart (the SVG grows by its width) when every corner would.
pub fn xy_svg(plot: &XyPlot, width: u32, height: u32) -> String {
    let mut out = String::new();
    {
        let p = Placement::of(plot, width, height);
        let ((x0, x1), (y0, y1), legend_corner) = (p.x, p.y, p.corner.clone());
        let outside = plot.series.len() > 1 && p.covered > 0;
        let extra = if outside {
            legend_column_px(&plot.series)
        } else {
            0
        };
        // Errors from the SVG backend writing to a String cannot happen; keep going regardless.
        let canvas = SVGBackend::with_string(&mut out, (width + extra, height)).into_drawing_area();
        let _ = canvas.fill(&WHITE);
        let (root, legend_area) = canvas.split_horizontally(width);
        if outside {
            draw_legend_column(&legend_area, &plot.series);
        }
        let drawable = |q: &(f64, f64)| drawable(plot, q);
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&plot.title, ("sans-serif", 18))
            .margin(12)
            .margin_right(24)
            .x_label_area_size(42)
            .y_label_area_size(64);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                let _ = chart
                    .configure_mesh()
                    .x_desc(&plot.x.label)
                    .y_desc(&plot.y.label)
                    .x_label_formatter(&|v| tick(snap(*v, x0, x1, plot.x.log)))
                    .y_label_formatter(&|v| tick(snap(*v, y0, y1, plot.y.log)))
                    .draw();
                for (i, s) in plot.series.iter().enumerate() {
                    let colour = PALETTE[i % PALETTE.len()];
                    let pts: Vec<(f64, f64)> =
                        s.points.iter().copied().filter(|p| drawable(p)).collect();
                    if s.style == Style::Dashed {
                        if let Ok(a) = chart.draw_series(DashedLineSeries::new(
                            pts.clone(),
                            6,
                            4,
                            colour.stroke_width(1),
                        )) {
                            a.label(&s.name).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(1))
                            });
                        }
                    }
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
                        // Shapes cycle too (circle, square, triangle, cross), so series that
                        // coincide stay visible on top of each other.
                        let legend = s.style == Style::Markers;
                        macro_rules! marks {
                            ($make:expr, $key:expr) => {{
                                if let Ok(a) = chart.draw_series(pts.iter().map(|&p| $make(p))) {
                                    if legend {
                                        a.label(&s.name).legend($key);
                                    }
                                }
                            }};
                        }
                        match marker(i) {
                            Marker::Circle => marks!(
                                move |p| Circle::new(p, 3, colour.filled()),
                                move |(x, y)| Circle::new((x + 9, y), 3, colour.filled())
                            ),
                            Marker::Square => marks!(
                                move |p| EmptyElement::at(p)
                                    + Rectangle::new([(-3, -3), (3, 3)], colour.filled()),
                                move |(x, y)| Rectangle::new(
                                    [(x + 6, y - 3), (x + 12, y + 3)],
                                    colour.filled()
                                )
                            ),
                            Marker::Triangle => marks!(
                                move |p| TriangleMarker::new(p, 4, colour.filled()),
                                move |(x, y)| TriangleMarker::new((x + 9, y), 4, colour.filled())
                            ),
                            Marker::Cross => marks!(
                                move |p| Cross::new(p, 4, colour.stroke_width(2)),
                                move |(x, y)| Cross::new((x + 9, y), 4, colour.stroke_width(2))
                            ),
                        }
                    }
                }
                if plot.series.len() > 1 && !outside {
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
        let _ = canvas.present();
    }
    out
}

/// A point the axes can show (finite, and positive on a log axis).
fn drawable(plot: &XyPlot, p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && (!plot.x.log || p.0 > 0.0) && (!plot.y.log || p.1 > 0.0)
}

/// The axes' ranges and the legend's corner with the data it would cover there.
struct Placement {
    x: (f64, f64),
    y: (f64, f64),
    corner: SeriesLabelPosition,
    covered: usize,
}

impl Placement {
    fn of(plot: &XyPlot, width: u32, height: u32) -> Self {
        let all = || {
            plot.series
                .iter()
                .flat_map(|s| s.points.iter())
                .filter(|p| drawable(plot, p))
        };
        let x = range(all().map(|p| p.0), plot.x.log);
        let y = range(all().map(|p| p.1), plot.y.log);
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
            let pts: Vec<&(f64, f64)> = s.points.iter().filter(|p| drawable(plot, p)).collect();
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
        let (corner, covered) = emptiest_corner(
            samples.iter(),
            (x.0, x.1, plot.x.log),
            (y.0, y.1, plot.y.log),
            box_w,
            box_h,
        );
        Placement {
            x,
            y,
            corner,
            covered,
        }
    }
}

/// The legend as a column of its own: a sample of each series' line or marker and its name.
fn draw_legend_column<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    series: &[Series],
) {
    for (i, s) in series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let y = 48 + 18 * i as i32;
        let _ = match s.style {
            Style::Markers => match marker(i) {
                Marker::Circle => area.draw(&Circle::new((17, y), 3, colour.filled())),
                Marker::Square => {
                    area.draw(&Rectangle::new([(14, y - 3), (20, y + 3)], colour.filled()))
                }
                Marker::Triangle => area.draw(&TriangleMarker::new((17, y), 4, colour.filled())),
                Marker::Cross => area.draw(&Cross::new((17, y), 4, colour.stroke_width(2))),
            },
            Style::Dashed => area.draw(&PathElement::new(
                vec![(8, y), (14, y), (20, y), (26, y)],
                colour.stroke_width(1),
            )),
            _ => area.draw(&PathElement::new(
                vec![(8, y), (26, y)],
                colour.stroke_width(2),
            )),
        };
        let _ = area.draw(&Text::new(
            s.name.clone(),
            (32, y - 7),
            ("sans-serif", 12).into_font().color(&BLACK),
        ));
    }
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
        // Three circles for the first series; none for the second (NaN, and 0 on a log axis),
        // whose legend key is its own marker, a square.
        assert_eq!(a.matches("<circle").count(), 3);
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick(10000.0), "10000");
        assert_eq!(tick(1e5), "1e5");
        assert_eq!(tick(2.5e-4), "2.5e-4");
        assert_eq!(tick(0.1), "0.1");
        assert_eq!(tick(12.5), "12.5");
        assert_eq!(tick(-3.0), "-3");
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(snap(-1.36e-20, -1e-4, 2.5e-4, false)), "0");
        assert_eq!(tick(snap(1e-5, -1e-4, 2.5e-4, false)), "1e-5");
        assert_eq!(tick(snap(1e-12, 1e-12, 1e-3, true)), "1e-12");
    }

    /// Nine electrodes and a reference on one chart: distinct colours, every label on the canvas
    /// (ticks up to 1e4 on a log axis included), and the legend beside the chart when the data
    /// fill every corner.
    #[test]
    fn many_series_keep_distinct_colours_and_their_text_on_the_canvas() {
        let distinct: std::collections::BTreeSet<(u8, u8, u8)> =
            PALETTE.iter().map(|c| (c.0, c.1, c.2)).collect();
        assert_eq!(distinct.len(), PALETTE.len());
        assert!(PALETTE.len() >= 10);
        let names = ["S11", "S12", "S13", "M1", "M2", "M3", "S21", "S22", "S23"];
        let mut series: Vec<Series> = names
            .iter()
            .enumerate()
            .map(|(k, n)| Series {
                name: format!("{n} electrode voltage"),
                // Lines across the whole chart, top to bottom: no corner is free.
                points: (0..=8)
                    .map(|i| {
                        let x = 10f64.powf(i as f64 / 2.0);
                        (x, ((i + k) % 9) as f64)
                    })
                    .collect(),
                style: Style::LineAndMarkers,
            })
            .collect();
        series.push(Series {
            name: "no noise".into(),
            points: vec![(1.0, 4.0), (1e4, 4.0)],
            style: Style::Dashed,
        });
        let plot = XyPlot {
            title: "voltage against something long enough to matter".into(),
            x: Axis::log("force (N)"),
            y: Axis::linear("voltage (mV)"),
            series,
        };
        let svg = xy_svg(&plot, 640, 400);
        let outside = crate::plot::text_outside_canvas(&svg);
        assert!(outside.is_empty(), "{outside:?}");
        assert!(
            !svg.starts_with("<svg width=\"640\""),
            "the legend moved beside the chart"
        );
        for (i, _) in names.iter().enumerate() {
            let c = PALETTE[i];
            let hex = format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
            assert!(svg.contains(&hex), "series {i} drawn in {hex}");
        }
        assert!(
            svg.contains("10000") && !svg.contains("10000."),
            "tick labels"
        );
    }
}
