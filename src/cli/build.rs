//! `tactfab build FILE -o DIR`: everything for one process file, written atomically.

use tactfab::report::{build, summary, Options, SolidCheck};

use super::args::{BuildArgs, GradingArg};
use super::output::count;
use super::{
    check_out, design, origin, solid_levels, write_dir, Outcome, Progress, VERIFY_SOLID_LEVELS,
};

/// The summary's name.
pub const SUMMARY: &str = "build.json";

pub fn run(args: &BuildArgs) -> anyhow::Result<Outcome> {
    let (loaded, design) = design(&args.process)?;
    check_out(&args.out, args.replace, &args.process)?;
    let opts = Options {
        origin: origin(&args.process, &loaded),
        fe: Some(args.accuracy.into()),
        gds_epoch_s: args.date.epoch_s,
        allow_unconverged: args.gate.allow_unconverged,
        verify_solid: args.verify_solid.then_some(SolidCheck {
            levels: solid_levels(
                args.solid_levels,
                VERIFY_SOLID_LEVELS,
                usize::from(args.accuracy.max_levels),
            ),
            graded: args.graded,
            tied_shear: !args.plain_shear,
            grading: GradingArg::or_auto(args.solid_grading),
        }),
    };
    let built = {
        let progress = Progress::new();
        build(&loaded, &design, &opts, &mut |s| progress.stage(s))?
    };
    let mut files = built.files();
    let s = summary(&built, &files);
    files.push((
        SUMMARY.to_string(),
        (serde_json::to_string_pretty(&s)? + "\n").into_bytes(),
    ));
    write_dir(&args.out, &files, args.replace, &args.process)?;

    let mut out = String::new();
    let errors = built.plan.warnings.iter().filter(|c| c.is_error()).count();
    out.push_str(&format!(
        "{} rev {}: {} files in {}\n",
        s.device,
        s.revision,
        files.len(),
        args.out.display()
    ));
    out.push_str(&format!(
        "  checks: {errors} errors, {} warnings (see the traveler)\n",
        built.plan.warnings.len() - errors
    ));
    out.push_str(&format!(
        "  DRC: {} violations, {} failing\n",
        s.drc_violations, s.drc_failing
    ));
    match &built.fe {
        Some(fe) => {
            for sc in &fe.scenes {
                let limits = if sc.limits.is_empty() {
                    "no limits".to_string()
                } else {
                    sc.limits
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join("; ")
                };
                let ms = built
                    .fe_reports
                    .iter()
                    .find(|r| r.scene == sc.name)
                    .map_or(0.0, |r| r.solve_ms);
                // A safety-factor limit states the factor itself, with its error.
                let safety = if sc
                    .limits
                    .iter()
                    .any(|c| c.limit == tactfab::process::LimitKind::MinSafetyFactor)
                {
                    String::new()
                } else {
                    let sf = sc.stress_from.judged_text(sc.safety_factor, 2, "");
                    format!(", safety factor {sf}")
                };
                // The scene's warnings by code, so a factor under the required one is not
                // read past on the terminal (the traveler and build.json give each in full).
                let mut warned: Vec<String> = Vec::new();
                for w in &sc.warnings {
                    let code = w.code.to_string();
                    if !warned.contains(&code) {
                        warned.push(code);
                    }
                }
                let warned = if warned.is_empty() {
                    String::new()
                } else {
                    format!("; warnings: {}", warned.join(", "))
                };
                out.push_str(&format!(
                    "  FE `{}`: {:.3} mV/N ({}){safety}; {}{warned} ({ms:.0} ms)\n",
                    sc.name, sc.sensitivity_mv_per_n, sc.most_sensitive, limits
                ));
            }
        }
        None => out.push_str("  FE: no scenes declared in checks.scenes\n"),
    }
    if let Some(first) = built.solid_check.first() {
        let grading = if first.graded {
            ", graded at the tooth base edges".to_string()
        } else if first.graded_teeth > 0 {
            format!(
                ", graded at the plate's hottest teeth ({})",
                if first.local_refinement {
                    "locally"
                } else {
                    "by lines"
                }
            )
        } else if first.reads_tooth_bases() {
            " (uniform: can miss the worst tooth base; --graded)".to_string()
        } else {
            String::new()
        };
        let shear = if first.tied_shear {
            ", transverse shear tied"
        } else {
            ", plain bricks (--plain-shear)"
        };
        out.push_str(&format!(
            "  solid rung: {} on {}{grading}{shear}, in {}-solid-check.json\n",
            count(built.solid_check.len(), "scene"),
            count(first.levels.len(), "level"),
            s.device
        ));
    }
    let (_, html) = built.traveler_names();
    out.push_str(&format!("  traveler: {}\n", args.out.join(html).display()));
    if s.failures.is_empty() {
        out.push_str("build passed\n");
    } else {
        out.push_str(&format!("build FAILED: {} checks\n", s.failures.len()));
        for f in &s.failures {
            out.push_str(&format!("  FAIL: {f}\n"));
        }
    }
    print!("{out}");
    Ok(if s.passed {
        Outcome::Ok
    } else {
        Outcome::CheckFailed
    })
}
