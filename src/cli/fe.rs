//! `tactfab fe FILE`: what each electrode reads under the declared or ad-hoc scenes.

use anyhow::{bail, Context};

use tactfab::export::file::{self, Proof};
use tactfab::process::{Limits, Scene, SceneLoad};
use tactfab::report::limit_failures;
use tactfab::sensor::support_stiffness::SupportStiffness;
use tactfab::sensor::{
    convergence_svg, evaluate_many_with, plate_modes, MeshOptions, PlateModes, SceneReport,
    SensorGeometry, MODAL_LEVELS, MODES_REPORTED,
};

use super::args::{FeArgs, GradingArg};
use super::output::{count, f};
use super::{design, Outcome};

pub fn run(args: &FeArgs) -> anyhow::Result<Outcome> {
    let (_, design) = design(&args.process)?;
    super::warn_process_errors(&args.process, &design);
    let scenes = scenes(args, &design.process.checks.scenes)?;
    if args.convergence {
        // Before the solve (after the process file's own errors): a plot path that would cost
        // the user a file is refused at once.
        file::check(&args.plot, Proof::SvgStamp, &[&args.process.file]).context("--plot")?;
    }
    if let Some(path) = &args.json_file {
        file::check(path, Proof::JsonStamp, &[&args.process.file]).context("--json-file")?;
    }
    let g = SensorGeometry::new(&design);
    if args.accuracy.model == super::args::ModelArg::Solid {
        if args.verify_solid {
            bail!(
                "--verify-solid checks a plate answer against the solid rung; with --model solid \
                 the answer is the solid itself (drop one of them)"
            );
        }
        return solid(args, &g, &scenes);
    }
    if args.solid_levels.is_some() && !args.verify_solid {
        bail!(
            "--solid-levels sets the solid rung's levels: give it with --model solid or \
             --verify-solid"
        );
    }
    if args.solid_grading.is_some() && !args.verify_solid {
        bail!(
            "--solid-grading applies to the solid rung: give it with --model solid or \
             --verify-solid"
        );
    }
    if args.plain_shear && !args.verify_solid {
        bail!(
            "--plain-shear applies to the solid rung: give it with --model solid or --verify-solid"
        );
    }
    let mut reports = evaluate_many_with(
        &g,
        &scenes,
        args.accuracy.into(),
        MeshOptions {
            symmetry: !args.no_symmetry,
            graded: args.graded,
            stations: true,
        },
    )
    .context("the plate rungs")?;
    let solid = if args.verify_solid {
        verify_solid(args, &g, &scenes, &mut reports)?
    } else {
        Vec::new()
    };
    let modes = plate_modes(&g, MODES_REPORTED, MODAL_LEVELS)
        .context("natural frequencies of the plate")?;
    let supports = SupportStiffness::of(&g).context("the supports' stiffness")?;
    let failed = reports.iter().zip(&scenes).any(|(r, s)| {
        !limit_failures(r, &s.limits).is_empty()
            || r.warnings
                .iter()
                .any(|w| w.severity == tactfab::finding::Severity::Error)
    });
    if args.json || args.json_file.is_some() {
        let mut scenes = serde_json::to_value(&reports)?;
        if !args.timings {
            strip_timings(&mut scenes);
        }
        let mut v = serde_json::json!({ "scenes": scenes, "modes": modes, "supports": supports });
        if args.verify_solid {
            v["solid"] = serde_json::to_value(&solid)?;
        }
        json_out(args, &v)?;
    }
    if !args.json {
        for (k, (r, s)) in reports.iter().zip(&scenes).enumerate() {
            print!("{}", text(r, &limit_failures(r, &s.limits)));
            if let Some(solid) = solid.get(k) {
                print!("{}", solid_line(r, solid));
            }
            if args.convergence {
                print!("{}", convergence_table(r));
            }
        }
        print!("{}", supports.text());
        print!("{}", modes_text(&modes));
    }
    if args.convergence {
        let svg = file::stamp_svg(convergence_svg(&reports));
        file::write(
            &args.plot,
            svg.as_bytes(),
            Proof::SvgStamp,
            &[&args.process.file],
        )
        .context("--plot")?;
        if !args.json {
            println!("convergence plot: {}", args.plot.display());
        }
    }
    if let Some(path) = &args.json_file {
        println!("json: {}", path.display());
    }
    Ok(if failed {
        Outcome::CheckFailed
    } else {
        Outcome::Ok
    })
}

