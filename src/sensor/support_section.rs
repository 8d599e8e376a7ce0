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
    graded_lines, hex27, merged_lines, Axis3, Constraint, Elasticity, HexGrid, NodeSet, SolidModel,
    SolidProblem, SolidSolution,
};
use crate::fe::{FeError, FeResult};

use super::geometry::{Base, ElectrodeSide, SensorGeometry};
use super::solid_mesh::{silicon_elasticity, PiecewiseLinear, BASE, PVDF, SILICON};

/// Length of the plate stub past the clamp line, in plate thicknesses \[choice\]: the wall
/// corner's field decays over about one thickness (Saint-Venant), so five leave the end a beam.
pub const STUB_THICKNESSES: f64 = 5.0;

/// Growth of the section's elements away from the wall's corner and the film \[choice\]: the
/// corner's give converges to 0.6 % per halving with it (`tests`).
const GROWTH: f64 = 1.4;

/// Shear correction of the stub's Timoshenko compliance (rectangle, Timoshenko 1921).
const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

/// The edge stiffness of one support, per unit length along the wall, and the charge of the
/// film under it.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportSection {
    /// Stiffness per unit length on the plate's (w, theta, u) at the clamp line: w (m) down the
    /// plate's normal, theta the slope pointing into the support (as
    /// [`crate::fe::EdgeSpring`]), u (m) the mid-plane's in-plane displacement towards the span;
    /// [[N/m^2, N/m, N/m^2], [N/m, N, N/m], [N/m^2, N/m, N/m^2]].
    pub stiffness: [[f64; 3]; 3],
    /// The film under the support, column by column of the section's elements from the die
    /// edge to the support's footprint edge (support 1's y; support 2 mirrors it).
    pub film: Vec<FilmColumn>,
}

/// One column of the film under a support: its y extent (um) and its charge per unit length of
/// wall per unit clamp-line motion (w, theta, u) in the plate's signs (pC/m per m, per rad, per
/// m), the support islands' polarity (paper 001's d33 times the compressive force).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmColumn {
    pub y0_um: f64,
    pub y1_um: f64,
    pub per_motion: [f64; 3],
}

/// The 3 x 3 stiffness per unit length (`width_um` of section) of a section's end, the nodes
/// `is_end` of constraint group `group`: the end moved as a rigid plane by w, by the slope s =
/// dw/dy (u_y = -s (z - z_mid)) and by u, one at a time, and the generalized reactions
/// conjugate to (w, s, u) read. `each` sees every solve (its column and its motion).
pub(super) fn end_stiffness(
    model: &SolidModel,
    group: &str,
    is_end: impl Fn([f64; 3]) -> bool,
    z_mid: f64,
    width_um: f64,
    each: impl FnMut(usize, f64, &SolidSolution) -> FeResult<()>,
) -> FeResult<[[f64; 3]; 3]> {
    wave_end_stiffness(model, group, is_end, z_mid, (|_| 1.0, width_um), each)
}

/// [`end_stiffness`] for an end motion shaped along the wall by `shape.0(x_um)` (a cosine
/// along a slab), per unit length: the generalized reactions weighted by the shape, over the
/// shape's square integral `shape.1` (um).
fn wave_end_stiffness(
    model: &SolidModel,
    group: &str,
    is_end: impl Fn([f64; 3]) -> bool,
    z_mid: f64,
    shape: (impl Fn(f64) -> f64, f64),
    mut each: impl FnMut(usize, f64, &SolidSolution) -> FeResult<()>,
) -> FeResult<[[f64; 3]; 3]> {
    let (along, width_um) = shape;
    let (dw, ds, du) = (1e-6, 1e-3, 1e-6);
    let mut k = [[0.0; 3]; 3];
    for (j, q) in [dw, ds, du].into_iter().enumerate() {
        let sol = model.solve_prescribed(|p| {
            Ok(if !is_end(p) {
                [0.0; 3]
            } else {
                let c = along(p[0]);
                match j {
                    0 => [0.0, 0.0, c * dw],
                    1 => [0.0, -c * ds * (p[2] - z_mid) * 1e-6, 0.0],
                    _ => [0.0, c * du, 0.0],
                }
            })
        })?;
        let mut gen = [0.0; 3];
        for (p, r) in sol.nodal_reactions(group) {
            let c = along(p[0]);
            gen[0] += c * r[2];
            gen[1] -= c * r[1] * (p[2] - z_mid) * 1e-6;
            gen[2] += c * r[1];
        }
        for i in 0..3 {
            k[i][j] = gen[i] / q / (width_um * 1e-6);
        }
        each(j, q, &sol)?;
    }
    Ok(k)
}

