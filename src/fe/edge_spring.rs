//! Elastic edge supports ([`EdgeSpring`]): a distributed spring on w and the normal slope along a
//! mesh line, integrated with the BFS element's own edge interpolation (along a line the BFS
//! field is Hermite-cubic in w with the tangential slope, and in the normal slope with the twist;
//! Bogner, Fox, Schmit 1965), so the springs add no dofs and fall inside the existing stencil.

use crate::fe::dofs::MeshLine;
use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;
use crate::fe::problem::{Axis, EdgeSpring};

/// One segment of a spring's line: its two nodes (start, end) and its length (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringSegment {
    pub nodes: [usize; 2],
    /// Tangential coordinates of the two nodes (um).
    pub t_um: [f64; 2],
}

/// Segments of the spring's line within [from_um, to_um]; an error if the line is not a mesh line
/// or holds no segment.
pub fn segments(mesh: &RectMesh, s: &EdgeSpring) -> FeResult<Vec<SpringSegment>> {
    let line = MeshLine::find(
        mesh,
        s.along,
        s.at_um,
        (s.from_um, s.to_um),
        &s.group,
        "add the spring line's position to the required mesh lines",
    )?;
    let out: Vec<SpringSegment> = line
        .span
        .windows(2)
        .enumerate()
        .filter(|(_, w)| line.covers(w[0]) && line.covers(w[1]))
        .map(|(m, w)| SpringSegment {
            nodes: [line.node(mesh, m), line.node(mesh, m + 1)],
            t_um: [w[0], w[1]],
        })
        .collect();
    if out.is_empty() {
        return Err(FeError::EmptySupport {
            group: s.group.clone(),
            hint: "check the spring's from_um/to_um against the plate size",
        });
    }
    Ok(out)
}

/// An error unless `g` is finite, symmetric and positive semi-definite (every principal minor
/// at least -1e-12 of its scale): a Pasternak term that is not one would make the plate
/// indefinite.
pub fn check_semi_definite(g: &[[f64; 3]; 3], group: &str) -> FeResult<()> {
    let scale = |i: usize, j: usize| (g[i][i] * g[j][j]).abs().sqrt().max(f64::MIN_POSITIVE);
    let sym = (0..3).all(|i| (0..3).all(|j| (g[i][j] - g[j][i]).abs() <= 1e-9 * scale(i, j)));
    let finite = g.iter().flatten().all(|v| v.is_finite());
    let minor2 = |i: usize, j: usize| g[i][i] * g[j][j] - g[i][j] * g[j][i];
    let det = crate::fe::solid::hex27::det3(g);
    let full = g[0][0] * g[1][1] * g[2][2];
    let psd = (0..3).all(|i| g[i][i] >= 0.0)
        && [(0, 1), (0, 2), (1, 2)]
            .iter()
            .all(|&(i, j)| minor2(i, j) >= -1e-12 * g[i][i] * g[j][j])
        && det >= -1e-12 * full.abs();
    if finite && sym && psd {
        return Ok(());
    }
    Err(FeError::NotPositiveDefinite {
        detail: format!("along-wall stiffness {g:?} on '{group}'"),
        hint: "a Pasternak term needs a finite, symmetric, positive semi-definite G",
    })
}

/// Hermite cubics on [0, 1] (values at the ends, slopes scaled by the length h).
fn hermite(xi: f64, h: f64) -> [f64; 4] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        h * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        h * (x3 - x2),
    ]
}

/// Row vectors N_w and N_theta over the segment's 8 dofs (node a: w, w_x, w_y, w_xy; node b
/// likewise) at xi.
pub(crate) fn shape_rows(s: &EdgeSpring, xi: f64, h_m: f64) -> ([f64; 8], [f64; 8]) {
    rows_from(s, hermite(xi, h_m))
}

/// N_w and N_theta over the segment's 8 dofs from the four Hermite functions (or their
/// derivatives) `hm`: w and the tangential slope carry w; the normal slope and the twist carry
/// theta.
fn rows_from(s: &EdgeSpring, hm: [f64; 4]) -> ([f64; 8], [f64; 8]) {
    let (tang, normal, twist) = match s.along {
        Axis::X => (1, 2, 3),
        Axis::Y => (2, 1, 3),
    };
    let (mut nw, mut nt) = ([0.0; 8], [0.0; 8]);
    for (node, (v, d)) in [(0, (hm[0], hm[1])), (1, (hm[2], hm[3]))] {
        nw[4 * node] = v;
        nw[4 * node + tang] = d;
        nt[4 * node + normal] = s.outward * v;
        nt[4 * node + twist] = s.outward * d;
    }
    (nw, nt)
}

