//! The stress near a sharp re-entrant edge of a solved solid (issue 16, item 7): a 2-D submodel of
//! the edge's cross-section, driven by the solid's displacement field, on a mesh graded towards
//! the edge.
//!
//! At a straight re-entrant edge (a tooth's base, the U-channel's wall meeting the plate) the
//! elastic stress is singular, sigma ~ r^(lambda - 1) with 1/2 < lambda < 1 (Williams 1952, J.
//! Appl. Mech. 19: 526), so the solid's peak stress grows with its mesh and has no limit. What
//! does converge is the field at a stated distance from the edge. The submodel resolves it: a disc
//! (or disc sector) of radius R around the edge in the plane normal to it, polar 9-node
//! quadrilaterals in rings graded geometrically towards the edge (a fixed number per octave of
//! r, so every ring sees the singular field alike), each angular sector its own material. The
//! solid's displacement is prescribed on the arc r = R (the cut boundary of a classical
//! submodel, e.g. Cormier, Smallwood, Sinclair, Meda 1999, Int. J. Numer. Meth. Eng. 46: 889);
//! the faces of the sectors that meet no other sector are free. Along the edge the field is
//! smooth, so the section is in generalised plane strain: the displacement's derivative along
//! the edge, du/dt, is the solid's (taken by a central difference), and every node carries all
//! three displacement components, so anisotropic materials couple in-plane and out-of-plane
//! strains as they do in the solid.
//!
//! A geometrically nonlinear solid is read in a corotated frame: the rigid rotation of the edge's
//! neighbourhood (the polar decomposition F = R U of the solid's deformation gradient there) is
//! taken out of the driver, and the submodel is linear in what remains (strains of 1e-3: the
//! second Piola-Kirchhoff stress of St. Venant-Kirchhoff and the linear stress differ by that
//! order).

use std::sync::{Arc, Mutex};

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Mat, Side};

use super::elasticity::{Elasticity, VOIGT};
use super::principal::principal_stresses_pa;
use crate::fe::{FeError, FeResult};

/// A corner's frame in the solid: the edge point and three orthonormal axes (s across the edge
/// in the section plane, z the section's other axis, t along the edge).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerFrame {
    pub origin_um: [f64; 3],
    pub e_s: [f64; 3],
    pub e_z: [f64; 3],
    pub e_t: [f64; 3],
}

/// One angular sector of the section, from `from_rad` to `to_rad` (counter-clockwise from +s
/// towards +z), of one material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerSector {
    pub from_rad: f64,
    pub to_rad: f64,
    pub material: Elasticity,
}

/// How the driver's displacement is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriverKinematics {
    /// A small-strain solid: its displacement as it is.
    Linear,
    /// A geometrically nonlinear solid: its local rigid rotation taken out first.
    Corotated,
}

/// The submodel's mesh: radius, the distance at which the stress is read, and the refinement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerMesh {
    pub radius_um: f64,
    /// The ring the stress is read on; rings are placed so one lies exactly here.
    pub read_at_um: f64,
    /// Rings per octave of r (1, 2, 4, ...); the sectors' elements are at most 30 deg / this wide.
    pub rings_per_octave: usize,
    /// Octaves of rings inside `read_at_um`.
    pub octaves_inside: usize,
}

/// Octaves of rings inside the read-out ring \[choice\]: every section (the edges', the vertices'
/// and the plate rungs' tooth base) is graded alike there.
pub const OCTAVES_INSIDE: usize = 3;

/// Inside this fraction of the radius du/dt is the edge's own (most of the graded rings: it
/// saves most of the driver's reads).
const CONSTANT_DT_FRACTION: f64 = 1.0 / 64.0;

/// Most elements a corner submodel may have (bounds the work before allocating).
pub const MAX_CORNER_ELEMENTS: usize = 200_000;

/// A section's sparsity pattern, the order its assembled values fill it in, and its symbolic
/// factorisation.
#[derive(Debug)]
struct SectionPattern {
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    llt: SymbolicLlt<usize>,
}

