//! `tactfab check FILE`: validate, summarise, list defaults and every warning.

use tactfab::spelling::yaml;

use super::output::{checks, f};
use super::{load, Outcome, ProcessArgs};

pub fn run(args: &ProcessArgs) -> anyhow::Result<Outcome> {
    let loaded = load(args)?;
    let p = &loaded.process;
    let plan = tactfab::etch::plan(p);
    let g = &p.geometry;
    let mut out = String::new();
    out.push_str(&format!(
        "{}: {} rev {} ({})\n",
        args.file.display(),
        p.device.name,
        p.device.revision,
        p.device.description
    ));
    out.push_str(&format!(
        "  wafer ({}) {} +/- {} um, {} mm; die {} x {} mm, plate {} um, supports {} mm, teeth {} \
         {} um high\n",
        "100",
        p.wafer.thickness_um,
        p.wafer.thickness_tolerance_um,
        p.wafer.diameter_mm,
        g.die_length_um / 1000.0,
        g.die_width_um / 1000.0,
        g.plate_thickness_um,
        g.support_width_um / 1000.0,
        yaml(&g.teeth.pattern),
        g.teeth.height_um
    ));
    out.push_str(&format!(
        "  {} masks, {} steps, {} etch steps\n",
        p.masks.len(),
        p.steps.len(),
        plan.steps.len()
    ));
    out.push_str(&format!(
        "  computed: plate {} um (target {}), oxide {} um\n",
        f(plan.plate_thickness_um, 1),
        plan.plate_target_um,
        f(plan.oxide_thickness_um, 3)
    ));
    if !loaded.overrides.is_empty() {
        out.push_str("overrides:\n");
        for (path, arg) in &loaded.overrides {
            out.push_str(&format!("  {path} <- --set {arg}\n"));
        }
    }
    if !loaded.defaults_used.is_empty() {
        out.push_str("defaults used (from ../shared/reference):\n");
        for d in &loaded.defaults_used {
            out.push_str(&format!("  {} = {}  {}\n", d.path, d.value, d.source));
        }
    }
    let errors = plan.warnings.iter().filter(|c| c.is_error()).count();
    out.push_str(&format!(
        "checks: {} errors, {} warnings\n",
        errors,
        plan.warnings.len() - errors
    ));
    out.push_str(&checks(&plan.warnings));
    print!("{out}");
    Ok(if plan.has_errors() {
        Outcome::CheckFailed
    } else {
        Outcome::Ok
    })
}
