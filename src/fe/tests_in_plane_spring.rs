//! The large-deflection plate on edge springs with an in-plane give
//! ([`EdgeSpring::normal_in_plane_pa`]): a clamped strip whose edges give in-plane against the
//! closed form (Timoshenko & Woinowsky-Krieger sec. 3 with the springs in series with the
//! strip's stretch), the stiff and soft limits (held and sliding edges), equilibrium and
//! symmetry.

use super::tests_vonkarman::{mesh, mirror_sides_and_pressure, SPAN_UM, T_UM, WIDTH_UM};
use super::vonkarman::{clamped_strip_reference, NonlinearOptions};
use super::*;

fn mat() -> PlateMaterial {
    PlateMaterial::silicon(DieEdge::Along110)
}

/// A strip spanning y in [0, SPAN] with mirror lines on both x edges (cylindrical bending), its
/// ends on edge springs stiff enough in w and the slope to be clamps (their finite stiffness
/// moves the answers by ~1e-6), with the in-plane spring `k_pa` (or held).
fn strip(n: usize, pressure_pa: f64, k_pa: Option<f64>) -> PlateProblem {
    let mut p = PlateProblem::new(mesh(n), T_UM, mat());
    for (g, at, out) in [("y0", 0.0, -1.0), ("y1", SPAN_UM, 1.0)] {
        p.edge_springs.push(EdgeSpring {
            group: g.into(),
            along: Axis::X,
            at_um: at,
            from_um: 0.0,
            to_um: WIDTH_UM,
            outward: out,
            stiffness: [[1e20, 0.0], [0.0, 1e10]],
            normal_in_plane_pa: k_pa,
            coupled: None,
            along_wall: None,
        });
    }
    mirror_sides_and_pressure(&mut p, pressure_pa);
    p
}

fn solve(p: &PlateProblem, opts: NonlinearOptions) -> PlateSolution {
    VonKarman::new(p, opts)
        .unwrap()
        .solve(&p.load_cases[0])
        .unwrap()
        .0
}

/// (A, D) of the strip in plane strain across it.
fn strip_stiffness() -> (f64, f64) {
    let t = T_UM * 1e-6;
    (mat().q22_pa * t, mat().q22_pa * t.powi(3) / 12.0)
}

/// Pressure with a linear centre deflection of 1.6 thicknesses: the membrane force matters.
fn pressure() -> f64 {
    let (_, d) = strip_stiffness();
    1.6 * T_UM * 1e-6 * 384.0 * d / (SPAN_UM * 1e-6).powi(4)
}

/// Hand derivation: the strip's membrane force N is constant, N L / A = u(L) - u(0) +
/// 1/2 int w'^2, and each end gives N / k towards the span, so N = A_eff / (2 L) int w'^2 with
/// A_eff = A / (1 + 2 A / (k L)): the clamped strip's closed form with A_eff.
#[test]
fn a_strip_on_in_plane_springs_is_the_clamped_strip_with_the_springs_in_series() {
    let (a, d) = strip_stiffness();
    let l = SPAN_UM * 1e-6;
    // Springs as soft as the strip's own stretch: A_eff = A / 2.
    let k = 2.0 * a / l;
    let q = pressure();
    let (w_ref, n_ref) = clamped_strip_reference(q, l, d, 0.5 * a);
    let (w_held, _) = clamped_strip_reference(q, l, d, a);
    assert!(
        w_ref > 1.05 * w_held,
        "the give matters: {w_ref} vs {w_held}"
    );
    let s = solve(&strip(64, q, Some(k)), NonlinearOptions::default());
    let w = s.deflection_m(0.5 * WIDTH_UM, 0.5 * SPAN_UM);
    let ny = s.membrane_forces(0.5 * WIDTH_UM, 0.5 * SPAN_UM)[1];
    assert!((w - w_ref).abs() < 2e-3 * w_ref, "{w} vs {w_ref}");
    // N sampled at the centre carries the bilinear in-plane field's error (0.4 % on the held
    // strip at this mesh, 0.9 % here); the springs' own force, k v at the ends, is the line's N.
    assert!((ny - n_ref).abs() < 1e-2 * n_ref, "{ny} vs {n_ref} N/m");
    // Each end gives N / k towards the span (v = +N/k at y = 0, -N/k at y = L).
    for (y, sign) in [(0.0, 1.0), (SPAN_UM, -1.0)] {
        let v = s.node_values(0.5 * WIDTH_UM, y)[5];
        assert!(
            (sign * v * k - n_ref).abs() < 2e-3 * n_ref,
            "k v({y}) {} vs N {n_ref}",
            v * k
        );
    }
}

