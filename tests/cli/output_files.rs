//! Single output files (`fe --plot`, `etch --svg`, a sweep's shards and merge) replace only
//! what tactfab wrote, never the input or a user's file, and refuse before the work.

use std::path::Path;

use super::harness::{tactfab, tactfab_in, REFERENCE};

/// A copy of the bundled process file in `dir`, as a user's own input.
fn input_in(dir: &Path) -> std::path::PathBuf {
    let p = dir.join("p.yaml");
    std::fs::copy(super::harness::root().join(REFERENCE), &p).unwrap();
    p
}

#[test]
fn fe_plot_replaces_its_own_plot_only() {
    let dir = tempfile::tempdir().unwrap();
    let input = input_in(dir.path());
    let yaml = std::fs::read(&input).unwrap();
    let fe = |plot: &str| {
        tactfab_in(
            dir.path(),
            &[
                "fe",
                "p.yaml",
                "--scene",
                "pressure-2n",
                "--max-levels",
                "2",
                "--convergence",
                "--plot",
                plot,
            ],
        )
    };
    // The input, by another spelling of its path: refused, untouched.
    let r = fe("./p.yaml");
    r.expect_code(2);
    assert!(
        r.stderr.contains("--plot") && r.stderr.contains("it is the input"),
        "{}",
        r.stderr
    );
    assert_eq!(std::fs::read(&input).unwrap(), yaml);
    // Its own plot, twice: the second run replaces the first, byte for byte the same.
    fe("plot.svg").expect_code(0);
    // The plot itself keeps its text on its canvas, as Chromium lays it out.
    super::harness::assert_svgs_fit(dir.path());
    let first = std::fs::read(dir.path().join("plot.svg")).unwrap();
    fe("plot.svg").expect_code(0);
    assert_eq!(std::fs::read(dir.path().join("plot.svg")).unwrap(), first);
    // Edited since, or a user's file: refused, left as it was.
    let edited = String::from_utf8(first)
        .unwrap()
        .replacen("<svg", "<svg ", 1);
    std::fs::write(dir.path().join("plot.svg"), &edited).unwrap();
    std::fs::write(dir.path().join("notes.txt"), "mine").unwrap();
    for (plot, kept) in [("plot.svg", edited.as_str()), ("notes.txt", "mine")] {
        let r = fe(plot);
        r.expect_code(2);
        assert!(
            r.stderr.contains("tactfab did not write it") && r.stderr.contains("hint:"),
            "{}",
            r.stderr
        );
        assert!(
            !r.stdout.contains("pressure-2n"),
            "refused before the solve"
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join(plot)).unwrap(),
            kept
        );
    }
}

