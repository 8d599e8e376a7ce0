//! <110> bars through the plan and the DRC: COMPENSATOR_OUTSIDE_DIE and COMPENSATORS_COLLIDE
//! fire at the bar lengths derived by hand, and not below them; bad bar widths are refused with
//! their field path.

use crate::finding::{Code, DrcCode};

/// Bundled process as bars of length `l_um` (ratio 200 / L) with `sets` on top: which of the
/// two codes the plan and the DRC of the drawn masks report.
fn codes(l_um: f64, sets: &[&str]) -> ([bool; 2], [bool; 2]) {
    let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    let mut all = vec![
        "steps.tmah-etch.compensation.geometry=bar_110".to_string(),
        format!("steps.tmah-etch.compensation.ratio={}", 200.0 / l_um),
        "layout.test_die.enabled=false".to_string(),
    ];
    all.extend(sets.iter().map(|s| s.to_string()));
    let p = crate::process::load_str(&text, "mis-grasper.yaml", &all)
        .unwrap()
        .process;
    let plan = crate::etch::plan(&p);
    let masks = crate::layout::build(&p, &plan).unwrap();
    let drc = crate::drc::check(&masks, &p, &plan);
    let has = |v: &[crate::finding::Finding], c: DrcCode| v.iter().any(|w| w.code == Code::Drc(c));
    let (out, col) = (DrcCode::CompensatorOutsideDie, DrcCode::CompensatorsCollide);
    (
        [has(&plan.warnings, out), has(&plan.warnings, col)],
        [has(&drc.violations, out), has(&drc.violations, col)],
    )
}

/// Bundled checkered teeth start 500 um inside the die's x ends: a bar may be 500 um long.
#[test]
fn outside_die_at_the_outer_teeth_inset() {
    assert_eq!(codes(495.0, &[]), ([false; 2], [false; 2]));
    assert_eq!(codes(505.0, &[]), ([true, false], [true, false]));
}

/// Checkered, 2600 um pitch: the facing bar is two cells away, 2 x 2600 - 2000 = 3200 um, so
/// the plan's bars touch beyond L = 1600 and the DRC's come closer than min_space (10 um)
/// beyond 1595. The teeth are moved 3500 um in from the die's x ends so the die does not
/// limit first. Matrix, 3000 um pitch: across the 1000 um street, 500 / 495; a 300 um y street
/// does not limit bars (it does squares: the test can fail).
#[test]
fn collide_where_facing_bars_meet() {
    let inner = [
        "geometry.teeth.pitch_x_um=2600",
        "geometry.teeth.count_x=8",
        "geometry.teeth.origin_x_um=3000",
    ];
    assert_eq!(codes(1590.0, &inner).1, [false, false]);
    assert_eq!(codes(1598.0, &inner), ([false, false], [false, true]));
    assert_eq!(codes(1605.0, &inner), ([false, true], [false, true]));
    let matrix = [
        "geometry.teeth.pattern=matrix",
        "geometry.teeth.pitch_y_um=2300",
        "geometry.teeth.count_x=8",
        "geometry.teeth.origin_x_um=3000",
    ];
    assert_eq!(codes(490.0, &matrix), ([false; 2], [false; 2]));
    assert_eq!(codes(497.0, &matrix), ([false, false], [false, true]));
    assert_eq!(codes(505.0, &matrix), ([false, true], [false, true]));
    // The same 300 um y street with corner-attached squares of 160 um: they collide along y.
    let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    let mut sets: Vec<String> = matrix.iter().map(|s| s.to_string()).collect();
    sets.push(format!(
        "steps.tmah-etch.compensation.ratio={}",
        200.0 / 160.0
    ));
    let p = crate::process::load_str(&text, "f.yaml", &sets)
        .unwrap()
        .process;
    let plan = crate::etch::plan(&p);
    assert!(plan
        .warnings
        .iter()
        .any(|w| w.code == Code::Drc(DrcCode::CompensatorsCollide)));
}

/// b <= 0, b wider than the tooth top, and b for a square geometry: each refused naming
/// `steps[..].compensation.bar_width_um`; a good b is drawn and reported by the plan.
#[test]
fn bad_bar_widths_are_refused_with_their_path() {
    let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    let bar = "steps.tmah-etch.compensation.geometry=bar_110".to_string();
    for (sets, what) in [
        (
            vec![
                bar.clone(),
                "steps.tmah-etch.compensation.bar_width_um=0".into(),
            ],
            "out of range",
        ),
        (
            vec![
                bar.clone(),
                "steps.tmah-etch.compensation.bar_width_um=-5".into(),
            ],
            "out of range",
        ),
        (
            vec![
                bar.clone(),
                "steps.tmah-etch.compensation.bar_width_um=2001".into(),
            ],
            "out of range",
        ),
        (
            vec!["steps.tmah-etch.compensation.bar_width_um=50".into()],
            "draws squares",
        ),
    ] {
        let err = crate::process::load_str(&text, "f.yaml", &sets)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("compensation.bar_width_um") && err.contains(what),
            "{sets:?}: {err}"
        );
    }
    let p = crate::process::load_str(
        &text,
        "f.yaml",
        &[bar, "steps.tmah-etch.compensation.bar_width_um=80".into()],
    )
    .unwrap()
    .process;
    let c = crate::etch::plan(&p).steps[0].compensation.unwrap();
    assert_eq!(c.bar_width_um, Some(80.0));
}

/// The default width is six side undercuts: 6 x 8.33 = 50.0 um for the bundled TMAH etch.
#[test]
fn default_width_is_six_undercuts() {
    let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    let sets = ["steps.tmah-etch.compensation.geometry=bar_110".to_string()];
    let p = crate::process::load_str(&text, "f.yaml", &sets)
        .unwrap()
        .process;
    let s = &crate::etch::plan(&p).steps[0];
    let b = s.compensation.unwrap().bar_width_um.unwrap();
    assert!(
        (b - 6.0 * s.undercut_um).abs() < 1e-9 && (b - 49.97).abs() < 0.01,
        "{b}"
    );
}

/// The test die ladders bar lengths, also on a die without teeth (the plan then draws no
/// compensation, so the bar width is the default worked out there too), and keeps no room
/// above its teeth (a bar reaches nothing along y).
#[test]
fn test_die_ladders_bars() {
    let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    let build = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let p = crate::process::load_str(&text, "f.yaml", &sets)
            .unwrap()
            .process;
        let plan = crate::etch::plan(&p);
        crate::layout::build(&p, &plan).unwrap().test_die.unwrap()
    };
    let squares = build(&[]);
    let bar = "steps.tmah-etch.compensation.geometry=bar_110";
    for sets in [vec![bar], vec![bar, "geometry.teeth.pattern=none"]] {
        let t = build(&sets);
        assert_eq!(t.geometry, crate::process::CompensationGeometry::Bar110);
        assert_eq!(t.a_um, squares.a_um);
        // Corner-attached squares of up to 517.6 um reach that far along y on both sides.
        let dy = squares.size_um[1] - t.size_um[1];
        assert!((dy - 2.0 * squares.a_um[6]).abs() < 1e-6, "{dy}");
    }
}
