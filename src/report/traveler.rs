//! The traveler (run sheet) as data: header, starting material, masks, one row per step with what
//! tactfab computed and its provenance, hold points, the stack after each step, checks, the places
//! where the source disagrees with the computation, the FE summary and the compensation design.
//! The writers ([`super::markdown`], [`super::html`]) only format it.

use serde::Serialize;

use crate::drc::DrcReport;
use crate::etch::compensation::Reach;
use crate::etch::{limits, EtchPlan, EtchStep, OxidationResult, OxideEtchResult, ResistResult};
use crate::finding::{Code, EtchCode, Finding};
use crate::layout::MaskSet;
use crate::process::{
    Assemble, Etchant, Expose, Generic, MetalEtch, Oxidation, OxideEtch, Process, Provenance, Side,
    SiliconEtch, SpinCoat, Step, StepParams,
};

use super::fe::FeSummary;
use super::inventory::Inventory;
use super::section::{stacks, Cut, Stack};

/// Oxide thickness tolerance: what the plan's OXIDE_CLAIM check allows.
pub const OXIDE_TOL_REL: f64 = limits::OXIDE_CLAIM_REL;
/// Etch depth tolerance: beyond it the plan calls a depth "not what was asked".
pub const DEPTH_TOL_REL: f64 = limits::MISMATCH_REL;
/// Plate tolerance: that of the plan's PLATE_TOLERANCE check.
pub const PLATE_TOL_REL: f64 = limits::PLATE_TOLERANCE_REL;
/// Resist thickness tolerance \[choice\]: spin-coat repeatability of a few %; 10 % flags a wrong
/// speed.
pub const RESIST_TOL_REL: f64 = 0.10;
/// Stop for a depth measurement at this fraction of the computed time (process-physics.md).
pub const HOLD_FRACTION: f64 = 0.9;
/// Oxide left after the silicon etch must stay above this share of the grown oxide.
pub use limits::MASK_MARGIN_REL;

/// A computed number and where it comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Computed {
    pub what: String,
    pub value: String,
    pub provenance: String,
}

/// What the operator measures against.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Target {
    pub quantity: String,
    /// `200.0 um +/- 2.0 um`.
    pub value: String,
    /// Why this tolerance.
    pub basis: String,
}

/// One process step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepRow {
    pub number: usize,
    pub name: String,
    /// The step kind in words.
    pub process: String,
    pub equipment: String,
    pub parameters: String,
    pub computed: Vec<Computed>,
    pub target: Option<Target>,
    /// Hold point ids that belong to this step.
    pub holds: Vec<String>,
    /// What the floor does around the step whatever the file says: safety, rinse and dry,
    /// inspection ([`floor_notes`]).
    pub floor: Vec<String>,
}

/// Safety, rinse/dry and inspection lines for a step of this kind [choice: the practice of
/// university cleanroom wet-bench SOPs; the process file's `notes` add to them]. HF (BOE, oxide
/// strip) and hot TMAH are the two chemicals of this process that kill through skin contact.
pub fn floor_notes(params: &StepParams) -> Vec<String> {
    const DRY: &str = "Rinse: DI water cascade until the resistivity recovers, then N2 dry.";
    const HF: &str = "Safety: HF (BOE): HF-rated gloves over nitrile, face shield and apron, \
                      calcium gluconate gel at the bench; never alone.";
    match params {
        StepParams::Clean(_) => vec![
            "Safety: follow the chemical's SOP (acids: face shield and apron).".into(),
            DRY.into(),
        ],
        StepParams::Develop(_) => vec![
            DRY.into(),
            "Inspect: microscope; every opening cleared, edges sharp, no resist residue, before \
             any etch."
                .into(),
        ],
        StepParams::OxideEtch(_) => vec![
            HF.into(),
            DRY.into(),
            "Inspect: the opened silicon dewets (hydrophobic) when the oxide is cleared.".into(),
        ],
        StepParams::SiliconEtch(e) => vec![
            match e.etchant {
                crate::process::Etchant::Tmah => format!(
                    "Safety: hot TMAH ({} C) is toxic through the skin (fatal exposures \
                     reported): face shield, chemical gloves and apron, lid and condenser on the \
                     bath; never alone.",
                    e.temp_c
                ),
                crate::process::Etchant::Koh => format!(
                    "Safety: hot KOH ({} C) is caustic: face shield, chemical gloves and apron; \
                     never alone.",
                    e.temp_c
                ),
            },
            "Rinse: DI water cascade, then a hot DI rinse (no residue crystallises), N2 dry; \
             wafers stay vertical in their carrier."
                .into(),
        ],
        StepParams::Strip(s) => match s.target {
            crate::process::StripTarget::Oxide => vec![HF.into(), DRY.into()],
            crate::process::StripTarget::Resist => vec![
                "Safety: solvents are flammable: fume hood, no hotplate on.".into(),
                "Rinse: IPA, then DI water, N2 dry.".into(),
            ],
        },
        StepParams::MetalEtch(_) => vec![
            "Safety: acid etchant: face shield, gloves and apron.".into(),
            DRY.into(),
            "Inspect: microscope; every island separated, no aluminium bridges.".into(),
        ],
        StepParams::Expose(_) => {
            vec!["Safety: UV: the aligner's shield closed; no eye exposure.".into()]
        }
        StepParams::Oxidation(o) => vec![format!(
            "Safety: furnace at {} C: the boat on the paddle, heat gloves, wafers cool on the \
             boat before handling.",
            o.temp_c
        )],
        StepParams::Bake(b) if b.temp_c >= 90.0 => {
            vec!["Safety: hot plate or oven at over 90 C: tweezers, heat gloves.".into()]
        }
        StepParams::Bake(_) => Vec::new(),
        StepParams::SpinCoat(_) | StepParams::Mount(_) | StepParams::Assemble(_) => Vec::new(),
    }
}

/// A stop with engineer sign-off.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoldPoint {
    pub id: String,
    /// Step name (or `start`).
    pub step: String,
    pub when: String,
    pub measure: String,
    /// One blank per reading the measurement asks for, by label.
    pub readings: Vec<String>,
    pub accept: String,
    pub then: String,
}

