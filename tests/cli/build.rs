//! `tactfab build` and `tactfab traveler`: the files, exit codes, atomic output, determinism, the
//! Markdown traveler against its golden file, and the HTML traveler rendered in headless Chromium.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use super::harness::{chromium, headless, root, run, REFERENCE};

const GOLDEN: &str = "tests/golden/mis-grasper-traveler.md";

fn read_all(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        m.insert(
            e.file_name().to_string_lossy().into_owned(),
            std::fs::read(e.path()).unwrap(),
        );
    }
    m
}

/// Entry names of a directory, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn json(bytes: &[u8]) -> serde_json::Value {
    serde_json::from_slice(bytes).unwrap()
}

#[test]
fn traveler_markdown_matches_golden() {
    let t = tempfile::tempdir().unwrap();
    let base = t.path().join("trav");
    let (code, stdout, stderr) = run(&[
        "traveler",
        REFERENCE,
        "-o",
        base.to_str().unwrap(),
        "--no-fe",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let md = std::fs::read_to_string(base.join("mis-grasper-traveler.md")).unwrap();
    assert!(base.join("mis-grasper-traveler.html").is_file());
    let golden = root().join(GOLDEN);
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&golden, &md).unwrap();
    }
    let want = std::fs::read_to_string(&golden).unwrap_or_default();
    if md != want {
        let first = md
            .lines()
            .zip(want.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(md.lines().count().min(want.lines().count()));
        panic!(
            "the traveler differs from {GOLDEN} at line {}:\n  got:  {}\n  want: {}\n(regenerate \
             with UPDATE_GOLDEN=1 cargo test traveler_markdown_matches_golden after checking the \
             change)",
            first + 1,
            md.lines().nth(first).unwrap_or("<end>"),
            want.lines().nth(first).unwrap_or("<end>")
        );
    }
}

#[test]
fn traveler_is_one_directory_and_fe_can_be_skipped() {
    let t = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = run(&[
        "traveler",
        REFERENCE,
        "-o",
        t.path().join("sub/run").to_str().unwrap(),
        "--no-fe",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert_eq!(
        names(&t.path().join("sub/run")),
        [
            "mis-grasper-traveler.html",
            "mis-grasper-traveler.md",
            "tactfab.sha256"
        ]
    );
    let md = std::fs::read_to_string(t.path().join("sub/run/mis-grasper-traveler.md")).unwrap();
    assert!(md.contains("Not computed here (`--no-fe`)"));
    assert!(!md.contains("W1 ____"), "one wafer: one blank per reading");
    // A lot of three wafers: each hold-point reading gets a blank per wafer; 0 or 26 is refused.
    let lot = t.path().join("lot");
    let (code, stdout, stderr) = run(&[
        "traveler",
        REFERENCE,
        "-o",
        lot.to_str().unwrap(),
        "--no-fe",
        "--set",
        "wafer.lot_wafers=3",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let md = std::fs::read_to_string(lot.join("mis-grasper-traveler.md")).unwrap();
    assert!(
        md.contains("centre: W1 ____ W2 ____ W3 ____"),
        "{}",
        md.lines().find(|l| l.contains("| H1 |")).unwrap_or("no H1")
    );
    for bad in ["0", "26", "2.5"] {
        let (code, _, stderr) = run(&[
            "traveler",
            REFERENCE,
            "-o",
            t.path().join("bad").to_str().unwrap(),
            "--no-fe",
            "--set",
            &format!("wafer.lot_wafers={bad}"),
        ]);
        assert_eq!(code, 2, "{bad}: {stderr}");
        assert!(stderr.contains("wafer.lot_wafers"), "{bad}: {stderr}");
    }
}

/// The full build, once: files, summary, hashes, FE section; then its HTML in Chromium.
#[test]
fn build_writes_everything_and_the_html_renders() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("out");
    let (code, stdout, stderr) = run(&["build", REFERENCE, "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(
        stderr.is_empty(),
        "no progress when stderr is not a terminal: {stderr}"
    );
    assert!(stdout.contains("build passed"), "{stdout}");
    // Each scene's line states its safety factor once: a declared limit states it with its
    // error, a scene without one plainly.
    for line in stdout.lines().filter(|l| l.starts_with("  FE `")) {
        assert_eq!(line.matches("safety factor").count(), 1, "{line}");
        // A factor under the required 3 is named there too, not only in the traveler (until
        // 2026-11-30 the line said "safety factor 0.69; no limits" and nothing more).
        let below = line.starts_with("  FE `centre-1n`") || line.starts_with("  FE `max-grasp-4n`");
        assert_eq!(line.contains("BELOW_SAFETY_FACTOR"), below, "{line}");
    }
    // Mask drawings and FE plots alike keep their text on the canvas.
    super::harness::assert_svgs_fit(&out);
    let files = read_all(&out);
    let names: Vec<&str> = files.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "build.json",
            "mis-grasper-back-si.svg",
            "mis-grasper-drc.lyrdb",
            "mis-grasper-drc.txt",
            "mis-grasper-etch-plan.json",
            "mis-grasper-front-si.svg",
            "mis-grasper-pvdf.svg",
            "mis-grasper-traveler.html",
            "mis-grasper-traveler.md",
            "mis-grasper-wafer.svg",
            "mis-grasper.gds",
            "mis-grasper.lyp",
            "tactfab.sha256",
        ]
    );
    // The masks are the committed set, byte for byte.
    for m in [
        "mis-grasper.gds",
        "mis-grasper-front-si.svg",
        "mis-grasper-back-si.svg",
        "mis-grasper-pvdf.svg",
        "mis-grasper-wafer.svg",
        "mis-grasper.lyp",
    ] {
        assert!(
            files[m] == std::fs::read(root().join("masks").join(m)).unwrap(),
            "{m} differs from masks/"
        );
    }
    let s = json(&files["build.json"]);
    assert_eq!(s["passed"], true);
    assert_eq!(s["failures"].as_array().unwrap().len(), 0);
    // The FE summary's tissue section: paper 002's lump raises the face pressure and M2, the
    // void lowers both, and the traveler says so.
    let tissue = &s["fe"]["tissue"]["features"];
    let f = |i: usize, k: &str| tissue[i][k].as_f64().unwrap();
    assert_eq!(
        (tissue[0]["feature"].as_str(), tissue[1]["feature"].as_str()),
        (Some("lump"), Some("void"))
    );
    assert!(
        f(0, "extreme_ratio") > 1.0 && f(1, "extreme_ratio") < 1.0,
        "{tissue}"
    );
    assert!(f(0, "m2_feature_mv") > f(0, "m2_background_mv"), "{tissue}");
    assert!(f(1, "m2_feature_mv") < f(1, "m2_background_mv"), "{tissue}");
    let md = String::from_utf8_lossy(&files["mis-grasper-traveler.md"]);
    assert!(md.contains("Hidden features in grasped tissue"));
    // The large-deflection scenes' estimate is the discretisation's alone: the table says so.
    assert!(
        md.contains("(discretisation only: model not estimated)"),
        "{md}"
    );
    // What the plate stood on: the bundled file clamps it, so no springs to state.
    assert_eq!(s["fe"]["supports"]["support_model"], "clamped");
    assert!(s["fe"]["supports"].get("bare").is_none(), "{}", s["fe"]);
    // Every listed file's hash is the file's (an independent SHA-256: the sha256sum tool when
    // present).
    let listed = s["files"].as_array().unwrap();
    assert_eq!(
        listed.len(),
        files.len() - 2,
        "all but build.json and the manifest"
    );
    for f in listed {
        let name = f["name"].as_str().unwrap();
        assert_eq!(f["bytes"].as_u64().unwrap() as usize, files[name].len());
        if let Ok(o) = Command::new("sha256sum").arg(out.join(name)).output() {
            let sum = String::from_utf8_lossy(&o.stdout);
            assert_eq!(
                sum.split_whitespace().next().unwrap(),
                f["sha256"].as_str().unwrap(),
                "{name}"
            );
        }
    }
    assert_eq!(
        s["masks"]["gds_sha256"],
        listed
            .iter()
            .find(|f| f["name"] == "mis-grasper.gds")
            .unwrap()["sha256"]
    );
    // FE: the four declared scenes, the limit of centre-1n checked and passed, no timings.
    let scenes = s["fe"]["scenes"].as_array().unwrap();
    let names: Vec<&str> = scenes.iter().map(|x| x["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        ["centre-1n", "max-grasp-4n", "line-y5mm", "pressure-2n"]
    );
    assert_eq!(scenes[0]["limits"][0]["limit"], "min_safety_factor");
    assert_eq!(scenes[0]["limits"][0]["passed"], true);
    // A factor under materials.silicon.safety_factor (3) is a warning, limit or not: the
    // centre load's 2.21 and the 4 N grasp's 0.69, not the line load's 8.
    let below = |k: usize| {
        scenes[k]["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["code"] == "BELOW_SAFETY_FACTOR" && w["severity"] == "warning")
    };
    assert_eq!(
        (0..4).map(below).collect::<Vec<_>>(),
        [true, true, false, false]
    );
    assert!(s.get("timings_ms").is_none());
    assert_eq!(s["process_file"], "mis-grasper.yaml");
    let sha = s["process_sha256"].as_str().unwrap();
    assert_eq!(sha.len(), 64);
    // Traceability: the tool, the overrides (none here) and how the scenes were solved.
    assert_eq!(
        s["tool"].as_str().unwrap(),
        format!("tactfab {}", env!("CARGO_PKG_VERSION"))
    );
    assert_eq!(s["overrides"], serde_json::json!([]));
    assert_eq!(s["fe_accuracy"]["model"], "auto");
    assert!(s["fe_accuracy"]["tol_rel"].as_f64().is_some());
    let md = String::from_utf8(files["mis-grasper-traveler.md"].clone()).unwrap();
    assert!(
        md.contains(sha),
        "the traveler names the process file's SHA-256"
    );
    assert!(md.contains("--model auto at --tol"), "and the rung asked");
    // What the floor needs beside the recipe: safety for HF and hot TMAH, rinse and dry, the
    // dose's lamp intensity, dicing before the first assembly step.
    for want in [
        "Safety: hot TMAH (80 C) is toxic through the skin",
        "Safety: HF (BOE)",
        "Rinse: DI water cascade",
        "dose: 60-150 mJ/cm² needs 4.0-10.0 mW/cm² at 15 s",
        "dice the wafer into its 9 dies",
        "RESIST_IN_BATH",
        "warning[BELOW_SAFETY_FACTOR]: safety factor 0.69 is under the required 3",
    ] {
        assert!(md.contains(want), "the traveler lacks {want:?}");
    }
    assert!(
        md.contains("PASS safety factor") && md.contains("| centre-1n |"),
        "FE table in the traveler"
    );
    assert!(
        !md.contains("solve_ms") && !md.contains(" ms"),
        "no timings in the traveler"
    );
    // The plate sensitivity ordering of paper 002: a middle electrode reads most at the centre.
    assert!(
        scenes[0]["most_sensitive"]
            .as_str()
            .unwrap()
            .starts_with('M'),
        "{}",
        scenes[0]["most_sensitive"]
    );

    render_in_chromium(&out.join("mis-grasper-traveler.html"), t.path());
    print_to_pdf(&out.join("mis-grasper-traveler.html"), t.path());
}

/// Prints the HTML traveler to A4 PDF in headless Chromium and reads it back with pdftotext:
/// every page carries the running header (device, revision, lot and wafer blanks) and
/// "page i of n", and the whole run sheet stays within a bounded number of pages.
fn print_to_pdf(html: &Path, work: &Path) {
    let pdftotext = Command::new("pdftotext").arg("-v").output().is_ok();
    let (Some(chrome), true) = (chromium(), pdftotext) else {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("`.ci/run` installs chromium and poppler-utils (pdftotext)");
        }
        eprintln!("SKIPPED the print test: needs chromium and pdftotext (poppler-utils)");
        return;
    };
    let pdf = work.join("traveler.pdf");
    let out = headless(&chrome, &work.join("profile-pdf"))
        .arg("--no-pdf-header-footer")
        .arg(format!("--print-to-pdf={}", pdf.display()))
        .arg(format!("file://{}", html.canonicalize().unwrap().display()))
        .output()
        .unwrap();
    assert!(pdf.exists(), "{}", String::from_utf8_lossy(&out.stderr));
    let txt = work.join("traveler.txt");
    let ok = Command::new("pdftotext")
        .arg("-layout")
        .arg(&pdf)
        .arg(&txt)
        .status()
        .unwrap();
    assert!(ok.success());
    let text = std::fs::read_to_string(&txt).unwrap();
    let pages: Vec<&str> = text
        .split('\u{c}')
        .filter(|p| !p.trim().is_empty())
        .collect();
    let n = pages.len();
    assert!((3..=24).contains(&n), "{n} pages");
    for (i, p) in pages.iter().enumerate() {
        assert!(
            p.contains("Traveler mis-grasper rev A") && p.contains("Lot ____"),
            "page {} lacks the running header:\n{p}",
            i + 1
        );
        assert!(
            p.contains(&format!("page {} of {n}", i + 1)),
            "page {} lacks its number:\n{p}",
            i + 1
        );
    }
    // The nine-column run sheet prints on landscape pages, the rest portrait (pdfinfo, from
    // poppler-utils like pdftotext).
    let info = Command::new("pdfinfo")
        .args(["-f", "1", "-l", &n.to_string()])
        .arg(&pdf)
        .output()
        .unwrap();
    let info = String::from_utf8_lossy(&info.stdout);
    let landscape: Vec<usize> = info
        .lines()
        .filter(|l| l.starts_with("Page ") && l.contains(" size:"))
        .filter_map(|l| {
            let nums: Vec<f64> = l
                .split_whitespace()
                .filter_map(|w| w.parse().ok())
                .collect();
            // "Page 3 size: 841.92 x 594.96 pts": page, width, height.
            (nums.len() >= 3 && nums[1] > nums[2]).then_some(nums[0] as usize)
        })
        .collect();
    assert!(!landscape.is_empty() && landscape.len() < n, "{info}");
    for &k in &landscape {
        let p = pages[k - 1];
        assert!(
            p.contains("Deviation"),
            "landscape page {k} is not the run sheet:\n{p}"
        );
    }
}

/// Renders `html` to PNG on an A4-proportioned window, fails on console errors, and checks the
/// rendered DOM has every section heading.
fn render_in_chromium(html: &Path, work: &Path) {
    let Some(chrome) = chromium() else {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("chromium is not installed: `.ci/run` installs the Debian package `chromium`");
        }
        eprintln!(
            "SKIPPED the Chromium render: chromium is not on PATH (install the Debian package \
             `chromium`)"
        );
        return;
    };
    let url = format!("file://{}", html.canonicalize().unwrap().display());
    let png = work.join("traveler.png");
    let base = |profile: &str| {
        let mut c = headless(&chrome, &work.join(profile));
        c.args([
            "--disable-quic",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1240,1754",
        ]);
        c
    };
    let shot = base("profile-shot")
        .arg(format!("--screenshot={}", png.display()))
        .arg(&url)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&shot.stderr);
    assert!(shot.status.success(), "chromium failed:\n{err}");
    let bytes = std::fs::read(&png).unwrap_or_else(|e| panic!("no screenshot ({e}):\n{err}"));
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height of the window.
    let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((w, h), (1240, 1754));
    assert!(
        bytes.len() > 20_000,
        "an empty page compresses to a few kB: {} bytes",
        bytes.len()
    );
    let dom = base("profile-dom")
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .unwrap();
    let dom_err = String::from_utf8_lossy(&dom.stderr);
    for log in [&err, &dom_err] {
        for line in log.lines() {
            assert!(
                !(line.contains("CONSOLE") || line.contains("Uncaught")),
                "console message while rendering: {line}"
            );
        }
    }
    let dom = String::from_utf8_lossy(&dom.stdout);
    for h in [
        "Header",
        "Starting material",
        "Masks",
        "Steps",
        "Hold points",
        "Cross-sections",
        "Checks and warnings",
        "FE sensitivity",
        "Corner compensation",
    ] {
        assert!(
            dom.contains(&format!("<h2>{h}</h2>")),
            "rendered page lacks the `{h}` section"
        );
    }
    assert!(
        dom.matches("<svg").count() >= 14 + 3 + 2,
        "cross-sections (one per step that changes the stack), masks and plots are inline SVG"
    );
}

#[test]
fn build_is_deterministic_and_replaces_only_its_own_output() {
    let t = tempfile::tempdir().unwrap();
    let (a, b) = (t.path().join("a"), t.path().join("b"));
    let fast = ["--max-levels", "1"];
    // The process file named relatively and absolutely: the same bytes.
    let absolute = root().join(REFERENCE);
    for (d, file) in [(&a, REFERENCE), (&b, absolute.to_str().unwrap())] {
        let mut args = vec!["build", file, "-o", d.to_str().unwrap()];
        args.extend(fast);
        let (code, stdout, stderr) = run(&args);
        assert!(code == 0 || code == 1, "{stdout}\n{stderr}");
    }
    let (fa, fb) = (read_all(&a), read_all(&b));
    assert_eq!(fa.keys().collect::<Vec<_>>(), fb.keys().collect::<Vec<_>>());
    for (name, bytes) in &fa {
        assert!(*bytes == fb[name], "{name} differs between two builds");
    }
    // A second build replaces the first and leaves nothing beside it (without FE scenes from
    // here on: what is kept or replaced does not depend on them, and each FE build costs ~20 s).
    let args = vec![
        "build",
        REFERENCE,
        "-o",
        a.to_str().unwrap(),
        "--set",
        "checks.scenes=[]",
    ];
    let (code, ..) = run(&args);
    assert!(code == 0 || code == 1);
    assert_eq!(names(t.path()), ["a", "b"]);
    // A note the user put into the previous build is not lost: refused, unless --overwrite.
    std::fs::write(a.join("notes.txt"), "mine").unwrap();
    let (code, _, stderr) = run(&args);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("notes.txt") && stderr.contains("--overwrite"),
        "{stderr}"
    );
    assert!(a.join("notes.txt").exists());
    let mut forced = args.clone();
    forced.push("--overwrite");
    let (code, ..) = run(&forced);
    assert!(code == 0 || code == 1);
    assert!(!a.join("notes.txt").exists());
    // A directory that is not a build output is refused and left alone.
    let foreign = t.path().join("mine");
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "keep").unwrap();
    let (code, _, stderr) = run(&[
        "build",
        REFERENCE,
        "-o",
        foreign.to_str().unwrap(),
        "--set",
        "checks.scenes=[]",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("did not write"), "{stderr}");
    assert_eq!(
        read_all(&foreign).into_keys().collect::<Vec<_>>(),
        ["notes.txt"]
    );
}

#[test]
fn failed_limit_exits_1_and_lists_it() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("out");
    let (code, stdout, stderr) = run(&[
        "build",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--max-levels",
        "1",
        "--set",
        "checks.scenes[1].limits.max_stress_mpa=1",
    ]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("build FAILED: "), "{stdout}");
    // One mesh level cannot show convergence: that is a failure too, naming the way out.
    assert!(
        stdout
            .lines()
            .any(|l| l.contains("FAIL: scene `max-grasp-4n`: not converged")
                && l.contains("--allow-unconverged")),
        "{stdout}"
    );
    let fail = stdout
        .lines()
        .find(|l| l.contains("FAIL: scene `max-grasp-4n`") && l.contains("stress"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        fail.contains("stress") && fail.ends_with("> 1 MPa"),
        "{fail}"
    );
    // Written for inspection, with the failure in the summary and the traveler.
    let s = json(&std::fs::read(out.join("build.json")).unwrap());
    assert_eq!(s["passed"], false);
    let listed: Vec<&str> = s["failures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(
        listed.contains(&fail.trim().trim_start_matches("FAIL: ")),
        "{listed:?}"
    );
    let md = std::fs::read_to_string(out.join("mis-grasper-traveler.md")).unwrap();
    assert!(
        md.contains("**FAIL** stress"),
        "the traveler shows the failed limit"
    );
    assert!(
        md.contains("> **BUILD FAILED") && md.contains(&format!("> - {}", listed[0])),
        "the traveler opens with the failures"
    );
}

#[test]
fn bad_input_exits_2_without_output() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("out");
    let (code, _, stderr) = run(&[
        "build",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--set",
        "wafer.thickness_um=-1",
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("wafer.thickness_um"), "{stderr}");
    let (code2, _, stderr2) = run(&[
        "build",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--tol",
        "0",
    ]);
    assert_eq!(code2, 2);
    assert!(stderr2.contains("--tol"), "{stderr2}");
    assert!(
        names(t.path()).is_empty(),
        "nothing written, no temporary directory left"
    );
}

/// Text outputs show the YAML spelling of every kind (`both`, `corner_attached`), never Rust's
/// `Debug` (`Both`, `CornerAttached`).
#[test]
fn outputs_spell_kinds_as_the_yaml_does() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    let mut text = String::new();
    for args in [
        vec!["etch", REFERENCE],
        vec!["check", REFERENCE],
        vec!["masks", REFERENCE, "-o", out.to_str().unwrap()],
    ] {
        let (code, stdout, stderr) = run(&args);
        assert!(code == 0, "{args:?}: {stderr}");
        text.push_str(&stdout);
    }
    assert!(text.contains("side both") && text.contains("compensation corner_attached"));
    let camel = text.split(|c: char| !c.is_ascii_alphanumeric()).find(|w| {
        let upper = w.chars().filter(|c| c.is_ascii_uppercase()).count();
        w.len() > 3
            && w.starts_with(|c: char| c.is_ascii_uppercase())
            && upper >= 2
            && w.chars().any(|c| c.is_ascii_lowercase())
            && !["McGill", "MicroFab", "DelRio"].contains(w)
    });
    assert_eq!(camel, None, "a Rust Debug name in the output:\n{text}");
}

