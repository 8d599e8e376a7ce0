//! `tactfab etch --simulate`: the simulated tooth in the JSON, the text and the SVG, its
//! finding against the process file's tolerance, and bad input (through the real binary, on a
//! coarse grid to stay quick).

use serde_json::Value;

use super::harness::{tactfab, REFERENCE};

fn simulate(extra: &[&str]) -> (i32, Value) {
    simulate_on("20", extra)
}

/// `etch --json --simulate` on the bundled file with a grid step.
pub(super) fn simulate_on(grid_um: &str, extra: &[&str]) -> (i32, Value) {
    let mut args = vec![
        "etch",
        REFERENCE,
        "--json",
        "--simulate",
        "--grid-um",
        grid_um,
    ];
    args.extend_from_slice(extra);
    let run = tactfab(&args);
    assert!(run.code == 0, "exit {}: {}", run.code, run.stderr);
    (run.code, serde_json::from_str(&run.stdout).expect("JSON"))
}

fn codes(v: &Value) -> Vec<&str> {
    v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["code"].as_str().unwrap())
        .collect()
}

#[test]
fn simulation_reports_the_corner_and_writes_the_plan_view() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("tooth.svg");
    let (_, v) = simulate(&["--svg", svg.to_str().unwrap()]);
    let s = &v["simulation"];
    // The bundled TMAH recipe with the KOH rule a = h / 0.544: the compensator is gone before
    // the end and the corner rounds (sign: < 0 inwards).
    let dev = s["corner_deviation_um"].as_f64().unwrap();
    assert!(dev < -25.0, "{dev}");
    assert_eq!(s["corner_shape"], "rounded");
    let t = s["compensator_consumed_h"].as_f64().unwrap();
    assert!(t > 1.0 && t < 8.5, "{t}");
    assert!((s["floor_depth_um"].as_f64().unwrap() - 204.0).abs() < 1e-6);
    assert!((s["time_h"].as_f64().unwrap() - 8.5).abs() < 1e-12);
    let und = s["edge_undercut_um"].as_f64().unwrap();
    assert!(und > 0.0 && und < 20.0, "{und}");
    assert!(s["facets"]
        .as_array()
        .unwrap()
        .iter()
        .any(|f| f["family"] == "111"));
    assert_eq!(s["history"].as_array().unwrap().len(), 41);
    assert!(codes(&v).contains(&"ETCHED_CORNER_DEVIATION"));
    let text = std::fs::read_to_string(&svg).unwrap();
    // The plot, then the stamp that lets the next run replace it (`export::file`).
    assert!(text.starts_with("<svg"), "{text}");
    let (svg, stamp) = text.rsplit_once("</svg>").unwrap();
    assert!(
        stamp.starts_with("\n<!-- tactfab sha256 of the bytes above: ")
            && stamp.ends_with(" -->\n"),
        "{stamp}"
    );
    assert!(svg.contains("<path"));
    assert!(text.matches("<path").count() > 10, "contours drawn");
}

/// The back mask's support corner beside the tooth: the floor edge and width against the
/// etch plan's, the wall against h / tan 54.74 deg, both convex corners receded, and its plan
/// view written beside the tooth's, both rendering with their text on the canvas; JSON and
/// both SVGs byte-identical run to run.
#[test]
fn back_mask_is_simulated_and_drawn_beside_the_tooth() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("tooth.svg");
    let args = ["--svg", svg.to_str().unwrap()];
    let (_, v) = simulate(&args);
    let b = &v["simulation"]["back"];
    let num = |k: &str| b[k].as_f64().unwrap_or_else(|| panic!("{k}: {b}"));
    assert!((num("floor_depth_um") - 204.0).abs() < 1e-6);
    let plan_floor = v["channel_floor_y_um"][0].as_f64().unwrap();
    assert!((num("plan_floor_edge_y_um") - plan_floor).abs() < 1e-9);
    // 20 um grid (the wall 7 cells wide): the floor edge within two cells of the plan, the
    // run-out within a cell (measured 14 um here, 2.3 um on 10 um).
    assert!((num("floor_edge_y_um") - plan_floor).abs() < 40.0, "{b}");
    assert!(
        (num("run_out_um") - num("closed_form_run_out_um")).abs() < 20.0,
        "{b}"
    );
    assert!(num("floor_width_um") > 9600.0 && num("floor_width_um") < 9800.0);
    let corners = b["corners"].as_array().unwrap();
    assert_eq!(corners.len(), 2);
    for c in corners {
        assert_eq!(c["kind"], "convex");
        let d = c["deviation_um"].as_f64().unwrap();
        assert!(d < -300.0 && d > -600.0, "{c}");
        assert!(c["error"]["extrapolated_um"].as_f64().is_some(), "{c}");
    }
    assert!(b["floor_edge_error"]["error_um"].as_f64().is_some());
    let back_svg = dir.path().join("tooth-back.svg");
    let first = std::fs::read(&back_svg).expect("the back plan view beside the tooth's");
    let text = String::from_utf8(first.clone()).unwrap();
    assert!(
        text.starts_with("<svg") && text.contains("Back mask") && text.matches("<path").count() > 5
    );
    // Both plan views keep their text on the canvas (estimated, and laid out in Chromium).
    super::harness::assert_svgs_fit(dir.path());
    let front = std::fs::read(&svg).unwrap();
    let (_, again) = simulate(&args);
    assert_eq!(v, again);
    assert_eq!(std::fs::read(&back_svg).unwrap(), first);
    assert_eq!(std::fs::read(&svg).unwrap(), front);
}