/// The tool a step of this kind runs on when the process file names none [choice: the usual
/// cleanroom tool for the kind]; the traveler marks it `(default)`.
fn default_equipment(params: &StepParams) -> &'static str {
    match params {
        StepParams::Clean(_) => "wet bench",
        StepParams::Oxidation(_) => "oxidation furnace",
        StepParams::SpinCoat(_) => "spinner",
        StepParams::Bake(_) => "hotplate",
        StepParams::Expose(_) => "mask aligner",
        StepParams::Develop(_) => "wet bench (developer)",
        StepParams::OxideEtch(_) => "wet bench (BOE)",
        StepParams::SiliconEtch(_) => "heated etch bath",
        StepParams::Strip(_) => "wet bench",
        StepParams::Mount(_) => "bench",
        StepParams::MetalEtch(_) => "wet bench",
        StepParams::Assemble(_) => "assembly bench",
    }
}

/// Labels `prefix 1` .. `prefix n`.
fn numbered(prefix: &str, n: usize) -> Vec<String> {
    (1..=n).map(|i| format!("{prefix}{i}")).collect()
}

/// A number of the source against what tactfab computes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Discrepancy {
    pub code: Code,
    pub quantity: String,
    pub source_says: String,
    pub computed: String,
}

/// The compensation design of a silicon etch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompensationRow {
    pub step: String,
    pub geometry: String,
    pub depth_um: f64,
    pub ratio: f64,
    pub side_um: f64,
    /// Width of a <110> bar; none for squares.
    pub bar_width_um: Option<f64>,
    pub reach: Reach,
    pub min_gap: Reach,
    /// Street between facing tooth corners the pitch leaves (x, y).
    pub street_um: (f64, f64),
    /// Side range for a TMAH test die when the ratio is the KOH rule.
    pub test_die_um: Option<(f64, f64)>,
}

impl CompensationRow {
    /// Column titles of the compensation table, shared by the Markdown and HTML writers.
    pub const HEADINGS: [&'static str; 8] = [
        "step",
        "geometry",
        "depth h (um)",
        "a = h / ratio (um)",
        "reach (um)",
        "needs between corners (um)",
        "street x / y (um)",
        "TMAH test die",
    ];

    /// The row's cells as plain text (each writer escapes for its own format).
    pub fn cells(&self) -> Vec<String> {
        vec![
            self.step.clone(),
            self.geometry.clone(),
            format!("{:.1}", self.depth_um),
            match self.bar_width_um {
                Some(b) => format!("{:.1} (h / {}) x {b:.1} wide", self.side_um, self.ratio),
                None => format!("{:.1} (h / {})", self.side_um, self.ratio),
            },
            xy(self.reach),
            xy(self.min_gap),
            format!("{:.0} / {:.0}", self.street_um.0, self.street_um.1),
            self.test_die_um
                .map(|(a, b)| format!("a from {a:.0} to {b:.0} um"))
                .unwrap_or_else(|| "-".into()),
        ]
    }
}

/// One number when x and y agree, else `x / y`.
fn xy(r: Reach) -> String {
    if r.x_um == r.y_um {
        format!("{:.1}", r.x_um)
    } else {
        format!("{:.1} / {:.1}", r.x_um, r.y_um)
    }
}

/// Violations the traveler lists per DRC code (the DRC report file lists them all).
pub const DRC_PER_CODE: usize = 10;

/// The whole traveler.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Traveler {
    pub device: String,
    pub revision: String,
    pub description: String,
    /// Tool, process file name and SHA-256, `--set` overrides.
    pub origin: super::Origin,
    /// How the FE checks were solved; None when skipped.
    pub fe_accuracy: Option<crate::sensor::Accuracy>,
    /// How the plate rungs hold the plate at the etched walls (`materials.base.support_model`).
    pub support_model: crate::process::SupportModel,
    /// Fields the fab fills in.
    pub header_fields: Vec<String>,
    /// Wafers on this traveler (`wafer.lot_wafers`): blanks per wafer at the hold points.
    pub lot_wafers: u32,
    pub material: Vec<(String, String)>,
    pub inventory: Inventory,
    pub steps: Vec<StepRow>,
    pub holds: Vec<HoldPoint>,
    pub cut: Cut,
    pub stacks: Vec<Stack>,
    /// Etch-plan checks, errors first, then by code (stable order).
    pub checks: Vec<Finding>,
    /// The design-rule check of the masks, as data.
    pub drc: DrcReport,
    /// What drawing the masks found.
    pub layout_warnings: Vec<Finding>,
    pub discrepancies: Vec<Discrepancy>,
    pub compensation: Vec<CompensationRow>,
    pub defaults_used: Vec<Provenance>,
    pub overrides: Vec<(String, String)>,
    pub fe: Option<FeSummary>,
    /// The etch simulation of one tooth on a coarse grid (`etch_sim::TRAVELER_GRID_UM`), or
    /// why it did not run; none when the traveler was made without it.
    pub etch_sim: Option<EtchSimRow>,
}

/// Grid of the traveler's etch simulation \[choice: 20 um and its double cost a fraction of a
/// second, where 5 um costs seconds; the corner's error estimate says what that grid misses\].
pub const ETCH_SIM_GRID_UM: f64 = 20.0;

/// The simulated tooth as the traveler prints it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EtchSimRow {
    /// Why it was not simulated (no teeth, no interior tooth, ...); the numbers are then absent.
    pub not_simulated: Option<String>,
    pub grid_um: f64,
    pub time_h: f64,
    pub corner_deviation_um: f64,
    pub corner_error: Option<crate::etch::sim::richardson::CornerError>,
    pub corner_shape: crate::etch::sim::CornerShape,
    pub tolerance_um: f64,
    pub edge_undercut_um: f64,
    pub compensator_consumed_h: Option<f64>,
    pub floor_residue_height_um: f64,
}

impl EtchSimRow {
    /// The row of a simulation.
    pub fn of(s: &crate::etch::sim::ToothSimulation) -> EtchSimRow {
        EtchSimRow {
            not_simulated: None,
            grid_um: s.grid_um,
            time_h: s.time_h,
            corner_deviation_um: s.corner_deviation_um,
            corner_error: s.corner_error,
            corner_shape: s.corner_shape,
            tolerance_um: s.tolerance_um,
            edge_undercut_um: s.edge_undercut_um,
            compensator_consumed_h: s.compensator_consumed_h,
            floor_residue_height_um: s.floor_residue_height_um,
        }
    }

