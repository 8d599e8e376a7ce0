//! The 3-D tissue slab: a block of tissue L (x, along the jaw) x W (y, across the jaw) x H (z)
//! bonded to the sensor face z = 0 (held) and to the jaw z = H (moved down by `compression` H),
//! free on its four sides, with an optional sphere (lump with its E and nu, or void) anywhere
//! inside: the scene of issue 17 item 1 that neither the plane section ([`super::inclusion`])
//! nor the axisymmetric cylinder ([`super::axislab`]) is, since the slab's own free edges across
//! the jaw and a lump off the axis are both 3-D.
//!
//! Elements: the Q2/P1 (B-bar) brick of [`super::hex_bbar`] on a structured mesh of boxes,
//! graded geometrically (ratio [`GRADING`]) from a uniform `near` size over the sphere (and from
//! the face up to its top) to at most `far` elsewhere. As in [`super::axislab`], an element the
//! sphere crosses mixes both stiffnesses by the sphere's share of its volume (8 x 8 x 8 samples),
//! and one at least 99 % void is left out. Mirror planes (u normal = 0) halve the block in x when
//! the sphere is at x = L / 2 and in y when it is at y = W / 2 (a quarter when centred).
//!
//! The face pressure P(x, y) is the consistent projection of the face nodes' reactions,
//! M p = f with M_ij = int N_i N_j dA over the face (exact for any pressure in the Q2 trace
//! space); on a structured face M = M_x (x) M_y, solved direction by direction. P0(x, y) is the
//! same block without the sphere on the same mesh, so d = P / P0 - 1 carries no mesh bias of the
//! background. The linear system is factored by sparse Cholesky ([`crate::fe::cholesky`]) in
//! the lattice's nested-dissection order ([`crate::fe::solid::ordering`]).

use std::collections::HashMap;
use std::sync::Arc;

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::Mat;
use serde::Serialize;

use super::continuum::lame;
use super::hex_bbar::{box_nodes, brick_q2, BrickQ2};
use super::inclusion::{Feature, Slab};
use super::SoftnessError;
use crate::fe::cholesky::SymbolicFactor;
use crate::fe::solid::hex27::DOFS;

/// Largest mesh \[choice\]: 8,000 bricks (about 2e5 unknowns; the 0.4 mm mesh of the default
/// slab is 4,576 bricks, 112,359 unknowns, 30 s).
pub const MAX_ELEMENTS: usize = 8_000;

/// Largest Cholesky factor \[choice\]: 2e8 entries (1.6 GB), checked after the symbolic
/// analysis and before the numeric factor is allocated.
pub const MAX_FACTOR_ENTRIES: usize = 200_000_000;

/// Ratio of neighbouring element sizes away from the sphere \[choice\].
pub const GRADING: f64 = 1.3;

/// The 3-D slab and its sphere (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Slab3d {
    /// Along the jaw (x), the plane section's width.
    pub length_m: f64,
    /// Across the jaw (y).
    pub width_m: f64,
    pub thickness_m: f64,
    pub tissue_e_pa: f64,
    pub tissue_nu: f64,
    /// Shortening between the jaws, as a fraction of the thickness.
    pub compression: f64,
    pub feature: Feature,
    /// The sphere's centre: x along, y across (from the slab's corner), z above the face.
    pub centre_m: [f64; 3],
    pub radius_m: f64,
}

impl Slab3d {
    /// The plane `slab` extruded across the jaw to `width_m`, its disc become a sphere at
    /// `centre_y_m` across (the disc's x and height kept).
    pub fn from_slab(s: &Slab, width_m: f64, centre_y_m: f64) -> Slab3d {
        Slab3d {
            length_m: s.width_m,
            width_m,
            thickness_m: s.thickness_m,
            tissue_e_pa: s.tissue_e_pa,
            tissue_nu: s.tissue_nu,
            compression: s.compression,
            feature: s.feature,
            centre_m: [s.centre_x_m, centre_y_m, s.centre_height_m],
            radius_m: s.radius_m,
        }
    }
}

/// Element sizes (m): `near` over the sphere and under it down to the face, growing by
/// [`GRADING`] up to `far` elsewhere.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Mesh3d {
    pub near_m: f64,
    pub far_m: f64,
}

