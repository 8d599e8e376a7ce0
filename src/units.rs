//! Physical constants and unit conversions shared by the models.

/// Boltzmann constant in eV/K (CODATA 2018, exact).
pub const BOLTZMANN_EV_PER_K: f64 = 8.617_333_262e-5;
/// Vacuum permittivity in F/m (CODATA 2018).
pub const EPS0_F_PER_M: f64 = 8.854_187_812_8e-12;
/// Angle between {111} sidewalls and the (100) surface: atan(sqrt 2) = 54.7356 deg.
pub fn sidewall_angle_rad() -> f64 {
    2f64.sqrt().atan()
}

/// Celsius to kelvin.
pub fn kelvin(temp_c: f64) -> f64 {
    temp_c + 273.15
}

/// `x` with exactly `decimals` decimals: text and CSV output stay byte-stable.
pub fn fixed(x: f64, decimals: usize) -> String {
    format!("{x:.decimals$}")
}

/// `1 level`, `3 levels`: a count with its noun, plural when it is not one.
///
/// ```
/// assert_eq!(tactfab::units::count(1, "level"), "1 level");
/// assert_eq!(tactfab::units::count(3, "problem"), "3 problems");
/// ```
pub fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}