/// A (w, theta, u) stiffness condensed to (w, theta) with u free: the 3 x 3's Schur complement.
pub fn with_in_plane_free(k: &[[f64; 3]; 3]) -> [[f64; 2]; 2] {
    std::array::from_fn(|i| std::array::from_fn(|j| k[i][j] - k[i][2] * k[2][j] / k[2][2]))
}

/// The inverse of a 3 x 3 stiffness or compliance; None if it is singular.
fn inverse3(m: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let det = hex27::det3(&m);
    (det.is_finite() && det.abs() >= 1e-300).then(|| hex27::inverse3(&m, det))
}

impl SupportSection {
    /// Solves the section of the design's support 1 (support 2 mirrors it) on a mesh graded
    /// towards the wall; `refine` halves every element size that many times (a convergence
    /// check). `tooth` is the top's y extent of the row of teeth standing on the support: its
    /// lines are kept (so both sections read the film by the same columns), and the tooth's
    /// frustum stands on the plate over the support when its flag is set.
    fn solve(g: &SensorGeometry, refine: u32, tooth: Option<([f64; 2], bool)>) -> FeResult<Self> {
        let (problem, fr) = section_problem(g, 0.5f64.powi(refine as i32), tooth, None, false)?;
        let model = SolidModel::new(&problem)?;
        let film_top = fr.film_top;
        let is_end = |p: [f64; 3]| fr.is_end(p);
        // Film charge per column per unit end motion (pC/m).
        let mut film: Vec<(f64, f64, [f64; 3])> = Vec::new();
        let width_um = fr.length_um;
        let k_end = end_stiffness(&model, "end", is_end, fr.z_mid, width_um, |j, q, sol| {
            for (c, (y_lo, y_hi, charge)) in film_charges(g, sol, film_top)?.into_iter().enumerate()
            {
                if j == 0 {
                    film.push((y_lo, y_hi, [0.0; 3]));
                }
                film[c].2[j] = charge / q / (width_um * 1e-6);
            }
            Ok(())
        })?;
        let (stiffness, a) = edge_from_end(g, k_end, fr.stub)?;
        let p = FLIP;
        let film = film
            .into_iter()
            .map(|(y0_um, y1_um, r)| FilmColumn {
                y0_um,
                y1_um,
                per_motion: std::array::from_fn(|j| {
                    p[j] * (0..3).map(|i| r[i] * a[i][j]).sum::<f64>()
                }),
            })
            .collect();
        Ok(SupportSection { stiffness, film })
    }

    /// Charge (pC per m of wall) of the film under the support between y0_um and y1_um from the
    /// die edge (support 1's coordinates) per unit clamp-line motion (w, theta, u), the plate's
    /// signs; a column partly inside counts by its overlap.
    pub fn island_charge(&self, y0_um: f64, y1_um: f64) -> [f64; 3] {
        let mut q = [0.0; 3];
        for c in &self.film {
            let overlap = (c.y1_um.min(y1_um) - c.y0_um.max(y0_um)).max(0.0);
            if overlap > 0.0 {
                let share = overlap / (c.y1_um - c.y0_um);
                for (q, r) in q.iter_mut().zip(c.per_motion) {
                    *q += share * r;
                }
            }
        }
        q
    }

    /// Stiffness on (w, theta) with the in-plane displacement free (the plate's membrane force
    /// zero at the edge, as the linear plate has it): the 3 x 3's Schur complement.
    pub fn bending_stiffness(&self) -> [[f64; 2]; 2] {
        with_in_plane_free(&self.stiffness)
    }

    /// In-plane stiffness (N/m^2) with w and theta free: the reciprocal of the compliance's
    /// in-plane entry.
    pub fn in_plane_pa(&self) -> f64 {
        inverse3(self.stiffness).map_or(f64::NAN, |c| 1.0 / c[2][2])
    }
}

/// Both supports as sections: the bare support, and where teeth stand on a support's footprint
/// (the checkered pattern's first and last rows do) the support under a tooth, each over the x
/// intervals it holds. Along the wall the plate sees each piece's own springs, side by side: the
/// tooth's block turns less (the bundled design's rotational stiffness, u free, 355 N against
/// 190 N bare) and its film reads about half as much per unit edge moment.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportSections {
    pub bare: SupportSection,
    /// The section under a tooth of the row on support 1 (support 2's row is taken as its
    /// mirror image).
    pub under_tooth: Option<SupportSection>,
    /// x intervals (um) of the teeth standing on support 1 and on support 2: the plate step's
    /// width ([`super::frustum_step::inset`]).
    pub teeth_x_um: [Vec<[f64; 2]>; 2],
    /// The bare support's Pasternak term along the wall ([`along_wall_stiffness`]), taken
    /// along the whole clamp line, teeth or not.
    pub along_wall: [[f64; 3]; 3],
}

