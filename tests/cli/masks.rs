//! `tactfab masks`: files, inventory, DRC exit codes, determinism, GDS read back with gds21 and
//! KLayout, the committed masks/ set.

use std::collections::BTreeMap;
use std::path::Path;

use super::harness::{root, run, run_env};

const PROCESS: &str = "process/mis-grasper.yaml";
const FILES: [&str; 9] = [
    "tactfab.sha256",
    "mis-grasper.gds",
    "mis-grasper.lyp",
    "mis-grasper-drc.lyrdb",
    "mis-grasper-drc.txt",
    "mis-grasper-front-si.svg",
    "mis-grasper-back-si.svg",
    "mis-grasper-pvdf.svg",
    "mis-grasper-wafer.svg",
];

fn generate(dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let d = dir.to_str().unwrap();
    let mut args = vec!["masks", PROCESS, "-o", d];
    args.extend_from_slice(extra);
    run_env(&args, env)
}

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

#[test]
fn bundled_process_writes_the_set_and_passes_drc() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    let (code, stdout, stderr) = generate(&out, &[], &[]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let files = read_all(&out);
    assert_eq!(files.keys().cloned().collect::<Vec<_>>(), {
        let mut v: Vec<String> = FILES.iter().map(|s| s.to_string()).collect();
        v.sort();
        v
    });
    for needle in [
        "1/0",
        "2/0",
        "3/0",
        "10/0",
        "63/0",
        "64/0",
        "65/0",
        "light field",
        "MIRRORED",
        "DRC passed",
        "MIS_GRASPER_WAFER",
    ] {
        assert!(stdout.contains(needle), "missing `{needle}` in\n{stdout}");
    }
    // The back mask is the mirrored one and says which file carries the mirror.
    let back = stdout
        .lines()
        .skip_while(|l| !l.contains("back-si"))
        .nth(1)
        .unwrap_or_default();
    assert!(
        back.contains("mis-grasper-back-si.svg` is mirrored"),
        "{stdout}"
    );
}

#[test]
fn committed_masks_regenerate_byte_identical() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    let (code, stdout, stderr) = generate(&out, &[], &[]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let fresh = read_all(&out);
    let committed = read_all(&root().join("masks"));
    assert_eq!(
        committed.keys().collect::<Vec<_>>(),
        fresh.keys().collect::<Vec<_>>(),
        "masks/ holds other files than the generator writes"
    );
    for (name, bytes) in &fresh {
        assert!(
            committed[name] == *bytes,
            "masks/{name} differs from a fresh run: regenerate with `cargo run -- masks {PROCESS} \
             -o masks`"
        );
    }
}

/// (record type, byte range) of every GDS record.
fn records(b: &[u8]) -> Vec<(u8, std::ops::Range<usize>)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i + 4 <= b.len() {
        let len = usize::from(u16::from_be_bytes([b[i], b[i + 1]]));
        assert!(len >= 4, "bad record length at {i}");
        out.push((b[i + 2], i..i + len));
        i += len;
    }
    out
}

