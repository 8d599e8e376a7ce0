//! `tactfab etch FILE [--json]`: the etch plan.

use tactfab::spelling::yaml;

use super::args::EtchArgs;
use super::output::{checks, f};
use super::{load, Outcome};

pub fn run(args: &EtchArgs) -> anyhow::Result<Outcome> {
    let loaded = load(&args.process)?;
    let plan = tactfab::etch::plan(&loaded.process);
    if args.json {
        let mut v = serde_json::to_value(&plan)?;
        v["defaults_used"] = serde_json::to_value(&loaded.defaults_used)?;
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
                out.push_str(&format!(
                    "  compensation {}: square {} um (a = h/{}), reaches {} um, needs {} um \
                     between facing corners\n",
                    yaml(&c.kind),
                    f(c.side_um, 1),
                    c.ratio,
                    f(c.reach_um, 1),
                    f(c.min_gap_um, 1)
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
        out.push_str(&checks(&plan.warnings));
        print!("{out}");
    }
    Ok(if plan.has_errors() {
        Outcome::CheckFailed
    } else {
        Outcome::Ok
    })
}