impl Mesh3d {
    /// \[choice\] 0.67 mm (3 elements over a 2 mm radius) near, 2.5 mm far.
    pub const DEFAULT: Mesh3d = Mesh3d {
        near_m: 2e-3 / 3.0,
        far_m: 2.5e-3,
    };
}

/// The face pressure of the 3-D slab with and without its sphere, over the whole face (mirror
/// halves unfolded).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FaceField {
    /// Face node lines (m) along (x) and across (y) the jaw.
    pub x_m: Vec<f64>,
    pub y_m: Vec<f64>,
    /// Pressures (Pa, compression positive) at node (i, j), index j * x_m.len() + i.
    pub p_pa: Vec<f64>,
    pub p0_pa: Vec<f64>,
    /// The largest and smallest P / P0 and where (x, y in m).
    pub peak_ratio: f64,
    pub peak_at_m: [f64; 2],
    pub min_ratio: f64,
    pub min_at_m: [f64; 2],
    /// Bricks (x, y, z) of the modelled part, its unknowns (with the sphere), and the mirror
    /// planes used (x, y).
    pub elements: [usize; 3],
    pub unknowns: usize,
    pub mirrored: [bool; 2],
    /// Total axial force (N, whole block, with the sphere) on the face (the sum of the face
    /// nodes' reactions) and on the jaw: equal at equilibrium.
    pub face_force_n: f64,
    pub jaw_force_n: f64,
}

/// Bilinear interpolation on node lines (clamped to the face).
fn bilinear(xs: &[f64], ys: &[f64], v: &[f64], x: f64, y: f64) -> f64 {
    let locate = |ls: &[f64], t: f64| -> (usize, f64) {
        let n = ls.len();
        if n < 2 {
            return (0, 0.0);
        }
        let t = t.clamp(ls[0], ls[n - 1]);
        let i = ls.partition_point(|&l| l <= t).clamp(1, n - 1);
        let h = ls[i] - ls[i - 1];
        (i - 1, if h > 0.0 { (t - ls[i - 1]) / h } else { 0.0 })
    };
    let (i, s) = locate(xs, x);
    let (j, t) = locate(ys, y);
    let nx = xs.len();
    let at = |a: usize, b: usize| v[b.min(ys.len() - 1) * nx + a.min(nx - 1)];
    (1.0 - t) * ((1.0 - s) * at(i, j) + s * at(i + 1, j))
        + t * ((1.0 - s) * at(i, j + 1) + s * at(i + 1, j + 1))
}

impl FaceField {
    /// P / P0 node by node.
    pub fn ratio(&self) -> Vec<f64> {
        self.p_pa
            .iter()
            .zip(&self.p0_pa)
            .map(|(a, b)| a / b)
            .collect()
    }
    /// P at (x, y) on the face (m, slab coordinates), bilinear between the nodes.
    pub fn p_at_pa(&self, x: f64, y: f64) -> f64 {
        bilinear(&self.x_m, &self.y_m, &self.p_pa, x, y)
    }
    /// P0 at (x, y), as [`Self::p_at_pa`].
    pub fn p0_at_pa(&self, x: f64, y: f64) -> f64 {
        bilinear(&self.x_m, &self.y_m, &self.p0_pa, x, y)
    }
}

fn bad<T>(field: &'static str, value: f64, hint: &'static str) -> Result<T, SoftnessError> {
    Err(SoftnessError::BadInput { field, value, hint })
}

fn positive(v: f64) -> bool {
    v > 0.0 && v.is_finite()
}

/// Checks the slab and mesh (user input: errors, never panics).
fn check(s: &Slab3d, m: &Mesh3d) -> Result<(), SoftnessError> {
    for (f, v) in [
        ("length_m", s.length_m),
        ("width_m", s.width_m),
        ("thickness_m", s.thickness_m),
    ] {
        if !positive(v) {
            return bad(f, v, "the slab needs a positive size");
        }
    }
    super::inclusion::check_materials(s.tissue_e_pa, s.tissue_nu, s.compression, s.feature)?;
    if s.feature != Feature::None {
        let (r, c) = (s.radius_m, s.centre_m);
        let inside = positive(r)
            && c[0] - r > 0.0
            && c[0] + r < s.length_m
            && c[1] - r > 0.0
            && c[1] + r < s.width_m
            && c[2] - r > 0.0
            && c[2] + r < s.thickness_m;
        if !inside {
            return bad("radius_m", r, "the sphere must lie inside the tissue block");
        }
    }
    if !(positive(m.near_m) && positive(m.far_m) && m.near_m <= m.far_m) {
        return bad(
            "mesh near_m",
            m.near_m,
            "element sizes 0 < near <= far, e.g. 0.67 and 2.5 mm",
        );
    }
    Ok(())
}

