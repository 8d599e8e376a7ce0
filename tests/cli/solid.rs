//! The solid rung: what is meshed is what is etched (volumes in closed form), equilibrium,
//! mirror symmetry, linearity, and `fe --model solid` through the binary.

use tactfab::process::{Limits, Scene, SceneLoad};
use tactfab::sensor::solid::{evaluate_solid, top_loads, SolidGrading, SolidRun};
use tactfab::sensor::solid_mesh::{
    build, Base, SensorSolid, SolidMeshOptions, BASE, PVDF, SILICON,
};

use super::harness::{run_env, tactfab};
use super::sensor::geometry;

/// A 12 mm die with four columns of teeth (the bundled scenes moved onto it): cheap to solve
/// whole.
const SHORT: [&str; 4] = [
    "geometry.die_length_um=12000",
    "geometry.teeth.count_x=4",
    "checks.scenes[0].load.point.x_um=6000",
    "checks.scenes[1].load.point.x_um=6000",
];

/// A 6 x 9 mm die with two columns and three rows of teeth (the point scenes at its centre, the
/// half model's mirror through the middle row): a level of it solves in about a sixth of the
/// short die's time (16 s against 95 s for the centre load through the binary, 2026-12-02), for
/// the tests that check what the binary says rather than numbers of the bundled design.
const TINY: [&str; 8] = [
    "geometry.die_length_um=6000",
    "geometry.teeth.count_x=2",
    "geometry.die_width_um=9000",
    "geometry.teeth.count_y=3",
    "checks.scenes[0].load.point.x_um=3000",
    "checks.scenes[1].load.point.x_um=3000",
    "checks.scenes[0].load.point.y_um=4500",
    "checks.scenes[1].load.point.y_um=4500",
];

/// `fe` with the solid rung on `levels` levels of the tiny test die, then `rest`.
fn tiny_levels<'a>(levels: &'a str, rest: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "fe",
        "process/mis-grasper.yaml",
        "--model",
        "solid",
        "--max-levels",
        levels,
    ];
    args.extend_from_slice(rest);
    with_sets(&args, &TINY)
}

/// `build --verify-solid FLAGS` on one level of the tiny die's geometry with `scenes` (a
/// `checks.scenes=...` set), unconverged allowed.
fn tiny_verify_build<'a>(out: &'a str, flags: &[&'a str], scenes: &'a str) -> Vec<&'a str> {
    let mut args = vec![
        "build",
        "process/mis-grasper.yaml",
        "-o",
        out,
        "--verify-solid",
    ];
    args.extend_from_slice(flags);
    args.extend(["--max-levels", "1", "--allow-unconverged"]);
    let mut sets = TINY[..4].to_vec();
    sets.push(scenes);
    with_sets(&args, &sets)
}

/// [`tiny_levels`] on one level.
fn tiny_one_level<'a>(rest: &[&'a str]) -> Vec<&'a str> {
    tiny_levels("1", rest)
}

/// `args` followed by a `--set` of each of `sets`.
fn with_sets<'a>(args: &[&'a str], sets: &[&'a str]) -> Vec<&'a str> {
    let mut out = args.to_vec();
    for s in sets {
        out.extend(["--set", s]);
    }
    out
}

/// `args` followed by the `--set`s that make the short test die.
fn on_short_die<'a>(args: &[&'a str]) -> Vec<&'a str> {
    with_sets(args, &SHORT)
}

fn point(x_um: f64, y_um: f64, force_n: f64) -> Scene {
    Scene {
        name: "p".into(),
        load: SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um: 500.0,
        },
        limits: Limits::default(),
    }
}

/// The tooth whose top's centre is nearest (x, y) um (the hot tooth of a load there).
fn tooth_nearest(g: &tactfab::sensor::SensorGeometry, x_um: f64, y_um: f64) -> usize {
    let d = |i: usize| {
        let t = g.etched.tooth_tops_um[i];
        (0.5 * (t[0] + t[2]) - x_um).hypot(0.5 * (t[1] + t[3]) - y_um)
    };
    (0..g.etched.tooth_tops_um.len())
        .min_by(|&a, &b| d(a).total_cmp(&d(b)))
        .expect("the design has teeth")
}

fn run(levels: usize, symmetry: bool) -> SolidRun {
    SolidRun {
        base: Base::Rigid,
        levels,
        tol: 0.01,
        symmetry,
        nonlinear: false,
        graded: false,
        tied_shear: true,
        grading: SolidGrading::Lines,
    }
}

#[test]
fn the_meshed_silicon_is_the_etched_silicon() {
    // Whole die, Plexiglas base, coarse mesh: the mapped {111} faces are exact, so the volumes
    // are the etched shape's in closed form at any mesh size.
    let g = geometry(&[]);
    let base = g.base;
    let Base::Elastic { thickness_um, .. } = base else {
        panic!("the bundled base is Plexiglas")
    };
    let s = build(
        &g,
        &[],
        base,
        SolidMeshOptions::level(2000.0, 0),
        &[],
        None,
        None,
    )
    .unwrap();
    let v = s.material_volumes_um3();
    let (l, w, t) = (g.length_um, g.width_um, g.plate_thickness_um);
    let e = &g.etched;
    let (a, ro, h) = (2000.0, e.tooth_run_out_um, e.tooth_height_um);
    assert_eq!(e.tooth_tops_um.len(), 25);
    // Frustum of a square pyramid: V = h/3 (A1 + A2 + sqrt(A1 A2)).
    let (a1, a2) = (a * a, (a + 2.0 * ro).powi(2));
    let frustum = h / 3.0 * (a1 + a2 + (a1 * a2).sqrt());
    // Each support: trapezoid from its footprint edge e to the wall's foot y0, height d.
    let (d, f) = (e.support_height_um, g.film_thickness_um);
    let (e1, y0) = (e.support_edge_y_um, g.plate_y0_um);
    let supports = 2.0 * l * d * 0.5 * (e1 + y0);
    let silicon = l * w * t + 25.0 * frustum + supports;
    assert!(
        ((v[usize::from(SILICON)] - silicon) / silicon).abs() < 1e-9,
        "{} vs {silicon}",
        v[usize::from(SILICON)]
    );
    // Films: under both supports' footprints, and under the plate between the walls over the
    // film's height (the wall at height z is at e1 + (y0 - e1)(z - f)/d).
    let wall_integral = e1 * f + (y0 - e1) / d * (d * d - (d - f) * (d - f)) / 2.0;
    let films = 2.0 * l * e1 * f + l * (w * f - 2.0 * wall_integral);
    assert!(
        ((v[usize::from(PVDF)] - films) / films).abs() < 1e-9,
        "{} vs {films}",
        v[1]
    );
    let base_v = l * w * thickness_um;
    assert!(((v[usize::from(BASE)] - base_v) / base_v).abs() < 1e-12);
}

