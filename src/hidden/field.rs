//! The slab's pressure on the die face. The slab of [`crate::softness::inclusion`] is a 2-D
//! section (plane strain) along the jaw; the face is 2-D in plan. The map \[choice\]:
//!
//! - background: the featureless slab's P0(x) along the jaw, the slab centred on the die, the
//!   same at every y across it (the tissue covers the face; its own free edges across the jaw
//!   are not modelled);
//! - feature: its disturbance d(s) = P / P0 - 1 at distance s from it along the face, times the
//!   local background: dP(x, y) = P0(x) d(r). A sphere ([`Shape::Sphere`], the default) takes d
//!   from the 3-D scene by axisymmetry: the sphere on the axis of a tissue cylinder between the
//!   jaws ([`crate::softness::axislab`], its radius half the slab's width, elements of the
//!   section's size near the sphere, their edges on it; P0 on the same mesh), r the distance in
//!   plan. A cylinder lying across the jaw (the plane-strain
//!   disc itself) has r = |x - x_c| at every y. [`Shape::RotatedSection`] is the older
//!   approximation of a sphere: the plane section's d rotated about the centre (a void disturbs
//!   far more as a cylinder than as a sphere: 0.31 against 0.55 at the minimum).
//!
//! A cell's pressure is the mean over a 4 x 4 grid of points in it: the cells are the field's
//! discretisation, the plate's unit responses ([`super::cells`]) are exact for it.

use serde::Serialize;

use crate::softness::axislab::sphere_profile;
use crate::softness::inclusion::{face_pressure_pa, Feature, Slab};

/// Elements across the tissue cylinder's radius for `nx` along the slab: the same size.
fn axi_elements(nx: usize) -> usize {
    (nx / 2).max(1)
}

use super::cells::CellGrid;
use super::HiddenError;

/// Sub-samples per cell side.
const SUB: usize = 4;

/// How the slab's section becomes a feature in plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// A sphere: d(r) from the axisymmetric cylinder of tissue with the sphere on its axis.
    Sphere,
    /// The plane section's disturbance rotated about the centre (the approximation of a sphere
    /// before the axisymmetric scene; kept to compare).
    RotatedSection,
    /// A cylinder lying across the jaw (along y): the section's disturbance at every y.
    Cylinder,
}

/// Linear interpolation in increasing `xs`; `outside` beyond the ends.
fn interp(xs: &[f64], ys: &[f64], x: f64, outside: f64) -> f64 {
    let n = xs.len();
    if n == 0 || x < xs[0] || x > xs[n - 1] || x.is_nan() {
        return outside;
    }
    let i = xs.partition_point(|&v| v <= x).clamp(1, n - 1);
    let (x0, x1) = (xs[i - 1], xs[i]);
    let t = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[i - 1] + t * (ys[i] - ys[i - 1])
}

/// The featureless grasp along the jaw.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Background {
    /// The slab (its feature ignored) and its mesh.
    pub slab: Slab,
    pub elements: (usize, usize),
    /// Face nodes in die coordinates (the slab centred on the die) and P0 there.
    pub x_um: Vec<f64>,
    pub p0_pa: Vec<f64>,
}

impl Background {
    /// Solves the featureless `slab` on `nx` x `ny` Q2/P1 elements and centres it on a die of
    /// length `die_length_um`.
    pub fn new(slab: &Slab, nx: usize, ny: usize, die_length_um: f64) -> Result<Self, HiddenError> {
        let plain = Slab {
            feature: Feature::None,
            ..*slab
        };
        let p0_pa = face_pressure_pa(&plain, nx, ny)?;
        let shift = 0.5 * (die_length_um - slab.width_m * 1e6);
        let x_um = (0..=2 * nx)
            .map(|i| shift + slab.width_m * 1e6 * i as f64 / (2 * nx) as f64)
            .collect();
        Ok(Background {
            slab: plain,
            elements: (nx, ny),
            x_um,
            p0_pa,
        })
    }

    /// P0 at x (um, die coordinates); no tissue beyond the slab.
    pub fn at(&self, x_um: f64) -> f64 {
        interp(&self.x_um, &self.p0_pa, x_um, 0.0)
    }

    /// The background's mean pressure on each cell (Pa).
    pub fn cells(&self, grid: &CellGrid) -> Vec<f64> {
        (0..grid.len())
            .map(|k| {
                let (x0, _, x1, _) = grid.rect(k);
                (0..SUB)
                    .map(|a| self.at(x0 + (x1 - x0) * (a as f64 + 0.5) / SUB as f64))
                    .sum::<f64>()
                    / SUB as f64
            })
            .collect()
    }
}