/// Sizes growing by [`GRADING`] from `near` (capped at `far`) that fill `len`: the count whose
/// sum is nearest `len`, then scaled to fit exactly.
fn grow(len: f64, near: f64, far: f64, cap: usize) -> Option<Vec<f64>> {
    if len <= 1e-12 * far {
        return Some(Vec::new());
    }
    let mut sizes = Vec::new();
    let (mut h, mut sum) = (near, 0.0);
    loop {
        h = (h * GRADING).min(far);
        if sizes.len() >= cap {
            return None;
        }
        sizes.push(h);
        sum += h;
        if sum >= len {
            break;
        }
    }
    if sizes.len() > 1 && (sum - len) > (len - (sum - h)) {
        sizes.pop();
        sum -= h;
    }
    Some(sizes.into_iter().map(|v| v * len / sum).collect())
}

/// Element boundaries on [a, b]: uniform `near` over `focus` (clipped), graded outward; uniform
/// `far` without a focus. None if over `cap` elements.
fn graded_lines(
    a: f64,
    b: f64,
    focus: Option<(f64, f64)>,
    near: f64,
    far: f64,
    cap: usize,
) -> Option<Vec<f64>> {
    let uniform = |lo: f64, hi: f64, h: f64| -> Option<Vec<f64>> {
        let n = ((hi - lo) / h * (1.0 - 1e-9)).ceil().max(1.0);
        if n > cap as f64 {
            return None;
        }
        let n = n as usize;
        Some(
            (1..=n)
                .map(|k| lo + (hi - lo) * k as f64 / n as f64)
                .collect(),
        )
    };
    let Some((c0, c1)) = focus else {
        let mut v = vec![a];
        v.extend(uniform(a, b, far)?);
        return Some(v);
    };
    let (c0, c1) = (c0.max(a), c1.min(b));
    let mut v = vec![a];
    let left = grow(c0 - a, near, far, cap)?;
    let mut x = a;
    for h in left.iter().rev() {
        x += h;
        v.push(x);
    }
    *v.last_mut()? = c0;
    if c1 > c0 {
        v.extend(uniform(c0, c1, near)?);
    }
    let mut x = c1;
    for h in grow(b - c1, near, far, cap)? {
        x += h;
        v.push(x);
    }
    *v.last_mut()? = b;
    v.dedup_by(|p, q| (*p - *q).abs() <= 1e-12 * (b - a));
    (v.len() <= cap + 1).then_some(v)
}

fn node_lines(lines: &[f64]) -> Vec<f64> {
    let mut v = vec![lines[0]];
    for w in lines.windows(2) {
        v.push(0.5 * (w[0] + w[1]));
        v.push(w[1]);
    }
    v
}

/// The modelled block's element lines in x, y, z and the mirror planes used.
struct Lines {
    e: [Vec<f64>; 3],
    mirrored: [bool; 2],
}

fn lines(s: &Slab3d, m: &Mesh3d) -> Result<Lines, SoftnessError> {
    let on_mid = |c: f64, l: f64| (c - 0.5 * l).abs() <= 1e-9 * l;
    let feat = s.feature != Feature::None;
    let mirrored = [
        !feat || on_mid(s.centre_m[0], s.length_m),
        !feat || on_mid(s.centre_m[1], s.width_m),
    ];
    let (r, c) = (s.radius_m, s.centre_m);
    // [choice] The near zone reaches half a radius beyond the sphere (and down to the face).
    let margin = 0.5 * r;
    let ext = [s.length_m, s.width_m, s.thickness_m];
    let too_many = |d: usize| SoftnessError::BadInput {
        field: "elements",
        value: ext[d] / m.near_m,
        hint: "the mesh would exceed 8,000 bricks: use larger element sizes",
    };
    let mut e: [Vec<f64>; 3] = Default::default();
    for d in 0..3 {
        let lo = if d < 2 && mirrored[d] {
            0.5 * ext[d]
        } else {
            0.0
        };
        let focus = feat.then(|| {
            if d == 2 {
                (0.0, c[2] + r + margin)
            } else {
                (c[d] - r - margin, c[d] + r + margin)
            }
        });
        e[d] = graded_lines(lo, ext[d], focus, m.near_m, m.far_m, MAX_ELEMENTS)
            .ok_or_else(|| too_many(d))?;
    }
    let n: f64 = e.iter().map(|l| (l.len() - 1) as f64).product();
    if n > MAX_ELEMENTS as f64 {
        return Err(SoftnessError::BadInput {
            field: "elements",
            value: n,
            hint: "the mesh would exceed 8,000 bricks: use larger element sizes",
        });
    }
    Ok(Lines { e, mirrored })
}

