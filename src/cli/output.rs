//! Small text-formatting helpers shared by subcommands.

use tactfab::etch::Check;

/// Lines `warning[CODE]: message` for every check, errors first.
pub fn checks(checks: &[Check]) -> String {
    let mut sorted: Vec<&Check> = checks.iter().collect();
    sorted.sort_by_key(|c| std::cmp::Reverse(c.severity));
    sorted.iter().map(|c| format!("  {c}\n")).collect()
}

/// Fixed-decimal formatting so text output is stable.
pub fn f(x: f64, decimals: usize) -> String {
    format!("{x:.decimals$}")
}