    /// The row saying why there is no simulation.
    pub fn missing(why: String) -> EtchSimRow {
        EtchSimRow {
            not_simulated: Some(why),
            grid_um: 0.0,
            time_h: 0.0,
            corner_deviation_um: 0.0,
            corner_error: None,
            corner_shape: crate::etch::sim::CornerShape::Square,
            tolerance_um: 0.0,
            edge_undercut_um: 0.0,
            compensator_consumed_h: None,
            floor_residue_height_um: 0.0,
        }
    }
}

/// What the traveler is made from.
pub struct TravelerInput<'a> {
    pub process: &'a Process,
    /// The process file, its SHA-256 and the overrides.
    pub origin: &'a super::Origin,
    pub fe_accuracy: Option<crate::sensor::Accuracy>,
    pub defaults_used: &'a [Provenance],
    pub overrides: &'a [(String, String)],
    pub plan: &'a EtchPlan,
    pub set: &'a MaskSet,
    pub drc: &'a DrcReport,
    pub inventory: Inventory,
    pub fe: Option<FeSummary>,
}

use crate::spelling::yaml as label;

fn side(s: Side) -> &'static str {
    match s {
        Side::Front => "front",
        Side::Back => "back",
        Side::Both => "both sides",
    }
}

/// Assembles the traveler.
pub fn traveler(input: TravelerInput<'_>) -> Traveler {
    let p = input.process;
    let plan = input.plan;
    let mut holds = vec![start_hold(p, plan)];
    let mut steps = step_rows(&input, &mut holds);
    plate_hold(plan, &mut steps, &mut holds);
    Traveler {
        device: p.device.name.clone(),
        revision: p.device.revision.clone(),
        description: p.device.description.clone(),
        origin: input.origin.clone(),
        fe_accuracy: input.fe_accuracy,
        support_model: p.materials.base.support_model,
        header_fields: header_fields(),
        lot_wafers: p.wafer.lot_wafers,
        material: material(p, plan),
        inventory: input.inventory,
        steps,
        holds,
        cut: Cut::new(p, input.set),
        stacks: stacks(p, plan),
        checks: sorted_checks(plan),
        drc: input.drc.clone(),
        layout_warnings: input.set.warnings.clone(),
        discrepancies: discrepancies(p, plan),
        compensation: compensation(p, plan),
        defaults_used: input.defaults_used.to_vec(),
        overrides: input.overrides.to_vec(),
        fe: input.fe,
        etch_sim: None,
    }
}