#[test]
fn tolerance_and_rates_come_from_the_process_file() {
    let (_, v) = simulate(&["--set", "etchants.etched_corner_tolerance_um=1000"]);
    assert_eq!(v["simulation"]["corner_shape"], "square");
    assert!(!codes(&v).contains(&"ETCHED_CORNER_DEVIATION"));
    let (_, w) = simulate(&["--set", "etchants.tmah_r411_over_r100=1.5"]);
    let r = &w["simulation"]["rates"];
    assert!((r["r411_um_per_h"].as_f64().unwrap() - 36.0).abs() < 1e-9);
    assert!((r["r311_um_per_h"].as_f64().unwrap() - 1.3 * 24.0).abs() < 1e-9);
    // The defaults used are listed with their source.
    let used = v["defaults_used"].as_array().unwrap();
    assert!(used
        .iter()
        .any(|d| d["path"] == "etchants.tmah_r311_over_r100"
            && d["source"].as_str().unwrap().starts_with("[est]")));
}

#[test]
fn text_report_and_sensitivity() {
    let run = tactfab(&[
        "etch",
        REFERENCE,
        "--simulate",
        "--grid-um",
        "30",
        "--sensitivity",
    ]);
    run.expect_code(0);
    assert!(
        run.stdout.contains("simulated tooth (4, 2) cell"),
        "{}",
        run.stdout
    );
    for line in [
        "simulated back (U-channel) at support 1's corner",
        "wall run-out",
        "convex corner at (0.0, 0.0) um",
        "convex corner at (0.0, 2500.0) um",
    ] {
        assert!(run.stdout.contains(line), "{line}: {}", run.stdout);
    }
    for case in ["nominal", "r311_low", "r311_high", "r411_low", "r411_high"] {
        assert!(
            run.stdout.contains(&format!("sensitivity {case}: corner")),
            "{}",
            run.stdout
        );
    }
}

#[test]
fn bad_simulation_input_is_exit_2() {
    let run = tactfab(&["etch", REFERENCE, "--simulate", "--grid-um", "0.5"]);
    run.expect_code(2);
    assert!(run.stderr.contains("--grid-um"), "{}", run.stderr);
    let run = tactfab(&["etch", REFERENCE, "--grid-um", "5"]);
    run.expect_code(2);
    let run = tactfab(&[
        "etch",
        REFERENCE,
        "--simulate",
        "--set",
        "etchants.tmah_r311_over_r100=-1",
    ]);
    run.expect_code(2);
    assert!(
        run.stderr.contains("etchants.tmah_r311_over_r100"),
        "{}",
        run.stderr
    );
    let run = tactfab(&[
        "etch",
        REFERENCE,
        "--simulate",
        "--set",
        "geometry.teeth.pattern=none",
    ]);
    run.expect_code(2);
    assert!(run.stderr.contains("no teeth"), "{}", run.stderr);
    // A grid finer than the cells can hold is refused before anything is allocated.
    let run = tactfab(&["etch", REFERENCE, "--simulate", "--grid-um", "1"]);
    run.expect_code(2);
    assert!(run.stderr.contains("grid"), "{}", run.stderr);
}

