//! Assumed transverse shear strains for the 27-node brick: the MITC9 tying (Bucalem & Bathe,
//! "Higher-order MITC general shell elements", IJNME 36, 1993; Bathe, Finite Element Procedures,
//! 2nd ed. 2014, sec. 5.4, beam, plate and shell elements) carried over to the brick whose zeta
//! runs through the plate. The strain gamma_xz is sampled on the two lines xi = +-1/sqrt 3 (at the
//! point's own eta and zeta) and interpolated linearly in xi; gamma_yz likewise on eta = +-1/sqrt
//! 3. Those are the points where the quadratic brick's spurious transverse shear in bending (the
//! Legendre P2 part, 3 xi^2 - 1) vanishes, so a thin plate no longer locks: a 100 um strip on 1 mm
//! bricks reads its deflection 3.7 % low with the displacement strains and 0.016 % low tied
//! (`tests`).
//!
//! Cartesian components are tied along the reference axes, so only bricks whose xi, eta, zeta run
//! along x, y, z are tied ([`ties`] checks it; every tensor grid here has z through the plate's
//! thickness), and only parallelepipeds (a constant Jacobian): there the tied strain of any
//! displacement integrates to the plain one (two Gauss points in xi integrate the quadratic
//! exactly), so the patch test stays exact. A distorted brick (the tapered ones along the {111}
//! walls, which are stocky and do not lock) keeps its displacement strains; the mesh stays
//! conforming either way, tying changes an element's strain operator, not its displacements. The
//! tying is linear in the displacements, so the linear B keeps its sparsity per node (only rows yz
//! and xz change).

use crate::fe::solid::hex27::{self, PointGeometry, NODES};

/// How the brick's transverse shear strains gamma_yz and gamma_xz are taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TransverseShear {
    /// From the displacement field at the point (the plain isoparametric brick).
    #[default]
    Displacement,
    /// Tied on the lines xi (for gamma_xz) or eta (for gamma_yz) = +-1/sqrt 3 on every
    /// parallelepiped brick; distorted bricks as `Displacement` (module doc).
    Tied,
}

/// True if the tying applies to this brick under `shear`: tied, the brick a parallelepiped
/// (every node at x_c + J xi_n with the centre's Jacobian, to 1e-9 of its size), and its
/// reference axes xi, eta, zeta running mostly along x, y, z (each row of J largest on its own
/// axis: gamma_xz is tied along xi and gamma_yz along eta, which on a brick whose zeta runs
/// along x would tie the wrong shears; such a brick keeps its plain strains).
pub fn ties(nodes_m: &[[f64; 3]; NODES], shear: TransverseShear) -> bool {
    if shear != TransverseShear::Tied {
        return false;
    }
    let centre = nodes_m[13];
    let j = hex27::jacobian(nodes_m, [0.0; 3]);
    let along_axes = (0..3).all(|r| (0..3).all(|d| d == r || j[r][d].abs() < j[r][r].abs()));
    if !along_axes {
        return false;
    }
    let size = (0..3)
        .map(|r| j[r].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    nodes_m.iter().enumerate().all(|(n, x)| {
        let xi = [n % 3, (n / 3) % 3, n / 9].map(hex27::node_coordinate);
        (0..3).all(|d| {
            let affine = centre[d] + (0..3).map(|r| xi[r] * j[r][d]).sum::<f64>();
            (x[d] - affine).abs() <= 1e-9 * size
        })
    })
}

/// The tying coordinate 1/sqrt 3: the zeros of the Legendre polynomial P2.
pub const TYING: f64 = 0.577_350_269_189_625_8;

/// Linear Lagrange weights at `s` of the two tying lines -TYING and +TYING.
pub fn tying_weights(s: f64) -> [f64; 2] {
    [0.5 * (1.0 - s / TYING), 0.5 * (1.0 + s / TYING)]
}

/// The four tying points of `xi` with their weights: `[(point, weight); 2]` for gamma_xz (Voigt
/// row 4, lines in xi) then two for gamma_yz (row 3, lines in eta).
pub fn tying_points(xi: [f64; 3]) -> [([f64; 3], f64); 4] {
    let wx = tying_weights(xi[0]);
    let wy = tying_weights(xi[1]);
    [
        ([-TYING, xi[1], xi[2]], wx[0]),
        ([TYING, xi[1], xi[2]], wx[1]),
        ([xi[0], -TYING, xi[2]], wy[0]),
        ([xi[0], TYING, xi[2]], wy[1]),
    ]
}

/// One node's strain-displacement coefficients: rows xx, yy, zz and xy are the shape gradient
/// `n` (B_n of [`hex27::strain`]); row yz takes `yz[0]` u_y + `yz[1]` u_z and row xz takes
/// `xz[0]` u_x + `xz[1]` u_z (Nz, Ny and Nz, Nx without tying).
#[derive(Debug, Clone, Copy, Default)]
pub struct NodeB {
    pub n: [f64; 3],
    pub yz: [f64; 2],
    pub xz: [f64; 2],
}

/// The geometry at `xi` and every node's B coefficients, the shears tied if `tied` (what
/// [`ties`] says of the brick, asked once per brick by the caller).
pub fn b_at(
    nodes_m: &[[f64; 3]; NODES],
    xi: [f64; 3],
    tied: bool,
) -> (PointGeometry, [NodeB; NODES]) {
    let g = hex27::geometry(nodes_m, xi);
    let mut b: [NodeB; NODES] = std::array::from_fn(|n| {
        let [nx, ny, nz] = g.dn_dx[n];
        NodeB {
            n: [nx, ny, nz],
            yz: [nz, ny],
            xz: [nz, nx],
        }
    });
    if tied {
        for b in b.iter_mut() {
            b.yz = [0.0; 2];
            b.xz = [0.0; 2];
        }
        for (k, (p, w)) in tying_points(xi).into_iter().enumerate() {
            let t = hex27::geometry(nodes_m, p);
            for (bn, [nx, ny, nz]) in b.iter_mut().zip(t.dn_dx) {
                if k < 2 {
                    bn.xz[0] += w * nz;
                    bn.xz[1] += w * nx;
                } else {
                    bn.yz[0] += w * nz;
                    bn.yz[1] += w * ny;
                }
            }
        }
    }
    (g, b)
}

/// Small strain (Voigt, engineering shears) at `xi` under `shear`.
pub fn strain_at(
    nodes_m: &[[f64; 3]; NODES],
    u_m: &[f64; hex27::DOFS],
    xi: [f64; 3],
    shear: TransverseShear,
) -> [f64; 6] {
    let (_, b) = b_at(nodes_m, xi, ties(nodes_m, shear));
    let mut e = [0.0; 6];
    for (n, bn) in b.iter().enumerate() {
        let (ux, uy, uz) = (u_m[3 * n], u_m[3 * n + 1], u_m[3 * n + 2]);
        let [nx, ny, nz] = bn.n;
        e[0] += nx * ux;
        e[1] += ny * uy;
        e[2] += nz * uz;
        e[3] += bn.yz[0] * uy + bn.yz[1] * uz;
        e[4] += bn.xz[0] * ux + bn.xz[1] * uz;
        e[5] += ny * ux + nx * uy;
    }
    e
}