/// The tangential derivatives (1/m) of [`shape_rows`]' N_w and N_theta at xi.
pub(crate) fn shape_rows_dt(s: &EdgeSpring, xi: f64, h_m: f64) -> ([f64; 8], [f64; 8]) {
    let x2 = xi * xi;
    rows_from(
        s,
        [
            (6.0 * x2 - 6.0 * xi) / h_m,
            1.0 - 4.0 * xi + 3.0 * x2,
            (6.0 * xi - 6.0 * x2) / h_m,
            3.0 * x2 - 2.0 * xi,
        ],
    )
}

pub(crate) const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// Segment stiffness int (N^T K N + N'^T G N') dt over the segment (8 x 8, row-major by the
/// dofs of shape_rows), G the (w, theta) block of [`EdgeSpring::along_wall`]; 4-point Gauss is
/// exact for the products of cubics.
pub fn segment_matrix(s: &EdgeSpring, seg: &SpringSegment) -> [[f64; 8]; 8] {
    let h = (seg.t_um[1] - seg.t_um[0]) * 1e-6;
    let mut m = [[0.0; 8]; 8];
    let mut add = |k: [[f64; 2]; 2], (nw, nt): ([f64; 8], [f64; 8]), wq: f64| {
        for i in 0..8 {
            let ai = k[0][0] * nw[i] + k[0][1] * nt[i];
            let bi = k[1][0] * nw[i] + k[1][1] * nt[i];
            for j in 0..8 {
                m[i][j] += wq * h * (ai * nw[j] + bi * nt[j]);
            }
        }
    };
    for (xi, wq) in GAUSS4 {
        add(s.stiffness, shape_rows(s, xi, h), wq);
        if let Some(g) = s.along_wall {
            add(
                [[g[0][0], g[0][1]], [g[1][0], g[1][1]]],
                shape_rows_dt(s, xi, h),
                wq,
            );
        }
    }
    m
}

/// (w, theta) of the spring's line at tangential coordinate t_um from the global dofs `u` (4
/// bending dofs per node; theta pointing away from the plate, as the spring takes it); None off
/// the line's segments.
pub fn edge_state(
    s: &EdgeSpring,
    segs: &[SpringSegment],
    u: &[f64],
    t_um: f64,
) -> Option<(f64, f64)> {
    let seg = segs
        .iter()
        .find(|g| t_um >= g.t_um[0] && t_um <= g.t_um[1])?;
    let h = (seg.t_um[1] - seg.t_um[0]) * 1e-6;
    let xi = (t_um - seg.t_um[0]) / (seg.t_um[1] - seg.t_um[0]);
    let (nw, nt) = shape_rows(s, xi, h);
    let ue = segment_dofs(seg, 4).map(|d| u[d]);
    let w = nw.iter().zip(&ue).map(|(a, b)| a * b).sum();
    let t = nt.iter().zip(&ue).map(|(a, b)| a * b).sum();
    Some((w, t))
}

/// Adds every spring's segment matrices to the assembled lower-triangle values of `pattern`.
pub fn add_to_values(
    pattern: &crate::fe::assemble::Pattern,
    vals: &mut [f64],
    mesh: &RectMesh,
    free_index: &[usize],
    springs: &[(EdgeSpring, Vec<SpringSegment>)],
) {
    for (s, segs) in springs {
        for seg in segs {
            let m = segment_matrix(s, seg);
            let flat: Vec<f64> = m.iter().flatten().copied().collect();
            pattern.add_node_block(vals, mesh, free_index, &seg.nodes, &flat);
        }
    }
}

/// Global dofs of a segment in [`segment_matrix`] order, `m` dofs per node (the 4 bending dofs
/// first).
pub fn segment_dofs(seg: &SpringSegment, m: usize) -> [usize; 8] {
    std::array::from_fn(|i| m * seg.nodes[i / 4] + i % 4)
}

/// Adds the springs' forces K_s u to the internal force `r` (`m` dofs per node).
pub fn add_forces(
    springs: &[(EdgeSpring, Vec<SpringSegment>)],
    u: &[f64],
    m: usize,
    r: &mut [f64],
) {
    for (s, segs) in springs {
        for seg in segs {
            let k = segment_matrix(s, seg);
            let dofs = segment_dofs(seg, m);
            for i in 0..8 {
                r[dofs[i]] += (0..8).map(|j| k[i][j] * u[dofs[j]]).sum::<f64>();
            }
        }
    }
}

