//! The bytes of a process file before YAML sees them: a size limit, UTF-8, one document.

use std::io::Read;
use std::path::Path;

use super::error::{LoadError, Location, Problem};

/// Largest process file tactfab reads: 1 MiB. A process file is a few kB (the bundled ones are
/// under 12 kB); anything larger is the wrong file (`/dev/zero`, a GDS, a log). [`super::load`]
/// reads at most this many bytes plus one, so an endless input is refused at once.
pub const MAX_FILE_BYTES: usize = 1 << 20;

/// Reads at most [`MAX_FILE_BYTES`] + 1 bytes of `file` and returns them as text.
pub fn read(file: &Path) -> Result<String, LoadError> {
    let io = |cause| LoadError::Io {
        path: file.to_path_buf(),
        cause,
    };
    let f = std::fs::File::open(file).map_err(io)?;
    let mut bytes = Vec::new();
    f.take(MAX_FILE_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    let name = file.display().to_string();
    check_size(bytes.len(), &name)?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        LoadError::Invalid(vec![not_utf8(e.as_bytes(), at, &name)])
    })
}

/// [`LoadError::TooLarge`] when `len` exceeds [`MAX_FILE_BYTES`].
pub fn check_size(len: usize, file: &str) -> Result<(), LoadError> {
    if len > MAX_FILE_BYTES {
        return Err(LoadError::TooLarge {
            file: file.to_string(),
            limit: MAX_FILE_BYTES,
        });
    }
    Ok(())
}

/// The first byte that is not UTF-8, at its line and column (columns count characters).
fn not_utf8(bytes: &[u8], at: usize, file: &str) -> Problem {
    let before = &bytes[..at];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    // `before` is valid UTF-8 by construction.
    let column = std::str::from_utf8(&before[line_start..]).map_or(1, |s| s.chars().count() + 1);
    Problem {
        location: Location::File {
            file: file.to_string(),
            line,
            column,
        },
        path: ".".into(),
        message: format!(
            "byte 0x{:02x} is not UTF-8 text",
            bytes.get(at).copied().unwrap_or(0)
        ),
        expected: "a UTF-8 text file".into(),
        hint: "save the file as UTF-8; a process file is plain text (Latin-1 `u` for micro, a \
               word-processor file or a binary are not)"
            .into(),
    }
}

/// The line of a `---` that starts a second YAML document, if any. A `---` before any content
/// only opens the first document. Block scalars cannot hold a `---` at column 1, so a line scan
/// is exact.
pub fn second_document(text: &str) -> Option<usize> {
    let mut content = false;
    let mut opened = false;
    for (i, line) in text.lines().enumerate() {
        let is_marker = line
            .strip_prefix("---")
            .is_some_and(|r| r.is_empty() || r.starts_with([' ', '\t']));
        if is_marker {
            if content || opened {
                return Some(i + 1);
            }
            opened = true;
            continue;
        }
        let t = line.trim_start();
        if !(t.is_empty() || t.starts_with('#') || line.starts_with('%')) {
            content = true;
        }
    }
    None
}

/// The problem for a second document starting at `line`.
pub fn second_document_problem(line: usize, file: &str) -> Problem {
    Problem {
        location: Location::File {
            file: file.to_string(),
            line,
            column: 1,
        },
        path: ".".into(),
        message: "a second YAML document starts here".into(),
        expected: "one document: one process per file".into(),
        hint: "remove this `---` line, or put the second process in a file of its own".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_leading_marker_is_one_document() {
        assert_eq!(second_document("---\na: 1\n"), None);
        assert_eq!(second_document("# c\n---\na: 1\n"), None);
        assert_eq!(second_document("a: 1\n---\nb: 2\n"), Some(2));
        assert_eq!(second_document("---\n---\n"), Some(2));
        assert_eq!(second_document("a: |\n  ---\n"), None);
        assert_eq!(second_document("a: 1\n----\n"), None);
    }

    #[test]
    fn bad_byte_is_located() {
        let p = not_utf8(b"a: 1\nb: x\xff", 9, "f.yaml");
        assert_eq!(p.location.to_string(), "f.yaml:2:5");
    }
}
