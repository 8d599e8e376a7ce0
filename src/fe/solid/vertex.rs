//! The stress near a frustum's base vertex, where two sharp re-entrant edges meet (issue 16, item
//! 7): a 3-D submodel graded towards the vertex and its edges, nested to the critical distance.
//!
//! Near the vertex the field is three-dimensional (a vertex singularity of its own on top of the
//! two edges' Williams fields; Sinclair 2004, Appl. Mech. Rev., doi:10.1115/1.1767846, sec. 5,
//! reviews them), so the edges' sections
//! ([`crate::fe::solid::corner`]) do not hold there. Locally the material is a cone: the half-space
//! under the plate's top face and the frustum above, between its two {111} sidewalls. In vertex
//! axes (x along one base edge, y along the other, z up; the frustum over x, y >= 0) it is the
//! unit cube's {z <= 0} and {x, y >= 0}, mapped by X = x + c z (1 - x), Y = y + c z (1 - y) for
//! z > 0 (c = the sidewall's run over its height): the sidewalls x = 0 and y = 0 become X = c z
//! and Y = c z, the cube's faces stay planes. Grid lines at 0 and +-2^-j (j = 0..K, every
//! octave or every other) grade the 27-node bricks geometrically towards the three coordinate
//! planes: towards the vertex in all three directions and towards each edge in its two cross
//! directions, so a station on an edge sees its section resolved as finely as the vertex.
//!
//! A classical submodel (Cormier et al. 1999, Int. J. Numer. Meth. Eng. 46: 889) driven on the
//! cube's faces by the solid's displacement, then nested: each next model, 1/8 of the size (or
//! what is left), is driven by the last one's field on its own faces, down to the critical
//! distance. The models are geometrically alike, so one factorisation of the unit cube serves
//! every level (stiffness scales with size, the displacements do not) and every vertex of the
//! same material and slope.

use crate::fe::solid::corner::{
    polar_rotation, CornerMesh, DriverKinematics, SectionPatterns, OCTAVES_INSIDE,
};
use crate::fe::solid::elasticity::Elasticity;
use crate::fe::solid::grid::{HexGrid, NodeMap};
use crate::fe::solid::problem::{Axis3, Constraint, NodeSet, SolidProblem};
use crate::fe::solid::solution::SolidSolution;
use crate::fe::solid::solve::SolidModel;
use crate::fe::{FeError, FeResult};
use rayon::prelude::*;
use std::sync::Arc;

/// A vertex's frame in the solid: the vertex and its axes (x, y along the two edges into the
/// frustum's sides, z up out of the plate's face), right-handed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexFrame {
    pub origin_um: [f64; 3],
    pub e_x: [f64; 3],
    pub e_y: [f64; 3],
    pub e_z: [f64; 3],
}

impl VertexFrame {
    fn axes(&self) -> [[f64; 3]; 3] {
        [self.e_x, self.e_y, self.e_z]
    }
    /// World point (um) of local point `p` (um).
    pub fn world_um(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| {
            self.origin_um[i] + p[0] * self.e_x[i] + p[1] * self.e_y[i] + p[2] * self.e_z[i]
        })
    }
    /// Local point (um) of world point `q` (um).
    pub fn local_um(&self, q: [f64; 3]) -> [f64; 3] {
        let d: [f64; 3] = std::array::from_fn(|i| q[i] - self.origin_um[i]);
        self.axes().map(|e| e[0] * d[0] + e[1] * d[1] + e[2] * d[2])
    }
}

/// How finely the unit model is graded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VertexGrading {
    /// A grid line every octave, down to 2^-7 of the model's size.
    Fine,
    /// Every other octave, down to 2^-6: the coarser model whose difference bounds the error.
    Coarse,
}

impl VertexGrading {
    fn lines(self) -> Vec<f64> {
        let js: Vec<i32> = match self {
            VertexGrading::Fine => (0..=7).collect(),
            VertexGrading::Coarse => (0..=3).map(|j| 2 * j).collect(),
        };
        let mut out: Vec<f64> = js.iter().map(|&j| -(2f64.powi(-j))).collect();
        out.push(0.0);
        out.extend(js.iter().rev().map(|&j| 2f64.powi(-j)));
        out
    }
}

