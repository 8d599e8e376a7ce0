//! `tactfab sweep` (shards, merge, bad input) and `tactfab softness` through the binary, on reduced
//! grids so the suite stays fast; the library's unit tests check the numbers against references.

use super::harness::{tactfab, REFERENCE};

const GRID: [&str; 8] = [
    "--length-um",
    "20000,35000,3",
    "--width-um",
    "12000,18000,3",
    "--thickness-um",
    "90,110,2",
    "--tol",
    "0.2",
];

fn sweep(out: &str, extra: &[&str]) -> super::harness::Run {
    let mut args = vec!["sweep", REFERENCE, "-o", out, "--no-error-estimate"];
    args.extend_from_slice(&GRID);
    args.extend_from_slice(extra);
    tactfab(&args)
}

#[test]
fn sharded_sweep_merges_to_the_unsharded_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let (whole, parts) = (dir.path().join("whole"), dir.path().join("parts"));
    let r = sweep(whole.to_str().unwrap(), &[]);
    r.expect_code(0);
    assert!(
        r.stdout.contains("prototype 30 x 15 mm") && r.stdout.contains("in the family"),
        "{}",
        r.stdout
    );
    for i in 1..=3 {
        sweep(parts.to_str().unwrap(), &["--shard", &format!("{i}/3")]).expect_code(0);
    }
    assert!(!parts.join("sweep.csv").exists());
    // Merged with another --tol than the shards: refused, the family would be wrong.
    let r = tactfab(&["sweep", "--merge", parts.to_str().unwrap()]);
    r.expect_code(2);
    assert!(r.stderr.contains("--tol"), "{}", r.stderr);
    tactfab(&["sweep", "--merge", parts.to_str().unwrap(), "--tol", "0.2"]).expect_code(0);
    let a = std::fs::read(whole.join("sweep.csv")).unwrap();
    assert_eq!(a, std::fs::read(parts.join("sweep.csv")).unwrap());
    assert_eq!(String::from_utf8(a).unwrap().lines().count(), 19);
    super::harness::assert_svgs_fit(&parts);
    let svg = std::fs::read_to_string(parts.join("family.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("length (mm)"));
    // The prototype is marked, from the shards' record of it.
    assert!(svg.contains("prototype 30.0 x 15.0 mm, 100 um"), "{svg}");
    // The merged plot is the unsharded one, title and all.
    assert_eq!(
        svg,
        std::fs::read_to_string(whole.join("family.svg")).unwrap()
    );
    // Determinism: a second run gives the same bytes.
    sweep(whole.to_str().unwrap(), &[]).expect_code(0);
    assert_eq!(
        std::fs::read(whole.join("sweep.csv")).unwrap(),
        std::fs::read(parts.join("sweep.csv")).unwrap()
    );
}

#[test]
fn sweep_bad_input_is_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let r = sweep(out.to_str().unwrap(), &["--shard", "4/3"]);
    r.expect_code(2);
    assert!(r.stderr.contains("bad shard '4/3'"), "{}", r.stderr);
    let r = tactfab(&[
        "sweep",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--width-um",
        "5,1,3",
    ]);
    r.expect_code(2);
    assert!(r.stderr.contains("--width-um"), "{}", r.stderr);
    assert!(!out.join("sweep.csv").exists());
    let r = tactfab(&["sweep", "--merge", dir.path().to_str().unwrap()]);
    r.expect_code(2);
    assert!(r.stderr.contains("no sweep-i-of-n.csv"), "{}", r.stderr);
}

#[test]
fn softness_table_plot_and_inverse() {
    let dir = tempfile::tempdir().unwrap();
    let r = tactfab(&[
        "softness",
        REFERENCE,
        "--e-range-pa",
        "1e4,1e8,5",
        "--forces-n",
        "1,5",
        "-o",
        dir.path().to_str().unwrap(),
    ]);
    r.expect_code(0);
    for s in [
        "disagreement composite beam vs FE",
        "FE error at E_t",
        "inverse round trip (FE)",
        "M2",
    ] {
        assert!(r.stdout.contains(s), "{s}\n{}", r.stdout);
    }
    let csv = std::fs::read_to_string(dir.path().join("softness.csv")).unwrap();
    assert!(csv.starts_with("tissue_e_pa,force_n,fe_voltage_mv,composite_voltage_mv"));
    assert_eq!(csv.lines().count(), 11);
    super::harness::assert_svgs_fit(dir.path());
    assert!(std::fs::read_to_string(dir.path().join("softness.svg"))
        .unwrap()
        .contains("tissue modulus"));
    // A voltage no tissue can give is a clear error.
    let r = tactfab(&[
        "softness",
        REFERENCE,
        "--e-range-pa",
        "1e4,1e8,3",
        "--invert",
        "-5,3",
    ]);
    r.expect_code(2);
    assert!(
        r.stderr.contains("outside the model's range"),
        "{}",
        r.stderr
    );
}

