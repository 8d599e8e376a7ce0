//! PVDF electrodes: `units` sensing units along x, each with an Al island over support 1 (S1k),
//! over the U-channel (Mk) and over support 2 (S2k). Islands are separated by `gap_um` (in x
//! between units; in y centred on the U-channel's etched {111} wall, between the support's
//! footprint and the channel floor, so both keep the same margin from it) and kept
//! `edge_margin_um` from the film edge. Each island holds a square wire pad at its outer edge (part of the island).
//! `pattern: four_cross` draws paper 000's four islands instead ([`four_cross`]).

use crate::process::{ElectrodePattern, Electrodes};

use super::boolean::{rect, union};
use super::maskset::{Electrode, ElectrodeSide};

/// The etched wall of the U-channel along support 1, across the die (y, um): from the support's
/// footprint edge (the back mask's edge less its undercut) to the channel floor's edge (where the
/// {111} wall meets the plate). Support 2's wall is its mirror about the die's centre line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    pub support_edge_um: f64,
    pub floor_edge_um: f64,
}

impl Wall {
    /// The split between the support and middle islands: the wall's middle.
    pub fn middle_um(self) -> f64 {
        (self.support_edge_um + self.floor_edge_um) / 2.0
    }
}

/// The islands in die (= film) coordinates, named S11.., M1.., S21.. .
pub fn islands(
    e: &Electrodes,
    die_length_um: f64,
    die_width_um: f64,
    wall: Wall,
) -> Vec<Electrode> {
    if e.pattern == ElectrodePattern::FourCross {
        return four_cross(e, die_length_um, die_width_um, wall.floor_edge_um);
    }
    let n = e.units.max(1);
    let m = e.edge_margin_um;
    let g = e.gap_um;
    let unit_w = (die_length_um - 2.0 * m - f64::from(n - 1) * g) / f64::from(n);
    let split = wall.middle_um();
    let rows = [
        (ElectrodeSide::Support1, m, split - g / 2.0),
        (
            ElectrodeSide::Middle,
            split + g / 2.0,
            die_width_um - split - g / 2.0,
        ),
        (
            ElectrodeSide::Support2,
            die_width_um - split + g / 2.0,
            die_width_um - m,
        ),
    ];
    let p = e.wire_pad_um;
    let mut out = Vec::new();
    for &(side, y0, y1) in &rows {
        for k in 0..n {
            let x0 = m + f64::from(k) * (unit_w + g);
            let x1 = x0 + unit_w;
            let xc = (x0 + x1) / 2.0;
            // Outer edge: the film edge for the support rows; for the middle row the x end of the
            // first and last unit, else the edge towards support 1.
            let (px, py) = match side {
                ElectrodeSide::Support1 => (xc - p / 2.0, y0),
                ElectrodeSide::Support2 => (xc - p / 2.0, y1 - p),
                _ if k == 0 && n > 1 => (x0, (y0 + y1) / 2.0 - p / 2.0),
                _ if k == n - 1 && n > 1 => (x1 - p, (y0 + y1) / 2.0 - p / 2.0),
                ElectrodeSide::Middle => (xc - p / 2.0, y0),
            };
            let shapes = union(&[rect(x0, y0, x1, y1), rect(px, py, px + p, py + p)]);
            let prefix = match side {
                ElectrodeSide::Support1 => "S1",
                ElectrodeSide::Middle => "M",
                ElectrodeSide::Support2 => "S2",
            };
            let name = format!("{prefix}{}", k + 1);
            for polygon in shapes {
                out.push(Electrode {
                    name: name.clone(),
                    side,
                    polygon,
                    pad: [px, py, p],
                });
            }
        }
    }
    out
}

/// Four rectangular islands over the plate in a cross about the die centre: A (+x), B (+y),
/// C (-x), D (-y). With s the channel floor's span (between the etched walls, whose feet lie at
/// `floor_edge_um` from the die's long edges): width s / 4, inner end s / 8 + gap from
/// the centre (so neighbouring corners stay `gap_um` apart in x and y), outer end s / 2 - gap (so
/// B and D keep `gap_um` from the etched walls). The wire pad sits at each island's outer end.
pub fn four_cross(
    e: &Electrodes,
    die_length_um: f64,
    die_width_um: f64,
    floor_edge_um: f64,
) -> Vec<Electrode> {
    let (cx, cy) = (die_length_um / 2.0, die_width_um / 2.0);
    let span = die_width_um - 2.0 * floor_edge_um;
    let (half_w, r0, r1) = (span / 8.0, span / 8.0 + e.gap_um, span / 2.0 - e.gap_um);
    let p = e.wire_pad_um;
    // (name, island rectangle, pad lower-left)
    let specs = [
        (
            "A",
            (cx + r0, cy - half_w, cx + r1, cy + half_w),
            (cx + r1 - p, cy - p / 2.0),
        ),
        (
            "B",
            (cx - half_w, cy + r0, cx + half_w, cy + r1),
            (cx - p / 2.0, cy + r1 - p),
        ),
        (
            "C",
            (cx - r1, cy - half_w, cx - r0, cy + half_w),
            (cx - r1, cy - p / 2.0),
        ),
        (
            "D",
            (cx - half_w, cy - r1, cx + half_w, cy - r0),
            (cx - p / 2.0, cy - r1),
        ),
    ];
    let mut out = Vec::new();
    for (name, (x0, y0, x1, y1), (px, py)) in specs {
        for polygon in union(&[rect(x0, y0, x1, y1), rect(px, py, px + p, py + p)]) {
            out.push(Electrode {
                name: name.to_string(),
                side: ElectrodeSide::Middle,
                polygon,
                pad: [px, py, p],
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::process::Axis;
    use geo::{Area, BoundingRect};

    #[test]
    fn four_cross_islands_are_disjoint_symmetric_and_on_the_plate() {
        let e = Electrodes {
            pattern: ElectrodePattern::FourCross,
            units: 1,
            gap_um: 500.0,
            edge_margin_um: 250.0,
            wire_pad_um: 1000.0,
            drawn_axis: Axis::X,
        };
        let v = four_cross(&e, 24_000.0, 22_000.0, 2500.0);
        let names: Vec<&str> = v.iter().map(|i| i.name.as_str()).collect();
        assert_eq!(names, ["A", "B", "C", "D"]);
        let b: Vec<_> = v
            .iter()
            .map(|i| i.polygon.bounding_rect().unwrap())
            .collect();
        // Span 17 mm: 4.25 mm wide, from 2.625 mm to 8 mm off the centre (12, 11) mm.
        assert!((b[0].min().x - 14_625.0).abs() < 1e-9 && (b[0].max().x - 20_000.0).abs() < 1e-9);
        assert!(
            (b[1].max().y - 19_000.0).abs() < 1e-9 && b[1].max().y <= 22_000.0 - 2500.0 - 250.0
        );
        // A and C, B and D mirror about the centre; all four have the same area (pad inside).
        assert!((b[0].min().x + b[2].max().x - 24_000.0).abs() < 1e-9);
        assert!((b[1].min().y + b[3].max().y - 22_000.0).abs() < 1e-9);
        let a0 = v[0].polygon.unsigned_area();
        assert!(
            v.iter()
                .all(|i| (i.polygon.unsigned_area() - a0).abs() < 1e-6)
                && (a0 - 4250.0 * 5375.0).abs() < 1e-6
        );
        // Neighbouring corners (A and B) keep the gap in both x and y.
        assert!(
            b[0].min().x - b[1].max().x >= 500.0 - 1e-9
                && b[1].min().y - b[0].max().y >= 500.0 - 1e-9
        );
    }
}
