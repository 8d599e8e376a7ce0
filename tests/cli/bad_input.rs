//! The malformed-input corpus: every file in tests/bad-input/ must fail with exit 2 and exactly
//! the messages in its `.expected` file (all problems at once, each with file:line:column).

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
        cases.len() >= 20,
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
        // Every problem line names file:line:column (or the --set argument) and a field path.
        for line in run.stderr.lines().filter(|l| l.contains(".yaml:")) {
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
            "--set steps.tmah-etch.temp_c=150: steps[10].temp_c: 150 C for TMAH is out of range"
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

#[test]
fn unknown_subcommand_and_flag_are_usage_errors() {
    tactfab(&["frobnicate"]).expect_code(2);
    tactfab(&["etch", REFERENCE, "--jsn"]).expect_code(2);
}
