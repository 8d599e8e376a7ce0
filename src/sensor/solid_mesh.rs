//! The sensor as a 3D solid, built from the same design as the plate rungs (issue 16): silicon
//! with the etched shape (frustum teeth with {111} sidewalls, supports with the U-channel's {111}
//! walls), the PVDF film under the supports and the film bonded under the plate across the channel
//! floor, on a Plexiglas base or a rigid one. Papers 001 and 002 modelled the sensor this way in
//! ANSYS (SOLID45 for silicon and Plexiglas, SOLID227 for the PVDF).
//!
//! The mesh is a structured grid of 27-node bricks ([`crate::fe::solid`]) whose lines are the
//! design's feature lines. The sloped {111} faces are mapped, not stair-cased: in the teeth layer
//! each tooth's base edge line moves linearly with height to the tooth top's edge, and in the
//! support layer the wall line moves from the support's footprint edge to the channel floor's
//! edge. Every other line between two fixed anchor lines moves in proportion, so no element
//! inverts. z is up from the base's top face (the film under the supports starts there).

use crate::fe::solid::{
    merged_lines, Axis3, Constraint, Elasticity, FaceRect, HexGrid, NodeSet, Outward, SolidLoad,
    SolidProblem, TransverseShear,
};
use crate::fe::{FeError, FeResult};

pub use super::geometry::Base;
use super::geometry::{SensorGeometry, SiliconStiffness};

/// Material indices of the solid model.
pub const SILICON: u16 = 0;
pub const PVDF: u16 = 1;
pub const BASE: u16 = 2;

/// Heights of the layer interfaces (um, z up from the base's top face).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layers {
    /// Bottom of the base (0 for a rigid base).
    pub base_bottom_um: f64,
    /// Top of the support film (its bottom is z = 0).
    pub film_top_um: f64,
    /// Bottom of the film bonded under the plate.
    pub floor_film_bottom_um: f64,
    /// Plate underside (= support height + support film).
    pub plate_bottom_um: f64,
    pub plate_top_um: f64,
    pub teeth_top_um: f64,
}

impl Layers {
    /// The plate's mid-plane, where the plate rungs report their deflection.
    pub fn plate_mid_um(&self) -> f64 {
        0.5 * (self.plate_bottom_um + self.plate_top_um)
    }
}

/// A monotone piecewise-linear map of one coordinate: `from[i] -> to[i]`, identity outside.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseLinear {
    from: Vec<f64>,
    to: Vec<f64>,
}

impl PiecewiseLinear {
    /// Anchors (from, to); an error unless both stay increasing (a map that folds would invert
    /// elements: e.g. tooth bases that merge, a DRC error the FE cannot mesh).
    pub fn new(mut anchors: Vec<(f64, f64)>) -> FeResult<Self> {
        anchors.sort_by(|a, b| a.0.total_cmp(&b.0));
        anchors.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-9);
        if let Some(w) = anchors.windows(2).find(|w| w[1].1 <= w[0].1) {
            return Err(FeError::SolidInput {
                detail: format!(
                    "the etched shape folds: {:.1} -> {:.1} um and {:.1} -> {:.1} um",
                    w[0].0, w[0].1, w[1].0, w[1].1
                ),
                hint: "etched tooth bases or channel walls overlap (see the DRC): fix the design",
            });
        }
        Ok(PiecewiseLinear {
            from: anchors.iter().map(|a| a.0).collect(),
            to: anchors.iter().map(|a| a.1).collect(),
        })
    }

    fn eval(xs: &[f64], ys: &[f64], v: f64) -> f64 {
        if xs.len() < 2 || v <= xs[0] || v >= xs[xs.len() - 1] {
            // Outside the anchors: a shift by the nearest end's displacement (none at the ends
            // the builder uses, which are fixed).
            return match xs.first() {
                Some(&x0) if v <= x0 => v + (ys[0] - x0),
                Some(_) => v + (ys[ys.len() - 1] - xs[xs.len() - 1]),
                None => v,
            };
        }
        let i = xs.partition_point(|&x| x <= v).clamp(1, xs.len() - 1);
        let t = (v - xs[i - 1]) / (xs[i] - xs[i - 1]);
        ys[i - 1] + t * (ys[i] - ys[i - 1])
    }

    /// The mapped coordinate.
    pub fn apply(&self, v: f64) -> f64 {
        Self::eval(&self.from, &self.to, v)
    }

    /// The coordinate that maps to `v`.
    pub fn invert(&self, v: f64) -> f64 {
        Self::eval(&self.to, &self.from, v)
    }
}

/// A load on the top surface: total force over a polygon (um, die coordinates), spread as a
/// uniform pressure over the parts of the polygon where the top surface faces up (tooth tops
/// and the exposed plate; the sloped sidewalls carry none of a flat contact), or one point force.
#[derive(Debug, Clone, PartialEq)]
pub enum TopLoad {
    Patch {
        polygon_um: Vec<(f64, f64)>,
        force_n: f64,
    },
    Point {
        x_um: f64,
        y_um: f64,
        force_n: f64,
    },
}

/// The solid model of a design, ready to factorise.
#[derive(Debug, Clone)]
pub struct SensorSolid {
    pub problem: SolidProblem,
    pub layers: Layers,
    /// The part of the die meshed (x0, x1, y0, y1), um: the whole die or the part below and left
    /// of the mirror lines.
    pub domain_um: (f64, f64, f64, f64),
    /// Mirror lines x = .. and y = .. the part solved is bounded by.
    pub mirror_x_um: Option<f64>,
    pub mirror_y_um: Option<f64>,
    /// Per case, the smallest fraction of a contact's area that found an upward face (1 unless
    /// part of it lies over sidewalls; the pressure there is raised so the total stays the force).
    pub loaded_fraction: Vec<f64>,
    /// The farthest a feature line (an edge of a tooth or an electrode, a wall, a load's side,
    /// an anchor) stands from the mesh line it merged into, um: lines closer than the gap the
    /// grid's [`HexGrid::tolerance_um`] holds merge, the lower kept. 0 when each is a mesh line.
    pub edge_moved_um: f64,
}

