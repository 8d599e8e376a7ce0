//! The YAML spelling of an enum value: what the user writes in the process file (`both`,
//! `corner_attached`) and the only spelling tactfab's output shows, never Rust's `Debug`.

use serde::Serialize;

/// The serde name of a unit variant (`Side::Both` -> `both`); for anything else its JSON text.
///
/// ```
/// use tactfab::process::{CompensationGeometry, Side};
/// assert_eq!(tactfab::spelling::yaml(&Side::Both), "both");
/// assert_eq!(tactfab::spelling::yaml(&CompensationGeometry::CornerAttached), "corner_attached");
/// assert_eq!(tactfab::spelling::yaml(&CompensationGeometry::Bar110), "bar_110");
/// ```
pub fn yaml<T: Serialize>(t: &T) -> String {
    match serde_json::to_value(t) {
        Ok(serde_json::Value::String(s)) => s,
        Ok(other) => other.to_string(),
        Err(e) => format!("<{e}>"),
    }
}