/// What fixes a section's pattern: its rings, its elements round the edge, and whether it wraps
/// (the free dofs and the element order follow from these).
type SectionTopology = (usize, usize, bool);

/// Patterns and symbolic factorisations of corner sections by their topology, shared by every
/// section solved with the same cache (the pattern once, the values many times, as faer's
/// sparse solvers are built to be used): one read-out's sections repeat a few topologies (the
/// stations of one edge kind share one; a vertex's two edges, and two vertices, share each
/// station's). Values, and so every answer, are as without it. Drop it with the read-out: its
/// entries are a few MB each.
#[derive(Debug, Default)]
pub struct SectionPatterns(Mutex<Vec<(SectionTopology, Arc<SectionPattern>)>>);

impl SectionPatterns {
    fn get(&self, key: SectionTopology) -> Option<Arc<SectionPattern>> {
        let cache = self.0.lock().unwrap_or_else(|e| e.into_inner());
        cache
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, p)| p.clone())
    }

    /// Topologies held.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    fn insert(&self, key: SectionTopology, pattern: Arc<SectionPattern>) {
        let mut cache = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if !cache.iter().any(|(k, _)| *k == key) {
            cache.push((key, pattern));
        }
    }
}

/// A solved corner submodel.
#[derive(Debug, Clone)]
pub struct CornerSolution {
    frame: CornerFrame,
    sectors: Vec<CornerSector>,
    /// Element angles: (from, to, sector index).
    angles: Vec<(f64, f64, usize)>,
    /// Ring radii, m: rings[0] = 0, last = R.
    rings_m: Vec<f64>,
    wraps: bool,
    /// Displacement per node (3 components, m).
    u: Vec<[f64; 3]>,
    /// The local rigid rotation taken out of the driver (du/dt is read again from the driver
    /// where a stress is wanted).
    rotation: [[f64; 3]; 3],
    /// Free dofs solved.
    pub dofs: usize,
}

const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Quadratic Lagrange basis on (-1, 0, 1) and its derivative.
fn lagrange2(x: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)],
        [x - 0.5, -2.0 * x, x + 0.5],
    )
}

fn add3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale3(a: [f64; 3], k: f64) -> [f64; 3] {
    a.map(|v| v * k)
}
fn matvec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}
fn transpose(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[j][i]))
}