#[test]
fn supports_carry_the_load_and_each_scales_with_it() {
    // An off-centre load on the tiny die (two columns of teeth): equilibrium through the
    // films, the nearer support carrying more, and twice the force twice every reading.
    let g = geometry(&TINY);
    let one = evaluate_solid(&g, &point(2000.0, 4000.0, 1.0), run(1, true), &[], &[]).unwrap();
    let two = evaluate_solid(&g, &point(2000.0, 4000.0, 2.0), run(1, true), &[], &[]).unwrap();
    let r1 = &one.levels[0].readout;
    let r2 = &two.levels[0].readout;
    assert!((r1.support1_n + r1.support2_n - 1.0).abs() < 1e-9, "{r1:?}");
    assert!(r1.support1_n > 0.6 && r1.support2_n < 0.4, "{r1:?}");
    for (a, b) in r1.charge_pc.iter().zip(&r2.charge_pc) {
        assert!((2.0 * a - b).abs() <= 1e-9 * b.abs().max(1e-3), "{a} {b}");
    }
    assert!((2.0 * r1.deflection_at_load_um - r2.deflection_at_load_um).abs() < 1e-9);
    // The sharp edges' stresses too (the corner submodels are linear in their driver).
    assert_eq!(r1.edge_stress.len(), 3, "{:?}", r1.edge_stress);
    for (a, b) in r1.edge_stress.iter().zip(&r2.edge_stress) {
        assert_eq!((a.kind, a.at_um), (b.kind, b.at_um));
        assert!(
            (2.0 * a.stress_mpa - b.stress_mpa).abs() <= 1e-9 * b.stress_mpa,
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn edge_stress_follows_the_wedge_singularity_with_the_critical_distance() {
    // Four times the critical distance (twice K_Ic): the stress falls as r^(lambda - 1), lambda
    // = 0.634 for an isotropic wedge of 234.74 deg (lambda sin 2a + sin 2 lambda a = 0, Williams
    // 1952): 4^-0.366 = 0.602; silicon's anisotropy and the regular part of the field move it
    // by a few per cent. Both kinds are tensile somewhere along their edges and resolved by
    // their submodels to better than 1 %.
    let g = geometry(&TINY);
    let tough = geometry(
        &[
            TINY.as_slice(),
            &["materials.silicon.fracture_toughness_mpa_sqrt_m=1.44"],
        ]
        .concat(),
    );
    let scene = point(2000.0, 4000.0, 1.0);
    let a = evaluate_solid(&g, &scene, run(1, true), &[], &[]).unwrap();
    let b = evaluate_solid(&tough, &scene, run(1, true), &[], &[]).unwrap();
    let (ra, rb) = (&a.levels[0].readout, &b.levels[0].readout);
    for (x, y) in ra.edge_stress.iter().zip(&rb.edge_stress) {
        assert_eq!(x.kind, y.kind);
        assert!((y.read_at_um / x.read_at_um - 4.0).abs() < 1e-12);
        let ratio = y.stress_mpa / x.stress_mpa;
        assert!((ratio - 0.602).abs() < 0.03, "{:?}: {ratio}", x.kind);
        assert!(x.submodel_error_mpa < 0.01 * x.stress_mpa.abs(), "{x:?}");
    }
    // The peak a Gauss point of the solid sees lies far below the stress at L / 2.
    let worst = ra
        .edge_stress
        .iter()
        .map(|e| e.stress_mpa)
        .fold(0.0, f64::max);
    assert!(
        worst > 3.0 * ra.max_principal_mpa,
        "{worst} {}",
        ra.max_principal_mpa
    );
}

#[test]
fn a_graded_tooth_beyond_the_mirror_grades_its_image() {
    // The plate may name a tooth outside the part the solid solves: its mirror image in that
    // part gets the lines, so either tooth of a mirrored pair grades the same mesh.
    let g = geometry(&[]);
    let w = g.width_um;
    let tops = &g.etched.tooth_tops_um;
    let (i, j) = (0..tops.len())
        .find_map(|i| {
            let t = tops[i];
            (t[3] < 0.5 * w)
                .then(|| {
                    tops.iter().position(|u| {
                        (u[0] - t[0]).abs() < 1e-6 && (u[1] - (w - t[3])).abs() < 1e-6
                    })
                })
                .flatten()
                .map(|j| (i, j))
        })
        .expect("a mirrored pair of teeth");
    let lines = |teeth: &[usize]| {
        let s = build(
            &g,
            &[],
            Base::Rigid,
            SolidMeshOptions::level(2000.0, 0),
            teeth,
            None,
            Some(0.5 * w),
        )
        .unwrap();
        let [x, y, _] = s.problem.grid.lines_um();
        (x.to_vec(), y.to_vec())
    };
    let (below, above, none) = (lines(&[i]), lines(&[j]), lines(&[]));
    assert_eq!(below.0.len(), above.0.len());
    assert_eq!(below.1.len(), above.1.len());
    for (a, b) in below.1.iter().zip(&above.1) {
        assert!((a - b).abs() < 1e-6, "{a} {b}");
    }
    assert!(below.1.len() > none.1.len() && below.0.len() > none.0.len());
}

#[test]
fn the_graded_solid_adds_lines_at_the_tooth_bases_and_only_softens() {
    // `--graded` adds grid lines round every tooth base edge: the graded mesh's space holds the
    // uniform one's (the lines split elements where the map is linear), so the conforming
    // solution can only grow more compliant: the deflection under the load rises, and both
    // balance the load.
    let g = geometry(&TINY);
    let solve = |graded: bool, teeth: &[usize]| {
        evaluate_solid(
            &g,
            &point(3000.0, 4500.0, 0.02),
            SolidRun {
                graded,
                ..run(1, true)
            },
            &[],
            teeth,
        )
        .unwrap()
    };
    let (uniform, graded) = (solve(false, &[]), solve(true, &[]));
    assert!(!uniform.graded && graded.graded);
    assert_eq!(
        (uniform.graded_teeth, graded.graded_teeth),
        (0, g.etched.tooth_tops_um.len())
    );
    let (u, v) = (&uniform.levels[0], &graded.levels[0]);
    assert!(v.dofs > 2 * u.dofs, "{} {}", u.dofs, v.dofs);
    let (wu, wv) = (
        u.readout.deflection_at_load_um,
        v.readout.deflection_at_load_um,
    );
    assert!(wv > wu * (1.0 + 1e-3), "{wu} {wv}");
    // One tooth graded (the one nearest the load, as the plate's hot teeth are): its lines only,
    // between the two in dofs and in deflection (the spaces nest).
    let near = tooth_nearest(&g, 3000.0, 4500.0);
    let one = solve(false, &[near]);
    assert!(!one.graded && one.graded_teeth == 1);
    let o = &one.levels[0];
    assert!(
        u.dofs < o.dofs && o.dofs < v.dofs,
        "{} {} {}",
        u.dofs,
        o.dofs,
        v.dofs
    );
    let wo = o.readout.deflection_at_load_um;
    assert!(wu < wo && wo < wv, "{wu} {wo} {wv}");
    for r in [&u.readout, &o.readout, &v.readout] {
        let total = r.support1_n + r.support2_n;
        assert!((total - 0.02).abs() < 1e-9 * 0.02, "{total}");
    }
    // Through the binary: `--graded` reaches the solid, which says so (the JSON's `graded`:
    // `build_verify_solid_graded_reaches_the_solid_rung`).
    let out = tactfab(&tiny_one_level(&["--point", "3,4.5,0.02,0.5", "--graded"]));
    out.expect_code(0);
    assert!(
        out.stdout.contains("graded at the tooth base edges")
            && !out.stdout.contains("can miss the worst tooth base"),
        "{}",
        out.stdout
    );
}

#[test]
fn the_levels_cells_are_finer_across_the_span() {
    // The plate bends across its span (README, "Finer across the span"): a level's cells in y
    // between the channel walls are at most half its in-plane size, elsewhere at most the size;
    // the extra lines all lie in the span, x is as before, and what is meshed is still what is
    // etched.
    let g = geometry(&SHORT);
    let opts = SolidMeshOptions::level(1000.0, 0);
    assert_eq!(opts.span_element_um, 0.5 * opts.element_um);
    let mesh = |o: SolidMeshOptions| build(&g, &[], g.base, o, &[], None, None).unwrap();
    let (fine, even) = (
        mesh(opts.clone()),
        mesh(SolidMeshOptions {
            span_element_um: opts.element_um,
            ..opts.clone()
        }),
    );
    let lines = |s: &SensorSolid, axis: usize| s.problem.grid.lines_um()[axis].to_vec();
    let (y0, y1) = (g.plate_y0_um, g.plate_y1_um);
    let tol = 1e-6;
    let widest = |ys: &[f64], inside: bool| {
        ys.windows(2)
            .filter(|w| (w[0] >= y0 - tol && w[1] <= y1 + tol) == inside)
            .map(|w| w[1] - w[0])
            .fold(0.0, f64::max)
    };
    let (yf, ye) = (lines(&fine, 1), lines(&even, 1));
    assert!(widest(&yf, true) <= 500.0 + tol, "{}", widest(&yf, true));
    assert!(widest(&ye, true) > 500.0 + tol, "{}", widest(&ye, true));
    assert!(widest(&yf, false) <= 1000.0 + tol);
    assert_eq!(widest(&yf, false), widest(&ye, false));
    let extra: Vec<f64> = yf
        .iter()
        .copied()
        .filter(|y| !ye.iter().any(|e| (e - y).abs() < tol))
        .collect();
    assert!(!extra.is_empty());
    assert!(
        extra.iter().all(|&y| y > y0 && y < y1),
        "{extra:?} outside {y0}..{y1}"
    );
    assert_eq!(lines(&fine, 0), lines(&even, 0));
    for (a, b) in fine
        .material_volumes_um3()
        .iter()
        .zip(even.material_volumes_um3())
    {
        assert!(((a - b) / a).abs() < 1e-9, "{a} {b}");
    }
}

#[test]
fn local_refinement_grades_the_hot_tooth_and_merges_back_elsewhere() {
    // Local grading: the cells beside the hot tooth's base edges (and the channel walls) are
    // bisected toward them and merge back into the uniform cells away from the tooth (hanging
    // nodes between). Its space holds the uniform mesh's, so the deflection under the load only
    // rises; it costs fewer dofs than the same tooth graded by lines across the die; what is
    // meshed is still what is etched; the supports carry the load. Auto (the default) solves
    // the one whose factor is smaller, exactly as that grading asked for by name. Uniform grades
    // no tooth, the hot one given or not.
    let g = geometry(&TINY);
    let near = tooth_nearest(&g, 3000.0, 4500.0);
    let solve = |grading: SolidGrading, teeth: &[usize]| {
        evaluate_solid(
            &g,
            &point(3000.0, 4500.0, 0.02),
            SolidRun {
                grading,
                ..run(1, true)
            },
            &[],
            teeth,
        )
        .unwrap()
    };
    let (uniform, lines, local, auto) = (
        solve(SolidGrading::Uniform, &[near]),
        solve(SolidGrading::Lines, &[near]),
        solve(SolidGrading::Local, &[near]),
        solve(SolidGrading::Auto, &[near]),
    );
    assert!(local.local_refinement && !lines.local_refinement && !uniform.local_refinement);
    assert_eq!(uniform.graded_teeth, 0);
    assert!(local.grading_choice.is_none() && lines.grading_choice.is_none());
    let choice = auto.grading_choice.expect("auto reports its choice");
    assert!(choice.refused.is_none(), "{choice:?}");
    assert_eq!(
        choice.local_factor_entries,
        Some(local.levels[0].factor_entries)
    );
    assert_eq!(
        choice.lines_factor_entries,
        Some(lines.levels[0].factor_entries)
    );
    let chosen = if choice.local_factor_entries < choice.lines_factor_entries {
        &local
    } else {
        &lines
    };
    assert_eq!(auto.local_refinement, chosen.local_refinement);
    assert_eq!(auto.levels[0].readout, chosen.levels[0].readout);
    let (u, l, o) = (&uniform.levels[0], &lines.levels[0], &local.levels[0]);
    assert!(
        u.dofs < o.dofs && o.dofs < l.dofs,
        "{} {} {}",
        u.dofs,
        o.dofs,
        l.dofs
    );
    let (wu, wo) = (
        u.readout.deflection_at_load_um,
        o.readout.deflection_at_load_um,
    );
    assert!(wo > wu * (1.0 + 1e-4), "{wu} {wo}");
    let total = o.readout.support1_n + o.readout.support2_n;
    assert!((total - 0.02).abs() < 1e-9 * 0.02, "{total}");
    // The merged grid's materials are the etched shape's, as the tensor grid's.
    let opts = SolidMeshOptions::level(1000.0, 0);
    let mesh = |local_refinement: bool| {
        build(
            &g,
            &[],
            g.base,
            SolidMeshOptions {
                local_refinement,
                ..opts.clone()
            },
            &[near],
            None,
            None,
        )
        .unwrap()
    };
    let (tensor, merged) = (mesh(false), mesh(true));
    assert!(merged.problem.grid.has_merged() && !tensor.problem.grid.has_merged());
    // The channel walls (re-entrant along the whole die) are graded too: a cell of at most half
    // a plate thickness either side of each wall line (the uniform mesh may have one by chance:
    // row 0's tooth edges run a few um from the wall).
    let t = g.plate_thickness_um;
    let beside = |s: &SensorSolid, wall: f64, side: f64| {
        s.problem.grid.lines_um()[1].iter().any(|&y| {
            let d = side * (y - wall);
            d > 1e-6 && d <= 0.5 * t + 1e-6
        })
    };
    for wall in [g.plate_y0_um, g.plate_y1_um] {
        for side in [-1.0, 1.0] {
            assert!(beside(&merged, wall, side), "{wall} {side}");
        }
    }
    for (a, b) in tensor
        .material_volumes_um3()
        .iter()
        .zip(merged.material_volumes_um3())
    {
        assert!(((a - b) / a).abs() < 1e-9, "{a} {b}");
    }
    // Through the binary: the summary says so; without the solid `--solid-grading` is a usage
    // error naming the flag.
    let out = tactfab(&tiny_one_level(&[
        "--point",
        "3,4.5,0.02,0.5",
        "--solid-grading",
        "local",
    ]));
    out.expect_code(0);
    assert!(
        out.stdout.contains("(locally: hanging nodes)")
            && out.stdout.contains("(h 1000 um, 500 across the span,"),
        "{}",
        out.stdout
    );
    let out = tactfab(&on_short_die(&[
        "fe",
        "process/mis-grasper.yaml",
        "--solid-grading",
        "lines",
    ]));
    out.expect_code(2);
    assert!(out.stderr.contains("--solid-grading"), "{}", out.stderr);
}

#[test]
fn tied_shear_unlocks_the_plate_bricks_and_keeps_equilibrium() {
    // The plain 27-node bricks lock in the 100 um plate on elements of several thicknesses
    // (unit test `tied_shear_does_not_lock_a_thin_strip`: -3.7 % at 10 t): tying the transverse
    // shears makes the same mesh more compliant under the load (on the bundled design's centre
    // load, level 2: 0.6495 against 0.6434 um, the graded reference about 0.650), with the same
    // dofs, and both balance the load.
    let g = geometry(&TINY);
    let solve = |tied_shear: bool| {
        evaluate_solid(
            &g,
            &point(3000.0, 4500.0, 0.02),
            SolidRun {
                tied_shear,
                ..run(1, true)
            },
            &[],
            &[],
        )
        .unwrap()
    };
    let (plain, tied) = (solve(false), solve(true));
    assert!(!plain.tied_shear && tied.tied_shear);
    let (p, t) = (&plain.levels[0], &tied.levels[0]);
    assert_eq!(p.dofs, t.dofs);
    let (wp, wt) = (
        p.readout.deflection_at_load_um,
        t.readout.deflection_at_load_um,
    );
    assert!(wt > wp * (1.0 + 2e-3), "plain {wp}, tied {wt}");
    for r in [&p.readout, &t.readout] {
        let total = r.support1_n + r.support2_n;
        assert!((total - 0.02).abs() < 1e-9 * 0.02, "{total}");
    }
    // Through the binary: `--plain-shear` unties, and the text says so (tied by default, as the
    // JSON of `solid_levels_sets_the_solid_rungs_levels` says); without the solid rung
    // `--plain-shear` is a usage error.
    // (Uniform levels on the tiny die: the subject is the shear, not the numbers.)
    let out = tactfab(&tiny_one_level(&[
        "--point",
        "3,4.5,0.02,0.5",
        "--plain-shear",
        "--solid-grading",
        "uniform",
    ]));
    out.expect_code(0);
    assert!(
        out.stdout.contains("plain bricks (--plain-shear)")
            && !out.stdout.contains("transverse shear tied"),
        "{}",
        out.stdout
    );
    let out = tactfab(&["fe", "process/mis-grasper.yaml", "--plain-shear"]);
    out.expect_code(2);
    assert!(
        out.stderr
            .contains("--plain-shear applies to the solid rung"),
        "{}",
        out.stderr
    );
}

#[test]
fn the_nonlinear_solid_stiffens_and_keeps_equilibrium_in_the_deformed_state() {
    // A quarter of a short matrix die, centre load. At 4 N the plate deflects most of its own
    // thickness: membrane action stiffens it (less deflection than the linear solid) and the
    // films still carry the load exactly (nominal stresses through the reference section). At
    // 10 mN the two models agree to the square of the load's effect (w/t ~ 0.01).
    let mut sets = SHORT.to_vec();
    sets.push("geometry.teeth.pattern=matrix");
    let g = geometry(&sets);
    let nl = |f: f64, nonlinear: bool| {
        let r = evaluate_solid(
            &g,
            &point(6000.0, 7500.0, f),
            SolidRun {
                nonlinear,
                ..run(1, true)
            },
            &[],
            &[],
        )
        .unwrap();
        assert_eq!(r.nonlinear, nonlinear);
        let l = &r.levels[0];
        assert_eq!(l.newton_iterations.is_some(), nonlinear);
        assert_eq!(l.factorisations.is_some(), nonlinear);
        if let (Some(its), Some(fac)) = (l.newton_iterations, l.factorisations) {
            eprintln!(
                "{f} N: {its} Newton iterations, {fac} factorisations, {} dofs",
                l.dofs
            );
            assert!(fac >= 1 && fac <= its, "{its} {fac}");
        }
        r.levels[0].readout.clone()
    };
    let (lin, tl) = (nl(4.0, false), nl(4.0, true));
    // To Newton's residual tolerance (1e-10 of the force scale at each dof), not round-off.
    assert!(
        (tl.support1_n + tl.support2_n - 4.0).abs() < 1e-9 * 4.0,
        "{tl:?}"
    );
    let t = g.plate_thickness_um;
    assert!(lin.deflection_at_load_um > 0.5 * t, "{lin:?}");
    let stiffening = tl.deflection_at_load_um / lin.deflection_at_load_um;
    assert!(stiffening > 0.5 && stiffening < 0.98, "{stiffening}");
    let (lin, tl) = (nl(0.01, false), nl(0.01, true));
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(
        rel(tl.deflection_at_load_um, lin.deflection_at_load_um) < 1e-3,
        "{tl:?} {lin:?}"
    );
    let m2 = 4;
    assert!(
        rel(tl.charge_pc[m2], lin.charge_pc[m2]) < 2e-3,
        "{tl:?} {lin:?}"
    );
}

/// A channel wall that lands within the line gap of a tooth row's base edge (the supports 8 um
/// wider: the wall 0.33 um below row 0's edge on the plate) merges the two lines, so the
/// meshed edge stands off the drawn one. The submodels, placed on the drawn corner, read the
/// solid within the grid's tolerance (until 2026-12-01 the run stopped, exit 2: "the corner
/// submodel reads the solid at ... outside it"), and what they read lies between the designs
/// with the wall 4 um either side, whose lines do not merge.
#[test]
fn a_wall_a_fraction_of_a_micron_from_a_tooth_edge_is_read() {
    use tactfab::sensor::edge_stress::EdgeKind;
    let design = |width: &str| {
        let set = format!("geometry.support_width_um={width}");
        geometry(&[&SHORT[..], &[set.as_str()]].concat())
    };
    let near = design("2508");
    let ro = near.etched.tooth_run_out_um;
    let edge = near
        .etched
        .tooth_tops_um
        .iter()
        .map(|t| t[3] + ro)
        .find(|y| (y - near.plate_y0_um).abs() < 1.0)
        .expect("a tooth edge within a micron of the wall");
    let s = build(
        &near,
        &[],
        Base::Rigid,
        SolidMeshOptions::level(1000.0, 0),
        &[],
        None,
        Some(7500.0),
    )
    .unwrap();
    let ys = s.problem.grid.lines_um()[1];
    let on = |v: f64| ys.iter().any(|y| (y - v).abs() < 1e-6);
    assert!(
        on(near.plate_y0_um) && !on(edge),
        "{edge} {}",
        near.plate_y0_um
    );
    assert!((edge - near.plate_y0_um).abs() < s.problem.grid.tolerance_um());
    assert!((s.edge_moved_um - (edge - near.plate_y0_um)).abs() < 1e-9);
    // The centre load's most loaded tooth base section is on that edge.
    let scene = point(6000.0, 7500.0, 1.0);
    // Each design's edge stresses, and how far its level's feature lines moved (the JSON's
    // `edge_moved_um`): only the merged design's did.
    let read = |g: &tactfab::sensor::SensorGeometry, moved_um: f64| {
        let level = evaluate_solid(g, &scene, run(1, true), &[], &[])
            .expect("read")
            .levels
            .remove(0);
        assert!((level.edge_moved_um - moved_um).abs() < 1e-9, "{moved_um}");
        level.readout.edge_stress
    };
    let at = read(&near, s.edge_moved_um);
    let (below, above) = (read(&design("2504"), 0.0), read(&design("2512"), 0.0));
    let kind = |v: &[tactfab::sensor::edge_stress::EdgeStress], k| {
        v.iter()
            .find(|e| e.kind == k)
            .cloned()
            .expect("each kind read")
    };
    let tooth = kind(&at, EdgeKind::ToothBase);
    assert!((tooth.at_um[1] - edge).abs() < 1e-6, "{tooth:?}");
    for k in [EdgeKind::ToothBase, EdgeKind::SupportEdge] {
        let (a, lo, hi) = (kind(&at, k), kind(&below, k), kind(&above, k));
        let (lo, hi) = (
            lo.stress_mpa.min(hi.stress_mpa),
            lo.stress_mpa.max(hi.stress_mpa),
        );
        assert!(
            a.stress_mpa > lo && a.stress_mpa < hi,
            "{k:?}: {a:?} not in {lo}..{hi}"
        );
    }
}

#[test]
fn edge_stress_estimate_includes_the_bricks_through_the_thickness() {
    // Three levels refine in plane only; level 0 again with twice the bricks through the plate,
    // then with eight in boxes round the readings, measures what the thickness does to the
    // edges' stresses: their values take the correction and their estimate what is left.
    let g = geometry(&TINY);
    let r = evaluate_solid(&g, &point(3000.0, 4500.0, 1.0), run(3, true), &[], &[]).unwrap();
    assert_eq!(r.edge_thickness.len(), 3, "{:?}", r.edge_thickness);
    let lambda = tactfab::fe::solid::corner::tooth_base_exponent();
    let finest = &r.levels[2].readout.edge_stress;
    let scale = finest.iter().fold(0.0f64, |m, e| m.max(e.stress_mpa.abs()));
    for c in &r.edge_thickness {
        let level0 = r.levels[0]
            .readout
            .edge_stress
            .iter()
            .find(|e| e.kind == c.kind)
            .unwrap();
        assert_eq!(c.two_bricks_mpa, level0.stress_mpa);
        let eight = c.eight_bricks_mpa.expect("the eight-brick boxes solved");
        let (d1, d2) = (
            c.four_bricks_mpa - c.two_bricks_mpa,
            eight - c.four_bricks_mpa,
        );
        let rho = d2 / d1;
        if (0.0..1.0).contains(&rho) {
            // Monotone: the value moves to the eight bricks' and what is left is the last step
            // at the observed rate or 2 lambda, whichever is slower.
            let r = rho.max(2f64.powf(-2.0 * lambda));
            assert!((c.correction_mpa - (d1 + d2)).abs() < 1e-9 * scale);
            assert!((c.error_mpa - d2.abs() * r / (1.0 - r)).abs() < 1e-9 * scale);
        } else {
            let worst = d1.abs().max((d1 + d2).abs());
            assert_eq!(c.correction_mpa, 0.0);
            assert!((c.error_mpa - worst / (1.0 - 2f64.powf(-lambda))).abs() < 1e-9 * scale);
        }
        let name = format!("{}_stress", c.kind.as_str());
        let q = r.quantities.iter().find(|q| q.name == name).unwrap();
        let at_finest = finest.iter().find(|e| e.kind == c.kind).unwrap();
        assert!((q.value - (at_finest.stress_mpa + c.correction_mpa)).abs() < 1e-9 * scale);
        let disc = q.discretisation.expect("three levels");
        assert!(disc * scale >= c.error_mpa * (1.0 - 1e-9), "{disc} {c:?}");
    }
    // A tooth's base edge: more bricks through the plate raise it (the corner's field resolved
    // closer in), as on the bundled design, and the eight bricks more again.
    let tooth = r
        .edge_thickness
        .iter()
        .find(|c| c.kind == tactfab::sensor::edge_stress::EdgeKind::ToothBase)
        .unwrap();
    assert!(tooth.four_bricks_mpa > tooth.two_bricks_mpa, "{tooth:?}");
    assert!(
        tooth.eight_bricks_mpa > Some(tooth.four_bricks_mpa),
        "{tooth:?}"
    );
    assert!(tooth.correction_mpa > 0.0, "{tooth:?}");
}

#[test]
fn mirrored_parts_read_as_the_whole_die() {
    // A matrix of teeth on the tiny die and a centre load: symmetric about both centre lines, so
    // a quarter is solved; the whole die on the same lines must read the same.
    let mut sets = TINY.to_vec();
    sets.push("geometry.teeth.pattern=matrix");
    let g = geometry(&sets);
    let scene = point(3000.0, 4500.0, 1.0);
    let quarter = evaluate_solid(&g, &scene, run(1, true), &[], &[]).unwrap();
    assert!(
        quarter.part_solved.starts_with("quarter"),
        "{}",
        quarter.part_solved
    );
    let whole = evaluate_solid(&g, &scene, run(1, false), &[], &[]).unwrap();
    assert_eq!(whole.part_solved, "whole die");
    let (q, w) = (&quarter.levels[0].readout, &whole.levels[0].readout);
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-6 * scale;
    let qmax = w.charge_pc.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (a, b) in q.charge_pc.iter().zip(&w.charge_pc) {
        assert!(
            close(*a, *b, qmax),
            "{:?} vs {:?}",
            q.charge_pc,
            w.charge_pc
        );
    }
    assert!(close(
        q.deflection_at_load_um,
        w.deflection_at_load_um,
        w.deflection_at_load_um
    ));
    assert!(close(q.support1_n, w.support1_n, 1.0) && close(q.support2_n, w.support2_n, 1.0));
    // The stress averaged under the contact, whose squares reach over both mirrors: read at the
    // images in the quarter (until 2026-11-29 NaN there, and "safety factor inf").
    assert!(
        w.stress_averaged_mpa > 0.0
            && close(
                q.stress_averaged_mpa,
                w.stress_averaged_mpa,
                w.stress_averaged_mpa
            ),
        "{} vs {}",
        q.stress_averaged_mpa,
        w.stress_averaged_mpa
    );
    // The left and right units read alike by symmetry, in the whole model too.
    assert!(close(w.charge_pc[0], w.charge_pc[2], qmax));
    // The sharp edges: the quarter's stations are the whole die's in that quarter, and the
    // worst section of each kind has the same stress (its image, or itself on a mirror plane).
    assert_eq!(q.edge_stress.len(), w.edge_stress.len());
    for (a, b) in q.edge_stress.iter().zip(&w.edge_stress) {
        assert_eq!(a.kind, b.kind);
        assert!(
            close(a.stress_mpa, b.stress_mpa, b.stress_mpa.abs()),
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn a_hot_edge_crossing_the_mirror_is_read_across_it() {
    // The tiny die: a tooth centred on the mirror y = 4.5 mm beside a centre load: its
    // base edge along y is hottest where it crosses the mirror, so the half model's corner
    // submodel there reaches beyond the part solved and reads the image. The whole die reads
    // the same. Until 2026-12-02 the half read the edge otherwise (this test failed), and `fe
    // --model solid` on this die stopped with exit 2: "the corner submodel reads the solid at
    // ... outside it".
    let g = geometry(&TINY);
    let scene = point(3000.0, 4500.0, 1.0);
    let half = evaluate_solid(&g, &scene, run(1, true), &[], &[]).unwrap();
    assert!(half.part_solved.starts_with("half"), "{}", half.part_solved);
    let whole = evaluate_solid(&g, &scene, run(1, false), &[], &[]).unwrap();
    let (h, w) = (&half.levels[0].readout, &whole.levels[0].readout);
    assert!(!w.edge_stress.is_empty());
    assert_eq!(h.edge_stress.len(), w.edge_stress.len());
    for (a, b) in h.edge_stress.iter().zip(&w.edge_stress) {
        assert_eq!(a.kind, b.kind);
        assert!(
            (a.stress_mpa - b.stress_mpa).abs() <= 1e-6 * b.stress_mpa.abs(),
            "{a:?} {b:?}"
        );
    }
    let tooth = w
        .edge_stress
        .iter()
        .find(|e| e.kind == tactfab::sensor::edge_stress::EdgeKind::ToothBase)
        .expect("a tooth base edge");
    assert!((tooth.at_um[1] - 4500.0).abs() < 1.0, "{tooth:?}");
}

#[test]
fn contact_loads_find_the_tooth_tops() {
    // A patch centred on a tooth top lies on it entirely; the force is all applied.
    let g = geometry(&[]);
    let t = g.etched.tooth_tops_um[0];
    let (loads, at) = top_loads(
        &g,
        &point(0.5 * (t[0] + t[2]), 0.5 * (t[1] + t[3]), 1.0).load,
    );
    let s = build(
        &g,
        &[loads],
        Base::Rigid,
        SolidMeshOptions::level(1000.0, 0),
        &[],
        None,
        None,
    )
    .unwrap();
    assert_eq!(s.loaded_fraction, vec![1.0]);
    assert!(at.0 > t[0] && at.0 < t[2]);
}

#[test]
fn fe_model_solid_through_the_binary() {
    // The text on stdout and the JSON in a file, from one solve.
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("solid.json");
    let json = json.to_str().unwrap();
    let args = tiny_one_level(&["--scene", "line-y5mm", "--json-file", json]);
    let text = tactfab(&args);
    text.expect_code(0);
    let written = std::fs::read_to_string(json).unwrap();
    let v: serde_json::Value = serde_json::from_str(&written).expect("json");
    let r: &serde_json::Value = &v["scenes"][0];
    let q = r["quantities"].as_array().unwrap();
    // Deflection, nine charges, two reactions, the averaged and peak stresses, the two kinds
    // of sharp edge and the teeth's base vertices.
    assert_eq!(q.len(), 1 + 9 + 2 + 2 + 2 + 1, "{q:?}");
    let get = |n: &str| {
        q.iter().find(|x| x["name"] == n).unwrap()["value"]
            .as_f64()
            .unwrap()
    };
    assert!((get("reaction_support1") + get("reaction_support2") - 1.0).abs() < 1e-9);
    // Each electrode's charge split by piezo term adds up to it; the middle islands read the
    // plate's bending through d31 (the film under the span is in plane stress: s3 is small).
    let readout = &r["levels"][0]["readout"];
    // No wall-clock fields without --timings: the same input gives the same bytes.
    assert!(r.get("solve_ms").is_none() && r["levels"][0].get("time_ms").is_none());
    let charges = readout["charge_pc"].as_array().unwrap();
    let terms = readout["charge_terms_pc"].as_array().unwrap();
    assert_eq!(charges.len(), 9);
    assert_eq!(terms.len(), 9);
    for (q, t) in charges.iter().zip(terms) {
        let q = q.as_f64().unwrap();
        let t: Vec<f64> = t
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert!(
            (t.iter().sum::<f64>() - q).abs() <= 1e-9 * q.abs().max(1e-12),
            "{t:?} vs {q}"
        );
    }
    let term = |i: usize, k: usize| terms[i][k].as_f64().unwrap();
    // The charges are listed in the electrodes' order.
    let m2 = q
        .iter()
        .filter(|x| x["name"].as_str().unwrap().starts_with("charge_"))
        .position(|x| x["name"] == "charge_M2")
        .unwrap();
    assert!(term(m2, 2).abs() < 0.05 * term(m2, 0).abs(), "{terms:?}");
    // Every compared quantity carries the linear plate's value (the tooth base's from its edge
    // section); the solid's own stresses (the peak, the walls' and the vertices' at the critical
    // distance) have none to compare with.
    let own = [
        "max_principal_stress",
        "support_edge_stress",
        "tooth_vertex_stress",
    ];
    assert!(q
        .iter()
        .filter(|x| !own.contains(&x["name"].as_str().unwrap()))
        .all(|x| x["plate_value"].is_number()));
    assert!(q
        .iter()
        .filter(|x| own.contains(&x["name"].as_str().unwrap()))
        .all(|x| x["plate_value"].is_null()));
    // The text states a safety factor only for an edge in tension at L / 2: the line load hogs
    // the plate over the walls, which closes their corners under the plate.
    assert!(get("support_edge_stress") < 0.0, "{q:?}");
    assert!(text.stdout.ends_with(&format!("json: {json}\n")));
    let wall = text
        .stdout
        .lines()
        .find(|l| l.trim_start().starts_with("support_edge stress"))
        .expect("the wall's line");
    assert!(
        wall.ends_with("in compression there, no crack to open"),
        "{wall}"
    );
    assert!(!text.stdout.contains("safety factor -"), "{}", text.stdout);
    // The levels are graded where the plate finds the worst tooth base, and say so; the
    // caveat of uniform levels is left out.
    assert!(
        text.stdout.contains("the plate finds hottest (")
            && !text.stdout.contains("can miss the worst tooth base"),
        "{}",
        text.stdout
    );
    // A press on a support leaves the averaged stress under the plate in compression: no
    // negative factor from it either.
    // (Uniform levels, which say they can miss the worst tooth base: half a graded level.)
    let on_support = tiny_one_level(&["--point", "3,1.25,0.02,0.5", "--solid-grading", "uniform"]);
    let text = tactfab(&on_support);
    text.expect_code(0);
    assert!(
        text.stdout.contains("can miss the worst tooth base")
            && !text.stdout.contains("the plate finds hottest"),
        "{}",
        text.stdout
    );
    let averaged = text
        .stdout
        .lines()
        .find(|l| l.contains("from the averaged stress"))
        .expect("the averaged stress's line");
    assert!(
        averaged.contains("safety factor inf (in compression)"),
        "{averaged}"
    );
    assert!(!text.stdout.contains("safety factor -"), "{}", text.stdout);
    // The studies refuse it with a usage-level error.
    let bad = tactfab(&[
        "orient",
        "process/mis-grasper.yaml",
        "--model",
        "solid",
        "-o",
        "x",
    ]);
    assert_eq!(bad.code, 2, "{}", bad.stderr);
    assert!(bad.stderr.contains("solid rung"), "{}", bad.stderr);
}

#[test]
fn the_converse_piezo_effect_is_negligible_for_this_film() {
    // k31^2 = d31^2 E / (eps0 eps_r): 20 pC/N, 3 GPa, eps_r 12 give 1.1 %; the film carries about
    // 2 % of the bending stiffness, so feeding the charge back would move the structure by about
    // 2e-4, far under any tolerance the rungs are asked for: the solid leaves it out.
    let g = geometry(&[]);
    let k2 = tactfab::sensor::solid_readout::coupling_k31_squared(&g);
    let expect = (20e-12f64).powi(2) * 3e9 / (8.8541878128e-12 * 12.0);
    assert!(
        (k2 - expect).abs() < 1e-9 * expect && (0.010..0.012).contains(&k2),
        "{k2}"
    );
    let share = tactfab::sensor::solid_readout::film_bending_share(&g);
    assert!(share > 0.005 && share < 0.05, "{share}");
    assert!(k2 * share < 1e-3);
}

#[test]
fn build_verify_solid_fails_where_the_plate_and_the_solid_disagree() {
    // On the tiny die the support electrodes read the opposite sign in the solid (the force
    // goes through the film at the wall, outside the islands), as on the short one: the check
    // must fail the build and say which quantity, and the comparison is written beside the
    // traveler. Two of the bundled scenes, the centre load and the pressure.
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("b");
    // One level of the plate and (so) of the solid: the disagreement is far beyond any estimate
    // (the second solid level triples the test's time). A safety factor no rung meets on the
    // centre load: the solid's own check must say so too.
    let args = tiny_verify_build(
        out.to_str().unwrap(),
        &[],
        "checks.scenes=[{name: centre-1n, load: {point: {x_um: 3000, y_um: 4500, force_n: 1, \
         radius_um: 500}}, limits: {min_safety_factor: 1000}}, {name: pressure-2n, load: \
         {pressure: {force_n: 2}}}]",
    );
    let run = tactfab(&args);
    run.expect_code(1);
    assert!(
        run.stdout.contains("differs from the solid rung's") && run.stdout.contains("charge_S"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("scene `centre-1n` on the solid rung: safety factor"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("solid rung: 2 scenes on 1 level, graded at the plate's hottest teeth ("),
        "{}",
        run.stdout
    );
    let text = std::fs::read_to_string(out.join("mis-grasper-solid-check.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["scenes"].as_array().unwrap().len(), 2);
    assert_eq!(v["scenes"][0]["graded"], false);
    assert!(v["scenes"][0]["grading_choice"]["local_factor_entries"].is_u64());
    assert!(v["scenes"][0]["graded_teeth"].as_u64().unwrap() > 0);
    let sf = &v["limits"][0][0];
    assert_eq!(sf["limit"], "min_safety_factor");
    assert_eq!(sf["passed"], false);
    // The solid's factor against the stress it reports, taken on the unsafe side.
    let stress = v["scenes"][0]["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["name"] == "max_stress_averaged")
        .unwrap()["extrapolated"]
        .as_f64()
        .unwrap();
    let factor = sf["value"].as_f64().unwrap();
    assert!(
        factor > 0.0 && factor * stress <= 4000.0 * (1.0 + 1e-12),
        "{factor} {stress}"
    );
    // ... and against the teeth's base edges' stress at the critical distance, which governs.
    let edge = v["scenes"][0]["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["name"] == "tooth_base_stress")
        .unwrap()["value"]
        .as_f64()
        .unwrap();
    assert!(
        edge > stress && factor * edge <= 4000.0 * (1.0 + 1e-12),
        "{factor} {edge}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("build.json")).unwrap()).unwrap();
    assert_eq!(summary["passed"], false);
    // The plate answers carry the solid's measurement as their model error (item 4): at least
    // the largest plate - solid difference of the scene, and the scene is then not converged.
    for (k, solid) in v["scenes"].as_array().unwrap().iter().enumerate() {
        let fe = &summary["fe"]["scenes"][k];
        assert_eq!(fe["name"], solid["scene"]);
        assert_eq!(fe["model"], solid["plate_rung"]);
        let worst = solid["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|q| q["name"] != "max_stress_peak")
            .filter_map(|q| q["plate_difference"].as_f64())
            .fold(0.0f64, f64::max);
        let model = fe["error"]["model"].as_f64().unwrap();
        assert!(worst > 0.0 && model >= worst, "{k}: {model} < {worst}");
        assert_eq!(fe["converged"], false, "{k}");
    }
}

#[test]
fn the_support_section_brings_the_plain_plate_to_the_solid() {
    // The short die without teeth on a rigid base under a uniform pressure (across the span the
    // plane-strain case the section solves): the large-deflection plate on the supports'
    // section (its turn, give and in-plane pull, and the film under the plate) against the solid
    // rung. Measured: deflection +1.7 %, M2 +2.9 % (the solid's two uniform levels read the
    // wall's corner stiff: with the walls graded the full die agrees to 0.6 %); the clamp reads
    // M2 11 % low. With the coupling's sign flipped M2 reads 30 % high.
    let base = [
        "fe",
        "process/mis-grasper.yaml",
        "--pressure",
        "0.02",
        "--set",
        "geometry.teeth.pattern=none",
        "--set",
        "materials.base.kind=rigid",
        "--json",
    ];
    let read = |extra: &[&str]| {
        let out = tactfab(&on_short_die(&[&base[..], extra].concat()));
        out.expect_code(0);
        let j: serde_json::Value = serde_json::from_str(&out.stdout).expect("json");
        j["scenes"][0].clone()
    };
    let solid = read(&["--model", "solid", "--max-levels", "2"]);
    // No teeth: nothing for the plate to rank, the solid's levels stay uniform.
    assert_eq!(solid["graded_teeth"], 0);
    let q = |name: &str| {
        solid["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .find(|q| q["name"] == name)
            .unwrap()["value"]
            .as_f64()
            .unwrap()
    };
    let (w_solid, m2_solid) = (q("deflection_at_load"), q("charge_M2"));
    let plate = |extra: &[&str]| {
        let s = read(&[&["--model", "large-deflection"], extra].concat());
        let m2 = s["electrodes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["name"] == "M2")
            .unwrap()["charge_pc"]
            .as_f64()
            .unwrap();
        let r = &s["reactions_n"];
        let total = r["support1"].as_f64().unwrap() + r["support2"].as_f64().unwrap();
        assert!((total - 0.02).abs() < 1e-6 * 0.02, "{total}");
        (s["deflection_at_load_um"].as_f64().unwrap(), m2)
    };
    let (w, m2) = plate(&["--set", "materials.base.support_model=solid_section"]);
    let (_, m2_clamped) = plate(&[]);
    assert!((w - w_solid).abs() < 0.03 * w_solid, "{w} {w_solid}");
    assert!((m2 - m2_solid).abs() < 0.05 * m2_solid, "{m2} {m2_solid}");
    assert!(
        (m2_clamped - m2_solid).abs() > 2.0 * (m2 - m2_solid).abs(),
        "{m2_clamped} {m2} {m2_solid}"
    );
}

#[test]
fn build_verify_solid_graded_reaches_the_solid_rung() {
    // `build --verify-solid --graded` reaches the solid rung (one light scene on the tiny die,
    // one level: the flag is the scene's, every level takes it) and says so; --graded alone is
    // a usage error.
    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("b");
    let run = tactfab(&tiny_verify_build(
        out.to_str().unwrap(),
        &["--graded"],
        "checks.scenes=[{name: light, load: {point: {x_um: 3000, y_um: 4500, force_n: 0.02, \
         radius_um: 500}}}]",
    ));
    assert!(matches!(run.code, 0 | 1), "{}", run.stderr);
    assert!(
        run.stdout
            .contains("solid rung: 1 scene on 1 level, graded at the tooth base edges"),
        "{}",
        run.stdout
    );
    let text = std::fs::read_to_string(out.join("mis-grasper-solid-check.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let scene = &v["scenes"][0];
    assert_eq!(scene["scene"], "light");
    assert_eq!(scene["graded"], true);
    assert_eq!(scene["levels"].as_array().unwrap().len(), 1);
    let run = tactfab(&["build", "process/mis-grasper.yaml", "-o", "x", "--graded"]);
    run.expect_code(2);
    assert!(run.stderr.contains("--verify-solid"), "{}", run.stderr);
}

#[test]
fn fe_verify_solid_takes_the_plate_answers_model_error_from_the_solid() {
    // The line load on the tiny die (the large-deflection plate answers it, so the solid is
    // nonlinear): its differences become the plate answer's `model` part. One level of each:
    // `--max-levels` bounds the solid's levels too; uniform (`--solid-grading` reaches
    // `--verify-solid`): the subject is the comparison, at half a graded level's cost.
    let args = with_sets(
        &[
            "fe",
            "process/mis-grasper.yaml",
            "--scene",
            "line-y5mm",
            "--verify-solid",
            "--max-levels",
            "1",
            "--solid-grading",
            "uniform",
            "--json",
        ],
        &TINY,
    );
    let run = tactfab(&args);
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap_or_else(|e| {
        panic!("{e}\n{}\n{}", run.stdout, run.stderr);
    });
    let solid = &v["solid"][0];
    let plate = &v["scenes"][0];
    assert_eq!(solid["plate_rung"], plate["model"]["kind"]);
    assert_eq!(solid["levels"].as_array().unwrap().len(), 1);
    assert_eq!(solid["graded_teeth"], 0, "{solid}");
    let by_name = |name: &str| {
        solid["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .find(|q| q["name"] == name)
            .unwrap_or_else(|| panic!("{name}"))["plate_difference"]
            .as_f64()
            .unwrap()
    };
    let mut worst = 0.0f64;
    for q in plate["quantities"].as_array().unwrap() {
        let name = q["name"].as_str().unwrap();
        if name == "max_stress_peak" {
            continue;
        }
        // One solid level gives no estimate: the model part is at least the difference itself.
        let d = by_name(name);
        let m = q["error"]["model"].as_f64().unwrap();
        assert!(m >= d, "{name}: model {m} < solid difference {d}");
        worst = worst.max(d);
        let total = q["error"]["total"].as_f64();
        let converged = q["converged"].as_bool().unwrap();
        assert!(!converged || total.is_some_and(|t| t < 0.01), "{name}");
    }
    // The support electrodes read the opposite sign in the solid: far beyond the tolerance.
    assert!(worst > 0.5, "{worst}");
    assert_eq!(plate["converged"], false);
    assert!(plate["error"]["model"].as_f64().unwrap() >= worst);
    // The answer's safety factor is the solid's where the solid's governing stress (a sharp
    // edge's at the critical distance) is worse than the plate's averaged stress.
    let governing = [
        "max_stress_averaged",
        "tooth_base_stress",
        "support_edge_stress",
        "tooth_vertex_stress",
    ]
    .iter()
    .map(|n| {
        solid["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .find(|q| q["name"] == *n)
            .unwrap_or_else(|| panic!("{n}"))["value"]
            .as_f64()
            .unwrap()
    })
    .fold(0.0f64, f64::max);
    let sf = plate["safety_factor"].as_f64().unwrap();
    assert!(sf * governing <= 4000.0 * (1.0 + 1e-9), "{sf} {governing}");
    // The plate answer judges the tooth base itself (its edge section); it takes the solid's
    // safety factor, with EDGE_STRESS, only where that is lower.
    assert_eq!(plate["stress_from"], "tooth_base");
    let own = 4000.0 / plate["max_stress_mpa"].as_f64().unwrap();
    assert!(sf <= own * (1.0 + 1e-12), "{sf} {own}");
    assert_eq!(
        run.stdout.contains("EDGE_STRESS"),
        sf < own * (1.0 - 1e-12),
        "{}",
        run.stdout
    );
    // The plate's tooth base against the solid's, an independent model of the same edge: within
    // 25 % (measured 13.1 % on one level each, 12.4 % with the plate on three levels and the
    // solid on two: the plate reads higher; coarse solid levels with two bricks through the
    // plate read the edge about 10 % low on the bundled design, README).
    let d = by_name("tooth_base_stress");
    assert!(d > 0.0 && d < 0.25, "{d}");
    // The solid checks a plate answer: with --model solid there is nothing to check.
    let run = tactfab(&[
        "fe",
        "process/mis-grasper.yaml",
        "--model",
        "solid",
        "--verify-solid",
    ]);
    run.expect_code(2);
    assert!(run.stderr.contains("--verify-solid"), "{}", run.stderr);
}

/// A factor larger than the memory allowed is refused after the symbolic analysis, before it is
/// allocated (exit 2, what it needs against what there is), not left to the OOM killer; with
/// several levels the largest mesh is asked first; where only one grading's factor fits, auto
/// solves that one; a malformed limit is bad input whatever the subcommand.
#[test]
fn a_factor_over_the_memory_limit_is_refused_before_it_is_allocated() {
    // The factor (MB) a run of `levels` solid levels under a 300 MB limit refuses.
    let refused = |levels: &str, rest: &[&str]| -> u64 {
        let mut args = tiny_levels(levels, &["--scene", "centre-1n"]);
        args.extend_from_slice(rest);
        let (code, stdout, stderr) = run_env(&args, &[("TACTFAB_MEMORY_LIMIT_MB", "300")]);
        assert_eq!(code, 2, "{stdout}\n{stderr}");
        assert!(stdout.is_empty(), "{stdout}");
        assert!(
            stderr.contains("a Cholesky factor of")
                && stderr.contains("more than the 300 MB the limit TACTFAB_MEMORY_LIMIT_MB sets")
                && stderr.contains("hint:"),
            "{stderr}"
        );
        stderr
            .split(" MB, more than")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no size in {stderr}"))
    };
    // One level: level 0's own factor. Three: a larger one (the finest level's or the thickness
    // check's), so it was asked before level 0, whose factor would have been refused first.
    let (level0, three) = (refused("1", &[]), refused("3", &[]));
    assert!(level0 > 300 && three > level0, "{level0} {three}");
    // Auto's fallback: under a limit between the two gradings' needs, the one that fits is
    // solved, not the run refused, and the text and the JSON say why the other was not.
    let (local, lines) = (
        refused("1", &["--solid-grading", "local"]),
        refused("1", &["--solid-grading", "lines"]),
    );
    assert!(local.abs_diff(lines) >= 4, "{local} {lines}");
    let between = ((local + lines) / 2).to_string();
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("fe.json");
    let json_arg = json.to_str().unwrap();
    let args = tiny_levels("1", &["--scene", "centre-1n", "--json-file", json_arg]);
    let (code, stdout, stderr) = run_env(&args, &[("TACTFAB_MEMORY_LIMIT_MB", &between)]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let solid = &v["scenes"][0];
    assert_eq!(solid["local_refinement"], local < lines, "{solid}");
    let choice = &solid["grading_choice"];
    let (taken, other) = if local < lines {
        ("local_factor_entries", "lines_factor_entries")
    } else {
        ("lines_factor_entries", "local_factor_entries")
    };
    assert!(
        choice[taken].is_u64() && choice[other].is_null(),
        "{choice}"
    );
    let limit = format!("more than the {between} MB the limit TACTFAB_MEMORY_LIMIT_MB sets");
    let why = choice["refused"].as_str().unwrap_or_default();
    assert!(why.contains(&limit) && !why.contains("hint"), "{choice}");
    let (how, other_how) = if local < lines {
        ("locally: hanging nodes", "by lines")
    } else {
        ("by lines across the die", "locally")
    };
    assert!(
        stdout.contains(&format!("({how}; {other_how} was refused: ")) && stdout.contains(&limit),
        "{stdout}"
    );
    for bad in ["abc", "0", "-5", "inf"] {
        let (code, _, stderr) = run_env(
            &["etch", "process/mis-grasper.yaml"],
            &[("TACTFAB_MEMORY_LIMIT_MB", bad)],
        );
        assert_eq!(code, 2, "{bad}: {stderr}");
        assert!(
            stderr.contains(&format!(
                "TACTFAB_MEMORY_LIMIT_MB is `{bad}`, not a positive number"
            )),
            "{stderr}"
        );
    }
}

/// The bundled scenes' plate ladder factorises two 354 MB tangents side by side on 2 cores (and
/// later one of 679 MB). Under a 700 MB limit the second is refused beside the first, solved again
/// after it, and the answers are the same as without a limit, byte for byte; under 600 MB the
/// 679 MB factor is refused even alone.
#[test]
fn factors_that_fit_only_one_at_a_time_are_solved_one_at_a_time() {
    let args = ["fe", "process/mis-grasper.yaml", "--json"];
    let (code, free, stderr) = run_env(&args, &[]);
    assert_eq!(code, 0, "{stderr}");
    let (code, limited, stderr) = run_env(&args, &[("TACTFAB_MEMORY_LIMIT_MB", "700")]);
    assert_eq!(code, 0, "{stderr}");
    assert!(free == limited, "the answers under the limit differ");
    let (code, _, stderr) = run_env(&args, &[("TACTFAB_MEMORY_LIMIT_MB", "600")]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("needs 679 MB, more than the 600 MB"),
        "{stderr}"
    );
}

/// `--solid-levels` sets the solid's levels past the default three (the fourth at 354 um), whose
/// estimate then comes from the last three; anything but 1-5, or without `--model solid`, is
/// exit 2. (The plain plate on a rigid base: four levels in seconds.)
#[test]
fn solid_levels_sets_the_solid_rungs_levels() {
    let mut args = with_sets(
        &["fe", "process/mis-grasper.yaml", "--model", "solid"],
        &TINY,
    );
    args.extend([
        "--solid-levels",
        "4",
        "--set",
        "materials.base.kind=rigid",
        "--set",
        "geometry.teeth.pattern=none",
        "--point",
        "3,4.5,0.02,0.5",
        "--json",
        "--timings",
    ]);
    let out = tactfab(&args);
    out.expect_code(0);
    let four: serde_json::Value = serde_json::from_str(&out.stdout).expect("json");
    // --timings: each level's time and the scene's, their sum (without it, none:
    // `fe_model_solid_through_the_binary`).
    let ms = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{v}"));
    let times: Vec<f64> = four["scenes"][0]["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| ms(&l["time_ms"]))
        .collect();
    let total = ms(&four["scenes"][0]["solve_ms"]);
    assert!(times.iter().all(|t| *t > 0.0), "{times:?}");
    assert!(
        (times.iter().sum::<f64>() - total).abs() <= 1e-9 * total,
        "{times:?} {total}"
    );
    // Tied shears by default (`--plain-shear` unties them:
    // `tied_shear_unlocks_the_plate_bricks_and_keeps_equilibrium`).
    assert_eq!(four["scenes"][0]["tied_shear"], true);
    let l4 = four["scenes"][0]["levels"].as_array().unwrap().clone();
    assert_eq!(l4.len(), 4);
    let h = |l: &serde_json::Value| l["element_um"].as_f64().unwrap();
    assert!(
        (h(&l4[3]) - 500.0 / 2f64.sqrt()).abs() < 1e-6,
        "{}",
        h(&l4[3])
    );
    let w = |l: &serde_json::Value| l["readout"]["deflection_at_load_um"].as_f64().unwrap();
    let q = four["scenes"][0]["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["name"] == "deflection_at_load")
        .unwrap()
        .clone();
    assert_eq!(q["value"].as_f64().unwrap(), w(&l4[3]));
    // The fourth level's estimate: the shipped three-mesh one on levels 1-3.
    let est =
        tactfab::fe::ThreeMesh::new(w(&l4[1]), w(&l4[2]), w(&l4[3]), 2f64.sqrt(), 2f64.sqrt())
            .fine_error();
    let disc = q["discretisation"].as_f64().unwrap();
    assert!(
        (disc * w(&l4[3]).abs() - est).abs() <= 1e-9 * est.max(1e-30),
        "{disc} {est}"
    );
    let solid = ["fe", "process/mis-grasper.yaml", "--model", "solid"];
    for bad in [
        vec!["fe", "process/mis-grasper.yaml", "--solid-levels", "2"],
        [&solid[..], &["--solid-levels", "0"]].concat(),
        [&solid[..], &["--solid-levels", "6"]].concat(),
    ] {
        let out = tactfab(&bad);
        out.expect_code(2);
        assert!(out.stderr.contains("--solid-levels"), "{}", out.stderr);
    }
    // The plate ladder's convergence table is not the solid's: refused, not ignored.
    let out = tactfab(&[&solid[..], &["--convergence"]].concat());
    out.expect_code(2);
    assert!(
        out.stderr.contains("--convergence") && out.stderr.contains("--json"),
        "{}",
        out.stderr
    );
}

/// `--solid-levels` with `--verify-solid` (`fe` and `build`): three levels give the solid its own
/// estimate, and the plate answer's model part is then the difference plus that estimate; the
/// flag without `--verify-solid` on `build` is exit 2. (The plain plate on a rigid base, one
/// light scene: seconds a level.)
#[test]
fn verify_solid_takes_its_levels_from_solid_levels() {
    const PLAIN: [&str; 4] = [
        "materials.base.kind=rigid",
        "geometry.teeth.pattern=none",
        "checks.scenes=[{name: light, load: {point: {x_um: 3000, y_um: 7500, force_n: 0.02, \
         radius_um: 500}}}]",
        "geometry.die_length_um=6000",
    ];
    let run = tactfab(&with_sets(
        &[
            "fe",
            "process/mis-grasper.yaml",
            "--verify-solid",
            "--solid-levels",
            "3",
            "--json",
        ],
        &PLAIN,
    ));
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap_or_else(|e| {
        panic!("{e}\n{}\n{}", run.stdout, run.stderr);
    });
    let (solid, plate) = (&v["solid"][0], &v["scenes"][0]);
    assert_eq!(solid["levels"].as_array().unwrap().len(), 3);
    assert_eq!(solid["plate_rung"], plate["model"]["kind"]);
    let mut taken = 0;
    for q in plate["quantities"].as_array().unwrap() {
        let name = q["name"].as_str().unwrap();
        let Some(s) = solid["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["name"] == name)
        else {
            continue;
        };
        let (Some(d), Some(est)) = (s["plate_difference"].as_f64(), s["discretisation"].as_f64())
        else {
            panic!("{name}: no difference or no estimate on three levels: {s}");
        };
        let model = q["error"]["model"].as_f64().unwrap();
        assert!(model >= d + est - 1e-15, "{name}: {model} < {d} + {est}");
        taken += 1;
    }
    assert!(taken >= 5, "{taken}");

    let t = tempfile::tempdir().unwrap();
    let out = t.path().join("b");
    let run = tactfab(&with_sets(
        &[
            "build",
            "process/mis-grasper.yaml",
            "-o",
            out.to_str().unwrap(),
            "--verify-solid",
            "--solid-levels",
            "3",
            "--allow-unconverged",
        ],
        &PLAIN,
    ));
    assert!(matches!(run.code, 0 | 1), "{}", run.stderr);
    assert!(
        run.stdout.contains("solid rung: 1 scene on 3 levels"),
        "{}",
        run.stdout
    );
    let text = std::fs::read_to_string(out.join("mis-grasper-solid-check.json")).unwrap();
    let check: serde_json::Value = serde_json::from_str(&text).unwrap();
    // The same solve as `fe`'s: the same levels, bit for bit.
    assert_eq!(check["scenes"][0]["levels"], solid["levels"]);
    assert!(check["scenes"][0]["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .all(|q| q["name"] == "max_principal_stress" || !q["discretisation"].is_null()));
    for bad in [
        vec![
            "build",
            "process/mis-grasper.yaml",
            "-o",
            "x",
            "--solid-levels",
            "3",
        ],
        vec![
            "build",
            "process/mis-grasper.yaml",
            "-o",
            "x",
            "--verify-solid",
            "--solid-levels",
            "9",
        ],
        vec!["fe", "process/mis-grasper.yaml", "--solid-levels", "3"],
    ] {
        let run = tactfab(&bad);
        run.expect_code(2);
        assert!(run.stderr.contains("--solid-levels"), "{}", run.stderr);
    }
}