#[test]
fn same_input_same_bytes_and_source_date_epoch_changes_only_dates() {
    let t = tempfile::tempdir().unwrap();
    let (a, b, c) = (t.path().join("a"), t.path().join("b"), t.path().join("c"));
    assert_eq!(generate(&a, &[], &[]).0, 0);
    assert_eq!(generate(&b, &[], &[]).0, 0);
    assert_eq!(
        generate(&c, &[], &[("SOURCE_DATE_EPOCH", "1700000000")]).0,
        0
    );
    let (fa, fb, fc) = (read_all(&a), read_all(&b), read_all(&c));
    assert_eq!(fa, fb);
    for name in FILES {
        // The manifest lists the GDS's hash, so it changes with the GDS.
        if !name.ends_with(".gds") && name != "tactfab.sha256" {
            assert_eq!(fa[name], fc[name], "{name} depends on SOURCE_DATE_EPOCH");
        }
    }
    let (ga, gc) = (&fa["mis-grasper.gds"], &fc["mis-grasper.gds"]);
    assert_eq!(ga.len(), gc.len());
    assert_ne!(ga, gc, "SOURCE_DATE_EPOCH did not reach the dates");
    let recs = records(ga);
    let mut diffs = 0;
    for (i, (x, y)) in ga.iter().zip(gc.iter()).enumerate() {
        if x != y {
            diffs += 1;
            let (rt, _) = recs.iter().find(|(_, r)| r.contains(&i)).unwrap();
            // 0x01 BGNLIB, 0x05 BGNSTR: the only records that carry dates.
            assert!(
                *rt == 0x01 || *rt == 0x05,
                "byte {i} differs in record type {rt:#04x}"
            );
        }
    }
    assert!(diffs > 0);
    // Zero dates by default.
    let lib = gds21::GdsLibrary::from_bytes(ga).unwrap();
    assert_eq!(lib.dates.modified.year, 0);
    assert!(lib
        .structs
        .iter()
        .all(|s| s.dates.modified.year == 0 && s.dates.accessed.month == 0));
    let libc = gds21::GdsLibrary::from_bytes(gc).unwrap();
    assert_eq!(
        (
            libc.dates.modified.year,
            libc.dates.modified.month,
            libc.dates.modified.day
        ),
        (123, 11, 14)
    );
}

#[test]
fn gds_reads_back_with_gds21() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    assert_eq!(generate(&out, &["--format", "gds"], &[]).0, 0);
    assert!(
        !out.join("mis-grasper-pvdf.svg").exists(),
        "--format gds wrote SVG"
    );
    let lib = gds21::GdsLibrary::from_bytes(&std::fs::read(out.join("mis-grasper.gds")).unwrap())
        .unwrap();
    assert!((lib.units.0 - 1e-3).abs() < 1e-12 && (lib.units.1 - 1e-9).abs() < 1e-18);
    let names: Vec<&str> = lib.structs.iter().map(|s| s.name.as_str()).collect();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted, "cells not sorted by name");
    assert_eq!(
        names,
        [
            "MIS_GRASPER_DIE",
            "MIS_GRASPER_TEST_DIE",
            "MIS_GRASPER_TOOTH",
            "MIS_GRASPER_WAFER"
        ]
    );
    let mut arefs = 0;
    let mut boundaries = 0;
    for s in &lib.structs {
        for e in &s.elems {
            match e {
                gds21::GdsElement::GdsBoundary(b) => {
                    boundaries += 1;
                    assert_eq!(b.xy.first(), b.xy.last(), "unclosed boundary in {}", s.name);
                    assert!(b.xy.len() >= 4 && b.xy.len() <= 4001);
                    let a2: i128 =
                        b.xy.windows(2)
                            .map(|w| {
                                i128::from(w[0].x) * i128::from(w[1].y)
                                    - i128::from(w[1].x) * i128::from(w[0].y)
                            })
                            .sum();
                    assert!(
                        a2 > 0,
                        "clockwise boundary in {} on layer {}",
                        s.name,
                        b.layer
                    );
                }
                gds21::GdsElement::GdsArrayRef(a) => {
                    arefs += 1;
                    assert_eq!(a.name, "MIS_GRASPER_DIE");
                    // xy = [origin, origin + cols * col pitch, origin + rows * row pitch]
                    assert_eq!(a.rows, 1);
                    assert_eq!(
                        i64::from(a.xy[1].x - a.xy[0].x),
                        i64::from(a.cols) * 30_300_000
                    );
                    assert_eq!(a.xy[2].y - a.xy[0].y, 15_300_000);
                }
                _ => {}
            }
        }
    }
    assert!(arefs >= 2, "expected several AREF rows, got {arefs}");
    assert!(boundaries > 30);
}

