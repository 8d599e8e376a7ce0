//! Convex-corner compensation squares for anisotropic etching.

use serde::Serialize;

use crate::process::CompensationGeometry;

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
}