impl SupportSections {
    /// Solves the bare section and, if teeth stand on the supports, the section under a tooth;
    /// `refine` as [`SupportSection`]'s (the along-wall slab keeps its own sizes: its
    /// convergence is checked on its own).
    pub fn new(g: &SensorGeometry, refine: u32) -> FeResult<Self> {
        let et = &g.etched;
        let (e1, w) = (et.support_edge_y_um, g.width_um);
        let row = |on: &dyn Fn(&[f64; 4]) -> bool| -> Vec<[f64; 4]> {
            et.tooth_tops_um.iter().copied().filter(|t| on(t)).collect()
        };
        let rows = [
            row(&|t: &[f64; 4]| t[1] < e1 && t[3] > 0.0),
            row(&|t: &[f64; 4]| t[3] > w - e1 && t[1] < w),
        ];
        // The tooth's y extent on support 1, or support 2's mirrored.
        let top = match (rows[0].first(), rows[1].first()) {
            (Some(t), _) => Some([t[1], t[3]]),
            (None, Some(t)) => Some([w - t[3], w - t[1]]),
            _ => None,
        };
        // The slab is about half the cost and independent of the two sections: solved beside
        // them.
        let (sections, slab) = rayon::join(
            || -> FeResult<_> {
                let bare = SupportSection::solve(g, refine, top.map(|t| (t, false)))?;
                let under_tooth = top
                    .map(|t| SupportSection::solve(g, refine, Some((t, true))))
                    .transpose()?;
                Ok((bare, under_tooth))
            },
            || along_wall_stiffness(g, SLAB_SCALE),
        );
        let (bare, under_tooth) = sections?;
        let along_wall = semi_definite_part(slab?, bare.stiffness)?;
        if under_tooth.is_none() {
            return Ok(SupportSections {
                bare,
                under_tooth,
                teeth_x_um: [Vec::new(), Vec::new()],
                along_wall,
            });
        }
        let grow = et.tooth_run_out_um * (1.0 - et.tooth_step_inset);
        let intervals = |r: &[[f64; 4]]| -> Vec<[f64; 2]> {
            let mut v: Vec<[f64; 2]> = r
                .iter()
                .map(|t| [(t[0] - grow).max(0.0), (t[2] + grow).min(g.length_um)])
                .filter(|i| i[1] > i[0])
                .collect();
            v.sort_by(|a, b| a[0].total_cmp(&b[0]));
            v
        };
        Ok(SupportSections {
            bare,
            under_tooth,
            teeth_x_um: [intervals(&rows[0]), intervals(&rows[1])],
            along_wall,
        })
    }

    /// The section at `x_um` along support 1 (`side` 0) or support 2 (1).
    pub fn at(&self, side: usize, x_um: f64) -> &SupportSection {
        match &self.under_tooth {
            Some(t)
                if self.teeth_x_um[side]
                    .iter()
                    .any(|i| x_um >= i[0] && x_um <= i[1]) =>
            {
                t
            }
            _ => &self.bare,
        }
    }

