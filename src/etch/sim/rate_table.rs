//! The orientation-dependent etch rate R(n): a table over the main planes, interpolated over the
//! surface normal.
//!
//! The interpolation follows ViennaPS's `WetEtchingVelocityField`
//! (`include/viennaps/models/psWetEtching.hpp`): the normal's absolute crystal components are
//! sorted, N0 >= N1 >= N2, and R is piecewise linear in the central (gnomonic) projection
//! (u, w) = (N1 / N0, N2 / N0) of the fundamental triangle {100}-{110}-{111}. ViennaPS splits the
//! triangle at the {110}-{311} line; here the {h11} planes of the table lie on the triangle's
//! {100}-{111} edge at u = w = 1/h and the triangle is fanned from {110} to consecutive ones, so
//! with {100}, {110}, {111}, {311} the two interpolations are the same (tested), and {411} adds
//! one more fan triangle.

use serde::Serialize;

/// Etch rates of the main planes (um/h). {311} and {411} are optional: without them R is
/// interpolated along the {100}-{111} edge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RateTable {
    pub r100_um_per_h: f64,
    pub r110_um_per_h: f64,
    pub r111_um_per_h: f64,
    pub r311_um_per_h: Option<f64>,
    pub r411_um_per_h: Option<f64>,
}

/// A [`RateTable`] ready to evaluate: the {h11} edge points sorted by u = 1 / h.
#[derive(Debug, Clone)]
pub struct RateModel {
    table: RateTable,
    /// (u, R) on the {100}-{111} edge, u ascending from 0 ({100}) to 1 ({111}).
    edge: Vec<(f64, f64)>,
}

impl RateModel {
    /// Panics (programmer error) on a non-finite or negative rate: the process validator
    /// guarantees positive rates.
    #[track_caller]
    pub fn new(table: RateTable) -> Self {
        let mut edge = vec![(0.0, table.r100_um_per_h)];
        if let Some(r) = table.r411_um_per_h {
            edge.push((0.25, r));
        }
        if let Some(r) = table.r311_um_per_h {
            edge.push((1.0 / 3.0, r));
        }
        edge.push((1.0, table.r111_um_per_h));
        for &(_, r) in edge.iter().chain([(0.0, table.r110_um_per_h)].iter()) {
            assert!(r.is_finite() && r >= 0.0, "etch rate {r} is not >= 0");
        }
        RateModel { table, edge }
    }

    /// The table this model interpolates.
    pub fn table(&self) -> &RateTable {
        &self.table
    }

    /// R for a normal in crystal axes (any length > 0; only its direction matters).
    pub fn rate_crystal(&self, n: [f64; 3]) -> f64 {
        let mut a = [n[0].abs(), n[1].abs(), n[2].abs()];
        // Sort descending (three compares).
        if a[0] < a[1] {
            a.swap(0, 1);
        }
        if a[1] < a[2] {
            a.swap(1, 2);
        }
        if a[0] < a[1] {
            a.swap(0, 1);
        }
        if a[0] <= 0.0 {
            return self.table.r100_um_per_h;
        }
        let (u, w) = (a[1] / a[0], a[2] / a[0]);
        // The line from {110} = (1, 0) through (u, w) meets the edge u = w at t; the point is
        // {110} + s (edge point - {110}) with s = 1 - u + w.
        let s = 1.0 - u + w;
        let r110 = self.table.r110_um_per_h;
        if s <= 1e-15 {
            return r110;
        }
        let t = w / s;
        r110 + s * (self.edge_rate(t) - r110)
    }

    /// R for a normal in the wafer frame of a (100) wafer with die edges along <110>: x along
    /// \[110\], y along \[-110\], z along \[001\] (out of the wafer).
    pub fn rate_wafer(&self, v: [f64; 3]) -> f64 {
        const S: f64 = std::f64::consts::FRAC_1_SQRT_2;
        self.rate_crystal([S * (v[0] - v[1]), S * (v[0] + v[1]), v[2]])
    }

    /// Linear interpolation along the {100}-{111} edge at u = w = t.
    fn edge_rate(&self, t: f64) -> f64 {
        let e = &self.edge;
        let k = e.partition_point(|&(u, _)| u <= t).clamp(1, e.len() - 1);
        let ((u0, r0), (u1, r1)) = (e[k - 1], e[k]);
        r0 + (r1 - r0) * (t - u0) / (u1 - u0)
    }