/// A feature's disturbance of the background, d(s) = P / P0 - 1.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Disturbance {
    pub feature: Feature,
    pub shape: Shape,
    pub radius_m: f64,
    /// Height of the disc's centre above the sensor face.
    pub height_m: f64,
    /// Distance from the centre along the face (um) and d there.
    pub s_um: Vec<f64>,
    pub d: Vec<f64>,
    /// The largest and smallest P / P0 of the section.
    pub peak_ratio: f64,
    pub min_ratio: f64,
}

impl Disturbance {
    /// The disc of `radius_m` at `height_m` in the middle of the background's slab (same mesh).
    pub fn new(
        bg: &Background,
        feature: Feature,
        radius_m: f64,
        height_m: f64,
        shape: Shape,
    ) -> Result<Self, HiddenError> {
        let slab = Slab {
            feature,
            radius_m,
            centre_height_m: height_m,
            centre_x_m: 0.5 * bg.slab.width_m,
            ..bg.slab
        };
        let (nx, ny) = bg.elements;
        let ratio = |a: &f64, b: &f64| if *b > 0.0 { a / b - 1.0 } else { 0.0 };
        let (s_um, d): (Vec<f64>, Vec<f64>) = if shape == Shape::Sphere {
            // The sphere's own P0 on its own mesh (which follows the sphere).
            let p = sphere_profile(&slab, axi_elements(nx), ny)?;
            let d = p
                .p_pa
                .iter()
                .zip(&p.p0_pa)
                .map(|(a, b)| ratio(a, b))
                .collect();
            (p.r_m.iter().map(|r| r * 1e6).collect(), d)
        } else {
            let p = face_pressure_pa(&slab, nx, ny)?;
            // The right half from the centre node (the section is mirror-symmetric about it).
            let d = p[nx..]
                .iter()
                .zip(&bg.p0_pa[nx..])
                .map(|(a, b)| ratio(a, b))
                .collect();
            (bg.x_um[nx..].iter().map(|x| x - bg.x_um[nx]).collect(), d)
        };
        let (peak, low) = d
            .iter()
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(a, b), &v| {
                (a.max(1.0 + v), b.min(1.0 + v))
            });
        Ok(Disturbance {
            feature,
            shape,
            radius_m,
            height_m,
            s_um,
            d,
            peak_ratio: peak,
            min_ratio: low,
        })
    }

    /// d at distance `s_um` from the centre; none beyond the slab's half-length.
    pub fn at(&self, s_um: f64) -> f64 {
        interp(&self.s_um, &self.d, s_um.abs(), 0.0)
    }

    /// The extra pressure dP = P0(x) d(r) on each cell (Pa) with the feature's centre at
    /// `centre_um` (x along the jaw, y across, die coordinates).
    pub fn cells(&self, bg: &Background, grid: &CellGrid, centre_um: (f64, f64)) -> Vec<f64> {
        let reach = self.s_um.last().copied().unwrap_or(0.0);
        (0..grid.len())
            .map(|k| {
                let (x0, y0, x1, y1) = grid.rect(k);
                // Nothing reaches a cell wholly beyond the disturbance.
                let dx = (x0 - centre_um.0).max(centre_um.0 - x1).max(0.0);
                let dy = (y0 - centre_um.1).max(centre_um.1 - y1).max(0.0);
                let far = match self.shape {
                    Shape::Sphere | Shape::RotatedSection => dx.hypot(dy),
                    Shape::Cylinder => dx,
                };
                if far > reach {
                    return 0.0;
                }
                let mut sum = 0.0;
                for a in 0..SUB {
                    let x = x0 + (x1 - x0) * (a as f64 + 0.5) / SUB as f64;
                    let p0 = bg.at(x);
                    for b in 0..SUB {
                        let y = y0 + (y1 - y0) * (b as f64 + 0.5) / SUB as f64;
                        let r = match self.shape {
                            Shape::Sphere | Shape::RotatedSection => {
                                (x - centre_um.0).hypot(y - centre_um.1)
                            }
                            Shape::Cylinder => x - centre_um.0,
                        };
                        sum += p0 * self.at(r);
                    }
                }
                sum / (SUB * SUB) as f64
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_and_zero_outside() {
        let xs = [0.0, 1.0, 3.0];
        let ys = [2.0, 4.0, 0.0];
        assert_eq!(interp(&xs, &ys, 0.5, 9.0), 3.0);
        assert_eq!(interp(&xs, &ys, 2.0, 9.0), 2.0);
        assert_eq!(interp(&xs, &ys, 3.0, 9.0), 0.0);
        assert_eq!(interp(&xs, &ys, 3.5, 9.0), 9.0);
        assert_eq!(interp(&xs, &ys, f64::NAN, 9.0), 9.0);
    }
}