#[test]
fn klayout_verifies_the_mask_set() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    let (code, stdout, stderr) = generate(&out, &[], &[]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    // Expected values straight from the process file and the etch plan, not from the layout code.
    let loaded = tactfab::process::load(&root().join(PROCESS), &[]).unwrap();
    let p = &loaded.process;
    let plan = tactfab::etch::plan(p);
    let comp = plan
        .steps
        .iter()
        .find_map(|s| s.compensation)
        .expect("compensation");
    let g = &p.geometry;
    let e = &g.electrodes;
    let n = f64::from(e.units);
    let unit_w = (g.die_length_um - 2.0 * e.edge_margin_um - (n - 1.0) * e.gap_um) / n;
    // The support/middle gap is centred on the etched {111} wall: from the support's footprint
    // (back mask edge less the undercut) to its foot, a run-out h / tan 54.74 deg = h / sqrt 2 on.
    let undercut: f64 = plan
        .steps
        .iter()
        .filter(|s| s.side != tactfab::process::Side::Front)
        .map(|s| s.undercut_um)
        .sum();
    let split = g.support_width_um - undercut + plan.back_depth_um / 2f64.sqrt() / 2.0;
    // Edges land on the 1 nm grid when written.
    let nm = |v: f64| (v * 1e3).round() / 1e3;
    let (w, m) = (g.die_width_um, e.edge_margin_um);
    let s_h = nm(split - e.gap_um / 2.0) - m;
    let m_h = nm(w - split - e.gap_um / 2.0) - nm(split + e.gap_um / 2.0);
    let widths: Vec<f64> = (0..e.units)
        .map(|k| {
            let x0 = m + f64::from(k) * (unit_w + e.gap_um);
            nm(x0 + unit_w) - nm(x0)
        })
        .collect();
    let mut areas: Vec<f64> = widths.iter().map(|x| x * s_h).collect();
    areas.extend(widths.iter().map(|x| x * m_h));
    areas.extend(widths.iter().map(|x| x * s_h));
    let ov = p.layout.compensation_overlap_um;
    let expected = serde_json::json!({
        "die_length_um": g.die_length_um,
        "die_width_um": g.die_width_um,
        "teeth": 25,
        "top_um": g.teeth.top_um,
        "comp_side_um": comp.side_um,
        "comp_overlap_um": ov,
        "island_area_um2": g.teeth.top_um.powi(2) + 4.0 * (comp.side_um.powi(2) - ov * ov),
        "electrode_areas_um2": areas,
        "min_electrode_gap_um": e.gap_um,
        "support_width_um": g.support_width_um,
        "min_width_um": p.drc.min_width_um,
        "min_space_um": p.drc.min_space_um,
        "usable_radius_um": p.wafer.diameter_mm * 500.0 - p.layout.edge_exclusion_mm * 1000.0,
        "masks": [["front-si", "1/0", false], ["back-si", "2/0", true], ["pvdf", "3/0", false]],
    });
    let exp_path = t.path().join("expected.json");
    std::fs::write(&exp_path, expected.to_string()).unwrap();
    let py = std::process::Command::new("python3")
        .arg(root().join("tests/klayout_check.py"))
        .arg(out.join("mis-grasper.gds"))
        .arg(&out)
        .arg(&exp_path)
        .output()
        .expect("python3 runs");
    let (so, se) = (
        String::from_utf8_lossy(&py.stdout),
        String::from_utf8_lossy(&py.stderr),
    );
    if se.contains("No module named 'klayout'") {
        panic!(
            "KLayout's Python module is missing: run `pip install klayout` (this check does not \
             skip)\n{se}"
        );
    }
    assert!(py.status.success(), "klayout_check.py failed:\n{so}\n{se}");
    assert!(so.contains("ALL CHECKS PASSED"), "{so}");
}

