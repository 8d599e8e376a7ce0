//! The plate on elastic edge supports ([`EdgeSpring`]) against the beam with elastic end
//! restraints in closed form, the stiff-spring limit against the clamp, equilibrium, symmetry
//! and linearity.

use crate::fe::footing::FootingBeam;
use crate::fe::*;

const L_UM: f64 = 10_000.0;
const B_UM: f64 = 1_000.0;
const T_UM: f64 = 100.0;

fn iso() -> PlateMaterial {
    PlateMaterial::isotropic(169e9, 0.28)
}

/// End stiffness of a 300 um silicon strip on a soft foundation (about a 2 mm Plexiglas base
/// under a film), so the edges visibly settle and turn.
fn footing_k() -> [[f64; 2]; 2] {
    FootingBeam {
        d_nm: iso().bending_stiffness(300e-6).d22_nm,
        k_pa_per_m: 2e12,
        length_m: 2.5e-3,
    }
    .end_stiffness()
}

/// A strip spanning y in [0, L] (the springs' lines), b wide along x with mirror lines on both
/// long edges (cylindrical bending), or the same strip turned by 90 degrees.
fn strip(k: [[f64; 2]; 2], turned: bool, ny: usize) -> PlateProblem {
    let (lx, ly, nx, nyy) = if turned {
        (L_UM, B_UM, ny, 2)
    } else {
        (B_UM, L_UM, 2, ny)
    };
    let mut p = PlateProblem::new(RectMesh::uniform(lx, ly, nx, nyy), T_UM, iso());
    let (span, cross) = if turned {
        (Axis::Y, Axis::X)
    } else {
        (Axis::X, Axis::Y)
    };
    for (g, at, out) in [("a", 0.0, -1.0), ("b", L_UM, 1.0)] {
        p.edge_springs.push(EdgeSpring {
            group: g.into(),
            along: span,
            at_um: at,
            from_um: 0.0,
            to_um: B_UM,
            outward: out,
            stiffness: k,
            normal_in_plane_pa: None,
            coupled: None,
            along_wall: None,
        });
    }
    for at in [0.0, B_UM] {
        p.supports.push(LineSupport {
            group: "mirror".into(),
            kind: SupportKind::Symmetry,
            along: cross,
            at_um: at,
            from_um: 0.0,
            to_um: L_UM,
        });
    }
    p
}

/// Beam D w'''' = q on [0, L] with end springs [V; M] = K [w0; theta0], theta0 the slope out of
/// the span: w = w0 + A y (L - y) + q / (24 D) y^2 (L - y)^2 with V = q L / 2 and
/// M = -D w''(0) (the natural end conditions of the energy); returns w(y).
fn beam_reference(k: [[f64; 2]; 2], q: f64, d: f64, l: f64) -> impl Fn(f64) -> f64 {
    // Unknowns (w0, A); theta0 = -A L.
    // V:  k00 w0 - k01 L A = q L / 2
    // M:  k10 w0 - k11 L A = 2 A D - q L^2 / 12
    let (a11, a12, b1) = (k[0][0], -k[0][1] * l, q * l / 2.0);
    let (a21, a22, b2) = (k[1][0], -k[1][1] * l - 2.0 * d, -q * l * l / 12.0);
    let det = a11 * a22 - a12 * a21;
    let w0 = (b1 * a22 - a12 * b2) / det;
    let a = (a11 * b2 - a21 * b1) / det;
    move |y: f64| w0 + a * y * (l - y) + q / (24.0 * d) * y * y * (l - y) * (l - y)
}

fn solve(p: &mut PlateProblem, force_n: f64) -> PlateSolution {
    p.load_cases = vec![vec![Load::Pressure {
        region: None,
        total_force_n: force_n,
    }]];
    p.solve().unwrap().remove(0)
}

