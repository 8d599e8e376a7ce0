//! One output file (a plot, a shard's CSV) written at a path the user names, and never at the
//! cost of the user's file.
//!
//! [`super::dir`] proves a directory is tactfab's by its manifest. A single file carries its own
//! proof instead ([`Proof`]): an SVG ends with a comment holding the SHA-256 of everything
//! before it ([`stamp_svg`]), so an existing file whose hash still matches is an unchanged
//! tactfab plot; a JSON object ends with a key holding the same ([`stamp_json`]); a CSV begins
//! with tactfab's header line. An existing file without its proof
//! (a user's notes, an edited plot, a directory) is refused, and so is every input file, proof
//! or not. The check runs before the work ([`check`]) and again at the write ([`write()`]),
//! which goes through a temporary file and a rename ([`super::write_atomic`]).

use std::path::{Path, PathBuf};

use super::ExportError;
use crate::digest::sha256_hex;

/// How an existing file shows that tactfab wrote it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Proof {
    /// An SVG that ends with [`stamp_svg`]'s comment and still hashes to it.
    SvgStamp,
    /// A JSON object whose last key is [`stamp_json`]'s and still hashes to it.
    JsonStamp,
    /// A CSV whose first line is this header.
    CsvHeader(&'static str),
}

/// The stamp's opening; the hash and the closing follow.
const STAMP_OPEN: &str = "<!-- tactfab sha256 of the bytes above: ";
const STAMP_CLOSE: &str = " -->\n";

/// Existing files larger than this are not tactfab's (its plots are a few MB at most), and are
/// not read to find out.
const MAX_PROOF_BYTES: u64 = 256 << 20;

/// `svg` with the comment that proves it tactfab's: the SHA-256 of every byte before it. The
/// same input gives the same bytes.
///
/// ```
/// let svg = tactfab::export::file::stamp_svg("<svg/>\n".into());
/// assert!(svg.starts_with("<svg/>\n<!-- tactfab sha256"));
/// ```
pub fn stamp_svg(mut svg: String) -> String {
    if !svg.ends_with('\n') {
        svg.push('\n');
    }
    let hash = sha256_hex(svg.as_bytes());
    svg.push_str(STAMP_OPEN);
    svg.push_str(&hash);
    svg.push_str(STAMP_CLOSE);
    svg
}

/// The JSON stamp's key, opened after the object's last member; the hash and the closing follow.
const JSON_OPEN: &str = ",\n  \"tactfab_sha256\": \"";
const JSON_CLOSE: &str = "\"\n}\n";

/// A pretty-printed JSON object (`serde_json::to_string_pretty`) with a last key,
/// `tactfab_sha256`, holding the SHA-256 of every byte before that key's line (the object up to
/// its last member): still JSON, and provably tactfab's until edited. The same input gives the
/// same bytes. `None` if `json` is not a non-empty pretty-printed object.
///
/// ```
/// let json = tactfab::export::file::stamp_json("{\n  \"a\": 1\n}").unwrap();
/// assert!(json.starts_with("{\n  \"a\": 1,\n  \"tactfab_sha256\": \""));
/// assert!(json.ends_with("\"\n}\n"));
/// ```
pub fn stamp_json(json: &str) -> Option<String> {
    let body = json.trim_end().strip_suffix("\n}")?;
    if !body.starts_with("{\n") {
        return None;
    }
    let hash = sha256_hex(body.as_bytes());
    Some(format!("{body}{JSON_OPEN}{hash}{JSON_CLOSE}"))
}

/// Whether `bytes` end with `open`, the SHA-256 (hex) of every byte before `open`, and `close`.
fn hash_stamped(bytes: &[u8], open: &str, close: &str) -> bool {
    let Some(body) = bytes.strip_suffix(close.as_bytes()) else {
        return false;
    };
    let Some(at) = body.len().checked_sub(open.len() + 64) else {
        return false;
    };
    let (above, stamp) = body.split_at(at);
    stamp.starts_with(open.as_bytes()) && stamp[open.len()..] == *sha256_hex(above).as_bytes()
}

/// Whether `bytes` carry `proof`.
fn proven(bytes: &[u8], proof: Proof) -> bool {
    match proof {
        Proof::SvgStamp => hash_stamped(bytes, STAMP_OPEN, STAMP_CLOSE),
        Proof::JsonStamp => hash_stamped(bytes, JSON_OPEN, JSON_CLOSE),
        Proof::CsvHeader(header) => bytes
            .strip_prefix(header.as_bytes())
            .is_some_and(|rest| rest.starts_with(b"\n") || rest.starts_with(b"\r\n")),
    }
}

/// `path` made absolute as [`super::dir`] resolves its directories (or as given, if it cannot
/// be), so two spellings of one file compare equal.
fn resolve(path: &Path) -> PathBuf {
    super::dir::resolve(path).unwrap_or_else(|_| path.to_path_buf())
}

/// Refuses `path` if it is one of `inputs`, or holds something tactfab cannot prove by `proof`
/// that it wrote. A path that does not exist yet is fine.
pub fn check(path: &Path, proof: Proof, inputs: &[&Path]) -> Result<(), ExportError> {
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if path.file_name().is_none() || !parent.is_dir() {
        return Err(ExportError::Invalid(format!(
            "`{}`: not a file name in an existing directory",
            path.display()
        )));
    }
    let target = resolve(path);
    if let Some(input) = inputs.iter().find(|i| resolve(i) == target) {
        return Err(ExportError::InputFile {
            path: path.to_path_buf(),
            input: input.to_path_buf(),
        });
    }
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(cause) => {
            return Err(ExportError::Io {
                path: path.to_path_buf(),
                cause,
            })
        }
    };
    let ours = meta.is_file()
        && meta.len() <= MAX_PROOF_BYTES
        && std::fs::read(path).is_ok_and(|bytes| proven(&bytes, proof));
    if ours {
        Ok(())
    } else {
        Err(ExportError::ForeignFile {
            path: path.to_path_buf(),
        })
    }
}