#[test]
fn drc_violation_exits_1_and_waivers_release_it() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    // A 2.5 mm pitch leaves 500 um between diagonal teeth: the 368 um compensators overlap.
    let tight = [
        "--set",
        "geometry.teeth.pitch_x_um=2500",
        "--set",
        "geometry.teeth.pitch_y_um=2500",
    ];
    let (code, stdout, stderr) = generate(&out, &tight, &[]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("COMPENSATORS_COLLIDE"), "{stdout}");
    assert!(stdout.contains("DRC FAILED"), "{stdout}");
    let codes: Vec<String> = stdout
        .lines()
        .filter_map(|l| {
            l.strip_prefix("  ")
                .and_then(|r| r.split_once(": "))
                .map(|(c, _)| c.to_string())
        })
        .filter(|c| {
            c.chars().all(|ch| ch.is_ascii_uppercase() || ch == '_')
                && tactfab::finding::DrcCode::ALL
                    .iter()
                    .any(|k| k.as_str() == c)
        })
        .collect();
    assert!(!codes.is_empty());
    let waive = format!("drc.waive=[{}]", codes.join(", "));
    let mut args = tight.to_vec();
    args.extend(["--set", &waive]);
    let (code, stdout, _) = generate(&t.path().join("w"), &args, &[]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("(waived)"), "{stdout}");
    // Every violation is in the text report and, read by KLayout, in the marker database at its
    // place; waived ones carry the `waived` tag.
    for (dir, waived) in [(&out, false), (&t.path().join("w"), true)] {
        let txt = std::fs::read_to_string(dir.join("mis-grasper-drc.txt")).unwrap();
        let n: usize = txt
            .strip_prefix("DRC: ")
            .and_then(|r| r.split_once(' '))
            .and_then(|(n, _)| n.parse().ok())
            .unwrap_or_else(|| panic!("{txt}"));
        assert_eq!(
            txt.matches(" um: ").count(),
            n,
            "every violation listed:\n{txt}"
        );
        let py = std::process::Command::new("python3")
            .arg("-c")
            .arg(
                "import sys, klayout.rdb as rdb\n\
                 r = rdb.ReportDatabase('drc'); r.load(sys.argv[1])\n\
                 items = list(r.each_item())\n\
                 cats = {c.rdb_id(): c.name() for c in r.each_category()}\n\
                 print(len(items), sum('waived' in i.tags_str for i in items), r.top_cell_name,\n\
                       sorted(set(cats[i.category_id()] for i in items)))\n\
                 print(next(iter(items[0].each_value())).to_s())",
            )
            .arg(dir.join("mis-grasper-drc.lyrdb"))
            .output()
            .unwrap();
        let so = String::from_utf8_lossy(&py.stdout);
        assert!(
            py.status.success(),
            "{}",
            String::from_utf8_lossy(&py.stderr)
        );
        let first: Vec<&str> = so.lines().next().unwrap().split(' ').collect();
        assert_eq!(first[0], n.to_string(), "{so}");
        assert_eq!(
            first[1],
            if waived { n.to_string() } else { "0".into() },
            "{so}"
        );
        assert_eq!(first[2], "MIS_GRASPER_DIE", "{so}");
        assert!(so.contains("COMPENSATORS_COLLIDE"), "{so}");
        assert!(so.lines().nth(1).unwrap().starts_with("box: ("), "{so}");
    }
}

#[test]
fn streets_between_dies_are_checked() {
    let t = tempfile::tempdir().unwrap();
    // 200 um between the back supports of neighbouring dies self-stops at 141 um.
    let (code, stdout, _) = generate(
        &t.path().join("m"),
        &["--set", "geometry.dicing_street_um=200"],
        &[],
    );
    assert_eq!(code, 1, "{stdout}");
    assert!(
        stdout.contains("STREET_TOO_NARROW") && stdout.contains("across the dicing street"),
        "{stdout}"
    );
}

