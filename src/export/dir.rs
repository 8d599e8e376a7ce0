//! A whole output directory written as one unit, and never at the cost of a user's file.
//!
//! The files are built in a temporary directory beside the target, with a manifest
//! ([`MANIFEST`], `sha256sum` format: the SHA-256 and name of every file tactfab wrote), then
//! swapped into place in one step (Linux `renameat2(RENAME_EXCHANGE)`; elsewhere two renames), so
//! a reader, or a kill at any moment, sees the old directory or the new one, never a mix.
//!
//! An existing directory is replaced only when tactfab can prove it wrote everything in it: it is
//! empty, or every entry is a file listed in its manifest with the same SHA-256. Anything else (a
//! file the user added or edited, a folder that merely holds a `build.json`) is refused with the
//! list of what would be lost, unless the caller passed the overwrite flag; the input files are
//! never replaced, flag or not. Temporary and old directories that a killed run left beside the
//! target (named after it and a process id that no longer runs) are removed by the next run.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::ExportError;

/// The manifest every output directory holds: `<sha256>  <name>` per file, as `sha256sum` writes.
pub const MANIFEST: &str = "tactfab.sha256";

/// What the caller allows: `overwrite` is the value of `flag` (named in the refusal), `inputs`
/// the files the output must never replace.
#[derive(Debug, Clone, Copy)]
pub struct Guard<'a> {
    pub overwrite: bool,
    pub flag: &'a str,
    pub inputs: &'a [&'a Path],
}

impl Guard<'_> {
    /// No overwrite flag, no inputs (tests and callers whose input cannot lie in the output).
    pub const STRICT: Guard<'static> = Guard {
        overwrite: false,
        flag: "--overwrite",
        inputs: &[],
    };
}

use crate::digest::sha256_hex;

/// The manifest text of `files` (sorted by name, so the bytes depend on the content only).
pub fn manifest(files: &[(String, Vec<u8>)]) -> String {
    let sorted: BTreeMap<&str, &[u8]> = files
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect();
    sorted
        .iter()
        .map(|(name, bytes)| format!("{}  {name}\n", sha256_hex(bytes)))
        .collect()
}

/// Parses a manifest: name -> SHA-256. Lines that do not parse make it no manifest.
fn parse_manifest(text: &str) -> Option<BTreeMap<String, String>> {
    text.lines()
        .map(|l| {
            let (hash, name) = l.split_once("  ")?;
            (hash.len() == 64 && hash.bytes().all(|b| b.is_ascii_hexdigit()) && !name.is_empty())
                .then(|| (name.to_string(), hash.to_string()))
        })
        .collect()
}

/// What in `dir` tactfab cannot prove it wrote (empty: the directory may be replaced).
fn foreign_entries(dir: &Path) -> Result<Vec<String>, ExportError> {
    let io = |cause| ExportError::Io {
        path: dir.to_path_buf(),
        cause,
    };
    let listed = std::fs::read_to_string(dir.join(MANIFEST))
        .ok()
        .and_then(|t| parse_manifest(&t));
    let mut foreign = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let entry = entry.map_err(io)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == MANIFEST && listed.is_some() {
            continue;
        }
        let ours = entry.file_type().map_err(io)?.is_file()
            && listed
                .as_ref()
                .and_then(|m| m.get(&name))
                .is_some_and(|hash| {
                    std::fs::read(entry.path()).is_ok_and(|bytes| &sha256_hex(&bytes) == hash)
                });
        if !ours {
            foreign.push(name);
        }
    }
    foreign.sort();
    Ok(foreign)
}

/// The directory `path` would be written into, made absolute without requiring it to exist.
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path)
        .ok()
        .and_then(|a| {
            let parent = a.parent()?.canonicalize().ok()?;
            Some(parent.join(a.file_name()?))
        })
        .unwrap_or_else(|| path.to_path_buf())
}

/// Refuses to write where an input file lies.
fn check_inputs(dir: &Path, inputs: &[&Path]) -> Result<(), ExportError> {
    let target = absolute(dir);
    for input in inputs {
        let input = input.canonicalize().unwrap_or_else(|_| absolute(input));
        if input.starts_with(&target) {
            return Err(ExportError::InputInside {
                dir: dir.to_path_buf(),
                input,
            });
        }
    }
    Ok(())
}