    /// [from_um, to_um] along support `side` cut where the section changes, each piece with its
    /// section.
    pub fn pieces(
        &self,
        side: usize,
        from_um: f64,
        to_um: f64,
    ) -> Vec<(f64, f64, &SupportSection)> {
        let mut cuts = vec![from_um, to_um];
        for i in &self.teeth_x_um[side] {
            cuts.extend(i.iter().copied().filter(|&c| c > from_um && c < to_um));
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        cuts.windows(2)
            .filter(|c| c[1] > c[0])
            .map(|c| (c[0], c[1], self.at(side, 0.5 * (c[0] + c[1]))))
            .collect()
    }

    /// Where the section changes along either support (um): lines the plate's mesh keeps.
    pub fn x_lines_um(&self) -> Vec<f64> {
        self.teeth_x_um
            .iter()
            .flatten()
            .flatten()
            .copied()
            .collect()
    }
}

/// Where a section's parts lie (um, z from the base's top face).
struct SectionFrame {
    film_top: f64,
    floor_bottom: f64,
    z_mid: f64,
    y_end: f64,
    stub: f64,
    /// The section's length along the wall.
    length_um: f64,
    /// Position tolerance (um).
    tol_um: f64,
}

impl SectionFrame {
    /// True at a node of the stub's end (the plate and the film under it).
    fn is_end(&self, p: [f64; 3]) -> bool {
        (p[1] - self.y_end).abs() < self.tol_um && p[2] > self.floor_bottom - self.tol_um
    }
}

/// The section's solid problem: plane strain (`slab` None) or a slab `slab.0` um long along the
/// wall in `slab.1` elements between two mirror planes; the end of the stub held ("end").
/// `scale` multiplies every element size; `stub_only` keeps the plate stub alone, clamped at
/// the clamp line ("wall"), on the same lines.
fn section_problem(
    g: &SensorGeometry,
    scale: f64,
    tooth: Option<([f64; 2], bool)>,
    slab: Option<(f64, usize)>,
    stub_only: bool,
) -> FeResult<(SolidProblem, SectionFrame)> {
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
    let k = scale;
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
            // Across the base: a quarter of its thickness, never finer than the stub's
            // elements (a thin base is a Winkler layer under the support; a base of 1e-9 um
            // asked for 3e13 lines).
            ys.extend(graded_lines(
                y_end,
                half_w,
                0.5 * t * k,
                GROWTH,
                (0.25 * thickness_um).max(0.5 * t) * k,
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
    // The wall: the logical line y0 at every height, mapped to the {111} slope below the plate.
    let wall = PiecewiseLinear::new(vec![
        (0.0, 0.0),
        ((e1 - run).max(0.5 * e1), (e1 - run).max(0.5 * e1)),
        (y0, e1),
        (y0 + run, y0 + run),
        (half_w, half_w),
    ])?;
    // The support islands' edges (support 2's mirrored), so each film column is read whole.
    for el in &g.electrodes {
        let (a, b) = match el.side {
            ElectrodeSide::Support1 => (el.y0_um, el.y1_um),
            ElectrodeSide::Support2 => (g.width_um - el.y1_um, g.width_um - el.y0_um),
            ElectrodeSide::Middle => continue,
        };
        for v in [a, b] {
            if v > 0.0 && v < e1 {
                ys.push(wall.invert(v));
            }
        }
    }
    // The tooth row standing on the support: its base lines, the frustum mapped above.
    let (h_tooth, ro) = (et.tooth_height_um, et.tooth_run_out_um);
    let tooth_base = tooth.map(|([a, b], _)| [a - ro, b + ro]);
    if let Some([a, b]) = tooth_base {
        ys.extend([a, b]);
        zs.extend(graded_lines(
            plate_top,
            plate_top + h_tooth,
            0.1 * t * k,
            GROWTH,
            0.25 * t * k,
        ));
    }
    let solid_tooth = tooth.is_some_and(|(_, on)| on);
    let (ys, zs) = (merged_lines(ys), merged_lines(zs));
    // Plane strain: one element 0.25 t long; the slab: its elements over the half wavelength.
    let xs: Vec<f64> = match slab {
        None => vec![0.0, 0.25 * t],
        Some((len, n)) => (0..=n).map(|i| len * i as f64 / n as f64).collect(),
    };

    let mut grid = HexGrid::new(&xs, &ys, &zs)?;
    let has_base = h_base.is_some() && !stub_only;
    grid.assign(|[_, yc, zc]| {
        let under_support = yc < y0;
        if stub_only {
            let in_stub = yc > y0 && yc < y_end && zc > floor_bottom && zc < plate_top;
            in_stub.then_some(if zc < plate_bottom { PVDF } else { SILICON })
        } else if zc < 0.0 {
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
        } else if zc < plate_top {
            (yc < y_end).then_some(SILICON)
        } else {
            let [a, b] = tooth_base?;
            (solid_tooth && yc > a && yc < b).then_some(SILICON)
        }
    });
    let frustum = match tooth_base {
        Some([a, b]) => {
            PiecewiseLinear::new(vec![(0.0, 0.0), (a, a + ro), (b, b - ro), (half_w, half_w)])?
        }
        None => PiecewiseLinear::new(vec![(0.0, 0.0), (half_w, half_w)])?,
    };
    let grid = grid.with_map(std::sync::Arc::new(move |[x, y, z]: [f64; 3]| {
        if z < plate_bottom {
            let s = ((plate_bottom - z) / (plate_bottom - film_top)).min(1.0);
            [x, y + s * (wall.apply(y) - y), z]
        } else if z > plate_top {
            let s = ((z - plate_top) / h_tooth).min(1.0);
            [x, y + s * (frustum.apply(y) - y), z]
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
    let frame = SectionFrame {
        film_top,
        floor_bottom,
        z_mid,
        y_end,
        stub,
        length_um: xs[xs.len() - 1] - xs[0],
        tol_um: 1e-6 * t,
    };
    let big = 1e9;
    let mut end = Constraint::clamp(
        "end",
        NodeSet::Box {
            min_um: [-big, y_end, floor_bottom],
            max_um: [big, y_end, big],
        },
    );
    match slab {
        None => problem
            .constraints
            .extend([end, Constraint::plane_strain_x("plane_strain")]),
        Some((len, _)) => {
            // The end's plane free to warp along the wall; the slab's ends are mirrors.
            end.fixed = [false, true, true];
            problem.constraints.extend([
                end,
                Constraint::symmetry("x0", Axis3::X, 0.0),
                Constraint::symmetry("x1", Axis3::X, len),
            ]);
        }
    }
    if stub_only {
        problem.constraints.push(Constraint::clamp(
            "wall",
            NodeSet::Box {
                min_um: [-big, -big, plate_bottom],
                max_um: [big, y0, big],
            },
        ));
        return Ok((problem, frame));
    }
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
    Ok((problem, frame))
}

/// A 3 x 3 on (w, theta or s, u).
type Mat3 = [[f64; 3]; 3];

/// The plate's w points down (the section's z up), and its theta at support 1 (the span at
/// larger y) is -dw/dy of that w, so +s of the section's: flip w's sign.
const FLIP: [f64; 3] = [-1.0, 1.0, 1.0];

/// The edge's stiffness at the clamp line (the plate's signs) from the stub end's stiffness
/// `k_end` (the section's signs), and the end's motion per unit clamp-line motion (the
/// section's signs, for the film's read-out).
fn edge_from_end(g: &SensorGeometry, k_end: [[f64; 3]; 3], stub: f64) -> FeResult<(Mat3, Mat3)> {
    let c_end = inverse3(k_end).ok_or(FeError::NonFinite {
        hint: "the support section's end stiffness is singular",
    })?;
    let l = stub * 1e-6;
    let k_s = edge_stiffness(c_end, stub_compliance(g, l), l)?;
    let p = FLIP;
    let stiffness = std::array::from_fn(|i| std::array::from_fn(|j| p[i] * p[j] * k_s[i][j]));
    // The end's motion for a clamp-line motion d0: the clamp line's forces k_s d0 carried to
    // the end over the stub (f_end = T^-T f0, T^-1 = `link_inverse`), then the end's compliance.
    let ti = link_inverse(l);
    let a: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            (0..3)
                .map(|m| c_end[i][m] * (0..3).map(|n| ti[n][m] * k_s[n][j]).sum::<f64>())
                .sum()
        })
    });
    Ok((stiffness, a))
}

/// The inverse of the rigid link over a stub of length `l_m` (w_end = w0 + L s0).
fn link_inverse(l_m: f64) -> [[f64; 3]; 3] {
    [[1.0, -l_m, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
}

/// The edge's stiffness at the clamp line (the section's signs) from the end's compliance and
/// the stub's: c_end = T c0 T^T + c_stub, T the rigid link over the stub.
fn edge_stiffness(
    c_end: [[f64; 3]; 3],
    c_stub: [[f64; 3]; 3],
    l_m: f64,
) -> FeResult<[[f64; 3]; 3]> {
    let m: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| c_end[i][j] - c_stub[i][j]));
    let ti = link_inverse(l_m);
    let c0: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            (0..3)
                .map(|a| (0..3).map(|b| ti[i][a] * m[a][b] * ti[j][b]).sum::<f64>())
                .sum()
        })
    });
    inverse3(c0).ok_or(FeError::NonFinite {
        hint: "the support section's edge compliance is singular: refine the section",
    })
}