#[test]
fn errors_leave_no_partial_output() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    // Passes validation (pad < support width) but a 2.2 mm pad cannot fit a 2 mm island.
    let (code, _, stderr) = generate(
        &out,
        &["--set", "geometry.electrodes.wire_pad_um=2200"],
        &[],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("the electrodes do not fit"), "{stderr}");
    assert!(!out.exists(), "output written on error");
    let (code, _, stderr) = generate(&out, &["--set", "drc.waive=[MIN_WDITH]"], &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("MIN_WDITH"), "{stderr}");
    assert!(!out.exists(), "output written on error");
    assert_eq!(
        std::fs::read_dir(t.path()).unwrap().count(),
        0,
        "temporary files left behind"
    );
    let (code, _, _) = run(&[
        "masks",
        "process/does-not-exist.yaml",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(!out.exists());
    // DIR is a file: an I/O error, nothing left behind.
    std::fs::write(&out, b"x").unwrap();
    let (code, _, stderr) = generate(&out, &[], &[]);
    assert_eq!(code, 2, "{stderr}");
    assert_eq!(std::fs::read_dir(t.path()).unwrap().count(), 1);
}

#[test]
fn vertex_only_compensators_fail_drc() {
    let t = tempfile::tempdir().unwrap();
    // Without overlap a corner-attached square touches its tooth at one point: a zero-width neck.
    let (code, stdout, _) = generate(
        &t.path().join("m"),
        &["--set", "layout.compensation_overlap_um=0"],
        &[],
    );
    assert_eq!(code, 1, "{stdout}");
    assert!(stdout.contains("single point"), "{stdout}");
}

/// Each process-aware rule fires on a design that breaks it.
#[test]
fn each_rule_fires_on_a_broken_design() {
    let t = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 4] = [
        // 2.2 mm matrix pitch: 2 mm tops grow 2.28 mm bases after 204 um of etching.
        (
            &[
                "geometry.teeth.pattern=matrix",
                "geometry.teeth.pitch_x_um=2200",
                "geometry.teeth.pitch_y_um=2200",
            ],
            "TEETH_BASES_MERGE",
        ),
        // 2.05 mm cells leave 25 um from the outer tooth to the die edge; compensators reach 358
        // um.
        (
            &[
                "geometry.teeth.pitch_x_um=2050",
                "geometry.teeth.pitch_y_um=2050",
            ],
            "COMPENSATOR_OUTSIDE_DIE",
        ),
        // Islands 300 um apart with a 400 um minimum.
        (
            &[
                "geometry.electrodes.gap_um=300",
                "drc.min_electrode_gap_um=400",
            ],
            "ELECTRODE_GAP",
        ),
        // 8 um label pixels are below the 10 um minimum width.
        (&["layout.label_pixel_um=8"], "MIN_WIDTH"),
    ];
    for (k, (sets, code)) in cases.iter().enumerate() {
        let mut args = Vec::new();
        for s in sets.iter() {
            args.extend(["--set", *s]);
        }
        let (exit, stdout, stderr) = generate(&t.path().join(format!("c{k}")), &args, &[]);
        assert_eq!(exit, 1, "{sets:?}\n{stdout}\n{stderr}");
        assert!(
            stdout.contains(&format!("  {code}: ")),
            "{code} not reported for {sets:?}:\n{stdout}"
        );
    }
}

/// Labels obey the rules of the layer they are drawn on: a shape on the PVDF mask that is not an
/// electrode (a label pixel) closer to an island than the electrode gap is an ELECTRODE_GAP
/// violation at its place, and the bundled set (whose label found no room) passes.
#[test]
fn pvdf_labels_keep_the_electrode_gap() {
    use tactfab::layout::LayerKind;
    let p = tactfab::process::load_str(
        include_str!("../../process/mis-grasper.yaml"),
        "mis-grasper.yaml",
        &[],
    )
    .expect("valid process")
    .process;
    let mut d = tactfab::design::Design::new(p).expect("design");
    let clean = tactfab::drc::check(&d.masks, &d.process, &d.plan);
    assert!(clean.passed(), "{}", clean.summary(5));
    let min = d.process.drc.min_electrode_gap_um;
    let e = d.masks.electrodes[0].clone();
    let b = geo::BoundingRect::bounding_rect(&e.polygon).unwrap();
    // A 20 um label pixel half the gap to the right of the first island.
    let x = b.max().x + 0.5 * min;
    let y = 0.5 * (b.min().y + b.max().y);
    let pixel = geo::Polygon::new(
        geo::LineString::from(vec![
            (x, y),
            (x + 20.0, y),
            (x + 20.0, y + 20.0),
            (x, y + 20.0),
        ]),
        vec![],
    );
    let die = d.masks.die_cell.clone();
    d.masks
        .cells
        .get_mut(&die)
        .unwrap()
        .add(LayerKind::Pvdf, [pixel]);
    let r = tactfab::drc::check(&d.masks, &d.process, &d.plan);
    let hit: Vec<_> = r
        .violations
        .iter()
        .filter(|v| v.code.as_str() == "ELECTRODE_GAP" && v.message.contains(&e.name))
        .collect();
    assert_eq!(hit.len(), 1, "{}", r.summary(5));
    assert!(
        hit[0].message.contains("not an electrode"),
        "{}",
        hit[0].message
    );
    assert!(!r.passed());
}

