//! Export of a [`MaskSet`](crate::layout::MaskSet): GDSII ([`gds`]), SVG per mask ([`svg`]) and a
//! KLayout layer-properties file ([`lyp`]). This is the only place where f64 um become integer nm
//! (database unit 1 nm, user unit 1 um).

pub mod dir;
pub mod file;
pub mod gds;
pub mod lyp;
pub mod lyrdb;
pub mod svg;
pub mod xml;

use std::path::Path;

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// gds21's own error is not Send + Sync: its message is kept instead.
    #[error("GDS: {0}")]
    Gds(String),
    #[error("coordinate {value_um} um does not fit a 32-bit nm integer")]
    OutOfRange { value_um: f64 },
    #[error("{}: {cause}", path.display())]
    Io {
        path: std::path::PathBuf,
        cause: std::io::Error,
    },
    #[error("{0}")]
    Invalid(String),
    /// The output directory holds what tactfab cannot prove it wrote.
    #[error(
        "{}: not replaced: it holds {} that tactfab did not write (or that changed since): {}\n  \
         hint: choose another directory, or pass {flag} to replace it with everything in it",
        dir.display(),
        if entries.len() == 1 { "an entry" } else { "entries" },
        entries.join(", ")
    )]
    Foreign {
        dir: std::path::PathBuf,
        entries: Vec<String>,
        flag: String,
    },
    /// An input file lies inside the output directory.
    #[error(
        "{}: not replaced: the input {} lies inside it\n  hint: write the output elsewhere",
        dir.display(),
        input.display()
    )]
    InputInside {
        dir: std::path::PathBuf,
        input: std::path::PathBuf,
    },
    /// An output file's path holds what tactfab cannot prove it wrote ([`mod@file`]).
    #[error(
        "{}: not replaced: tactfab did not write it (or it changed since)\n  \
         hint: name another output path, or move the file away first",
        path.display()
    )]
    ForeignFile { path: std::path::PathBuf },
    /// An output file's path is an input file.
    #[error(
        "{}: not replaced: it is the input {}\n  hint: name another output path",
        path.display(),
        input.display()
    )]
    InputFile {
        path: std::path::PathBuf,
        input: std::path::PathBuf,
    },
}

/// um (already on the 1 nm grid) to integer nm.
pub fn nm(value_um: f64) -> Result<i32, ExportError> {
    let v = (value_um * 1000.0).round();
    if !v.is_finite() || v < f64::from(i32::MIN) || v > f64::from(i32::MAX) {
        return Err(ExportError::OutOfRange { value_um });
    }
    Ok(v as i32)
}

/// nm integer as um with exactly 3 decimals (stable text, no float formatting).
pub fn um_text(nm: i64) -> String {
    let sign = if nm < 0 { "-" } else { "" };
    let a = nm.unsigned_abs();
    format!("{sign}{}.{:03}", a / 1000, a % 1000)
}

/// nm integer as mm with exactly 6 decimals.
pub fn mm_text(nm: i64) -> String {
    let sign = if nm < 0 { "-" } else { "" };
    let a = nm.unsigned_abs();
    format!("{sign}{}.{:06}", a / 1_000_000, a % 1_000_000)
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so a
/// failed write never leaves a truncated file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    let io = |cause| ExportError::Io {
        path: path.to_path_buf(),
        cause,
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    remove_stale_temporaries(dir, &name);
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}

/// Removes `.<name>.tmp-<pid>` files beside `name` that a killed run of [`write_atomic`] left
/// (their process no longer runs).
fn remove_stale_temporaries(dir: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let prefix = format!(".{name}.tmp-");
    for entry in entries.flatten() {
        let stale = entry
            .file_name()
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix)?.parse::<u32>().ok())
            .is_some_and(|pid| pid != std::process::id() && !dir::alive(pid));
        if stale && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_killed_writes_temporary_is_removed_by_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plot.svg");
        // A pid above the kernel's limit (2^22) never runs; another file's temporary stays.
        let dead = dir.path().join(".plot.svg.tmp-4194305");
        let other = dir.path().join(".notes.svg.tmp-4194305");
        for p in [&dead, &other] {
            std::fs::write(p, "half").unwrap();
        }
        write_atomic(&path, b"whole").unwrap();
        assert!(!dead.exists() && other.exists());
        assert_eq!(std::fs::read(&path).unwrap(), b"whole");
    }

    #[test]
    fn fixed_decimals() {
        assert_eq!(um_text(20_000_001), "20000.001");
        assert_eq!(um_text(-1_500), "-1.500");
        assert_eq!(um_text(0), "0.000");
        assert_eq!(mm_text(30_000_000), "30.000000");
        assert_eq!(nm(20000.001).unwrap(), 20_000_001);
        assert!(nm(3e6).is_err());
    }
}
