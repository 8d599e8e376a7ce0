//! PVDF electrodes: `units` sensing units along x, each with an Al island over support 1 (S1k),
//! over the U-channel (Mk) and over support 2 (S2k). Islands are separated by `gap_um` (in x
//! between units; in y centred on the support edges) and kept `edge_margin_um` from the film
//! edge. Each island holds a square wire pad at its outer edge (part of the island).

use crate::process::Electrodes;

use super::boolean::{rect, union};
use super::maskset::Electrode;

/// The islands in die (= film) coordinates, named S11.., M1.., S21.. .
pub fn islands(e: &Electrodes, die_length_um: f64, die_width_um: f64, support_width_um: f64) -> Vec<Electrode> {
    let n = e.units.max(1);
    let m = e.edge_margin_um;
    let g = e.gap_um;
    let unit_w = (die_length_um - 2.0 * m - f64::from(n - 1) * g) / f64::from(n);
    let rows = [
        ("S1", m, support_width_um - g / 2.0),
        ("M", support_width_um + g / 2.0, die_width_um - support_width_um - g / 2.0),
        ("S2", die_width_um - support_width_um + g / 2.0, die_width_um - m),
    ];
    let p = e.wire_pad_um;
    let mut out = Vec::new();
    for (row, (prefix, y0, y1)) in rows.iter().enumerate() {
        for k in 0..n {
            let x0 = m + f64::from(k) * (unit_w + g);
            let x1 = x0 + unit_w;
            let xc = (x0 + x1) / 2.0;
            // Outer edge: the film edge for the support rows; for the middle row the x end of the
            // first and last unit, else the edge towards support 1.
            let (px, py) = match row {
                0 => (xc - p / 2.0, *y0),
                2 => (xc - p / 2.0, y1 - p),
                _ if k == 0 && n > 1 => (x0, (y0 + y1) / 2.0 - p / 2.0),
                _ if k == n - 1 && n > 1 => (x1 - p, (y0 + y1) / 2.0 - p / 2.0),
                _ => (xc - p / 2.0, *y0),
            };
            let shapes = union(&[rect(x0, *y0, x1, *y1), rect(px, py, px + p, py + p)]);
            let name = if *prefix == "M" { format!("M{}", k + 1) } else { format!("{prefix}{}", k + 1) };
            for polygon in shapes {
                out.push(Electrode { name: name.clone(), polygon, pad: [px, py, p] });
            }
        }
    }
    out
}