/// The symmetric (mode I) exponent lambda of a re-entrant wedge of material angle `angle_rad`
/// (pi to 2 pi) with free faces, isotropic: the root in (1/2, 1) of lambda sin(2 a) + sin(2
/// lambda a) = 0, a = angle / 2 (Williams 1952, J. Appl. Mech. 19: 526, Eq. 8); 0.634 for the
/// {111} corners' 234.74 deg.
pub fn williams_exponent(angle_rad: f64) -> f64 {
    let a = 0.5 * angle_rad.clamp(std::f64::consts::PI + 1e-9, std::f64::consts::TAU);
    let f = |l: f64| l * (2.0 * a).sin() + (2.0 * l * a).sin();
    let (mut lo, mut hi) = (0.5, 1.0 - 1e-12);
    if f(lo) * f(hi) > 0.0 {
        return 0.5;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// [`williams_exponent`] of the tooth's base edge, where a {111} sidewall (54.74 deg) meets the
/// (100) plate: material angle 234.74 deg, lambda 0.634.
pub fn tooth_base_exponent() -> f64 {
    williams_exponent(std::f64::consts::PI + 54.7356f64.to_radians())
}

/// Rotation of the polar decomposition F = R U by Higham's iteration R <- (R + R^-T) / 2
/// (Higham 1986, SIAM J. Sci. Stat. Comput. 7: 1160), which converges quadratically.
pub fn polar_rotation(f: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut r = f;
    for _ in 0..50 {
        let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
            - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        if det.abs() < 1e-300 || !det.is_finite() {
            break;
        }
        // R^-T = cofactor(R) / det.
        let cof = |i: usize, j: usize| {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            r[i1][j1] * r[i2][j2] - r[i1][j2] * r[i2][j1]
        };
        let next: [[f64; 3]; 3] =
            [0, 1, 2].map(|i| [0, 1, 2].map(|j| 0.5 * (r[i][j] + cof(i, j) / det)));
        let change: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (next[i][j] - r[i][j]).abs())
            .fold(0.0, f64::max);
        r = next;
        if change < 1e-15 {
            break;
        }
    }
    r
}

/// The ring radii (m): 0, then `rings_per_octave` per octave from `octaves_inside` octaves
/// inside `read_at_um` up to R, with one ring exactly at `read_at_um`; the last interval is
/// never thinner than half a step.
fn ring_radii_m(m: &CornerMesh) -> Vec<f64> {
    let p = m.rings_per_octave as f64;
    let step = 2f64.powf(1.0 / p);
    let (read, r) = (m.read_at_um * 1e-6, m.radius_um * 1e-6);
    let mut out = vec![0.0];
    let first = -((m.octaves_inside * m.rings_per_octave) as i64);
    let mut k = first;
    loop {
        let rho = read * step.powi(k as i32);
        if rho * step.sqrt() >= r {
            break;
        }
        out.push(rho);
        k += 1;
    }
    out.push(r);
    out
}

impl CornerFrame {
    fn point_um(&self, s_m: f64, z_m: f64) -> [f64; 3] {
        [0, 1, 2].map(|i| self.origin_um[i] + 1e6 * (s_m * self.e_s[i] + z_m * self.e_z[i]))
    }
}

/// The displacement driver in the corotated frame: u'(X) = R^T (X - X0 + u(X) - u(X0)) - (X - X0)
/// and its derivative along the edge g' = R^T (e_t + du/dt) - e_t.
struct Driver<'a, D: Fn([f64; 3]) -> Option<[f64; 3]>> {
    field: &'a D,
    frame: CornerFrame,
    rt: [[f64; 3]; 3],
    u0: [f64; 3],
    dt_um: f64,
    /// du/dt on the edge itself (corotated), and the radius (m) inside which it stands for the
    /// section's.
    g_edge: [f64; 3],
    constant_dt_m: f64,
}

impl<'a, D: Fn([f64; 3]) -> Option<[f64; 3]>> Driver<'a, D> {
    /// The driver of a submodel of radius `radius_um` with the local `rotation` taken out.
    fn new(
        field: &'a D,
        frame: CornerFrame,
        rotation: &[[f64; 3]; 3],
        radius_um: f64,
    ) -> FeResult<Self> {
        let mut d = Driver {
            field,
            frame,
            rt: transpose(rotation),
            u0: field(frame.origin_um).ok_or_else(|| outside(frame.origin_um))?,
            dt_um: (radius_um * 0.05).max(1e-3),
            g_edge: [0.0; 3],
            constant_dt_m: CONSTANT_DT_FRACTION * radius_um * 1e-6,
        };
        d.g_edge = d.along_edge(frame.origin_um)?;
        Ok(d)
    }

    fn displacement(&self, p_um: [f64; 3]) -> FeResult<[f64; 3]> {
        let u = (self.field)(p_um).ok_or_else(|| outside(p_um))?;
        let d = [0, 1, 2].map(|i| (p_um[i] - self.frame.origin_um[i]) * 1e-6);
        let x = add3(d, [0, 1, 2].map(|i| u[i] - self.u0[i]));
        let y = matvec(&self.rt, x);
        Ok([0, 1, 2].map(|i| y[i] - d[i]))
    }
    /// du/dt at the section's point (s, z) (m): within [`CONSTANT_DT_FRACTION`] of the radius
    /// the edge's own (the solid's du/dt is continuous there: its element faces through the
    /// edge contain t, and it varies on the solid's element scale, not the submodel's inner
    /// rings'), else read at the point.
    fn along_edge_at(&self, s_m: f64, z_m: f64) -> FeResult<[f64; 3]> {
        if s_m.hypot(z_m) < self.constant_dt_m {
            Ok(self.g_edge)
        } else {
            self.along_edge(self.frame.point_um(s_m, z_m))
        }
    }