impl SensorSolid {
    /// (x, y) um carried into the part solved through its mirrors (the part ends at each mirror
    /// m: [0, m]), and which of x and y was reflected: the whole die's symmetric field at (x, y)
    /// is the part's at the image, with those components reversed.
    pub fn mirror_image_um(&self, (x, y): (f64, f64)) -> ((f64, f64), [bool; 2]) {
        let reflect = |v: f64, mirror: Option<f64>| match mirror {
            Some(m) if v > m => (2.0 * m - v, true),
            _ => (v, false),
        };
        let ((x, fx), (y, fy)) = (reflect(x, self.mirror_x_um), reflect(y, self.mirror_y_um));
        ((x, y), [fx, fy])
    }

    /// Volume of each material (um^3, by [`SILICON`], [`PVDF`], [`BASE`]) in the part solved:
    /// the mapped elements integrated exactly (3x3x3 Gauss points on the quadratic map), so the
    /// solid's silicon can be checked against the etched shape in closed form.
    pub fn material_volumes_um3(&self) -> [f64; 3] {
        use crate::fe::solid::hex27;
        let grid = &self.problem.grid;
        let mut v = [0.0; 3];
        for e in 0..grid.element_count() {
            let Some(m) = grid.material(e) else {
                continue;
            };
            let nodes = grid.element_nodes(e).map(|n| grid.node_position_um(n));
            v[usize::from(m)] += hex27::gauss_points()
                .iter()
                .map(|&(xi, w)| hex27::geometry(&nodes, xi).det_j * w)
                .sum::<f64>();
        }
        v
    }
}

/// Mesh density (the largest in-plane element, um, and the elements through each layer) and how
/// the bricks take their transverse shears.
#[derive(Debug, Clone, PartialEq)]
pub struct SolidMeshOptions {
    pub element_um: f64,
    /// The largest cell across the span (y between the channel walls): the plate bends across
    /// its span, so [`SolidMeshOptions::level`] makes it [`SPAN_REFINEMENT`] times finer there.
    pub span_element_um: f64,
    pub plate_layers: usize,
    pub teeth_layers: usize,
    pub support_layers: usize,
    pub base_layers: usize,
    /// Lines at [`TOOTH_EDGE_GRADING`] plate thicknesses either side of every tooth base edge.
    pub tooth_edge_grading: bool,
    /// The bricks' transverse shear strains ([`TransverseShear::Tied`], the rung's levels: a thin
    /// plate on bricks of several thicknesses does not lock).
    pub shear: TransverseShear,
    /// Grade the hot teeth's base edges locally: the cells either side of such an edge are
    /// bisected toward it down to [`LOCAL_GRADING_CELL`] plate thicknesses (instead of the
    /// [`TOOTH_EDGE_GRADING`] lines), and away from the tooth (beyond [`LOCAL_GRADING_MARGIN`]
    /// plate thicknesses) they merge back into their coarse cell; the finer cells' nodes on its
    /// faces hang. The channel walls' cells are bisected toward the walls the same way and stay
    /// fine along the die.
    pub local_refinement: bool,
    /// The ratio of each brick in the teeth to the next one nearer their base (1: uniform;
    /// [`TEETH_BRICK_GRADING`] on the rung's levels).
    pub teeth_grading: f64,
    /// Every brick of the plate and the teeth bisected this many times through the thickness
    /// (the thickness check's 1): the planes nest, so a coarser field lies in the finer space
    /// and the grading stays.
    pub brick_halvings: u32,
    /// Where the bricks keep all `brick_halvings`: in-plane boxes `[x0, x1, y0, y1]` um
    /// (unmapped, as the plate's top and bottom faces are). Elsewhere each brick's halves
    /// merge back into bricks of `brick_halvings_outside` halvings, whose faces the finer
    /// bricks' nodes hang on. Empty: `brick_halvings` everywhere.
    pub fine_brick_boxes_um: Vec<[f64; 4]>,
    pub brick_halvings_outside: u32,
}

/// The ratio of the upper brick in the teeth to the lower one, at their base \[measured\]: the
/// bricks shrink toward the re-entrant edge the tooth base submodels are driven from. Measured on
/// the bundled `centre-1n` (1 N, level 0, two bricks in the plate and the teeth, against the
/// thickness check's four), the check's estimate of the tooth base went from 3.42 % uniform to
/// 2.88 % at 3 (50 + 150 um), the vertex's from 3.72 % to 1.88 %, the support edge's from 2.13 %
/// to 2.03 %, for the same dofs; grading the plate's bricks toward the teeth as well (3: 2.39,
/// 1.76, 5.41 %; 2: 2.45, 1.70, 4.08 %) coarsens the support edge at the plate's underside.
pub const TEETH_BRICK_GRADING: f64 = 3.0;

/// How far along a graded edge, beyond the tooth's base, its graded cells stay fine, in plate
/// thicknesses \[choice\]: the singular field at a vertex decays over a few plate thicknesses.
pub const LOCAL_GRADING_MARGIN: f64 = 2.0;

/// The cell next to a locally graded edge, at most, in plate thicknesses \[choice\]: the finest
/// cell of [`TOOTH_EDGE_GRADING`].
pub const LOCAL_GRADING_CELL: f64 = 0.5;