/// Each nested model is this much smaller than the one driving it (or less, at the last).
pub const NEST_RATIO: f64 = 8.0;
/// Nested models at most (bounds the work: 8^12 spans any die down to atoms).
const MAX_NEST: usize = 12;

/// The unit model (cube of half-size 1 um), factorised once.
#[derive(Debug, Clone)]
pub struct VertexModel {
    model: SolidModel,
    lines: Vec<f64>,
    slope: f64,
    /// Free dofs of the unit model.
    pub dofs: usize,
}

fn map(slope: f64) -> NodeMap {
    Arc::new(move |p: [f64; 3]| {
        if p[2] > 0.0 {
            [
                p[0] + slope * p[2] * (1.0 - p[0]),
                p[1] + slope * p[2] * (1.0 - p[1]),
                p[2],
            ]
        } else {
            p
        }
    })
}

impl VertexModel {
    /// The unit model of a frustum whose sidewalls run `slope` (0 <= slope < 1) per unit height,
    /// of `material` (in vertex axes).
    pub fn new(slope: f64, material: &Elasticity, grading: VertexGrading) -> FeResult<Self> {
        if !(0.0..0.9).contains(&slope) {
            return Err(FeError::SolidInput {
                detail: format!("vertex sidewall slope {slope} (run per height)"),
                hint: "a vertex submodel needs sidewalls steeper than 48 deg (run < 0.9 height)",
            });
        }
        Self::build(slope, material, grading, true)
    }

    /// The whole cube of material (no frustum, no free faces): what a uniform strain is exact
    /// on, to test the driving and the nesting.
    #[cfg(test)]
    pub(crate) fn full_cube(material: &Elasticity, grading: VertexGrading) -> FeResult<Self> {
        Self::build(0.0, material, grading, false)
    }

    fn build(
        slope: f64,
        material: &Elasticity,
        grading: VertexGrading,
        cone: bool,
    ) -> FeResult<Self> {
        let lines = grading.lines();
        let mut grid = HexGrid::new(&lines, &lines, &lines)?.with_map(map(slope));
        if cone {
            grid.assign(|c| (c[2] < 0.0 || (c[0] > 0.0 && c[1] > 0.0)).then_some(0));
        }
        let mut p = SolidProblem::new(grid, vec![*material]);
        for axis in [Axis3::X, Axis3::Y, Axis3::Z] {
            for at_um in [-1.0, 1.0] {
                p.constraints
                    .push(Constraint::clamp("driven", NodeSet::Plane { axis, at_um }));
            }
        }
        // Read for stresses only: no refinement step (its residual is ~1e-9 of the drive).
        let model = SolidModel::new(&p)?.without_refinement();
        Ok(VertexModel {
            dofs: model.n_free_dofs(),
            model,
            lines,
            slope,
        })
    }

    /// The unmapped point of mapped unit point `p` (the map inverted exactly).
    fn unmap(&self, p: [f64; 3]) -> [f64; 3] {
        if p[2] > 0.0 {
            let k = self.slope * p[2];
            [(p[0] - k) / (1.0 - k), (p[1] - k) / (1.0 - k), p[2]]
        } else {
            p
        }
    }

    /// Element and local point of mapped unit point `p`; None outside the material.
    pub fn locate(&self, sol: &SolidSolution, p: [f64; 3]) -> Option<([usize; 3], [f64; 3])> {
        let q = self.unmap(p);
        let n = self.lines.len() - 1;
        // World-to-local round-off, relative to the model (a point on a sidewall of a small
        // model far from the die's origin).
        let tol = 1e-9;
        // Candidate cells per axis: the one holding q, and its neighbour when q is on a line.
        let cells = |v: f64| -> Vec<usize> {
            if !(-1.0 - tol..=1.0 + tol).contains(&v) {
                return Vec::new();
            }
            let i = self.lines.partition_point(|&l| l <= v).clamp(1, n) - 1;
            let mut out = vec![i];
            if (v - self.lines[i]).abs() <= tol && i > 0 {
                out.push(i - 1);
            }
            if (v - self.lines[i + 1]).abs() <= tol && i + 1 < n {
                out.push(i + 1);
            }
            out
        };
        let grid = sol.grid();
        for &i in &cells(q[0]) {
            for &j in &cells(q[1]) {
                for &k in &cells(q[2]) {
                    let e = grid.element([i, j, k]);
                    if grid.material(e).is_none() {
                        continue;
                    }
                    let xi = [(i, q[0]), (j, q[1]), (k, q[2])].map(|(c, v)| {
                        let (a, b) = (self.lines[c], self.lines[c + 1]);
                        (2.0 * (v - a) / (b - a) - 1.0).clamp(-1.0, 1.0)
                    });
                    return Some(([i, j, k], xi));
                }
            }
        }
        None
    }
}