    /// Central difference; one-sided where the solid ends on one side (a mirror plane).
    fn along_edge(&self, p_um: [f64; 3]) -> FeResult<[f64; 3]> {
        let h = self.dt_um;
        let at = |k: f64| {
            let q = [0, 1, 2].map(|i| p_um[i] + k * h * self.frame.e_t[i]);
            (self.field)(q)
        };
        let (a, b, span) = match (at(1.0), at(-1.0)) {
            (Some(a), Some(b)) => (a, b, 2.0 * h),
            (Some(a), None) => (a, at(0.0).ok_or_else(|| outside(p_um))?, h),
            (None, Some(b)) => (at(0.0).ok_or_else(|| outside(p_um))?, b, h),
            (None, None) => return Err(outside(p_um)),
        };
        let g = [0, 1, 2].map(|i| (a[i] - b[i]) / (span * 1e-6));
        let y = matvec(&self.rt, add3(self.frame.e_t, g));
        Ok([0, 1, 2].map(|i| y[i] - self.frame.e_t[i]))
    }
}

fn outside(p_um: [f64; 3]) -> FeError {
    FeError::SolidInput {
        detail: format!(
            "the corner submodel reads the solid at ({:.3}, {:.3}, {:.3}) um, outside it",
            p_um[0], p_um[1], p_um[2]
        ),
        hint: "the submodel's radius must stay inside the solid's material around the edge",
    }
}

/// Voigt strain (engineering shears) of the displacement gradient a (x) b, symmetrised.
fn sym_voigt(a: [f64; 3], b: [f64; 3]) -> [f64; 6] {
    VOIGT.map(|(i, j)| {
        if i == j {
            a[i] * b[i]
        } else {
            a[i] * b[j] + a[j] * b[i]
        }
    })
}

/// The element's nodes (angular a, radial b) as node indices.
struct Topology {
    n_ang: usize,
    wraps: bool,
}

impl Topology {
    fn node(&self, ri: usize, ai: usize) -> usize {
        if ri == 0 {
            0
        } else {
            let ai = if self.wraps { ai % self.n_ang } else { ai };
            1 + (ri - 1) * self.n_ang + ai
        }
    }
}

/// Shape functions of element (k, m) at (xi along the angle, eta along the radius): the nine
/// nodes, their values and physical derivatives (d/ds, d/dz in m^-1), the point (s, z) in m and
/// the Jacobian determinant.
struct ElementGeometry {
    nodes: [usize; 9],
    xy: [[f64; 2]; 9],
}

impl ElementGeometry {
    fn new(
        topo: &Topology,
        rings: &[f64],
        angles: &[(f64, f64, usize)],
        k: usize,
        m: usize,
    ) -> Self {
        let (t0, t1, _) = angles[m];
        let rr = [rings[k], 0.5 * (rings[k] + rings[k + 1]), rings[k + 1]];
        let tt = [t0, 0.5 * (t0 + t1), t1];
        let mut nodes = [0; 9];
        let mut xy = [[0.0; 2]; 9];
        for b in 0..3 {
            for a in 0..3 {
                nodes[3 * b + a] = topo.node(2 * k + b, 2 * m + a);
                xy[3 * b + a] = [rr[b] * tt[a].cos(), rr[b] * tt[a].sin()];
            }
        }
        ElementGeometry { nodes, xy }
    }