#[test]
fn a_stiff_in_plane_spring_holds_the_edge_and_a_soft_one_lets_it_slide() {
    let q = pressure();
    let (a, _) = strip_stiffness();
    let k_strip = a / (SPAN_UM * 1e-6);
    let centre = |s: &PlateSolution| s.deflection_m(0.5 * WIDTH_UM, 0.5 * SPAN_UM);
    let held = centre(&solve(&strip(32, q, None), NonlinearOptions::default()));
    let stiff = centre(&solve(
        &strip(32, q, Some(1e7 * k_strip)),
        NonlinearOptions::default(),
    ));
    assert!((stiff - held).abs() < 1e-6 * held, "{stiff} vs held {held}");
    let sliding = NonlinearOptions {
        in_plane: InPlane::Sliding,
        ..Default::default()
    };
    let slid = centre(&solve(&strip(32, q, None), sliding));
    let soft = centre(&solve(
        &strip(32, q, Some(1e-7 * k_strip)),
        NonlinearOptions::default(),
    ));
    assert!(
        (soft - slid).abs() < 1e-6 * slid,
        "{soft} vs sliding {slid}"
    );
    // Sliding asked for: the in-plane springs are not applied.
    let slid_sprung = centre(&solve(&strip(32, q, Some(k_strip)), sliding));
    assert_eq!(slid_sprung, slid, "sliding ignores the in-plane springs");
    assert!(slid > 1.2 * held, "the limits differ: {slid} vs {held}");
}

/// A whole 4 x 3 mm plate on footing-like springs along y = 0 and y = 3 mm (free x edges) under
/// an off-centre point load: the springs carry the load; the in-plane springs' forces cancel
/// (nothing else holds the plate across); mirroring the load about y = 1.5 mm mirrors w and v.
#[test]
fn in_plane_springs_balance_and_mirror() {
    let k_bend = crate::fe::footing::FootingBeam {
        d_nm: mat().bending_stiffness(300e-6).d22_nm,
        k_pa_per_m: 2e12,
        length_m: 2.5e-3,
    }
    .end_stiffness();
    let k_u = 2e9;
    let plate = |y_load: f64| {
        let mut p = PlateProblem::new(RectMesh::uniform(4000.0, 3000.0, 16, 12), 50.0, mat());
        for (g, at, out) in [("a", 0.0, -1.0), ("b", 3000.0, 1.0)] {
            p.edge_springs.push(EdgeSpring {
                group: g.into(),
                along: Axis::X,
                at_um: at,
                from_um: 0.0,
                to_um: 4000.0,
                outward: out,
                stiffness: k_bend,
                normal_in_plane_pa: Some(k_u),
                coupled: None,
                along_wall: None,
            });
        }
        let load = vec![Load::Point {
            x_um: 1500.0,
            y_um: y_load,
            force_n: 1.5,
            radius_um: 0.0,
        }];
        p.load_cases.push(load);
        solve(&p, NonlinearOptions::default())
    };
    let (s, m) = (plate(1000.0), plate(2000.0));
    let w_max = s.deflection_m(1500.0, 1000.0);
    assert!(w_max > 25e-6, "membrane forces matter: {w_max}");
    let total: f64 = s.reactions().iter().map(|r| r.force_n).sum();
    assert!((total - 1.5).abs() < 1e-9, "reactions {total}");
    // Consistent spring forces k h (v_a + v_b) / 2 per segment, summed over both lines.
    let xs = &s.mesh().x_um;
    let mut fy = [0.0; 2];
    for (i, y) in [0.0, 3000.0].into_iter().enumerate() {
        for w in xs.windows(2) {
            let h = (w[1] - w[0]) * 1e-6;
            let (va, vb) = (s.node_values(w[0], y)[5], s.node_values(w[1], y)[5]);
            fy[i] += k_u * h * 0.5 * (va + vb);
        }
    }
    assert!(fy[0] > 0.0 && fy[1] < 0.0, "both edges pulled in: {fy:?}");
    assert!(
        (fy[0] + fy[1]).abs() < 1e-9 * fy[0],
        "in-plane balance {fy:?}"
    );
    for (x, y) in [
        (700.0, 1100.0),
        (3100.0, 600.0),
        (1500.0, 0.0),
        (2500.0, 2900.0),
    ] {
        let (a, b) = (s.node_values(x, y), m.node_values(x, 3000.0 - y));
        assert!((a[0] - b[0]).abs() <= 1e-9 * w_max, "w ({x}, {y})");
        let v_scale = fy[0].abs() / (k_u * 4000e-6);
        assert!(
            (a[5] + b[5]).abs() <= 1e-7 * v_scale,
            "v ({x}, {y}): {a:?} {b:?}"
        );
    }
}