/// Whether process `pid` still runs (no `/proc`: assume it does, and keep its directory).
pub(super) fn alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// Removes `.<stem>.tactfab-{tmp,old}-<pid>` directories beside the target whose process is gone.
fn remove_stale(parent: &Path, stem: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let pid = [".tactfab-tmp-", ".tactfab-old-"].iter().find_map(|kind| {
            let rest = name.strip_prefix(&format!(".{stem}{kind}"))?;
            rest.parse::<u32>().ok()
        });
        if pid.is_some_and(|p| p != std::process::id() && !alive(p)) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// Swaps the directories `a` and `b` in one step where the platform can.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| {
        CString::new(p.as_os_str().as_bytes())
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))
    };
    let (a, b) = (c(a)?, c(b)?);
    // SAFETY: both paths are valid NUL-terminated strings that outlive the call.
    let rc = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> std::io::Result<()> {
    Err(std::io::Error::from(std::io::ErrorKind::Unsupported))
}

/// `dir` as an absolute path without `.` or `..`: canonical when it exists, else its existing
/// parent canonical with its name.
pub(super) fn resolve(dir: &Path) -> std::io::Result<PathBuf> {
    if dir.exists() {
        return dir.canonicalize();
    }
    let abs = std::path::absolute(dir)?;
    match (abs.parent(), abs.file_name()) {
        (Some(p), Some(n)) if p.exists() => Ok(p.canonicalize()?.join(n)),
        _ => Ok(abs),
    }
}

/// What [`write_dir_atomic`] would refuse, checked alone: callers run it before the work, so a
/// refused directory costs the user nothing (the write checks again). Returns the directory
/// resolved (`.`, `..` and symlinks), its parent and its name.
pub fn check_dir(dir: &Path, guard: &Guard) -> Result<(PathBuf, PathBuf, String), ExportError> {
    let io = |cause| ExportError::Io {
        path: dir.to_path_buf(),
        cause,
    };
    // `.`, `..` and symlinks resolved, so `-o .` is the directory it names (and is refused when
    // it holds the input), not a path without a name.
    let resolved = resolve(dir).map_err(io)?;
    let dir = resolved.as_path();
    let parent: PathBuf = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let stem = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .ok_or_else(|| ExportError::Invalid(format!("{}: not a directory name", dir.display())))?;
    check_inputs(dir, guard.inputs)?;
    if dir.exists() {
        if !dir.is_dir() {
            return Err(ExportError::Invalid(format!(
                "{} exists and is not a directory",
                dir.display()
            )));
        }
        let foreign = foreign_entries(dir)?;
        if !foreign.is_empty() && !guard.overwrite {
            return Err(ExportError::Foreign {
                dir: dir.to_path_buf(),
                entries: foreign,
                flag: guard.flag.to_string(),
            });
        }
    }
    Ok((resolved, parent, stem))
}