    /// (N, dN/ds, dN/dz, (s, z), det J) at (xi, eta).
    #[allow(clippy::type_complexity)]
    fn at(&self, xi: f64, eta: f64) -> Option<([f64; 9], [[f64; 2]; 9], [f64; 2], f64)> {
        let (na, da) = lagrange2(xi);
        let (nb, db) = lagrange2(eta);
        let mut n = [0.0; 9];
        let mut dxi = [[0.0; 2]; 9];
        for b in 0..3 {
            for a in 0..3 {
                n[3 * b + a] = na[a] * nb[b];
                dxi[3 * b + a] = [da[a] * nb[b], na[a] * db[b]];
            }
        }
        let mut j = [[0.0; 2]; 2];
        let mut p = [0.0; 2];
        for q in 0..9 {
            for r in 0..2 {
                p[r] += n[q] * self.xy[q][r];
                for c in 0..2 {
                    j[r][c] += self.xy[q][r] * dxi[q][c];
                }
            }
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det.abs() < 1e-300 {
            return None;
        }
        let inv = [
            [j[1][1] / det, -j[0][1] / det],
            [-j[1][0] / det, j[0][0] / det],
        ];
        let d = dxi.map(|g| {
            [
                g[0] * inv[0][0] + g[1] * inv[1][0],
                g[0] * inv[0][1] + g[1] * inv[1][1],
            ]
        });
        Some((n, d, p, det))
    }
}

/// Solves the corner submodel: `sectors` contiguous and increasing, spanning at most a full turn
/// (a full turn is a closed disc, else the first and last faces are free); `field` the solid's
/// displacement (m) at an undeformed point (um), None outside it.
///
/// Sections of the same topology share their pattern and symbolic factorisation through
/// `patterns` ([`SectionPatterns`]).
///
/// Panics if the sectors or the mesh are malformed (misuse); a driver that cannot be read or a
/// singular system is an error.
#[track_caller]
pub fn solve_corner<D: Fn([f64; 3]) -> Option<[f64; 3]>>(
    frame: CornerFrame,
    sectors: &[CornerSector],
    mesh: CornerMesh,
    kinematics: DriverKinematics,
    field: &D,
    patterns: &SectionPatterns,
) -> FeResult<CornerSolution> {
    assert!(!sectors.is_empty(), "a corner needs at least one sector");
    for w in sectors.windows(2) {
        assert!(
            (w[0].to_rad - w[1].from_rad).abs() < 1e-12,
            "corner sectors must be contiguous"
        );
    }
    assert!(
        sectors.iter().all(|s| s.to_rad > s.from_rad),
        "sectors must increase"
    );
    let span = sectors.last().expect("non-empty").to_rad - sectors[0].from_rad;
    let full = std::f64::consts::TAU;
    assert!(span <= full + 1e-9, "sectors span more than a full turn");
    assert!(
        mesh.rings_per_octave >= 1
            && mesh.read_at_um > 0.0
            && mesh.radius_um > 4.0 * mesh.read_at_um,
        "corner mesh: the read-out ring must lie well inside the radius"
    );
    let wraps = (span - full).abs() < 1e-9;
    let d_max = (30f64).to_radians() / mesh.rings_per_octave as f64;
    let mut angles = Vec::new();
    for (i, s) in sectors.iter().enumerate() {
        let n = ((s.to_rad - s.from_rad) / d_max).ceil().max(1.0) as usize;
        for q in 0..n {
            let a = s.from_rad + (s.to_rad - s.from_rad) * q as f64 / n as f64;
            let b = s.from_rad + (s.to_rad - s.from_rad) * (q + 1) as f64 / n as f64;
            angles.push((a, b, i));
        }
    }
    let rings = ring_radii_m(&mesh);
    let (n_rings, n_el_ang) = (rings.len() - 1, angles.len());
    if n_rings.saturating_mul(n_el_ang) > MAX_CORNER_ELEMENTS {
        return Err(FeError::TooLarge {
            detail: format!("corner submodel of {n_rings} x {n_el_ang} elements"),
            limit: MAX_CORNER_ELEMENTS,
            hint: "use fewer rings per octave",
        });
    }
    let n_ang = if wraps {
        2 * n_el_ang
    } else {
        2 * n_el_ang + 1
    };
    let topo = Topology { n_ang, wraps };
    let n_nodes = 1 + 2 * n_rings * n_ang;

    // The driver's frame: the local rigid rotation, read where the material around the edge is
    // widest (on the bisector of the widest sector, at R / 2), by central differences of R / 8.
    let rotation = match kinematics {
        DriverKinematics::Linear => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        DriverKinematics::Corotated => {
            let widest = sectors
                .iter()
                .max_by(|a, b| (a.to_rad - a.from_rad).total_cmp(&(b.to_rad - b.from_rad)))
                .expect("non-empty");
            let th = 0.5 * (widest.from_rad + widest.to_rad);
            let r_m = 0.5 * mesh.radius_um * 1e-6;
            let c = frame.point_um(r_m * th.cos(), r_m * th.sin());
            let h = mesh.radius_um / 8.0;
            let mut f = [[0.0; 3]; 3];
            for e in [frame.e_s, frame.e_z, frame.e_t] {
                let a = [0, 1, 2].map(|i| c[i] + h * e[i]);
                let b = [0, 1, 2].map(|i| c[i] - h * e[i]);
                let ua = field(a).ok_or_else(|| outside(a))?;
                let ub = field(b).ok_or_else(|| outside(b))?;
                // dx/dX along e = e + du/de, assembled in die axes: F = sum (e + du/de) (x) e.
                let dx = add3(e, [0, 1, 2].map(|i| (ua[i] - ub[i]) / (2.0 * h * 1e-6)));
                for i in 0..3 {
                    for j in 0..3 {
                        f[i][j] += dx[i] * e[j];
                    }
                }
            }
            polar_rotation(f)
        }
    };
    let driver = Driver::new(field, frame, &rotation, mesh.radius_um)?;

    // Dofs: the arc's nodes are prescribed.
    let mut free = vec![usize::MAX; n_nodes];
    let mut fixed = vec![[0.0; 3]; n_nodes];
    let mut n_free = 0;
    for ri in 0..=2 * n_rings {
        let r = if ri % 2 == 0 {
            rings[ri / 2]
        } else {
            0.5 * (rings[ri / 2] + rings[ri / 2 + 1])
        };
        for ai in 0..(if ri == 0 { 1 } else { n_ang }) {
            let node = topo.node(ri, ai);
            if ri == 2 * n_rings {
                let (el, half) = (ai / 2, ai % 2);
                let (t0, t1, _) = angles[el.min(n_el_ang - 1)];
                let th = if ai == 2 * n_el_ang {
                    angles[n_el_ang - 1].1
                } else if half == 0 {
                    t0
                } else {
                    0.5 * (t0 + t1)
                };
                fixed[node] = driver.displacement(frame.point_um(r * th.cos(), r * th.sin()))?;
            } else {
                free[node] = n_free;
                n_free += 1;
            }
        }
    }
    let n = 3 * n_free;
    let topology: SectionTopology = (n_rings, n_el_ang, wraps);
    let cached = patterns.get(topology);
    // The pattern's entries, in the order the values come, where it is not known yet.
    let mut pairs = Vec::new();
    let mut vals = Vec::new();
    let mut rhs = vec![0.0; n];
    for k in 0..n_rings {
        for m in 0..n_el_ang {
            let geo = ElementGeometry::new(&topo, &rings, &angles, k, m);
            let c = &sectors[angles[m].2].material.c_pa;
            let mut ke = [[0.0; 27]; 27];
            let mut fe = [0.0; 27];
            for (xi, wx) in GAUSS3 {
                for (eta, wy) in GAUSS3 {
                    let Some((_, d, p, det)) = geo.at(xi, eta) else {
                        continue;
                    };
                    let w = wx * wy * det.abs();
                    let g = driver.along_edge_at(p[0], p[1])?;
                    let eps0 = sym_voigt(g, frame.e_t);
                    let s0 = mul6(c, &eps0);
                    let b: Vec<[f64; 6]> = (0..27)
                        .map(|q| {
                            let (node, comp) = (q / 3, q % 3);
                            let dir =
                                add3(scale3(frame.e_s, d[node][0]), scale3(frame.e_z, d[node][1]));
                            let mut unit = [0.0; 3];
                            unit[comp] = 1.0;
                            sym_voigt(unit, dir)
                        })
                        .collect();
                    let cb: Vec<[f64; 6]> = b.iter().map(|bq| mul6(c, bq)).collect();
                    for i in 0..27 {
                        fe[i] -= w * dot6(&b[i], &s0);
                        for j in 0..=i {
                            ke[i][j] += w * dot6(&b[i], &cb[j]);
                        }
                    }
                }
            }
            // Only the lower triangle was summed.
            let upper = |i: usize, j: usize| if j <= i { ke[i][j] } else { ke[j][i] };
            let dof = |q: usize| -> Option<usize> {
                let f = free[geo.nodes[q / 3]];
                (f != usize::MAX).then(|| 3 * f + q % 3)
            };
            for (i, fi) in fe.iter().enumerate() {
                let Some(gi) = dof(i) else { continue };
                rhs[gi] += fi;
                for j in 0..27 {
                    match dof(j) {
                        Some(gj) if gj <= gi => {
                            if cached.is_none() {
                                pairs.push(Pair { row: gi, col: gj });
                            }
                            vals.push(upper(i, j));
                        }
                        Some(_) => {}
                        None => rhs[gi] -= upper(i, j) * fixed[geo.nodes[j / 3]][j % 3],
                    }
                }
            }
        }
    }
    let sparse = |e: String| FeError::Sparse {
        detail: e,
        hint: "the corner submodel is too large: use fewer rings per octave",
    };
    let pattern = match cached {
        Some(p) => p,
        None => {
            let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
                .map_err(|e| sparse(format!("{e:?}")))?;
            let llt = SymbolicLlt::try_new(symbolic.as_ref(), Side::Lower)
                .map_err(|e| sparse(format!("{e:?}")))?;
            let p = Arc::new(SectionPattern {
                symbolic,
                argsort,
                llt,
            });
            patterns.insert(topology, p.clone());
            p
        }
    };
    let mat = SparseColMat::<usize, f64>::new_from_argsort(
        pattern.symbolic.clone(),
        &pattern.argsort,
        &vals,
    )
    .map_err(|e| sparse(format!("{e:?}")))?;
    let llt = Llt::try_new_with_symbolic(pattern.llt.clone(), mat.as_ref(), Side::Lower).map_err(
        |e| FeError::NotPositiveDefinite {
            detail: format!("corner submodel: {e:?}"),
            hint: "a sector's material is not positive definite",
        },
    )?;
    let mut x = Mat::<f64>::zeros(n, 1);
    for (i, v) in rhs.iter().enumerate() {
        x[(i, 0)] = *v;
    }
    llt.solve_in_place(x.as_mut());
    let u: Vec<[f64; 3]> = (0..n_nodes)
        .map(|node| match free[node] {
            usize::MAX => fixed[node],
            f => [x[(3 * f, 0)], x[(3 * f + 1, 0)], x[(3 * f + 2, 0)]],
        })
        .collect();
    if u.iter().flatten().any(|v| !v.is_finite()) {
        return Err(FeError::NonFinite {
            hint: "the corner submodel's driver has non-finite values",
        });
    }
    Ok(CornerSolution {
        frame,
        sectors: sectors.to_vec(),
        angles,
        rings_m: rings,
        wraps,
        u,
        rotation,
        dofs: n,
    })
}

fn mul6(c: &[[f64; 6]; 6], e: &[f64; 6]) -> [f64; 6] {
    [0, 1, 2, 3, 4, 5].map(|i| (0..6).map(|j| c[i][j] * e[j]).sum())
}
fn dot6(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    (0..6).map(|i| a[i] * b[i]).sum()
}

impl CornerSolution {
    /// The ring radii (um), innermost (0) first.
    pub fn rings_um(&self) -> Vec<f64> {
        self.rings_m.iter().map(|r| r * 1e6).collect()
    }