/// The coarse cells either side of the line standing for `v` in `lines` (sorted: the nearest
/// within `gap_um`, the gap closer than which the lines were merged, so an edge whose line gave
/// way to a neighbour's is graded at that line), each with the lines bisecting it toward that
/// line until the cell next to it is at most `h_min_um`: (cell's low end, high end, new lines).
/// A grading of ratio 2 whose lines nest, so that the cell merges back whole.
fn bisect_toward(lines: &[f64], v: f64, h_min_um: f64, gap_um: f64) -> Vec<(f64, f64, Vec<f64>)> {
    let Some((c, _)) = lines
        .iter()
        .map(|l| (l - v).abs())
        .enumerate()
        .filter(|&(_, d)| d < gap_um)
        .min_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return Vec::new();
    };
    let v = lines[c];
    let mut out = Vec::new();
    for w in [c.checked_sub(1), Some(c + 1)]
        .into_iter()
        .flatten()
        .filter_map(|i| lines.get(i))
    {
        let mut h = (w - v).abs();
        let dir = (w - v).signum();
        let mut new = Vec::new();
        while h > h_min_um && new.len() < 30 {
            h *= 0.5;
            new.push(v + dir * h);
        }
        if !new.is_empty() {
            out.push((v.min(*w), v.max(*w), new));
        }
    }
    out
}

/// How much finer than elsewhere the levels' cells are across the span (y between the channel
/// walls) \[choice, measured\]. The plate bends across its span, and between the stiff tooth rows
/// the thin plate carries the curvature. On the bundled `centre-1n` (1 N, level 0, 1000 um
/// cells, nonlinear), y cells of 500 um across the span moved the deflection at the load +0.93 %
/// and M2 +0.66 % for 11 % more dofs; 250 um +1.0 % and +0.70 %; 125 um +1.04 % and +0.72 %. By
/// contrast, 250 um in x across the whole die moved them +0.44 % and +0.34 % for 2.3 times the
/// dofs, and 125 um in x and y within 2 mm of the load +0.99 % and +0.55 % for 2 times.
pub const SPAN_REFINEMENT: f64 = 2.0;

/// Where the graded mesh adds lines round a tooth base edge, in plate thicknesses: measured on
/// the bundled design, the band from 0.5 to 2 t off the edges holds the solid's error there (a
/// further pair at 0.25 t moves the deflection 0.035 % and the edge stress 0.5 %; the pair at
/// 0.5 t alone gains under two thirds of what both pairs gain on the deflection).
pub const TOOTH_EDGE_GRADING: [f64; 2] = [0.5, 2.0];

impl SolidMeshOptions {
    /// Level `level` of a refinement sequence: the in-plane size halves every two levels (a
    /// factor sqrt 2 per level) from `coarse_um`; through the thickness two quadratic bricks in
    /// the plate (bending) and in the teeth, one in every other layer (the fill of a 3D factor
    /// grows with the square of the node layers). The teeth's second brick is for the
    /// re-entrant edge at their base, whose field the edge submodels are driven from: measured
    /// on the bundled `centre-1n` (1 N, level 0), one brick of the tooth's 200 um read the tooth
    /// base 2108 MPa, two 2158, and with every brick near the edge halved again (four in the
    /// plate and the teeth) 2181; the deflection moves 0.17 %, for 11 % more time and 8 % more
    /// memory. The teeth's pair is graded toward their base ([`TEETH_BRICK_GRADING`]).
    pub fn level(coarse_um: f64, level: usize) -> Self {
        let element_um = coarse_um / 2f64.sqrt().powi(level as i32);
        SolidMeshOptions {
            element_um,
            span_element_um: element_um / SPAN_REFINEMENT,
            plate_layers: 2,
            teeth_layers: 2,
            support_layers: 1,
            base_layers: 1,
            tooth_edge_grading: false,
            shear: TransverseShear::Tied,
            local_refinement: false,
            teeth_grading: TEETH_BRICK_GRADING,
            brick_halvings: 0,
            fine_brick_boxes_um: Vec::new(),
            brick_halvings_outside: 0,
        }
    }
}

/// The planes of a layer from `a_um` to `b_um` (the first included, the last not): `n` bricks,
/// each `ratio` times the one before it from `a_um`, each then bisected `halvings` times.
fn graded_planes(a_um: f64, b_um: f64, n: usize, ratio: f64, halvings: u32) -> Vec<f64> {
    let n = n.max(1);
    let sizes: Vec<f64> = (0..n).map(|k| ratio.powi(k as i32)).collect();
    let total: f64 = sizes.iter().sum();
    let parts = 1usize << halvings;
    let mut planes = Vec::with_capacity(n * parts);
    let mut z = 0.0;
    for size in sizes {
        for k in 0..parts {
            planes.push(a_um + (b_um - a_um) * (z + size * k as f64 / parts as f64) / total);
        }
        z += size;
    }
    planes
}

/// A coarse cell beside a graded edge line, bisected toward it: from `lo_um` to `hi_um` along
/// `axis`, and the intervals along the other axis where it stays fine.
#[derive(Debug, Clone)]
struct GradedBand {
    axis: usize,
    lo_um: f64,
    hi_um: f64,
    keep_um: Vec<(f64, f64)>,
}