/// `--verify-solid`: each scene on the solid rung (`--solid-levels`, else
/// [`super::VERIFY_SOLID_LEVELS`] levels or fewer when `--max-levels` is lower, as `build
/// --verify-solid`), whose
/// differences become the plate answers' model error where the solid was compared with the rung
/// that answered.
fn verify_solid(
    args: &FeArgs,
    g: &SensorGeometry,
    scenes: &[Scene],
    reports: &mut [SceneReport],
) -> anyhow::Result<Vec<tactfab::sensor::solid::SolidReport>> {
    use tactfab::sensor::solid::{solid_against_plate, SolidRun};
    let acc: tactfab::sensor::Accuracy = args.accuracy.into();
    let mut out = Vec::new();
    let progress = super::Progress::new();
    for (i, (s, r)) in scenes.iter().zip(reports.iter_mut()).enumerate() {
        progress.message(solid_stage(&s.name, i, scenes.len()));
        let run = SolidRun {
            base: g.base,
            levels: super::solid_levels(
                args.solid_levels,
                super::VERIFY_SOLID_LEVELS,
                acc.max_levels,
            ),
            tol: acc.tol_rel,
            symmetry: !args.no_symmetry,
            nonlinear: false,
            graded: args.graded,
            tied_shear: !args.plain_shear,
            grading: GradingArg::or_auto(args.solid_grading),
        };
        let solid = solid_against_plate(g, s, run, acc, Some(r)).context("solid solve failed")?;
        r.take_model_error_from(g, &solid, acc.tol_rel);
        out.push(solid);
    }
    Ok(out)
}

/// The spinner's text while the solid rung runs (a minute or more per scene).
fn solid_stage(scene: &str, i: usize, n: usize) -> String {
    format!("solid rung: scene `{scene}` ({} of {n})", i + 1)
}

/// What `--verify-solid` did to one scene's errors.
fn solid_line(r: &SceneReport, solid: &tactfab::sensor::solid::SolidReport) -> String {
    if solid.plate_rung != r.model.kind.to_string() {
        return format!(
            "  solid check: the solid was compared with the {} rung auto picks, not with this \
             {} answer: its model error is left as it was\n",
            solid.plate_rung, r.model.kind
        );
    }
    let worst = solid
        .disagreements(0.0)
        .into_iter()
        .next()
        .map_or_else(String::new, |(n, d)| format!("; the largest, {n}: {d:.1e}"));
    format!(
        "  solid check ({}, {}): model error taken from the solid{worst}\n",
        count(solid.levels.len(), "level"),
        if solid.nonlinear {
            "nonlinear"
        } else {
            "linear"
        },
    )
}

/// The JSON `v` on stdout (`--json`) or, stamped as tactfab's, in `--json-file` (stdout keeps
/// the text): one solve gives both.
fn json_out(args: &FeArgs, v: &serde_json::Value) -> anyhow::Result<()> {
    let pretty = serde_json::to_string_pretty(v)?;
    match &args.json_file {
        Some(path) => {
            let stamped = file::stamp_json(&pretty).context("--json-file: not a JSON object")?;
            file::write(
                path,
                stamped.as_bytes(),
                Proof::JsonStamp,
                &[&args.process.file],
            )
            .context("--json-file")?;
        }
        None => println!("{pretty}"),
    }
    Ok(())
}

/// Removes the wall-clock fields (`solve_ms`, each level's `time_ms`) from the scenes' JSON.
fn strip_timings(scenes: &mut serde_json::Value) {
    for scene in scenes.as_array_mut().into_iter().flatten() {
        if let Some(o) = scene.as_object_mut() {
            o.remove("solve_ms");
        }
        for level in scene["convergence"].as_array_mut().into_iter().flatten() {
            if let Some(o) = level.as_object_mut() {
                o.remove("time_ms");
            }
        }
    }
}

