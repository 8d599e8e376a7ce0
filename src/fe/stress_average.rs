//! The largest principal stress averaged over a small square: the stress a Kirchhoff plate can
//! answer for near a thickness step or a point-like load.
//!
//! Plate theory describes the stress field only at distances of about a thickness from a
//! discontinuity (Saint-Venant); at a re-entrant corner of a stepped plate the point stress of
//! the plate model is singular (Williams 1952, J. Appl. Mech. 19: sigma ~ r^(lambda - 1) with
//! lambda < 1), so its peak grows without bound as the mesh is refined. Its average over a square
//! of side about a thickness is finite and converges, and is what the safety factor is judged on.

use crate::fe::problem::RectUm;
use crate::fe::solution::{PlateSolution, StressPeak, Surface};

/// Candidate centres taken from the point samples before the local search.
const CANDIDATES: usize = 4;

/// 2-point Gauss-Legendre rule mapped to [lo, hi] (exact for cubics).
fn gauss2_on(lo: f64, hi: f64) -> [(f64, f64); 2] {
    let (h, m) = (0.5 * (hi - lo), 0.5 * (hi + lo));
    let d = h / 3f64.sqrt();
    [(m - d, h), (m + d, h)]
}

/// Largest principal of a plane stress tensor (sx, sy, txy).
fn principal(s: [f64; 3]) -> f64 {
    0.5 * (s[0] + s[1]) + (0.25 * (s[0] - s[1]).powi(2) + s[2] * s[2]).sqrt()
}

impl PlateSolution {
    /// Mean stress tensors [bottom, top] over the square of side `side_um` centred at (x, y),
    /// clipped to the plate, by 2x2 Gauss per element part: exact for the BFS curvatures (degree
    /// <= 3 in each direction), approximate for the membrane strain's w_x^2 / 2.
    fn mean_stress(&self, x_um: f64, y_um: f64, side_um: f64) -> Option<[[f64; 3]; 2]> {
        let h = 0.5 * side_um;
        let sq = RectUm {
            x0_um: x_um - h,
            y0_um: y_um - h,
            x1_um: x_um + h,
            y1_um: y_um + h,
        };
        let mut sum = [[0.0; 3]; 2];
        let mut area = 0.0;
        for (e, x0, x1, y0, y1) in self.clipped(&sq) {
            for (x, wx) in gauss2_on(x0, x1) {
                for (y, wy) in gauss2_on(y0, y1) {
                    let s = self.surface_stresses(e, x, y);
                    for f in 0..2 {
                        for c in 0..3 {
                            sum[f][c] += wx * wy * s[f][c];
                        }
                    }
                    area += wx * wy;
                }
            }
        }
        (area > 0.0).then(|| sum.map(|t| t.map(|v| v / area)))
    }

    /// The largest principal stress averaged over a square of side `side_um` whose centre lies in
    /// `rect` (either surface). The search does not depend on the mesh, so the value converges
    /// with it: centres on a grid of about `side_um` over `rect`, then from the
    /// four best a pattern search (steps side/2 down to side/8). None when `rect`
    /// misses the plate.
    pub fn averaged_principal_stress(&self, rect: RectUm, side_um: f64) -> Option<StressPeak> {
        let r = rect.normalised();
        let value = |x: f64, y: f64| -> Option<StressPeak> {
            let s = self.mean_stress(x, y, side_um)?;
            let (b, t) = (principal(s[0]), principal(s[1]));
            Some(StressPeak {
                x_um: x,
                y_um: y,
                sigma_pa: b.max(t),
                surface: if b >= t {
                    Surface::Bottom
                } else {
                    Surface::Top
                },
            })
        };
        let cells = |len: f64| ((len / side_um).ceil() as usize).clamp(1, 4096);
        let (nx, ny) = (cells(r.x1_um - r.x0_um), cells(r.y1_um - r.y0_um));
        let mut grid: Vec<StressPeak> = Vec::with_capacity(nx * ny);
        for i in 0..nx {
            for j in 0..ny {
                let x = r.x0_um + (r.x1_um - r.x0_um) * (i as f64 + 0.5) / nx as f64;
                let y = r.y0_um + (r.y1_um - r.y0_um) * (j as f64 + 0.5) / ny as f64;
                grid.extend(value(x, y));
            }
        }
        grid.sort_by(|a, b| b.sigma_pa.total_cmp(&a.sigma_pa));
        let mut best: Option<StressPeak> = None;
        for start in grid.into_iter().take(CANDIDATES) {
            let mut at = start;
            let mut step = 0.5 * side_um;
            let mut moves = 0;
            while step >= side_um / 8.0 && moves < 64 {
                moves += 1;
                let better = [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0)]
                    .into_iter()
                    .chain([(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)])
                    .filter_map(|(dx, dy): (f64, f64)| {
                        let x = (at.x_um + dx * step).clamp(r.x0_um, r.x1_um);
                        let y = (at.y_um + dy * step).clamp(r.y0_um, r.y1_um);
                        value(x, y)
                    })
                    .filter(|p| p.sigma_pa > at.sigma_pa)
                    .max_by(|a, b| a.sigma_pa.total_cmp(&b.sigma_pa));
                match better {
                    Some(p) => at = p,
                    None => step *= 0.5,
                }
            }
            if best.is_none_or(|b| at.sigma_pa > b.sigma_pa) {
                best = Some(at);
            }
        }
        best
    }
}