#[test]
fn tissue_lump_and_void_through_the_binary() {
    // Paper 002 sec. V.B: > 40 % more pressure over a lump, ~65 % less over a void; with the
    // geometry tactfab chooses (30 x 10 mm slab, 2 mm disc 4 mm above the sensor) on a coarser
    // mesh for speed.
    let t = tempfile::tempdir().unwrap();
    let mut ratios = Vec::new();
    for feature in ["lump", "void"] {
        let out = t.path().join(feature);
        let run = tactfab(&[
            "tissue",
            "process/mis-grasper.yaml",
            "-o",
            out.to_str().unwrap(),
            "--feature",
            feature,
            "--across",
            "60",
            "--through",
            "20",
        ]);
        run.expect_code(0);
        let csv = std::fs::read_to_string(out.join("tissue.csv")).unwrap();
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("x_mm,P_pa,P0_pa,P_over_P0"));
        let r: Vec<f64> = lines
            .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
            .collect();
        assert_eq!(r.len(), 121);
        ratios.push(r[60]);
        let svg = std::fs::read_to_string(out.join("tissue.svg")).unwrap();
        assert!(tactfab::plot::text_outside_canvas(&svg).is_empty());
        // The same feature as a sphere: three fitted meshes and the Richardson estimate.
        let conv = std::fs::read_to_string(out.join("tissue-sphere-convergence.csv")).unwrap();
        assert!(
            conv.starts_with("mesh,elements,extreme_P_over_P0,order,error\nscale 2,"),
            "{conv}"
        );
        // (On this coarse 60 x 20 the sequence is pre-asymptotic: the estimate is left empty
        // and the text says why.)
        let rich = conv.lines().last().unwrap();
        assert!(rich.starts_with("richardson,,"), "{conv}");
        assert!(
            (rich.len() > 14 && run.stdout.contains("Richardson estimate"))
                || (rich == "richardson,,,," && run.stdout.contains("no Richardson estimate")),
            "{conv}\n{}",
            run.stdout
        );
        let sphere = std::fs::read_to_string(out.join("tissue-sphere.csv")).unwrap();
        assert!(sphere.starts_with("r_mm,P_pa,P0_pa,P_over_P0\n0.000000,"));
    }
    assert!(ratios[0] > 1.4 && ratios[1] < 0.4, "{ratios:?}");
    // A disc that does not fit in the slab is bad input.
    let bad = tactfab(&[
        "tissue",
        "process/mis-grasper.yaml",
        "-o",
        t.path().join("bad").to_str().unwrap(),
        "--radius-mm",
        "6",
    ]);
    assert_eq!(bad.code, 2, "{}", bad.stderr);
    assert!(
        bad.stderr.contains("--radius-mm") && bad.stderr.contains("inside the slab"),
        "{}",
        bad.stderr
    );
    assert!(!t.path().join("bad").exists());
}

/// `tactfab tissue` into `out`, coarse for speed (a 60 x 20 slab mesh, 1.5 mm cells, two plate
/// levels), with `extra` flags.
pub(super) fn coarse_tissue(out: &std::path::Path, extra: &[&str]) -> super::harness::Run {
    let mut args = vec![
        "tissue",
        "process/mis-grasper.yaml",
        "-o",
        out.to_str().unwrap(),
        "--across",
        "60",
        "--through",
        "20",
        "--cell-mm",
        "1.5",
        "--max-levels",
        "2",
    ];
    args.extend_from_slice(extra);
    tactfab(&args)
}