/// `--timings` on the solid's JSON: each level's `time_ms` and each scene's `solve_ms` (their
/// sum), as the plate's JSON names them; left out by default so the bytes are stable.
fn add_solid_timings(
    scenes: &mut serde_json::Value,
    reports: &[tactfab::sensor::solid::SolidReport],
) {
    for (scene, r) in scenes.as_array_mut().into_iter().flatten().zip(reports) {
        let mut total_ms = 0.0;
        for (level, l) in scene["levels"]
            .as_array_mut()
            .into_iter()
            .flatten()
            .zip(&r.levels)
        {
            level["time_ms"] = serde_json::json!(1e3 * l.seconds);
            total_ms += 1e3 * l.seconds;
        }
        scene["solve_ms"] = serde_json::json!(total_ms);
    }
}

/// The scenes to run: `--point`/`--pressure` if given, else the file's (optionally one `--scene`).
fn scenes(args: &FeArgs, declared: &[Scene]) -> anyhow::Result<Vec<Scene>> {
    let mut out = Vec::new();
    for pt in &args.point {
        out.push(Scene {
            name: format!("point-{}-{}-{}N", pt.x_mm, pt.y_mm, pt.force_n),
            load: SceneLoad::Point {
                x_um: pt.x_mm * 1000.0,
                y_um: pt.y_mm * 1000.0,
                force_n: pt.force_n,
                radius_um: pt.radius_mm * 1000.0,
            },
            limits: Limits::default(),
        });
    }
    for force in &args.pressure {
        out.push(Scene {
            name: format!("pressure-{force}N"),
            load: SceneLoad::Pressure {
                force_n: *force,
                region: None,
            },
            limits: Limits::default(),
        });
    }
    if !out.is_empty() {
        return Ok(out);
    }
    let chosen: Vec<Scene> = match &args.scene {
        Some(name) => declared
            .iter()
            .filter(|s| &s.name == name)
            .cloned()
            .collect(),
        None => declared.to_vec(),
    };
    if chosen.is_empty() {
        let known: Vec<_> = declared.iter().map(|s| s.name.as_str()).collect();
        match &args.scene {
            Some(n) => bail!(
                "no scene `{n}` in checks.scenes (known: {})",
                known.join(", ")
            ),
            None => bail!(
                "the process file declares no checks.scenes: give --point X_MM,Y_MM,FORCE_N or \
                 --pressure FORCE_N"
            ),
        }
    }
    Ok(chosen)
}

fn text(r: &SceneReport, failures: &[String]) -> String {
    let mut s = format!(
        "scene `{}` ({} N): {} model, {} elements, {} dofs, {}, {} ms, estimated error {}\n",
        r.scene,
        r.force_n,
        r.model.kind,
        r.model.elements,
        r.model.dofs,
        count(r.model.levels, "level"),
        f(r.solve_ms, 1),
        // Without the model part the number is the discretisation's alone: said in the header
        // too, where a reader stops, in the traveler's words (convergence has its own lines).
        tactfab::report::sheet::err_text(r.error_estimate, r.error.model.is_some(), true)
    );
    if !r.model.reason.is_empty() {
        s.push_str(&format!("  rung: {}\n", r.model.reason));
    }
    let part =
        |v: Option<f64>| v.map_or_else(|| "not estimated".to_string(), |e| format!("{e:.1e}"));
    s.push_str(&format!(
        "  error: discretisation {} + model {} = {}\n",
        part(r.error.discretisation),
        match r.error.model {
            Some(m) => format!("{m:.1e}"),
            None => "not estimated (--verify-solid measures it against the 3D solid)".into(),
        },
        match (r.error.total, r.error.model) {
            (Some(t), None) => format!("at least {t:.1e}"),
            (t, _) => part(t),
        }
    ));
    if let Some(t) = &r.touch_down {
        s.push_str(&format!(
            "  touch-down: {} (gap {} um under the plate; {})\n",
            t.load_n.map_or_else(
                || "none below 100x this load".to_string(),
                |l| format!("{} N", f(l, 2))
            ),
            f(t.gap_um, 1),
            t.basis
        ));
    }
    if let Some(sym) = &r.model.symmetry {
        s.push_str(&format!(
            "  symmetric: solved the {sym}; readings on the mirrored whole plate\n"
        ));
    }
    if let Some(grading) = &r.model.grading {
        s.push_str(&format!("  graded mesh: {grading}\n"));
    }
    s.push_str(&format!(
        "  deflection {} um at the load, {} um max; stress {} MPa {}; safety factor {}; max load \
         {}\n",
        f(r.deflection_at_load_um, 2),
        f(r.max_deflection_um, 2),
        f(r.max_stress_mpa, 1),
        r.stress_from.describe(),
        r.stress_from.judged_text(r.safety_factor, 2, ""),
        r.stress_from.judged_text(r.max_permissible_load_n, 2, " N")
    ));
    s.push_str(&format!(
        "  reactions: support 1 {} N, support 2 {} N; most sensitive {} at {} mV/N\n",
        f(r.reactions_n.support1, 4),
        f(r.reactions_n.support2, 4),
        r.most_sensitive,
        f(r.sensitivity_mv_per_n, 3)
    ));
    s.push_str("  electrode   charge_pc   voltage_mv\n");
    for e in &r.electrodes {
        s.push_str(&format!(
            "  {:<9} {:>11} {:>12}\n",
            e.name,
            f(e.charge_pc, 3),
            f(e.voltage_mv, 3)
        ));
    }
    for w in &r.warnings {
        s.push_str(&format!("  {w}\n"));
    }
    for x in failures {
        s.push_str(&format!("  FAIL: {x}\n"));
    }
    s
}