/// Merges the bisected cells back into their coarse cells where they are not needed: over each
/// pair of in-plane units (a band's coarse cell, or a single cell), along each axis whose band
/// is far (no keep interval meets the other unit), and through the thickness over each of
/// `z_groups` (cells `k0 .. k1`: a brick's halves) unless the box meets one of `fine_boxes_um`
/// (`[x0, x1, y0, y1]`, where each cell stays a brick). Cells the merge refuses (void or of two
/// materials, or bent by the node map) stay as they are. Every box merged is a union of whole
/// units and groups, so neighbours nest.
fn merge_back(
    grid: &mut HexGrid,
    bands: &[GradedBand],
    z_groups: &[(usize, usize)],
    fine_boxes_um: &[[f64; 4]],
) {
    let thick = z_groups.iter().any(|&(a, b)| b - a > 1);
    if bands.is_empty() && !thick {
        return;
    }
    let lines: [Vec<f64>; 3] = grid.lines_um().map(<[f64]>::to_vec);
    let tol = 1e-6 * grid.extent_um();
    let index = |axis: usize, v: f64| lines[axis].iter().position(|&l| (l - v).abs() <= tol);
    // Per in-plane axis: units (first cell, end cell, the band's keep intervals if a band).
    type Keep = Vec<(f64, f64)>;
    let units = |axis: usize| -> Vec<(usize, usize, Option<Keep>)> {
        let mut ranges: Vec<(usize, usize, Keep)> = Vec::new();
        for bd in bands.iter().filter(|bd| bd.axis == axis) {
            let (Some(a), Some(b)) = (index(axis, bd.lo_um), index(axis, bd.hi_um)) else {
                continue;
            };
            // Teeth in one row or column share a coarse cell: one band keeps them all.
            match ranges.iter_mut().find(|r| r.0 == a && r.1 == b) {
                Some(r) => r.2.extend(bd.keep_um.iter().copied()),
                None => ranges.push((a, b, bd.keep_um.clone())),
            }
        }
        ranges.sort_by_key(|r| r.0);
        let mut out = Vec::new();
        let mut at = 0;
        for (a, b, keep) in ranges {
            if a < at {
                continue;
            }
            out.extend((at..a).map(|i| (i, i + 1, None)));
            out.push((a, b, Some(keep)));
            at = b;
        }
        out.extend((at..lines[axis].len() - 1).map(|i| (i, i + 1, None)));
        out
    };
    let (ux, uy) = (units(0), units(1));
    // A band unit is far from the other axis's unit when none of its keep intervals meets it.
    let far = |keep: &Option<Vec<(f64, f64)>>, axis: usize, (a, b): (usize, usize)| {
        keep.as_ref().is_some_and(|k| {
            let (c0, c1) = (lines[axis][a], lines[axis][b]);
            !k.iter().any(|&(k0, k1)| c1 > k0 && c0 < k1)
        })
    };
    let singles: Vec<(usize, usize)> = (0..lines[2].len() - 1).map(|k| (k, k + 1)).collect();
    // A box stays fine through the thickness where it meets a fine box.
    let fine = |(a, b): (usize, usize), (c, d): (usize, usize)| {
        fine_boxes_um.iter().any(|f| {
            lines[0][b] > f[0] && lines[0][a] < f[1] && lines[1][d] > f[2] && lines[1][c] < f[3]
        })
    };
    for (x0, x1, kx) in &ux {
        for (y0, y1, ky) in &uy {
            if kx.is_none() && ky.is_none() && !thick {
                continue;
            }
            let merge_x = far(kx, 1, (*y0, *y1));
            let merge_y = far(ky, 0, (*x0, *x1));
            let xs: Vec<(usize, usize)> = if merge_x {
                vec![(*x0, *x1)]
            } else {
                (*x0..*x1).map(|i| (i, i + 1)).collect()
            };
            let ys: Vec<(usize, usize)> = if merge_y {
                vec![(*y0, *y1)]
            } else {
                (*y0..*y1).map(|j| (j, j + 1)).collect()
            };
            for &(a, b) in &xs {
                for &(c, d) in &ys {
                    let zs = if fine((a, b), (c, d)) {
                        &singles
                    } else {
                        z_groups
                    };
                    for &(k0, k1) in zs {
                        if b - a == 1 && d - c == 1 && k1 - k0 == 1 {
                            continue;
                        }
                        // A refused box (void, two materials, bent by the map) stays fine.
                        let _ = grid.merge([a, c, k0], [b, d, k1]);
                    }
                }
            }
        }
    }
}

/// Silicon's elasticity in die axes.
pub fn silicon_elasticity(s: SiliconStiffness) -> Elasticity {
    match s {
        SiliconStiffness::Cubic {
            c11_pa,
            c12_pa,
            c44_pa,
            die_edge,
        } => Elasticity::cubic(c11_pa, c12_pa, c44_pa).in_die_axes(die_edge),
        SiliconStiffness::Isotropic { e_pa, nu } => Elasticity::isotropic(e_pa, nu),
    }
}

/// Lines `lines` with extra ones so no interval `(a, b)` exceeds `max_um(a, b)` (taken as at
/// least `min_um`, so the count stays bounded), and none closer than `min_um` (the later of two
/// near lines is dropped, but the last line, the domain's end at a mirror or the die's edge,
/// stays and the line before it gives way); with the farthest any given line stands from its
/// nearest kept one (a merged edge is meshed at the nearest line: materials go by cell centre).
fn subdivide(
    mut lines: Vec<f64>,
    max_um: impl Fn(f64, f64) -> f64,
    min_um: f64,
) -> (Vec<f64>, f64) {
    lines.sort_by(f64::total_cmp);
    let mut merged: Vec<f64> = Vec::with_capacity(lines.len());
    for &v in &lines {
        match merged.last() {
            Some(&last) if v - last < min_um => {}
            _ => merged.push(v),
        }
    }
    if let (Some(&end), Some(&kept)) = (lines.last(), merged.last()) {
        if end > kept {
            if merged.len() >= 2 {
                merged.pop();
            }
            merged.push(end);
        }
    }
    // Each given line's distance to the nearest kept one.
    let moved_um = lines
        .iter()
        .map(|&v| {
            let i = merged.partition_point(|&m| m < v);
            [i.checked_sub(1), Some(i)]
                .into_iter()
                .flatten()
                .filter_map(|j| merged.get(j))
                .map(|m| (m - v).abs())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    let mut out = Vec::new();
    for w in merged.windows(2) {
        let n = ((w[1] - w[0]) / max_um(w[0], w[1]).max(min_um))
            .ceil()
            .max(1.0) as usize;
        for k in 0..n {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / n as f64);
        }
    }
    if let Some(&last) = merged.last() {
        out.push(last);
    }
    (out, moved_um)
}

/// One axis of the teeth layer: tooth base edges (the lines) move to the tooth top edges at the
/// top; the domain ends stay.
fn teeth_axis_map(edges: &[(f64, f64)], lo: f64, hi: f64) -> FeResult<PiecewiseLinear> {
    // (base, top) per edge, sorted by base.
    let mut e: Vec<(f64, f64)> = edges.to_vec();
    e.sort_by(|a, b| a.0.total_cmp(&b.0));
    e.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-6);
    // No fixed anchors between edges: the streets widen and the teeth narrow towards the top,
    // which keeps the map increasing while every tooth top has a width (streets are void there).
    let mut anchors = vec![(lo, lo), (hi, hi)];
    for &(base, top) in &e {
        if base > lo + 1e-6 && base < hi - 1e-6 {
            anchors.push((base, top));
        }
    }
    PiecewiseLinear::new(anchors)
}