/// The sphere's share of the box's volume (8^3 midpoint samples; exact 0 or 1 when the box is
/// clear of the surface).
fn sphere_share(lo: [f64; 3], hi: [f64; 3], c: [f64; 3], r: f64) -> f64 {
    let near: f64 = (0..3)
        .map(|d| (c[d].clamp(lo[d], hi[d]) - c[d]).powi(2))
        .sum();
    if near >= r * r {
        return 0.0;
    }
    let far: f64 = (0..3)
        .map(|d| (c[d] - lo[d]).abs().max((c[d] - hi[d]).abs()).powi(2))
        .sum();
    if far <= r * r {
        return 1.0;
    }
    const S: usize = 8;
    let at = |d: usize, k: usize| lo[d] + (hi[d] - lo[d]) * (k as f64 + 0.5) / S as f64 - c[d];
    let mut inside = 0usize;
    for a in 0..S {
        for b in 0..S {
            for q in 0..S {
                if at(0, a).powi(2) + at(1, b).powi(2) + at(2, q).powi(2) < r * r {
                    inside += 1;
                }
            }
        }
    }
    inside as f64 / (S * S * S) as f64
}

/// One solve: the face nodes' pressures (Pa) on the modelled part (node lines in x fastest),
/// the unknowns, and the modelled part's face and jaw forces (N).
struct Solved {
    p_pa: Vec<f64>,
    unknowns: usize,
    face_n: f64,
    jaw_n: f64,
}

