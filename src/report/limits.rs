//! Pass/fail limits of a declared scene (`checks.scenes[].limits`) against its FE report.
//!
//! Shared by `tactfab fe`, `tactfab build` and the traveler, so a limit means the same everywhere.

use serde::Serialize;

use crate::process::Limits;
use crate::sensor::SceneReport;

/// One declared limit and how the report fares against it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitCheck {
    /// The limit's field in the process file, e.g. `min_safety_factor`.
    pub limit: &'static str,
    /// The reported value the limit is compared with.
    pub value: f64,
    /// The declared bound.
    pub bound: f64,
    pub passed: bool,
}

impl std::fmt::Display for LimitCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (v, b) = (self.value, self.bound);
        let ok = self.passed;
        match self.limit {
            "min_sensitivity_mv_per_n" => write!(
                f,
                "sensitivity {v:.3} mV/N {} {b} mV/N",
                if ok { ">=" } else { "<" }
            ),
            "max_stress_mpa" => write!(
                f,
                "stress {v:.1} MPa {} {b} MPa",
                if ok { "<=" } else { ">" }
            ),
            "min_safety_factor" => write!(
                f,
                "safety factor {v:.2} {} {b}",
                if ok { ">=" } else { "<" }
            ),
            _ => write!(
                f,
                "deflection {v:.1} um {} {b} um",
                if ok { "<=" } else { ">" }
            ),
        }
    }
}

/// Every declared limit of `l` checked against `r`, in a fixed order (sensitivity, stress, safety
/// factor, deflection). Sensitivity is the largest |V|/F; the deflection limit bounds |max
/// deflection|.
pub fn check_limits(r: &SceneReport, l: &Limits) -> Vec<LimitCheck> {
    check_values(
        r.sensitivity_mv_per_n,
        r.max_stress_mpa,
        r.safety_factor,
        r.max_deflection_um,
        l,
    )
}

fn check_values(
    sensitivity_mv_per_n: f64,
    stress_mpa: f64,
    safety_factor: f64,
    deflection_um: f64,
    l: &Limits,
) -> Vec<LimitCheck> {
    let mut v = Vec::new();
    if let Some(b) = l.min_sensitivity_mv_per_n {
        v.push(LimitCheck {
            limit: "min_sensitivity_mv_per_n",
            value: sensitivity_mv_per_n,
            bound: b,
            passed: sensitivity_mv_per_n >= b,
        });
    }
    if let Some(b) = l.max_stress_mpa {
        v.push(LimitCheck {
            limit: "max_stress_mpa",
            value: stress_mpa,
            bound: b,
            passed: stress_mpa <= b,
        });
    }
    if let Some(b) = l.min_safety_factor {
        v.push(LimitCheck {
            limit: "min_safety_factor",
            value: safety_factor,
            bound: b,
            passed: safety_factor >= b,
        });
    }
    if let Some(b) = l.max_deflection_um {
        v.push(LimitCheck {
            limit: "max_deflection_um",
            value: deflection_um,
            bound: b,
            passed: deflection_um.abs() <= b,
        });
    }
    v
}

/// Every declared limit of `l` checked against the solid rung's answer `r` (`build
/// --verify-solid`), each value taken on its unsafe side by the solid's own estimate: the
/// averaged stress extrapolated and raised by its estimate (the safety factor from the worst of it
/// and the sharp edges' stresses at the critical distance, against `fracture_mpa`), the largest deflection and the largest electrode voltage per newton of the
/// finest mesh moved by the estimates of the deflection and of the charges.
pub fn check_solid_limits(
    r: &crate::sensor::solid::SolidReport,
    l: &Limits,
    fracture_mpa: f64,
) -> Vec<LimitCheck> {
    let q = |name: &str| r.quantities.iter().find(|q| q.name == name);
    let disc = |name: &str| q(name).and_then(|q| q.discretisation).unwrap_or(0.0);
    let charge_disc = r
        .quantities
        .iter()
        .filter(|q| q.name.starts_with("charge_"))
        .filter_map(|q| q.discretisation)
        .fold(0.0, f64::max);
    let Some(finest) = r.levels.last() else {
        return Vec::new();
    };
    let stress = q("max_stress_averaged").map_or(f64::NAN, |q| q.extrapolated)
        * (1.0 + disc("max_stress_averaged"));
    // The safety factor is judged on the worst of that and the sharp edges' stresses at the
    // critical distance, each on its unsafe side.
    let governing = r.governing_stress().map_or(stress, |(_, s)| s.max(stress));
    let volts = finest
        .readout
        .voltage_mv
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    check_values(
        volts / r.force_n.abs() * (1.0 - charge_disc),
        stress,
        fracture_mpa / governing,
        finest.readout.max_deflection_um.abs() * (1.0 + disc("deflection_at_load")),
        l,
    )
}

/// The limits `r` violates, as readable lines (`stress 812.0 MPa > 500 MPa`).
pub fn limit_failures(r: &SceneReport, l: &Limits) -> Vec<String> {
    check_limits(r, l)
        .iter()
        .filter(|c| !c.passed)
        .map(ToString::to_string)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_pass_fail_and_text() {
        let l = Limits {
            min_sensitivity_mv_per_n: Some(10.0),
            max_stress_mpa: Some(500.0),
            min_safety_factor: Some(1.0),
            max_deflection_um: Some(5.0),
        };
        let ok = check_values(12.0, 400.0, 3.0, -4.0, &l);
        assert_eq!(ok.len(), 4);
        assert!(ok.iter().all(|c| c.passed), "{ok:?}");
        let bad = check_values(9.5, 812.0, 0.8, -6.0, &l);
        let text: Vec<String> = bad
            .iter()
            .filter(|c| !c.passed)
            .map(ToString::to_string)
            .collect();
        assert_eq!(
            text,
            [
                "sensitivity 9.500 mV/N < 10 mV/N",
                "stress 812.0 MPa > 500 MPa",
                "safety factor 0.80 < 1",
                "deflection -6.0 um > 5 um"
            ]
        );
        // Bounds are inclusive; undeclared limits are not checked.
        assert!(check_values(10.0, 500.0, 1.0, 5.0, &l)
            .iter()
            .all(|c| c.passed));
        assert!(check_values(0.0, 1e9, 0.0, 1e9, &Limits::default()).is_empty());
    }
}