/// The die's tooth frusta as (x base edges, y base edges) with their top positions, and the
/// mid-street anchors each axis needs.
struct ToothEdges {
    x: Vec<(f64, f64)>,
    y: Vec<(f64, f64)>,
}

fn tooth_edges(g: &SensorGeometry) -> ToothEdges {
    let e = &g.etched;
    let ro = e.tooth_run_out_um;
    let (l, w) = (g.length_um, g.width_um);
    let mut x = Vec::new();
    let mut y = Vec::new();
    for t in &e.tooth_tops_um {
        // A base reaching past the die edge is cut there by the saw: that face stays vertical.
        let cut = |base: f64, top: f64, lo: f64, hi: f64| {
            if base < lo || base > hi {
                (top.clamp(lo, hi), top.clamp(lo, hi))
            } else {
                (base, top)
            }
        };
        x.push(cut(t[0] - ro, t[0], 0.0, l));
        x.push(cut(t[2] + ro, t[2], 0.0, l));
        y.push(cut(t[1] - ro, t[1], 0.0, w));
        y.push(cut(t[3] + ro, t[3], 0.0, w));
    }
    ToothEdges { x, y }
}

/// Characteristic length of the support on its film, a beam on an elastic foundation:
/// lambda = (4 D / k)^(1/4) with D = Q22 d^3 / 12 the support's bending stiffness across its
/// width and k = E_oed / t_f the film's stiffness per area, E_oed = E (1 - nu) / ((1 + nu)(1 - 2
/// nu)) for a film bonded on both faces (Hetenyi, Beams on Elastic Foundation, 1946, ch. 2).
pub fn foundation_length_um(g: &SensorGeometry) -> f64 {
    let d = g.etched.support_height_um * 1e-6;
    let dd = g.material.bending_stiffness(d).d22_nm;
    let nu = g.pvdf_nu;
    let e_oed = g.pvdf_e_pa * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let k = e_oed / (g.film_thickness_um * 1e-6);
    (4.0 * dd / k).powf(0.25) * 1e6
}

