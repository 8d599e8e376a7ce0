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
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File { file, line, column } => write!(f, "{file}:{line}:{column}"),
            Location::Override { arg } => write!(f, "--set {arg}"),
            Location::Unknown { file } => write!(f, "{file}"),
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
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.location, self.path, self.message)?;
        if !self.expected.is_empty() {
            write!(f, " (expected {})", self.expected)?;
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
    for p in problems {
        out.push_str(&p.to_string());
        out.push('\n');
    }
    let n = problems.len();
    out.push_str(&format!(
        "{n} problem{} found; nothing was written\n  hint: fix every line above; `tactfab check \
         FILE` re-validates",
        if n == 1 { "" } else { "s" }
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
