//! `tactfab masks FILE -o DIR [--format gds,svg]`: mask set, inventory and DRC.
//!
//! Everything is rendered in memory and written as one directory
//! ([`tactfab::export::dir::write_dir_atomic`]): an error leaves no partial output, and DIR holds
//! the files of one run, never a mix. A DRC failure still writes the set (to be inspected) but
//! exits 1 and says so.

use tactfab::export::gds::GdsOptions;

use super::args::{Format, MasksArgs};
use super::{check_out, design, write_dir, Outcome};

pub fn run(args: &MasksArgs) -> anyhow::Result<Outcome> {
    let (_, design) = design(&args.process)?;
    check_out(&args.out, args.replace, &args.process)?;
    let (p, plan, set) = (&design.process, &design.plan, &design.masks);
    let drc = tactfab::drc::check(set, p, plan);

    let epoch = args.date.epoch_s;
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let formats = if args.format.is_empty() {
        vec![Format::Gds, Format::Svg]
    } else {
        args.format.clone()
    };
    if formats.contains(&Format::Gds) {
        files.push((
            format!("{}.gds", set.device),
            set.to_gds(&GdsOptions {
                date_epoch_s: epoch,
            })?,
        ));
        files.push((format!("{}.lyp", set.device), set.to_lyp().into_bytes()));
        files.push((
            format!("{}-drc.lyrdb", set.device),
            tactfab::export::lyrdb::to_lyrdb(&drc, set).into_bytes(),
        ));
    }
    files.push((
        format!("{}-drc.txt", set.device),
        drc.summary(usize::MAX).into_bytes(),
    ));
    if formats.contains(&Format::Svg) {
        for m in &set.masks {
            files.push((
                format!("{}-{}.svg", set.device, m.name),
                set.to_svg(m)?.into_bytes(),
            ));
        }
        files.push((
            format!("{}-wafer.svg", set.device),
            set.wafer_map_svg()?.into_bytes(),
        ));
    }
    let mut out = set.inventory();
    if !set.warnings.is_empty() {
        out.push_str("layout warnings:\n");
        for w in &set.warnings {
            out.push_str(&format!("  {w}\n"));
        }
    }
    let plan_errors = plan.warnings.iter().filter(|c| c.is_error()).count();
    if plan_errors > 0 {
        out.push_str(&format!(
            "etch plan: {plan_errors} errors (see `tactfab etch`)\n"
        ));
    }
    out.push_str(&drc.summary(10));
    if !drc.violations.is_empty() {
        out.push_str(&format!(
            "  (every violation: {d}-drc.txt; in KLayout: klayout {d}.gds -m {d}-drc.lyrdb)\n",
            d = set.device
        ));
    }
    let verdict = if drc.passed() {
        "DRC passed\n".to_string()
    } else {
        format!(
            "DRC FAILED: {} violations; the files are written for inspection, do not release them \
             (waive a rule in `drc.waive` only on purpose)\n",
            drc.failing()
        )
    };
    write_dir(&args.out, &files, args.replace, &args.process)?;
    for (name, bytes) in &files {
        out.push_str(&format!(
            "wrote {} ({} bytes)\n",
            args.out.join(name).display(),
            bytes.len()
        ));
    }
    print!("{out}{verdict}");
    Ok(if drc.passed() {
        Outcome::Ok
    } else {
        Outcome::CheckFailed
    })
}
