//! The supports as an elastic section for the plate rungs (issue 16, item 5): one support's
//! cross-section across the wall, solved as a plane-strain solid (the solid rung's bricks, one
//! element along the wall, u_x held), gives the edge stiffness the plate feels at its clamp line.
//!
//! The section is what the 3D solid has there, less the teeth: the support of the channel depth
//! with its {111} wall (the back mask's edge and the plan's run-out), the PVDF film under it and
//! the base (Plexiglas, held at its bottom, reaching to the die's mid-width, or rigid), the plate
//! over the support and a stub of it into the span with the film bonded under it. The stub's end
//! is moved as a rigid plane (Saint-Venant: the corner's disturbance has decayed over
//! [`STUB_THICKNESSES`] plate thicknesses) by w, its slope and its stretch, one at a time; the
//! reactions give the end's 3 x 3 stiffness, and subtracting the stub's own compliance (a
//! composite Timoshenko cantilever) leaves the edge's stiffness at the clamp line, the wall
//! corner's local give included.

use crate::fe::solid::{
    graded_lines, hex27, merged_lines, Axis3, Constraint, Elasticity, HexGrid, NodeSet, Prescribed,
    SolidModel, SolidProblem,
};
use crate::fe::{FeError, FeResult};

use super::geometry::{Base, SensorGeometry};
use super::solid_mesh::{silicon_elasticity, PiecewiseLinear, BASE, PVDF, SILICON};

/// Length of the plate stub past the clamp line, in plate thicknesses \[choice\]: the wall
/// corner's field decays over about one thickness (Saint-Venant), so five leave the end a beam.
pub const STUB_THICKNESSES: f64 = 5.0;

/// Growth of the section's elements away from the wall's corner and the film \[choice\]: the
/// corner's give converges to 0.6 % per halving with it (`tests`).
const GROWTH: f64 = 1.4;

/// Shear correction of the stub's Timoshenko compliance (rectangle, Timoshenko 1921).
const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

/// The edge stiffness of one support, per unit length along the wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportSection {
    /// Stiffness per unit length on the plate's (w, theta, u) at the clamp line: w (m) down the
    /// plate's normal, theta the slope pointing into the support (as
    /// [`crate::fe::EdgeSpring`]), u (m) the mid-plane's in-plane displacement towards the span;
    /// [[N/m^2, N/m, N/m^2], [N/m, N, N/m], [N/m^2, N/m, N/m^2]].
    pub stiffness: [[f64; 3]; 3],
}

/// The inverse of a 3 x 3 stiffness or compliance; None if it is singular.
fn inverse3(m: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let det = hex27::det3(&m);
    (det.is_finite() && det.abs() >= 1e-300).then(|| hex27::inverse3(&m, det))
}