#[test]
fn electrodes_sit_on_the_etched_back_and_the_rule_fires_when_they_do_not() {
    // Bundled design: each support/middle gap is centred on the etched {111} wall, so a middle
    // island keeps the same margin to the wall's foot as its support island to the wall's top.
    let loaded = tactfab::process::load(&root().join(PROCESS), &[]).unwrap();
    let design = tactfab::design::Design::new(loaded.process).unwrap();
    let plan = &design.plan;
    let [f0, f1] = plan.channel_floor_y_um;
    let foot = plan.channel_wall_y_um[0];
    // Independent of the layout code: run-out h / sqrt 2 (tan 54.74 deg = sqrt 2) less undercut.
    let undercut = plan.steps[0].undercut_um;
    assert!((f0 - (2500.0 - undercut + plan.back_depth_um / 2f64.sqrt())).abs() < 1e-9);
    assert!((f1 - (15_000.0 - f0)).abs() < 1e-9 && (foot - (2500.0 - undercut)).abs() < 1e-9);
    let geo = tactfab::sensor::SensorGeometry::new(&design);
    assert_eq!(
        (geo.plate_y0_um, geo.plate_y1_um),
        (f0, f1),
        "clamped at the walls' feet"
    );
    let min = design.process.drc.min_wall_margin_um;
    for e in &geo.electrodes {
        let margin = match e.side {
            tactfab::sensor::ElectrodeSide::Middle => (e.y0_um - f0).min(f1 - e.y1_um),
            tactfab::sensor::ElectrodeSide::Support1 => foot - e.y1_um,
            tactfab::sensor::ElectrodeSide::Support2 => e.y0_um - (15_000.0 - foot),
        };
        let want = (design.process.geometry.electrodes.gap_um - (f0 - foot)) / 2.0;
        // Within the 1 nm grid the edges are snapped to.
        assert!(
            (margin - want).abs() < 1e-3 && margin >= min,
            "{}: {margin} vs {want}",
            e.name
        );
    }
    // A 250 um gap leaves (250 - 144.2 + 8.3) / 2 = 57 um on either side of the wall: all nine
    // islands violate the 100 um margin; a 50 um margin releases them.
    let t = tempfile::tempdir().unwrap();
    let narrow = ["--set", "geometry.electrodes.gap_um=250"];
    let (code, stdout, _) = generate(&t.path().join("a"), &narrow, &[]);
    assert_eq!(code, 1, "{stdout}");
    assert_eq!(
        stdout.matches("    ELECTRODE_NEAR_WALL [pvdf]").count(),
        9,
        "{stdout}"
    );
    let mut relaxed = narrow.to_vec();
    relaxed.extend(["--set", "drc.min_wall_margin_um=50"]);
    let (code, stdout, _) = generate(&t.path().join("b"), &relaxed, &[]);
    assert_eq!(code, 0, "{stdout}");
}