fn convergence_table(r: &SceneReport) -> String {
    let mut s = String::from(
        "  level  h_um  elements     dofs   time_ms  deflection_um  charge_pc   est_error  order\n",
    );
    for (i, l) in r.convergence.iter().enumerate() {
        s.push_str(&format!(
            "  {:>5} {:>5} {:>9} {:>8} {:>9} {:>14} {:>10} {:>11} {:>6}\n",
            i,
            f(l.max_element_um, 0),
            l.elements,
            l.dofs,
            f(l.time_ms, 1),
            f(l.deflection_at_load_um, 4),
            f(l.charge_pc, 4),
            l.error_estimate
                .map(|e| format!("{e:.2e}"))
                .unwrap_or_else(|| "-".into()),
            l.observed_order
                .map(|p| f(p, 2))
                .unwrap_or_else(|| "-".into())
        ));
    }
    s
}

/// `fe --model solid`: each scene on the solid rung next to the linear plate's values.
fn solid(args: &FeArgs, g: &SensorGeometry, scenes: &[Scene]) -> anyhow::Result<Outcome> {
    use tactfab::sensor::solid::{solid_against_plate, SolidReport, SolidRun};
    use tactfab::sensor::Accuracy;
    if args.convergence {
        // The plate ladder's table and plot; the solid's levels are in its summary line and
        // its JSON (`levels`, with `--timings` their times).
        bail!(
            "--convergence tabulates the plate rungs' levels; with --model solid use --json \
             (each scene's `levels`, --timings for their times)"
        );
    }
    let acc: Accuracy = args.accuracy.into();
    let levels = super::solid_levels(
        args.solid_levels,
        super::MODEL_SOLID_LEVELS,
        usize::from(args.accuracy.max_levels),
    );
    let mut reports: Vec<SolidReport> = Vec::new();
    let progress = super::Progress::new();
    for (i, s) in scenes.iter().enumerate() {
        progress.message(solid_stage(&s.name, i, scenes.len()));
        let run = SolidRun {
            base: g.base,
            levels,
            tol: acc.tol_rel,
            symmetry: !args.no_symmetry,
            nonlinear: false,
            graded: args.graded,
            tied_shear: !args.plain_shear,
            grading: GradingArg::or_auto(args.solid_grading),
        };
        reports.push(solid_against_plate(g, s, run, acc, None).context("solid solve failed")?);
    }
    drop(progress);
    if args.json || args.json_file.is_some() {
        let mut scenes = serde_json::to_value(&reports)?;
        if args.timings {
            add_solid_timings(&mut scenes, &reports);
        }
        json_out(args, &serde_json::json!({ "scenes": scenes }))?;
        if args.json {
            return Ok(Outcome::Ok);
        }
    }
    for r in &reports {
        let last = r.levels.last().expect("a level");
        let secs: f64 = r.levels.iter().map(|l| l.seconds).sum();
        println!(
            "scene `{}` ({} N): solid model ({}), {}; base {}; {}, {} dofs and {:.0} MB \
             of factor on the last (h {} um, {} across the span{}), {:.1} s",
            r.scene,
            f(r.force_n, 3),
            if r.nonlinear {
                let its: usize = r.levels.iter().filter_map(|l| l.newton_iterations).sum();
                let fac: usize = r.levels.iter().filter_map(|l| l.factorisations).sum();
                let single: usize = r
                    .levels
                    .iter()
                    .filter_map(|l| l.single_precision_factorisations)
                    .sum();
                let precision = match single {
                    0 => String::new(),
                    s if s == fac => " in single precision, preconditioning CG".to_string(),
                    s => format!(", {s} in single precision"),
                };
                format!(
                    "geometrically nonlinear: Total Lagrangian, St. Venant-Kirchhoff, dead load; \
                     {}, {}{precision}",
                    count(its, "Newton iteration"),
                    count(fac, "factorisation")
                )
            } else {
                "linear".to_string()
            },
            r.part_solved,
            r.base,
            count(r.levels.len(), "level"),
            last.dofs,
            // Single precision takes 4 bytes an entry.
            last.factor_entries as f64
                * if last.single_precision_factorisations.unwrap_or(0) > 0
                    && last.single_precision_factorisations == last.factorisations
                {
                    4e-6
                } else {
                    8e-6
                },
            f(last.element_um, 0),
            f(last.span_element_um, 0),
            grading_text(r),
            secs
        );
        if r.contact_on_top_faces < 1.0 - 1e-9 {
            println!(
                "  contact: {:.0} % of the patch on upward faces (the rest over tooth sidewalls, \
                 its force moved onto the rest)",
                100.0 * r.contact_on_top_faces
            );
        }
        if last.edge_moved_um > 0.0 {
            println!(
                "  mesh: a feature line (an edge, a wall, a load's side) stands {:.3} um off \
                 the mesh line it merged into; read-outs take points that close outside the \
                 material from its nearest face",
                last.edge_moved_um
            );
        }
        let plate_name = if r.plate_rung == "large_deflection_plate" {
            "LD plate"
        } else {
            "linear plate"
        };
        println!(
            "  {:22} {:>12} {:>9} {:>12} {:>12} {:>13}",
            "quantity", "solid", "disc.", "extrapolated", plate_name, "plate - solid"
        );
        let e = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |v| format!("{v:.1e}"));
        for q in &r.quantities {
            println!(
                "  {:22} {:>9} {:3} {:>8} {:>12} {:>12} {:>13}",
                q.name,
                f(q.value, 4),
                q.unit,
                e(q.discretisation),
                f(q.extrapolated, 4),
                q.plate_value.map_or_else(|| "-".to_string(), |v| f(v, 4)),
                e(q.plate_difference)
            );
        }
        // What each island reads, term by term, on the finest level.
        let terms: Vec<String> = g
            .electrodes
            .iter()
            .zip(&last.readout.charge_terms_pc)
            .map(|(e, t)| {
                format!(
                    "{} {} / {} / {}",
                    e.name,
                    f(t[0], 4),
                    f(t[1], 4),
                    f(t[2], 4)
                )
            })
            .collect();
        println!(
            "  charge by piezo term (finest level, pC, d31 s1 / d32 s2 / d33 s3): {}",
            terms.join("; ")
        );
        if let Some(q) = r
            .quantities
            .iter()
            .find(|q| q.name == "max_stress_averaged")
        {
            // Averaged in compression (a load on a support): nothing opens, no finite factor.
            // Not read (no averaging square on the die) is no factor at all, never "inf".
            let sf = |s: f64| {
                if s > 0.0 {
                    f(g.fracture_strength_mpa / s, 2)
                } else if s < 0.0 {
                    "inf (in compression)".to_string()
                } else if s == 0.0 {
                    "inf".to_string()
                } else {
                    "not read".to_string()
                }
            };
            println!(
                "  safety factor {} from the averaged stress (fracture {} MPa; the {} \
                 says {})",
                sf(q.value),
                f(g.fracture_strength_mpa, 0),
                plate_name,
                q.plate_value.map_or_else(|| "-".into(), sf)
            );
        }
        if let Some(last) = r.levels.last() {
            if last.readout.edge_stress.is_empty() {
                let l = tactfab::sensor::edge_stress::critical_distance_um(
                    g.fracture_toughness_mpa_sqrt_m,
                    g.fracture_strength_mpa,
                );
                println!(
                    "  no sharp edge's stress read: none in the part solved, or the critical \
                     distance L / 2 = {} um is not small against the corner submodels' radius \
                     (the theory of critical distances' point method needs it so)",
                    f(0.5 * l, 4)
                );
            }
            // A corner in compression at L / 2 does not open: no factor to state.
            let opening = |stress_mpa: f64| {
                if stress_mpa > 0.0 {
                    format!(
                        "safety factor {}",
                        f(g.fracture_strength_mpa / stress_mpa, 3)
                    )
                } else {
                    "in compression there, no crack to open".to_string()
                }
            };
            for e in &last.readout.edge_stress {
                if let Some(along) = e.along_edge_um {
                    println!(
                        "  {} stress on the finest level {} MPa at L/2 = {} nm from a tooth's \
                         base corner and its edges (worst {} um along an edge from the corner, \
                         at x {} y {} mm; vertex submodels nested from a half-size of {} um, \
                         their own estimate {} MPa): {}",
                        e.kind.as_str(),
                        f(e.stress_mpa, 4),
                        f(e.read_at_um * 1e3, 3),
                        f(along, 4),
                        f(e.at_um[0] * 1e-3, 4),
                        f(e.at_um[1] * 1e-3, 4),
                        f(e.radius_um, 3),
                        f(e.submodel_error_mpa, 3),
                        opening(e.stress_mpa),
                    );
                    continue;
                }
                println!(
                    "  {} stress on the finest level {} MPa at L/2 = {} nm from the edge \
                     (section at x {} y {} mm; corner submodel of radius {} um, its own \
                     estimate {} MPa): {}",
                    e.kind.as_str(),
                    f(e.stress_mpa, 4),
                    f(e.read_at_um * 1e3, 3),
                    f(e.at_um[0] * 1e-3, 4),
                    f(e.at_um[1] * 1e-3, 4),
                    f(e.radius_um, 3),
                    f(e.submodel_error_mpa, 3),
                    opening(e.stress_mpa),
                );
            }
        }
        let box_um = tactfab::sensor::edge_stress::FINE_BRICK_BOX * g.plate_thickness_um;
        for c in &r.edge_thickness {
            match (c.eight_bricks_mpa, c.correction_mpa != 0.0) {
                (Some(eight), true) => println!(
                    "  {} through the thickness (level 0, 2, 4 and 8 bricks through the plate and \
                     the teeth, the 8 within {} um of the reading): {}, {}, {} MPa (order {}): \
                     {} MPa added to the finest level's value, {} MPa left in its disc. (the \
                     last difference at that rate, or at 2 lambda, the rate away from the \
                     corner, if slower)",
                    c.kind.as_str(),
                    f(box_um, 0),
                    f(c.two_bricks_mpa, 4),
                    f(c.four_bricks_mpa, 4),
                    f(eight, 4),
                    c.observed_order.map_or("-".to_string(), |p| f(p, 2)),
                    f(c.correction_mpa, 3),
                    f(c.error_mpa, 3)
                ),
                (eight, _) => println!(
                    "  {} through the thickness (level 0, 2 against 4 bricks through the plate and \
                     the teeth{}): {} against {} MPa, taken as an error of {} MPa in its disc. \
                     (the largest difference over 1 - 2^-lambda, the corner's rate)",
                    c.kind.as_str(),
                    eight.map_or(", 8 did not fit in memory".to_string(), |e| format!(
                        ", and {} MPa with 8, which do not converge monotonically",
                        f(e, 4)
                    )),
                    f(c.two_bricks_mpa, 4),
                    f(c.four_bricks_mpa, 4),
                    f(c.error_mpa, 3)
                ),
            }
        }
        if let Some((name, s)) = r.governing_stress() {
            println!(
                "  governing: {name}, {} MPa with its estimate: safety factor {} against the \
                 required {} (L = (1/pi)(K_Ic/sigma_0)^2, K_Ic {} MPa m^1/2, theory of critical \
                 distances)",
                f(s, 4),
                f(g.fracture_strength_mpa / s, 3),
                f(g.safety_factor, 2),
                f(g.fracture_toughness_mpa_sqrt_m, 3)
            );
            if r.graded_teeth == 0 && r.reads_tooth_bases() {
                // Measured on the bundled design: the uniform levels read the worst tooth base
                // a third low, beyond their estimate (README, "--graded on the solid rung").
                println!(
                    "  (uniform levels: they can miss the worst tooth base, beyond this estimate; \
                     --graded grades every level at the tooth base edges, ~4x the dofs)"
                );
            }
        }
        println!(
            "  converged: {} (tol {:.0e}; the peak principal stress sits at a re-entrant corner \
             and is reported, not required to converge: the edges' stresses at the critical \
             distance are); plate - solid is taken against the \
             extrapolated solid, which is known to within its disc.",
            if r.converged { "yes" } else { "no" },
            acc.tol_rel
        );
    }
    if let Some(path) = &args.json_file {
        println!("json: {}", path.display());
    }
    Ok(Outcome::Ok)
}