/// The nested submodels of one vertex: each level's size (um) and solution (displacements in
/// vertex axes, m).
#[derive(Debug, Clone)]
pub struct VertexChain<'a> {
    model: &'a VertexModel,
    pub frame: VertexFrame,
    levels: Vec<(f64, SolidSolution)>,
}

impl<'a> VertexChain<'a> {
    /// Drives the unit model at `frame` with half-size `radius_um` from `field` (world point,
    /// um, to displacement in die axes, m), then nests models down to `smallest_um`.
    pub fn solve<D: Fn([f64; 3]) -> Option<[f64; 3]>>(
        model: &'a VertexModel,
        frame: VertexFrame,
        radius_um: f64,
        smallest_um: f64,
        kinematics: DriverKinematics,
        field: &D,
    ) -> FeResult<Self> {
        assert!(
            radius_um > 0.0 && smallest_um > 0.0 && smallest_um <= radius_um,
            "vertex chain: 0 < smallest <= radius"
        );
        let outside = |q: [f64; 3]| FeError::SolidInput {
            detail: format!(
                "the vertex submodel reads the solid at ({:.3}, {:.3}, {:.3}) um, outside it",
                q[0], q[1], q[2]
            ),
            hint: "the vertex submodel must stay inside the solid's material around the vertex",
        };
        let read = |q: [f64; 3]| field(q).ok_or_else(|| outside(q));
        let u0 = read(frame.origin_um)?;
        // The rigid rotation below the vertex, from F by central differences (as the corner's).
        let rotation = match kinematics {
            DriverKinematics::Linear => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            DriverKinematics::Corotated => {
                let c = frame.world_um([0.0, 0.0, -0.5 * radius_um]);
                let h = radius_um / 8.0;
                let mut f = [[0.0; 3]; 3];
                for e in frame.axes() {
                    let ua = read(std::array::from_fn(|i| c[i] + h * e[i]))?;
                    let ub = read(std::array::from_fn(|i| c[i] - h * e[i]))?;
                    for i in 0..3 {
                        let dx = e[i] + (ua[i] - ub[i]) / (2.0 * h * 1e-6);
                        for j in 0..3 {
                            f[i][j] += dx * e[j];
                        }
                    }
                }
                polar_rotation(f)
            }
        };
        let axes = frame.axes();
        // u'(X) = R^T (X - X0 + u(X) - u(X0)) - (X - X0), in vertex axes.
        let driver = |q: [f64; 3]| -> FeResult<[f64; 3]> {
            let u = read(q)?;
            let d: [f64; 3] = std::array::from_fn(|i| (q[i] - frame.origin_um[i]) * 1e-6);
            let x: [f64; 3] = std::array::from_fn(|i| d[i] + u[i] - u0[i]);
            let y: [f64; 3] =
                std::array::from_fn(|j| (0..3).map(|i| rotation[i][j] * x[i]).sum::<f64>());
            let die: [f64; 3] = std::array::from_fn(|i| y[i] - d[i]);
            Ok(axes.map(|e| e[0] * die[0] + e[1] * die[1] + e[2] * die[2]))
        };
        let mut levels: Vec<(f64, SolidSolution)> = Vec::new();
        let mut r = radius_um;
        loop {
            let sol = match levels.last() {
                None => model
                    .model
                    .solve_prescribed(|p| driver(frame.world_um(p.map(|v| v * r))))?,
                Some((r_prev, prev)) => {
                    let k = r / r_prev;
                    model.model.solve_prescribed(|p| {
                        let q = p.map(|v| v * k);
                        let (e, xi) = model.locate(prev, q).ok_or_else(|| FeError::SolidInput {
                            detail: "a nested vertex model's face lies outside the last one".into(),
                            hint: "internal: the nested models share the vertex's cone",
                        })?;
                        prev.displacement_at(e, xi).ok_or(FeError::NonFinite {
                            hint: "internal: a nested vertex model read a void element",
                        })
                    })?
                }
            };
            levels.push((r, sol));
            if r <= smallest_um * (1.0 + 1e-9) {
                break;
            }
            if levels.len() >= MAX_NEST {
                return Err(FeError::TooLarge {
                    detail: format!(
                        "vertex submodels from {radius_um} um down to {smallest_um} um"
                    ),
                    limit: MAX_NEST,
                    hint: "the critical distance is too small against the vertex: check the \
                           fracture toughness and strength",
                });
            }
            r = (r / NEST_RATIO).max(smallest_um);
        }
        Ok(VertexChain {
            model,
            frame,
            levels,
        })
    }

