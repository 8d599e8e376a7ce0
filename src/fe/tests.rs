//! Validation tests against the references in fe-validation.md (Kirchhoff plate benchmarks,
//! MacNeal-Harder patch test, fixed-fixed beam Eq. 3-6) and solver invariants.

use crate::fe::*;

const B_UM: f64 = 10_000.0;
const T_UM: f64 = 100.0;

fn iso() -> PlateMaterial {
    PlateMaterial::isotropic(169e9, 0.3)
}

fn d_iso() -> f64 {
    iso().bending_stiffness(T_UM * 1e-6).d11_nm
}

/// a x b plate (b = 10 mm along y, a = ratio b along x), ny = n elements across b.
fn rect_plate(ratio: f64, n: usize, kind: SupportKind, material: PlateMaterial) -> PlateProblem {
    let nx = (ratio * n as f64).round() as usize;
    let mut p = PlateProblem::new(RectMesh::uniform(ratio * B_UM, B_UM, nx, n), T_UM, material);
    p.support_all_edges(kind);
    p
}

fn alpha_q(ratio: f64, n: usize, kind: SupportKind) -> f64 {
    let mut p = rect_plate(ratio, n, kind, iso());
    let q = 1.0;
    let (a, b) = (ratio * B_UM * 1e-6, B_UM * 1e-6);
    p.load_cases.push(vec![Load::Pressure {
        region: None,
        total_force_n: q * a * b,
    }]);
    let s = &p.solve().unwrap()[0];
    s.max_deflection().w_m * d_iso() / (q * b.powi(4))
}