/// Builds the solid model for the given top loads (one load case each); the teeth in
/// `graded_teeth` (indices into the etched tooth tops) get the [`TOOTH_EDGE_GRADING`] lines
/// round their base edges, every tooth does under `opts.tooth_edge_grading`.
pub fn build(
    g: &SensorGeometry,
    cases: &[Vec<TopLoad>],
    base: Base,
    opts: SolidMeshOptions,
    graded_teeth: &[usize],
    mirror_x_um: Option<f64>,
    mirror_y_um: Option<f64>,
) -> FeResult<SensorSolid> {
    let et = &g.etched;
    let (l, w) = (g.length_um, g.width_um);
    let f = g.film_thickness_um;
    let d = et.support_height_um;
    let t = g.plate_thickness_um;
    let h = et.tooth_height_um;
    if !(d > f + 1.0 && t > 0.0 && f > 0.0) {
        return Err(FeError::SolidInput {
            detail: format!(
                "support height {d:.1} um, film {f:.1} um, plate {t:.1} um: the film under the \
                 plate must fit in the channel"
            ),
            hint: "the solid model needs a channel deeper than the PVDF film",
        });
    }
    let layers = Layers {
        base_bottom_um: match base {
            Base::Rigid => 0.0,
            Base::Elastic { thickness_um, .. } => -thickness_um,
        },
        film_top_um: f,
        floor_film_bottom_um: d,
        plate_bottom_um: f + d,
        plate_top_um: f + d + t,
        teeth_top_um: f + d + t + if et.tooth_tops_um.is_empty() { 0.0 } else { h },
    };
    let x_hi = mirror_x_um.unwrap_or(l);
    let y_hi = mirror_y_um.unwrap_or(w);
    let teeth = tooth_edges(g);
    let tx = teeth_axis_map(&teeth.x, 0.0, l)?;
    let ty = teeth_axis_map(&teeth.y, 0.0, w)?;
    // The channel walls: support 1's wall line sits at the floor edge y0 and moves to the
    // footprint edge at the support's bottom; support 2 mirrors it. Anchors one wall run out on
    // either side stay.
    let (e1, y0) = (et.support_edge_y_um, g.plate_y0_um);
    let (e2, y1) = (w - et.support_edge_y_um, g.plate_y1_um);
    let run = (y0 - e1).max(0.0);
    // Fixed anchors one run beyond either side of each wall (within the support and the span).
    let wall_anchors = [
        (e1 - run).max(0.5 * e1),
        (y0 + run).min(0.5 * (y0 + y1)),
        (y1 - run).max(0.5 * (y0 + y1)),
        (e2 + run).min(0.5 * (e2 + w)),
    ];
    let wall = PiecewiseLinear::new(vec![
        (0.0, 0.0),
        (wall_anchors[0], wall_anchors[0]),
        (y0, e1),
        (wall_anchors[1], wall_anchors[1]),
        (wall_anchors[2], wall_anchors[2]),
        (y1, e2),
        (wall_anchors[3], wall_anchors[3]),
        (w, w),
    ])?;

    // In-plane lines (before the map): die ends, mirrors, electrodes, tooth base edges and the
    // anchors, the walls, and each load polygon's vertices at plate level and at tooth-top level.
    // The centre lines always: the whole die's mesh is then its mirrored parts' union.
    let mut xs = vec![0.0, l, x_hi, 0.5 * l];
    let mut ys = vec![0.0, w, y_hi, 0.5 * w, y0, y1];
    ys.extend(wall_anchors);
    // The support on its film is a beam on an elastic foundation: the load it takes at the wall
    // decays (and changes sign) over its characteristic length, which the lines resolve.
    let lambda = foundation_length_um(g);
    for k in [0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0] {
        let at = e1 - k * lambda;
        if at > 0.0 {
            let orig = wall.invert(at);
            ys.extend([orig, w - orig]);
        }
    }
    for el in &g.electrodes {
        xs.extend([el.x0_um, el.x1_um]);
        ys.extend([el.y0_um, el.y1_um]);
    }
    xs.extend(tx.from.iter().copied());
    ys.extend(ty.from.iter().copied());
    // `tooth_edges` lists each tooth's two edges in turn: edges 2 i and 2 i + 1 are tooth i's.
    let graded = |edge: usize| opts.tooth_edge_grading || graded_teeth.contains(&(edge / 2));
    // A listed tooth beyond a mirror is graded as its image in the part solved (the list may
    // come from a plate solved whole or in another part).
    let images = |v: f64, m: Option<f64>| -> [Option<f64>; 2] {
        [
            Some(v),
            m.filter(|_| !opts.tooth_edge_grading).map(|m| 2.0 * m - v),
        ]
    };
    for k in TOOTH_EDGE_GRADING.iter().filter(|_| !opts.local_refinement) {
        for (_, e) in teeth.x.iter().enumerate().filter(|(i, _)| graded(*i)) {
            for v in [e.0 - k * t, e.0 + k * t] {
                xs.extend(images(v, mirror_x_um).into_iter().flatten());
            }
        }
        for (_, e) in teeth.y.iter().enumerate().filter(|(i, _)| graded(*i)) {
            for v in [e.0 - k * t, e.0 + k * t] {
                ys.extend(images(v, mirror_y_um).into_iter().flatten());
            }
        }
    }
    for case in cases {
        for load in case {
            let pts: Vec<(f64, f64)> = match load {
                TopLoad::Patch { polygon_um, .. } => polygon_um.clone(),
                TopLoad::Point { x_um, y_um, .. } => vec![(*x_um, *y_um)],
            };
            for (px, py) in pts {
                xs.extend([px, tx.invert(px)]);
                ys.extend([py, ty.invert(py)]);
            }
        }
    }
    let clip = |v: &mut Vec<f64>, hi: f64| v.retain(|&c| (0.0..=hi + 1e-9).contains(&c));
    clip(&mut xs, x_hi);
    clip(&mut ys, y_hi);
    // Lines closer than this merge (the lower kept): a drawn edge may stand up to it off its
    // line, which the grid's tolerance tells its readers.
    let gap_um = (0.02 * opts.element_um.min(t)).max(1.0);
    let (mut xs, x_moved_um) = subdivide(xs, |_, _| opts.element_um, gap_um);
    // Across the span (between the walls at the plate's underside) finer, the plate bending
    // there ([`SPAN_REFINEMENT`]).
    let y_cell_um = |a: f64, b: f64| {
        if a >= y0 - 1e-6 && b <= y1 + 1e-6 {
            opts.span_element_um.min(opts.element_um)
        } else {
            opts.element_um
        }
    };
    let (mut ys, y_moved_um) = subdivide(ys, y_cell_um, gap_um);
    // Local grading: the cells either side of a graded edge bisected toward it; away from its
    // tooth they merge back (below, once the map is set).
    let mut bands = Vec::new();
    if opts.local_refinement {
        // The channel walls meet the plate's underside in a re-entrant edge along the whole
        // die, whose peak may sit anywhere along it: their cells are bisected toward the wall
        // line and stay fine along the die (they are the teeth bands' coarse cells).
        let coarse = ys.clone();
        for v in [y0, y1].into_iter().filter(|&v| v < y_hi - 1e-6) {
            for (_, _, new) in bisect_toward(&coarse, v, LOCAL_GRADING_CELL * t, gap_um) {
                ys.extend(new);
            }
        }
        ys = merged_lines(ys);
        let margin = LOCAL_GRADING_MARGIN * t;
        for (axis, edges, others, mirror, other_mirror) in [
            (0, &teeth.x, &teeth.y, mirror_x_um, mirror_y_um),
            (1, &teeth.y, &teeth.x, mirror_y_um, mirror_x_um),
        ] {
            let lines = if axis == 0 { &mut xs } else { &mut ys };
            let coarse = lines.clone();
            for (i, e) in edges.iter().enumerate().filter(|(i, _)| graded(*i)) {
                let tooth = i / 2;
                let (o0, o1) = (others[2 * tooth].0, others[2 * tooth + 1].0);
                let mut keep = vec![(o0.min(o1) - margin, o0.max(o1) + margin)];
                if let Some(m) = other_mirror {
                    keep.push((2.0 * m - o0.max(o1) - margin, 2.0 * m - o0.min(o1) + margin));
                }
                for v in images(e.0, mirror).into_iter().flatten() {
                    for (lo_um, hi_um, new) in
                        bisect_toward(&coarse, v, LOCAL_GRADING_CELL * t, gap_um)
                    {
                        lines.extend(new);
                        bands.push(GradedBand {
                            axis,
                            lo_um,
                            hi_um,
                            keep_um: keep.clone(),
                        });
                    }
                }
            }
            *lines = merged_lines(std::mem::take(lines));
        }
    }
    let mut zs = Vec::new();
    // Uniform layers: the same planes as a graded layer of ratio 1, never bisected.
    let layer = |zs: &mut Vec<f64>, a: f64, b: f64, n: usize| {
        zs.extend(graded_planes(a, b, n, 1.0, 0));
    };
    if let Base::Elastic { thickness_um, .. } = base {
        layer(&mut zs, -thickness_um, 0.0, opts.base_layers);
    }
    layer(&mut zs, 0.0, f, 1);
    layer(&mut zs, f, d, opts.support_layers);
    layer(&mut zs, d, f + d, 1);
    // At most 16 bricks per brick: the check asks for 1.
    let halvings = opts.brick_halvings.min(4);
    // Away from the fine boxes each brick's halves merge back in groups of this many cells.
    let group = if opts.fine_brick_boxes_um.is_empty() {
        1
    } else {
        1usize << (halvings - opts.brick_halvings_outside.min(halvings))
    };
    let below_plate = zs.len();
    let (n, q) = (opts.plate_layers, 1.0);
    zs.extend(graded_planes(f + d, f + d + t, n, q, halvings));
    if !et.tooth_tops_um.is_empty() {
        let (n, q) = (opts.teeth_layers, opts.teeth_grading);
        zs.extend(graded_planes(f + d + t, f + d + t + h, n, q, halvings));
    }
    let z_groups: Vec<(usize, usize)> = (0..below_plate)
        .map(|k| (k, k + 1))
        .chain(
            (below_plate..zs.len())
                .step_by(group)
                .map(|k| (k, k + group)),
        )
        .collect();
    zs.push(layers.teeth_top_um);

    let mut grid = HexGrid::new(&xs, &ys, &zs)?.with_tolerance_um(gap_um);
    // Materials by logical position (the unmapped element's centre).
    let tooth_top = |xc: f64, yc: f64| {
        et.tooth_tops_um.iter().any(|tt| {
            // Logical (unmapped) tooth column: between its base edge lines.
            let (bx0, bx1) = (tx.invert(tt[0]), tx.invert(tt[2]));
            let (by0, by1) = (ty.invert(tt[1]), ty.invert(tt[3]));
            xc > bx0 && xc < bx1 && yc > by0 && yc < by1
        })
    };
    let under_support = |yc: f64| yc < y0 || yc > y1;
    let lay = layers;
    let has_base = matches!(base, Base::Elastic { .. });
    grid.assign(|[xc, yc, zc]| {
        if zc < 0.0 {
            has_base.then_some(BASE)
        } else if zc < lay.film_top_um {
            under_support(yc).then_some(PVDF)
        } else if zc < lay.floor_film_bottom_um {
            under_support(yc).then_some(SILICON)
        } else if zc < lay.plate_bottom_um {
            Some(if under_support(yc) { SILICON } else { PVDF })
        } else if zc < lay.plate_top_um {
            Some(SILICON)
        } else {
            tooth_top(xc, yc).then_some(SILICON)
        }
    });
    let map_lay = layers;
    let (txm, tym, wallm) = (tx.clone(), ty.clone(), wall.clone());
    let grid = grid.with_map(std::sync::Arc::new(move |[x, y, z]: [f64; 3]| {
        let (mut xo, mut yo) = (x, y);
        if z > map_lay.plate_top_um {
            // Teeth: base edges at the plate top, top edges at the tooth top.
            let s = (z - map_lay.plate_top_um) / (map_lay.teeth_top_um - map_lay.plate_top_um);
            xo = x + s * (txm.apply(x) - x);
            yo = y + s * (tym.apply(y) - y);
        } else if z < map_lay.plate_bottom_um {
            // Walls: the floor edge at the plate's underside, the footprint edge at the
            // support's bottom and below.
            let s = ((map_lay.plate_bottom_um - z)
                / (map_lay.plate_bottom_um - map_lay.film_top_um))
                .min(1.0);
            yo = y + s * (wallm.apply(y) - y);
        }
        [xo, yo, z]
    }));

    let mut grid = grid;
    merge_back(&mut grid, &bands, &z_groups, &opts.fine_brick_boxes_um);

    let silicon = silicon_elasticity(g.silicon);
    let pvdf = Elasticity::isotropic(g.pvdf_e_pa, g.pvdf_nu);
    let base_el = match base {
        Base::Elastic { e_pa, nu, .. } => Elasticity::isotropic(e_pa, nu),
        Base::Rigid => pvdf,
    };
    let mut problem = SolidProblem::new(grid, vec![silicon, pvdf, base_el]);
    problem.shear = opts.shear;
    problem.constraints.push(Constraint::clamp(
        "base",
        NodeSet::Plane {
            axis: Axis3::Z,
            at_um: layers.base_bottom_um,
        },
    ));
    if let Some(m) = mirror_x_um {
        problem
            .constraints
            .push(Constraint::symmetry("mirror_x", Axis3::X, m));
    }
    if let Some(m) = mirror_y_um {
        problem
            .constraints
            .push(Constraint::symmetry("mirror_y", Axis3::Y, m));
    }
    let mut loaded_fraction = Vec::new();
    for case in cases {
        let (loads, frac) = top_loads(&problem, case, (x_hi, y_hi), (mirror_x_um, mirror_y_um));
        problem.load_cases.push(loads);
        loaded_fraction.push(frac);
    }
    Ok(SensorSolid {
        problem,
        layers,
        domain_um: (0.0, x_hi, 0.0, y_hi),
        mirror_x_um,
        mirror_y_um,
        loaded_fraction,
        edge_moved_um: x_moved_um.max(y_moved_um),
    })
}