    /// The levels' half-sizes (um), the largest first.
    pub fn radii_um(&self) -> Vec<f64> {
        self.levels.iter().map(|l| l.0).collect()
    }

    /// The level that reads a local point at cube-distance `reach_um` from the vertex: the
    /// smallest whose half-size is at least `reach_um / fraction`.
    fn level_for(&self, reach_um: f64, fraction: f64) -> Option<usize> {
        self.levels
            .iter()
            .rposition(|l| reach_um <= fraction * l.0 * (1.0 + 1e-9))
    }

    /// Displacement (m, in vertex axes with the rigid rotation out) at local point `p_um`, from
    /// level `level`.
    pub fn displacement_local_m(&self, level: usize, p_um: [f64; 3]) -> Option<[f64; 3]> {
        let (r, sol) = &self.levels[level];
        let (e, xi) = self.model.locate(sol, p_um.map(|v| v / r))?;
        sol.displacement_at(e, xi)
    }

    /// Stress (Voigt, Pa, vertex axes) at local point `p_um` from level `level`.
    pub fn stress_local_pa(&self, level: usize, p_um: [f64; 3]) -> Option<[f64; 6]> {
        let (r, sol) = &self.levels[level];
        let (e, xi) = self.model.locate(sol, p_um.map(|v| v / r))?;
        // The unit model's strains are per unit um; the level's lengths are r um.
        sol.stress_at(e, xi).map(|s| s.map(|v| v / r))
    }

    /// A driver for a corner submodel in the solid's axes: the displacement at world point
    /// `q_um` (die axes, m, the rigid rotation out) read from the smallest level that holds
    /// every point within `reach_um` of the vertex inside `fraction` of its size.
    pub fn field_for(
        &self,
        reach_um: f64,
        fraction: f64,
    ) -> impl Fn([f64; 3]) -> Option<[f64; 3]> + '_ {
        let level = self.level_for(reach_um, fraction).unwrap_or(0);
        move |q: [f64; 3]| {
            let u = self.displacement_local_m(level, self.frame.local_um(q))?;
            let a = self.frame.axes();
            Some(std::array::from_fn(|i| {
                a[0][i] * u[0] + a[1][i] * u[1] + a[2][i] * u[2]
            }))
        }
    }
}

/// Where a vertex's reading lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VertexPlace {
    /// On the sphere of the critical distance round the vertex itself (the directions nearer the
    /// vertex than either edge).
    Vertex,
    /// On the cylinder of the critical distance round edge 0 (along x) or 1 (along y), at
    /// `s_um` from the vertex: read directly near the vertex, further out by the edge's
    /// section driven by the nested models.
    Edge { edge: usize, s_um: f64 },
}

/// A vertex's largest principal stress at the critical distance, and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexReading {
    pub stress_pa: f64,
    pub place: VertexPlace,
}