/// Solves the block with `feature` on the given lines.
fn face_pressure(s: &Slab3d, ln: &Lines, feature: Feature) -> Result<Solved, SoftnessError> {
    let [ex, ey, ez] = &ln.e;
    let ne = [ex.len() - 1, ey.len() - 1, ez.len() - 1];
    let nl = ne.map(|n| 2 * n + 1);
    let node = |i: usize, j: usize, k: usize| i + nl[0] * (j + nl[1] * k);
    let n_nodes = nl[0] * nl[1] * nl[2];
    // Element materials: the sphere's volume share, None when left out (void).
    let mut share = Vec::with_capacity(ne[0] * ne[1] * ne[2]);
    for k in 0..ne[2] {
        for j in 0..ne[1] {
            for i in 0..ne[0] {
                let (lo, hi) = ([ex[i], ey[j], ez[k]], [ex[i + 1], ey[j + 1], ez[k + 1]]);
                let f = if feature == Feature::None {
                    0.0
                } else {
                    sphere_share(lo, hi, s.centre_m, s.radius_m)
                };
                share.push(if feature == Feature::Void && f >= 0.99 {
                    None
                } else {
                    Some(f)
                });
            }
        }
    }
    let elem_nodes = |i: usize, j: usize, k: usize| -> [usize; 27] {
        std::array::from_fn(|q| node(2 * i + q % 3, 2 * j + (q / 3) % 3, 2 * k + q / 9))
    };
    let mut used = vec![false; n_nodes];
    for k in 0..ne[2] {
        for j in 0..ne[1] {
            for i in 0..ne[0] {
                if share[(k * ne[1] + j) * ne[0] + i].is_some() {
                    for q in elem_nodes(i, j, k) {
                        used[q] = true;
                    }
                }
            }
        }
    }
    // Unknowns: node order, component inner; fixed on the face (0), the jaw (0, 0, -delta),
    // normal components on the mirror planes, and unused nodes.
    const FIXED: usize = usize::MAX;
    let mut index = vec![FIXED; 3 * n_nodes];
    let mut n_free = 0;
    for k in 1..nl[2] - 1 {
        for j in 0..nl[1] {
            for i in 0..nl[0] {
                let q = node(i, j, k);
                if !used[q] {
                    continue;
                }
                for d in 0..3 {
                    let plane = (d == 0 && ln.mirrored[0] && i == 0)
                        || (d == 1 && ln.mirrored[1] && j == 0);
                    if !plane {
                        index[3 * q + d] = n_free;
                        n_free += 1;
                    }
                }
            }
        }
    }
    let delta = s.compression * s.thickness_m;
    let top = nl[2] - 1;
    let fixed_value = |q: usize, d: usize| -> f64 {
        if d == 2 && q / (nl[0] * nl[1]) == top {
            -delta
        } else {
            0.0
        }
    };
    // Pattern (lower triangle): the nodes sharing an element with each node (structured
    // ranges: a vertex line touches two elements' nodes +-2, a mid line one element's +-1).
    let range = |i: usize, n: usize| -> std::ops::RangeInclusive<usize> {
        let (lo, hi) = if i.is_multiple_of(2) {
            (i.saturating_sub(2), i + 2)
        } else {
            (i - 1, i + 1)
        };
        lo..=hi.min(n - 1)
    };
    let mut col_ptr = Vec::with_capacity(n_free + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for q in 0..n_nodes {
        let (i, j, k) = (q % nl[0], (q / nl[0]) % nl[1], q / (nl[0] * nl[1]));
        for d in 0..3 {
            let c = index[3 * q + d];
            if c == FIXED {
                continue;
            }
            for kk in range(k, nl[2]) {
                for jj in range(j, nl[1]) {
                    for ii in range(i, nl[0]) {
                        let m = node(ii, jj, kk);
                        for e in 0..3 {
                            let r = index[3 * m + e];
                            if r != FIXED && r >= c {
                                row_idx.push(r);
                            }
                        }
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
    }
    // Values, and the right-hand side from the jaw's prescribed displacement.
    let tissue = lame(s.tissue_e_pa, s.tissue_nu);
    let lump = match feature {
        Feature::Lump { e_pa, nu } => Some(lame(e_pa, nu)),
        _ => None,
    };
    let mut cache: HashMap<[u64; 3], Arc<BrickQ2>> = HashMap::new();
    let mut vals = vec![0.0; row_idx.len()];
    let mut rhs = Mat::<f64>::zeros(n_free, 1);
    let mut bottom = Vec::new();
    let stiffness = |b: &BrickQ2, f: f64| -> Vec<f64> {
        b.kmu
            .iter()
            .zip(&b.klam)
            .map(|(km, kl)| {
                let t = (1.0 - f) * (tissue.1 * km + tissue.0 * kl);
                t + lump.map_or(0.0, |(lam, mu)| f * (mu * km + lam * kl))
            })
            .collect()
    };
    for k in 0..ne[2] {
        for j in 0..ne[1] {
            for i in 0..ne[0] {
                let Some(f) = share[(k * ne[1] + j) * ne[0] + i] else {
                    continue;
                };
                let h = [ex[i + 1] - ex[i], ey[j + 1] - ey[j], ez[k + 1] - ez[k]];
                let b = cache
                    .entry(h.map(f64::to_bits))
                    .or_insert_with(|| Arc::new(brick_q2(&box_nodes([0.0; 3], h))))
                    .clone();
                let ke = stiffness(&b, f);
                let nodes = elem_nodes(i, j, k);
                let g: [usize; DOFS] = std::array::from_fn(|l| index[3 * nodes[l / 3] + l % 3]);
                for (lj, &gj) in g.iter().enumerate() {
                    if gj == FIXED {
                        let v = fixed_value(nodes[lj / 3], lj % 3);
                        if v != 0.0 {
                            for (li, &gi) in g.iter().enumerate() {
                                if gi != FIXED {
                                    rhs[(gi, 0)] -= ke[li * DOFS + lj] * v;
                                }
                            }
                        }
                        continue;
                    }
                    let (s0, s1) = (col_ptr[gj], col_ptr[gj + 1]);
                    let rows = &row_idx[s0..s1];
                    for (li, &gi) in g.iter().enumerate() {
                        if gi == FIXED || gi < gj {
                            continue;
                        }
                        if let Ok(p) = rows.binary_search(&gi) {
                            vals[s0 + p] += ke[li * DOFS + lj];
                        }
                    }
                }
                if k == 0 || k + 1 == ne[2] {
                    bottom.push((k, i, j, nodes, ke));
                }
            }
        }
    }
    let solver = |e: crate::fe::FeError| SoftnessError::Solver {
        detail: e.to_string(),
        hint: "out of memory or not positive definite: use a coarser mesh, check E > 0, nu < 0.5",
    };
    let pattern = SymbolicSparseColMat::new_checked(n_free, n_free, col_ptr, None, row_idx);
    let mut fwd = Vec::with_capacity(n_free);
    for q in crate::fe::solid::ordering::nested_dissection(nl) {
        fwd.extend((0..3).map(|d| index[3 * q + d]).filter(|&c| c != FIXED));
    }
    let sym = SymbolicFactor::new(pattern.as_ref(), &fwd).map_err(solver)?;
    if sym.factor_len() > MAX_FACTOR_ENTRIES {
        return Err(SoftnessError::BadInput {
            field: "elements",
            value: sym.factor_len() as f64,
            hint: "the Cholesky factor would exceed 2e8 entries (1.6 GB): use larger element sizes",
        });
    }
    let llt = sym
        .factor(SparseColMat::<usize, f64>::new(pattern, vals).as_ref())
        .map_err(solver)?;
    llt.solve_in_place(rhs.as_mut());
    if (0..n_free).any(|i| !rhs[(i, 0)].is_finite()) {
        return Err(SoftnessError::Solver {
            detail: "non-finite solution".into(),
            hint: "check E, nu and the squeeze for NaN/inf",
        });
    }
    let value = |q: usize, d: usize| -> f64 {
        match index[3 * q + d] {
            FIXED => fixed_value(q, d),
            c => rhs[(c, 0)],
        }
    };
    // The face nodes' axial reactions (compression positive), node lines x fastest.
    // The jaw's: the reactions of the top layer's top nodes (pulling the jaw down: negative).
    let mut force = vec![0.0; nl[0] * nl[1]];
    let mut jaw_n = 0.0;
    for (k, i, j, nodes, ke) in &bottom {
        let ue: Vec<f64> = (0..DOFS).map(|l| value(nodes[l / 3], l % 3)).collect();
        let layers = [(*k == 0, 0), (*k + 1 == ne[2], 2)];
        for c in layers.iter().filter(|l| l.0).map(|l| l.1) {
            for a in 0..3 {
                for b in 0..3 {
                    let row = 3 * (a + 3 * b + 9 * c) + 2;
                    let f: f64 = (0..DOFS).map(|q| ke[row * DOFS + q] * ue[q]).sum();
                    if c == 0 {
                        force[(2 * j + b) * nl[0] + 2 * i + a] += f;
                    } else {
                        jaw_n -= f;
                    }
                }
            }
        }
    }
    let face_n = force.iter().sum();
    // M p = f with M = M_x (x) M_y: solve along x for every y line, then along y.
    let mx = face_mass(ex);
    let my = face_mass(ey);
    for row in force.chunks_mut(nl[0]) {
        let p = solve_dense(&mx, row);
        row.copy_from_slice(&p);
    }
    for i in 0..nl[0] {
        let col: Vec<f64> = (0..nl[1]).map(|j| force[j * nl[0] + i]).collect();
        for (j, v) in solve_dense(&my, &col).into_iter().enumerate() {
            force[j * nl[0] + i] = v;
        }
    }
    Ok(Solved {
        p_pa: force,
        unknowns: n_free,
        face_n,
        jaw_n,
    })
}

/// The 1-D Q2 mass matrix M_ij = int N_i N_j dx on element lines `e` (dense, exact: 2 + 2 <= 5
/// with 3-point Gauss).
fn face_mass(e: &[f64]) -> Vec<Vec<f64>> {
    let n = 2 * (e.len() - 1) + 1;
    let mut m = vec![vec![0.0; n]; n];
    for (k, w) in e.windows(2).enumerate() {
        let h = w[1] - w[0];
        // The exact Q2 element mass on [0, h]: h / 30 [[4, 2, -1], [2, 16, 2], [-1, 2, 4]].
        let local = [[4.0, 2.0, -1.0], [2.0, 16.0, 2.0], [-1.0, 2.0, 4.0]];
        for a in 0..3 {
            for b in 0..3 {
                m[2 * k + a][2 * k + b] += h / 30.0 * local[a][b];
            }
        }
    }
    m
}

/// Solves the small SPD system m x = f by Gaussian elimination without pivoting.
fn solve_dense(m: &[Vec<f64>], f: &[f64]) -> Vec<f64> {
    let n = f.len();
    let mut a: Vec<Vec<f64>> = m.to_vec();
    let mut x = f.to_vec();
    for k in 0..n {
        for i in k + 1..n.min(k + 3) {
            let r = a[i][k] / a[k][k];
            if r == 0.0 {
                continue;
            }
            let end = n.min(k + 3);
            let (top, rest) = a.split_at_mut(i);
            for (v, w) in rest[0][k..end].iter_mut().zip(&top[k][k..end]) {
                *v -= r * w;
            }
            x[i] -= r * x[k];
        }
    }
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n.min(i + 3)).map(|j| a[i][j] * x[j]).sum();
        x[i] = (x[i] - s) / a[i][i];
    }
    x
}

/// Unfolds a modelled face (node lines `xs`, `ys`, values x fastest) across the mirror planes:
/// the lines and values over the whole face.
fn unfold(
    xs: &[f64],
    ys: &[f64],
    v: &[f64],
    mirrored: [bool; 2],
    ext: [f64; 2],
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    // Full lines and, for each, the modelled index it mirrors.
    let full = |ls: &[f64], m: bool, l: f64| -> (Vec<f64>, Vec<usize>) {
        if !m {
            return (ls.to_vec(), (0..ls.len()).collect());
        }
        let mut p: Vec<(f64, usize)> = ls
            .iter()
            .enumerate()
            .skip(1)
            .rev()
            .map(|(k, &x)| (l - x, k))
            .collect();
        p.extend(ls.iter().copied().zip(0..));
        p.into_iter().unzip()
    };
    let (fx, ix) = full(xs, mirrored[0], ext[0]);
    let (fy, iy) = full(ys, mirrored[1], ext[1]);
    let mut out = Vec::with_capacity(fx.len() * fy.len());
    for &j in &iy {
        for &i in &ix {
            out.push(v[j * xs.len() + i]);
        }
    }
    (fx, fy, out)
}

/// P(x, y) with the sphere and P0(x, y) without it on `mesh`, over the whole face.
pub fn face_field(s: &Slab3d, mesh: &Mesh3d) -> Result<FaceField, SoftnessError> {
    check(s, mesh)?;
    let ln = lines(s, mesh)?;
    let with = face_pressure(s, &ln, s.feature)?;
    let p0 = if s.feature == Feature::None {
        with.p_pa.clone()
    } else {
        face_pressure(s, &ln, Feature::None)?.p_pa
    };
    let (p, unknowns) = (&with.p_pa, with.unknowns);
    let copies = ln
        .mirrored
        .iter()
        .map(|&m| if m { 2.0 } else { 1.0 })
        .product::<f64>();
    let (xs, ys) = (node_lines(&ln.e[0]), node_lines(&ln.e[1]));
    let ext = [s.length_m, s.width_m];
    let (x_m, y_m, p_pa) = unfold(&xs, &ys, p, ln.mirrored, ext);
    let (_, _, p0_pa) = unfold(&xs, &ys, &p0, ln.mirrored, ext);
    let (mut peak, mut low) = ((f64::NEG_INFINITY, [0.0; 2]), (f64::INFINITY, [0.0; 2]));
    for (q, (a, b)) in p_pa.iter().zip(&p0_pa).enumerate() {
        let (r, at) = (a / b, [x_m[q % x_m.len()], y_m[q / x_m.len()]]);
        if r > peak.0 {
            peak = (r, at);
        }
        if r < low.0 {
            low = (r, at);
        }
    }
    Ok(FaceField {
        x_m,
        y_m,
        p_pa,
        p0_pa,
        peak_ratio: peak.0,
        peak_at_m: peak.1,
        min_ratio: low.0,
        min_at_m: low.1,
        elements: [ln.e[0].len() - 1, ln.e[1].len() - 1, ln.e[2].len() - 1],
        unknowns,
        mirrored: ln.mirrored,
        face_force_n: copies * with.face_n,
        jaw_force_n: copies * with.jaw_n,
    })
}

#[cfg(test)]
#[path = "slab3d_tests.rs"]
mod tests;