/// A strip on coupled springs ([`EdgeSpring::coupled`]: the end turns and moves in plane
/// together) in the linear regime against the hand derivation. By symmetry
/// w = w_e + a y (L - y) + q y^2 (L - y)^2 / (24 D) and N = -2 A u_e / L, u_e each end's in-plane
/// displacement towards the span; the end state is (w_e, theta_e = -a L, u_e), and the potential
/// 2 D L a^2 + 2 A u_e^2 / L + q_e^T K q_e - q (w_e L + a L^3 / 6) is stationary at the answer
/// (a 3 x 3 system). The same springs without the coupling read 17 % off.
#[test]
fn a_strip_on_coupled_springs_turns_and_pulls_as_the_hand_derivation() {
    let (a_m, d) = strip_stiffness();
    let l = SPAN_UM * 1e-6;
    // Springs of the strip's own order: the end turns (k_tt 5 D / L), gives in plane (k_uu
    // 3 A / L) and couples the two strongly; w nearly held.
    let (kt, ku) = (5.0 * d / l, 3.0 * a_m / l);
    let ktu = -0.8 * (kt * ku).sqrt();
    let kw = 1e4 * d / l.powi(3);
    let k = [[kw, 0.0, 0.0], [0.0, kt, ktu], [0.0, ktu, ku]];
    let q = 1e-4 * pressure();
    // The hand solution: rows of dPi/d(w_e, a, u_e) = 0, with q_e = T x, T = diag(1, -L, 1).
    let tm = [1.0, -l, 1.0];
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = 2.0 * tm[i] * k[i][j] * tm[j];
        }
    }
    m[1][1] += 4.0 * d * l;
    m[2][2] += 4.0 * a_m / l;
    let rhs = [q * l, q * l.powi(3) / 6.0, 0.0];
    // m is symmetric: its transposed solve is its solve.
    let x = crate::fe::solid::hex27::solve_transposed(&m, rhs).expect("regular");
    let w_ref = x[0] + x[1] * l * l / 4.0 + q * l.powi(4) / (24.0 * d * 16.0);
    let n_ref = -2.0 * a_m * x[2] / l;
    let coupled = |with: bool| {
        let mut p = strip(64, q, Some(ku));
        for s in &mut p.edge_springs {
            s.stiffness = [[kw, 0.0], [0.0, kt]];
            s.coupled = with.then_some(k);
        }
        solve(&p, NonlinearOptions::default())
    };
    let s = coupled(true);
    let w = s.deflection_m(0.5 * WIDTH_UM, 0.5 * SPAN_UM);
    let ny = s.membrane_forces(0.5 * WIDTH_UM, 0.5 * SPAN_UM)[1];
    assert!((w - w_ref).abs() < 1e-3 * w_ref, "{w} vs {w_ref}");
    assert!(
        (ny - n_ref).abs() < 1e-2 * n_ref.abs(),
        "{ny} vs {n_ref} N/m"
    );
    let uncoupled = coupled(false).deflection_m(0.5 * WIDTH_UM, 0.5 * SPAN_UM);
    assert!(
        (uncoupled - w_ref).abs() > 0.03 * w_ref,
        "{uncoupled} vs {w_ref}"
    );
    // The reactions carry the load with the coupling's share.
    let total: f64 = ["y0", "y1"]
        .iter()
        .map(|g| s.reaction_n(g).unwrap_or(f64::NAN))
        .sum();
    let load = q * SPAN_UM * 1e-6 * WIDTH_UM * 1e-6;
    assert!((total - load).abs() < 1e-6 * load, "{total} vs {load}");
}
