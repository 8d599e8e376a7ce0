//! Natural frequencies against closed forms: the simply supported rectangle (Navier, exact for
//! Kirchhoff), a long plate clamped on its long edges against the clamped-clamped beam with D in
//! place of EI, convergence from above, mass-orthonormal modes, and the exact scalings with
//! thickness and added mass.

use std::f64::consts::PI;

use super::mass::{element_mass, MassModel};
use super::*;

/// Silicon-like isotropic plate; rho is a test value (the sensor takes its own from the process).
const E_PA: f64 = 169e9;
const RHO: f64 = 2329.0;

fn plate(lx_um: f64, ly_um: f64, nx: usize, ny: usize, t_um: f64, nu: f64) -> PlateProblem {
    PlateProblem::new(
        RectMesh::uniform(lx_um, ly_um, nx, ny),
        t_um,
        PlateMaterial::isotropic(E_PA, nu),
    )
}

fn modes(p: &PlateProblem, n: usize) -> Modes {
    natural_frequencies(
        p,
        MassModel::plate(RHO),
        ModalOptions {
            modes: n,
            ..Default::default()
        },
    )
    .unwrap()
}

/// sqrt(D / (rho t)) for the isotropic test plate.
fn stiffness_per_mass(t_um: f64, nu: f64) -> f64 {
    let t = t_um * 1e-6;
    (E_PA * t.powi(3) / (12.0 * (1.0 - nu * nu)) / (RHO * t)).sqrt()
}

/// The lowest `k` Navier frequencies of a simply supported a x b plate, Hz:
/// omega_mn = pi^2 (m^2/a^2 + n^2/b^2) sqrt(D / (rho t)) (Leissa, Vibration of Plates, NASA SP-160,
/// Eq. 4.20).
fn navier_hz(a_m: f64, b_m: f64, t_um: f64, nu: f64, k: usize) -> Vec<f64> {
    let c = stiffness_per_mass(t_um, nu);
    let mut f: Vec<f64> = (1..=8)
        .flat_map(|m| (1..=8).map(move |n| (m as f64, n as f64)))
        .map(|(m, n)| PI * PI * (m * m / (a_m * a_m) + n * n / (b_m * b_m)) * c / (2.0 * PI))
        .collect();
    f.sort_by(f64::total_cmp);
    f.truncate(k);
    f
}

#[test]
fn simply_supported_rectangle_matches_navier() {
    let (a, b, t, nu) = (10_000.0, 6_000.0, 100.0, 0.25);
    let mut p = plate(a, b, 20, 12, t, nu);
    p.support_all_edges(SupportKind::SimplySupported);
    let m = modes(&p, 6);
    let exact = navier_hz(a * 1e-6, b * 1e-6, t, nu, 6);
    for (k, (mode, f)) in m.modes.iter().zip(&exact).enumerate() {
        let rel = mode.freq_hz / f - 1.0;
        // From above (consistent mass, conforming element) and close: the sixth mode has the
        // shortest wavelength on this mesh.
        assert!(
            (0.0..2e-4).contains(&rel),
            "mode {k}: {} vs {f} Hz ({rel:.2e})",
            mode.freq_hz
        );
        // Eigenvalues to 1e-10 leave eigenvectors good to about its square root.
        assert!(mode.residual < 1e-4, "mode {k} residual {}", mode.residual);
    }
    let first = m.modes[0].freq_hz / exact[0] - 1.0;
    assert!(first < 2e-6, "fundamental {first:.2e}");
}

#[test]
fn frequencies_converge_from_above() {
    let (a, b, t, nu) = (10_000.0, 6_000.0, 100.0, 0.25);
    let exact = navier_hz(a * 1e-6, b * 1e-6, t, nu, 1)[0];
    let errors: Vec<f64> = [(2, 1), (4, 2), (8, 4), (16, 8)]
        .iter()
        .map(|&(nx, ny)| {
            let mut p = plate(a, b, nx, ny, t, nu);
            p.support_all_edges(SupportKind::SimplySupported);
            modes(&p, 1).modes[0].freq_hz / exact - 1.0
        })
        .collect();
    for w in errors.windows(2) {
        assert!(
            w[1] >= -1e-12 && w[1] < w[0],
            "not monotone from above: {errors:?}"
        );
    }
    // BFS with consistent mass: the eigenvalue error falls about as h^4 (16x per halving).
    assert!(errors[3] < errors[2] / 8.0, "{errors:?}");
}

/// A plate clamped along y = 0 and y = b, free at both ends, 10 spans long.
fn long_clamped_plate(nu: f64, ny: usize) -> PlateProblem {
    let (l, b) = (20_000.0, 2_000.0);
    let mut p = plate(l, b, 10, ny, 50.0, nu);
    for (g, y) in [("y0", 0.0), ("y1", b)] {
        p.supports.push(LineSupport {
            group: g.into(),
            kind: SupportKind::Clamped,
            along: Axis::X,
            at_um: y,
            from_um: 0.0,
            to_um: l,
        });
    }
    p
}

