//! The sensor plate's natural frequencies (`sensor::plate_modes`): without teeth against the
//! clamped-clamped beam with D22 and the plate's areal mass, with teeth between Rayleigh bounds,
//! and `tactfab fe` reporting them against the 5 Hz test (text and JSON).

use std::f64::consts::PI;

use tactfab::fe::modal::clamped_clamped_beta_l;
use tactfab::sensor::plate_modes;

use super::harness::{tactfab, REFERENCE};
use super::sensor::geometry;

#[test]
fn plate_without_teeth_is_the_clamped_clamped_strip_and_teeth_stay_within_bounds() {
    let g = geometry(&["geometry.teeth.pattern=none"]);
    let m = plate_modes(&g, 3, 4).unwrap();
    let t = g.plate_thickness_um * 1e-6;
    let d22 = g.material.q22_pa * t.powi(3) / 12.0;
    let areal = g.si_density_kg_per_m3 * t + g.film_density_kg_per_m3 * g.film_thickness_um * 1e-6;
    let span = (g.plate_y1_um - g.plate_y0_um) * 1e-6;
    let bl = clamped_clamped_beta_l();
    let beam_hz = bl * bl / (span * span) * (d22 / areal).sqrt() / (2.0 * PI);
    let rel = m.modes[0].freq_hz / beam_hz - 1.0;
    // Three spans long with free ends; Q12 / Q22 = 0.06 couples little: within 0.1 %.
    assert!(
        rel.abs() < 1e-3,
        "{} vs {beam_hz} Hz ({rel:.2e})",
        m.modes[0].freq_hz
    );
    // Converged on the sensor's meshes, and reported so.
    let e = m.modes[0].error_rel.unwrap();
    assert!(e < 1e-4, "estimated error {e}");
    assert!(m.modes.windows(2).all(|w| w[0].freq_hz <= w[1].freq_hz));
    // Teeth add stiffness (raising every Rayleigh quotient) and mass (lowering it): with them f1
    // lies between the plate with the teeth's stiffness but only its own mass made as heavy as
    // a tooth everywhere, and the plate as stiff as a tooth everywhere with its own mass
    // (measured: 7329 Hz with the checkered teeth against 7353 Hz without; the isolated
    // islands add about as much mass as stiffness to the mode).
    let teeth = geometry(&[]);
    let with = plate_modes(&teeth, 1, 3).unwrap();
    let tooth_t = teeth.teeth[0].thickness_um * 1e-6;
    let film = g.film_density_kg_per_m3 * g.film_thickness_um * 1e-6;
    let heaviest = g.si_density_kg_per_m3 * tooth_t + film;
    let f_plain = m.modes[0].freq_hz;
    let lower = f_plain * (areal / heaviest).sqrt();
    let upper = f_plain * (tooth_t / t).powf(1.5);
    let f_teeth = with.modes[0].freq_hz;
    assert!(
        lower < f_teeth && f_teeth < upper && (f_teeth / f_plain - 1.0).abs() > 1e-4,
        "{lower} < {f_teeth} < {upper} (plain {f_plain})"
    );
    // The quasi-static check: f1 / 5 Hz, and the single-mode amplification at 5 Hz.
    let f1 = with.modes[0].freq_hz;
    assert!((with.above_test - f1 / 5.0).abs() < 1e-9 * f1);
    let r = 5.0 / f1;
    assert!((with.quasi_static_error_at_test - r * r / (1.0 - r * r)).abs() < 1e-15);
    // A denser plate rings lower: f ~ 1 / sqrt(rho) where the film's share is fixed.
    let heavy = geometry(&[
        "geometry.teeth.pattern=none",
        "materials.silicon.density_g_per_cm3=9.316",
        "materials.pvdf.density_g_per_cm3=7.04",
    ]);
    let h = plate_modes(&heavy, 1, 2).unwrap();
    let light = plate_modes(&g, 1, 2).unwrap();
    assert!((light.modes[0].freq_hz / h.modes[0].freq_hz - 2.0).abs() < 1e-9);
}

#[test]
fn fe_reports_the_frequencies_and_the_supports_in_text_and_json() {
    let args = ["fe", REFERENCE, "--model", "plate", "--max-levels", "1"];
    let r = tactfab(&args);
    r.expect_code(0);
    assert!(
        r.stdout.contains("natural frequencies:") && r.stdout.contains("mode 1: "),
        "{}",
        r.stdout
    );
    assert!(r.stdout.contains("x the 5 Hz test force"), "{}", r.stdout);
    assert!(
        r.stdout
            .contains("held at the supports as `support_model: clamped` says"),
        "{}",
        r.stdout
    );
    assert!(
        r.stdout
            .contains("supports: `support_model: clamped`: w and the slope held"),
        "{}",
        r.stdout
    );
    let mut json = args.to_vec();
    json.push("--json");
    let j = tactfab(&json);
    j.expect_code(0);
    let v: serde_json::Value = serde_json::from_str(&j.stdout).unwrap();
    let modes = v["modes"]["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 4);
    let f1 = modes[0]["freq_hz"].as_f64().unwrap();
    assert!(f1 > 1e3, "{f1}");
    assert!((v["modes"]["above_test"].as_f64().unwrap() - f1 / 5.0).abs() < 1e-9 * f1);
    assert_eq!(v["supports"]["support_model"], "clamped");
    // The footing's springs, through the binary: finite, positive, in the YAML's spelling.
    let mut footing = json.clone();
    footing.extend(["--set", "materials.base.support_model=elastic_footing"]);
    let f = tactfab(&footing);
    f.expect_code(0);
    let v: serde_json::Value = serde_json::from_str(&f.stdout).unwrap();
    assert_eq!(v["supports"]["support_model"], "elastic_footing");
    // The modes stand on the same springs: softer than the clamp, so lower (Rayleigh), and
    // they say so.
    assert_eq!(v["modes"]["support_model"], "elastic_footing");
    let f1_footing = v["modes"]["modes"][0]["freq_hz"].as_f64().unwrap();
    assert!(f1_footing < 0.995 * f1, "{f1_footing} against {f1} clamped");
    for k in ["k_w_w_pa", "k_theta_theta_n", "rotation_n", "in_plane_pa"] {
        let x = v["supports"]["bare"][k].as_f64().unwrap();
        assert!(x.is_finite() && x > 0.0, "{k} {x}");
    }
}