/// The test die read back through KLayout: one placement in the wafer, seven teeth on the front
/// layer whose island areas give a = h / 0.544 -/+ 150 um in 50 um steps (computed here from the
/// file's numbers, not from the layout code), their labels, and DRC clean.
#[test]
fn klayout_finds_the_test_die_ladder() {
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("m");
    let (code, stdout, stderr) = generate(&out, &[], &[]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(
        stdout.contains("test die: MIS_GRASPER_TEST_DIE"),
        "{stdout}"
    );
    let loaded = tactfab::process::load(&root().join(PROCESS), &[]).unwrap();
    let p = &loaded.process;
    let centre = 200.0 / 0.544;
    let expected: Vec<f64> = (-3..=3).map(|k| centre + 50.0 * f64::from(k)).collect();
    let expected_text = format!("{expected:?}");
    let script = format!(
        r#"
import sys, math, klayout.db as db
ly = db.Layout(); ly.read(sys.argv[1])
top = ly.top_cell()
td = ly.cell("MIS_GRASPER_TEST_DIE")
assert td is not None, "no test die cell"
refs = [i for i in top.each_inst() if i.cell_index == td.cell_index()]
assert len(refs) == 1, "placed %d times" % len(refs)
li = ly.find_layer(1, 0)
top_um, ov = {top}, {ov}
region = db.Region(td.begin_shapes_rec(li))
a = []
for poly in region.merged().each():
    area = poly.area() * ly.dbu ** 2
    if area > top_um ** 2:
        a.append((poly.bbox().left, math.sqrt((area - top_um ** 2) / 4 + ov ** 2)))
a = [v for _, v in sorted(a)]
exp = {exp}
assert len(a) == len(exp), (a, exp)
for got, want in zip(a, exp):
    assert abs(got - want) < 0.01, (got, want)
texts = [s.text.string for s in td.each_shape(ly.find_layer(63, 0)) if s.is_text()]
for want in exp:
    assert ("A=%.1f UM" % want) in texts, (want, texts)
print("TEST DIE OK", ["%.1f" % v for v in a])
"#,
        top = p.geometry.teeth.top_um,
        ov = p.layout.compensation_overlap_um,
        exp = expected_text,
    );
    let py = std::process::Command::new("python3")
        .arg("-c")
        .arg(&script)
        .arg(out.join("mis-grasper.gds"))
        .output()
        .expect("python3 runs");
    let (so, se) = (
        String::from_utf8_lossy(&py.stdout),
        String::from_utf8_lossy(&py.stderr),
    );
    assert!(py.status.success(), "{so}\n{se}");
    assert!(so.contains("TEST DIE OK"), "{so}");
    assert!(stdout.contains("DRC passed"), "{stdout}");
}

/// Switched off, the masks are those of a file without the section, byte for byte; bad ladders
/// are exit 2 naming the field.
#[test]
fn test_die_switch_and_bad_values() {
    let t = tempfile::tempdir().unwrap();
    let (off, plain) = (t.path().join("off"), t.path().join("plain"));
    let (code, o, e) = generate(&off, &["--set", "layout.test_die.enabled=false"], &[]);
    assert_eq!(code, 0, "{o}\n{e}");
    let text = std::fs::read_to_string(root().join(PROCESS)).unwrap();
    let start = text.find("\nlayout:\n").expect("layout section");
    let end = start + 1 + text[start + 1..].find("\nchecks:").unwrap();
    let without = format!("{}{}", &text[..start], &text[end..]);
    assert!(!without.contains("test_die"));
    let file = t.path().join("mis-grasper.yaml");
    std::fs::write(&file, without).unwrap();
    let (code, o, e) = run(&[
        "masks",
        file.to_str().unwrap(),
        "-o",
        plain.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{o}\n{e}");
    let (a, b) = (read_all(&off), read_all(&plain));
    for (name, bytes) in &a {
        // The manifest names the process file's hash, which differs.
        if name != "tactfab.sha256" {
            assert!(b[name] == *bytes, "{name} differs with the test die off");
        }
    }
    for (set, field) in [
        ("layout.test_die.step_um=0", "layout.test_die.step_um"),
        ("layout.test_die.step_um=10", "layout.test_die.step_um"),
        ("layout.test_die.span_um=-1", "layout.test_die.span_um"),
        (
            "layout.test_die.centre_a_um=100",
            "layout.test_die.centre_a_um",
        ),
        (
            "layout.test_die.centre_a_um=-5",
            "layout.test_die.centre_a_um",
        ),
        ("layout.test_die.colour=red", "layout.test_die"),
    ] {
        let d = t.path().join("bad");
        let (code, o, e) = generate(&d, &["--set", set], &[]);
        assert_eq!(code, 2, "{set}: {o}\n{e}");
        assert!(e.contains(field), "{set}: {e}");
        assert!(!d.exists(), "{set}: exit 2 writes nothing");
    }
}