/// Stations read directly on the smallest model, in critical distances from the vertex.
const DIRECT_STATIONS: [f64; 6] = [0.0, 1.0, 2.0, 4.0, 8.0, 12.0];
/// The smallest model's half-size in critical distances: the direct stations within 0.45 of it,
/// its finest cells under a quarter of the distance.
pub const SMALLEST_IN_READS: f64 = 30.0;
/// The first section's station (critical distances) and the sections' radius (of the station's
/// distance): a disc of radius s / 4 round the edge at s, with the critical distance inside it.
const FIRST_SECTION: f64 = 18.0;
const SECTION_RADIUS: f64 = 0.25;
/// Sections reach this fraction of the largest model's size (where a caller's own reading of
/// the edges takes over: `sensor::edge_stress` starts the tooth bases' sections there).
pub const LAST_SECTION: f64 = 0.6;
/// Sections per edge at most (one per octave: 40 octaves span any die down to atoms).
const MAX_SECTIONS: usize = 40;

/// Distance of local point `p` from the nearer edge ray (x >= 0 on the x axis, y >= 0 on the y
/// axis).
fn edge_distance(p: [f64; 3]) -> f64 {
    let norm = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let d0 = if p[0] >= 0.0 { p[1].hypot(p[2]) } else { norm };
    let d1 = if p[1] >= 0.0 { p[0].hypot(p[2]) } else { norm };
    d0.min(d1)
}

