//! Convex-corner compensation squares for anisotropic etching.

use serde::Serialize;

use crate::process::{CompensationGeometry, Geometry, TeethPattern};

/// The compensation design for one etch depth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CompensationDesign {
    /// `corner_attached` or `centred`.
    pub kind: CompensationGeometry,
    /// Side of the square drawn on the mask.
    pub side_um: f64,
    /// The ratio in a = h / ratio.
    pub ratio: f64,
    /// Smallest street between two facing compensated corners before the squares touch.
    pub min_gap_um: f64,
    /// How far the square reaches beyond the corner along x and along y.
    pub reach_um: f64,
}

/// a = h / ratio (paper 002 sec. VI.A, after the KOH work of its ref. \[33\]); a square centred on
/// the corner needs side sqrt 2 a to reach as far along the diagonal (process-physics.md).
///
/// Facing corners across a street of width g: corner-attached squares reach a into the street
/// from each side, so they meet at g = 2a; centred squares of side s reach s/2 each, meeting at
/// g = s = sqrt 2 a. (process-physics.md lists `>= a` for the centred case; the geometry of a
/// square centred on the corner gives sqrt 2 a, which we use as the stricter value.)
pub fn design(depth_um: f64, ratio: f64, kind: CompensationGeometry) -> CompensationDesign {
    let a = depth_um / ratio;
    let (side_um, reach_um) = match kind {
        CompensationGeometry::CornerAttached => (a, a),
        CompensationGeometry::Centred => (2f64.sqrt() * a, 2f64.sqrt() * a / 2.0),
    };
    CompensationDesign {
        kind,
        side_um,
        ratio,
        min_gap_um: 2.0 * reach_um,
        reach_um,
    }
}

/// How far a compensator of size a (a = h / ratio) reaches beyond its corner along x and y:
/// a corner-attached, sqrt 2 a / 2 centred ([`design`]).
pub fn reach_per_a(kind: CompensationGeometry) -> f64 {
    match kind {
        CompensationGeometry::CornerAttached => 1.0,
        CompensationGeometry::Centred => std::f64::consts::FRAC_1_SQRT_2,
    }
}

/// The largest compensator a of `kind` the teeth of `g` can carry, and what limits it: facing
/// compensators must stay `min_space_um` apart (the DRC's COMPENSATORS_COLLIDE: across the
/// street for a matrix, corner to corner diagonally for a checkered pattern, whose orthogonal
/// neighbour cells are empty) and the outer teeth's must stay on the die
/// (COMPENSATOR_OUTSIDE_DIE). Matches the plan's checks: a compensator of this a passes both.
pub fn largest_a_um(
    g: &Geometry,
    kind: CompensationGeometry,
    min_space_um: f64,
) -> (f64, &'static str) {
    let t = &g.teeth;
    let (gx, gy) = (t.pitch_x_um - t.top_um, t.pitch_y_um - t.top_um);
    // Largest reach r between facing compensators.
    let street = match t.pattern {
        TeethPattern::Matrix => 0.5 * (gx.min(gy) - min_space_um),
        _ => {
            // Diagonal neighbours: the squares' facing corners are (gx - 2r, gy - 2r) apart;
            // the distance falls monotonically in r, so bisect for min_space.
            let dist = |r: f64| (gx - 2.0 * r).max(0.0).hypot((gy - 2.0 * r).max(0.0));
            let (mut lo, mut hi) = (0.0, 0.5 * gx.max(gy));
            if dist(lo) < min_space_um {
                hi = 0.0;
            }
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if dist(mid) >= min_space_um {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        }
    };
    // Outer teeth: reach within the die on every side.
    let inset_x = t.origin_x_um + (t.pitch_x_um - t.top_um) / 2.0;
    let inset_y = t.origin_y_um + (t.pitch_y_um - t.top_um) / 2.0;
    let end_x = g.die_length_um
        - (t.origin_x_um + f64::from(t.count_x) * t.pitch_x_um - (t.pitch_x_um - t.top_um) / 2.0);
    let end_y = g.die_width_um
        - (t.origin_y_um + f64::from(t.count_y) * t.pitch_y_um - (t.pitch_y_um - t.top_um) / 2.0);
    let die = inset_x.min(inset_y).min(end_x).min(end_y);
    let (r, why) = if street <= die {
        (street, "facing compensators min_space apart")
    } else {
        (die, "outer teeth's compensators on the die")
    };
    (r.max(0.0) / reach_per_a(kind), why)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_values() {
        let c = design(200.0, 0.544, CompensationGeometry::CornerAttached);
        assert!((c.side_um - 367.647).abs() < 1e-3);
        assert!((c.min_gap_um - 735.294).abs() < 1e-3);
        let z = design(200.0, 0.544, CompensationGeometry::Centred);
        assert!((z.side_um - 519.93).abs() < 0.01);
        assert!((z.min_gap_um - z.side_um).abs() < 1e-9);
    }

    #[test]
    fn largest_a_fits_the_street_and_no_more() {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
        let mut g = crate::process::load_str(&text, "mis-grasper.yaml", &[])
            .unwrap()
            .process
            .geometry;
        let t = &mut g.teeth;
        (t.top_um, t.pitch_x_um, t.pitch_y_um) = (2000.0, 3000.0, 3000.0);
        (t.origin_x_um, t.origin_y_um) = (0.0, 0.0);
        (g.die_length_um, g.die_width_um) = (1e5, 1e5);
        g.teeth.pattern = TeethPattern::Checkered;
        // Diagonal corners sqrt 2 (1000 - 2a) apart = 10 um.
        let (a, why) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!(
            (a - (1000.0 - 10.0 / 2f64.sqrt()) / 2.0).abs() < 1e-9,
            "{a} {why}"
        );
        let (c, _) = largest_a_um(&g, CompensationGeometry::Centred, 10.0);
        assert!((c - 2f64.sqrt() * a).abs() < 1e-9);
        // The plan's collision rule passes at the limit (min gap 2 reach <= street).
        let d = design(200.0, 200.0 / a, CompensationGeometry::CornerAttached);
        assert!(d.min_gap_um <= 1000.0);
        g.teeth.pattern = TeethPattern::Matrix;
        let (m, _) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!((m - 495.0).abs() < 1e-9);
        // A die edge 300 um beyond the outer tooth tops limits the reach to 300.
        (g.die_length_um, g.die_width_um) = (10.0 * 3000.0 - 200.0, 1e5);
        g.teeth.count_x = 10;
        let (e, why) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!((e - 300.0).abs() < 1e-9 && why.contains("die"), "{e} {why}");
    }
}