/// Element sizes of the slab's section against the plane-strain section's \[choice\]: the
/// difference K(k) - K(0) cancels most of the corner's error, so G moves by under 1 % between
/// eight times coarser and the section's own sizes (`tests` check four: 0.3 %). The slab takes
/// 4 s at eight, 8 s and a 1.7 GB peak at four (the optimised dev build).
const SLAB_SCALE: f64 = 8.0;

/// Elements of the slab along its half wavelength \[choice\]: 27-node bricks; 16 move the
/// along-wall stiffness by 0.5 % (its w entry; 4 were 2.6 % off), 8 by 0.4 % (`tests`).
const SLAB_ELEMENTS: usize = 6;

/// The edge's stiffness along the wall (issue 16, item 5): what a plane-strain section cannot
/// see, the support, the film and the base spreading a clamp-line motion that varies along the
/// wall. A slab of the section half a wavelength long between mirror planes is moved at its
/// stub's end by (w, s, u) cos(k x) (a Fourier mode of the prism, the finite-strip idea of
/// Cheung 1976) and by the same uniformly; the stub's own part is taken away with the stub
/// alone on the same slab (clamped at the clamp line), and the edge's stiffness per unit
/// length rises from K(0) to K(k). The plate takes the rise as a Pasternak term along its clamp
/// line, K(k) = K(0) + k^2 G (Pasternak's shear layer, as Kerr 1964 reviews it): G (plate
/// signs; [[N, N m, N], [N m, N m^2, N m], [N, N m, N]] on (w', theta', u')) measured at the
/// wavenumber of the channel floor's width as the half wavelength, the span's first mode along
/// the wall.
pub fn along_wall_stiffness(g: &SensorGeometry, scale: f64) -> FeResult<[[f64; 3]; 3]> {
    along_wall_on(g, scale, SLAB_ELEMENTS)
}

