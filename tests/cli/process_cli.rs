//! `tactfab check` and `tactfab etch` on the bundled process file, through the real binary.

use serde_json::Value;

use super::harness::{tactfab, REFERENCE};

fn etch_json(extra: &[&str]) -> (i32, Value) {
    let mut args = vec!["etch", REFERENCE, "--json"];
    args.extend_from_slice(extra);
    let run = tactfab(&args);
    assert!(
        run.code == 0 || run.code == 1,
        "exit {}: {}",
        run.code,
        run.stderr
    );
    (
        run.code,
        serde_json::from_str(&run.stdout).expect("etch --json prints JSON"),
    )
}

fn codes(v: &Value) -> Vec<String> {
    v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["code"].as_str().unwrap().to_string())
        .collect()
}

#[track_caller]
fn close(got: &Value, want: f64, tol: f64) {
    let g = got
        .as_f64()
        .unwrap_or_else(|| panic!("not a number: {got}"));
    assert!((g - want).abs() <= tol, "got {g}, want {want} +/- {tol}");
}

#[test]
fn check_passes_with_the_papers_discrepancies_as_warnings() {
    let run = tactfab(&["check", REFERENCE]);
    run.expect_code(0);
    for code in [
        "OXIDE_CLAIM",
        "ETCH_TIME_DEPTH_MISMATCH",
        "PLATE_THICKNESS_MISMATCH",
        "COMP_RATIO_FROM_KOH",
        "PLATE_TOLERANCE",
        "PIEZO_CONSTANTS_INCONSISTENT",
    ] {
        assert!(
            run.stdout.contains(&format!("warning[{code}]")),
            "missing {code}:\n{}",
            run.stdout
        );
    }
    assert!(run.stdout.contains("defaults used"), "{}", run.stdout);
    assert!(
        run.stdout.contains("[lit] Tabata 1992"),
        "provenance of defaults is stated"
    );
}

#[test]
fn json_contract_and_hand_computed_values() {
    let (code, v) = etch_json(&[]);
    assert_eq!(code, 0);
    // Top level.
    close(&v["plate_thickness_um"], 92.0, 1e-9); // 8.5 h x 24 um/h = 204 um per face
    close(&v["oxide_thickness_um"], 0.942, 0.005); // Deal-Grove wet, 1100 C, 2 h, (100)
    assert!(v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .all(|w| w["code"].is_string() && w["message"].is_string()));
    // The TMAH step.
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 1);
    let s = &steps[0];
    assert_eq!(s["name"], "tmah-etch");
    assert_eq!(s["etchant"], "TMAH");
    assert_eq!(s["side"], "both");
    close(&s["depth_um"], 200.0, 0.0);
    close(&s["rate_um_per_h"], 24.0, 0.0);
    close(&s["time_h"], 8.5, 0.0);
    close(&s["time_for_depth_h"], 8.3333, 1e-4); // 200 / 24
    close(&s["sidewall_run_out_um"], 204.0 / 2f64.sqrt(), 1e-9);
    close(&s["undercut_um"], 0.8 * 8.5 / (2f64 / 3.0).sqrt(), 1e-6); // R111 = 24/30, sin 54.74 = sqrt(2/3)
    close(&s["min_street_um"], 282.843, 1e-3);
    let c = &s["compensation"];
    assert_eq!(c["kind"], "corner_attached");
    close(&c["side_um"], 367.647, 1e-3); // 200 / 0.544
    close(&c["min_gap"]["x_um"], 735.294, 1e-3);
    close(&c["min_gap"]["y_um"], 735.294, 1e-3);
}

#[test]
fn etch_json_is_deterministic() {
    let a = tactfab(&["etch", REFERENCE, "--json"]);
    let b = tactfab(&["etch", REFERENCE, "--json"]);
    assert_eq!(a.stdout, b.stdout);
}

#[test]
fn computed_time_reaches_the_target_plate() {
    // Dropping the recipe time makes tactfab use the computed 8.333 h: a 100 um plate.
    let (_, v) = etch_json(&["--set", "steps.tmah-etch.time_h=null"]);
    close(&v["plate_thickness_um"], 100.0, 1e-9);
    let c = codes(&v);
    assert!(
        !c.contains(&"ETCH_TIME_DEPTH_MISMATCH".into())
            && !c.contains(&"PLATE_THICKNESS_MISMATCH".into()),
        "{c:?}"
    );
}

#[test]
fn tight_pitch_makes_compensators_collide() {
    let (code, v) = etch_json(&[
        "--set",
        "geometry.teeth.pitch_x_um=2600",
        "--set",
        "geometry.teeth.pitch_y_um=2600",
    ]);
    assert_eq!(code, 1);
    assert!(
        codes(&v).contains(&"COMPENSATORS_COLLIDE".into()),
        "{:?}",
        codes(&v)
    );
    // Checkered teeth only meet at diagonal corners: one roomy axis is enough.
    let (_, v) = etch_json(&["--set", "geometry.teeth.pitch_x_um=2600"]);
    assert!(!codes(&v).contains(&"COMPENSATORS_COLLIDE".into()));
    // A matrix faces corners along each axis: one tight axis collides.
    let (code, v) = etch_json(&[
        "--set",
        "geometry.teeth.pitch_x_um=2600",
        "--set",
        "geometry.teeth.pattern=matrix",
    ]);
    assert_eq!(code, 1);
    assert!(codes(&v).contains(&"COMPENSATORS_COLLIDE".into()));
}

#[test]
fn resist_is_not_a_tmah_mask() {
    let run = tactfab(&["check", REFERENCE, "--set", "steps.tmah-etch.mask=resist"]);
    run.expect_code(1);
    assert!(
        run.stdout.contains("error[RESIST_NOT_A_MASK]"),
        "{}",
        run.stdout
    );
}