/// The plate's natural frequencies and the quasi-static check.
pub fn modes_text(m: &PlateModes) -> String {
    let mut s = format!(
        "natural frequencies: whole plate held at the supports as `support_model: {}` says, \
         teeth and the PVDF film's mass ({} kg/m^2) included, {}, {} dofs\n",
        tactfab::spelling::yaml(&m.support_model),
        f(m.film_kg_per_m2, 4),
        count(m.levels, "level"),
        m.dofs
    );
    for (i, mode) in m.modes.iter().enumerate() {
        s.push_str(&format!(
            "  mode {}: {} Hz (estimated error {})\n",
            i + 1,
            f(mode.freq_hz, 1),
            mode.error_rel
                .map_or_else(|| "n/a".to_string(), |e| format!("{e:.1e}"))
        ));
    }
    s.push_str(&format!(
        "  quasi-static: f1 is {}x the 5 Hz test force and {}x the 1 Hz pulse; a single mode \
         driven at 5 Hz departs from its static answer by {:.1e} (air in the gap not modelled)\n",
        f(m.above_test, 0),
        f(m.above_pulse, 0),
        m.quasi_static_error_at_test
    ));
    s
}

/// How the solid's bricks take their shears and its levels were graded, for its summary line.
fn grading_text(r: &tactfab::sensor::solid::SolidReport) -> String {
    let shear = if r.tied_shear {
        ", transverse shear tied"
    } else {
        ", plain bricks (--plain-shear)"
    };
    let grading = if r.graded {
        ", graded at the tooth base edges".to_string()
    } else if r.graded_teeth == 1 {
        ", graded at the base edges of the tooth the plate finds hottest".to_string()
    } else if r.graded_teeth > 1 {
        format!(
            ", graded at the base edges of the {} teeth the plate finds hottest",
            r.graded_teeth
        )
    } else {
        String::new()
    };
    let how = if r.local_refinement {
        "locally: hanging nodes"
    } else {
        "by lines across the die"
    };
    // Auto's choice with the factor sizes that made it.
    let local = match &r.grading_choice {
        Some(c) if !grading.is_empty() => {
            let (mine, other, other_how) = if r.local_refinement {
                (c.local_factor_entries, c.lines_factor_entries, "by lines")
            } else {
                (c.lines_factor_entries, c.local_factor_entries, "locally")
            };
            match (mine, other, &c.refused) {
                (Some(mine), Some(other), _) => format!(
                    " ({how}; the smaller factor, {:.0} M entries against {:.0} M {other_how})",
                    mine as f64 * 1e-6,
                    other as f64 * 1e-6
                ),
                // The other grading could not be analysed: say why this one was solved.
                (_, _, Some(why)) => format!(" ({how}; {other_how} was refused: {why})"),
                _ => format!(" ({how})"),
            }
        }
        _ if r.local_refinement && !grading.is_empty() => format!(" ({how})"),
        _ => String::new(),
    };
    format!("{shear}{grading}{local}")
}