/// The half wavelength along the wall [`along_wall_stiffness`] measures at (um): the channel
/// floor's width, the span's first mode along the wall.
pub fn along_wall_half_wavelength_um(g: &SensorGeometry) -> f64 {
    g.plate_y1_um - g.plate_y0_um
}

/// [`along_wall_stiffness`] with `n_x` elements along the slab.
fn along_wall_on(g: &SensorGeometry, scale: f64, n_x: usize) -> FeResult<[[f64; 3]; 3]> {
    let half_um = along_wall_half_wavelength_um(g);
    let k = std::f64::consts::PI / (half_um * 1e-6);
    // [whole, stub] x [uniform, wave] end compliances.
    let mut c = [[[[0.0; 3]; 3]; 2]; 2];
    for (part, stub_only) in [false, true].into_iter().enumerate() {
        let (problem, fr) = section_problem(g, scale, None, Some((half_um, n_x)), stub_only)?;
        let model = SolidModel::new(&problem)?;
        let is_end = |p: [f64; 3]| fr.is_end(p);
        for (wave, c) in c[part].iter_mut().enumerate() {
            let kx = if wave == 1 { k * 1e-6 } else { 0.0 };
            let norm = if wave == 1 { 0.5 * half_um } else { half_um };
            let k_end = wave_end_stiffness(
                &model,
                "end",
                is_end,
                fr.z_mid,
                (|x: f64| (kx * x).cos(), norm),
                |_, _, _| Ok(()),
            )?;
            *c = inverse3(k_end).ok_or(FeError::NonFinite {
                hint: "the support slab's end stiffness is singular",
            })?;
        }
    }
    let l = STUB_THICKNESSES * g.plate_thickness_um * 1e-6;
    let k0 = edge_stiffness(c[0][0], c[1][0], l)?;
    let kk = edge_stiffness(c[0][1], c[1][1], l)?;
    let p = FLIP;
    Ok(std::array::from_fn(|i| {
        std::array::from_fn(|j| p[i] * p[j] * (kk[i][j] - k0[i][j]) / (k * k))
    }))
}

/// The semi-definite part of `g` in the metric of the positive definite `k0` (the generalized
/// eigenproblem G v = lambda K0 v with the negative lambda set to zero): K(k) - K(0) need not be
/// semi-definite (on a rigid base the (w, theta) block is not, at every mesh scale), and a
/// Pasternak term that is not would let a motion oscillating fast enough along the wall lower
/// the energy without bound.
fn semi_definite_part(g: [[f64; 3]; 3], k0: [[f64; 3]; 3]) -> FeResult<[[f64; 3]; 3]> {
    let fail = || FeError::NonFinite {
        hint: "the support section's edge stiffness is not positive definite (or its along-wall \
               rise not finite): the section's silicon, film and base stiffnesses differ by more \
               than its solve resolves; check materials.*",
    };
    let rows = |m: [[f64; 3]; 3]| m.iter().map(|r| r.to_vec()).collect::<Vec<_>>();
    let (lambda, q) = crate::fe::modal::definite_eigen(&rows(g), &rows(k0)).map_err(|_| fail())?;
    // Q^T K0 Q = I and Q^T G Q = Lambda, so G = K0 Q Lambda Q^T K0: keep max(Lambda, 0).
    let kq: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|c| (0..3).map(|m| k0[i][m] * q[m][c]).sum()));
    let out: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            (0..3)
                .map(|c| lambda[c].max(0.0) * kq[i][c] * kq[j][c])
                .sum()
        })
    });
    if out.iter().flatten().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(fail())
    }
}