/// A recipe that etches through the wafer: the build fails as a check (exit 1) listing the plan's
/// errors and that the scenes were not solved, never an internal FE error.
#[test]
fn etch_through_is_a_failed_check_not_an_fe_error() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("out");
    let (code, stdout, stderr) = run(&[
        "build",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--max-levels",
        "1",
        "--set",
        "steps.tmah-etch.time_h=20",
    ]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("DEPTH_EXCEEDS_WAFER"), "{stdout}");
    assert!(
        stdout.contains("FAIL: FE: the 4 declared scenes were not solved"),
        "{stdout}"
    );
    assert!(!stderr.contains("stiffness"), "{stderr}");
    let md = std::fs::read_to_string(out.join("mis-grasper-traveler.md")).unwrap();
    assert!(
        md.contains("**Not solved**"),
        "the traveler says why there is no FE"
    );
    // `fe` on the same recipe refuses with the reason, not a solver failure.
    let (code, _, stderr) = run(&[
        "fe",
        REFERENCE,
        "--max-levels",
        "1",
        "--set",
        "steps.tmah-etch.time_h=20",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("etches through the wafer"), "{stderr}");
}

/// Work is bounded before anything is allocated: a calibration grid of ~29,000 loads on a mesh
/// with a line through each is refused at once (exit 2, naming the limit), not run out of memory.
#[test]
fn oversized_solves_are_refused_before_allocating() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("cal");
    let (code, _, stderr) = run(&[
        "calibrate",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--x-step-mm",
        "0.1",
        "--y-step-mm",
        "0.1",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains(&format!(
            "above the limit of {}",
            tactfab::sensor::MAX_SOLUTION_VALUES
        )),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
    // A sweep of 1000^3 designs (every axis within its own range) is refused as a whole.
    let (code, _, stderr) = run(&[
        "sweep",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--length-um",
        "10000,40000,1000",
        "--width-um",
        "7500,20000,1000",
        "--thickness-um",
        "50,150,1000",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("1000000000 designs, above the limit"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
}

/// `build f.yaml -o .` run inside the folder holding the input: refused, the input and the
/// user's files untouched (a previous version deleted them when a `build.json` was there).
#[test]
fn output_dot_holding_the_input_is_refused() {
    let t = tempfile::tempdir().unwrap();
    std::fs::copy(root().join(REFERENCE), t.path().join("f.yaml")).unwrap();
    std::fs::write(t.path().join("build.json"), "{}").unwrap();
    let r = super::harness::tactfab_in(
        t.path(),
        &["build", "f.yaml", "-o", ".", "--max-levels", "1"],
    );
    r.expect_code(2);
    assert!(r.stderr.contains("lies inside it"), "{}", r.stderr);
    assert_eq!(names(t.path()), ["build.json", "f.yaml"]);
}

/// The traveler reads as typeset text: µm and ±, never `um` or `+/-`, and code quoted in messages
/// is `<code>` in HTML, never literal Markdown backticks.
#[test]
fn traveler_text_is_typeset() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("t");
    let (code, _, stderr) = run(&[
        "traveler",
        REFERENCE,
        "--no-fe",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let html = std::fs::read_to_string(out.join("mis-grasper-traveler.html")).unwrap();
    // Text outside the inline SVG figures.
    let mut text = String::new();
    for part in html.split("<svg") {
        text.push_str(part.split_once("</svg>").map_or(part, |(_, after)| after));
    }
    assert!(text.contains(" µm") && text.contains(" ± "));
    assert!(!text.contains('`'), "literal backticks in the HTML");
    assert!(!text.contains("+/-"));
    // One blank per reading: H1 asks for five wafer thicknesses, H2 for five oxide readings a face.
    assert!(text.contains("centre: ______<br>N: ______"), "H1 readings");
    assert_eq!(text.matches("front 5: ______").count(), 1, "H2 readings");
    let words: Vec<&str> = text
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .filter(|w| *w == "um")
        .collect();
    assert!(
        words.is_empty(),
        "{} bare `um` in the HTML text",
        words.len()
    );
}

/// Counts in the run sheet and the notes come from the design, not from the bundled one: the
/// four-element sensor's film is patterned into 4 islands.
#[test]
fn island_count_follows_the_electrode_pattern() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("t");
    let args = ["traveler", "process/four-element.yaml", "--no-fe", "-o"];
    let (code, _, stderr) = run(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{stderr}");
    let md = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "md"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .unwrap();
    assert!(md.contains("patterned (4 islands)"), "four islands");
    assert!(!md.contains("9 islands"));
}

/// The rendered SVG check sees what a reader would: a label running off its chart is caught, a
/// chart of tactfab's is clean.
#[test]
fn rendered_svg_check_catches_text_off_the_canvas() {
    if super::harness::chromium().is_none() && std::env::var("CI").is_err() {
        eprintln!("SKIPPED: chromium is not on PATH");
        return;
    }
    let bad = r#"<svg width="100" height="50" xmlns="http://www.w3.org/2000/svg"><text x="90" y="20" font-size="10">far too long</text></svg>"#;
    let plot = tactfab::plot::XyPlot {
        title: "voltage against force".into(),
        x: tactfab::plot::Axis::log("force (N)"),
        y: tactfab::plot::Axis::linear("voltage (mV)"),
        series: vec![tactfab::plot::Series {
            name: "M2".into(),
            points: vec![(1e-3, 0.2), (10_000.0, 2000.0)],
            style: tactfab::plot::Style::LineAndMarkers,
        }],
    };
    let good = tactfab::plot::xy_svg(&plot, 640, 400);
    let found = super::harness::rendered_text_outside(&[
        ("bad.svg".into(), bad.into()),
        ("good.svg".into(), good),
    ]);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with("bad.svg: \"far too long\""),
        "{found:?}"
    );
}

/// The traveler carries the simulated tooth: its corner numbers (Markdown and HTML) and the plan
/// view and diagonal cross-section (HTML).
#[test]
fn traveler_shows_the_simulated_tooth() {
    let t = tempfile::tempdir().unwrap();
    let base = t.path().join("trav");
    let (code, stdout, stderr) = run(&[
        "traveler",
        REFERENCE,
        "-o",
        base.to_str().unwrap(),
        "--no-fe",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let md = std::fs::read_to_string(base.join("mis-grasper-traveler.md")).unwrap();
    let html = std::fs::read_to_string(base.join("mis-grasper-traveler.html")).unwrap();
    for doc in [&md, &html] {
        assert!(
            doc.contains("Etch simulation of one tooth"),
            "no simulation paragraph"
        );
        assert!(doc.contains("extrapolated corner"));
    }
    assert!(
        html.contains("etched tooth along its diagonal"),
        "no cross-section"
    );
    assert!(html.contains("top edge at"), "no plan view");
    // Without teeth the traveler says why there is no simulation.
    let base2 = t.path().join("none");
    let (code, o, e) = run(&[
        "traveler",
        REFERENCE,
        "-o",
        base2.to_str().unwrap(),
        "--no-fe",
        "--set",
        "geometry.teeth.pattern=none",
    ]);
    assert!(code == 0 || code == 1, "{o}\n{e}");
    let md = std::fs::read_to_string(base2.join("mis-grasper-traveler.md")).unwrap();
    assert!(
        md.contains("Etch simulation of the tooth: not run (the process draws no teeth"),
        "{md}"
    );
}
