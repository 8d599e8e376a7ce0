//! `tactfab tissue --slab 3d`: the 3-D slab's face field, its files, through the sensor, and
//! bad sizes named by their flags.

use super::harness::tactfab;

/// Coarse for speed: 1 mm bricks near the lump, 3 mm far; otherwise as the 2-D slab's tests.
fn coarse(out: &std::path::Path, extra: &[&str]) -> super::harness::Run {
    let mut args = vec!["--slab", "3d", "--near-mm", "1", "--far-mm", "3"];
    args.extend_from_slice(extra);
    super::softsweep::coarse_tissue(out, &args)
}

#[test]
fn the_3d_slab_writes_its_face_field_and_loads_the_sensor_deterministically() {
    let t = tempfile::tempdir().unwrap();
    let (a, b) = (t.path().join("a"), t.path().join("b"));
    // Off the jaw's middle (a half block), through the sensor.
    let run = coarse(&a, &["--y-mm", "4.5", "--through-sensor"]);
    run.expect_code(0);
    assert!(
        run.stdout.contains("3-D slab 30.00 x 15.00 x 10.00 mm"),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("a half by symmetry"), "{}", run.stdout);
    assert!(
        run.stdout.contains("sphere in the 3-D slab"),
        "{}",
        run.stdout
    );
    let csv = std::fs::read_to_string(a.join("tissue-3d.csv")).unwrap();
    assert!(csv.starts_with("x_mm,y_mm,p0_kpa,p_kpa,p_over_p0\n"));
    // The peak sits over the lump (y 4.5 mm), above 1.
    let best = csv
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[4], v[0], v[1])
        })
        .fold((0.0, 0.0, 0.0), |m, v| if v.0 > m.0 { v } else { m });
    assert!(best.0 > 1.3 && (best.1 - 15.0).abs() < 1.0 && (best.2 - 4.5).abs() < 1.5);
    let svg = std::fs::read_to_string(a.join("tissue-3d.svg")).unwrap();
    let outside = tactfab::plot::text_outside_canvas(&svg);
    assert!(outside.is_empty(), "{outside:?}");
    // The same bytes on a second run.
    coarse(&b, &["--y-mm", "4.5", "--through-sensor"]).expect_code(0);
    for f in [
        "tissue-3d.csv",
        "tissue-3d.svg",
        "face-pressure.csv",
        "through-sensor.csv",
    ] {
        assert_eq!(
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
            "{f}"
        );
    }
}

#[test]
fn bad_3d_sizes_name_their_flags() {
    let t = tempfile::tempdir().unwrap();
    for (flags, named) in [
        // The sphere through the jaw's edge.
        (&["--y-mm", "1"][..], "--radius-mm"),
        (&["--jaw-width-mm", "3"][..], "--radius-mm"),
        // Too many bricks, and near coarser than far.
        (&["--near-mm", "0.05", "--far-mm", "0.05"][..], "--near-mm"),
        (&["--near-mm", "3", "--far-mm", "1"][..], "--near-mm"),
        (&["--near-mm", "0"][..], "--near-mm"),
    ] {
        let out = t.path().join("bad");
        let mut args = vec![
            "tissue",
            "process/mis-grasper.yaml",
            "-o",
            out.to_str().unwrap(),
            "--slab",
            "3d",
        ];
        args.extend_from_slice(flags);
        let r = tactfab(&args);
        assert_eq!(r.code, 2, "{flags:?}: {}", r.stderr);
        assert!(r.stderr.contains(named), "{flags:?}: {}", r.stderr);
        assert!(!out.exists());
    }
}