/// Charge (pC) of each film column under the support in a section solution, by y (um): minus
/// the integral of D3 = d31 s1 + d32 s2 + d33 s3 (IEEE Std 176; 1 the drawn axis) over the
/// column divided by the film's thickness, the solid rung's support-island read-out.
fn film_charges(
    g: &SensorGeometry,
    sol: &SolidSolution,
    film_top: f64,
) -> FeResult<Vec<(f64, f64, f64)>> {
    let grid = sol.grid();
    let pos = sol.node_positions_um();
    let [_, ny, nz] = grid.n_elements();
    let zs = grid.lines_um()[2];
    let t_film = g.film_thickness_um * 1e-6;
    let mut out = Vec::new();
    for j in 0..ny {
        let mut column: Option<(f64, f64, f64)> = None;
        for k in 0..nz {
            let zc = 0.5 * (zs[k] + zs[k + 1]);
            let e = grid.element([0, j, k]);
            if !(zc > 0.0 && zc < film_top) || grid.material(e) != Some(PVDF) {
                continue;
            }
            let nodes_um = grid.element_nodes(e).map(|n| pos[n]);
            let nodes_m = nodes_um.map(|p| p.map(|c| c * 1e-6));
            let (lo, hi) = nodes_um
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                    (a.0.min(p[1]), a.1.max(p[1]))
                });
            let c = column.get_or_insert((lo, hi, 0.0));
            for (xi, wgt) in hex27::gauss_points() {
                let dv = hex27::geometry(&nodes_m, xi).det_j * wgt;
                let st = sol.stress_at([0, j, k], xi).ok_or(FeError::NonFinite {
                    hint: "the support section's film has an element without stress",
                })?;
                let (s1, s2) = match g.drawn_axis {
                    crate::process::Axis::Y => (st[1], st[0]),
                    crate::process::Axis::X => (st[0], st[1]),
                };
                let d3 = g.d31_pc_per_n * s1 + g.d32_pc_per_n * s2 + g.d33_pc_per_n * st[2];
                c.2 -= d3 * dv / t_film;
            }
        }
        out.extend(column);
    }
    Ok(out)
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
    fn the_slab_without_a_wave_is_the_plane_strain_section() {
        // Between two mirror planes, moved uniformly, the slab is in plane strain whatever its
        // length and elements: its end stiffness is the one-element section's (the same lines
        // across the wall), to round-off.
        let g = geometry(&[]);
        let end = |slab: Option<(f64, usize)>| {
            let (problem, fr) = section_problem(&g, SLAB_SCALE, None, slab, false).unwrap();
            let model = SolidModel::new(&problem).unwrap();
            let is_end = |p: [f64; 3]| fr.is_end(p);
            end_stiffness(&model, "end", is_end, fr.z_mid, fr.length_um, |_, _, _| {
                Ok(())
            })
            .unwrap()
        };
        let (a, b) = (end(None), end(Some((3_000.0, 3))));
        for i in 0..3 {
            for j in 0..3 {
                let scale = (a[i][i] * a[j][j]).sqrt();
                assert!((a[i][j] - b[i][j]).abs() < 1e-7 * scale, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn the_along_wall_stiffness_is_semi_definite_and_converges() {
        // The bundled design (Plexiglas base): at the span's wavenumber the edge is stiffer in
        // every direction than plane strain says (G's diagonal positive), most in plane (k^2
        // G_uu is 47 % of K(0)'s in-plane entry); G is semi-definite as measured (the
        // projection leaves it); half the element sizes or 8 elements along the slab instead of
        // 6 move each entry by under 1 % of sqrt(G_ii G_jj).
        let g = geometry(&[]);
        let s = SupportSections::new(&g, 0).unwrap();
        let gm = along_wall_stiffness(&g, SLAB_SCALE).unwrap();
        assert_eq!(
            s.along_wall,
            semi_definite_part(gm, s.bare.stiffness).unwrap()
        );
        let k = std::f64::consts::PI / ((g.plate_y1_um - g.plate_y0_um) * 1e-6);
        let rise = k * k * gm[2][2] / s.bare.stiffness[2][2];
        assert!((0.35..0.6).contains(&rise), "{rise}");
        for i in 0..3 {
            for j in 0..3 {
                assert!(
                    (s.along_wall[i][j] - gm[i][j]).abs() < 1e-9 * (gm[i][i] * gm[j][j]).sqrt(),
                    "{gm:?} {:?}",
                    s.along_wall
                );
            }
            assert!(gm[i][i] > 0.0, "{gm:?}");
        }
        for other in [
            along_wall_on(&g, 0.5 * SLAB_SCALE, SLAB_ELEMENTS).unwrap(),
            along_wall_on(&g, SLAB_SCALE, 8).unwrap(),
        ] {
            for i in 0..3 {
                for j in 0..3 {
                    let scale = (gm[i][i] * gm[j][j]).sqrt();
                    assert!(
                        (other[i][j] - gm[i][j]).abs() < 0.01 * scale,
                        "{gm:?} {other:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn on_a_rigid_base_the_along_wall_stiffness_is_projected() {
        // On a rigid base K(k) - K(0)'s (w, theta) block is indefinite at every mesh scale
        // (coupling 1.25 times the diagonals' mean); its semi-definite part in K(0)'s metric
        // keeps the positive directions and is accepted by the plate.
        let g = geometry(&["materials.base.kind=rigid"]);
        let s = SupportSections::new(&g, 0).unwrap();
        let gm = along_wall_stiffness(&g, SLAB_SCALE).unwrap();
        assert!(gm[0][1] * gm[0][1] > gm[0][0] * gm[1][1], "{gm:?}");
        let p = s.along_wall;
        assert!(
            crate::fe::edge_spring::check_semi_definite(&p, "support1").is_ok(),
            "{p:?}"
        );
        // Projection only adds: no direction is stiffer along the wall in the raw G than kept.
        for i in 0..3 {
            assert!(p[i][i] >= gm[i][i] * (1.0 - 1e-9), "{gm:?} {p:?}");
        }
    }

    #[test]
    fn the_section_is_symmetric_positive_definite_and_converges() {
        // The bundled design: the stiffness is a stiffness, and one halving of every element
        // moves its condensed entries by under 3 % (measured 1.7 %, then 0.6 %; the wall's
        // corner is singular: its give converges from one side). On a rigid base the edge is
        // stiffer, the subtraction of the stub's compliance amplifies the section's error, and
        // the entries move 13 % and then 4 %.
        let g = geometry(&[]);
        let (a, b) = (
            SupportSections::new(&g, 0).unwrap().bare,
            SupportSections::new(&g, 1).unwrap().bare,
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
        let s = SupportSections::new(&g, 0).unwrap().bare;
        let lap = crate::sensor::footing::SupportFooting::new(&g).in_plane_pa;
        let k = s.in_plane_pa();
        assert!((k - lap).abs() < 0.05 * lap, "{k} {lap}");
    }

    #[test]
    fn a_tooth_on_the_support_stiffens_its_edge_and_quiets_its_film() {
        // The bundled checkered pattern's first and last rows stand on the supports: five teeth
        // each, at the same x, so the pieces alternate bare and under a tooth, cover the wall,
        // and are the same on both supports. Under a tooth the edge turns less (the block of
        // support, plate and tooth is 500 um thick, not 300) and its film reads less per unit
        // moment at the edge (measured 0.53 of the bare support's).
        let g = geometry(&[]);
        let s = SupportSections::new(&g, 0).unwrap();
        let tooth = s.under_tooth.as_ref().expect("teeth stand on the supports");
        assert_eq!(s.teeth_x_um[0].len(), 5);
        assert_eq!(s.teeth_x_um[0], s.teeth_x_um[1]);
        let pieces = s.pieces(0, 0.0, g.length_um);
        assert_eq!(pieces.len(), 11);
        assert!(pieces.windows(2).all(|p| p[0].1 == p[1].0));
        assert_eq!((pieces[0].0, pieces[10].1), (0.0, g.length_um));
        for (i, p) in pieces.iter().enumerate() {
            assert_eq!(std::ptr::eq(p.2, tooth), i % 2 == 1, "{i}");
        }
        let (kb, kt) = (s.bare.bending_stiffness(), tooth.bending_stiffness());
        eprintln!(
            "rotational stiffness: bare {:.1} N, under a tooth {:.1} N",
            kb[1][1], kt[1][1]
        );
        assert!(kt[1][1] > 1.3 * kb[1][1], "{kb:?} {kt:?}");
        let island = g.electrodes.iter().find(|e| e.name == "S12").expect("S12");
        let (qb, qt) = (
            s.bare.island_charge(island.y0_um, island.y1_um),
            tooth.island_charge(island.y0_um, island.y1_um),
        );
        // Charge per unit edge moment (w and u free): q C e_theta.
        let per_moment = |s: &SupportSection, q: [f64; 3]| {
            let c = inverse3(s.stiffness).unwrap();
            (0..3).map(|i| q[i] * c[i][1]).sum::<f64>()
        };
        let (mb, mt) = (per_moment(&s.bare, qb), per_moment(tooth, qt));
        eprintln!("per moment: bare {mb:.4e}, under a tooth {mt:.4e}");
        assert!(mt.abs() < 0.75 * mb.abs(), "{qb:?} {qt:?}");
        // Without teeth there is one section.
        let plain = geometry(&["geometry.teeth.pattern=none"]);
        let s = SupportSections::new(&plain, 0).unwrap();
        assert!(s.under_tooth.is_none() && s.pieces(0, 0.0, plain.length_um).len() == 1);
    }
}