impl SupportSection {
    /// Solves the section of the design's support 1 (support 2 mirrors it) on a mesh graded
    /// towards the wall; `refine` halves every element size that many times (a convergence
    /// check).
    pub fn new(g: &SensorGeometry, refine: u32) -> FeResult<Self> {
        let et = &g.etched;
        let (f, d, t) = (
            g.film_thickness_um,
            et.support_height_um,
            g.plate_thickness_um,
        );
        let (e1, y0) = (et.support_edge_y_um, g.plate_y0_um);
        if !(d > f + 1.0 && t > 0.0 && f > 0.0 && e1 > 0.0 && y0 >= e1) {
            return Err(FeError::SolidInput {
                detail: format!(
                    "support height {d:.1} um, film {f:.1} um, plate {t:.1} um, footprint edge \
                     {e1:.1} um, floor edge {y0:.1} um"
                ),
                hint: "the support section needs a channel deeper than the PVDF film and a \
                       support of some width",
            });
        }
        let k = 0.5f64.powi(refine as i32);
        let run = y0 - e1;
        let stub = STUB_THICKNESSES * t;
        let y_end = y0 + stub;
        let half_w = 0.5 * g.width_um;
        if y_end >= half_w {
            return Err(FeError::SolidInput {
                detail: format!("the plate stub ends at {y_end:.0} um, past the die's middle"),
                hint: "the support section needs a span of more than ten plate thicknesses",
            });
        }
        // z from the base's top face, as the solid rung's.
        let (film_top, floor_bottom, plate_bottom) = (f, d, f + d);
        let plate_top = plate_bottom + t;
        let z_mid = plate_bottom + 0.5 * t;

        // Lines (logical: the wall is the line y0 at every height, mapped to its slope).
        let h_fine = 0.02 * t * k;
        let mut ys = Vec::new();
        ys.extend(graded_lines(y0, 0.0, h_fine, GROWTH, 0.5 * t * k));
        ys.extend(graded_lines(y0, y_end, h_fine, GROWTH, 0.5 * t * k));
        let mut zs = Vec::new();
        let h_base = match g.base {
            Base::Elastic { thickness_um, .. } => {
                ys.extend(graded_lines(
                    y_end,
                    half_w,
                    0.5 * t * k,
                    GROWTH,
                    0.25 * thickness_um * k,
                ));
                zs.extend(graded_lines(
                    0.0,
                    -thickness_um,
                    0.5 * f * k,
                    GROWTH,
                    0.2 * thickness_um * k,
                ));
                Some(thickness_um)
            }
            Base::Rigid => None,
        };
        zs.extend(graded_lines(0.0, film_top, 0.5 * f * k, 1.0, 0.5 * f * k));
        zs.extend(graded_lines(
            film_top,
            floor_bottom,
            h_fine,
            GROWTH,
            0.25 * t * k,
        ));
        zs.extend(graded_lines(
            floor_bottom,
            film_top,
            h_fine,
            GROWTH,
            0.25 * t * k,
        ));
        zs.extend(graded_lines(
            floor_bottom,
            plate_bottom,
            0.5 * f * k,
            1.0,
            0.5 * f * k,
        ));
        zs.extend(graded_lines(
            plate_bottom,
            plate_top,
            h_fine,
            GROWTH,
            0.25 * t * k,
        ));
        let (ys, zs) = (merged_lines(ys), merged_lines(zs));
        let xs = [0.0, 0.25 * t];

        let mut grid = HexGrid::new(&xs, &ys, &zs)?;
        let has_base = h_base.is_some();
        grid.assign(|[_, yc, zc]| {
            let under_support = yc < y0;
            if zc < 0.0 {
                has_base.then_some(BASE)
            } else if zc < film_top {
                under_support.then_some(PVDF)
            } else if zc < floor_bottom {
                under_support.then_some(SILICON)
            } else if zc < plate_bottom {
                if under_support {
                    Some(SILICON)
                } else {
                    (yc < y_end).then_some(PVDF)
                }
            } else {
                (yc < y_end).then_some(SILICON)
            }
        });
        let wall = PiecewiseLinear::new(vec![
            (0.0, 0.0),
            ((e1 - run).max(0.5 * e1), (e1 - run).max(0.5 * e1)),
            (y0, e1),
            (y0 + run, y0 + run),
            (half_w, half_w),
        ])?;
        let grid = grid.with_map(std::sync::Arc::new(move |[x, y, z]: [f64; 3]| {
            if z < plate_bottom {
                let s = ((plate_bottom - z) / (plate_bottom - film_top)).min(1.0);
                [x, y + s * (wall.apply(y) - y), z]
            } else {
                [x, y, z]
            }
        }));

        let silicon = silicon_elasticity(g.silicon);
        let pvdf = Elasticity::isotropic(g.pvdf_e_pa, g.pvdf_nu);
        let base_el = match g.base {
            Base::Elastic { e_pa, nu, .. } => Elasticity::isotropic(e_pa, nu),
            Base::Rigid => pvdf,
        };
        let mut problem = SolidProblem::new(grid, vec![silicon, pvdf, base_el]);
        let big = 1e9;
        problem.constraints.push(Constraint::clamp(
            "end",
            NodeSet::Box {
                min_um: [-big, y_end, floor_bottom],
                max_um: [big, y_end, big],
            },
        ));
        problem.constraints.push(Constraint {
            group: "plane_strain".into(),
            nodes: NodeSet::Box {
                min_um: [-big; 3],
                max_um: [big; 3],
            },
            fixed: [true, false, false],
            value: Prescribed::Zero,
        });
        if has_base {
            problem
                .constraints
                .push(Constraint::symmetry("mid_width", Axis3::Y, half_w));
        }
        problem.constraints.push(Constraint::clamp(
            "base",
            NodeSet::Plane {
                axis: Axis3::Z,
                at_um: -h_base.unwrap_or(0.0),
            },
        ));
        let model = SolidModel::new(&problem)?;
        let tol = 1e-6 * t;
        let is_end = |p: [f64; 3]| (p[1] - y_end).abs() < tol && p[2] > floor_bottom - tol;
        // The end moved by w, by the slope s = dw/dy (u_y = -s (z - z_mid)) and by u, one at a
        // time; the generalized reactions conjugate to (w, s, u) are its stiffness.
        let (dw, ds, du) = (1e-6, 1e-3, 1e-6);
        let mut k_end = [[0.0; 3]; 3];
        for (j, q) in [dw, ds, du].into_iter().enumerate() {
            let sol = model.solve_prescribed(|p| {
                Ok(if !is_end(p) {
                    [0.0; 3]
                } else {
                    match j {
                        0 => [0.0, 0.0, dw],
                        1 => [0.0, -ds * (p[2] - z_mid) * 1e-6, 0.0],
                        _ => [0.0, du, 0.0],
                    }
                })
            })?;
            let mut gen = [0.0; 3];
            for (p, r) in sol.nodal_reactions("end") {
                gen[0] += r[2];
                gen[1] -= r[1] * (p[2] - z_mid) * 1e-6;
                gen[2] += r[1];
            }
            for i in 0..3 {
                k_end[i][j] = gen[i] / q / ((xs[1] - xs[0]) * 1e-6);
            }
        }
        let c_end = inverse3(k_end).ok_or(FeError::NonFinite {
            hint: "the support section's end stiffness is singular",
        })?;
        let c_stub = stub_compliance(g, stub * 1e-6);
        // c_end = T c0 T^T + c_stub with T the rigid link over the stub (w_end = w0 + L s0).
        let l = stub * 1e-6;
        let m: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| c_end[i][j] - c_stub[i][j]));
        let ti = [[1.0, -l, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let c0: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .map(|a| (0..3).map(|b| ti[i][a] * m[a][b] * ti[j][b]).sum::<f64>())
                    .sum()
            })
        });
        let k_s = inverse3(c0).ok_or(FeError::NonFinite {
            hint: "the support section's edge compliance is singular: refine the section",
        })?;
        // The plate's w points down (the section's z up), and its theta at support 1 (the span at
        // larger y) is -dw/dy of that w, so +s of the section's: flip w's sign.
        let p = [-1.0, 1.0, 1.0];
        let stiffness = std::array::from_fn(|i| std::array::from_fn(|j| p[i] * p[j] * k_s[i][j]));
        Ok(SupportSection { stiffness })
    }

    /// Stiffness on (w, theta) with the in-plane displacement free (the plate's membrane force
    /// zero at the edge, as the linear plate has it): the 3 x 3's Schur complement.
    pub fn bending_stiffness(&self) -> [[f64; 2]; 2] {
        let k = &self.stiffness;
        std::array::from_fn(|i| std::array::from_fn(|j| k[i][j] - k[i][2] * k[2][j] / k[2][2]))
    }

    /// In-plane stiffness (N/m^2) with w and theta free: the reciprocal of the compliance's
    /// in-plane entry.
    pub fn in_plane_pa(&self) -> f64 {
        inverse3(self.stiffness).map_or(f64::NAN, |c| 1.0 / c[2][2])
    }
}

