//! Clamped rectangular plates: `fe::modal` against an independent Rayleigh-Ritz reference.
//!
//! No table of clamped-plate coefficients is in `../shared`, so the reference is computed here:
//! w(x, y) = sum c_mn f_m(xi) f_n(eta), f_m = (1 - xi^2)^2 P_m(xi) (Legendre P_m; the factor
//! makes w and its slope vanish on the edges: every term is clamped), xi = 2 x / a, eta = 2 y / b.
//! The Kirchhoff energies (Leissa, Vibration of Plates, NASA SP-160, 1969, Eq. 1.5 and 1.7)
//! U = D / 2 int (w_xx^2 + w_yy^2 + 2 nu w_xx w_yy + 2 (1 - nu) w_xy^2) dA, T = rho h omega^2 / 2
//! int w^2 dA separate into 1-D integrals of polynomials, integrated exactly by Gauss-Legendre;
//! K c = lambda M c is reduced by M's Cholesky factor and solved by a dense symmetric eigen
//! solver, to round-off. The Ritz values converge from above as the basis grows (shown).
//!
//! For the reader, Leissa's published frequency parameters lambda = omega a^2 sqrt(rho h / D) of
//! the clamped square (SP-160, Table 4.23, \[lit\]): 35.992, 73.413, 73.413, 108.27, 131.64,
//! 132.24. The test asserts against the Ritz values, not these.

use faer::{Mat, Side};

use super::mass::MassModel;
use super::*;

const E_PA: f64 = 169e9;
const RHO: f64 = 2329.0;

/// Legendre P_0..P_{n-1} and their first two derivatives at x: Bonnet's recursion and its
/// derivatives (no division by x^2 - 1, so the ends are fine).
fn legendre(n: usize, x: f64) -> Vec<[f64; 3]> {
    let mut p = vec![[0.0; 3]; n.max(2)];
    p[0] = [1.0, 0.0, 0.0];
    p[1] = [x, 1.0, 0.0];
    for k in 1..n.max(2) - 1 {
        let kf = k as f64;
        // (k + 1) P_{k+1} = (2k + 1) x P_k - k P_{k-1}, differentiated twice.
        let (a, b) = (p[k], p[k - 1]);
        let c = (2.0 * kf + 1.0) / (kf + 1.0);
        let d = kf / (kf + 1.0);
        p[k + 1] = [
            c * x * a[0] - d * b[0],
            c * (a[0] + x * a[1]) - d * b[1],
            c * (2.0 * a[1] + x * a[2]) - d * b[2],
        ];
    }
    p.truncate(n);
    p
}

/// Gauss-Legendre nodes and weights of order n (Newton on P_n from Chebyshev guesses).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let p = legendre(n + 1, x);
                let (pn, dpn) = (p[n][0], p[n][1]);
                let dx = pn / dpn;
                x -= dx;
                dp = dpn;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// f_m = (1 - x^2)^2 P_m and its two derivatives.
fn basis(n: usize, x: f64) -> Vec<[f64; 3]> {
    let (g, g1, g2) = (
        (1.0 - x * x).powi(2),
        -4.0 * x * (1.0 - x * x),
        -4.0 + 12.0 * x * x,
    );
    legendre(n, x)
        .iter()
        .map(|p| {
            [
                g * p[0],
                g1 * p[0] + g * p[1],
                g2 * p[0] + 2.0 * g1 * p[1] + g * p[2],
            ]
        })
        .collect()
}

/// The 1-D integrals int f_m^(i) f_k^(j) dxi over [-1, 1] for (i, j) in (0,0), (1,1), (2,2),
/// (2,0): exact (degree <= 2 (n + 3)).
fn integrals(n: usize) -> [Vec<Vec<f64>>; 4] {
    let mut out: [Vec<Vec<f64>>; 4] = std::array::from_fn(|_| vec![vec![0.0; n]; n]);
    for (x, w) in gauss_legendre(n + 5) {
        let f = basis(n, x);
        for m in 0..n {
            for k in 0..n {
                out[0][m][k] += w * f[m][0] * f[k][0];
                out[1][m][k] += w * f[m][1] * f[k][1];
                out[2][m][k] += w * f[m][2] * f[k][2];
                out[3][m][k] += w * f[m][2] * f[k][0];
            }
        }
    }
    out
}

