//! Builds the [`EtchPlan`] step by step, carrying the wafer state (oxide, resist) along.

use serde::Serialize;

use super::compensation::{default_bar_width_um, design, CompensationDesign};
use super::geometry::{
    mesa_base_um, min_street_um, sidewall_run_out_um, undercut_um, v_groove_depth_um,
};
use super::limits::*;
use super::oxidation::{DealGrove, SI_CONSUMED_PER_OXIDE};
use super::rate::{koh_rate_100, koh_rate_110, tmah_rate_100};
use super::resist::spin_thickness_um;
use crate::finding::{DrcCode, EtchCode, Finding, Severity};
use crate::process::{
    CompensationGeometry, EtchMask, Etchant, Process, Side, StepParams, TeethPattern,
};
use crate::units::EPS0_F_PER_M;

/// Everything computed from the process. Field names are the stable JSON contract.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EtchPlan {
    pub wafer_thickness_um: f64,
    /// wafer - front etch depth - back etch depth, from the depths the recipe actually reaches.
    pub plate_thickness_um: f64,
    /// The target from the geometry, for comparison.
    pub plate_target_um: f64,
    /// Worst-case plate thickness range from the wafer tolerance.
    pub plate_range_um: [f64; 2],
    /// Thermal oxide grown per face by the oxidation model.
    pub oxide_thickness_um: f64,
    pub front_depth_um: f64,
    pub back_depth_um: f64,
    /// The plate's underside between the U-channel's etched {111} walls, across the die (y, um):
    /// the back mask's support edges moved inwards by the back etch's sidewall run-out. The plate
    /// is clamped here and the middle electrodes must lie inside it.
    pub channel_floor_y_um: [f64; 2],
    /// The etched {111} wall along support 1 (y, um): from the support's footprint edge (the back
    /// mask's edge less its undercut) to the channel floor's edge. Support 2's is its mirror.
    pub channel_wall_y_um: [f64; 2],
    pub steps: Vec<EtchStep>,
    pub oxidations: Vec<OxidationResult>,
    pub resists: Vec<ResistResult>,
    pub oxide_etches: Vec<OxideEtchResult>,
    /// Warnings and errors, each with a stable code.
    pub warnings: Vec<Finding>,
}

impl EtchPlan {
    pub fn has_errors(&self) -> bool {
        self.warnings.iter().any(Finding::is_error)
    }
}

/// One anisotropic silicon etch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EtchStep {
    pub name: String,
    /// Written `TMAH` or `KOH` (the JSON contract predates the enum).
    #[serde(serialize_with = "etchant_label")]
    pub etchant: Etchant,
    pub concentration_wt_pct: f64,
    pub temp_c: f64,
    pub side: Side,
    /// Target depth per face.
    pub depth_um: f64,
    /// (100) rate used: the measured override when given, else the model.
    pub rate_um_per_h: f64,
    pub rate_source: String,
    /// The model's (100) rate at this bath, reported even when a measurement overrides it.
    pub model_rate_um_per_h: f64,
    pub rate_110_um_per_h: f64,
    pub rate_111_um_per_h: f64,
    /// Time the recipe runs: the given time, else the time for the target depth.
    pub time_h: f64,
    /// Time to reach the target depth at this rate.
    pub time_for_depth_h: f64,
    /// Depth reached in `time_h`.
    pub achieved_depth_um: f64,
    pub sidewall_run_out_um: f64,
    pub undercut_um: f64,
    /// Narrowest street that still reaches the full depth.
    pub min_street_um: f64,
    /// Base of a tooth whose top is geometry.teeth.top_um (front and both-side etches).
    pub mesa_base_um: Option<f64>,
    pub mask: EtchMask,
    pub mask_consumed_um: f64,
    pub mask_remaining_um: f64,
    pub compensation: Option<CompensationDesign>,
}