#[test]
fn strip_on_footings_matches_the_beam_with_elastic_end_restraints() {
    let k = footing_k();
    let f = 0.1;
    let q = f / (L_UM * B_UM * 1e-12);
    let d = iso().bending_stiffness(T_UM * 1e-6).d22_nm;
    let w_ref = beam_reference(k, q, d, L_UM * 1e-6);
    for turned in [false, true] {
        let mut p = strip(k, turned, 20);
        let s = solve(&mut p, f);
        let mut worst: f64 = 0.0;
        for j in 0..=20 {
            let y = L_UM * j as f64 / 20.0;
            let (x, yy) = if turned {
                (y, 0.5 * B_UM)
            } else {
                (0.5 * B_UM, y)
            };
            let w = s.deflection_m(x, yy);
            worst = worst.max((w - w_ref(y * 1e-6)).abs());
        }
        let w_mid = w_ref(0.5 * L_UM * 1e-6);
        // Hermite beam elements are nodally exact: only round-off remains.
        assert!(
            worst < 1e-9 * w_mid,
            "turned {turned}: {worst:e} of {w_mid:e}"
        );
        // The supports give: the span is visibly softer than clamped (q L^4 / (384 D)).
        let clamped = q * (L_UM * 1e-6).powi(4) / (384.0 * d);
        assert!(w_mid > 1.03 * clamped, "{w_mid:e} vs clamped {clamped:e}");
        // Equilibrium: the springs carry the load, half each.
        for g in ["a", "b"] {
            let r = s.reaction_n(g).unwrap();
            assert!((r - 0.5 * f).abs() < 1e-10 * f, "{g}: {r}");
        }
    }
}

#[test]
fn stiff_footing_is_the_clamp_and_the_response_is_linear() {
    let k0 = footing_k();
    let clamped = {
        let mut p = strip(k0, false, 20);
        p.edge_springs.clear();
        for (g, at) in [("a", 0.0), ("b", L_UM)] {
            p.supports.insert(
                0,
                LineSupport {
                    group: g.into(),
                    kind: SupportKind::Clamped,
                    along: Axis::X,
                    at_um: at,
                    from_um: 0.0,
                    to_um: B_UM,
                },
            );
        }
        solve(&mut p, 0.1).deflection_m(0.5 * B_UM, 0.5 * L_UM)
    };
    let mut prev = f64::INFINITY;
    for scale in [1.0, 1e2, 1e4, 1e6] {
        let k = k0.map(|r| r.map(|v| v * scale));
        let w = solve(&mut strip(k, false, 20), 0.1).deflection_m(0.5 * B_UM, 0.5 * L_UM);
        let rel = (w - clamped) / clamped;
        assert!(rel > 0.0 && rel < prev, "scale {scale}: {rel}");
        prev = rel;
    }
    assert!(prev < 1e-4, "{prev}");
    // Linearity: twice the load, twice the field.
    let mut p = strip(k0, false, 20);
    let (a, b) = (solve(&mut p, 0.1), solve(&mut p, 0.2));
    for (x, y) in [(0.0, 0.0), (500.0, 2500.0), (1000.0, 5000.0)] {
        let (wa, wb) = (a.deflection_m(x, y), b.deflection_m(x, y));
        assert!(
            (wb - 2.0 * wa).abs() < 1e-12 * wa.abs().max(1e-12),
            "{wa} {wb}"
        );
    }
}

#[test]
fn von_karman_on_footings_is_the_linear_plate_at_small_load_and_balances() {
    let mut p = strip(footing_k(), false, 20);
    let lin = solve(&mut p, 1e-4);
    let loads = p.load_cases[0].clone();
    let (nl, _) = VonKarman::new(&p, NonlinearOptions::default())
        .unwrap()
        .solve(&loads)
        .unwrap();
    let (a, b) = (
        lin.deflection_m(500.0, 5000.0),
        nl.deflection_m(500.0, 5000.0),
    );
    assert!((a - b).abs() < 1e-4 * a, "{a} {b}");
    let (ra, rb) = (nl.reaction_n("a").unwrap(), nl.reaction_n("b").unwrap());
    assert!((ra + rb - 1e-4).abs() < 1e-9 * 1e-4, "{ra} {rb}");
}
