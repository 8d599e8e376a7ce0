//! Polygon text from the 5x7 font: pixels as squares, merged by the boolean adapter.

use geo::Polygon;

use super::boolean::{rect, union};
use super::font::pixels;

/// Size of a line of `n` characters: 6 pixels per character (5 + 1 spacing) less the last
/// spacing, 7 pixels high.
pub fn line_size_um(n: usize, pixel_um: f64) -> (f64, f64) {
    let w = if n == 0 {
        0.0
    } else {
        (6 * n - 1) as f64 * pixel_um
    };
    (w, 7.0 * pixel_um)
}

/// Size of a block of lines, 3 pixels of leading between lines.
pub fn block_size_um(lines: &[String], pixel_um: f64) -> (f64, f64) {
    let w = lines
        .iter()
        .map(|l| line_size_um(l.chars().count(), pixel_um).0)
        .fold(0.0, f64::max);
    let n = lines.len();
    let h = if n == 0 {
        0.0
    } else {
        (7 * n + 3 * (n - 1)) as f64 * pixel_um
    };
    (w, h)
}

/// Merged polygons of `lines`, first line on top, lower-left corner of the block at (x, y).
/// Characters the font lacks are drawn as spaces (the caller upper-cases).
pub fn text_polygons(lines: &[String], x_um: f64, y_um: f64, pixel_um: f64) -> Vec<Polygon> {
    let n = lines.len();
    let mut squares = Vec::new();
    for (k, line) in lines.iter().enumerate() {
        let y0 = y_um + ((n - 1 - k) * 10) as f64 * pixel_um;
        for (i, c) in line.chars().enumerate() {
            let x0 = x_um + (6 * i) as f64 * pixel_um;
            for (px, py) in pixels(c).unwrap_or_default() {
                let (ax, ay) = (x0 + px as f64 * pixel_um, y0 + py as f64 * pixel_um);
                squares.push(rect(ax, ay, ax + pixel_um, ay + pixel_um));
            }
        }
    }
    union(&squares)
}

/// Upper-cases and replaces characters the font lacks with `-`.
pub fn printable(s: &str) -> String {
    s.to_uppercase()
        .chars()
        .map(|c| {
            if super::font::glyph(c).is_some() {
                c
            } else {
                '-'
            }
        })
        .collect()
}