#[test]
fn fe_json_file_gives_the_text_and_the_json_from_one_solve() {
    let dir = tempfile::tempdir().unwrap();
    let input = input_in(dir.path());
    let yaml = std::fs::read(&input).unwrap();
    let args = [
        "fe",
        "p.yaml",
        "--scene",
        "pressure-2n",
        "--max-levels",
        "2",
    ];
    let fe = |extra: &[&str]| tactfab_in(dir.path(), &[&args[..], extra].concat());
    let printed = fe(&["--json"]);
    printed.expect_code(0);
    let text = fe(&[]);
    text.expect_code(0);
    // Stdout is the text, with the file named at its end; the file is the JSON --json prints,
    // plus its stamp as the last key.
    let both = fe(&["--json-file", "fe.json"]);
    both.expect_code(0);
    // The header's wall-clock time left out.
    let untimed = |s: &str| {
        s.split(", ")
            .filter(|p| !p.ends_with(" ms"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    assert_eq!(
        untimed(&both.stdout),
        untimed(&format!("{}json: fe.json\n", text.stdout))
    );
    let written = std::fs::read_to_string(dir.path().join("fe.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&written).expect("the file is JSON");
    let stamp = v
        .as_object_mut()
        .unwrap()
        .remove("tactfab_sha256")
        .expect("stamped");
    assert_eq!(stamp.as_str().map(str::len), Some(64));
    let expected: serde_json::Value = serde_json::from_str(&printed.stdout).unwrap();
    assert_eq!(v, expected);
    assert!(
        written.ends_with(&format!("\"tactfab_sha256\": {stamp}\n}}\n")),
        "{written}"
    );
    // Its own file is replaced (the same bytes: deterministic); --timings goes with it.
    fe(&["--json-file", "fe.json"]).expect_code(0);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("fe.json")).unwrap(),
        written
    );
    let timed = fe(&["--json-file", "fe.json", "--timings"]);
    timed.expect_code(0);
    let timed = std::fs::read_to_string(dir.path().join("fe.json")).unwrap();
    assert!(timed.contains("\"solve_ms\""), "{timed}");
    // Edited since, a user's file, or the input: refused before the solve, left as they were.
    let edited = timed.replacen("\"scenes\"", "\"scenes\" ", 1);
    std::fs::write(dir.path().join("fe.json"), &edited).unwrap();
    std::fs::write(dir.path().join("notes.json"), "{}").unwrap();
    for (path, kept, why) in [
        ("fe.json", edited.as_bytes(), "tactfab did not write it"),
        ("notes.json", b"{}".as_slice(), "tactfab did not write it"),
        ("./p.yaml", yaml.as_slice(), "it is the input"),
    ] {
        let r = fe(&["--json-file", path]);
        r.expect_code(2);
        assert!(
            r.stderr.contains("--json-file") && r.stderr.contains(why),
            "{}",
            r.stderr
        );
        assert!(r.stdout.is_empty(), "refused before the solve");
        assert_eq!(std::fs::read(dir.path().join(path)).unwrap(), kept);
    }
    // One JSON at a time; --timings needs one.
    for bad in [&["--json", "--json-file", "x.json"][..], &["--timings"][..]] {
        let r = fe(bad);
        r.expect_code(2);
        assert!(!dir.path().join("x.json").exists());
    }
}

#[test]
fn etch_svg_refuses_the_input_and_a_users_back_plot_before_simulating() {
    let dir = tempfile::tempdir().unwrap();
    let input = input_in(dir.path());
    let yaml = std::fs::read(&input).unwrap();
    let etch = |svg: &str| tactfab_in(dir.path(), &["etch", "p.yaml", "--simulate", "--svg", svg]);
    let r = etch("p.yaml");
    r.expect_code(2);
    assert!(r.stderr.contains("it is the input"), "{}", r.stderr);
    assert_eq!(std::fs::read(&input).unwrap(), yaml);
    // The back corner's plot goes beside the tooth's: a user's file there stops both.
    std::fs::write(dir.path().join("tooth-back.svg"), "mine").unwrap();
    let r = etch("tooth.svg");
    r.expect_code(2);
    assert!(r.stderr.contains("tooth-back.svg"), "{}", r.stderr);
    assert!(!dir.path().join("tooth.svg").exists());
    assert_eq!(
        std::fs::read_to_string(dir.path().join("tooth-back.svg")).unwrap(),
        "mine"
    );
}

#[test]
fn sweep_shards_and_merge_keep_a_users_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("parts");
    let out_s = out.to_str().unwrap();
    let sweep = |shard: &str| {
        tactfab(&[
            "sweep",
            REFERENCE,
            "-o",
            out_s,
            "--no-error-estimate",
            "--length-um",
            "20000,35000,2",
            "--width-um",
            "12000,18000,2",
            "--thickness-um",
            "90,110,2",
            "--tol",
            "0.2",
            "--shard",
            shard,
        ])
    };
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("sweep-1-of-2.csv"), "mine").unwrap();
    let r = sweep("1/2");
    r.expect_code(2);
    assert!(r.stderr.contains("sweep-1-of-2.csv"), "{}", r.stderr);
    assert_eq!(
        std::fs::read_to_string(out.join("sweep-1-of-2.csv")).unwrap(),
        "mine"
    );
    std::fs::remove_file(out.join("sweep-1-of-2.csv")).unwrap();
    // A shard rerun replaces its own file.
    for shard in ["1/2", "2/2", "2/2"] {
        sweep(shard).expect_code(0);
    }
    let merge = || tactfab(&["sweep", "--merge", out_s, "--tol", "0.2"]);
    merge().expect_code(0);
    let merged = std::fs::read(out.join("sweep.csv")).unwrap();
    merge().expect_code(0);
    assert_eq!(std::fs::read(out.join("sweep.csv")).unwrap(), merged);
    // A user's plot where the merge draws: refused, and the CSV is not rewritten either.
    std::fs::write(out.join("family.svg"), "mine").unwrap();
    std::fs::remove_file(out.join("sweep.csv")).unwrap();
    let r = merge();
    r.expect_code(2);
    assert!(r.stderr.contains("family.svg"), "{}", r.stderr);
    assert!(!out.join("sweep.csv").exists());
    assert_eq!(
        std::fs::read_to_string(out.join("family.svg")).unwrap(),
        "mine"
    );
}

/// An output directory tactfab may not replace is refused before the work: under a 300 MB
/// memory limit the bundled build stops at its first large factor, so a refusal that waited for
/// the write would name the factor instead.
#[test]
fn an_output_directory_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let input = input_in(dir.path());
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let limit = [("TACTFAB_MEMORY_LIMIT_MB", "300")];
    let input_s = input.to_str().unwrap();
    for (target, why) in [
        (out.to_str().unwrap(), "notes.txt"),
        (dir.path().to_str().unwrap(), "lies inside it"),
    ] {
        let args = ["build", input_s, "-o", target, "--verify-solid"];
        let (code, stdout, stderr) = super::harness::run_env(&args, &limit);
        assert_eq!(code, 2, "{stdout}\n{stderr}");
        assert!(
            stderr.contains("not replaced") && stderr.contains(why) && !stderr.contains("factor"),
            "{stderr}"
        );
    }
    // Without the directory's guard the same run stops at the factor: the check above is
    // the early refusal, not the memory limit's.
    let fresh = dir.path().join("fresh");
    let args = [
        "build",
        input_s,
        "-o",
        fresh.to_str().unwrap(),
        "--verify-solid",
    ];
    let (code, _, stderr) = super::harness::run_env(&args, &limit);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("factor"), "{stderr}");
    assert!(!fresh.exists());
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
}
