//! Small text-formatting helpers shared by subcommands.

use tactfab::etch::Check;

/// Lines `warning[CODE]: message` for every check, errors first.
pub fn checks(checks: &[Check]) -> String {
    let mut sorted: Vec<&Check> = checks.iter().collect();
    sorted.sort_by_key(|c| std::cmp::Reverse(c.severity));
    sorted.iter().map(|c| format!("  {c}\n")).collect()
}

/// Fixed-decimal formatting so text output is stable.
pub use tactfab::units::fixed as f;
