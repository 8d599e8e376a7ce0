//! Property tests of the library: monotonic physics, conservation, and a fuzzed loader.

use proptest::prelude::*;
use tactfab::etch;
use tactfab::process::{self, load_str};

const REFERENCE: &str = include_str!("../../process/mis-grasper.yaml");

fn plan_with(sets: &[String]) -> etch::EtchPlan {
    let loaded = load_str(REFERENCE, "mis-grasper.yaml", sets).expect("valid overrides");
    etch::plan(&loaded.process)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Etch time grows with depth and falls with temperature (model rate, no measurement).
    #[test]
    fn time_grows_with_depth_and_falls_with_temperature(d1 in 10.0f64..240.0, dd in 1.0f64..100.0, t1 in 50.0f64..90.0, dt in 1.0f64..5.0) {
        let base = |depth: f64, temp: f64| {
            let p = plan_with(&[
                "steps.tmah-etch.measured_rate_um_per_h=null".into(),
                "steps.tmah-etch.time_h=null".into(),
                format!("steps.tmah-etch.depth_um={depth}"),
                format!("steps.tmah-etch.temp_c={temp}"),
            ]);
            p.steps[0].time_h
        };
        prop_assert!(base(d1 + dd, t1) > base(d1, t1));
        prop_assert!(base(d1, t1 + dt) < base(d1, t1));
    }

    /// wafer = plate + front + back for any depths and times.
    #[test]
    fn plate_thickness_is_conserved(depth in 10.0f64..240.0, time in 0.5f64..12.0, wafer in 300.0f64..700.0) {
        let p = plan_with(&[
            format!("steps.tmah-etch.depth_um={depth}"),
            format!("steps.tmah-etch.time_h={time}"),
            format!("wafer.thickness_um={wafer}"),
        ]);
        prop_assert!((p.plate_thickness_um + p.front_depth_um + p.back_depth_um - wafer).abs() < 1e-9);
        prop_assert!((p.front_depth_um - 24.0 * time).abs() < 1e-9);
    }

    /// Mutated reference files never panic the loader; every failure lists at least one problem.
    #[test]
    fn loader_never_panics(cut in 0usize..REFERENCE.len(), len in 0usize..40, insert in "[ -~\n\t]{0,12}") {
        let mut text = REFERENCE.to_string();
        let start = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
        let end = (start + len).min(text.len());
        let end = (end..=text.len()).find(|&i| text.is_char_boundary(i)).unwrap_or(text.len());
        text.replace_range(start..end, &insert);
        match load_str(&text, "fuzz.yaml", &[]) {
            Ok(l) => { let _ = etch::plan(&l.process); }
            Err(process::LoadError::Invalid(p)) => prop_assert!(!p.is_empty()),
            Err(e) => prop_assert!(false, "unexpected error kind: {e}"),
        }
    }

    /// Line-level mutations: swap a value for another type or drop a line.
    #[test]
    fn loader_survives_line_mutations(line in 0usize..220, kind in 0u8..4) {
        let mut lines: Vec<String> = REFERENCE.lines().map(str::to_string).collect();
        let i = line % lines.len();
        match kind {
            0 => { lines.remove(i); }
            1 => if let Some((k, _)) = lines[i].clone().split_once(": ") { lines[i] = format!("{k}: [1, 2]"); },
            2 => if let Some((k, _)) = lines[i].clone().split_once(": ") { lines[i] = format!("{k}: -1e9"); },
            _ => if let Some((k, _)) = lines[i].clone().split_once(": ") { lines[i] = format!("{k}: {{a: b}}"); },
        }
        let _ = load_str(&lines.join("\n"), "fuzz.yaml", &[]).map(|l| etch::plan(&l.process));
    }
}

#[test]
fn one_double_sided_etch_equals_two_single_sided_ones() {
    let both = plan_with(&["steps.tmah-etch.time_h=null".into()]);
    assert!((both.plate_thickness_um - 100.0).abs() < 1e-9);
    // Split the double-sided TMAH step into a front and a back etch of the same depth.
    let start = REFERENCE.find("  - name: tmah-etch").unwrap();
    let end = REFERENCE.find("  - name: strip-resist").unwrap();
    let step = &REFERENCE[start..end].replace("    time_h: 8.5 ", "    # no time ");
    let front = step
        .replace("side: both", "side: front")
        .replace("name: tmah-etch", "name: tmah-front");
    let back = step
        .replace("side: both", "side: back")
        .replace("name: tmah-etch", "name: tmah-back");
    let text = format!(
        "{}{}{}{}",
        &REFERENCE[..start],
        front,
        back,
        &REFERENCE[end..]
    );
    let split = etch::plan(
        &load_str(&text, "split.yaml", &[])
            .expect("split process loads")
            .process,
    );
    assert_eq!(split.steps.len(), 2);
    assert!((split.plate_thickness_um - both.plate_thickness_um).abs() < 1e-9);
    assert!(
        (split.front_depth_um - 200.0).abs() < 1e-9 && (split.back_depth_um - 200.0).abs() < 1e-9
    );
    // Only the front step carries the teeth compensation.
    assert!(split.steps[0].compensation.is_some() && split.steps[1].compensation.is_none());
}