/// Compliance of the stub (clamped at the clamp line, loaded at its end by the generalized
/// forces conjugate to (w, s, u)): the plate with the film bonded under it as a composite
/// Kirchhoff beam about the plate's mid-plane, N = A u' - B w'', m = -B u' + D w'' (Reddy,
/// Mechanics of Laminated Plates, Eq. 3.3.17 for the cylindrical bending of a laminate), plus
/// the plate's shear compliance L / (kappa G t) (Timoshenko).
fn stub_compliance(g: &SensorGeometry, l_m: f64) -> [[f64; 3]; 3] {
    let t = g.plate_thickness_um * 1e-6;
    let f = g.film_thickness_um * 1e-6;
    let q_si = g.material.q22_pa;
    let q_f = g.pvdf_e_pa / (1.0 - g.pvdf_nu * g.pvdf_nu);
    let zc = -0.5 * (t + f);
    let a = q_si * t + q_f * f;
    let b = q_f * f * zc;
    let dd = q_si * t.powi(3) / 12.0 + q_f * (f.powi(3) / 12.0 + f * zc * zc);
    let det = a * dd - b * b;
    // [u', w''] = S [N, m], S = inv([[A, -B], [-B, D]]).
    let (s11, s12, s22) = (dd / det, b / det, a / det);
    let g_yz = silicon_elasticity(g.silicon).c_pa[3][3];
    let shear = l_m / (SHEAR_CORRECTION * g_yz * t);
    let (l2, l3) = (l_m * l_m, l_m * l_m * l_m);
    [
        [s22 * l3 / 3.0 + shear, s22 * l2 / 2.0, s12 * l2 / 2.0],
        [s22 * l2 / 2.0, s22 * l_m, s12 * l_m],
        [s12 * l2 / 2.0, s12 * l_m, s11 * l_m],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::sensor::geometry::bundled as geometry;

    #[test]
    fn the_section_is_symmetric_positive_definite_and_converges() {
        // The bundled design: the stiffness is a stiffness, and one halving of every element
        // moves its condensed entries by under 3 % (measured 1.7 %, then 0.6 %; the wall's
        // corner is singular: its give converges from one side). On a rigid base the edge is
        // stiffer, the subtraction of the stub's compliance amplifies the section's error, and
        // the entries move 13 % and then 4 %.
        let g = geometry(&[]);
        let (a, b) = (
            SupportSection::new(&g, 0).unwrap(),
            SupportSection::new(&g, 1).unwrap(),
        );
        for s in [&a, &b] {
            let k = s.stiffness;
            for i in 0..3 {
                for j in 0..3 {
                    let scale = (k[i][i] * k[j][j]).sqrt();
                    assert!((k[i][j] - k[j][i]).abs() < 1e-6 * scale, "{k:?}");
                }
            }
            let kb = s.bending_stiffness();
            let det2 = kb[0][0] * kb[1][1] - kb[0][1] * kb[1][0];
            assert!(
                kb[0][0] > 0.0 && det2 > 0.0 && s.in_plane_pa() > 0.0,
                "{k:?}"
            );
        }
        let (ka, kb) = (a.bending_stiffness(), b.bending_stiffness());
        for (x, y) in [(ka[0][0], kb[0][0]), (ka[1][1], kb[1][1])] {
            assert!(y <= x * (1.0 + 1e-9) && y > 0.97 * x, "{x} {y}");
        }
    }

    #[test]
    fn a_soft_film_gives_volkersens_in_plane_stiffness() {
        // On a rigid base with a film a thousand times softer the support slides on the film as
        // a bonded lap: Volkersen's shear lag (the footing's closed form) within 5 % (the
        // section also lets the support bend and the film's ends relax).
        let g = geometry(&["materials.base.kind=rigid", "materials.pvdf.e_gpa=0.003"]);
        let s = SupportSection::new(&g, 0).unwrap();
        let lap = crate::sensor::footing::SupportFooting::new(&g).in_plane_pa;
        let k = s.in_plane_pa();
        assert!((k - lap).abs() < 0.05 * lap, "{k} {lap}");
    }
}