#[test]
fn tissue_through_the_sensor_locates_the_lump_and_maps_detectability() {
    // Coarse for speed: 1.5 mm cells, two plate levels, a 60 x 20 slab mesh, a 2 x 2 map.
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("sensor");
    let run = coarse_tissue(
        &out,
        &[
            "--x-mm",
            "13",
            "--y-mm",
            "8",
            "--locate",
            "--detectability",
            "--map-radii-mm",
            "1,2",
            "--map-heights-mm",
            "4,8.5",
            "--map-stiffness",
            "10",
        ],
    );
    run.expect_code(0);
    let csv = std::fs::read_to_string(out.join("through-sensor.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("electrode,V_background_mv,V_feature_mv,dV_mv")
    );
    assert_eq!(lines.count(), 9);
    // The full scenes on the default rung (auto), each with its error, beside the
    // superposition; the linear-only paths say so.
    let full = std::fs::read_to_string(out.join("through-sensor-full.csv")).unwrap();
    assert!(full.starts_with("electrode,V_background_mv,V_feature_mv,dV_mv,"));
    assert_eq!(full.lines().count(), 10);
    assert!(run
        .stdout
        .contains("full scenes (--model auto): the background on the "));
    assert!(
        run.stdout.contains("error: discretisation "),
        "{}",
        run.stdout
    );
    assert!(run
        .stdout
        .contains("detectability (linear plate, superposed)"));
    let face = std::fs::read_to_string(out.join("face-pressure.csv")).unwrap();
    assert!(face.starts_with("x_mm,y_mm,P0_pa,dP_pa\n"));
    // A lump, found within 2 mm of (13, 8) mm.
    let line = run
        .stdout
        .lines()
        .find(|l| l.contains("inverse on the linear plate"))
        .unwrap_or_else(|| panic!("{}", run.stdout));
    assert!(line.contains(": lump at x "), "{line}");
    let num = |key: &str| -> f64 {
        line.split(key)
            .nth(1)
            .unwrap()
            .split_whitespace()
            .next()
            .unwrap()
            .trim_end_matches([',', ' '])
            .parse()
            .unwrap()
    };
    let (x, y) = (num("lump at x "), num(", y "));
    assert!((x - 13.0).hypot(y - 8.0) < 2.0, "{line}");
    let map = std::fs::read_to_string(out.join("detectability.csv")).unwrap();
    let mut rows = map.lines();
    assert_eq!(
        rows.next(),
        Some("radius_mm,height_mm,stiffness_ratio,peak_P_over_P0,dV_norm_mv,snr,detectable")
    );
    // A 2 mm lump centred 8.5 mm up does not fit in the 10 mm slab: skipped.
    assert_eq!(rows.count(), 3, "{map}");
    for svg in ["through-sensor.svg", "detectability.svg"] {
        let s = std::fs::read_to_string(out.join(svg)).unwrap();
        assert!(tactfab::plot::text_outside_canvas(&s).is_empty(), "{svg}");
    }
}

#[test]
fn tissue_through_the_sensor_bad_flags_name_themselves() {
    let t = tempfile::tempdir().unwrap();
    for (flags, named) in [
        // The strip cannot carry a pressure field.
        (&["--through-sensor", "--model", "beam"][..], "--model"),
        (&["--through-sensor", "--cell-mm", "0.1"][..], "--cell-mm"),
        // A vessel is a tube: the default sphere is refused.
        (&["--vessel", "--feature", "void"][..], "--shape cylinder"),
        (&["--locate", "--noise-mv", "0"][..], "--noise-mv"),
        // A feature off the die would read nothing and pass as "no signal".
        (&["--through-sensor", "--y-mm", "100"][..], "--y-mm"),
        (
            &["--detectability", "--map-stiffness", "3,-1"][..],
            "--map-stiffness",
        ),
    ] {
        let out = t.path().join("bad");
        let mut args = vec![
            "tissue",
            "process/mis-grasper.yaml",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(flags);
        let r = tactfab(&args);
        assert_eq!(r.code, 2, "{flags:?}: {}", r.stderr);
        assert!(r.stderr.contains(named), "{flags:?}: {}", r.stderr);
        assert!(!out.exists());
    }
}

#[test]
fn tissue_vessel_pulses_through_the_amplifiers() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("vessel");
    let run = coarse_tissue(
        &out,
        &["--feature", "void", "--shape", "cylinder", "--vessel"],
    );
    run.expect_code(0);
    let csv = std::fs::read_to_string(out.join("vessel.csv")).unwrap();
    assert!(csv.starts_with("t_s,p_vessel_pa,V_S11_mv,"), "{csv}");
    assert_eq!(csv.lines().count(), 21);
    // 1.2 Hz: the instants span one period, the pressure between 80 and 120 mmHg.
    let p: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    let (lo, hi) = p
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(lo > 79.0 * 133.322 && hi < 121.0 * 133.322 && hi - lo > 35.0 * 133.322);
    let rec = std::fs::read_to_string(out.join("vessel-readout.csv")).unwrap();
    assert!(rec.starts_with("t_s,p_vessel_pa,V_S11_v,"));
    // 5 cycles of 1/1.2 s at 1 ms: t = 0 to 4.167 s, 4168 samples, and the header.
    assert_eq!(rec.lines().count(), 4169);
    assert!(run
        .stdout
        .contains("quasi-static: the plate's first natural frequency"));
    // The vessel's path: two patches scenes on the linear plate, no cell unit responses.
    assert!(
        run.stdout.contains("vessel on the linear plate: the grasp")
            && run.stdout.contains("as two patches scenes of one batch"),
        "{}",
        run.stdout
    );
    let svg = std::fs::read_to_string(out.join("vessel.svg")).unwrap();
    assert!(tactfab::plot::text_outside_canvas(&svg).is_empty());
}