/// Force each spring node takes in the load direction, (K_s u) at its w dof, per node of every
/// spring: (spring index, node, force N); `m` dofs per node.
pub fn nodal_forces(
    springs: &[(EdgeSpring, Vec<SpringSegment>)],
    u: &[f64],
    m: usize,
) -> Vec<(usize, usize, f64)> {
    let mut out: Vec<(usize, usize, f64)> = Vec::new();
    for (i, (s, segs)) in springs.iter().enumerate() {
        for seg in segs {
            let k = segment_matrix(s, seg);
            let dofs = segment_dofs(seg, m);
            for (a, row) in [(0usize, 0usize), (1, 4)] {
                let f: f64 = (0..8).map(|j| k[row][j] * u[dofs[j]]).sum();
                let node = seg.nodes[a];
                // Segments run in order: a shared node is the last one pushed.
                match out.last_mut() {
                    Some(o) if o.0 == i && o.1 == node => o.2 += f,
                    _ => out.push((i, node, f)),
                }
            }
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A spring along x at y = 0 (outward -1) with only a Pasternak term, on `n` segments of
    /// [0, L].
    pub(crate) fn pasternak_line(
        g: [[f64; 3]; 3],
        n: usize,
        l_um: f64,
    ) -> (EdgeSpring, Vec<SpringSegment>) {
        let s = EdgeSpring {
            group: "line".into(),
            along: Axis::X,
            at_um: 0.0,
            from_um: 0.0,
            to_um: l_um,
            outward: -1.0,
            stiffness: [[0.0; 2]; 2],
            normal_in_plane_pa: None,
            coupled: None,
            along_wall: Some(g),
        };
        let segs = (0..n)
            .map(|i| SpringSegment {
                nodes: [i, i + 1],
                t_um: [l_um * i as f64 / n as f64, l_um * (i + 1) as f64 / n as f64],
            })
            .collect();
        (s, segs)
    }

    #[test]
    fn the_pasternak_term_stores_g_k2_over_a_wave() {
        // w = a cos(k x) and theta = b cos(k x) (theta = -w_y here, outward -1) over a half
        // wavelength: 1/2 int q'^T G q' dx = G k^2 L / 4 per pair, summed over the segments'
        // 8 x 8 blocks; a uniform motion stores nothing (the term only sees the gradient).
        let g = [[400.0, 0.03, 0.0], [0.03, 6e-5, 0.0], [0.0, 0.0, 0.0]];
        let (l_um, n) = (9_710.0, 48);
        let (s, segs) = pasternak_line(g, n, l_um);
        let k = std::f64::consts::PI / (l_um * 1e-6);
        let (a, b) = (1e-6, 2e-4);
        let energy = |wave: bool| {
            let mut e = 0.0;
            for seg in &segs {
                let m = segment_matrix(&s, seg);
                let u: Vec<f64> = seg
                    .t_um
                    .iter()
                    .flat_map(|&x| {
                        let (c, sn) = if wave {
                            ((k * x * 1e-6).cos(), (k * x * 1e-6).sin())
                        } else {
                            (1.0, 0.0)
                        };
                        // w, w_x, w_y = -theta, w_xy.
                        [a * c, -a * k * sn, -b * c, b * k * sn]
                    })
                    .collect();
                for i in 0..8 {
                    for j in 0..8 {
                        e += 0.5 * u[i] * m[i][j] * u[j];
                    }
                }
            }
            e
        };
        let exact =
            (g[0][0] * a * a + 2.0 * g[0][1] * a * b + g[1][1] * b * b) * k * k * (l_um * 1e-6)
                / 4.0;
        let e = energy(true);
        assert!((e - exact).abs() < 1e-6 * exact, "{e} {exact}");
        assert!(energy(false).abs() < 1e-12 * exact);
    }

    #[test]
    fn a_pasternak_term_that_is_not_semi_definite_is_refused() {
        let ok = [
            [400.0, 0.03, -781.0],
            [0.03, 6e-5, 0.2],
            [-781.0, 0.2, 7944.0],
        ];
        assert!(check_semi_definite(&ok, "l").is_ok());
        // The rigid base's raw (w, theta) block: coupling above the diagonals' mean.
        let bad = [[663.6, 0.278, 0.0], [0.278, 7.4e-5, 0.0], [0.0, 0.0, 1.0]];
        let err = check_semi_definite(&bad, "support1")
            .unwrap_err()
            .to_string();
        assert!(err.contains("support1"), "{err}");
        let mut neg = ok;
        neg[2][2] = -1.0;
        assert!(check_semi_definite(&neg, "l").is_err());
        let mut asym = ok;
        asym[0][2] = 0.0;
        assert!(check_semi_definite(&asym, "l").is_err());
        let mut nan = ok;
        nan[1][1] = f64::NAN;
        assert!(check_semi_definite(&nan, "l").is_err());
    }
}