/// The header fields the fab fills in by hand.
fn header_fields() -> Vec<String> {
    [
        "Lot ID",
        "Wafer ID(s)",
        "Start date",
        "End date",
        "Engineer",
        "Operator(s)",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// The starting material: wafer, die edges, die, PVDF film and plate.
fn material(p: &Process, plan: &EtchPlan) -> Vec<(String, String)> {
    let w = &p.wafer;
    vec![
        (
            "wafer".to_string(),
            format!(
                "({}) Si, {} +/- {} um, {} mm diameter",
                label(&w.orientation),
                w.thickness_um,
                w.thickness_tolerance_um,
                w.diameter_mm
            ),
        ),
        (
            "die edges".to_string(),
            format!("along <{}>", label(&w.die_edge)),
        ),
        (
            "die".to_string(),
            format!(
                "{} x {} mm",
                p.geometry.die_length_um / 1000.0,
                p.geometry.die_width_um / 1000.0
            ),
        ),
        (
            "PVDF film".to_string(),
            format!(
                "{} um, metallised both sides, drawn axis (d31) along {}",
                p.materials.pvdf.thickness_um,
                label(&p.geometry.electrodes.drawn_axis)
            ),
        ),
        (
            "plate".to_string(),
            format!(
                "target {} um; the recipe leaves {:.1} um ({:.0}-{:.0} um over the wafer \
                 tolerance)",
                plan.plate_target_um,
                plan.plate_thickness_um,
                plan.plate_range_um[0],
                plan.plate_range_um[1]
            ),
        ),
    ]
}

/// The etch-plan checks, errors first, then by code (a stable sort keeps the plan's order).
fn sorted_checks(plan: &EtchPlan) -> Vec<Finding> {
    let mut checks = plan.warnings.clone();
    checks.sort_by(|a, b| {
        b.severity
            .cmp(&a.severity)
            .then(a.code.as_str().cmp(b.code.as_str()))
    });
    checks
}

/// Hold point H1: measure the wafer thickness before the first step.
fn start_hold(p: &Process, plan: &EtchPlan) -> HoldPoint {
    let w = &p.wafer;
    HoldPoint {
        id: "H1".into(),
        step: "start".into(),
        when: "before the first step".into(),
        measure: "wafer thickness w at the centre and 4 points 10 mm from the edge (um)".into(),
        readings: ["centre", "N", "E", "S", "W"].map(String::from).to_vec(),
        accept: format!(
            "{} +/- {} um (supplier tolerance)",
            w.thickness_um, w.thickness_tolerance_um
        ),
        then: format!(
            "the tolerance goes straight into the plate ({:.0}-{:.0} um with the recipe as \
             written); record w: the etch hold points finish to the plate target",
            plan.plate_range_um[0], plan.plate_range_um[1]
        ),
    }
}

/// The last hold point of a two-sided etch: measure the plate after the last silicon etch.
fn plate_hold(plan: &EtchPlan, steps: &mut [StepRow], holds: &mut Vec<HoldPoint>) {
    if !(plan.front_depth_um > 0.0 && plan.back_depth_um > 0.0) {
        return;
    }
    let id = format!("H{}", holds.len() + 1);
    let last_si = plan
        .steps
        .last()
        .map(|s| s.name.clone())
        .unwrap_or_default();
    holds.push(HoldPoint {
        id: id.clone(),
        step: last_si.clone(),
        when: "after the last silicon etch, before stripping the oxide".into(),
        measure: "plate thickness = w - front depth - back depth (um)".into(),
        readings: vec!["plate".into()],
        accept: format!(
            "{} +/- {:.1} um (5 %, as the PLATE_TOLERANCE check)",
            plan.plate_target_um,
            PLATE_TOL_REL * plan.plate_target_um
        ),
        then: "thicker: etch on (both faces); thinner: record, the FE sensitivity scales with \
               the plate"
            .into(),
    });
    if let Some(row) = steps.iter_mut().rev().find(|r| r.name == last_si) {
        row.holds.push(id);
    }
}

/// Where a process-file value comes from: its default's source, else the process file.
fn provenance(defaults_used: &[Provenance], path: &str) -> String {
    defaults_used
        .iter()
        .find(|d| d.path == path)
        .map(|d| format!("default: {}", d.source))
        .unwrap_or_else(|| "process file".into())
}

/// The plan's results not yet matched to a step, one iterator per step kind that has them.
struct PlanRows<'a> {
    oxidations: std::slice::Iter<'a, OxidationResult>,
    resists: std::slice::Iter<'a, ResistResult>,
    oxide_etches: std::slice::Iter<'a, OxideEtchResult>,
    silicon_etches: std::slice::Iter<'a, EtchStep>,
}

/// What one step kind puts in its row, and the hold point it opens (its id is given by
/// [`step_rows`], in the order the holds are opened).
#[derive(Default)]
struct StepCells {
    process: String,
    parameters: String,
    computed: Vec<Computed>,
    target: Option<Target>,
    hold: Option<HoldPoint>,
}

impl StepCells {
    /// A row with only the process in words and its parameters.
    fn plain(process: impl Into<String>, parameters: String) -> Self {
        StepCells {
            process: process.into(),
            parameters,
            ..Default::default()
        }
    }
}

/// One row per process step, in order; the hold points the steps open are numbered onto `holds`.
fn step_rows(input: &TravelerInput<'_>, holds: &mut Vec<HoldPoint>) -> Vec<StepRow> {
    let plan = input.plan;
    let mut rows = PlanRows {
        oxidations: plan.oxidations.iter(),
        resists: plan.resists.iter(),
        oxide_etches: plan.oxide_etches.iter(),
        silicon_etches: plan.steps.iter(),
    };
    let mut steps = Vec::new();
    // The wafer is diced before the first assembly step: the file has no kind for it, so the
    // traveler says where it goes without renumbering the steps.
    let first_assembly = input
        .process
        .steps
        .iter()
        .position(|s| matches!(s.params, StepParams::Assemble(_)));
    for (i, s) in input.process.steps.iter().enumerate() {
        let cells = step_cells(input, i, s, &mut rows);
        let mut step_holds = Vec::new();
        if let Some(mut hold) = cells.hold {
            hold.id = format!("H{}", holds.len() + 1);
            step_holds.push(hold.id.clone());
            holds.push(hold);
        }
        steps.push(StepRow {
            number: i + 1,
            name: s.name.clone(),
            process: cells.process,
            equipment: if s.equipment.trim().is_empty() {
                format!("{} (default)", default_equipment(&s.params))
            } else {
                s.equipment.clone()
            },
            parameters: with_notes(cells.parameters, &s.notes),
            computed: cells.computed,
            target: cells.target,
            holds: step_holds,
            floor: {
                let mut floor = Vec::new();
                let dies = input.set.die_origins.len();
                if Some(i) == first_assembly && dies > 1 {
                    floor.push(format!(
                        "Before this step: dice the wafer into its {dies} dies along the dicing \
                         streets ({:.0} x {:.0} um pitch; saw with the plate side on tape), \
                         rinse, N2 dry, inspect each die for chipping at the plate.",
                        input.set.pitch_x_um, input.set.pitch_y_um
                    ));
                }
                floor.extend(floor_notes(&s.params));
                floor
            },
        });
    }
    steps
}

/// The parameters column: the step's parameters, then its notes after a `; `.
fn with_notes(parameters: String, notes: &str) -> String {
    match (parameters.is_empty(), notes.is_empty()) {
        (_, true) => parameters,
        (true, false) => notes.to_string(),
        (false, false) => format!("{parameters}; {notes}"),
    }
}

/// The cells of step `i` by its kind, taking the plan's next result for kinds that have one.
fn step_cells(input: &TravelerInput<'_>, i: usize, s: &Step, rows: &mut PlanRows) -> StepCells {
    match &s.params {
        StepParams::Clean(g) => generic_cells("clean", g),
        StepParams::Mount(g) => generic_cells("mount on carrier", g),
        StepParams::Oxidation(o) => oxidation_cells(input, s, o, rows.oxidations.next()),
        StepParams::SpinCoat(c) => spin_coat_cells(input, i, c, rows.resists.next()),
        StepParams::Bake(b) => {
            StepCells::plain("bake", format!("{} C, {} min", b.temp_c, b.time_min))
        }
        StepParams::Expose(e) => expose_cells(input, i, e),
        StepParams::Develop(d) => {
            StepCells::plain("develop", format!("{}, {} s", d.developer, d.time_s))
        }
        StepParams::OxideEtch(e) => oxide_etch_cells(input, e, rows.oxide_etches.next()),
        StepParams::SiliconEtch(e) => silicon_etch_cells(input.plan, e, rows.silicon_etches.next()),
        StepParams::Strip(st) => {
            StepCells::plain(format!("strip {}", label(&st.target)), st.chemistry.clone())
        }
        StepParams::MetalEtch(m) => metal_etch_cells(input.set, m),
        StepParams::Assemble(a) => assemble_cells(a),
    }
}

/// A clean or mount step: temperature and time when given.
fn generic_cells(kind: &str, g: &Generic) -> StepCells {
    let mut v = Vec::new();
    if let Some(t) = g.temp_c {
        v.push(format!("{t} C"));
    }
    if let Some(t) = g.time_min {
        v.push(format!("{t} min"));
    }
    StepCells::plain(kind, v.join(", "))
}

/// An oxidation: Deal-Grove thickness and Si consumed, the ellipsometer target, and the hold that
/// checks the oxide outlives the silicon etch it masks.
fn oxidation_cells(
    input: &TravelerInput<'_>,
    s: &Step,
    o: &Oxidation,
    r: Option<&OxidationResult>,
) -> StepCells {
    let params = format!(
        "{} ambient, {} C, {} h",
        label(&o.ambient),
        o.temp_c,
        o.time_h
    );
    let mut cells = StepCells::plain(format!("thermal oxidation ({})", label(&o.ambient)), params);
    let Some(r) = r else { return cells };
    cells.computed.push(Computed {
        what: "oxide per face".into(),
        value: format!("{:.3} um", r.thickness_um),
        provenance: format!(
            "Deal-Grove x^2 + A x = B (t + tau), B = {:.4} um2/h, B/A = {:.3} \
             um/h (Plummer, Deal & Griffin Table 6-2)",
            r.b_um2_per_h, r.b_over_a_um_per_h
        ),
    });
    cells.computed.push(Computed {
        what: "Si consumed".into(),
        value: format!("{:.3} um", r.silicon_consumed_um),
        provenance: "0.44-0.46 x oxide (process-physics.md)".into(),
    });
    cells.target = Some(Target {
        quantity: "oxide thickness (ellipsometer), each face".into(),
        value: format!(
            "{:.3} um +/- {:.3} um",
            r.thickness_um,
            OXIDE_TOL_REL * r.thickness_um
        ),
        basis: "Deal-Grove; 5 % as the OXIDE_CLAIM check".into(),
    });
    cells.hold = oxide_hold(input.process, input.plan, s);
    cells
}

/// The oxide must outlive the next silicon etch it masks: measure it before lithography.
fn oxide_hold(p: &Process, plan: &EtchPlan, s: &Step) -> Option<HoldPoint> {
    let e = plan
        .steps
        .iter()
        .find(|e| e.mask == crate::process::EtchMask::Oxide && e.mask_consumed_um > 0.0)?;
    let need = e.mask_consumed_um / (1.0 - MASK_MARGIN_REL);
    Some(HoldPoint {
        id: String::new(),
        step: s.name.clone(),
        when: "after oxidation, before lithography".into(),
        measure: "oxide thickness on both faces (ellipsometer, 5 points)".into(),
        readings: [numbered("front ", 5), numbered("back ", 5)].concat(),
        accept: format!(
            ">= {need:.3} um: `{}` erodes {:.3} um ({:.2} h at {} um/h), and \
             {:.0} % must be left",
            e.name,
            e.mask_consumed_um,
            e.time_h,
            if e.etchant == Etchant::Tmah {
                p.etchants.tmah_oxide_rate_um_per_h
            } else {
                p.etchants.koh_oxide_rate_um_per_h
            },
            MASK_MARGIN_REL * 100.0
        ),
        then: "below: oxidise longer (re-run the plan with the measured \
               thickness as initial_oxide_um)"
            .into(),
    })
}

/// A spin coat: resist thickness from the spin curve t = t_ref (rpm / rpm_ref)^-n and its target.
fn spin_coat_cells(
    input: &TravelerInput<'_>,
    i: usize,
    c: &SpinCoat,
    r: Option<&ResistResult>,
) -> StepCells {
    let params = format!(
        "{}, {} rpm, {} s, {}, on {}",
        c.resist,
        c.speed_rpm,
        c.time_s,
        side(c.side),
        label(&c.substrate)
    );
    let mut cells = StepCells::plain("spin coat", params);
    let Some(r) = r else { return cells };
    let prov = |path: &str| provenance(input.defaults_used, path);
    cells.computed.push(Computed {
        what: "resist".into(),
        value: format!("{:.2} um", r.thickness_um),
        provenance: format!(
            "spin curve t = t_ref (rpm / rpm_ref)^-n: {} um at {} rpm ({}), n = \
             {:.3} ({})",
            c.ref_thickness_um,
            c.ref_speed_rpm,
            prov(&format!("steps[{i}].ref_thickness_um")),
            c.spin_exponent,
            prov(&format!("steps[{i}].spin_exponent"))
        ),
    });
    cells.target = Some(Target {
        quantity: "resist thickness".into(),
        value: format!(
            "{:.2} um +/- {:.2} um",
            r.thickness_um,
            RESIST_TOL_REL * r.thickness_um
        ),
        basis: "[choice] 10 %: a larger error means a wrong speed or resist".into(),
    });
    cells
}

/// An exposure: each mask's file, tone, side and GDS layer from the inventory.
/// S1813's broadband exposure dose window, mJ/cm² (../shared/reference/process-physics.md,
/// lithography).
const S1813_DOSE_MJ_PER_CM2: (f64, f64) = (60.0, 150.0);

fn expose_cells(input: &TravelerInput<'_>, i: usize, e: &Expose) -> StepCells {
    let mut cells = StepCells::plain(
        "UV exposure",
        format!("masks {}; {} s", e.masks.join(", "), e.time_s),
    );
    // Dose = intensity x time: the resist's window fixes the lamp intensity this time assumes.
    let resist = input.process.steps[..i]
        .iter()
        .rev()
        .find_map(|s| match &s.params {
            StepParams::SpinCoat(c) => Some(c.resist.as_str()),
            _ => None,
        });
    let (lo, hi) = S1813_DOSE_MJ_PER_CM2;
    let s1813 = resist.is_some_and(|r| r.to_ascii_uppercase().contains("1813"));
    cells.computed.push(if !s1813 {
        Computed {
            what: "dose".into(),
            value: format!(
                "intensity x {} s: the resist's datasheet dose over the measured lamp intensity \
                 sets the time",
                e.time_s
            ),
            provenance: format!("no dose window known for {}", resist.unwrap_or("no resist")),
        }
    } else {
        Computed {
            what: "dose".into(),
            value: format!(
            "{lo}-{hi} mJ/cm² needs {:.1}-{:.1} mW/cm² at {} s: measure the lamp, set the time to \
             dose / intensity",
            lo / e.time_s,
            hi / e.time_s,
            e.time_s
        ),
            provenance: "S1813 broadband dose window, reference/process-physics.md".into(),
        }
    });
    for name in &e.masks {
        if let Some(m) = input.inventory.masks.iter().find(|m| &m.name == name) {
            cells.computed.push(Computed {
                what: format!("mask {name}"),
                value: format!(
                    "{}, {}, {} side{}",
                    m.svg_file,
                    m.tone,
                    side(m.side),
                    if m.mirrored { ", MIRRORED" } else { "" }
                ),
                provenance: format!("GDS layer {} of {}", m.gds_layer, input.inventory.gds_file),
            });
        }
    }
    cells
}

/// An oxide etch: time = oxide / BOE rate plus the over-etch, and clear openings as the target.
fn oxide_etch_cells(
    input: &TravelerInput<'_>,
    e: &OxideEtch,
    r: Option<&OxideEtchResult>,
) -> StepCells {
    let mut cells = StepCells::plain(
        "oxide etch",
        format!(
            "{}, {}, over-etch {} %",
            e.etchant,
            side(e.side),
            e.overetch_pct
        ),
    );
    let Some(r) = r else { return cells };
    cells.computed.push(Computed {
        what: "etch time".into(),
        value: format!("{:.1} min", r.time_min),
        provenance: format!(
            "{:.3} um oxide at {} um/min ({}) + {} % over-etch",
            r.oxide_um,
            r.rate_um_per_min,
            provenance(input.defaults_used, "etchants.boe_rate_um_per_min"),
            e.overetch_pct
        ),
    });
    cells.target = Some(Target {
        quantity: "openings clear".into(),
        value: "0 um oxide in the openings (the surface dewets)".into(),
        basis: "a hard mask needs bare Si in every opening".into(),
    });
    cells
}

/// A silicon etch: the computed column, the depth target (1 %) and the 90 % depth hold.
fn silicon_etch_cells(plan: &EtchPlan, e: &SiliconEtch, r: Option<&EtchStep>) -> StepCells {
    let params = format!(
        "{} {} wt %, {} C, {}, {} mask{}",
        e.etchant.label(),
        e.concentration_wt_pct,
        e.temp_c,
        side(e.side),
        label(&e.mask),
        e.time_h
            .map(|t| format!(", recipe time {t} h"))
            .unwrap_or_default()
    );
    let mut cells = StepCells::plain("anisotropic Si etch", params);
    let Some(r) = r else { return cells };
    silicon_rows(r, &mut cells.computed);
    let tol = DEPTH_TOL_REL * r.depth_um;
    cells.target = Some(Target {
        quantity: format!("etch depth per face ({})", side(r.side)),
        value: format!("{:.1} um +/- {:.1} um", r.depth_um, tol),
        basis: "1 %, as the ETCH_TIME_DEPTH_MISMATCH check".into(),
    });
    cells.hold = Some(depth_hold(plan, r, tol));
    cells
}

/// Stop at HOLD_FRACTION of the computed time, measure the depth d, and finish from the measured
/// rate: remaining time = t_hold (D / d - 1).
fn depth_hold(plan: &EtchPlan, r: &EtchStep, tol: f64) -> HoldPoint {
    let two_sided = plan.steps.iter().any(|s| s.side == Side::Both)
        || (plan.front_depth_um > 0.0 && plan.back_depth_um > 0.0);
    let t_hold = HOLD_FRACTION * r.time_for_depth_h;
    let finish = if two_sided && plan.steps.len() == 1 {
        format!(
            "for the {} um plate finish to depth D = (w - {})/2 per face (w from \
             H1), remaining time = {:.3} h x (D / d - 1)",
            plan.plate_target_um, plan.plate_target_um, t_hold
        )
    } else {
        format!(
            "remaining time = {t_hold:.3} h x ({} um / d - 1)",
            r.depth_um
        )
    };
    HoldPoint {
        id: String::new(),
        step: r.name.clone(),
        when: format!(
            "at {:.0} % of the computed time: {:.3} h = {:.0} min (not the \
             recipe's {} h)",
            HOLD_FRACTION * 100.0,
            t_hold,
            t_hold * 60.0,
            r.time_h
        ),
        measure: format!(
            "etch depth d on each etched face (microscope focus or profilometer), \
             expected {:.1} um",
            HOLD_FRACTION * r.depth_um
        ),
        readings: match r.side {
            Side::Front => vec!["front d".into()],
            Side::Back => vec!["back d".into()],
            Side::Both => vec!["front d".into(), "back d".into()],
        },
        accept: format!(
            "d within {:.1} +/- {:.1} um; measured rate d / {t_hold:.3} h",
            HOLD_FRACTION * r.depth_um,
            HOLD_FRACTION * tol
        ),
        then: finish,
    }
}

/// A metal etch: the electrode islands it must leave isolated.
fn metal_etch_cells(set: &MaskSet, m: &MetalEtch) -> StepCells {
    let n = set.electrodes.len();
    let mut cells = StepCells::plain(
        "metal etch",
        format!("{}, {} C, {} min", m.etchant, m.temp_c, m.time_min),
    );
    cells.target = Some(Target {
        quantity: "electrode islands".into(),
        value: format!(
            "{n} isolated islands ({})",
            set.electrodes
                .iter()
                .map(|e| e.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        basis: "PVDF mask; check no continuity between neighbours".into(),
    });
    cells
}

/// An assembly step: temperature, time and wire count when given.
fn assemble_cells(a: &Assemble) -> StepCells {
    let mut v = Vec::new();
    if let Some(t) = a.temp_c {
        v.push(format!("{t} C"));
    }
    if let Some(t) = a.time_min {
        v.push(format!("{t} min"));
    }
    if a.wires > 0 {
        v.push(format!("{} wires", a.wires));
    }
    StepCells::plain("assemble", v.join(", "))
}

/// The computed column of a silicon etch.
fn silicon_rows(r: &EtchStep, c: &mut Vec<Computed>) {
    let mut push = |what: &str, value: String, provenance: String| {
        c.push(Computed {
            what: what.into(),
            value,
            provenance,
        })
    };
    push(
        "(100) rate",
        format!("{:.2} um/h", r.rate_um_per_h),
        format!("{}; model {:.2} um/h", r.rate_source, r.model_rate_um_per_h),
    );
    push(
        "time for target",
        format!("{:.3} h", r.time_for_depth_h),
        format!("{} um / {:.2} um/h", r.depth_um, r.rate_um_per_h),
    );
    push(
        "depth at run time",
        format!("{:.1} um", r.achieved_depth_um),
        format!("{:.3} h x {:.2} um/h", r.time_h, r.rate_um_per_h),
    );
    push(
        "sidewall run-out",
        format!("{:.1} um", r.sidewall_run_out_um),
        "h / tan 54.74 deg ({111} sidewalls)".into(),
    );
    push(
        "undercut",
        format!("{:.1} um", r.undercut_um),
        format!(
            "R111 t / sin 54.74 deg, R111 = {:.3} um/h",
            r.rate_111_um_per_h
        ),
    );
    if let Some(b) = r.mesa_base_um {
        push(
            "tooth base",
            format!("{b:.1} um"),
            "top + 2 h / tan 54.74 deg".into(),
        );
    }
    let erosion = if r.time_h > 0.0 {
        r.mask_consumed_um / r.time_h
    } else {
        0.0
    };
    push(
        "mask erosion",
        format!(
            "{:.3} um consumed, {:.3} um left",
            r.mask_consumed_um, r.mask_remaining_um
        ),
        format!(
            "{} mask at {erosion:.3} um/h for {:.3} h",
            label(&r.mask),
            r.time_h
        ),
    );
    if let Some(k) = &r.compensation {
        match k.bar_width_um {
            Some(b) => push(
                "compensation bar",
                format!("{:.1} x {b:.1} um", k.side_um),
                format!("L = h / {} ({})", k.ratio, label(&k.kind)),
            ),
            None => push(
                "compensation square",
                format!("{:.1} um", k.side_um),
                format!("a = h / {} ({})", k.ratio, label(&k.kind)),
            ),
        }
    }
}

/// Numbers the process file takes from its source that the computation contradicts.
pub fn discrepancies(p: &Process, plan: &EtchPlan) -> Vec<Discrepancy> {
    let mut v = Vec::new();
    for o in &plan.oxidations {
        if let (Some(e), Some(t)) = (o.expected_thickness_um, o.time_for_expected_h) {
            if (o.thickness_um - e).abs() / e > OXIDE_TOL_REL {
                v.push(Discrepancy {
                    code: EtchCode::OxideClaim.into(),
                    quantity: format!("oxide of `{}`", o.name),
                    source_says: format!("{e} um in {} h at {} C", o.time_h, o.temp_c),
                    computed: format!(
                        "{:.3} um (Deal-Grove); {e} um needs {t:.2} h",
                        o.thickness_um
                    ),
                });
            }
        }
    }
    for (s, e) in plan
        .steps
        .iter()
        .zip(p.steps.iter().filter_map(|s| match &s.params {
            StepParams::SiliconEtch(e) => Some(e),
            _ => None,
        }))
    {
        if let Some(t) = e.time_h {
            if (s.achieved_depth_um - s.depth_um).abs() / s.depth_um > DEPTH_TOL_REL {
                v.push(Discrepancy {
                    code: EtchCode::EtchTimeDepthMismatch.into(),
                    quantity: format!("etch time of `{}`", s.name),
                    source_says: format!(
                        "{t} h for {} um per face at {} um/h",
                        s.depth_um, s.rate_um_per_h
                    ),
                    computed: format!(
                        "{:.3} h for {} um; {t} h etches {:.1} um",
                        s.time_for_depth_h, s.depth_um, s.achieved_depth_um
                    ),
                });
            }
        }
    }
    if !plan.steps.is_empty()
        && (plan.plate_thickness_um - plan.plate_target_um).abs() / plan.plate_target_um
            > DEPTH_TOL_REL
    {
        v.push(Discrepancy {
            code: EtchCode::PlateThicknessMismatch.into(),
            quantity: "plate thickness".into(),
            source_says: format!("{} um", plan.plate_target_um),
            computed: format!(
                "{:.1} um = {} - {:.1} - {:.1} um with the recipe's times",
                plan.plate_thickness_um,
                plan.wafer_thickness_um,
                plan.front_depth_um,
                plan.back_depth_um
            ),
        });
    }
    for c in &plan.warnings {
        let (quantity, source_says) = match c.code {
            Code::Etch(EtchCode::CompRatioFromKoh) => (
                "corner compensation ratio",
                "a = h / 0.544 (a KOH rule) for TMAH",
            ),
            Code::Etch(EtchCode::PiezoConstantsInconsistent) => {
                ("PVDF g and d constants", "d, g and eps_r as given")
            }
            Code::Etch(EtchCode::RateModelDisagrees) => ("(100) etch rate", "the measured rate"),
            _ => continue,
        };
        v.push(Discrepancy {
            code: c.code,
            quantity: quantity.into(),
            source_says: source_says.into(),
            computed: c.message.clone(),
        });
    }
    v
}

/// Compensation designs of the etches that carry one.
fn compensation(p: &Process, plan: &EtchPlan) -> Vec<CompensationRow> {
    let t = &p.geometry.teeth;
    plan.steps
        .iter()
        .filter_map(|s| {
            let c = s.compensation?;
            let street = (t.pitch_x_um - t.top_um, t.pitch_y_um - t.top_um);
            let koh_rule = s.etchant == Etchant::Tmah && limits::KOH_RULE_RATIO.contains(&c.ratio);
            Some(CompensationRow {
                step: s.name.clone(),
                geometry: label(&c.kind),
                depth_um: s.depth_um,
                ratio: c.ratio,
                side_um: c.side_um,
                bar_width_um: c.bar_width_um,
                reach: c.reach,
                min_gap: c.min_gap,
                street_um: street,
                test_die_um: koh_rule
                    .then(|| (0.8 * s.depth_um / c.ratio, 1.5 * s.depth_um / c.ratio)),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::inventory::inventory;

    /// The bundled process without FE.
    pub(crate) fn bundled(sets: &[&str]) -> Traveler {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let loaded = crate::process::load_str(&text, "process/mis-grasper.yaml", &sets).unwrap();
        let p = &loaded.process;
        let plan = crate::etch::plan(p);
        let set = crate::layout::build(p, &plan).unwrap();
        let drc = crate::drc::check(&set, p, &plan);
        let svgs: Vec<String> = set.masks.iter().map(|m| set.to_svg(m).unwrap()).collect();
        let inv = inventory(&set, b"gds bytes", &svgs);
        traveler(TravelerInput {
            process: p,
            origin: &crate::report::Origin::new("mis-grasper.yaml", "0000", &loaded.overrides),
            fe_accuracy: None,
            defaults_used: &loaded.defaults_used,
            overrides: &loaded.overrides,
            plan: &plan,
            set: &set,
            drc: &drc,
            inventory: inv,
            fe: None,
        })
    }

    fn computed<'a>(r: &'a StepRow, what: &str) -> &'a str {
        &r.computed
            .iter()
            .find(|c| c.what == what)
            .unwrap_or_else(|| panic!("no `{what}` in {r:?}"))
            .value
    }

    #[test]
    fn etch_row_hold_and_paper_discrepancies() {
        let t = bundled(&[]);
        assert_eq!(t.steps.len(), 24);
        assert!(t.steps.iter().enumerate().all(|(i, r)| r.number == i + 1));
        let etch = t.steps.iter().find(|r| r.name == "tmah-etch").unwrap();
        // 200 um at the measured 24 um/h: 8.333 h; the paper's 8.5 h gives 204 um.
        assert_eq!(computed(etch, "time for target"), "8.333 h");
        assert_eq!(computed(etch, "depth at run time"), "204.0 um");
        assert_eq!(computed(etch, "compensation square"), "367.6 um");
        assert_eq!(etch.target.as_ref().unwrap().value, "200.0 um +/- 2.0 um");
        // Hold at 90 % of the computed time (7.5 h = 450 min), not of the recipe's 8.5 h.
        let hold = t.holds.iter().find(|h| h.step == "tmah-etch").unwrap();
        assert!(etch.holds.contains(&hold.id));
        assert!(hold.when.contains("7.500 h = 450 min"), "{}", hold.when);
        assert!(hold.then.contains("D = (w - 100)/2"), "{}", hold.then);
        // The oxide hold asks for the TMAH erosion with a 25 % margin.
        let ox = t.holds.iter().find(|h| h.step == "wet-oxidation").unwrap();
        assert!(ox.accept.starts_with(">= "), "{}", ox.accept);
        let codes: Vec<&str> = t.discrepancies.iter().map(|d| d.code.as_str()).collect();
        for c in [
            "OXIDE_CLAIM",
            "ETCH_TIME_DEPTH_MISMATCH",
            "PLATE_THICKNESS_MISMATCH",
            "COMP_RATIO_FROM_KOH",
            "PIEZO_CONSTANTS_INCONSISTENT",
        ] {
            assert!(codes.contains(&c), "{c} missing from {codes:?}");
        }
        let oxide = t
            .discrepancies
            .iter()
            .find(|d| d.code == EtchCode::OxideClaim.into())
            .unwrap();
        assert!(oxide.computed.starts_with("0.942 um"), "{}", oxide.computed);
        let comp = &t.compensation[0];
        assert_eq!(
            comp.test_die_um.map(|(a, b)| (a.round(), b.round())),
            Some((294.0, 551.0))
        );
    }

    #[test]
    fn computed_time_leaves_no_etch_discrepancy() {
        let t = bundled(&["steps.tmah-etch.time_h=null"]);
        let codes: Vec<&str> = t.discrepancies.iter().map(|d| d.code.as_str()).collect();
        assert!(
            !codes.contains(&"ETCH_TIME_DEPTH_MISMATCH")
                && !codes.contains(&"PLATE_THICKNESS_MISMATCH"),
            "{codes:?}"
        );
        assert!(codes.contains(&"OXIDE_CLAIM"));
    }

    #[test]
    fn stacks_follow_the_plan() {
        let t = bundled(&[]);
        let by = |name: &str| t.stacks[t.steps.iter().position(|r| r.name == name).unwrap()];
        let etched = by("tmah-etch");
        assert!(
            (etched.front_etch_um - 204.0).abs() < 1e-9
                && (etched.back_etch_um - 204.0).abs() < 1e-9
        );
        // The section's plate under the street between two teeth is the plan's plate.
        let y = 0.5 * (t.cut.teeth[0].1 + t.cut.teeth[1].0);
        let plate = t.cut.front_z(y, etched.front_etch_um) - t.cut.back_z(y, etched.back_etch_um);
        assert!((plate - 92.0).abs() < 1e-9, "{plate}");
        assert!(
            etched.oxide_front.patterned
                && etched.oxide_front.thickness_um > 0.0
                && etched.oxide_front.thickness_um < 0.942
        );
        assert_eq!(by("strip-oxide").oxide_front.thickness_um, 0.0);
        let film = by("al-etch").pvdf.unwrap();
        assert!(film.on_carrier && film.electrodes_patterned && !film.attached);
        let last = t.stacks.last().unwrap().pvdf.unwrap();
        assert!(last.attached && !last.on_carrier);
        // The cut crosses teeth and three electrodes (one per support, one middle).
        assert!(!t.cut.teeth.is_empty());
        assert_eq!(t.cut.electrodes.len(), 3, "{:?}", t.cut.electrodes);
    }

    #[test]
    fn writers_are_deterministic_and_self_contained() {
        let t = bundled(&[]);
        let md = crate::report::markdown::markdown(&t);
        assert_eq!(md, crate::report::markdown::markdown(&bundled(&[])));
        for h in [
            "## Header",
            "## Starting material",
            "## Masks",
            "## Steps",
            "## Hold points",
            "## Cross-sections",
            "## Checks and warnings",
            "## FE sensitivity",
            "## Corner compensation",
        ] {
            assert!(md.contains(h), "missing {h}");
        }
        let html = crate::report::html::html(&t, &Default::default());
        let changes = 1 + t.stacks.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(
            html.matches("<figure>").count(),
            changes,
            "one cross-section per step that changes the stack"
        );
        assert!(
            !html.contains("<script") && !html.contains(" src=") && !html.contains("href="),
            "self-contained"
        );
        assert!(
            !html.contains("http://")
                || html.matches("http://").count()
                    == html.matches("xmlns=\"http://www.w3.org/2000/svg\"").count()
        );
    }
}
