//! `tactfab etch FILE [--json] [--simulate]`: the etch plan, and the simulated tooth.

use anyhow::Context;
use tactfab::etch::sim::richardson::ToleranceDecision;
use tactfab::etch::sim::sensitivity::{self, Sensitivity};
use tactfab::etch::sim::sizing::{self, Sizing};
use tactfab::etch::sim::{BackSimulation, SimError, ToothSimulation};
use tactfab::etch::EtchPlan;
use tactfab::export::file::{self, Proof};
use tactfab::layout::MaskSet;
use tactfab::process::Process;
use tactfab::spelling::yaml;

use super::args::EtchArgs;
use super::output::{checks, f};
use super::{load, Outcome};

pub fn run(args: &EtchArgs) -> anyhow::Result<Outcome> {
    let loaded = load(&args.process)?;
    if let Some(path) = &args.svg {
        // Before the simulation (after the process file's own errors): neither plot may cost
        // the user a file.
        for p in [path.clone(), back_svg_path(path)] {
            file::check(&p, Proof::SvgStamp, &[&args.process.file]).context("--svg")?;
        }
    }
    let mut plan = tactfab::etch::plan(&loaded.process);
    let sim = if args.simulate {
        Some(simulate(args, &loaded.process, &mut plan)?)
    } else {
        None
    };
    if args.json {
        let mut v = serde_json::to_value(&plan)?;
        v["defaults_used"] = serde_json::to_value(&loaded.defaults_used)?;
        if let Some((s, sweep, sizing, back)) = &sim {
            v["simulation"] = serde_json::to_value(s)?;
            v["simulation"]["back"] = serde_json::to_value(back)?;
            if let Some(sw) = sweep {
                v["simulation"]["sensitivity"] = serde_json::to_value(sw)?;
            }
            if let Some(z) = sizing {
                v["sizing"] = serde_json::to_value(z)?;
            }
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let mut out = String::new();
        for o in &plan.oxidations {
            out.push_str(&format!(
                "oxidation `{}`: {} h at {} C -> {} um per face (B = {} um2/h, B/A = {} um/h)",
                o.name,
                o.time_h,
                o.temp_c,
                f(o.thickness_um, 3),
                f(o.b_um2_per_h, 4),
                f(o.b_over_a_um_per_h, 3)
            ));
            if let (Some(e), Some(t)) = (o.expected_thickness_um, o.time_for_expected_h) {
                out.push_str(&format!("; {e} um would need {} h", f(t, 2)));
            }
            out.push('\n');
        }
        for r in &plan.resists {
            out.push_str(&format!(
                "resist `{}`: {} at {} rpm -> {} um\n",
                r.name,
                r.resist,
                r.speed_rpm,
                f(r.thickness_um, 2)
            ));
        }
        for e in &plan.oxide_etches {
            out.push_str(&format!(
                "oxide etch `{}`: {} um at {} um/min -> {} min with over-etch\n",
                e.name,
                f(e.oxide_um, 3),
                e.rate_um_per_min,
                f(e.time_min, 1)
            ));
        }
        for s in &plan.steps {
            out.push_str(&format!(
                "silicon etch `{}`: {} {} wt % at {} C, side {}, target {} um\n",
                s.name,
                s.etchant.label(),
                s.concentration_wt_pct,
                s.temp_c,
                yaml(&s.side),
                s.depth_um
            ));
            out.push_str(&format!(
                "  rate (100) {} um/h [{}], model {} um/h; (110) {} um/h; (111) {} um/h\n",
                f(s.rate_um_per_h, 2),
                s.rate_source,
                f(s.model_rate_um_per_h, 2),
                f(s.rate_110_um_per_h, 2),
                f(s.rate_111_um_per_h, 3)
            ));
            out.push_str(&format!(
                "  time {} h (target depth needs {} h) -> {} um per face\n",
                f(s.time_h, 3),
                f(s.time_for_depth_h, 3),
                f(s.achieved_depth_um, 1)
            ));
            out.push_str(&format!(
                "  sidewall run-out {} um, undercut {} um, min street {} um",
                f(s.sidewall_run_out_um, 1),
                f(s.undercut_um, 1),
                f(s.min_street_um, 1)
            ));
            if let Some(b) = s.mesa_base_um {
                out.push_str(&format!(", tooth base {} um", f(b, 1)));
            }
            out.push('\n');
            out.push_str(&format!(
                "  {} mask: {} um consumed, {} um left\n",
                yaml(&s.mask),
                f(s.mask_consumed_um, 3),
                f(s.mask_remaining_um, 3)
            ));
            if let Some(c) = &s.compensation {
                let shape = match c.bar_width_um {
                    Some(b) => format!(
                        "bar {} x {} um (L = h/{})",
                        f(c.side_um, 1),
                        f(b, 1),
                        c.ratio
                    ),
                    None => format!("square {} um (a = h/{})", f(c.side_um, 1), c.ratio),
                };
                let (reach, gap) = if c.reach.x_um == c.reach.y_um {
                    (
                        format!("{} um", f(c.reach.x_um, 1)),
                        format!("{} um", f(c.min_gap.x_um, 1)),
                    )
                } else {
                    (
                        format!(
                            "{} um along x and {} um along y",
                            f(c.reach.x_um, 1),
                            f(c.reach.y_um, 1)
                        ),
                        format!(
                            "{} / {} um (x / y)",
                            f(c.min_gap.x_um, 1),
                            f(c.min_gap.y_um, 1)
                        ),
                    )
                };
                out.push_str(&format!(
                    "  compensation {}: {shape}, reaches {reach}, needs {gap} between facing \
                     corners\n",
                    yaml(&c.kind),
                ));
            }
        }
        out.push_str(&format!(
            "plate: {} um (wafer {} - front {} - back {}), {}-{} um over the wafer tolerance; \
             target {} um\n",
            f(plan.plate_thickness_um, 1),
            plan.wafer_thickness_um,
            f(plan.front_depth_um, 1),
            f(plan.back_depth_um, 1),
            f(plan.plate_range_um[0], 0),
            f(plan.plate_range_um[1], 0),
            plan.plate_target_um
        ));
        let [y0, y1] = plan.channel_floor_y_um;
        out.push_str(&format!(
            "channel floor: y {}-{} um between the etched {{111}} walls ({} um span; the plate is \
             clamped there)\n",
            f(y0, 1),
            f(y1, 1),
            f(y1 - y0, 1)
        ));
        if let Some((s, sweep, sizing, back)) = &sim {
            out.push_str(&simulation_text(s, sweep.as_ref()));
            if let Some(b) = back {
                out.push_str(&back_text(b));
            }
            if let Some(z) = sizing {
                out.push_str(&sizing_text(z));
            }
        }
        out.push_str(&checks(&plan.warnings));
        print!("{out}");
    }
    Ok(if plan.has_errors() {
        Outcome::CheckFailed
    } else {
        Outcome::Ok
    })
}

/// What `--simulate` computed: the tooth, the sweep and the sizing when asked, the back corner.
type Simulated = (
    ToothSimulation,
    Option<Sensitivity>,
    Option<Sizing>,
    Option<BackSimulation>,
);

/// Runs the tooth simulation (and the sweep), the back corner, writes the SVGs (the back's
/// beside the tooth's, `<stem>-back.svg`), adds the finding to the plan.
fn simulate(args: &EtchArgs, p: &Process, plan: &mut EtchPlan) -> anyhow::Result<Simulated> {
    let masks = tactfab::layout::build(p, plan)?;
    let sim = tactfab::etch::sim::simulate(p, plan, &masks, args.grid_um)?;
    let back = tactfab::etch::sim::simulate_back(p, plan, &masks, args.grid_um)?;
    let sweep = when(
        args.sensitivity,
        sensitivity::sweep,
        p,
        plan,
        &masks,
        args.grid_um,
    )?;
    let sizing = when(
        args.size_compensation,
        sizing::size,
        p,
        plan,
        &masks,
        args.grid_um,
    )?;
    if let Some(path) = &args.svg {
        let inputs = [args.process.file.as_path()];
        let plan_view = file::stamp_svg(tactfab::etch::sim::svg::plan_view(&sim));
        file::write(path, plan_view.as_bytes(), Proof::SvgStamp, &inputs).context("--svg")?;
        if let Some(b) = &back {
            let back_view = file::stamp_svg(tactfab::etch::sim::svg::back_plan_view(b));
            file::write(
                &back_svg_path(path),
                back_view.as_bytes(),
                Proof::SvgStamp,
                &inputs,
            )
            .context("--svg")?;
        }
    }
    plan.warnings.extend(tactfab::etch::sim::finding(&sim));
    Ok((sim, sweep, sizing, back))
}

/// A whole-design analysis on the simulation grid (the sweep, the sizing).
type Analysis<T> = fn(&Process, &EtchPlan, &MaskSet, f64) -> Result<T, SimError>;

/// Runs `analysis` when its flag is set.
fn when<T>(
    on: bool,
    analysis: Analysis<T>,
    p: &Process,
    plan: &EtchPlan,
    masks: &MaskSet,
    grid_um: f64,
) -> Result<Option<T>, SimError> {
    on.then(|| analysis(p, plan, masks, grid_um)).transpose()
}

/// `DIR/tooth.svg` -> `DIR/tooth-back.svg` (no extension: `-back.svg` appended).
fn back_svg_path(front: &std::path::Path) -> std::path::PathBuf {
    let stem = front
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    front.with_file_name(format!("{stem}-back.svg"))
}

/// The back corner's lines of the text report.
/// "; on the G um grid C, error E, extrapolated X" for a Richardson estimate, or nothing.
fn richardson_clause(e: Option<tactfab::etch::sim::back::Extrapolated>) -> String {
    e.map_or(String::new(), |e| {
        format!(
            "; on the {} um grid {}, error {}, extrapolated {}",
            f(e.coarse_grid_um, 2),
            f(e.coarse_um, 1),
            f(e.error_um, 1),
            f(e.extrapolated_um, 1)
        )
    })
}

fn back_text(b: &BackSimulation) -> String {
    let mut out = format!(
        "simulated back (U-channel) at support 1's corner, {} h ({}) on a {} um grid ({} nodes, \
         {} steps):\n",
        f(b.time_h, 2),
        b.steps
            .iter()
            .map(|s| format!("`{}`", s.name))
            .collect::<Vec<_>>()
            .join(", "),
        f(b.grid_um, 2),
        b.nodes,
        b.time_steps
    );
    out.push_str(&format!(
        "  channel floor {} um deep, its edge at y {} um (plan {} um{}); floor {} um wide \
         (plan {} um)\n",
        f(b.floor_depth_um, 1),
        f(b.floor_edge_y_um, 1),
        f(b.plan_floor_edge_y_um, 1),
        richardson_clause(b.floor_edge_error),
        f(b.floor_width_um, 1),
        f(b.plan_floor_width_um, 1)
    ));
    out.push_str(&format!(
        "  wall run-out {} um (closed form h / tan 54.74 deg {} um), edge undercut {} um (closed \
         form {} um)\n",
        f(b.run_out_um, 1),
        f(b.closed_form_run_out_um, 1),
        f(b.edge_undercut_um, 1),
        f(b.closed_form_undercut_um, 1)
    ));
    for c in &b.corners {
        out.push_str(&format!(
            "  {} corner at ({}, {}) um: {} along its bisector (< 0 receded into the mask; \
             closed form {} um){}\n",
            c.kind,
            f(c.at_um[0], 1),
            f(c.at_um[1], 1),
            c.deviation_um
                .map_or("beyond the cell".into(), |d| format!("{} um", f(d, 1))),
            f(c.closed_form_um, 1),
            richardson_clause(c.error)
        ));
    }
    out
}

/// The sizing's lines of the text report.
fn sizing_text(z: &Sizing) -> String {
    let mut out = format!(
        "compensation sizing by simulation ({} h, h = {} um, tolerance {} um; grid {} um and {} \
         um, Richardson; {} simulations, at most {} bisection steps per geometry):\n",
        f(z.time_h, 2),
        z.depth_um,
        z.tolerance_um,
        f(z.grid_um, 2),
        f(z.coarse_grid_um, 2),
        z.evaluations,
        z.max_bisection_steps
    );
    for g in &z.geometries {
        let ratio = g.sized_ratio.map_or("none".into(), |r| f(r, 3));
        out.push_str(&format!(
            "  {}{}: a up to {} um ({}); {} a = {} um (ratio h/a {}), corner {} um{}\n",
            yaml(&g.geometry),
            g.bar_width_um.map_or(String::new(), |b| format!(
                " (a is the bar's length; {} um wide)",
                f(b, 1)
            )),
            f(g.largest_a_um, 1),
            g.limited_by,
            if g.within_tolerance {
                "sized"
            } else {
                "no a meets the tolerance; best"
            },
            f(g.sized_a_um, 1),
            ratio,
            f(g.sized_corner_deviation_um, 1),
            g.bracket_a_um.map_or(String::new(), |[l, h]| format!(
                "; the corner's zero between a = {} and {} um",
                f(l, 1),
                f(h, 1)
            ))
        ));
        out.push_str(&format!(
            "    rule a = h/{} = {} um: {}{}\n",
            z.rule_ratio,
            f(g.rule_a_um, 1),
            yaml(&g.rule),
            g.rule_corner_deviation_um
                .map_or(String::new(), |c| format!(" (corner {} um)", f(c, 1)))
        ));
    }
    out
}

/// The simulation's lines of the text report.
fn simulation_text(s: &ToothSimulation, sweep: Option<&Sensitivity>) -> String {
    let mut out = format!(
        "simulated tooth ({}, {}) cell, {} h on a {} um grid ({} nodes, {} steps): rates um/h \
         (100) {} (110) {} (111) {} (311) {} (411) {}\n",
        s.tooth[0],
        s.tooth[1],
        f(s.time_h, 2),
        f(s.grid_um, 2),
        s.nodes,
        s.time_steps,
        f(s.rates.r100_um_per_h, 2),
        f(s.rates.r110_um_per_h, 2),
        f(s.rates.r111_um_per_h, 3),
        s.rates.r311_um_per_h.map_or("-".into(), |r| f(r, 2)),
        s.rates
            .r411_um_per_h
            .map_or("interpolated".into(), |r| f(r, 2)),
    );
    out.push_str(&format!(
        "  corner {} um along the diagonal from the drawn corner ({}; tolerance {} um), edge \
         undercut {} um; compensator consumed {}\n",
        f(s.corner_deviation_um, 1),
        yaml(&s.corner_shape),
        s.tolerance_um,
        f(s.edge_undercut_um, 1),
        s.compensator_consumed_h
            .map_or("never (or none drawn)".into(), |t| format!(
                "at {} h",
                f(t, 2)
            ))
    ));
    out.push_str(&match (&s.corner_error, s.corner_bridged) {
        (Some(e), _) => format!(
            "  corner on the {} um grid {} um: discretisation error {} um (Richardson, order {}), \
             extrapolated {} um; tolerance {}\n",
            f(e.coarse_grid_um, 2),
            f(e.coarse_corner_deviation_um, 1),
            f(e.error_um, 1),
            e.order,
            f(e.extrapolated_corner_deviation_um, 1),
            match e.decision {
                ToleranceDecision::Within => "met",
                ToleranceDecision::Beyond => "missed",
                ToleranceDecision::WithinError =>
                    "within the discretisation error (a finer grid decides)",
            }
        ),
        (None, true) => {
            "  the top bridges to the neighbour tooth: corner error not estimated\n".into()
        }
        (None, false) => "  corner error not estimated (one grid)\n".into(),
    });
    out.push_str(&format!(
        "  floor {} um deep; residue up to {} um over {} um2 of the cell; facets {}\n",
        f(s.floor_depth_um, 1),
        f(s.floor_residue_height_um, 1),
        f(s.floor_residue_area_um2, 0),
        s.facets
            .iter()
            .map(|x| format!("{{{}}} {} %", x.family, f(100.0 * x.area_share, 0)))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    if let Some(sw) = sweep {
        for c in &sw.cases {
            out.push_str(&format!(
                "  sensitivity {}: corner {} um\n",
                c.case,
                f(c.corner_deviation_um, 1)
            ));
        }
    }
    out
}
