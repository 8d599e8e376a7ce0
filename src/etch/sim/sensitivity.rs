//! The corner's sensitivity to the least-known rates (issue 19, item 5): the {311} and {411}
//! rates moved over their stated bands, one at a time, the rest of the table as the process
//! gives it.

use serde::Serialize;

use crate::etch::EtchPlan;
use crate::layout::MaskSet;
use crate::process::{Etchant, Process};

use super::run::{front_step, rate_table, simulate_with};
use super::SimError;

/// R311/R100 band for TMAH \[est: no source in ../shared; the top at R110/R100 = 1.75 so that
/// the convex-corner planes stay near {110}, reference/process-physics.md\].
pub const TMAH_R311_BAND: [f64; 2] = [0.9, 1.75];
/// R411/R100 band for TMAH \[est, as for {311}\].
pub const TMAH_R411_BAND: [f64; 2] = [0.9, 1.75];
/// R311/R100 band for KOH: Sato 1998's 1.80 +/- 15 % \[est: bath-to-bath scatter\].
pub const KOH_R311_BAND: [f64; 2] = [1.53, 2.07];
/// R411/R100 band for KOH \[est: no {411} rate in ../shared; KOH's convex-corner planes are
/// {411}, so they are among the fastest\].
pub const KOH_R411_BAND: [f64; 2] = [1.2, 2.2];

/// One run of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Case {
    /// `nominal`, `r311_low`, `r311_high`, `r411_low`, `r411_high`.
    pub case: String,
    pub r311_over_r100: f64,
    /// None: interpolated between {100} and {311}.
    pub r411_over_r100: Option<f64>,
    pub corner_deviation_um: f64,
    pub edge_undercut_um: f64,
    pub compensator_consumed_h: Option<f64>,
}

/// The sweep and its spread.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    pub cases: Vec<Case>,
    /// Largest minus smallest corner deviation over the cases.
    pub corner_spread_um: f64,
}

/// Runs the nominal table and each band end of {311} and {411}.
pub fn sweep(
    p: &Process,
    plan: &EtchPlan,
    masks: &MaskSet,
    grid_um: f64,
) -> Result<Sensitivity, SimError> {
    let step = front_step(plan).ok_or(SimError::NoFrontEtch)?;
    let base = rate_table(step, &p.etchants);
    let r100 = base.r100_um_per_h;
    let (b311, b411) = match step.etchant {
        Etchant::Tmah => (TMAH_R311_BAND, TMAH_R411_BAND),
        Etchant::Koh => (KOH_R311_BAND, KOH_R411_BAND),
    };
    let nominal311 = base.r311_um_per_h.map_or(1.0, |r| r / r100);
    let nominal411 = base.r411_um_per_h.map(|r| r / r100);
    let variants = [
        ("nominal", nominal311, nominal411),
        ("r311_low", b311[0], nominal411),
        ("r311_high", b311[1], nominal411),
        ("r411_low", nominal311, Some(b411[0])),
        ("r411_high", nominal311, Some(b411[1])),
    ];
    let mut cases = Vec::new();
    for (name, r311, r411) in variants {
        let mut t = base;
        t.r311_um_per_h = Some(r311 * r100);
        t.r411_um_per_h = r411.map(|r| r * r100);
        let s = simulate_with(p, step, masks, grid_um, t)?;
        cases.push(Case {
            case: name.to_string(),
            r311_over_r100: r311,
            r411_over_r100: r411,
            corner_deviation_um: s.corner_deviation_um,
            edge_undercut_um: s.edge_undercut_um,
            compensator_consumed_h: s.compensator_consumed_h,
        });
    }
    let (lo, hi) = cases
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
            (a.min(c.corner_deviation_um), b.max(c.corner_deviation_um))
        });
    Ok(Sensitivity {
        cases,
        corner_spread_um: hi - lo,
    })
}