impl VertexChain<'_> {
    /// The largest principal stress on the cylinder of radius `read_um` round edge `edge` at
    /// `s_um` from the vertex, read on the smallest model (points nearer the other edge or the
    /// vertex left out); None if none is inside it.
    pub fn direct(&self, edge: usize, s_um: f64, read_um: f64) -> Option<f64> {
        let pi = std::f64::consts::PI;
        let wall = 1f64.atan2(self.model.slope);
        let n = 64;
        (0..=n)
            .filter_map(|q| {
                let th = -pi + (wall + pi) * q as f64 / n as f64;
                self.on_surface(Self::section_point(edge, s_um, read_um, th), read_um)
            })
            .reduce(f64::max)
    }

    /// The largest principal stress at local point `p` on the smallest model, if `p` lies on
    /// the point method's surface (at least `read_um` from both edges) and in the material.
    fn on_surface(&self, p: [f64; 3], read_um: f64) -> Option<f64> {
        use crate::fe::solid::principal::principal_stresses_pa;
        if edge_distance(p) < read_um * (1.0 - 1e-6) {
            return None;
        }
        let s = self.stress_local_pa(self.levels.len() - 1, p)?;
        Some(principal_stresses_pa(&s)[0])
    }

    /// The largest principal stress at `mesh.read_at_um` from edge `edge` at `s_um` from the
    /// vertex, by the edge's section ([`crate::fe::solid::corner`]) on `mesh`, driven by the
    /// smallest model that holds it.
    pub fn section(
        &self,
        edge: usize,
        s_um: f64,
        mesh: CornerMesh,
        material_die: &Elasticity,
        patterns: &SectionPatterns,
    ) -> FeResult<f64> {
        use crate::fe::solid::corner::{solve_corner, CornerFrame, CornerSector};
        let pi = std::f64::consts::PI;
        let wall = 1f64.atan2(self.model.slope);
        let sectors = [CornerSector {
            from_rad: -pi,
            to_rad: wall,
            material: *material_die,
        }];
        let f = &self.frame;
        let (e_s, e_t) = if edge == 0 {
            (f.e_y, f.e_x)
        } else {
            (f.e_x, f.e_y.map(|v| -v))
        };
        let frame = CornerFrame {
            origin_um: f.world_um(Self::section_point(edge, s_um, 0.0, 0.0)),
            e_s,
            e_z: f.e_z,
            e_t,
        };
        let field = self.field_for(s_um + 1.1 * mesh.radius_um, 0.8);
        let corner = solve_corner(
            frame,
            &sectors,
            mesh,
            DriverKinematics::Linear,
            &field,
            patterns,
        )?;
        let ring = corner
            .ring_at(mesh.read_at_um)
            .expect("the mesh places a ring at the read-out");
        Ok(corner.max_principal_on_ring(ring, |k| k == 0, &field)?.0)
    }

    /// Unit vector of the edge's section point at angle `th` (from the edge's across axis into
    /// the frustum towards +z), and the edge's axis.
    fn section_point(edge: usize, s: f64, rho: f64, th: f64) -> [f64; 3] {
        let (a, z) = (rho * th.cos(), rho * th.sin());
        if edge == 0 {
            [s, a, z]
        } else {
            [a, s, z]
        }
    }

    /// The largest principal stress at `read_um` from the vertex's edges and the vertex (the
    /// point method's surface: every point at that distance from the nearest of them) over the
    /// places `only` selects (all if None); sections solved with `rings` rings per octave, of
    /// `material_die` (the material in the solid's axes).
    pub fn critical_stress(
        &self,
        read_um: f64,
        rings: usize,
        material_die: &Elasticity,
        only: Option<VertexPlace>,
        patterns: &SectionPatterns,
    ) -> FeResult<VertexReading> {
        let pi = std::f64::consts::PI;
        let mut best = VertexReading {
            stress_pa: f64::NEG_INFINITY,
            place: VertexPlace::Vertex,
        };
        let mut take = |stress: f64, place: VertexPlace| {
            if stress > best.stress_pa {
                best = VertexReading {
                    stress_pa: stress,
                    place,
                };
            }
        };
        let wanted = |p: VertexPlace| only.is_none_or(|o| o == p);
        let reach = 0.45 * self.levels[self.levels.len() - 1].0;
        // The vertex's own directions: below the street's corner (x, y, z <= 0).
        if wanted(VertexPlace::Vertex) {
            let n = 9;
            for a in 0..=n {
                for b in 0..=n {
                    let phi = pi + 0.5 * pi * a as f64 / n as f64;
                    let theta = 0.5 * pi + 0.5 * pi * b as f64 / n as f64;
                    let p = [
                        read_um * theta.sin() * phi.cos(),
                        read_um * theta.sin() * phi.sin(),
                        read_um * theta.cos(),
                    ];
                    if let Some(v) = self.on_surface(p, read_um) {
                        take(v, VertexPlace::Vertex);
                    }
                }
            }
        }
        // Direct stations on the edges' cylinders.
        for edge in 0..2 {
            for k in DIRECT_STATIONS {
                let s = k * read_um;
                let place = VertexPlace::Edge { edge, s_um: s };
                if s + read_um > reach || !wanted(place) {
                    continue;
                }
                if let Some(v) = self.direct(edge, s, read_um) {
                    take(v, place);
                }
            }
        }
        // Sections further out, driven by the nested models.
        let r0 = self.levels[0].0;
        // Stations halving from the outermost (fixed by the model's size, not by the critical
        // distance) down to the first whose disc holds the critical distance well inside.
        let mut stations = Vec::new();
        let mut s = LAST_SECTION * r0;
        while s >= FIRST_SECTION * read_um * (1.0 - 1e-9) && stations.len() < MAX_SECTIONS {
            stations.push(s);
            s *= 0.5;
        }
        // Independent submodels: solved in parallel, taken in order (the first largest wins).
        let places: Vec<(usize, f64)> = (0..2)
            .flat_map(|edge| stations.iter().map(move |&s| (edge, s)))
            .filter(|&(edge, s)| wanted(VertexPlace::Edge { edge, s_um: s }))
            .collect();
        let values: Vec<f64> = places
            .par_iter()
            .map(|&(edge, s)| {
                let mesh = CornerMesh {
                    radius_um: SECTION_RADIUS * s,
                    read_at_um: read_um,
                    rings_per_octave: rings,
                    octaves_inside: OCTAVES_INSIDE,
                };
                self.section(edge, s, mesh, material_die, patterns)
            })
            .collect::<Vec<_>>()
            .into_iter()
            .collect::<FeResult<_>>()?;
        for (&(edge, s), v) in places.iter().zip(values) {
            take(v, VertexPlace::Edge { edge, s_um: s });
        }
        if best.stress_pa.is_finite() {
            Ok(best)
        } else {
            Err(FeError::SolidInput {
                detail: "no vertex reading (the critical distance lies outside every model)".into(),
                hint: "the vertex submodel needs a critical distance well inside its radius",
            })
        }
    }
}
