//! The 3-D slab's face pressure on the die's cells: P0(x, y) and P(x, y) straight from
//! [`crate::softness::slab3d`], so the slab's free edges across the jaw are in the background
//! and a feature off the axis (near the jaw's edge) carries its own 3-D disturbance (instead of
//! [`super::field`]'s P0(x) the same at every y times a rotated d(r)). The slab is centred on
//! the die \[choice\]; no tissue (no pressure) beyond it. A cell's pressure is the mean over a
//! 4 x 4 grid of points in it, as in [`super::field`].

use crate::softness::slab3d::FaceField;

use super::cells::CellGrid;

/// Sub-samples per cell side (as [`super::field`]).
const SUB: usize = 4;

/// The slab's offset on the die (um): die = slab + offset, the slab centred on the die.
pub fn offset_um(face: &FaceField, grid: &CellGrid) -> (f64, f64) {
    let (lx, ly) = (
        face.x_m.last().copied().unwrap_or(0.0) * 1e6,
        face.y_m.last().copied().unwrap_or(0.0) * 1e6,
    );
    (0.5 * (grid.length_um - lx), 0.5 * (grid.width_um - ly))
}

/// Each cell's mean background P0 and extra pressure P - P0 (Pa), die cells of `grid`.
pub fn cells(face: &FaceField, grid: &CellGrid) -> (Vec<f64>, Vec<f64>) {
    let (ox, oy) = offset_um(face, grid);
    let (lx, ly) = (
        face.x_m.last().copied().unwrap_or(0.0),
        face.y_m.last().copied().unwrap_or(0.0),
    );
    let mut p0 = Vec::with_capacity(grid.len());
    let mut dp = Vec::with_capacity(grid.len());
    for k in 0..grid.len() {
        let (x0, y0, x1, y1) = grid.rect(k);
        let (mut a, mut b) = (0.0, 0.0);
        for i in 0..SUB {
            let x = ((x0 + (x1 - x0) * (i as f64 + 0.5) / SUB as f64) - ox) * 1e-6;
            for j in 0..SUB {
                let y = ((y0 + (y1 - y0) * (j as f64 + 0.5) / SUB as f64) - oy) * 1e-6;
                if (0.0..=lx).contains(&x) && (0.0..=ly).contains(&y) {
                    let q0 = face.p0_at_pa(x, y);
                    a += q0;
                    b += face.p_at_pa(x, y) - q0;
                }
            }
        }
        let n = (SUB * SUB) as f64;
        p0.push(a / n);
        dp.push(b / n);
    }
    (p0, dp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::softness::inclusion::{Feature, Slab};
    use crate::softness::slab3d::{face_field, Mesh3d, Slab3d};

    #[test]
    fn a_uniform_squeeze_loads_the_covered_cells_uniformly() {
        // nu = 0: P0 = E delta / H exactly; a 20 x 15 mm slab on a 30 x 15 mm die covers the
        // middle 20 mm: those cells carry P0, the ends nothing, and no feature adds nothing.
        let mut s = Slab3d::from_slab(&Slab::paper_002(Feature::None), 15e-3, 7.5e-3);
        s.length_m = 20e-3;
        s.tissue_nu = 0.0;
        let f = face_field(&s, &Mesh3d::DEFAULT).unwrap();
        let grid = CellGrid {
            nx: 30,
            ny: 15,
            length_um: 30e3,
            width_um: 15e3,
        };
        let (p0, dp) = cells(&f, &grid);
        let want = s.tissue_e_pa * s.compression;
        for k in 0..grid.len() {
            let (x0, _, x1, _) = grid.rect(k);
            let covered = x0 >= 5e3 - 1e-6 && x1 <= 25e3 + 1e-6;
            let expect = if covered {
                want
            } else if x1 <= 5e3 + 1e-6 || x0 >= 25e3 - 1e-6 {
                0.0
            } else {
                p0[k]
            };
            assert!((p0[k] - expect).abs() < 1e-9 * want, "cell {k}: {}", p0[k]);
            assert!(dp[k].abs() < 1e-12 * want);
        }
    }
}