fn etchant_label<S: serde::Serializer>(e: &Etchant, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(e.label())
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OxidationResult {
    pub name: String,
    pub thickness_um: f64,
    pub time_h: f64,
    pub temp_c: f64,
    pub b_um2_per_h: f64,
    pub b_over_a_um_per_h: f64,
    pub silicon_consumed_um: f64,
    /// Time the model needs for the source's claimed thickness, when one is given.
    pub time_for_expected_h: Option<f64>,
    pub expected_thickness_um: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResistResult {
    pub name: String,
    pub resist: String,
    pub side: Side,
    pub speed_rpm: f64,
    pub thickness_um: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OxideEtchResult {
    pub name: String,
    pub oxide_um: f64,
    pub rate_um_per_min: f64,
    /// Time to clear plus the over-etch.
    pub time_min: f64,
}

/// What the steps have computed so far, and the wafer state (oxide, etched depths) they carry.
#[derive(Default)]
struct PlanState {
    /// Oxide on the wafer now, per face.
    oxide_um: f64,
    front: f64,
    back: f64,
    oxidations: Vec<OxidationResult>,
    resists: Vec<ResistResult>,
    oxide_etches: Vec<OxideEtchResult>,
    steps: Vec<EtchStep>,
    warnings: Vec<Finding>,
}

impl PlanState {
    /// A silicon etch done: the depths it adds per face and the oxide it leaves.
    fn record(&mut self, side: Side, step: EtchStep) {
        if matches!(side, Side::Front | Side::Both) {
            self.front += step.achieved_depth_um;
        }
        if matches!(side, Side::Back | Side::Both) {
            self.back += step.achieved_depth_um;
        }
        self.oxide_um = step.mask_remaining_um.max(0.0);
        self.steps.push(step);
    }
}

/// Resist still on the wafer going into an anisotropic bath whose mask is oxide or nitride: TMAH
/// is a positive-resist developer and KOH strips resist (reference/process-physics.md: resist is
/// not a mask), so the coat dissolves into the bath, loading it and leaving residue; the source's
/// own order (paper 002: strip after the etch) is kept, with this warning.
fn resist_in_bath(
    index: usize,
    name: &str,
    e: &crate::process::SiliconEtch,
    coats: &[&str],
) -> Finding {
    Finding::warning(
        EtchCode::ResistInBath,
        format!(
            "step `{name}` (traveler step {}): the resist of {} is still on the wafer and \
             dissolves in the {} bath (hot, alkaline: TMAH develops positive resist); strip it \
             before the etch, or plan for the bath's loading and a post-etch clean",
            index + 1,
            coats
                .iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", "),
            e.etchant.label()
        ),
    )
}

/// The plan: each step's results in order, then the plate, geometry and piezo checks.
pub(super) fn build(p: &Process) -> EtchPlan {
    let mut st = PlanState::default();
    // The resist coats on the wafer now (stripped by a resist strip).
    let mut resist_on: Vec<&str> = Vec::new();
    for (i, s) in p.steps.iter().enumerate() {
        match &s.params {
            StepParams::Oxidation(o) => oxidation(p, &s.name, o, &mut st),
            StepParams::SpinCoat(c) => {
                resist_on.push(&s.name);
                st.resists.push(spin_coat(&s.name, c))
            }
            StepParams::Strip(strip) if strip.target == crate::process::StripTarget::Resist => {
                resist_on.clear()
            }
            StepParams::SiliconEtch(e) if e.mask != EtchMask::Resist && !resist_on.is_empty() => {
                st.warnings.push(resist_in_bath(i, &s.name, e, &resist_on));
                resist_on.clear();
                let step = silicon_etch(p, &s.name, e, st.oxide_um, &mut st.warnings);
                st.record(e.side, step);
            }
            StepParams::OxideEtch(e) => {
                let r = oxide_etch(p, &s.name, e, st.oxide_um);
                st.oxide_etches.push(r);
            }
            StepParams::Strip(strip) if strip.target == crate::process::StripTarget::Oxide => {
                st.oxide_um = 0.0
            }
            StepParams::SiliconEtch(e) => {
                let step = silicon_etch(p, &s.name, e, st.oxide_um, &mut st.warnings);
                st.record(e.side, step);
            }
            _ => {}
        }
    }

    let wafer = p.wafer.thickness_um;
    let (front, back) = (st.front, st.back);
    let plate = wafer - front - back;
    let tol = p.wafer.thickness_tolerance_um;
    if !st.steps.is_empty() {
        plate_checks(p, front, back, &mut st.warnings);
    }
    geometry_checks(p, &st.steps, &mut st.warnings);
    piezo_check(p, &mut st.warnings);

    EtchPlan {
        wafer_thickness_um: wafer,
        plate_thickness_um: plate,
        plate_target_um: p.geometry.plate_thickness_um,
        plate_range_um: [plate - tol, plate + tol],
        oxide_thickness_um: st.oxidations.last().map(|o| o.thickness_um).unwrap_or(0.0),
        front_depth_um: front,
        back_depth_um: back,
        channel_floor_y_um: channel_floor_y_um(p, back, back_undercut_um(&st.steps)),
        channel_wall_y_um: [
            p.geometry.support_width_um - back_undercut_um(&st.steps),
            channel_floor_y_um(p, back, back_undercut_um(&st.steps))[0],
        ],
        steps: st.steps,
        oxidations: st.oxidations,
        resists: st.resists,
        oxide_etches: st.oxide_etches,
        warnings: st.warnings,
    }
}

/// The channel floor as etched: a <110> mask edge etched `back_depth_um` deep ends in a {111}
/// wall whose foot lies h / tan 54.74 deg inside the edge ([`sidewall_run_out_um`]), less the
/// edge's undercut R111 t / sin 54.74 deg ([`undercut_um`]), both from process-physics.md. The
/// supports are drawn `support_width_um` wide on both long edges.
pub fn channel_floor_y_um(p: &Process, back_depth_um: f64, back_undercut_um: f64) -> [f64; 2] {
    let g = &p.geometry;
    let edge = g.support_width_um - back_undercut_um + sidewall_run_out_um(back_depth_um.max(0.0));
    [edge, g.die_width_um - edge]
}

/// Undercut of the back mask's edges summed over the back-side silicon etches.
fn back_undercut_um(steps: &[EtchStep]) -> f64 {
    steps
        .iter()
        .filter(|s| matches!(s.side, Side::Back | Side::Both))
        .map(|s| s.undercut_um)
        .sum()
}

/// An oxidation: Deal-Grove growth from the oxide already there, checked against the thickness
/// the source claims; the grown oxide becomes the wafer's.
fn oxidation(p: &Process, name: &str, o: &crate::process::Oxidation, st: &mut PlanState) {
    let dg = DealGrove::new(o.ambient, p.wafer.orientation, o.temp_c);
    let initial = o.initial_oxide_um.max(st.oxide_um);
    let x = dg.thickness_um(o.time_h, initial);
    let time_for_expected_h = o.expected_thickness_um.map(|e| dg.time_for_h(e, initial));
    if let (Some(e), Some(t)) = (o.expected_thickness_um, time_for_expected_h) {
        if (x - e).abs() / e > OXIDE_CLAIM_REL {
            st.warnings.push(Finding::warning(
                EtchCode::OxideClaim,
                format!(
                    "step `{}`: Deal-Grove gives {x:.3} um of oxide in {} h at {} C, \
                     not the {e} um stated; {e} um needs {t:.2} h",
                    name, o.time_h, o.temp_c
                ),
            ));
        }
    }
    st.oxidations.push(OxidationResult {
        name: name.to_string(),
        thickness_um: x,
        time_h: o.time_h,
        temp_c: o.temp_c,
        b_um2_per_h: dg.b_um2_per_h,
        b_over_a_um_per_h: dg.b_over_a_um_per_h,
        silicon_consumed_um: SI_CONSUMED_PER_OXIDE * (x - initial),
        time_for_expected_h,
        expected_thickness_um: o.expected_thickness_um,
    });
    st.oxide_um = x;
}

/// A spin coat: resist thickness from the spin curve.
fn spin_coat(name: &str, c: &crate::process::SpinCoat) -> ResistResult {
    ResistResult {
        name: name.to_string(),
        resist: c.resist.clone(),
        side: c.side,
        speed_rpm: c.speed_rpm,
        thickness_um: spin_thickness_um(
            c.ref_thickness_um,
            c.ref_speed_rpm,
            c.spin_exponent,
            c.speed_rpm,
        ),
    }
}

/// An oxide etch: time = oxide / BOE rate x (1 + over-etch).
fn oxide_etch(
    p: &Process,
    name: &str,
    e: &crate::process::OxideEtch,
    oxide_um: f64,
) -> OxideEtchResult {
    let rate = p.etchants.boe_rate_um_per_min;
    OxideEtchResult {
        name: name.to_string(),
        oxide_um,
        rate_um_per_min: rate,
        time_min: oxide_um / rate * (1.0 + e.overetch_pct / 100.0),
    }
}

/// The plate the etches leave (wafer - front - back) against the wafer, the geometry's target
/// and the wafer tolerance.
fn plate_checks(p: &Process, front: f64, back: f64, warnings: &mut Vec<Finding>) {
    let g = &p.geometry;
    let wafer = p.wafer.thickness_um;
    let plate = wafer - front - back;
    let tol = p.wafer.thickness_tolerance_um;
    if front + back >= wafer {
        warnings.push(Finding::error(
            EtchCode::DepthExceedsWafer,
            format!("front {front:.1} um + back {back:.1} um etch through the {wafer} um wafer"),
        ));
    } else if (plate - g.plate_thickness_um).abs() / g.plate_thickness_um > MISMATCH_REL {
        let severity = if (plate - g.plate_thickness_um).abs() / g.plate_thickness_um
            > PLATE_MISMATCH_ERROR_REL
        {
            Severity::Error
        } else {
            Severity::Warning
        };
        warnings.push(Finding::new(
            severity,
            EtchCode::PlateThicknessMismatch,
            format!(
                "the recipe leaves a {plate:.1} um plate ({wafer} - {front:.1} - {back:.1}), \
                 not the {} um of geometry.plate_thickness_um",
                g.plate_thickness_um
            ),
        ));
    }
    if tol / g.plate_thickness_um > PLATE_TOLERANCE_REL {
        warnings.push(Finding::warning(
            EtchCode::PlateTolerance,
            format!(
                "the wafer tolerance +/-{tol} um goes straight into the plate: {:.0}-{:.0} \
                 um; etch to 90 % of the time, measure the depth, then finish",
                plate - tol,
                plate + tol
            ),
        ));
    }
}

/// One anisotropic silicon etch: rates, time and depth, mask budget, compensation.
fn silicon_etch(
    p: &Process,
    name: &str,
    e: &crate::process::SiliconEtch,
    oxide_um: f64,
    warnings: &mut Vec<Finding>,
) -> EtchStep {
    let bath = bath_rates(p, name, e, warnings);
    let (rate, rate_source) = used_rate(p, name, e, bath.model_100, warnings);
    let scale = rate / bath.model_100;
    let r111 = rate / bath.r100_over_r111;
    let time_for_depth_h = e.depth_um / rate;
    let time_h = e.time_h.unwrap_or(time_for_depth_h);
    let achieved = rate * time_h;
    time_depth_check(name, e, rate, time_h, time_for_depth_h, achieved, warnings);
    let mask = mask_budget(name, e, bath.oxide_rate, oxide_um, time_h, warnings);
    let front_side = matches!(e.side, Side::Front | Side::Both);
    let teeth = &p.geometry.teeth;
    let compensation = if teeth.pattern != TeethPattern::None && front_side {
        let bar_width_um =
            default_bar_width_um(undercut_um(r111, time_h), p.drc.min_width_um, teeth.top_um);
        compensation(name, e, bar_width_um, warnings)
    } else {
        None
    };
    EtchStep {
        name: name.to_string(),
        etchant: e.etchant,
        concentration_wt_pct: e.concentration_wt_pct,
        temp_c: e.temp_c,
        side: e.side,
        depth_um: e.depth_um,
        rate_um_per_h: rate,
        rate_source,
        model_rate_um_per_h: bath.model_100,
        rate_110_um_per_h: bath.r110 * scale,
        rate_111_um_per_h: r111,
        time_h,
        time_for_depth_h,
        achieved_depth_um: achieved,
        sidewall_run_out_um: sidewall_run_out_um(achieved),
        undercut_um: undercut_um(r111, time_h),
        min_street_um: min_street_um(e.depth_um),
        mesa_base_um: (front_side && teeth.pattern != TeethPattern::None)
            .then(|| mesa_base_um(teeth.top_um, achieved)),
        mask: e.mask,
        mask_consumed_um: if mask.consumed.is_finite() {
            mask.consumed
        } else {
            0.0
        },
        mask_remaining_um: if mask.remaining.is_finite() {
            mask.remaining
        } else {
            0.0
        },
        compensation,
    }
}

/// The model rates of a bath: (100) and (110) rates, R100/R111 and the oxide mask's rate.
struct BathRates {
    model_100: f64,
    r110: f64,
    r100_over_r111: f64,
    oxide_rate: f64,
}

/// The bath's model rates: TMAH from the table with Arrhenius, KOH from Seidel 1990.
fn bath_rates(
    p: &Process,
    name: &str,
    e: &crate::process::SiliconEtch,
    warnings: &mut Vec<Finding>,
) -> BathRates {
    let et = &p.etchants;
    match e.etchant {
        Etchant::Tmah => {
            let r = tmah_model_rate(p, name, e, warnings);
            BathRates {
                model_100: r,
                r110: r * et.tmah_r110_over_r100,
                r100_over_r111: et.tmah_r100_over_r111,
                oxide_rate: et.tmah_oxide_rate_um_per_h,
            }
        }
        Etchant::Koh => BathRates {
            model_100: koh_rate_100(e.concentration_wt_pct, e.temp_c),
            r110: koh_rate_110(e.concentration_wt_pct, e.temp_c),
            r100_over_r111: et.koh_r100_over_r111,
            oxide_rate: et.koh_oxide_rate_um_per_h,
        },
    }
}

/// The TMAH (100) model rate (table + Arrhenius), warning on extrapolation and hillocks.
fn tmah_model_rate(
    p: &Process,
    name: &str,
    e: &crate::process::SiliconEtch,
    warnings: &mut Vec<Finding>,
) -> f64 {
    let et = &p.etchants;
    let table: Vec<_> = et
        .tmah
        .iter()
        .map(|r| (r.concentration_wt_pct, r.rate_100_um_per_h, r.temp_c))
        .collect();
    let (r, extrapolated) = tmah_rate_100(&table, e.concentration_wt_pct, e.temp_c, et.tmah_ea_ev);
    if extrapolated && e.measured_rate_um_per_h.is_none() {
        warnings.push(Finding::warning(
            EtchCode::RateExtrapolated,
            format!(
                "step `{name}`: no TMAH rate measured near {} wt %; the nearest table row \
                 is used",
                e.concentration_wt_pct
            ),
        ));
    }
    if e.concentration_wt_pct < TMAH_HILLOCK_WT_PCT {
        warnings.push(Finding::warning(
            EtchCode::HillockRisk,
            format!(
                "step `{name}`: TMAH at {} wt % forms hillocks on (100) below ~{TMAH_HILLOCK_WT_PCT} wt %",
                e.concentration_wt_pct
            ),
        ));
    }
    r
}

/// The (100) rate used and its source: the measured override when given (warning when it
/// disagrees with the model), else the model.
fn used_rate(
    p: &Process,
    name: &str,
    e: &crate::process::SiliconEtch,
    model_100: f64,
    warnings: &mut Vec<Finding>,
) -> (f64, String) {
    let (rate, rate_source) = match e.measured_rate_um_per_h {
        Some(m) => (m, "measured (process file)".to_string()),
        None => match e.etchant {
            Etchant::Tmah => (
                model_100,
                format!("TMAH table + Arrhenius, Ea = {} eV", p.etchants.tmah_ea_ev),
            ),
            Etchant::Koh => (model_100, "Seidel 1990 KOH model".to_string()),
        },
    };
    if let Some(m) = e.measured_rate_um_per_h {
        if (m - model_100).abs() / model_100 > RATE_MODEL_REL {
            warnings.push(Finding::warning(
                EtchCode::RateModelDisagrees,
                format!(
                    "step `{name}`: measured {m} um/h vs model {model_100:.1} um/h; the \
                     measurement is used"
                ),
            ));
        }
    }
    (rate, rate_source)
}

/// Depth reached in the recipe's time (rate x time) against the target depth.
fn time_depth_check(
    name: &str,
    e: &crate::process::SiliconEtch,
    rate: f64,
    time_h: f64,
    time_for_depth_h: f64,
    achieved: f64,
    warnings: &mut Vec<Finding>,
) {
    if (achieved - e.depth_um).abs() / e.depth_um > MISMATCH_REL {
        warnings.push(Finding::warning(
            EtchCode::EtchTimeDepthMismatch,
            format!(
                "step `{name}`: {time_h} h at {rate} um/h etches {achieved:.1} um per face, not \
                 {} um; {:.3} h reaches {} um",
                e.depth_um, time_for_depth_h, e.depth_um
            ),
        ));
    }
}

/// Mask consumed and left after a silicon etch (infinite for nitride and resist).
struct MaskBudget {
    consumed: f64,
    remaining: f64,
}

/// The mask budget: erosion = mask rate x time against the mask there, with the errors of a
/// resist mask, no oxide, a consumed oxide and the warning of a low margin.
fn mask_budget(
    name: &str,
    e: &crate::process::SiliconEtch,
    oxide_rate: f64,
    oxide_um: f64,
    time_h: f64,
    warnings: &mut Vec<Finding>,
) -> MaskBudget {
    let mask_rate = match e.mask {
        EtchMask::Oxide => oxide_rate,
        EtchMask::Nitride => 0.0,
        EtchMask::Resist => f64::INFINITY,
    };
    let consumed = if mask_rate.is_finite() {
        mask_rate * time_h
    } else {
        f64::INFINITY
    };
    let (start, remaining) = match e.mask {
        EtchMask::Oxide => (oxide_um, oxide_um - consumed),
        EtchMask::Nitride => (f64::INFINITY, f64::INFINITY),
        EtchMask::Resist => (0.0, f64::NEG_INFINITY),
    };
    match e.mask {
        EtchMask::Resist => warnings.push(Finding::error(
            EtchCode::ResistNotAMask,
            format!(
                "step `{name}`: photoresist does not mask {}: it dissolves (its developer is \
                 TMAH); use thermal oxide or nitride",
                e.etchant.label()
            ),
        )),
        EtchMask::Oxide if start <= 0.0 => warnings.push(Finding::error(
            EtchCode::NoOxideMask,
            format!("step `{name}`: masked by oxide, but no oxide is grown before it"),
        )),
        EtchMask::Oxide if remaining <= 0.0 => warnings.push(Finding::error(
            EtchCode::MaskConsumed,
            format!(
                "step `{name}`: {:.2} um of oxide is etched away in {time_h:.2} h at {mask_rate} \
                 um/h, but only {start:.3} um was grown; the mask fails at {:.1} h",
                consumed,
                start / mask_rate
            ),
        )),
        EtchMask::Oxide if remaining < MASK_MARGIN_REL * start => warnings.push(Finding::warning(
            EtchCode::MaskMarginLow,
            format!(
                "step `{name}`: only {remaining:.3} um of the {start:.3} um oxide is left at the \
                 end"
            ),
        )),
        _ => {}
    }
    MaskBudget {
        consumed,
        remaining,
    }
}

/// The corner compensation of an etch that shapes teeth: a = h / ratio, warning when the ratio is
/// the KOH rule used with TMAH or when there is none; a bar is the file's width wide, else
/// `default_bar_width_um`.
fn compensation(
    name: &str,
    e: &crate::process::SiliconEtch,
    default_bar_width_um: f64,
    warnings: &mut Vec<Finding>,
) -> Option<CompensationDesign> {
    let Some(c) = &e.compensation else {
        warnings.push(Finding::warning(
            EtchCode::NoCompensation,
            format!(
                "step `{name}`: the tooth corners are convex and will be undercut without \
                 compensation"
            ),
        ));
        return None;
    };
    if e.etchant == Etchant::Tmah && KOH_RULE_RATIO.contains(&c.ratio) {
        let a = e.depth_um / c.ratio;
        warnings.push(Finding::warning(
            EtchCode::CompRatioFromKoh,
            format!(
                "step `{name}`: a = h/{} comes from KOH rate ratios (R100/R110 = \
                 0.548); it is unvalidated for TMAH, whose convex corners undercut \
                 along near-{{110}} planes: add a test die with a from {:.0} to {:.0} \
                 um",
                c.ratio,
                0.8 * a,
                1.5 * a
            ),
        ));
    }
    let bar_width_um = (c.geometry == CompensationGeometry::Bar110)
        .then(|| c.bar_width_um.unwrap_or(default_bar_width_um));
    Some(design(e.depth_um, c.ratio, c.geometry, bar_width_um))
}

/// Cross-checks of geometry against the etch steps: depths, teeth spacing, compensators.
fn geometry_checks(p: &Process, steps: &[EtchStep], warnings: &mut Vec<Finding>) {
    depth_checks(p, steps, warnings);
    let t = &p.geometry.teeth;
    if t.pattern == TeethPattern::None {
        return;
    }
    let Some(front) = steps
        .iter()
        .find(|s| matches!(s.side, Side::Front | Side::Both))
    else {
        return;
    };
    street_check(t, front, warnings);
    if let Some(c) = &front.compensation {
        compensator_checks(&p.geometry, c, warnings);
    }
}

/// Wafer - teeth - channel must be the plate, and the etch depths per face the teeth height and
/// the channel depth.
fn depth_checks(p: &Process, steps: &[EtchStep], warnings: &mut Vec<Finding>) {
    let g = &p.geometry;
    let t = &g.teeth;
    let w = p.wafer.thickness_um;
    let implied = w - t.height_um * f64::from(t.pattern != TeethPattern::None) - g.channel_depth_um;
    if t.pattern != TeethPattern::None && (implied - g.plate_thickness_um).abs() > 1e-6 {
        warnings.push(Finding::error(
            EtchCode::GeometryInconsistent,
            format!(
                "wafer {w} - teeth {} - channel {} = {implied} um, but \
                 geometry.plate_thickness_um is {}",
                t.height_um, g.channel_depth_um, g.plate_thickness_um
            ),
        ));
    }
    let front_target: f64 = steps
        .iter()
        .filter(|s| matches!(s.side, Side::Front | Side::Both))
        .map(|s| s.depth_um)
        .sum();
    let back_target: f64 = steps
        .iter()
        .filter(|s| matches!(s.side, Side::Back | Side::Both))
        .map(|s| s.depth_um)
        .sum();
    if !steps.is_empty()
        && t.pattern != TeethPattern::None
        && (front_target - t.height_um).abs() > 1e-6
    {
        warnings.push(Finding::error(
            EtchCode::DepthGeometryMismatch,
            format!(
                "front etch depth {front_target} um differs from geometry.teeth.height_um {}",
                t.height_um
            ),
        ));
    }
    if !steps.is_empty() && (back_target - g.channel_depth_um).abs() > 1e-6 {
        warnings.push(Finding::error(
            EtchCode::DepthGeometryMismatch,
            format!(
                "back etch depth {back_target} um differs from geometry.channel_depth_um {}",
                g.channel_depth_um
            ),
        ));
    }
}

/// The narrowest street between facing parallel tooth edges must exceed the V-groove self-stop
/// width of the front etch.
fn street_check(t: &crate::process::Teeth, front: &EtchStep, warnings: &mut Vec<Finding>) {
    let (gx, gy) = (t.pitch_x_um - t.top_um, t.pitch_y_um - t.top_um);
    // Narrowest street between facing parallel tooth edges.
    let street = match t.pattern {
        TeethPattern::Matrix => gx.min(gy),
        _ => (2.0 * t.pitch_x_um - t.top_um).min(2.0 * t.pitch_y_um - t.top_um),
    };
    if street < front.min_street_um {
        warnings.push(Finding::error(
            DrcCode::StreetTooNarrow,
            format!(
                "the {street:.0} um street between teeth self-stops as a V-groove {:.0} um deep; \
                 full depth {} um needs {:.0} um (the tooth bases merge)",
                v_groove_depth_um(street),
                front.depth_um,
                front.min_street_um
            ),
        ));
    }
}

/// Compensators of facing tooth corners must not merge, and those of the outer teeth must stay
/// on the die.
fn compensator_checks(
    g: &crate::process::Geometry,
    c: &CompensationDesign,
    warnings: &mut Vec<Finding>,
) {
    let t = &g.teeth;
    let (gx, gy) = (t.pitch_x_um - t.top_um, t.pitch_y_um - t.top_um);
    let (nx, ny) = (c.min_gap.x_um, c.min_gap.y_um);
    // Facing corners: orthogonal neighbours (matrix) across gx or gy; diagonal neighbours
    // (checkered) across gx and gy at once, and the teeth two cells away along a row or
    // column (what a bar, reaching along x only, meets first) across pitch + street.
    let (two_x, two_y) = (gx + t.pitch_x_um, gy + t.pitch_y_um);
    let collide = match t.pattern {
        TeethPattern::Matrix => gx < nx || gy < ny,
        _ => (gx < nx && gy < ny) || two_x < nx || two_y < ny,
    };
    let kind = match c.kind {
        CompensationGeometry::CornerAttached => "corner-attached",
        CompensationGeometry::Centred => "centred",
        CompensationGeometry::Bar110 => "<110> bar",
    };
    if collide {
        let (needs, leaves, raise) = if nx == ny {
            (
                format!("{nx:.1} um"),
                format!("{gx:.0} x {gy:.0} um"),
                t.top_um + nx,
            )
        } else if t.pattern == TeethPattern::Matrix {
            (
                format!("{nx:.1} x {ny:.1} um"),
                format!("{gx:.0} x {gy:.0} um"),
                t.top_um + nx,
            )
        } else {
            (
                format!("{nx:.1} x {ny:.1} um"),
                format!("{two_x:.0} x {two_y:.0} um two cells apart"),
                0.5 * (t.top_um + nx),
            )
        };
        warnings.push(Finding::error(
            DrcCode::CompensatorsCollide,
            format!(
                "{kind} compensators of {:.1} um need {needs} between facing tooth corners; the \
                 pitch leaves {leaves}: they merge into a bridge. Raise the pitch to >= \
                 {raise:.0} um",
                c.side_um,
            ),
        ));
    }
    // Outermost teeth: compensators reach `reach` beyond the tooth top.
    let inset = (t.pitch_x_um - t.top_um) / 2.0;
    let inset_y = (t.pitch_y_um - t.top_um) / 2.0;
    let (rx, ry) = (c.reach.x_um, c.reach.y_um);
    let x0 = t.origin_x_um + inset - rx;
    let y0 = t.origin_y_um + inset_y - ry;
    let x1 = t.origin_x_um + t.count_x as f64 * t.pitch_x_um - inset + rx;
    let y1 = t.origin_y_um + t.count_y as f64 * t.pitch_y_um - inset_y + ry;
    if x0 < 0.0 || y0 < 0.0 || x1 > g.die_length_um || y1 > g.die_width_um {
        warnings.push(Finding::error(
            DrcCode::CompensatorOutsideDie,
            format!(
                "compensators of the outer teeth span x {x0:.0}..{x1:.0}, y {y0:.0}..{y1:.0} um, \
                 beyond the {} x {} um die",
                g.die_length_um, g.die_width_um
            ),
        ));
    }
}

/// g = d / (eps0 eps_r) (IEEE piezo relations; fe-validation.md): report when the given g, d and
/// eps_r disagree by more than 10 %.
fn piezo_check(p: &Process, warnings: &mut Vec<Finding>) {
    let f = &p.materials.pvdf;
    for (label, d, g) in [
        ("31", f.d31_pc_per_n, f.g31_vm_per_n),
        ("32", f.d32_pc_per_n, f.g32_vm_per_n),
        ("33", f.d33_pc_per_n, f.g33_vm_per_n),
    ] {
        let Some(g) = g else { continue };
        if g == 0.0 || d == 0.0 {
            continue;
        }
        let implied_eps_r = d * 1e-12 / (g * EPS0_F_PER_M);
        if (implied_eps_r - f.eps_r).abs() / f.eps_r > PIEZO_EPS_REL {
            warnings.push(Finding::warning(
                EtchCode::PiezoConstantsInconsistent,
                format!(
                    "d{label} = {d} pC/N with g{label} = {g} V m/N implies eps_r = \
                     {implied_eps_r:.1}, but eps_r is {}; tactfab uses d and eps_r and derives \
                     g{label} = {:.4} V m/N",
                    f.eps_r,
                    d * 1e-12 / (f.eps_r * EPS0_F_PER_M)
                ),
            ));
        }
    }
}