#[test]
fn depths_through_the_wafer_fail() {
    let (code, v) = etch_json(&[
        "--set",
        "steps.tmah-etch.depth_um=250",
        "--set",
        "steps.tmah-etch.time_h=null",
    ]);
    assert_eq!(code, 1);
    assert!(
        codes(&v).contains(&"DEPTH_EXCEEDS_WAFER".into()),
        "{:?}",
        codes(&v)
    );
}

#[test]
fn thin_oxide_is_consumed() {
    let (code, v) = etch_json(&[
        "--set",
        "steps.wet-oxidation.time_h=0.2",
        "--set",
        "steps.wet-oxidation.expected_thickness_um=null",
    ]);
    assert_eq!(code, 1);
    assert!(
        codes(&v).contains(&"MASK_CONSUMED".into()),
        "{:?}",
        codes(&v)
    );
}

#[test]
fn koh_uses_the_seidel_model_unless_measured() {
    let (_, v) = etch_json(&[
        "--set",
        "steps.tmah-etch.etchant=koh",
        "--set",
        "steps.tmah-etch.concentration_wt_pct=30",
        "--set",
        "steps.tmah-etch.measured_rate_um_per_h=null",
        "--set",
        "steps.tmah-etch.time_h=null",
    ]);
    let s = &v["steps"][0];
    close(&s["rate_um_per_h"], 81.0, 1.5); // reference: ~81 um/h at 30 %, 80 C
    assert!(s["rate_source"].as_str().unwrap().contains("Seidel"));
    // KOH erodes oxide ~7x faster than TMAH: 0.94 um lasts ~2.2 h, the etch takes ~2.5 h.
    assert!(
        codes(&v).contains(&"MASK_CONSUMED".into()),
        "{:?}",
        codes(&v)
    );
    assert!(!codes(&v).contains(&"COMP_RATIO_FROM_KOH".into()));
}

#[test]
fn low_concentration_tmah_warns_of_hillocks_and_extrapolation() {
    let (_, v) = etch_json(&[
        "--set",
        "steps.tmah-etch.concentration_wt_pct=10",
        "--set",
        "steps.tmah-etch.measured_rate_um_per_h=null",
    ]);
    let c = codes(&v);
    assert!(
        c.contains(&"HILLOCK_RISK".into()) && c.contains(&"RATE_EXTRAPOLATED".into()),
        "{c:?}"
    );
}

#[test]
fn text_output_names_the_numbers() {
    let run = tactfab(&["etch", REFERENCE]);
    run.expect_code(0);
    for s in [
        "8.333 h",
        "204.0 um per face",
        "367.6 um",
        "0.942 um",
        "1.60 um",
        "tooth base 2288.5 um",
    ] {
        assert!(run.stdout.contains(s), "missing `{s}` in\n{}", run.stdout);
    }
}

/// The paper's order takes the hard-baked resist into the hot TMAH bath (stripped after the
/// etch): a warning naming the coats and the traveler step; stripping it first silences it.
#[test]
fn resist_going_into_tmah_is_a_warning() {
    let run = tactfab(&["check", REFERENCE]);
    run.expect_code(0);
    let line = run
        .stdout
        .lines()
        .find(|l| l.contains("warning[RESIST_IN_BATH]"))
        .unwrap_or_else(|| panic!("no RESIST_IN_BATH:\n{}", run.stdout));
    assert!(
        line.contains("`tmah-etch` (traveler step 11)")
            && line.contains("`resist-back`, `resist-front`"),
        "{line}"
    );
    let text = std::fs::read_to_string(super::harness::root().join(REFERENCE)).unwrap();
    let mut p = tactfab::process::load_str(&text, "mis-grasper.yaml", &[])
        .expect("valid")
        .process;
    let at =
        |p: &tactfab::process::Process, n: &str| p.steps.iter().position(|s| s.name == n).expect(n);
    let strip = p.steps.remove(at(&p, "strip-resist"));
    let etch = at(&p, "tmah-etch");
    p.steps.insert(etch, strip);
    let plan = tactfab::etch::plan(&p);
    assert!(
        !plan
            .warnings
            .iter()
            .any(|w| w.code.as_str() == "RESIST_IN_BATH"),
        "{:?}",
        plan.warnings
    );
}

#[test]
fn analyses_say_when_the_process_fails_its_checks() {
    // The recipe leaves a 92 um plate whatever geometry.plate_thickness_um says; `fe` answers
    // for that plate and must say the process fails its checks (on stderr: stdout stays JSON).
    let fe = |extra: &[&str]| {
        let mut args = vec![
            "fe",
            REFERENCE,
            "--scene",
            "pressure-2n",
            "--model",
            "plate",
            "--max-levels",
            "1",
            "--json",
        ];
        args.extend_from_slice(extra);
        tactfab(&args)
    };
    let plain = fe(&[]);
    plain.expect_code(0);
    assert!(!plain.stderr.contains("fails"), "{}", plain.stderr);
    let run = fe(&["--set", "geometry.plate_thickness_um=5"]);
    run.expect_code(0);
    assert!(
        run.stderr.contains("warning: the process fails 2 checks")
            && run.stderr.contains("error[PLATE_THICKNESS_MISMATCH]")
            && run.stderr.contains("92.0 um plate"),
        "{}",
        run.stderr
    );
    // The answer is the recipe's plate: the same bytes as without the override.
    assert_eq!(run.stdout, plain.stdout);
    let _: Value = serde_json::from_str(&run.stdout).expect("JSON");
}
