//! Front silicon: square tooth tops on the cell grid, each with a compensator (a square or a
//! <110> bar) at its four convex corners, merged per tooth into one polygon (the tooth cell).

use geo::Polygon;

use crate::etch::CompensationDesign;
use crate::process::{CompensationGeometry, Teeth, TeethPattern};

use super::boolean::{rect, union};
use super::maskset::Tooth;

/// Cells that carry a tooth: checkered = even i + j, matrix = all, none = no cell.
pub fn has_tooth(pattern: TeethPattern, i: u32, j: u32) -> bool {
    match pattern {
        TeethPattern::Checkered => (i + j).is_multiple_of(2),
        TeethPattern::Matrix => true,
        TeethPattern::None => false,
    }
}

/// Tooth instances: the top is centred in its cell.
pub fn teeth(t: &Teeth) -> Vec<Tooth> {
    let mut out = Vec::new();
    for j in 0..t.count_y {
        for i in 0..t.count_x {
            if has_tooth(t.pattern, i, j) {
                out.push(Tooth {
                    i,
                    j,
                    x_um: t.origin_x_um
                        + f64::from(i) * t.pitch_x_um
                        + (t.pitch_x_um - t.top_um) / 2.0,
                    y_um: t.origin_y_um
                        + f64::from(j) * t.pitch_y_um
                        + (t.pitch_y_um - t.top_um) / 2.0,
                });
            }
        }
    }
    out
}

/// The compensators of a tooth whose top is [0, top]^2.
///
/// Corner-attached: the square shares the corner and extends diagonally outwards; it is pulled
/// `overlap_um` into the tooth so tooth and square form one simple polygon (a single shared
/// vertex would be a self-touching ring). Centred: side from the plan, centred on the corner.
/// <110> bar: L = `side_um` long along x beyond the corner, b wide, its outer edge on the
/// tooth's edge (mirrored about the tooth's centre lines), pulled `overlap_um` into the tooth
/// along x so the union does not rest on a shared edge alone.
pub fn compensators(top_um: f64, c: &CompensationDesign, overlap_um: f64) -> Vec<Polygon> {
    let mut out = Vec::new();
    for (cx, cy, sx, sy) in [
        (0.0, 0.0, -1.0, -1.0),
        (top_um, 0.0, 1.0, -1.0),
        (top_um, top_um, 1.0, 1.0),
        (0.0, top_um, -1.0, 1.0),
    ] {
        let sq = match c.kind {
            CompensationGeometry::CornerAttached => {
                let (x0, y0) = (cx - sx * overlap_um, cy - sy * overlap_um);
                rect(x0, y0, x0 + sx * c.side_um, y0 + sy * c.side_um)
            }
            CompensationGeometry::Centred => {
                let h = c.side_um / 2.0;
                rect(cx - h, cy - h, cx + h, cy + h)
            }
            CompensationGeometry::Bar110 => {
                let b = c.bar_width_um.expect("a bar design carries its width");
                rect(cx - sx * overlap_um, cy, cx + sx * c.side_um, cy - sy * b)
            }
        };
        out.push(sq);
    }
    out
}

/// The tooth cell: top plus compensators, merged; tooth lower-left corner at (0, 0).
pub fn tooth_cell(top_um: f64, comp: Option<&CompensationDesign>, overlap_um: f64) -> Vec<Polygon> {
    let mut shapes = vec![rect(0.0, 0.0, top_um, top_um)];
    if let Some(c) = comp {
        shapes.extend(compensators(top_um, c, overlap_um));
    }
    union(&shapes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::etch::compensation_design;
    use geo::Area;

    #[test]
    fn corner_attached_tooth_is_one_polygon_of_the_expected_area() {
        let c = compensation_design(200.0, 0.544, CompensationGeometry::CornerAttached, None);
        let t = tooth_cell(2000.0, Some(&c), 10.0);
        assert_eq!(t.len(), 1);
        let a = c.side_um;
        let expected = 2000.0 * 2000.0 + 4.0 * (a * a - 100.0);
        assert!(
            (t[0].unsigned_area() - expected).abs() < 1.0,
            "{} vs {expected}",
            t[0].unsigned_area()
        );
    }

    /// One polygon; area s^2 + 4 L b; the plain top lies inside (XOR of the union with the
    /// compensated tooth is zero) and the part outside the top is the four bars exactly.
    #[test]
    fn bar_tooth_is_one_polygon_of_the_expected_area() {
        use crate::layout::boolean::{rect, union, xor_area_um2};
        let (l, b) = (367.647, 50.0);
        let c = compensation_design(200.0, 200.0 / l, CompensationGeometry::Bar110, Some(b));
        let t = tooth_cell(2000.0, Some(&c), 10.0);
        assert_eq!(t.len(), 1);
        let expected = 2000.0 * 2000.0 + 4.0 * l * b;
        assert!(
            (t[0].unsigned_area() - expected).abs() < 1e-3,
            "{} vs {expected}",
            t[0].unsigned_area()
        );
        let bars = [
            rect(2000.0, 2000.0 - b, 2000.0 + l, 2000.0),
            rect(2000.0, 0.0, 2000.0 + l, b),
            rect(-l, 0.0, 0.0, b),
            rect(-l, 2000.0 - b, 0.0, 2000.0),
        ];
        let mut drawn = vec![rect(0.0, 0.0, 2000.0, 2000.0)];
        drawn.extend(bars);
        assert!(xor_area_um2(&union(&drawn), &t) < 1e-6);
    }

    #[test]
    fn checkered_count() {
        let t = Teeth {
            pattern: TeethPattern::Checkered,
            height_um: 200.0,
            top_um: 2000.0,
            pitch_x_um: 3000.0,
            pitch_y_um: 3000.0,
            count_x: 10,
            count_y: 5,
            origin_x_um: 0.0,
            origin_y_um: 0.0,
        };
        assert_eq!(teeth(&t).len(), 25);
        assert_eq!(
            teeth(&Teeth {
                pattern: TeethPattern::Matrix,
                ..t.clone()
            })
            .len(),
            50
        );
        assert_eq!(
            teeth(&Teeth {
                pattern: TeethPattern::None,
                ..t
            })
            .len(),
            0
        );
    }
}