#[test]
fn long_plate_clamped_on_two_edges_is_the_clamped_clamped_beam() {
    let bl = super::modal::clamped_clamped_beta_l();
    assert!((bl - 4.730_040_7).abs() < 1e-6, "beta L {bl}");
    let b = 2e-3;
    // omega = (beta L)^2 / L^2 sqrt(EI / (rho A)), here per unit width with D for EI.
    let beam = |nu: f64| bl * bl / (b * b) * stiffness_per_mass(50.0, nu) / (2.0 * PI);
    // nu = 0: the cylindrical mode meets the free-edge conditions exactly (M_x = -D nu w_yy = 0),
    // so only the discretisation across the span is left.
    let f0 = modes(&long_clamped_plate(0.0, 20), 1).modes[0].freq_hz;
    let rel0 = f0 / beam(0.0) - 1.0;
    assert!(
        (0.0..1e-5).contains(&rel0),
        "nu = 0: {f0} vs {} Hz ({rel0:.2e})",
        beam(0.0)
    );
    // nu = 0.3: the free ends relax the anticlastic constraint, so the plate is softer than
    // cylindrical bending near them (measured -8.8e-4 at 10 spans long).
    let f3 = modes(&long_clamped_plate(0.3, 20), 1).modes[0].freq_hz;
    let rel3 = f3 / beam(0.3) - 1.0;
    assert!(
        (-2e-3..0.0).contains(&rel3),
        "nu = 0.3: {f3} vs {} Hz ({rel3:.2e})",
        beam(0.3)
    );
}

#[test]
fn modes_are_mass_orthonormal_and_solve_the_pencil() {
    let mut p = plate(10_000.0, 6_000.0, 10, 6, 100.0, 0.25);
    p.support_all_edges(SupportKind::SimplySupported);
    let fac = Factorised::new(&p).unwrap();
    let m = fac
        .modes(
            MassModel::plate(RHO),
            ModalOptions {
                modes: 5,
                ..Default::default()
            },
        )
        .unwrap();
    let mel = element_mass(&p.mesh, &p.element_thickness_um(), MassModel::plate(RHO)).unwrap();
    let kel = fac.element_stiffness();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    for (i, a) in m.modes.iter().enumerate() {
        let ma = mel.apply(&p.mesh, &a.shape);
        let ka = kel.apply(&p.mesh, &a.shape);
        for (j, b) in m.modes.iter().enumerate() {
            let mij = dot(&b.shape, &ma);
            let kij = dot(&b.shape, &ka) / a.eigenvalue;
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((mij - want).abs() < 1e-10, "M[{i}][{j}] = {mij}");
            assert!((kij - want).abs() < 1e-8, "K[{i}][{j}] / omega_i^2 = {kij}");
        }
    }
    // Ascending.
    assert!(m.modes.windows(2).all(|w| w[0].freq_hz <= w[1].freq_hz));
}

#[test]
fn frequency_scales_with_thickness_and_falls_with_added_mass() {
    let f = |t_um: f64, mass: MassModel| {
        let mut p = plate(8_000.0, 5_000.0, 8, 5, t_um, 0.3);
        p.support_all_edges(SupportKind::Clamped);
        natural_frequencies(&p, mass, ModalOptions::default()).unwrap()
    };
    let thin = f(50.0, MassModel::plate(RHO));
    let thick = f(100.0, MassModel::plate(RHO));
    for (a, b) in thin.modes.iter().zip(&thick.modes) {
        // K ~ t^3, M ~ t: omega ~ t, exactly on the same mesh.
        assert!(
            (b.freq_hz / a.freq_hz - 2.0).abs() < 1e-9,
            "{} {}",
            a.freq_hz,
            b.freq_hz
        );
    }
    // A non-structural layer of the plate's own areal mass: omega falls by sqrt(2).
    let loaded = f(
        50.0,
        MassModel {
            density_kg_per_m3: RHO,
            added_kg_per_m2: RHO * 50e-6,
        },
    );
    for (a, b) in thin.modes.iter().zip(&loaded.modes) {
        assert!((a.freq_hz / b.freq_hz - 2f64.sqrt()).abs() < 1e-9);
    }
}

#[test]
fn an_unsupported_plate_or_a_bad_mass_is_an_error_not_a_panic() {
    let p = plate(8_000.0, 5_000.0, 4, 3, 50.0, 0.3);
    assert!(natural_frequencies(&p, MassModel::plate(RHO), ModalOptions::default()).is_err());
    let mut q = p.clone();
    q.support_all_edges(SupportKind::Clamped);
    for bad in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            natural_frequencies(&q, MassModel::plate(bad), ModalOptions::default()),
            Err(FeError::InvalidMass { .. })
        ));
    }
}