    /// The local rigid rotation taken out of the driver (identity for a linear driver).
    pub fn rotation(&self) -> [[f64; 3]; 3] {
        self.rotation
    }

    /// Stress (Voigt, Pa, in the solid's axes of the corotated frame) of element (k, m) at
    /// (xi, eta), with `g` the driver's du/dt there.
    fn stress(&self, k: usize, m: usize, xi: f64, eta: f64, g: [f64; 3]) -> Option<[f64; 6]> {
        let topo = Topology {
            n_ang: if self.wraps {
                2 * self.angles.len()
            } else {
                2 * self.angles.len() + 1
            },
            wraps: self.wraps,
        };
        let geo = ElementGeometry::new(&topo, &self.rings_m, &self.angles, k, m);
        let (_, d, _, _) = geo.at(xi, eta)?;
        let mut eps = sym_voigt(g, self.frame.e_t);
        for (q, node) in geo.nodes.iter().enumerate() {
            let dir = add3(
                scale3(self.frame.e_s, d[q][0]),
                scale3(self.frame.e_z, d[q][1]),
            );
            let e = sym_voigt(self.u[*node], dir);
            for i in 0..6 {
                eps[i] += e[i];
            }
        }
        Some(mul6(&self.sectors[self.angles[m].2].material.c_pa, &eps))
    }

