//! The malformed-input corpus: every file in tests/bad-input/ must fail with exit 2 and exactly
//! the messages in its `.expected` file (all problems at once, each with file:line:column).

use proptest::prelude::*;
use tactfab::process::{self, load_str, LoadError, Location, MAX_FILE_BYTES, MAX_PROBLEMS_SHOWN};

use super::harness::{root, tactfab, REFERENCE};

#[test]
fn corpus_gives_the_expected_messages() {
    let dir = root().join("tests/bad-input");
    let mut cases: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    cases.sort();
    assert!(
        cases.len() >= 43,
        "the corpus needs at least 20 files, has {}",
        cases.len()
    );
    let mut failures = Vec::new();
    for case in &cases {
        let rel = format!(
            "tests/bad-input/{}",
            case.file_name().unwrap().to_str().unwrap()
        );
        let expected = std::fs::read_to_string(case.with_extension("expected"))
            .unwrap_or_else(|_| panic!("{rel}: no .expected file"));
        let run = tactfab(&["check", &rel]);
        if run.code != 2 || run.stderr != expected || !run.stdout.is_empty() {
            failures.push(format!(
                "{rel}: exit {}\n--- got\n{}--- expected\n{}",
                run.code, run.stderr, expected
            ));
        }
        // Every problem line names file:line:column (or the --set argument) and a field path;
        // a default the file never wrote may have no line, and says `(default)`.
        for line in run
            .stderr
            .lines()
            .filter(|l| l.contains(".yaml:") && !l.contains(".yaml: "))
        {
            let after = line.split(".yaml:").nth(1).unwrap();
            let mut parts = after.splitn(3, ':');
            let (l, c) = (parts.next().unwrap(), parts.next().unwrap_or(""));
            assert!(
                l.parse::<usize>().is_ok() && c.parse::<usize>().is_ok(),
                "{rel}: no line:column in `{line}`"
            );
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn many_problems_are_reported_in_one_run() {
    let run = tactfab(&["check", "tests/bad-input/15-many-problems-at-once.yaml"]);
    run.expect_code(2);
    let problems = run
        .stderr
        .lines()
        .filter(|l| l.contains("15-many-problems-at-once.yaml:"))
        .count();
    assert_eq!(problems, 7, "{}", run.stderr);
    assert!(run.stderr.contains("7 problems found"));
}

#[test]
fn missing_file_is_exit_2_with_hint() {
    let run = tactfab(&["check", "process/no-such-file.yaml"]);
    run.expect_code(2);
    assert!(
        run.stderr
            .contains("process/no-such-file.yaml: cannot read the process file"),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("hint:"));
}

#[test]
fn bad_override_points_at_the_argument() {
    let run = tactfab(&["etch", REFERENCE, "--set", "steps.tmah-etch.temp_c=150"]);
    run.expect_code(2);
    assert!(
        run.stderr.contains(
            "--set steps.tmah-etch.temp_c=150: steps[10].temp_c (traveler step 11): 150 C for TMAH \
             is out of range"
        ),
        "{}",
        run.stderr
    );
    let run = tactfab(&["etch", REFERENCE, "--set", "steps.no-such-step.temp_c=80"]);
    run.expect_code(2);
    assert!(
        run.stderr.contains("no element named `no-such-step`"),
        "{}",
        run.stderr
    );
    let run = tactfab(&["etch", REFERENCE, "--set", "geometry.teeth.colour=red"]);
    run.expect_code(2);
    assert!(
        run.stderr
            .contains("--set geometry.teeth.colour=red: geometry.teeth.colour: unknown field"),
        "{}",
        run.stderr
    );
    let run = tactfab(&["etch", REFERENCE, "--set", "no-equals-sign"]);
    run.expect_code(2);
}

/// A base thinner than 1 um or softer than 1 MPa, or a film thinner than 0.1 um, is refused at
/// the flag: at 1e-9 um the supports' section asked for 3e13 grid lines (the machine's memory,
/// before the section was bounded by its stub's elements), at 1e-12 GPa it was singular, at
/// 1 kPa the solid rung's Newton ran past 300 s, and a 1e-9 um film past 400 s.
#[test]
fn a_base_or_film_too_thin_or_too_soft_is_refused_at_the_flag() {
    for (set, says) in [
        (
            "materials.pvdf.thickness_um=1e-9",
            "materials.pvdf.thickness_um: 0.000000001 um is out of range (expected a number in \
             [0.1, 1000] um)",
        ),
        (
            "materials.base.thickness_um=1e-9",
            "materials.base.thickness_um: 0.000000001 um is out of range (expected a number in \
             [1, 100000] um)",
        ),
        (
            "materials.base.e_gpa=1e-6",
            "materials.base.e_gpa: 0.000001 GPa is out of range (expected a number in [0.001, \
             1000] GPa)",
        ),
    ] {
        let run = tactfab(&[
            "fe",
            REFERENCE,
            "--set",
            "materials.base.support_model=solid_section",
            "--set",
            set,
        ]);
        run.expect_code(2);
        assert!(run.stderr.contains(says), "{}", run.stderr);
    }
}

#[test]
fn unknown_subcommand_and_flag_are_usage_errors() {
    tactfab(&["frobnicate"]).expect_code(2);
    tactfab(&["etch", REFERENCE, "--jsn"]).expect_code(2);
}

#[test]
fn default_lines_say_default() {
    let run = tactfab(&["check", "tests/bad-input/43-default-out-of-range.yaml"]);
    for line in run.stderr.lines().filter(|l| l.contains(".yaml: ")) {
        assert!(line.contains(" (default): "), "{line}");
    }
}

#[test]
fn over_the_cap_the_first_problems_are_shown_and_the_rest_counted() {
    let text = std::fs::read_to_string(root().join(REFERENCE)).unwrap();
    let bogus: String = (0..600).map(|i| format!("  bogus_{i:04}: 1\n")).collect();
    let text = text.replacen("geometry:\n", &format!("geometry:\n{bogus}"), 1);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("many.yaml");
    std::fs::write(&file, text).unwrap();
    let run = tactfab(&["check", file.to_str().unwrap()]);
    run.expect_code(2);
    let shown: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.contains("many.yaml:"))
        .collect();
    assert_eq!(shown.len(), MAX_PROBLEMS_SHOWN);
    assert!(shown[0].contains("bogus_0000"), "{}", shown[0]);
    assert!(shown[MAX_PROBLEMS_SHOWN - 1].contains("bogus_0499"));
    assert!(run
        .stderr
        .contains("\n... and 100 more\n600 problems found"));
}

#[test]
fn endless_and_oversized_inputs_are_refused_without_reading_them() {
    let start = std::time::Instant::now();
    let run = tactfab(&["check", "/dev/zero"]);
    run.expect_code(2);
    assert!(run.stderr.contains("larger than 1 MiB"), "{}", run.stderr);
    assert!(start.elapsed().as_secs() < 10);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("big.yaml");
    let mut text = std::fs::read_to_string(root().join(REFERENCE)).unwrap();
    text.push_str(&"#".repeat(MAX_FILE_BYTES - text.len()));
    std::fs::write(&file, &text).unwrap();
    tactfab(&["check", file.to_str().unwrap()]).expect_code(0);
    text.push('#');
    std::fs::write(&file, &text).unwrap();
    tactfab(&["check", file.to_str().unwrap()]).expect_code(2);
}

#[test]
fn problems_inside_what_a_set_created_are_blamed_on_the_set() {
    let run = tactfab(&["check", REFERENCE, "--set", "geometry.x.y=1"]);
    run.expect_code(2);
    assert!(
        run.stderr
            .starts_with("error: --set geometry.x.y=1: geometry.x: unknown field `x`"),
        "{}",
        run.stderr
    );
    let run = tactfab(&["check", REFERENCE, "--set", "device.name.x=1"]);
    run.expect_code(2);
    assert!(
        run.stderr
            .contains("--set device.name.x=1: `device.name` is a single value"),
        "{}",
        run.stderr
    );
    let run = tactfab(&[
        "check",
        REFERENCE,
        "--set",
        "geometry.support_width_um=7500",
    ]);
    run.expect_code(2);
    assert!(
        run.stderr.contains(
            "--set geometry.support_width_um=7500: geometry.support_width_um: two 7500 um supports"
        ),
        "{}",
        run.stderr
    );
}

const REFERENCE_TEXT: &str = include_str!("../../process/mis-grasper.yaml");

/// Lines of the reference that hold `key: scalar`.
fn scalar_lines() -> Vec<usize> {
    REFERENCE_TEXT
        .lines()
        .enumerate()
        .filter(|(_, l)| {
            let t = l.trim_start().trim_start_matches("- ");
            t.split_once(": ").is_some_and(|(k, v)| {
                !k.starts_with('#') && !v.trim().is_empty() && !v.starts_with('{')
            })
        })
        .map(|(i, _)| i)
        .collect()
}

/// One mutation of the reference text.
fn mutate(kind: u8, pick: usize, junk: &str, cut: usize) -> String {
    let mut lines: Vec<String> = REFERENCE_TEXT.lines().map(str::to_string).collect();
    let scalars = scalar_lines();
    let i = scalars[pick % scalars.len()];
    let replace = |lines: &mut Vec<String>, v: &str| {
        let (k, _) = lines[i].split_once(": ").unwrap();
        lines[i] = format!("{k}: {v}");
    };
    match kind {
        0 => {
            lines.remove(i);
        }
        1 => replace(&mut lines, &format!("{junk:?}")),
        2 => replace(&mut lines, junk),
        3 => replace(
            &mut lines,
            [".nan", ".inf", "-.inf", "1e999", "-1e308", "0", "-1"][pick % 7],
        ),
        4 => replace(&mut lines, &format!("{}", (pick as f64) * 1e15)),
        5 => {
            // Duplicate a top-level section under a new name and the same name.
            let starts: Vec<usize> = (0..lines.len())
                .filter(|&j| {
                    lines[j]
                        .chars()
                        .next()
                        .is_some_and(|c| c.is_ascii_lowercase())
                })
                .collect();
            let s = starts[pick % starts.len()];
            let e = starts
                .iter()
                .copied()
                .find(|&j| j > s)
                .unwrap_or(lines.len());
            let copy: Vec<String> = lines[s..e].to_vec();
            lines.extend(copy);
        }
        _ => {
            let text = lines.join("\n");
            let cut = (0..=cut % text.len())
                .rev()
                .find(|&c| text.is_char_boundary(c))
                .unwrap_or(0);
            return text[..cut].to_string();
        }
    }
    lines.join("\n")
}

/// Ok, or at least one problem with a place: a line of the file, a `--set` argument, or a
/// default's section or path.
fn assert_located(result: Result<process::Loaded, LoadError>) -> Result<(), TestCaseError> {
    match result {
        Ok(_) | Err(LoadError::BadOverride { .. }) => {}
        Err(LoadError::Invalid(problems)) => {
            prop_assert!(!problems.is_empty());
            prop_assert!(
                problems
                    .iter()
                    .any(|p| !matches!(p.location, Location::Unknown { .. })),
                "no problem is located: {problems:?}"
            );
        }
        Err(e) => prop_assert!(false, "unexpected error kind: {e}"),
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// Mutations of the reference (a key deleted, a scalar replaced by a string, junk, NaN, a huge
    /// or negative number, a section duplicated, the file truncated): the loader never panics
    /// and every failure is located.
    #[test]
    fn mutated_files_never_panic_and_are_located(kind in 0u8..7, pick in 0usize..10_000, junk in "[ -~]{0,12}", cut in 0usize..20_000) {
        let text = mutate(kind, pick, &junk, cut);
        assert_located(load_str(&text, "fuzz.yaml", &[]))?;
    }

    /// Random `--set path=value` arguments on the reference: no panic, every failure located.
    #[test]
    fn random_overrides_never_panic_and_are_located(
        path in prop::sample::select(vec![
            "geometry.die_width_um", "geometry.teeth", "geometry.teeth.count_x", "wafer",
            "steps.tmah-etch.temp_c", "steps[3]", "steps", "checks.scenes[0].load", "masks[1].name",
            "materials.pvdf.nu", "layout.layers.pvdf.layer", "drc", "device.name", "x.y.z",
            "geometry.support_width_um", "etchants.tmah[0].temp_c", "steps[99].x", "a..b", "",
        ]),
        value in prop::sample::select(vec![
            "1", "-1", "0", ".nan", ".inf", "1e999", "abc", "[]", "{}", "null", "[1, 2]",
            "{a: b}", "7500", "4294967296", "\"\"", "true", "{point: {x_um: 1}}",
        ]),
        extra in "[ -~]{0,16}",
    ) {
        let args = vec![format!("{path}={value}"), extra];
        assert_located(load_str(REFERENCE_TEXT, "fuzz.yaml", &args))?;
    }
}
