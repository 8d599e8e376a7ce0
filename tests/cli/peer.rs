//! The large-deflection rung against an independent code: scikit-fem (Argyris w, P2 u and v,
//! Newton; `benches/skfem_vk.py`) on a clamped, in-plane immovable square plate under uniform
//! pressure and a central point load, at loads whose linear deflection is 0.25 to 4 thicknesses.
//! The peer runs here (scikit-fem from tests/requirements.txt); a missing module fails the test.

use tactfab::fe::{quarter_square, Load, NonlinearOptions, PlateMaterial, VonKarman};

use super::harness::root;

const SIDE_UM: f64 = 10_000.0;
const T_UM: f64 = 100.0;
const E_PA: f64 = 169e9;
const NU: f64 = 0.3;

/// One `RESULT` line of the peer.
struct Peer {
    pressure: bool,
    wlin_over_t: f64,
    w_over_t: f64,
    change: f64,
}

fn peer(max_refinement: u32) -> Vec<Peer> {
    let out = std::process::Command::new("python3")
        .arg(root().join("benches/skfem_vk.py"))
        .arg(max_refinement.to_string())
        .output()
        .expect("python3 runs");
    let (so, se) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        !se.contains("No module named"),
        "scikit-fem is missing: pip install -r tests/requirements.txt (this check does not \
         skip)\n{se}"
    );
    assert!(out.status.success(), "skfem_vk.py failed:\n{so}\n{se}");
    so.lines()
        .filter_map(|l| l.strip_prefix("RESULT "))
        .map(|l| {
            let field = |k: &str| -> &str {
                l.split_whitespace()
                    .find_map(|kv| kv.strip_prefix(&format!("{k}=")))
                    .unwrap_or_else(|| panic!("{k} in {l}"))
            };
            let num = |k: &str| field(k).parse::<f64>().expect("a number");
            Peer {
                pressure: field("case") == "pressure",
                wlin_over_t: num("wlin_over_t"),
                w_over_t: num("w_over_t"),
                change: num("change"),
            }
        })
        .collect()
}

#[test]
fn large_deflection_plate_matches_scikit_fem_on_the_clamped_square() {
    let peers = peer(3);
    assert_eq!(peers.len(), 9, "5 pressures and 4 point loads");
    let t = T_UM * 1e-6;
    let a = SIDE_UM * 1e-6;
    let d = E_PA * t.powi(3) / (12.0 * (1.0 - NU * NU));
    // Linear coefficients of the clamped square (reference/fe-validation.md, a/b = 1).
    let (alpha_q, alpha_p) = (0.00126532, 0.0056120);
    let p = quarter_square(SIDE_UM, T_UM, PlateMaterial::isotropic(E_PA, NU), 24);
    let vk = VonKarman::new(&p, NonlinearOptions::default()).expect("quarter plate");
    let mut worst: Vec<(bool, f64, f64)> = Vec::new();
    for case in &peers {
        // Quarter loads: a quarter of the pressure's force, a quarter of the point force.
        let load = if case.pressure {
            let q = case.wlin_over_t * t * d / (alpha_q * a.powi(4));
            Load::Pressure {
                region: None,
                total_force_n: q * a * a / 4.0,
            }
        } else {
            let f = case.wlin_over_t * t * d / (alpha_p * a * a);
            Load::Point {
                x_um: SIDE_UM / 2.0,
                y_um: SIDE_UM / 2.0,
                force_n: f / 4.0,
                radius_um: 0.0,
            }
        };
        let (s, stats) = vk.solve(&[load]).expect("converges");
        let w = s.deflection_m(SIDE_UM / 2.0, SIDE_UM / 2.0) / t;
        let rel = (w - case.w_over_t) / case.w_over_t;
        worst.push((case.pressure, case.wlin_over_t, rel));
        assert!(stats.iterations <= 40, "{stats:?}");
        // The peer's change from its previous mesh (r = 3: up to 3.7e-3 for the point load,
        // whose error is ~1/3 of that at order 2; 6e-5 for pressure).
        assert!(case.change < 1e-2, "peer not converged: {}", case.change);
    }
    // Measured: pressure within 7.3e-4 (growing with the load: the bending boundary layer of
    // width sqrt(D / N) at the edges), point within 4.2e-4.
    for &(pressure, wlin, rel) in &worst {
        let bound = 1.5e-3;
        assert!(
            rel.abs() < bound,
            "{} at w_lin/t = {wlin}: tactfab vs scikit-fem {rel:.2e} ({worst:?})",
            if pressure { "pressure" } else { "point" }
        );
    }
    // Membrane stiffening is the answer at the top load, not a correction.
    let top = peers
        .iter()
        .find(|c| c.pressure && c.wlin_over_t == 4.0)
        .expect("top");
    assert!(top.w_over_t < 0.5 * top.wlin_over_t);
}
