//! Resist thickness from a power-law spin curve.

/// t = t_ref (rpm / rpm_ref)^-n (empirical spin curve; S1813 n = 0.51 from two measured points,
/// reference/process-physics.md).
pub fn spin_thickness_um(
    ref_thickness_um: f64,
    ref_speed_rpm: f64,
    exponent: f64,
    speed_rpm: f64,
) -> f64 {
    ref_thickness_um * (speed_rpm / ref_speed_rpm).powf(-exponent)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::process::defaults as d;

    #[test]
    fn s1813_curve() {
        let t = |rpm| {
            spin_thickness_um(
                d::s1813_ref_thickness_um(),
                d::s1813_ref_speed_rpm(),
                d::s1813_spin_exponent(),
                rpm,
            )
        };
        assert!((t(3915.0) - 1.4).abs() < 1e-12);
        assert!((t(1950.0) - 2.0).abs() < 1e-9);
        assert!((t(3000.0) - 1.604).abs() < 0.005);
    }
}
