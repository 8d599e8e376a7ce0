//! {111}-bounded etch geometry on (100) silicon with mask edges along <110>.

use crate::units::sidewall_angle_rad;

/// Horizontal run of one {111} sidewall: h / tan(54.74 deg) = h / sqrt 2 (process-physics.md).
pub fn sidewall_run_out_um(depth_um: f64) -> f64 {
    depth_um / sidewall_angle_rad().tan()
}

/// Base of a frustum mesa whose top is `top_um` after etching `depth_um`: top + 2 run-outs.
pub fn mesa_base_um(top_um: f64, depth_um: f64) -> f64 {
    top_um + 2.0 * sidewall_run_out_um(depth_um)
}

/// Lateral undercut of a <110> mask edge: R111 t / sin(54.74 deg) (process-physics.md).
pub fn undercut_um(rate_111_um_per_h: f64, time_h: f64) -> f64 {
    rate_111_um_per_h * time_h / sidewall_angle_rad().sin()
}

/// A street between two <110> edges reaches `depth_um` only if it is at least 2 run-outs wide,
/// sqrt 2 h; narrower ones self-stop as V-grooves (process-physics.md).
pub fn min_street_um(depth_um: f64) -> f64 {
    2.0 * sidewall_run_out_um(depth_um)
}

/// Depth at which a street of width `gap_um` self-stops as a V-groove: gap / sqrt 2.
pub fn v_groove_depth_um(gap_um: f64) -> f64 {
    gap_um * sidewall_angle_rad().tan() / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_values() {
        assert!((sidewall_run_out_um(200.0) - 141.421356).abs() < 1e-5);
        assert!((mesa_base_um(2000.0, 200.0) - 2282.8427).abs() < 1e-3);
        assert!((min_street_um(200.0) - 282.8427).abs() < 1e-3);
        assert!((v_groove_depth_um(min_street_um(200.0)) - 200.0).abs() < 1e-9);
        // 0.8 um/h for 8.5 h: 6.8 / sin(54.74) = 8.328 um.
        assert!((undercut_um(0.8, 8.5) - 8.3283).abs() < 1e-3);
    }
}
