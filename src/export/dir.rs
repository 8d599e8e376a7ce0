//! A whole output directory written atomically: built in a temporary directory beside the target,
//! then renamed into place, so readers see the old directory or the new one, never a mix.

use std::path::{Path, PathBuf};

use super::ExportError;

/// Writes `files` as the complete content of `dir`. An existing `dir` is replaced only when it is
/// empty or holds `marker` (a previous output of the same command): anything else is refused, so a
/// mistyped `-o` never deletes a user's directory.
pub fn write_dir_atomic(
    dir: &Path,
    files: &[(String, Vec<u8>)],
    marker: &str,
) -> Result<(), ExportError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |cause| ExportError::Io { path, cause }
    };
    let parent: PathBuf = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let stem = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .ok_or_else(|| ExportError::Invalid(format!("{}: not a directory name", dir.display())))?;
    if dir.exists() {
        if !dir.is_dir() {
            return Err(ExportError::Invalid(format!(
                "{} exists and is not a directory",
                dir.display()
            )));
        }
        let empty = std::fs::read_dir(dir).map_err(io(dir))?.next().is_none();
        if !empty && !dir.join(marker).is_file() {
            return Err(ExportError::Invalid(format!(
                "{} exists and is not an output of this command (no `{marker}`): choose another \
                 directory or remove it",
                dir.display()
            )));
        }
    }
    std::fs::create_dir_all(&parent).map_err(io(&parent))?;
    let tmp = parent.join(format!(".{stem}.tactfab-tmp-{}", std::process::id()));
    let old = parent.join(format!(".{stem}.tactfab-old-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let result = (|| {
        std::fs::create_dir(&tmp).map_err(io(&tmp))?;
        for (name, bytes) in files {
            let path = tmp.join(name);
            std::fs::write(&path, bytes).map_err(io(&path))?;
        }
        if dir.exists() {
            std::fs::rename(dir, &old).map_err(io(dir))?;
            if let Err(e) = std::fs::rename(&tmp, dir) {
                let _ = std::fs::rename(&old, dir);
                return Err(io(dir)(e));
            }
            let _ = std::fs::remove_dir_all(&old);
        } else {
            std::fs::rename(&tmp, dir).map_err(io(dir))?;
        }
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

    #[test]
    fn replaces_own_output_and_drops_stale_files() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        write_dir_atomic(&out, &files("one"), "build.json").unwrap();
        std::fs::write(out.join("stale.txt"), "x").unwrap();
        write_dir_atomic(&out, &files("two"), "build.json").unwrap();
        assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "two");
        assert!(!out.join("stale.txt").exists());
        // Nothing left beside it.
        let names: Vec<_> = std::fs::read_dir(root.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("out")]);
    }

    #[test]
    fn refuses_a_foreign_directory() {
        let root = tempfile::tempdir().unwrap();
        std::fs::write(root.path().join("precious.txt"), "keep").unwrap();
        let err = write_dir_atomic(root.path(), &files("x"), "build.json").unwrap_err();
        assert!(err.to_string().contains("not an output"), "{err}");
        assert_eq!(
            std::fs::read_to_string(root.path().join("precious.txt")).unwrap(),
            "keep"
        );
    }
}