/// The lowest `count` Ritz frequency parameters lambda = omega a^2 sqrt(rho h / D) of the clamped
/// a x b plate (b = `aspect` a) on the n x n basis.
fn ritz_lambdas(aspect: f64, nu: f64, n: usize, count: usize) -> Vec<f64> {
    let [a0, a1, a2, b20] = integrals(n);
    // a = 2 (xi in [-1, 1]); d/dx = d/dxi, d/dy = (2 / b) d/deta with b = 2 aspect.
    let s = 1.0 / aspect;
    let q = n * n;
    let idx = |m: usize, p: usize| m * n + p;
    let mut k = Mat::<f64>::zeros(q, q);
    let mut mm = Mat::<f64>::zeros(q, q);
    for m in 0..n {
        for p in 0..n {
            for k1 in 0..n {
                for l in 0..n {
                    let v = a2[m][k1] * a0[p][l]
                        + s.powi(4) * a0[m][k1] * a2[p][l]
                        + nu * s * s * (b20[m][k1] * b20[l][p] + b20[k1][m] * b20[p][l])
                        + 2.0 * (1.0 - nu) * s * s * a1[m][k1] * a1[p][l];
                    k[(idx(m, p), idx(k1, l))] = v;
                    mm[(idx(m, p), idx(k1, l))] = a0[m][k1] * a0[p][l];
                }
            }
        }
    }
    // K c = lambda_hat M c with D = rho h = 1, a = 2: omega^2 = lambda_hat (common Jacobian
    // cancels), lambda = omega a^2 = 4 sqrt(lambda_hat).
    let l = mm
        .llt(Side::Lower)
        .expect("the Ritz mass is positive definite");
    let lf = l.L();
    // C = L^-1 K L^-T.
    let mut z = k.clone();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(lf, z.as_mut(), faer::Par::Seq);
    let mut c = z.transpose().to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(lf, c.as_mut(), faer::Par::Seq);
    let c = Mat::from_fn(q, q, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let mut ev = c.self_adjoint_eigenvalues(Side::Lower).unwrap();
    ev.sort_by(f64::total_cmp);
    ev.iter().take(count).map(|v| 4.0 * v.sqrt()).collect()
}

/// The lowest `count` FE frequency parameters of the clamped a x b plate on nx x ny elements.
fn fe_lambdas(a_um: f64, b_um: f64, nx: usize, ny: usize, nu: f64, count: usize) -> Vec<f64> {
    let t_um = 100.0;
    let mut p = PlateProblem::new(
        RectMesh::uniform(a_um, b_um, nx, ny),
        t_um,
        PlateMaterial::isotropic(E_PA, nu),
    );
    p.support_all_edges(SupportKind::Clamped);
    let m = natural_frequencies(
        &p,
        MassModel::plate(RHO),
        ModalOptions {
            modes: count,
            ..Default::default()
        },
    )
    .unwrap();
    let t = t_um * 1e-6;
    let d = E_PA * t.powi(3) / (12.0 * (1.0 - nu * nu));
    let a = a_um * 1e-6;
    m.modes
        .iter()
        .map(|md| 2.0 * std::f64::consts::PI * md.freq_hz * a * a * (RHO * t / d).sqrt())
        .collect()
}

#[test]
fn the_ritz_reference_is_exact_where_known_and_converges() {
    // Gauss-Legendre integrates x^(2n - 1) exactly; the basis satisfies the clamped conditions.
    let g = gauss_legendre(7);
    let x12: f64 = g.iter().map(|(x, w)| w * x.powi(12)).sum();
    assert!((x12 - 2.0 / 13.0).abs() < 1e-14, "{x12}");
    for x in [-1.0, 1.0] {
        for f in basis(6, x) {
            assert!(f[0].abs() < 1e-14 && f[1].abs() < 1e-13, "{f:?}");
        }
    }
    // The fundamental of the square from above and converged: 6- to 18-term bases.
    let l: Vec<f64> = [6, 10, 14, 18]
        .iter()
        .map(|&n| ritz_lambdas(1.0, 0.3, n, 1)[0])
        .collect();
    eprintln!("Ritz clamped square lambda_1 on 6, 10, 14, 18 terms per direction: {l:?}");
    for w in l.windows(2) {
        assert!(w[1] <= w[0] * (1.0 + 1e-13), "{l:?}");
    }
    // Measured: 35.985514, 35.985194, 35.98519113, 35.98519112 (3.5e-10 between the last two:
    // the clamped corners slow a polynomial basis to algebraic convergence).
    assert!((l[3] / l[2] - 1.0).abs() < 1e-9, "{l:?}");
}

#[test]
fn clamped_square_and_rectangle_match_the_ritz_reference() {
    // The first six modes of the square and of the 2:1 rectangle (b = a / 2, so lambda is on
    // the long side a); Leissa's square values are in this file's doc comment. nu = 0.3.
    let nu = 0.3;
    for (aspect, nx, ny) in [(1.0, 16, 16), (0.5, 24, 12)] {
        let reference = ritz_lambdas(aspect, nu, 16, 6);
        let fe = fe_lambdas(10_000.0, 10_000.0 * aspect, nx, ny, nu, 6);
        let rel: Vec<f64> = fe
            .iter()
            .zip(&reference)
            .map(|(f, r)| f / r - 1.0)
            .collect();
        eprintln!("clamped b/a {aspect}: Ritz {reference:?}\n  FE {fe:?}\n  FE / Ritz - 1 {rel:?}");
        for (k, r) in rel.iter().enumerate() {
            // Conforming BFS with consistent mass: from above; within 1e-3 on these meshes.
            assert!((-1e-9..1e-3).contains(r), "mode {k}: {r:.2e}");
        }
    }
}