    /// The largest rate in the table.
    pub fn max_rate_um_per_h(&self) -> f64 {
        self.edge
            .iter()
            .map(|e| e.1)
            .fold(self.table.r110_um_per_h, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sato() -> RateTable {
        // Sato et al. 1998, 30 % KOH 70 C, um/min (reference/process-physics.md).
        RateTable {
            r100_um_per_h: 0.797,
            r110_um_per_h: 1.455,
            r111_um_per_h: 0.005,
            r311_um_per_h: Some(1.436),
            r411_um_per_h: None,
        }
    }

    /// ViennaPS's formula, written out independently (psWetEtching.hpp).
    fn viennaps(t: &RateTable, n: [f64; 3]) -> f64 {
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let mut a = [n[0].abs() / l, n[1].abs() / l, n[2].abs() / l];
        a.sort_by(|x, y| y.total_cmp(x));
        let r311 = t.r311_um_per_h.unwrap();
        if -a[0] + a[1] + 2.0 * a[2] < 0.0 {
            (t.r100_um_per_h * (a[0] - a[1] - 2.0 * a[2])
                + t.r110_um_per_h * (a[1] - a[2])
                + 3.0 * r311 * a[2])
                / a[0]
        } else {
            (t.r111_um_per_h * ((a[1] - a[0]) * 0.5 + a[2])
                + t.r110_um_per_h * (a[1] - a[2])
                + 1.5 * r311 * (a[0] - a[1]))
                / a[0]
        }
    }

    #[test]
    fn table_planes_are_reproduced() {
        let m = RateModel::new(sato());
        let cases = [
            ([1.0, 0.0, 0.0], 0.797),
            ([0.0, -1.0, 0.0], 0.797),
            ([1.0, 1.0, 0.0], 1.455),
            ([0.0, 1.0, -1.0], 1.455),
            ([1.0, 1.0, 1.0], 0.005),
            ([-1.0, 1.0, -1.0], 0.005),
            ([3.0, 1.0, 1.0], 1.436),
            ([1.0, -1.0, 3.0], 1.436),
        ];
        for (n, r) in cases {
            assert!((m.rate_crystal(n) - r).abs() < 1e-12, "{n:?}");
        }
        // Wafer frame: (001) is the wafer normal, x = [110] is a vertical {110} wall.
        assert!((m.rate_wafer([0.0, 0.0, 1.0]) - 0.797).abs() < 1e-12);
        assert!((m.rate_wafer([1.0, 0.0, 0.0]) - 1.455).abs() < 1e-12);
        // The {111} sidewall of a <110> edge: tilted 54.74 deg about x.
        let s = 2f64.sqrt();
        assert!((m.rate_wafer([0.0, s, 1.0]) - 0.005).abs() < 1e-12);
    }

    #[test]
    fn matches_viennaps_interpolation() {
        let t = sato();
        let m = RateModel::new(t);
        // A deterministic spread of directions over the sphere.
        let mut worst = 0.0f64;
        for i in 0..40 {
            for j in 0..80 {
                let th = std::f64::consts::PI * (i as f64 + 0.5) / 40.0;
                let ph = 2.0 * std::f64::consts::PI * (j as f64 + 0.3) / 80.0;
                let n = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
                worst = worst.max((m.rate_crystal(n) - viennaps(&t, n)).abs());
            }
        }
        assert!(worst < 1e-12, "{worst}");
    }

    #[test]
    fn r411_adds_a_vertex_and_is_continuous() {
        let t = RateTable {
            r411_um_per_h: Some(2.0),
            ..sato()
        };
        let m = RateModel::new(t);
        assert!((m.rate_crystal([4.0, 1.0, 1.0]) - 2.0).abs() < 1e-12);
        // Continuity across the {110}-{411} fan line: approach from both sides.
        let e = 1e-7;
        let a = m.rate_crystal([4.0, 1.0 + e, 1.0 - e]);
        let b = m.rate_crystal([4.0, 1.0 + e, 1.0 + e]);
        assert!((a - b).abs() < 1e-5, "{a} {b}");
        // Away from the new vertex's fan the table without {411} is unchanged.
        let m0 = RateModel::new(sato());
        let n = [1.0, 0.9, 0.7];
        assert!((m.rate_crystal(n) - m0.rate_crystal(n)).abs() < 1e-12);
    }
}