/// The top faces of every column, with their physical rectangles, as pressure loads: for each
/// patch the pressure on a face is the patch's force per covered area times the face's covered
/// fraction. A patch cut by a mirror line keeps the part inside the domain with the force of that
/// part (the mirror holds the rest).
fn top_loads(
    problem: &SolidProblem,
    case: &[TopLoad],
    (x_hi, y_hi): (f64, f64),
    mirrors: (Option<f64>, Option<f64>),
) -> (Vec<SolidLoad>, f64) {
    use crate::fe::clip::{clip_polygon, polygon_area};
    let grid = &problem.grid;
    let [xs, ys, zs] = grid.lines_um();
    let [nx, ny, nz] = grid.n_elements();
    // Top active element and its face's physical rectangle per column.
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let Some(k) = (0..nz)
                .rev()
                .find(|&k| grid.cell_material(grid.element([i, j, k])).is_some())
            else {
                continue;
            };
            let corner = |ii: usize, jj: usize| {
                grid.node_position_um(grid.node([2 * ii, 2 * jj, 2 * (k + 1)]))
            };
            let (a, b) = (corner(i, j), corner(i + 1, j + 1));
            faces.push((i, j, k, [a[0], a[1], b[0], b[1]]));
        }
    }
    let mut out = Vec::new();
    let mut frac: f64 = 1.0;
    for load in case {
        match load {
            TopLoad::Point {
                x_um,
                y_um,
                force_n,
            } => {
                // The image in the domain; a point on a mirror carries half (quarter) there.
                let share = [
                    mirrors.0.map(|m| (x_um - m).abs() < 1e-6),
                    mirrors.1.map(|m| (y_um - m).abs() < 1e-6),
                ]
                .iter()
                .filter(|v| **v == Some(true))
                .fold(1.0, |a, _| a * 0.5);
                let Some((_, _, k, _)) = faces.iter().find(|(_, _, _, r)| {
                    *x_um >= r[0] && *x_um <= r[2] && *y_um >= r[1] && *y_um <= r[3]
                }) else {
                    continue;
                };
                out.push(SolidLoad::Point {
                    at_um: [*x_um, *y_um, zs[k + 1]],
                    force_n: [0.0, 0.0, -force_n * share],
                    snap: crate::fe::solid::Snap::Nearest,
                });
            }
            TopLoad::Patch {
                polygon_um,
                force_n,
            } => {
                let area = polygon_area(polygon_um).abs();
                if area <= 0.0 {
                    continue;
                }
                let inside = polygon_area(&clip_polygon(polygon_um, 0.0, 0.0, x_hi, y_hi)).abs();
                let want = force_n * inside / area;
                let mut covered = Vec::new();
                for &(i, j, k, r) in &faces {
                    let a = polygon_area(&clip_polygon(polygon_um, r[0], r[1], r[2], r[3])).abs();
                    if a > 1e-9 * area {
                        covered.push((i, j, k, r, a));
                    }
                }
                let covered_area: f64 = covered.iter().map(|c| c.4).sum();
                if covered_area <= 0.0 {
                    continue;
                }
                let p = want / (covered_area * 1e-12);
                for (i, j, k, r, a) in covered {
                    let face_area = (r[2] - r[0]) * (r[3] - r[1]);
                    out.push(SolidLoad::Pressure {
                        face: FaceRect {
                            axis: Axis3::Z,
                            at_um: zs[k + 1],
                            outward: Outward::Plus,
                            from_um: [xs[i], ys[j]],
                            to_um: [xs[i + 1], ys[j + 1]],
                        },
                        pressure_pa: p * a / face_area,
                    });
                }
                frac = frac.min(covered_area / inside);
            }
        }
    }
    (out, frac)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lines closer than the gap merge into the lower, and say how far a given line stands
    /// from its nearest kept one; the domain's ends (a mirror, the die's edge) stay where they
    /// are, so a mirror's constraint always finds its plane.
    #[test]
    fn near_lines_merge_but_the_domains_ends_stay() {
        let coarse = |_: f64, _: f64| 1e9;
        for (given, kept, moved) in [
            (
                vec![0.0, 1000.0, 1000.4, 3000.0],
                vec![0.0, 1000.0, 3000.0],
                0.4,
            ),
            (
                vec![3000.0, 0.0, 1000.0, 2999.5, 0.3],
                vec![0.0, 1000.0, 3000.0],
                0.5,
            ),
            // Everything within the gap: both ends still.
            (vec![0.0, 0.2, 0.5], vec![0.0, 0.5], 0.2),
        ] {
            let (l, m) = subdivide(given.clone(), coarse, 1.0);
            assert_eq!(l, kept, "{given:?}");
            assert!((m - moved).abs() < 1e-9, "{given:?}: {m}");
        }
        // Subdivided evenly, none wider than asked.
        let (l, _) = subdivide(vec![0.0, 1000.0], |_, _| 300.0, 1.0);
        assert_eq!(l, vec![0.0, 250.0, 500.0, 750.0, 1000.0]);
    }

    /// An edge whose line gave way to a neighbour's within the gap is graded at that line, as
    /// an edge on it; one farther than the gap from every line is not graded.
    #[test]
    fn an_edge_merged_into_a_neighbours_line_is_graded_there() {
        let lines = [0.0, 1000.0, 3000.0];
        let on = bisect_toward(&lines, 1000.0, 100.0, 1.0);
        assert_eq!(
            on,
            vec![
                (0.0, 1000.0, vec![500.0, 750.0, 875.0, 937.5]),
                (1000.0, 3000.0, vec![2000.0, 1500.0, 1250.0, 1125.0, 1062.5]),
            ]
        );
        assert_eq!(bisect_toward(&lines, 1000.4, 100.0, 1.0), on);
        assert!(bisect_toward(&lines, 1001.5, 100.0, 1.0).is_empty());
    }

    /// A graded layer's bricks grow by the ratio from its first plane and fill it; bisected,
    /// every plane stays (the spaces nest) and the grading with it.
    #[test]
    fn graded_bricks_nest_when_bisected() {
        let close = |a: &[f64], b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
        };
        let coarse = graded_planes(100.0, 300.0, 2, 3.0, 0);
        assert!(close(&coarse, &[100.0, 150.0]), "{coarse:?}");
        let fine = graded_planes(100.0, 300.0, 2, 3.0, 1);
        assert!(close(&fine, &[100.0, 125.0, 150.0, 225.0]), "{fine:?}");
        assert!(close(
            &graded_planes(0.0, 30.0, 3, 1.0, 0),
            &[0.0, 10.0, 20.0]
        ));
        // No bricks asked for: one.
        assert_eq!(graded_planes(0.0, 1.0, 0, 3.0, 0), vec![0.0]);
    }
}