fn alpha_p(ratio: f64, n: usize, kind: SupportKind) -> f64 {
    let mut p = rect_plate(ratio, n, kind, iso());
    let b = B_UM * 1e-6;
    p.load_cases.push(vec![Load::Point {
        x_um: 0.5 * ratio * B_UM,
        y_um: 0.5 * B_UM,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    let s = &p.solve().unwrap()[0];
    s.deflection_m(0.5 * ratio * B_UM, 0.5 * B_UM) * d_iso() / b.powi(2)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Three-mesh Richardson value of a point-load alpha (O(h^2) is not assumed: the observed order is
/// used).
fn alpha_p_extrapolated(ratio: f64, n: usize, kind: SupportKind) -> (f64, Richardson) {
    let v: Vec<f64> = [n, 2 * n, 4 * n]
        .iter()
        .map(|&m| alpha_p(ratio, m, kind))
        .collect();
    let r = richardson(v[0], v[1], v[2], 2.0);
    (r.extrapolated, r)
}

const SS_Q: [(f64, f64); 4] = [
    (1.0, 0.00406235266),
    (1.5, 0.00772402162),
    (2.0, 0.01012866306),
    (3.0, 0.01223281084),
];
const SS_P: [(f64, f64); 4] = [
    (1.0, 0.0116008398),
    (1.5, 0.0153328266),
    (2.0, 0.0165239492),
    (3.0, 0.0169339503),
];
const CL_Q: [(f64, f64); 4] = [
    (1.0, 0.00126532),
    (1.5, 0.0021965),
    (2.0, 0.0025330),
    (3.0, 0.0026172),
];
const CL_P: [(f64, f64); 4] = [
    (1.0, 0.0056120),
    (1.5, 0.007043),
    (2.0, 0.007231),
    (3.0, 0.007243),
];

#[test]
fn macneal_harder_patch_test() {
    // w = 1e-3 (1 + x + 2y + x^2 + xy + y^2)/2 on 0.24 x 0.12 (m), E = 1e6, nu = 0.25, t = 0.001.
    let w = |x: f64, y: f64| 1e-3 * (1.0 + x + 2.0 * y + x * x + x * y + y * y) / 2.0;
    let wx = |x: f64, y: f64| 1e-3 * (1.0 + 2.0 * x + y) / 2.0;
    let wy = |x: f64, y: f64| 1e-3 * (2.0 + x + 2.0 * y) / 2.0;
    let xs = [0.0, 0.04, 0.10, 0.18, 0.24].map(|v| v * 1e6);
    let ys = [0.0, 0.03, 0.08, 0.12].map(|v| v * 1e6);
    let mesh = RectMesh {
        x_um: xs.to_vec(),
        y_um: ys.to_vec(),
    };
    let mut p = PlateProblem::new(mesh, 1000.0, PlateMaterial::isotropic(1e6, 0.25));
    for (i, &x) in xs.iter().enumerate() {
        for (j, &y) in ys.iter().enumerate() {
            if i == 0 || j == 0 || i == xs.len() - 1 || j == ys.len() - 1 {
                let (xm, ym) = (x * 1e-6, y * 1e-6);
                for (dof, value) in [
                    (Dof::W, w(xm, ym)),
                    (Dof::Wx, wx(xm, ym)),
                    (Dof::Wy, wy(xm, ym)),
                    (Dof::Wxy, 0.5e-3),
                ] {
                    p.prescribed.push(PrescribedDof {
                        group: "boundary".into(),
                        x_um: x,
                        y_um: y,
                        dof,
                        value,
                    });
                }
            }
        }
    }
    p.load_cases.push(vec![]);
    let s = &p.solve().unwrap()[0];
    let d = 1e6 * 1e-9 / (12.0 * (1.0 - 0.0625));
    // Exact: Mx = My = D (1 + nu) w_xx = 1.1111e-7, Mxy = D (1 - nu) w_xy = 3.3333e-8 (magnitudes);
    // with kappa = -w_xx the moments here are negative.
    let (mx_ref, mxy_ref) = (d * 1.25 * 1e-3, d * 0.75 * 0.5e-3);
    assert!(rel(mx_ref, 1.111e-7) < 1e-3 && rel(mxy_ref, 3.333e-8) < 1e-3);
    let mut worst: f64 = 0.0;
    for e in 0..s.mesh().n_elements() {
        let (x0, y0, x1, y1) = s.mesh().element_bounds_um(e);
        for (fx, fy) in [(0.5, 0.5), (0.2, 0.7), (0.9, 0.1)] {
            let m = s.moments(x0 + fx * (x1 - x0), y0 + fy * (y1 - y0));
            worst = worst
                .max(rel(-m[0], mx_ref))
                .max(rel(-m[1], mx_ref))
                .max(rel(-m[2], mxy_ref));
        }
    }
    eprintln!("patch test worst relative moment error {worst:.2e}");
    assert!(worst < 1e-6, "patch test failed: {worst}");
}

#[test]
fn simply_supported_uniform_load_5_digits() {
    for (ratio, reference) in SS_Q {
        let a = alpha_q(ratio, 16, SupportKind::SimplySupported);
        eprintln!(
            "SS q a/b={ratio}: {a:.10} ref {reference} rel {:.2e}",
            rel(a, reference)
        );
        assert!(
            rel(a, reference) < 5e-6,
            "a/b = {ratio}: {a} vs {reference}"
        );
    }
}

#[test]
fn simply_supported_point_load_5_digits() {
    for (ratio, reference) in SS_P {
        let (a, r) = alpha_p_extrapolated(ratio, 16, SupportKind::SimplySupported);
        let fine = alpha_p(ratio, 64, SupportKind::SimplySupported);
        eprintln!(
            "SS P a/b={ratio}: n=64 {fine:.10} (rel {:.2e}), extrapolated {a:.10} rel {:.2e}, \
             order {:?}",
            rel(fine, reference),
            rel(a, reference),
            r.observed_order
        );
        assert!(
            rel(a, reference) < 5e-6,
            "a/b = {ratio}: {a} vs {reference}"
        );
        assert!(rel(fine, reference) < 1e-4);
    }
}

#[test]
fn clamped_uniform_load_to_given_digits() {
    for (ratio, reference) in CL_Q {
        let a = alpha_q(ratio, 32, SupportKind::Clamped);
        eprintln!(
            "CL q a/b={ratio}: {a:.10} ref {reference} rel {:.2e}",
            rel(a, reference)
        );
        // Reference given to 5-6 digits: half a unit in the last digit.
        let tol = if ratio == 1.0 { 0.5e-8 } else { 0.5e-7 };
        assert!(
            (a - reference).abs() <= tol,
            "a/b = {ratio}: {a} vs {reference}"
        );
    }
}

#[test]
fn clamped_point_load_to_given_digits() {
    for (ratio, reference) in CL_P {
        let (a, r) = alpha_p_extrapolated(ratio, 16, SupportKind::Clamped);
        eprintln!(
            "CL P a/b={ratio}: extrapolated {a:.10} ref {reference} rel {:.2e} order {:?}",
            rel(a, reference),
            r.observed_order
        );
        // Half a unit in the last given digit, except a/b = 3: the converged value here is
        // 0.00724244 (meshes 16..128 agree to 1e-9), 6e-8 below the rounding boundary of
        // the given 0.007243, so only 1e-4 relative is asserted there (see the strip test
        // for an independent check).
        let tol = match ratio {
            1.0 => 0.5e-7,
            3.0 => 1e-4 * reference,
            _ => 0.5e-6,
        };
        assert!(
            (a - reference).abs() <= tol,
            "a/b = {ratio}: {a} vs {reference}"
        );
    }
}

#[test]
fn strip_limit() {
    // a/b = 8 approaches cylindrical bending at the centre: 5/384 (SS) and 1/384 (clamped) within
    // 0.5 %.
    let ss = alpha_q(8.0, 8, SupportKind::SimplySupported);
    let cl = alpha_q(8.0, 8, SupportKind::Clamped);
    eprintln!(
        "strip: SS {ss:.8} vs {:.8}, clamped {cl:.8} vs {:.8}",
        5.0 / 384.0,
        1.0 / 384.0
    );
    assert!(rel(ss, 5.0 / 384.0) < 5e-3);
    assert!(rel(cl, 1.0 / 384.0) < 5e-3);
    // Point load at a/b = 6 against the strip values (SS 0.0169611; clamped 0.00725 is 3-digit
    // Timoshenko: a Fourier-transform solution of the clamped strip computed while writing this
    // test gives 0.0072425, which the FE reproduces).
    let (ss_p, _) = alpha_p_extrapolated(6.0, 8, SupportKind::SimplySupported);
    let (cl_p, _) = alpha_p_extrapolated(6.0, 8, SupportKind::Clamped);
    eprintln!(
        "strip point: SS {ss_p:.8} vs 0.0169611, clamped {cl_p:.8} vs 0.00725 (Fourier 0.0072425)"
    );
    assert!(rel(ss_p, 0.0169611) < 1e-5);
    assert!(rel(cl_p, 0.00725) < 1.5e-3 && rel(cl_p, 0.0072425) < 1e-5);
}

/// Plate clamped on y = 0 and y = span, free ends at x = 0 and x = length, line load along x at y0.
fn line_load_plate(material: PlateMaterial, y0_um: f64) -> (PlateSolution, f64, f64) {
    let (span, length) = (5000.0, 20_000.0);
    let mesh = RectMesh::build(
        &[0.0, 8000.0, 12_000.0, length],
        &[0.0, y0_um, span],
        250.0,
        &[],
    );
    let h = mesh.x_um[1] - mesh.x_um[0];
    let mut p = PlateProblem::new(mesh, T_UM, material);
    for (g, at, from, to) in [
        ("mid0", 0.0, 8000.0, 12_000.0),
        ("mid1", span, 8000.0, 12_000.0),
        ("r1", 0.0, 0.0, length),
        ("r2", span, 0.0, length),
    ] {
        p.supports.push(LineSupport {
            group: g.into(),
            kind: SupportKind::Clamped,
            along: Axis::X,
            at_um: at,
            from_um: from,
            to_um: to,
        });
    }
    p.load_cases.push(vec![Load::Line {
        x0_um: 0.0,
        y0_um,
        x1_um: length,
        y1_um: y0_um,
        total_force_n: 2.0,
    }]);
    let s = p.solve().unwrap().remove(0);
    (s, length, 4000.0 + h)
}

#[test]
fn line_load_reproduces_fixed_fixed_beam() {
    let span = 5000.0;
    for y0 in [1500.0, 2500.0, 4000.0] {
        let beam = fixed_fixed_reactions(2.0, y0, span);
        // nu = 0: exact cylindrical bending, totals must match.
        let (s, _, _) = line_load_plate(PlateMaterial::isotropic(169e9, 0.0), y0);
        let r1 = s.reaction_n("r1").unwrap() + s.reaction_n("mid0").unwrap();
        let r2 = s.reaction_n("r2").unwrap() + s.reaction_n("mid1").unwrap();
        eprintln!(
            "beam y0={y0}: nu=0 R1 {r1:.8} vs {:.8} (rel {:.1e}), R2 {r2:.8} vs {:.8}",
            beam.r1,
            rel(r1, beam.r1),
            beam.r2
        );
        assert!(rel(r1, beam.r1) < 1e-6 && rel(r2, beam.r2) < 1e-6);
        // Orthotropic Si, free ends: the middle section carries the beam reaction per unit length
        // within 1 %.
        let (s, length, mid_len) = line_load_plate(PlateMaterial::silicon(DieEdge::Along110), y0);
        let per_len = 2.0 / length;
        let (m0, m1) = (
            s.reaction_n("mid0").unwrap() / mid_len,
            s.reaction_n("mid1").unwrap() / mid_len,
        );
        let (b1, b2) = (beam.r1 / 2.0 * per_len, beam.r2 / 2.0 * per_len);
        eprintln!(
            "beam y0={y0}: Si middle R1 {m0:.6e} vs {b1:.6e} (rel {:.1e}), R2 {m1:.6e} vs \
             {b2:.6e} (rel {:.1e})",
            rel(m0, b1),
            rel(m1, b2)
        );
        assert!(rel(m0, b1) < 0.01 && rel(m1, b2) < 0.01);
    }
}

fn clamped_si(n: usize) -> PlateProblem {
    rect_plate(
        1.5,
        n,
        SupportKind::Clamped,
        PlateMaterial::silicon(DieEdge::Along110),
    )
}

#[test]
fn reactions_sum_to_load() {
    let mut p = clamped_si(12);
    p.load_cases.push(vec![
        Load::Point {
            x_um: 3100.0,
            y_um: 7200.0,
            force_n: 0.7,
            radius_um: 0.0,
        },
        Load::Probe {
            x_um: 9000.0,
            y_um: 4000.0,
            width_um: 2000.0,
            height_um: 500.0,
            angle_deg: 33.0,
            total_force_n: 1.3,
        },
        Load::Pressure {
            region: Some(RectUm {
                x0_um: 1000.0,
                y0_um: 1000.0,
                x1_um: 4000.0,
                y1_um: 2500.0,
            }),
            total_force_n: 0.4,
        },
    ]);
    let s = &p.solve().unwrap()[0];
    let total: f64 = s.reactions().iter().map(|r| r.force_n).sum();
    eprintln!("reaction sum {total:.15} vs 2.4");
    assert!(rel(total, 2.4) < 1e-9, "{total}");
    assert!(rel(s.applied_force_n(), 2.4) < 1e-12);
}

#[test]
fn symmetric_load_mirror_reactions() {
    let mut p = rect_plate(
        1.0,
        10,
        SupportKind::Clamped,
        PlateMaterial::silicon(DieEdge::Along110),
    );
    p.load_cases.push(vec![Load::Point {
        x_um: 3000.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    p.load_cases.push(vec![Load::Point {
        x_um: 7000.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    let s = p.solve().unwrap();
    let r = |k: usize, g: &str| s[k].reaction_n(g).unwrap();
    assert!(rel(r(0, "y0"), r(0, "y1")) < 1e-9);
    assert!(rel(r(0, "x0"), r(1, "x1")) < 1e-9);
    assert!(rel(r(0, "x1"), r(1, "x0")) < 1e-9);
    assert!(r(0, "x0") > r(0, "x1"));
}

#[test]
fn linearity_superposition_determinism() {
    let p_a = Load::Point {
        x_um: 4100.0,
        y_um: 3300.0,
        force_n: 1e-3,
        radius_um: 0.0,
    };
    let p_b = Load::Probe {
        x_um: 9000.0,
        y_um: 6000.0,
        width_um: 1500.0,
        height_um: 700.0,
        angle_deg: 70.0,
        total_force_n: 2.0,
    };
    let big_a = Load::Point {
        x_um: 4100.0,
        y_um: 3300.0,
        force_n: 5.0,
        radius_um: 0.0,
    };
    let mut p = clamped_si(12);
    p.load_cases = vec![
        vec![p_a.clone()],
        vec![big_a],
        vec![p_b.clone()],
        vec![p_a, p_b],
    ];
    let f = Factorised::new(&p).unwrap();
    let s = f.solve(&p.load_cases).unwrap();
    let s2 = f.solve(&p.load_cases).unwrap();
    let pts = [(4100.0, 3300.0), (1234.0, 8765.0), (12_000.0, 2000.0)];
    for &(x, y) in &pts {
        assert!(
            rel(s[1].deflection_m(x, y), 5000.0 * s[0].deflection_m(x, y)) < 1e-12,
            "linearity"
        );
        let sum = s[0].deflection_m(x, y) + s[2].deflection_m(x, y);
        assert!(
            (s[3].deflection_m(x, y) - sum).abs() <= 1e-12 * sum.abs(),
            "superposition"
        );
    }
    for (a, b) in s.iter().zip(&s2) {
        assert_eq!(a.dofs(), b.dofs(), "determinism");
    }
    let again = clamped_si(12);
    let mut again = again;
    again.load_cases = p.load_cases.clone();
    assert_eq!(
        again.solve().unwrap()[3].dofs(),
        s[3].dofs(),
        "determinism across factorisations"
    );
}

#[test]
fn orthotropic_silicon_softer_than_isotropic() {
    let w = |m: PlateMaterial| {
        let mut p = rect_plate(1.0, 16, SupportKind::Clamped, m);
        p.load_cases.push(vec![Load::Point {
            x_um: 5000.0,
            y_um: 5000.0,
            force_n: 1.0,
            radius_um: 0.0,
        }]);
        p.solve().unwrap()[0].deflection_m(5000.0, 5000.0)
    };
    let (wo, wi) = (
        w(PlateMaterial::silicon(DieEdge::Along110)),
        w(PlateMaterial::isotropic(169e9, 0.064)),
    );
    eprintln!(
        "ortho {wo:.6e} iso {wi:.6e}: iso stiffer by {:.2} %",
        100.0 * (wo / wi - 1.0)
    );
    assert!(wo > wi && (wo / wi - 1.0) > 0.04 && (wo / wi - 1.0) < 0.10);
}

#[test]
fn refactor_reuses_symbolic() {
    let mut p = clamped_si(8);
    p.load_cases.push(vec![Load::Point {
        x_um: 7500.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    let mut f = Factorised::new(&p).unwrap();
    let w1 = f.solve(&p.load_cases).unwrap()[0].deflection_m(7500.0, 5000.0);
    p.base_thickness_um = 2.0 * T_UM;
    f.refactor(&p).unwrap();
    let w2 = f.solve(&p.load_cases).unwrap()[0].deflection_m(7500.0, 5000.0);
    assert!(rel(w1 / w2, 8.0) < 1e-9, "t^3 scaling: {}", w1 / w2);
    p.supports.pop();
    assert!(matches!(
        f.refactor(&p),
        Err(FeError::PatternMismatch { .. })
    ));
}

#[test]
fn missing_constraint_is_an_error_not_nan() {
    let mut p = PlateProblem::new(RectMesh::uniform(10_000.0, 10_000.0, 6, 6), T_UM, iso());
    p.load_cases.push(vec![Load::Point {
        x_um: 5000.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    let e = p.solve().unwrap_err();
    eprintln!("{e}");
    assert!(matches!(e, FeError::Underconstrained { free_modes: 3, .. }));
    // One simply supported edge still allows rotation about it.
    p.supports.push(LineSupport {
        group: "y0".into(),
        kind: SupportKind::SimplySupported,
        along: Axis::X,
        at_um: 0.0,
        from_um: 0.0,
        to_um: 10_000.0,
    });
    assert!(matches!(
        p.solve(),
        Err(FeError::Underconstrained { free_modes: 1, .. })
    ));
    // A cantilever (one clamped edge) is fine.
    p.supports[0].kind = SupportKind::Clamped;
    let s = p.solve().unwrap();
    assert!(s[0].max_deflection().w_m.is_finite());
    // Zero or negative thickness is reported, not factorised.
    p.thickness_regions.push(ThicknessRegion {
        x0_um: 0.0,
        y0_um: 0.0,
        x1_um: 2000.0,
        y1_um: 2000.0,
        thickness_um: 0.0,
        rise_um: 0.0,
    });
    assert!(matches!(p.solve(), Err(FeError::InvalidStiffness { .. })));
    // Support off the mesh lines.
    p.thickness_regions.clear();
    p.supports.push(LineSupport {
        group: "bad".into(),
        kind: SupportKind::Clamped,
        along: Axis::Y,
        at_um: 1234.0,
        from_um: 0.0,
        to_um: 10_000.0,
    });
    assert!(matches!(
        p.solve(),
        Err(FeError::SupportNotOnMeshLine { .. })
    ));
}

/// Checkerboard of 2.5 mm cells, thick cells 3x thicker (27x stiffer), clamped Si, 1 N at the
/// centre (a cross-point of the checkerboard).
fn checkerboard(level: usize) -> PlateProblem {
    let n = 4 << level;
    let mut p = PlateProblem::new(
        RectMesh::uniform(B_UM, B_UM, n, n),
        T_UM,
        PlateMaterial::silicon(DieEdge::Along110),
    );
    for i in 0..4 {
        for j in 0..4 {
            if (i + j) % 2 == 0 {
                let (x0, y0) = (2500.0 * i as f64, 2500.0 * j as f64);
                p.thickness_regions.push(ThicknessRegion {
                    x0_um: x0,
                    y0_um: y0,
                    x1_um: x0 + 2500.0,
                    y1_um: y0 + 2500.0,
                    thickness_um: 3.0 * T_UM,
                    rise_um: 0.0,
                });
            }
        }
    }
    p.support_all_edges(SupportKind::Clamped);
    p.load_cases.push(vec![Load::Point {
        x_um: 5000.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    p
}

/// The quantity `q` on the problems `build(level)` for each level, with the free dofs.
fn level_values(
    build: impl Fn(usize) -> PlateProblem,
    q: impl Fn(&[PlateSolution]) -> f64,
    levels: std::ops::Range<usize>,
) -> Vec<(f64, usize)> {
    levels
        .map(|level| {
            let p = build(level);
            let f = Factorised::new(&p).unwrap();
            (q(&f.solve(&p.load_cases).unwrap()), f.n_free_dofs())
        })
        .collect()
}

#[test]
fn checkerboard_convergence_reports_observed_order() {
    let q = |s: &[PlateSolution]| s[0].deflection_m(5000.0, 5000.0);
    let v = level_values(checkerboard, q, 0..5);
    let est = |k: usize| ThreeMesh::new(v[k - 2].0, v[k - 1].0, v[k].0, 2.0, 2.0);
    for (k, &(w, dofs)) in v.iter().enumerate().skip(2) {
        let e = est(k);
        eprintln!(
            "level {k} dofs {dofs} w {w:.8e} order {:?} rel.est {:.3e} kind {}",
            e.richardson.observed_order,
            e.fine_error() / w.abs(),
            e.richardson.kind
        );
    }
    // Estimate from levels 1-3 against the level-4 value.
    let e = est(3);
    let (f1, next) = (v[3].0, v[4].0);
    assert!(e.fine_error().is_finite() && e.richardson.gci_fine.is_finite());
    if let Some(p) = e.richardson.observed_order {
        assert!(p.is_finite() && p > 0.0);
    }
    // The next finer value moves towards the extrapolated one and by no more than the estimate
    // (the estimate never trusts an order above 1).
    assert!(
        (next - f1).abs() <= e.fine_error() + 1e-15,
        "next {next} f1 {f1} est {}",
        e.fine_error()
    );
    // The estimate falls level by level but slowly (p ~ 0.6): still above 1 % at level 4.
    let rel = |k: usize| est(k).fine_error() / v[k].0.abs();
    assert!(
        rel(4) < rel(3) && rel(3) < rel(2),
        "{} {} {}",
        rel(2),
        rel(3),
        rel(4)
    );
    assert!(rel(4) > 0.01, "{}", rel(4));
}

#[test]
fn hard_thin_plate_long_span() {
    // 50 um plate over a 40 mm clamped square span: still accurate; 0.1 N (w ~ 2 t) is flagged as
    // beyond the linear range, 1.6 mN (w ~ 0.03 t) is not.
    let mut p = PlateProblem::new(RectMesh::uniform(40_000.0, 40_000.0, 16, 16), 50.0, iso());
    p.support_all_edges(SupportKind::Clamped);
    p.load_cases.push(vec![Load::Pressure {
        region: None,
        total_force_n: 0.1,
    }]);
    p.load_cases.push(vec![Load::Pressure {
        region: None,
        total_force_n: 1.6e-3,
    }]);
    let s = p.solve().unwrap();
    let d = iso().bending_stiffness(50e-6).d11_nm;
    let q = 0.1 / (0.04f64 * 0.04);
    let a = s[0].max_deflection().w_m * d / (q * 0.04f64.powi(4));
    eprintln!(
        "thin plate alpha_q {a:.8} (ref 0.00126532), ratio w/t {:.1}",
        s[0].linear_range_ratio()
    );
    assert!(rel(a, 0.00126532) < 1e-5);
    assert!(s[0].exceeds_linear_range());
    assert!(!s[1].exceeds_linear_range());
}

#[test]
fn hard_load_at_free_corner() {
    // Cantilever clamped at x = 0; point load at the free corner (a, b).
    let w = |n: usize| {
        let mut p = PlateProblem::new(
            RectMesh::uniform(10_000.0, 5000.0, 2 * n, n),
            T_UM,
            PlateMaterial::silicon(DieEdge::Along110),
        );
        p.supports.push(LineSupport {
            group: "root".into(),
            kind: SupportKind::Clamped,
            along: Axis::Y,
            at_um: 0.0,
            from_um: 0.0,
            to_um: 5000.0,
        });
        p.load_cases.push(vec![Load::Point {
            x_um: 10_000.0,
            y_um: 5000.0,
            force_n: 1e-3,
            radius_um: 0.0,
        }]);
        let s = p.solve().unwrap().remove(0);
        assert!(rel(s.reaction_n("root").unwrap(), 1e-3) < 1e-9);
        let peak = s.max_deflection();
        assert!(
            (peak.x_um - 10_000.0).abs() < 1e-6 && (peak.y_um - 5000.0).abs() < 1e-6,
            "{peak:?}"
        );
        peak.w_m
    };
    let (w1, w2, w3) = (w(4), w(8), w(16));
    let r = richardson(w1, w2, w3, 2.0);
    eprintln!("free corner: {w1:.8e} {w2:.8e} {w3:.8e} -> {:?}", r);
    assert!(w3 > 0.0 && rel(w3, r.extrapolated) < 1e-3);
    // Beam bound: the corner deflects more than a cantilever beam of the full width with the same
    // load.
    let d = PlateMaterial::silicon(DieEdge::Along110).bending_stiffness(T_UM * 1e-6);
    let beam = 1e-3 * 0.01f64.powi(3) / (3.0 * d.d11_nm * 0.005);
    assert!(w3 > beam);
}

#[test]
fn hard_load_on_node_line_and_step() {
    let base = |mesh: RectMesh| {
        let mut p = PlateProblem::new(mesh, T_UM, PlateMaterial::silicon(DieEdge::Along110));
        p.support_all_edges(SupportKind::Clamped);
        p
    };
    // On a node vs just beside it: continuous.
    let mut p = base(RectMesh::uniform(10_000.0, 10_000.0, 20, 20));
    p.load_cases.push(vec![Load::Point {
        x_um: 3000.0,
        y_um: 4000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    p.load_cases.push(vec![Load::Point {
        x_um: 3000.0 + 1e-6,
        y_um: 4000.0 - 1e-6,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    // Patch centred on a mesh line (x = 5000) and on a node.
    p.load_cases.push(vec![Load::Point {
        x_um: 5000.0,
        y_um: 4250.0,
        force_n: 1.0,
        radius_um: 300.0,
    }]);
    let s = p.solve().unwrap();
    assert!(
        rel(
            s[0].deflection_m(5000.0, 5000.0),
            s[1].deflection_m(5000.0, 5000.0)
        ) < 1e-8
    );
    // The same patch on a mesh whose lines avoid x = 5000 agrees to discretisation accuracy.
    let mut q = base(RectMesh::build(
        &[0.0, 10_000.0],
        &[0.0, 10_000.0],
        10_000.0 / 21.0,
        &[],
    ));
    assert!(!q.mesh.x_um.iter().any(|&x| (x - 5000.0).abs() < 1.0));
    q.load_cases.push(vec![Load::Point {
        x_um: 5000.0,
        y_um: 4250.0,
        force_n: 1.0,
        radius_um: 300.0,
    }]);
    let sq = q.solve().unwrap();
    let (wa, wb) = (
        s[2].deflection_m(5000.0, 5000.0),
        sq[0].deflection_m(5000.0, 5000.0),
    );
    eprintln!("patch on line {wa:.6e} vs off line {wb:.6e}");
    assert!(rel(wa, wb) < 2e-3);
    // A probe straddling a thickness step (x = 5000): between the all-thin and all-thick plates.
    let probe = Load::Probe {
        x_um: 5000.0,
        y_um: 5000.0,
        width_um: 1000.0,
        height_um: 400.0,
        angle_deg: 20.0,
        total_force_n: 1.0,
    };
    let w_for = |regions: Vec<ThicknessRegion>| {
        let mut p = base(RectMesh::build(
            &[0.0, 5000.0, 10_000.0],
            &[0.0, 10_000.0],
            500.0,
            &[RefinePoint {
                x_um: 5000.0,
                y_um: 5000.0,
                h_min_um: 100.0,
            }],
        ));
        p.thickness_regions = regions;
        p.load_cases.push(vec![probe.clone()]);
        let s = p.solve().unwrap().remove(0);
        let total: f64 = s.reactions().iter().map(|r| r.force_n).sum();
        assert!(rel(total, 1.0) < 1e-9);
        s.deflection_m(5000.0, 5000.0)
    };
    let thick = |x0: f64, x1: f64| ThicknessRegion {
        x0_um: x0,
        y0_um: 0.0,
        x1_um: x1,
        y1_um: 10_000.0,
        thickness_um: 200.0,
        rise_um: 0.0,
    };
    let (thin, step, all) = (
        w_for(vec![]),
        w_for(vec![thick(5000.0, 10_000.0)]),
        w_for(vec![thick(0.0, 10_000.0)]),
    );
    eprintln!("step: thin {thin:.4e} step {step:.4e} thick {all:.4e}");
    assert!(thin > step && step > all);
    assert!(rel(thin / all, 8.0) < 1e-9);
}

#[test]
fn strain_and_stress_recovery_consistent() {
    // Clamped square, uniform load: centre bottom surface in tension, edges in compression;
    // integral of eps_y over a full span strip vanishes (clamped ends: int w_yy dy = 0).
    let mut p = rect_plate(
        1.0,
        16,
        SupportKind::Clamped,
        PlateMaterial::silicon(DieEdge::Along110),
    );
    p.load_cases.push(vec![Load::Pressure {
        region: None,
        total_force_n: 1.0,
    }]);
    let s = &p.solve().unwrap()[0];
    let c = s.bottom_strain(5000.0, 5000.0);
    let e = s.bottom_strain(5000.0, 0.0);
    assert!(c[0] > 0.0 && c[1] > 0.0 && e[1] < 0.0);
    let (ix, iy) = s.integrate_bottom_strain(RectUm {
        x0_um: 4000.0,
        y0_um: 0.0,
        x1_um: 6000.0,
        y1_um: 10_000.0,
    });
    eprintln!("int eps_x {ix:.4e}, int eps_y {iy:.4e} m^2");
    assert!(iy.abs() < 1e-9 * ix.abs().max(1e-30) * 1e3 && ix > 0.0);
    let peak = s
        .max_principal_stress(RectUm {
            x0_um: 0.0,
            y0_um: 0.0,
            x1_um: 10_000.0,
            y1_um: 10_000.0,
        })
        .unwrap();
    assert!(s
        .max_principal_stress(RectUm {
            x0_um: 20_000.0,
            y0_um: 0.0,
            x1_um: 30_000.0,
            y1_um: 1.0
        })
        .is_none());
    eprintln!("peak stress {peak:?}");
    // Largest tension of a clamped plate is at the edge midpoints on the loaded (top) side.
    assert_eq!(peak.surface, Surface::Top);
    assert!((peak.x_um - 5000.0).abs() < 1.0 || (peak.y_um - 5000.0).abs() < 1.0);
}

#[test]
fn moments_and_stress_against_timoshenko() {
    // Clamped square, uniform q, nu = 0.3: centre Mx ~ 0.0231 q b^2, edge-midpoint Mx ~ -0.0513 q
    // b^2 (Timoshenko & Woinowsky-Krieger Table 35, 3 digits, quoted from memory: not in
    // fe-validation.md), surface stress 6 M / t^2. Moments converge O(h^2): compare Richardson
    // values of n = 16, 32, 64.
    let run = |n: usize| {
        let mut p = rect_plate(1.0, n, SupportKind::Clamped, iso());
        p.load_cases.push(vec![Load::Pressure {
            region: None,
            total_force_n: 1.0,
        }]);
        let s = p.solve().unwrap().remove(0);
        let qb2 = 1.0 / 1e-4 * 1e-4;
        let peak = s
            .max_principal_stress(RectUm {
                x0_um: 0.0,
                y0_um: 0.0,
                x1_um: 10_000.0,
                y1_um: 10_000.0,
            })
            .unwrap();
        (
            s.moments(5000.0, 5000.0)[0] / qb2,
            s.moments(0.0, 5000.0)[0] / qb2,
            peak.sigma_pa * (T_UM * 1e-6f64).powi(2) / 6.0 / qb2,
        )
    };
    let (a, b, c) = (run(16), run(32), run(64));
    let mc = richardson(a.0, b.0, c.0, 2.0);
    let me = richardson(a.1, b.1, c.1, 2.0);
    let ms = richardson(a.2, b.2, c.2, 2.0);
    eprintln!("centre Mx/(q b^2) {:?} -> {mc:?}", (a.0, b.0, c.0));
    eprintln!("edge Mx/(q b^2) {:?} -> {me:?}", (a.1, b.1, c.1));
    eprintln!("peak stress t^2/(6 q b^2) {:?} -> {ms:?}", (a.2, b.2, c.2));
    assert!((mc.extrapolated - 0.0231).abs() < 3e-4 && (me.extrapolated + 0.0513).abs() < 3e-4);
    assert!((ms.extrapolated - 0.0513).abs() < 3e-4);
}

#[test]
fn smooth_problem_reports_high_observed_order() {
    // SS square, uniform load: BFS deflection converges O(h^4) (fe-validation.md); the estimate
    // must measure the order, not assume it.
    let build = |level: usize| {
        let mut p = rect_plate(1.0, 2 << level, SupportKind::SimplySupported, iso());
        p.load_cases.push(vec![Load::Pressure {
            region: None,
            total_force_n: 1.0,
        }]);
        p
    };
    let q = |s: &[PlateSolution]| s[0].deflection_m(5000.0, 5000.0);
    let v = level_values(build, q, 0..5);
    let e = ThreeMesh::new(v[2].0, v[3].0, v[4].0, 2.0, 2.0);
    let p = e.richardson.observed_order.unwrap();
    eprintln!("SS values {v:?} order {p}");
    assert!(p > 3.0 && p < 5.0, "observed order {p}");
    // q = 1 N / b^2 = 1e4 Pa: w = alpha q b^4 / D.
    let exact = 0.00406235266 * 1e4 * 1e-8 / d_iso();
    let estimate = e.fine_error() / v[4].0.abs();
    eprintln!(
        "extrapolated {:.10e} exact {exact:.10e}",
        e.richardson.extrapolated
    );
    // The estimate bounds the true error and is not wildly pessimistic.
    let true_error = rel(v[4].0, exact);
    assert!(
        true_error <= estimate && estimate < 1e-4,
        "{true_error} {estimate}"
    );
}

#[test]
#[should_panic(expected = "empty mesh")]
fn empty_mesh_panics() {
    let mut p = PlateProblem::new(
        RectMesh {
            x_um: vec![0.0],
            y_um: vec![0.0, 1.0],
        },
        T_UM,
        iso(),
    );
    p.support_all_edges(SupportKind::Clamped);
    let _ = p.solve();
}

#[test]
#[should_panic(expected = "outside the plate")]
fn evaluation_outside_plate_panics() {
    let mut p = rect_plate(1.0, 4, SupportKind::Clamped, iso());
    p.load_cases.push(vec![Load::Point {
        x_um: 5000.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    let s = p.solve().unwrap();
    s[0].deflection_m(-1.0, 5000.0);
}

#[test]
fn load_outside_plate_is_an_error() {
    let mut p = rect_plate(1.0, 4, SupportKind::Clamped, iso());
    p.load_cases.push(vec![Load::Probe {
        x_um: 9900.0,
        y_um: 5000.0,
        width_um: 500.0,
        height_um: 500.0,
        angle_deg: 10.0,
        total_force_n: 1.0,
    }]);
    assert!(matches!(
        p.solve(),
        Err(FeError::LoadOutsidePlate {
            case: 0,
            index: 0,
            ..
        })
    ));
}

/// Navier double series for a simply supported orthotropic plate, centre point load (Reddy, Eq.
/// 6.2.7 with H = D12 + 2 D66): w = 4P/(ab) sum_{m,n odd} 1/(pi^4 [D11 (m/a)^4 + 2H (m/a)^2 (n/b)^2
/// + D22 (n/b)^4]).
fn navier_ss_centre(d: BendingStiffness, a: f64, b: f64, force_n: f64, terms: usize) -> f64 {
    let h = d.d12_nm + 2.0 * d.d66_nm;
    let mut s = 0.0;
    for m in (1..=terms).step_by(2) {
        let am = (m as f64 / a).powi(2);
        for n in (1..=terms).step_by(2) {
            let bn = (n as f64 / b).powi(2);
            // sin(m pi/2)^2 sin(n pi/2)^2 = 1 for odd m, n
            s += 1.0 / (d.d11_nm * am * am + 2.0 * h * am * bn + d.d22_nm * bn * bn);
        }
    }
    4.0 * force_n / (a * b) * s / std::f64::consts::PI.powi(4)
}

#[test]
fn orthotropic_simply_supported_matches_navier_series() {
    let si = PlateMaterial::silicon(DieEdge::Along110);
    let (a, b) = (1.5 * B_UM * 1e-6, B_UM * 1e-6);
    let d = si.bending_stiffness(T_UM * 1e-6);
    // Series tail ~ 1/M^2: extrapolate from M and 2M.
    let (s1, s2) = (
        navier_ss_centre(d, a, b, 1.0, 2001),
        navier_ss_centre(d, a, b, 1.0, 4001),
    );
    let exact = s2 + (s2 - s1) / 3.0;
    let w = |n: usize| {
        let mut p = rect_plate(1.5, n, SupportKind::SimplySupported, si);
        p.load_cases.push(vec![Load::Point {
            x_um: 7500.0,
            y_um: 5000.0,
            force_n: 1.0,
            radius_um: 0.0,
        }]);
        p.solve().unwrap()[0].deflection_m(7500.0, 5000.0)
    };
    let r = richardson(w(16), w(32), w(64), 2.0);
    eprintln!(
        "SS Si 1.5:1 centre point: FE {:.9e} (order {:?}) Navier {exact:.9e} rel {:.2e}",
        r.extrapolated,
        r.observed_order,
        rel(r.extrapolated, exact)
    );
    assert!(rel(r.extrapolated, exact) < 1e-5);
    // For comparison with the clamped case: orthotropic/isotropic ratio on a simply supported
    // square.
    let iso_d = PlateMaterial::isotropic(169e9, 0.064).bending_stiffness(T_UM * 1e-6);
    let ratio = navier_ss_centre(d, b, b, 1.0, 4001) / navier_ss_centre(iso_d, b, b, 1.0, 4001);
    eprintln!("SS square centre point: Si/iso deflection ratio {ratio:.4}");
}

#[test]
fn probe_rotation_invariants() {
    // A rotated probe equals the same rectangle described differently: (w, h, 0) = (h, w, 90) =
    // axis-aligned pressure; and (angle) = (angle + 180). Mesh lines cut the probes at arbitrary
    // places.
    let mut p = clamped_si(9);
    let probe = |w: f64, h: f64, ang: f64| Load::Probe {
        x_um: 6100.0,
        y_um: 4300.0,
        width_um: w,
        height_um: h,
        angle_deg: ang,
        total_force_n: 1.0,
    };
    p.load_cases = vec![
        vec![probe(1500.0, 700.0, 0.0)],
        vec![probe(700.0, 1500.0, 90.0)],
        vec![Load::Pressure {
            region: Some(RectUm {
                x0_um: 5350.0,
                y0_um: 3950.0,
                x1_um: 6850.0,
                y1_um: 4650.0,
            }),
            total_force_n: 1.0,
        }],
        vec![probe(1500.0, 700.0, 37.0)],
        vec![probe(1500.0, 700.0, 217.0)],
    ];
    let s = p.solve().unwrap();
    let w = |k: usize| s[k].deflection_m(6100.0, 4300.0);
    assert!(rel(w(1), w(0)) < 1e-12 && rel(w(2), w(0)) < 1e-12);
    assert!(rel(w(4), w(3)) < 1e-12);
    assert!(rel(w(3), w(0)) > 1e-4, "rotation must matter");
}

/// A plate symmetric about x = 5 mm and y = 3 mm: clamped along y = 0 and y = 6 mm, free at the
/// x ends, a centred thicker region and a centred patch load; (x1, y1) is the corner of the part
/// meshed (the whole plate, or the lower-left quarter with symmetry lines).
fn symmetric_plate(x1: f64, y1: f64, nx: usize, ny: usize) -> PlateProblem {
    let mut p = PlateProblem::new(
        RectMesh::uniform(x1, y1, nx, ny),
        80.0,
        PlateMaterial::silicon(DieEdge::Along110),
    );
    p.thickness_regions.push(ThicknessRegion {
        x0_um: 3000.0,
        y0_um: 2000.0,
        x1_um: 7000.0,
        y1_um: 4000.0,
        thickness_um: 200.0,
        rise_um: 0.0,
    });
    p.supports.push(LineSupport {
        group: "low".into(),
        kind: SupportKind::Clamped,
        along: Axis::X,
        at_um: 0.0,
        from_um: 0.0,
        to_um: x1,
    });
    p
}

/// Half and quarter models with symmetry lines, mirrored back, equal the whole-plate solve on the
/// mirrored mesh to round-off: dofs, reactions (per group and per node), strains, deflections.
#[test]
fn mirrored_quarter_equals_whole_plate() {
    let (h, c) = (0.5 * std::f64::consts::PI.sqrt() * 600.0, (5000.0, 3000.0));
    let mut whole = symmetric_plate(10_000.0, 6000.0, 20, 12);
    whole.supports.push(LineSupport {
        group: "high".into(),
        kind: SupportKind::Clamped,
        along: Axis::X,
        at_um: 6000.0,
        from_um: 0.0,
        to_um: 10_000.0,
    });
    whole.load_cases.push(vec![Load::Point {
        x_um: c.0,
        y_um: c.1,
        force_n: 1.0,
        radius_um: 600.0,
    }]);
    let w = &whole.solve().unwrap()[0];

    let mut quarter = symmetric_plate(5000.0, 3000.0, 10, 6);
    for (along, at) in [(Axis::X, 3000.0), (Axis::Y, 5000.0)] {
        quarter.supports.push(LineSupport {
            group: "mirror".into(),
            kind: SupportKind::Symmetry,
            along,
            at_um: at,
            from_um: 0.0,
            to_um: 10_000.0,
        });
    }
    let patch = vec![(c.0 - h, c.1 - h), (c.0, c.1 - h), c, (c.0 - h, c.1)];
    quarter.load_cases.push(vec![Load::Polygon {
        points_um: patch,
        total_force_n: 0.25,
    }]);
    let q = &quarter.solve().unwrap()[0];
    let half = q.mirrored(Axis::Y, 5000.0, |g| g.to_string());
    let m = half.mirrored(Axis::X, 3000.0, |g| {
        if g == "low" {
            "high".into()
        } else {
            g.to_string()
        }
    });

    assert_eq!(m.mesh(), w.mesh());
    let scale = w
        .dofs()
        .iter()
        .step_by(4)
        .fold(0.0f64, |a, v| a.max(v.abs()));
    for (k, (a, b)) in m.dofs().iter().zip(w.dofs()).enumerate() {
        // Slopes and twist compared at the scale of w over the element size.
        let s = if k % 4 == 0 { scale } else { scale / 500e-6 };
        assert!((a - b).abs() <= 1e-9 * s, "dof {k}: {a} vs {b}");
    }
    for g in ["low", "high"] {
        let (a, b) = (m.reaction_n(g).unwrap(), w.reaction_n(g).unwrap());
        assert!(
            (a - b).abs() < 1e-12 && (a - 0.5).abs() < 1e-12,
            "{g}: {a} vs {b}"
        );
    }
    let nodal = |s: &PlateSolution, g: &str| {
        let mut v: Vec<(f64, f64)> = s
            .nodal_reactions(g)
            .iter()
            .map(|r| (r.x_um, r.force_n))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    for g in ["low", "high"] {
        let (a, b) = (nodal(&m, g), nodal(w, g));
        assert_eq!(
            a.len(),
            b.len(),
            "{g}: one reaction per node, the mirror line's counted once"
        );
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x.0 - y.0).abs() < 1e-9 && (x.1 - y.1).abs() < 1e-12,
                "{g}: {x:?} vs {y:?}"
            );
        }
    }
    let r = RectUm {
        x0_um: 1000.0,
        y0_um: 500.0,
        x1_um: 8000.0,
        y1_um: 5500.0,
    };
    let (ia, ib) = (m.integrate_bottom_strain(r), w.integrate_bottom_strain(r));
    assert!((ia.0 - ib.0).abs() <= 1e-9 * ib.0.abs() && (ia.1 - ib.1).abs() <= 1e-9 * ib.1.abs());
    assert!((m.max_deflection().w_m - w.max_deflection().w_m).abs() <= 1e-9 * scale);
    assert!((m.applied_force_n() - 1.0).abs() < 1e-12);
}
