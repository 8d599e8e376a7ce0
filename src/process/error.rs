//! Load errors: every problem of a process file at once, each with its place and what is allowed.

use std::fmt;
use std::path::PathBuf;

/// Where a problem sits: a position in the file, or a `--set` override from the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    File {
        file: String,
        line: usize,
        column: usize,
    },
    Override {
        arg: String,
    },
    Unknown {
        file: String,
    },
    /// A value the file never wrote: a default. `section` is the key where the user would write
    /// it, when the file has that section.
    Default {
        file: String,
        section: Option<(usize, usize)>,
    },
}

/// The most problems one error lists (the first ones in file order); the rest are counted.
pub const MAX_PROBLEMS_SHOWN: usize = 500;

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File { file, line, column } => write!(f, "{file}:{line}:{column}"),
            Location::Override { arg } => write!(f, "--set {arg}"),
            Location::Unknown { file } => write!(f, "{file}"),
            Location::Default {
                file,
                section: Some((line, column)),
            } => write!(f, "{file}:{line}:{column}"),
            Location::Default {
                file,
                section: None,
            } => write!(f, "{file}"),
        }
    }
}

/// One problem of a process file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    pub location: Location,
    /// Field path such as `steps[9].temp_c`; `.` for the document.
    pub path: String,
    pub message: String,
    /// What is allowed there (type, range, choices).
    pub expected: String,
    /// What to do about it, printed as `\n  hint: ...` under the problem; empty for none.
    pub hint: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let default = if matches!(self.location, Location::Default { .. }) {
            " (default)"
        } else {
            ""
        };
        // `steps[i]` is the YAML index; the traveler numbers steps from 1: say both.
        let step = self
            .path
            .strip_prefix("steps[")
            .and_then(|r| r.split_once(']'))
            .and_then(|(i, _)| i.parse::<usize>().ok())
            .map(|i| format!(" (traveler step {})", i + 1))
            .unwrap_or_default();
        write!(
            f,
            "{}: {}{default}{step}: {}",
            self.location, self.path, self.message
        )?;
        if !self.expected.is_empty() {
            write!(f, " (expected {})", self.expected)?;
        }
        if !self.hint.is_empty() {
            write!(f, "\n  hint: {}", self.hint)?;
        }
        Ok(())
    }
}

/// Why a process file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("{}: cannot read the process file: {cause}\n  hint: check the path; process files live in process/*.yaml", path.display())]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
    /// The file is larger than [`super::MAX_FILE_BYTES`]; only that much plus one byte was read.
    #[error(
        "{file}: the process file is larger than {} MiB; it was not read\n  hint: a process \
         file is a few kB of YAML; check the path",
        limit >> 20
    )]
    TooLarge { file: String, limit: usize },
    /// A `--set` argument is not `path=value`.
    #[error(
        "--set {arg}: {message}\n  hint: write --set path=value, e.g. --set \
         steps.tmah-etch.temp_c=85"
    )]
    BadOverride { arg: String, message: String },
    /// One or more problems in the file; all are listed.
    #[error("{}", format_problems(.0))]
    Invalid(Vec<Problem>),
}

fn format_problems(problems: &[Problem]) -> String {
    let mut out = String::new();
    for p in problems.iter().take(MAX_PROBLEMS_SHOWN) {
        out.push_str(&p.to_string());
        out.push('\n');
    }
    let n = problems.len();
    if n > MAX_PROBLEMS_SHOWN {
        out.push_str(&format!("... and {} more\n", n - MAX_PROBLEMS_SHOWN));
    }
    out.push_str(&format!(
        "{} found; nothing was written\n  hint: fix every line above; `tactfab check FILE` \
         re-validates",
        crate::units::count(n, "problem")
    ));
    out
}

impl LoadError {
    /// The problems, for tests and tools (empty for I/O errors).
    pub fn problems(&self) -> &[Problem] {
        match self {
            LoadError::Invalid(p) => p,
            _ => &[],
        }
    }
}