    /// The stresses (Voigt, Pa, solid axes) on ring `ring` (an index into [`Self::rings_um`],
    /// not the centre or the arc) in the sectors `which` selects, with their angles: the
    /// stresses of the elements inside and outside the ring averaged at five points per element
    /// edge.
    #[track_caller]
    pub fn stresses_on_ring<D: Fn([f64; 3]) -> Option<[f64; 3]>>(
        &self,
        ring: usize,
        which: impl Fn(usize) -> bool,
        field: &D,
    ) -> FeResult<Vec<(f64, [f64; 6])>> {
        assert!(
            ring >= 1 && ring + 1 < self.rings_m.len(),
            "the ring must have elements on both sides"
        );
        let radius_um = self.rings_m.last().copied().unwrap_or(0.0) * 1e6;
        let driver = Driver::new(field, self.frame, &self.rotation, radius_um)?;
        let r = self.rings_m[ring];
        let mut out = Vec::new();
        for (m, &(t0, t1, sector)) in self.angles.iter().enumerate() {
            if !which(sector) {
                continue;
            }
            for xi in [-1.0, -0.5, 0.0, 0.5, 1.0] {
                let th = t0 + 0.5 * (xi + 1.0) * (t1 - t0);
                let g = driver.along_edge_at(r * th.cos(), r * th.sin())?;
                if let (Some(a), Some(b)) = (
                    self.stress(ring - 1, m, xi, 1.0, g),
                    self.stress(ring, m, xi, -1.0, g),
                ) {
                    out.push((th, [0, 1, 2, 3, 4, 5].map(|i| 0.5 * (a[i] + b[i]))));
                }
            }
        }
        Ok(out)
    }

    /// The largest principal stress (Pa) on ring `ring` in the sectors `which` selects, and its
    /// angle ([`Self::stresses_on_ring`]).
    #[track_caller]
    pub fn max_principal_on_ring<D: Fn([f64; 3]) -> Option<[f64; 3]>>(
        &self,
        ring: usize,
        which: impl Fn(usize) -> bool,
        field: &D,
    ) -> FeResult<(f64, f64)> {
        let mut best = (f64::NEG_INFINITY, 0.0);
        for (th, s) in self.stresses_on_ring(ring, which, field)? {
            let p = principal_stresses_pa(&s)[0];
            if p > best.0 {
                best = (p, th);
            }
        }
        Ok(best)
    }

    /// The ring index at `r_um` (the mesh places one there).
    pub fn ring_at(&self, r_um: f64) -> Option<usize> {
        self.rings_m
            .iter()
            .position(|&r| (r * 1e6 - r_um).abs() <= 1e-9 * r_um.max(1e-12))
    }
}