#[test]
fn corner_error_is_richardson_from_the_grid_and_its_double() {
    let (_, v) = simulate(&[]);
    let s = &v["simulation"];
    let e = &s["corner_error"];
    let fine = s["corner_deviation_um"].as_f64().unwrap();
    let coarse = e["coarse_corner_deviation_um"].as_f64().unwrap();
    assert_eq!(e["coarse_grid_um"].as_f64().unwrap(), 40.0);
    assert_eq!(e["order"].as_f64().unwrap(), 1.0);
    // First order, ratio 2: extrapolated = 2 fine - coarse, error = fine - coarse.
    let ext = e["extrapolated_corner_deviation_um"].as_f64().unwrap();
    assert!((ext - (2.0 * fine - coarse)).abs() < 1e-9, "{ext}");
    assert!((e["error_um"].as_f64().unwrap() - (fine - coarse)).abs() < 1e-9);
    assert_eq!(e["decision"], "beyond");
    assert_eq!(s["corner_bridged"], false);
    // The coarse corner is what a run on that grid reports by itself.
    let (_, w) = simulate_on("40", &[]);
    let alone = w["simulation"]["corner_deviation_um"].as_f64().unwrap();
    assert!((alone - coarse).abs() < 1e-9, "{alone} vs {coarse}");
    let msg = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["code"] == "ETCHED_CORNER_DEVIATION")
        .unwrap()["message"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        msg.contains("extrapolated") && msg.contains("discretisation error"),
        "{msg}"
    );
    // A tolerance inside the band extrapolated +/- error: the finding says a finer grid decides.
    let tol = ext.abs() - 0.5 * (fine - coarse).abs();
    let (_, u) = simulate(&[
        "--set",
        &format!("etchants.etched_corner_tolerance_um={tol}"),
    ]);
    assert_eq!(u["simulation"]["corner_error"]["decision"], "within_error");
    let warned = u["warnings"].as_array().unwrap().iter().any(|w| {
        w["code"] == "ETCHED_CORNER_DEVIATION"
            && w["message"]
                .as_str()
                .unwrap()
                .contains("a finer --grid-um decides")
    });
    assert!(warned, "{}", u["warnings"]);
}

#[test]
fn size_compensation_reports_each_geometry_against_the_rule() {
    let (_, v) = simulate_on("40", &["--size-compensation"]);
    let z = &v["sizing"];
    assert_eq!(z["grid_um"].as_f64().unwrap(), 40.0);
    let coarse = z["coarse_grid_um"].as_f64().unwrap();
    assert!(coarse > 75.0 && coarse < 85.0, "{coarse}");
    assert!((z["rule_ratio"].as_f64().unwrap() - 0.544).abs() < 1e-12);
    let gs = z["geometries"].as_array().unwrap();
    let names: Vec<&str> = gs.iter().map(|g| g["geometry"].as_str().unwrap()).collect();
    assert_eq!(names, ["corner_attached", "centred", "bar_110"]);
    // The bar row names its width (the default, 6 side undercuts: 50.0 um); the squares none.
    let b = gs[2]["bar_width_um"].as_f64().unwrap();
    assert!((b - 49.97).abs() < 0.01, "{b}");
    assert!(gs[0].get("bar_width_um").is_none());
    for g in gs {
        let a = g["sized_a_um"].as_f64().unwrap();
        assert!(a >= 0.0 && a <= g["largest_a_um"].as_f64().unwrap() + 1e-9);
        assert!((g["rule_a_um"].as_f64().unwrap() - 200.0 / 0.544).abs() < 1e-9);
        assert!(g["rule"].is_string() && g["probes"].as_array().unwrap().len() >= 2);
    }
    // The text names both geometries and the rule.
    let run = tactfab(&[
        "etch",
        REFERENCE,
        "--simulate",
        "--grid-um",
        "40",
        "--size-compensation",
    ]);
    run.expect_code(0);
    for s in [
        "compensation sizing by simulation",
        "corner_attached:",
        "centred:",
        "bar_110 (a is the bar's length; 50.0 um wide):",
        "rule a = h/0.544",
    ] {
        assert!(run.stdout.contains(s), "{s}: {}", run.stdout);
    }
    // Deterministic JSON.
    let (_, w) = simulate_on("40", &["--size-compensation"]);
    assert_eq!(v, w);
    // Without --simulate: a usage error.
    tactfab(&["etch", REFERENCE, "--size-compensation"]).expect_code(2);
}

#[test]
fn bars_are_simulated_and_bad_widths_refused() {
    let bar = "steps.tmah-etch.compensation.geometry=bar_110";
    let (_, v) = simulate(&["--set", bar]);
    assert_eq!(v["steps"][0]["compensation"]["kind"], "bar_110");
    let s = &v["simulation"];
    // The bar is used up along its centre line during the etch, and the corner then rounds.
    let t = s["compensator_consumed_h"].as_f64().unwrap();
    assert!(t > 0.0 && t < 8.5, "{t}");
    assert!(s["corner_deviation_um"].as_f64().unwrap() < 0.0);
    for (w, what) in [("0", "out of range"), ("2500", "out of range")] {
        let run = tactfab(&[
            "etch",
            REFERENCE,
            "--set",
            bar,
            "--set",
            &format!("steps.tmah-etch.compensation.bar_width_um={w}"),
        ]);
        run.expect_code(2);
        assert!(
            run.stderr.contains("compensation.bar_width_um") && run.stderr.contains(what),
            "{}",
            run.stderr
        );
    }
    let run = tactfab(&[
        "etch",
        REFERENCE,
        "--set",
        "steps.tmah-etch.compensation.bar_width_um=50",
    ]);
    run.expect_code(2);
    assert!(run.stderr.contains("draws squares"), "{}", run.stderr);
}
