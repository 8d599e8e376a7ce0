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

/// Counts with their nouns in text output.
pub use tactfab::units::count;
