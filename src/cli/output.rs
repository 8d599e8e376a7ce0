//! Small text-formatting helpers shared by subcommands.

use tactfab::finding::Finding;

/// Lines `warning[CODE]: message` for every check, errors first.
pub fn checks(checks: &[Finding]) -> String {
    let mut sorted: Vec<&Finding> = checks.iter().collect();
    sorted.sort_by_key(|c| std::cmp::Reverse(c.severity));
    sorted.iter().map(|c| format!("  {c}\n")).collect()
}

/// Fixed-decimal formatting so text output is stable.
pub use tactfab::units::fixed as f;

/// `1 level`, `3 levels`: a count with its noun, plural when it is not one.
pub fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}