/// Writes `files` (plus the manifest) as the complete content of `dir`, replacing a previous
/// output of tactfab; see the module documentation for what is refused.
pub fn write_dir_atomic(
    dir: &Path,
    files: &[(String, Vec<u8>)],
    guard: &Guard,
) -> Result<(), ExportError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |cause| ExportError::Io { path, cause }
    };
    let (resolved, parent, stem) = check_dir(dir, guard)?;
    let dir = resolved.as_path();
    std::fs::create_dir_all(&parent).map_err(io(&parent))?;
    remove_stale(&parent, &stem);
    let pid = std::process::id();
    let tmp = parent.join(format!(".{stem}.tactfab-tmp-{pid}"));
    let old = parent.join(format!(".{stem}.tactfab-old-{pid}"));
    let _ = std::fs::remove_dir_all(&tmp);
    let result = (|| {
        std::fs::create_dir(&tmp).map_err(io(&tmp))?;
        for (name, bytes) in files {
            let path = tmp.join(name);
            std::fs::write(&path, bytes).map_err(io(&path))?;
        }
        let path = tmp.join(MANIFEST);
        std::fs::write(&path, manifest(files)).map_err(io(&path))?;
        if !dir.exists() {
            return std::fs::rename(&tmp, dir).map_err(io(dir));
        }
        if exchange(&tmp, dir).is_ok() {
            // `tmp` now holds the previous output.
            let _ = std::fs::remove_dir_all(&tmp);
            return Ok(());
        }
        std::fs::rename(dir, &old).map_err(io(dir))?;
        if let Err(e) = std::fs::rename(&tmp, dir) {
            let _ = std::fs::rename(&old, dir);
            return Err(io(dir)(e));
        }
        let _ = std::fs::remove_dir_all(&old);
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(text: &str) -> Vec<(String, Vec<u8>)> {
        vec![
            ("build.json".into(), b"{}".to_vec()),
            ("a.txt".into(), text.as_bytes().to_vec()),
        ]
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn replaces_its_own_output_and_leaves_nothing_beside_it() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        write_dir_atomic(&out, &files("one"), &Guard::STRICT).unwrap();
        assert_eq!(names(&out), ["a.txt", "build.json", MANIFEST]);
        write_dir_atomic(&out, &files("two"), &Guard::STRICT).unwrap();
        assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "two");
        assert_eq!(names(root.path()), ["out"]);
    }

    #[test]
    fn refuses_a_directory_with_files_it_did_not_write() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        // A folder that merely holds a `build.json` of its own.
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("build.json"), "{\"app\": 1}").unwrap();
        std::fs::write(out.join("index.html"), "keep").unwrap();
        let err = write_dir_atomic(&out, &files("x"), &Guard::STRICT).unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("build.json") && msg.contains("index.html"),
            "{msg}"
        );
        assert!(msg.contains("--overwrite"), "{msg}");
        assert_eq!(
            std::fs::read_to_string(out.join("index.html")).unwrap(),
            "keep"
        );
        // A previous output with a note the user added, or a file the user edited.
        let out = root.path().join("prev");
        write_dir_atomic(&out, &files("one"), &Guard::STRICT).unwrap();
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        assert!(write_dir_atomic(&out, &files("two"), &Guard::STRICT).is_err());
        std::fs::remove_file(out.join("notes.txt")).unwrap();
        std::fs::write(out.join("a.txt"), "edited").unwrap();
        let err = write_dir_atomic(&out, &files("two"), &Guard::STRICT).unwrap_err();
        assert!(err.to_string().contains("a.txt"), "{err}");
        // With the flag the user allows it.
        let allow = Guard {
            overwrite: true,
            ..Guard::STRICT
        };
        write_dir_atomic(&out, &files("two"), &allow).unwrap();
        assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "two");
    }

    #[test]
    fn never_replaces_a_directory_holding_an_input() {
        let root = tempfile::tempdir().unwrap();
        let input = root.path().join("f.yaml");
        std::fs::write(&input, "device: {}").unwrap();
        let guard = Guard {
            overwrite: true,
            flag: "--overwrite",
            inputs: &[&input],
        };
        let err = write_dir_atomic(root.path(), &files("x"), &guard).unwrap_err();
        assert!(err.to_string().contains("f.yaml"), "{err}");
        assert!(input.exists());
    }

    #[test]
    fn stale_directories_of_dead_runs_are_removed() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        // No process has pid u32::MAX - 1 (Linux pids are below 2^22).
        let stale = root
            .path()
            .join(format!(".out.tactfab-tmp-{}", u32::MAX - 1));
        std::fs::create_dir(&stale).unwrap();
        std::fs::write(stale.join("half.gds"), "x").unwrap();
        let unrelated = root.path().join(".out.tactfab-tmp-notapid");
        std::fs::create_dir(&unrelated).unwrap();
        write_dir_atomic(&out, &files("one"), &Guard::STRICT).unwrap();
        assert!(!stale.exists());
        assert!(unrelated.exists());
    }

    #[test]
    fn the_manifest_is_sha256sum_format_and_content_ordered() {
        let m = manifest(&[("b".into(), b"".to_vec()), ("a".into(), b"abc".to_vec())]);
        assert_eq!(
            m,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad  a\n\
             e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855  b\n"
        );
    }
}
