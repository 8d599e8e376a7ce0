//! `tactfab masks FILE -o DIR [--format gds,svg]`: mask set, inventory and DRC.
//!
//! Everything is rendered in memory, written to a temporary directory beside DIR, then renamed
//! into place: an error leaves no partial output. A DRC failure still writes the set (to be
//! inspected) but exits 1 and says so.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::ValueEnum;
use tactfab::export::gds::GdsOptions;

use super::{load, MasksArgs, Outcome};

/// Output formats; the .lyp goes with the GDS.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Gds,
    Svg,
}

pub fn run(args: &MasksArgs) -> anyhow::Result<Outcome> {
    let loaded = load(&args.process)?;
    let p = &loaded.process;
    let unknown = tactfab::drc::unknown_waivers(p);
    if !unknown.is_empty() {
        anyhow::bail!(
            "drc.waive: unknown rule code(s) {}\n  hint: codes are {}",
            unknown.join(", "),
            tactfab::drc::CODES
                .iter()
                .map(|(c, _)| *c)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let plan = tactfab::etch::plan(p);
    let set = tactfab::layout::build(p, &plan)?;
    let drc = tactfab::drc::check(&set, p, &plan);

    let epoch = super::source_date_epoch()?;
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
    }
    if formats.contains(&Format::Svg) {
        for m in &set.masks {
            files.push((
                format!("{}-{}.svg", set.device, m.name),
                set.to_svg(m)?.into_bytes(),
            ));
        }
    }
    write_all(&args.out, &files)?;

    let mut out = set.inventory();
    if !set.warnings.is_empty() {
        out.push_str("layout warnings:\n");
        for w in &set.warnings {
            out.push_str(&format!("  warning[{}]: {}\n", w.code, w.message));
        }
    }
    let plan_errors = plan.warnings.iter().filter(|c| c.is_error()).count();
    if plan_errors > 0 {
        out.push_str(&format!(
            "etch plan: {plan_errors} errors (see `tactfab etch`)\n"
        ));
    }
    out.push_str(&drc.summary(10));
    for (name, bytes) in &files {
        out.push_str(&format!(
            "wrote {} ({} bytes)\n",
            args.out.join(name).display(),
            bytes.len()
        ));
    }
    if drc.passed() {
        out.push_str("DRC passed\n");
    } else {
        out.push_str(&format!(
            "DRC FAILED: {} violations; the files are written for inspection, do not release them \
             (waive a rule in `drc.waive` only on purpose)\n",
            drc.failing()
        ));
    }
    print!("{out}");
    Ok(if drc.passed() {
        Outcome::Ok
    } else {
        Outcome::CheckFailed
    })
}

/// Writes every file into a temporary directory beside `dir`, then renames into place.
pub fn write_all(dir: &Path, files: &[(String, Vec<u8>)]) -> anyhow::Result<()> {
    let parent: PathBuf = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent)
        .with_context(|| format!("cannot create {}", parent.display()))?;
    let stem = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "masks".into());
    let tmp = parent.join(format!(".{stem}.tactfab-tmp-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let result = (|| -> anyhow::Result<()> {
        std::fs::create_dir(&tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
        for (name, bytes) in files {
            std::fs::write(tmp.join(name), bytes)
                .with_context(|| format!("cannot write {}", tmp.join(name).display()))?;
        }
        if !dir.exists() {
            std::fs::rename(&tmp, dir)
                .with_context(|| format!("cannot move the output to {}", dir.display()))?;
            return Ok(());
        }
        if !dir.is_dir() {
            anyhow::bail!("{} exists and is not a directory", dir.display());
        }
        for (name, _) in files {
            std::fs::rename(tmp.join(name), dir.join(name))
                .with_context(|| format!("cannot move {name} into {}", dir.display()))?;
        }
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&tmp);
    result
}