/// Writes `bytes` to `path` after [`check`]; `bytes` must carry `proof` themselves, so the next
/// run may replace them (a debug assertion: a writer that forgot its stamp would lock its users
/// out of their own output).
pub fn write(path: &Path, bytes: &[u8], proof: Proof, inputs: &[&Path]) -> Result<(), ExportError> {
    debug_assert!(
        proven(bytes, proof),
        "{}: written without its proof",
        path.display()
    );
    check(path, proof, inputs)?;
    super::write_atomic(path, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "length_um,width_um";

    #[test]
    fn a_stamped_svg_is_ours_until_it_is_edited() {
        let svg = stamp_svg("<svg></svg>".into());
        assert!(proven(svg.as_bytes(), Proof::SvgStamp));
        assert_eq!(svg, stamp_svg("<svg></svg>\n".into()), "deterministic");
        let edited = svg.replacen("<svg>", "<svg >", 1);
        assert!(!proven(edited.as_bytes(), Proof::SvgStamp));
        assert!(!proven(b"<svg></svg>\n", Proof::SvgStamp));
        assert!(!proven(b"", Proof::SvgStamp));
        assert!(!proven(STAMP_CLOSE.as_bytes(), Proof::SvgStamp));
    }

    #[test]
    fn a_stamped_json_is_ours_until_it_is_edited_and_stays_json() {
        let pretty = "{\n  \"a\": [\n    1,\n    2\n  ],\n  \"b\": \"x\"\n}";
        let json = stamp_json(pretty).unwrap();
        assert!(proven(json.as_bytes(), Proof::JsonStamp));
        assert_eq!(Some(json.clone()), stamp_json(&format!("{pretty}\n")));
        // Tests see serde_json's reading of it through the CLI; here the bytes.
        assert!(json.starts_with("{\n  \"a\": [\n    1,\n    2\n  ],\n  \"b\": \"x\",\n"));
        let edited = json.replacen('1', "3", 1);
        assert!(!proven(edited.as_bytes(), Proof::JsonStamp));
        assert!(!proven(pretty.as_bytes(), Proof::JsonStamp));
        assert!(!proven(b"", Proof::JsonStamp));
        assert!(!proven(JSON_CLOSE.as_bytes(), Proof::JsonStamp));
        // An SVG's stamp is not a JSON's, nor the other way round.
        assert!(!proven(json.as_bytes(), Proof::SvgStamp));
        let svg = stamp_svg("<svg/>".into());
        assert!(!proven(svg.as_bytes(), Proof::JsonStamp));
        // Not an object, or an empty one: nothing to stamp.
        assert_eq!(stamp_json("[1]"), None);
        assert_eq!(stamp_json("{}"), None);
    }

    #[test]
    fn a_csv_is_ours_by_its_whole_header_line() {
        let p = Proof::CsvHeader(HEADER);
        assert!(proven(b"length_um,width_um\n1,2\n", p));
        assert!(proven(b"length_um,width_um\r\n", p));
        assert!(!proven(b"length_um,width_um,mine\n", p));
        assert!(!proven(b"length_um,width_um", p));
        assert!(!proven(b"notes\n", p));
    }

    #[test]
    fn replaces_its_own_file_and_refuses_a_users_file_or_the_input() {
        let dir = tempfile::tempdir().unwrap();
        let plot = dir.path().join("plot.svg");
        let first = stamp_svg("<svg>1</svg>".into());
        write(&plot, first.as_bytes(), Proof::SvgStamp, &[]).unwrap();
        let second = stamp_svg("<svg>2</svg>".into());
        write(&plot, second.as_bytes(), Proof::SvgStamp, &[]).unwrap();
        assert_eq!(std::fs::read_to_string(&plot).unwrap(), second);
        // Edited since: no longer provably ours.
        std::fs::write(&plot, second.replace('2', "3")).unwrap();
        let err = write(&plot, first.as_bytes(), Proof::SvgStamp, &[]).unwrap_err();
        assert!(matches!(err, ExportError::ForeignFile { .. }), "{err}");
        assert!(std::fs::read_to_string(&plot).unwrap().contains("<svg>3"));
        // The input, by any spelling of its path, even when it would pass as ours.
        let input = dir.path().join("p.yaml");
        std::fs::write(&input, &first).unwrap();
        let spelled = dir.path().join(".").join("p.yaml");
        let err = write(&spelled, first.as_bytes(), Proof::SvgStamp, &[&input]).unwrap_err();
        assert!(matches!(err, ExportError::InputFile { .. }), "{err}");
        // A directory is never a file of ours.
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        let csv = b"length_um,width_um\n";
        let err = write(&sub, csv, Proof::CsvHeader(HEADER), &[]).unwrap_err();
        assert!(matches!(err, ExportError::ForeignFile { .. }), "{err}");
        assert!(sub.is_dir());
        // No name, or no such directory: refused before the work, as the write would fail.
        for bad in ["", "..", "/", "no-such-dir/plot.svg"] {
            let at = dir.path().join(bad);
            let at = if bad.is_empty() {
                Path::new("")
            } else {
                at.as_path()
            };
            let err = check(at, Proof::SvgStamp, &[]).unwrap_err();
            assert!(matches!(err, ExportError::Invalid(_)), "{bad}: {err}");
        }
        // No stray temporary files.
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(names.len(), 3, "{names:?}");
    }
}
