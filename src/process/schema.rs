//! The process file's shape: serde types, `deny_unknown_fields`, units in every numeric name.
//!
//! These are the validated model once [`crate::process::load`] has checked ranges and cross-field
//! rules. Defaultable constants carry serde defaults from [`super::defaults`]; the loader records
//! which defaults were used so the output can state their provenance.

use serde::{Deserialize, Serialize};

use super::defaults as d;

/// A whole process file: device, wafer, geometry, materials, masks and the ordered steps.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Process {
    pub device: Device,
    pub wafer: Wafer,
    pub geometry: Geometry,
    pub materials: Materials,
    pub masks: Vec<Mask>,
    /// Etchant tables and mask-erosion rates; every entry defaults to `../shared/reference`.
    #[serde(default)]
    pub etchants: Etchants,
    /// Sensitivity checks: FE scenes with pass/fail limits.
    #[serde(default)]
    pub checks: Checks,
    /// Mask-layout choices (layer map, wafer edge exclusion, label size).
    #[serde(default)]
    pub layout: Layout,
    /// Design-rule limits and waivers for `tactfab masks`.
    #[serde(default)]
    pub drc: Drc,
    /// The read-out electronics behind the electrodes (`tactfab readout`); every value defaults
    /// to a stated \[choice\].
    #[serde(default)]
    pub readout: ReadoutElectronics,
    /// Steps in the order the cleanroom runs them. Deserialised per step by the loader
    /// (the `kind` field selects the parameter set), so errors point into the right step.
    #[serde(skip)]
    pub steps: Vec<Step>,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Device {
    /// File-name-safe device name; output files are `<name>.gds` etc.
    pub name: String,
    pub revision: String,
    #[serde(default)]
    pub description: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum CrystalPlane {
    #[serde(rename = "100")]
    P100,
    #[serde(rename = "110")]
    P110,
    #[serde(rename = "111")]
    P111,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Direction {
    #[serde(rename = "110")]
    D110,
    #[serde(rename = "100")]
    D100,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Wafer {
    /// Surface orientation; anisotropic etch geometry here assumes (100).
    pub orientation: CrystalPlane,
    pub thickness_um: f64,
    /// Supplier tolerance; it goes straight into the plate thickness.
    #[serde(default = "d::wafer_thickness_tolerance_um")]
    pub thickness_tolerance_um: f64,
    #[serde(default = "d::wafer_diameter_mm")]
    pub diameter_mm: f64,
    /// Wafers run together on one traveler (1-25): each hold-point reading gets a blank per
    /// wafer.
    #[serde(default = "d::lot_wafers")]
    pub lot_wafers: u32,
    /// Crystal direction of the die edges.
    pub die_edge: Direction,
}

/// Device geometry in die coordinates: origin at the lower-left corner, x along the length,
/// y across the width (the supports run along x at both y edges).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    pub die_length_um: f64,
    pub die_width_um: f64,
    /// Target plate thickness under the U-channel.
    pub plate_thickness_um: f64,
    /// Width of each support strip along the two long (y) edges.
    pub support_width_um: f64,
    /// Back-side etch depth of the U-channel between the supports.
    pub channel_depth_um: f64,
    /// Dicing street between dies on the wafer.
    #[serde(default = "d::dicing_street_um")]
    pub dicing_street_um: f64,
    pub teeth: Teeth,
    pub electrodes: Electrodes,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TeethPattern {
    /// Teeth on the cells with even i + j.
    Checkered,
    /// A tooth on every cell.
    Matrix,
    /// Plain plate.
    None,
}

/// Square-topped frustum teeth on a regular grid of cells.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Teeth {
    pub pattern: TeethPattern,
    /// Front-side etch depth around the teeth.
    pub height_um: f64,
    /// Side of the square tooth top (the mask's drawn square).
    pub top_um: f64,
    pub pitch_x_um: f64,
    pub pitch_y_um: f64,
    pub count_x: u32,
    pub count_y: u32,
    /// Lower-left corner of cell (0, 0) in die coordinates.
    pub origin_x_um: f64,
    pub origin_y_um: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Axis {
    #[serde(rename = "x")]
    X,
    #[serde(rename = "y")]
    Y,
}

/// Which islands the PVDF mask carries.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ElectrodePattern {
    /// `units` sensing units along x, each S1k over support 1, Mk over the channel, S2k over
    /// support 2 (paper 002).
    #[default]
    Nine,
    /// Four islands over the plate in a cross about the die centre: A (+x), B (+y), C (-x), D (-y)
    /// (paper 000's four-element sensor; dimensions are a design choice, see
    /// process/four-element.yaml).
    FourCross,
}

impl ElectrodePattern {
    pub fn is_nine(&self) -> bool {
        *self == ElectrodePattern::Nine
    }
}

/// The PVDF electrode pattern: by default nine islands, three sensing units along x, each with one
/// island under support 1, one under the middle (U-channel) and one under support 2.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Electrodes {
    /// `nine` (default) or `four_cross`; left out of serialised output when it is the default.
    #[serde(default, skip_serializing_if = "ElectrodePattern::is_nine")]
    pub pattern: ElectrodePattern,
    pub units: u32,
    /// Gap between neighbouring islands (in x between units, in y between support and middle).
    pub gap_um: f64,
    /// Unmetallised margin along the film's outer edges.
    pub edge_margin_um: f64,
    /// Square pad at each island where its wire is attached with conductive epoxy.
    pub wire_pad_um: f64,
    /// Film drawn direction (the d31 axis) in die axes.
    pub drawn_axis: Axis,
}

impl Electrodes {
    /// Islands the PVDF mask carries: three per unit (S1k, Mk, S2k) or the four of the cross.
    pub fn island_count(&self) -> usize {
        match self.pattern {
            ElectrodePattern::Nine => 3 * self.units as usize,
            ElectrodePattern::FourCross => 4,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Materials {
    pub silicon: Silicon,
    pub pvdf: Pvdf,
    /// What the sensor stands on (the solid rung models it).
    #[serde(default)]
    pub base: BaseMaterial,
}

/// The base under the PVDF film: paper 002's Plexiglas plate, or rigid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BaseKind {
    Plexiglas,
    Rigid,
}

/// How the plate rungs hold the plate where the etched walls meet it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SupportModel {
    /// An ideal clamp (w and the normal slope held).
    Clamped,
    /// Each support is a beam on the film (and the base) as a Winkler foundation: edge springs
    /// from Hetenyi's end stiffness, and the support electrodes read the foundation pressure.
    ElasticFooting,
    /// Each support's cross-section solved as a plane-strain solid (support, {111} wall, film,
    /// base, the plate over it): edge springs from its stiffness at the clamp line.
    SolidSection,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BaseMaterial {
    #[serde(default = "d::base_kind")]
    pub kind: BaseKind,
    /// How the plate rungs hold the plate at the supports (the solid rung models them).
    #[serde(default = "d::support_model")]
    pub support_model: SupportModel,
    #[serde(default = "d::base_thickness_um")]
    pub thickness_um: f64,
    #[serde(default = "d::base_e_gpa")]
    pub e_gpa: f64,
    #[serde(default = "d::base_nu")]
    pub nu: f64,
}

impl Default for BaseMaterial {
    fn default() -> Self {
        BaseMaterial {
            kind: d::base_kind(),
            support_model: d::support_model(),
            thickness_um: d::base_thickness_um(),
            e_gpa: d::base_e_gpa(),
            nu: d::base_nu(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SiliconModel {
    /// Cubic stiffness C11, C12, C44 rotated into die axes.
    Anisotropic,
    /// The (E, nu) override.
    Isotropic,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Silicon {
    #[serde(default = "d::silicon_model")]
    pub model: SiliconModel,
    #[serde(default = "d::c11_gpa")]
    pub c11_gpa: f64,
    #[serde(default = "d::c12_gpa")]
    pub c12_gpa: f64,
    #[serde(default = "d::c44_gpa")]
    pub c44_gpa: f64,
    /// Used only with `model: isotropic`.
    #[serde(default = "d::si_e_gpa")]
    pub e_gpa: f64,
    #[serde(default = "d::si_nu")]
    pub nu: f64,
    #[serde(default = "d::fracture_strength_mpa")]
    pub fracture_strength_mpa: f64,
    /// K_Ic: with the strength, the critical distance at which the solid rung reads the stress
    /// of the sharp re-entrant edges (theory of critical distances).
    #[serde(default = "d::fracture_toughness_mpa_sqrt_m")]
    pub fracture_toughness_mpa_sqrt_m: f64,
    #[serde(default = "d::safety_factor")]
    pub safety_factor: f64,
    /// Mass density of the plate and teeth (the natural frequencies).
    #[serde(default = "d::si_density_g_per_cm3")]
    pub density_g_per_cm3: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Pvdf {
    #[serde(default = "d::pvdf_thickness_um")]
    pub thickness_um: f64,
    #[serde(default = "d::pvdf_e_gpa")]
    pub e_gpa: f64,
    #[serde(default = "d::pvdf_nu")]
    pub nu: f64,
    #[serde(default = "d::pvdf_density_g_per_cm3")]
    pub density_g_per_cm3: f64,
    #[serde(default = "d::d31_pc_per_n")]
    pub d31_pc_per_n: f64,
    #[serde(default = "d::d32_pc_per_n")]
    pub d32_pc_per_n: f64,
    #[serde(default = "d::d33_pc_per_n")]
    pub d33_pc_per_n: f64,
    #[serde(default = "d::eps_r")]
    pub eps_r: f64,
    /// Optional datasheet voltage constants; when given they are checked against d / (eps0 eps_r).
    #[serde(default)]
    pub g31_vm_per_n: Option<f64>,
    #[serde(default)]
    pub g32_vm_per_n: Option<f64>,
    #[serde(default)]
    pub g33_vm_per_n: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Front,
    Back,
    Both,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Tone {
    /// Chrome where the drawn shape is (clear field elsewhere).
    LightField,
    /// Clear where the drawn shape is.
    DarkField,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Mask {
    pub name: String,
    pub side: Side,
    pub tone: Tone,
    /// Whether the mask shop receives the drawn layer mirrored (back-side exposure).
    pub mirrored: bool,
    /// What the mask defines: `front_si`, `back_si` or `pvdf`.
    pub purpose: MaskPurpose,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MaskPurpose {
    FrontSi,
    BackSi,
    Pvdf,
}

/// Etch-rate tables and mask-erosion rates.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Etchants {
    /// TMAH (100) rates keyed by concentration; interpolated linearly in wt %.
    #[serde(default = "d::tmah_table")]
    pub tmah: Vec<TmahRate>,
    #[serde(default = "d::tmah_ea_ev")]
    pub tmah_ea_ev: f64,
    /// R(110)/R(100) for TMAH.
    #[serde(default = "d::tmah_r110_over_r100")]
    pub tmah_r110_over_r100: f64,
    /// R(100)/R(111) for TMAH.
    #[serde(default = "d::tmah_r100_over_r111")]
    pub tmah_r100_over_r111: f64,
    /// R(100)/R(111) for KOH (Sato 1998).
    #[serde(default = "d::koh_r100_over_r111")]
    pub koh_r100_over_r111: f64,
    /// R(311)/R(100) for TMAH, the etch simulation's orientation table.
    #[serde(default = "d::tmah_r311_over_r100")]
    pub tmah_r311_over_r100: f64,
    /// R(411)/R(100) for TMAH; none: interpolated between {100} and {311}.
    #[serde(default)]
    pub tmah_r411_over_r100: Option<f64>,
    /// R(311)/R(100) for KOH (Sato 1998).
    #[serde(default = "d::koh_r311_over_r100")]
    pub koh_r311_over_r100: f64,
    /// R(411)/R(100) for KOH; none: interpolated between {100} and {311}.
    #[serde(default)]
    pub koh_r411_over_r100: Option<f64>,
    /// How far the simulated etched tooth-top corner may lie from the drawn corner, along the
    /// diagonal, before `tactfab etch --simulate` reports ETCHED_CORNER_DEVIATION.
    #[serde(default = "d::etched_corner_tolerance_um")]
    pub etched_corner_tolerance_um: f64,
    /// Thermal SiO2 loss in TMAH (worst case).
    #[serde(default = "d::tmah_oxide_rate_um_per_h")]
    pub tmah_oxide_rate_um_per_h: f64,
    /// Thermal SiO2 loss in KOH.
    #[serde(default = "d::koh_oxide_rate_um_per_h")]
    pub koh_oxide_rate_um_per_h: f64,
    /// BOE etch rate of thermal oxide at room temperature.
    #[serde(default = "d::boe_rate_um_per_min")]
    pub boe_rate_um_per_min: f64,
}

impl Default for Etchants {
    fn default() -> Self {
        Etchants {
            tmah: d::tmah_table(),
            tmah_ea_ev: d::tmah_ea_ev(),
            tmah_r110_over_r100: d::tmah_r110_over_r100(),
            tmah_r100_over_r111: d::tmah_r100_over_r111(),
            koh_r100_over_r111: d::koh_r100_over_r111(),
            tmah_r311_over_r100: d::tmah_r311_over_r100(),
            tmah_r411_over_r100: None,
            koh_r311_over_r100: d::koh_r311_over_r100(),
            koh_r411_over_r100: None,
            etched_corner_tolerance_um: d::etched_corner_tolerance_um(),
            tmah_oxide_rate_um_per_h: d::tmah_oxide_rate_um_per_h(),
            koh_oxide_rate_um_per_h: d::koh_oxide_rate_um_per_h(),
            boe_rate_um_per_min: d::boe_rate_um_per_min(),
        }
    }
}

/// One measured TMAH (100) rate at a reference temperature.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TmahRate {
    pub concentration_wt_pct: f64,
    pub rate_100_um_per_h: f64,
    pub temp_c: f64,
    pub source: String,
}

/// One process step: common fields plus the parameters of its kind.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Step {
    pub name: String,
    pub equipment: String,
    pub notes: String,
    #[serde(flatten)]
    pub params: StepParams,
}

/// Fields every step has; `kind` selects the [`StepParams`] variant.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepCommon {
    pub name: String,
    pub kind: String,
    #[serde(default)]
    pub equipment: String,
    #[serde(default)]
    pub notes: String,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StepParams {
    Clean(Generic),
    Oxidation(Oxidation),
    SpinCoat(SpinCoat),
    Bake(Bake),
    Expose(Expose),
    Develop(Develop),
    OxideEtch(OxideEtch),
    SiliconEtch(SiliconEtch),
    Strip(Strip),
    Mount(Generic),
    MetalEtch(MetalEtch),
    Assemble(Assemble),
}

/// Every step kind and what it is, for error messages.
pub const STEP_KINDS: &[(&str, &str)] = &[
    ("clean", "wafer or film cleaning"),
    ("oxidation", "thermal oxidation (Deal-Grove)"),
    ("spin_coat", "resist spin coating"),
    ("bake", "soft/hard/cure bake"),
    ("expose", "UV exposure through masks"),
    ("develop", "resist development"),
    ("oxide_etch", "SiO2 wet etch (BOE)"),
    ("silicon_etch", "anisotropic TMAH/KOH etch"),
    ("strip", "resist or oxide removal"),
    ("mount", "mounting on a carrier"),
    ("metal_etch", "metal electrode wet etch"),
    ("assemble", "gluing and wiring"),
];

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Generic {
    #[serde(default)]
    pub time_min: Option<f64>,
    #[serde(default)]
    pub temp_c: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ambient {
    Wet,
    Dry,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Oxidation {
    pub ambient: Ambient,
    pub temp_c: f64,
    pub time_h: f64,
    /// Oxide present before this step (Deal-Grove's x_i).
    #[serde(default)]
    pub initial_oxide_um: f64,
    /// What the source claims this step grows; checked against the model.
    #[serde(default)]
    pub expected_thickness_um: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Substrate {
    Wafer,
    Pvdf,
    Carrier,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SpinCoat {
    pub resist: String,
    pub speed_rpm: f64,
    pub time_s: f64,
    pub side: Side,
    #[serde(default = "d::substrate_wafer")]
    pub substrate: Substrate,
    /// Spin curve: thickness at a reference speed and the exponent of t ~ rpm^-n.
    #[serde(default = "d::s1813_ref_thickness_um")]
    pub ref_thickness_um: f64,
    #[serde(default = "d::s1813_ref_speed_rpm")]
    pub ref_speed_rpm: f64,
    #[serde(default = "d::s1813_spin_exponent")]
    pub spin_exponent: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Bake {
    pub temp_c: f64,
    pub time_min: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Expose {
    /// Mask names from `masks`.
    pub masks: Vec<String>,
    pub time_s: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Develop {
    pub developer: String,
    pub time_s: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OxideEtch {
    pub etchant: String,
    pub side: Side,
    /// Over-etch beyond the computed clearing time, in percent.
    #[serde(default = "d::overetch_pct")]
    pub overetch_pct: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Etchant {
    Tmah,
    Koh,
}

impl Etchant {
    pub fn label(self) -> &'static str {
        match self {
            Etchant::Tmah => "TMAH",
            Etchant::Koh => "KOH",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EtchMask {
    Oxide,
    Nitride,
    Resist,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CompensationGeometry {
    /// Square sharing its corner with the convex corner, extending diagonally outwards.
    CornerAttached,
    /// Square centred on the convex corner.
    Centred,
    /// A <110> beam (Bao 1993, named in process-physics.md) at each convex corner, continuing
    /// the tooth's top edge along die x out into the street: for the corner (+s/2, +s/2) from
    /// the tooth centre the rectangle x in [s/2, s/2 + L], y in [s/2 - b, s/2], mirrored about
    /// the tooth's centre lines; L = h / ratio, b = `bar_width_um`.
    #[serde(rename = "bar_110")]
    Bar110,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Compensation {
    /// a = h / ratio. Defaults to the paper's 0.544 (a KOH-derived rule).
    #[serde(default = "d::compensation_ratio")]
    pub ratio: f64,
    pub geometry: CompensationGeometry,
    /// Width b of a `bar_110` beam (um; only for that geometry). None: b = 6 R111 t / sin 54.74
    /// deg, three times the width the two sides' {111} undercut cuts through during the etch
    /// (R100/R111 spans 12.5-50 about the tables' 30 in process-physics.md, so R111 may be 2.4
    /// times the table's), at least `drc.min_width_um` and at most the tooth top \[choice\].
    #[serde(default)]
    pub bar_width_um: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SiliconEtch {
    pub etchant: Etchant,
    pub concentration_wt_pct: f64,
    pub temp_c: f64,
    pub side: Side,
    /// Target depth per etched face.
    pub depth_um: f64,
    /// The time the recipe actually runs; when absent the time is computed from the depth.
    #[serde(default)]
    pub time_h: Option<f64>,
    /// Measured (100) rate for this bath; always wins over the models.
    #[serde(default)]
    pub measured_rate_um_per_h: Option<f64>,
    pub mask: EtchMask,
    /// Convex-corner compensation on the front (teeth) mask.
    #[serde(default)]
    pub compensation: Option<Compensation>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StripTarget {
    Resist,
    Oxide,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Strip {
    pub target: StripTarget,
    pub chemistry: String,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MetalEtch {
    pub etchant: String,
    pub temp_c: f64,
    pub time_min: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Assemble {
    #[serde(default)]
    pub temp_c: Option<f64>,
    #[serde(default)]
    pub time_min: Option<f64>,
    /// Wires attached in this step (nine electrodes plus the common).
    #[serde(default)]
    pub wires: u32,
}

/// Declared sensitivity checks.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Checks {
    #[serde(default)]
    pub scenes: Vec<Scene>,
}

/// A named load case on the die (die coordinates, um) with optional pass/fail limits.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    /// `{point: {...}}` and so on: one key naming the kind (serde_yaml's singleton-map form).
    #[serde(with = "serde_yaml::with::singleton_map")]
    pub load: SceneLoad,
    #[serde(default)]
    pub limits: Limits,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SceneLoad {
    /// A point force with a contact radius (the stress is reported for that patch).
    Point {
        x_um: f64,
        y_um: f64,
        force_n: f64,
        radius_um: f64,
    },
    /// Uniform pressure over the plate, or over a region, by total force.
    Pressure {
        force_n: f64,
        #[serde(default)]
        region: Option<RegionUm>,
    },
    /// A rectangular probe of the given size, centre and angle (deg, counter-clockwise from x).
    Probe {
        x_um: f64,
        y_um: f64,
        width_um: f64,
        height_um: f64,
        angle_deg: f64,
        force_n: f64,
    },
    /// A line force across the full plate length at `y_um` (the fixed-fixed beam case of paper
    /// 001).
    Line { y_um: f64, force_n: f64 },
    /// A piecewise-uniform pressure: rectangles, each with its own total force (a contact
    /// pressure sampled on cells, e.g. the grasped tissue of `tactfab tissue`). Read at the
    /// bounding box's centre.
    Patches { patches: Vec<PressurePatch> },
}

/// One rectangle of a [`SceneLoad::Patches`] load, uniformly pressed by `force_n`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PressurePatch {
    pub region: RegionUm,
    pub force_n: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RegionUm {
    pub x0_um: f64,
    pub y0_um: f64,
    pub x1_um: f64,
    pub y1_um: f64,
}

/// Pass/fail limits of a scene; absent limits are not checked.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Smallest acceptable |V|/F of the most sensitive middle electrode.
    #[serde(default)]
    pub min_sensitivity_mv_per_n: Option<f64>,
    #[serde(default)]
    pub max_stress_mpa: Option<f64>,
    #[serde(default)]
    pub min_safety_factor: Option<f64>,
    #[serde(default)]
    pub max_deflection_um: Option<f64>,
}

impl Limits {
    /// Every limit with its declared bound (None where absent), in the order checks list them.
    pub fn entries(&self) -> [(LimitKind, Option<f64>); 4] {
        [
            (LimitKind::MinSensitivity, self.min_sensitivity_mv_per_n),
            (LimitKind::MaxStress, self.max_stress_mpa),
            (LimitKind::MinSafetyFactor, self.min_safety_factor),
            (LimitKind::MaxDeflection, self.max_deflection_um),
        ]
    }
}

/// Which of a scene's [`Limits`] is meant; serialised as its field's name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitKind {
    /// `min_sensitivity_mv_per_n`: the most sensitive electrode's |V| / F.
    MinSensitivity,
    /// `max_stress_mpa`: the stress the safety factor is judged on.
    MaxStress,
    /// `min_safety_factor`: fracture strength over that stress.
    MinSafetyFactor,
    /// `max_deflection_um`: |the largest deflection|.
    MaxDeflection,
}

impl LimitKind {
    /// The field's name in the process file.
    pub fn yaml_name(self) -> &'static str {
        match self {
            LimitKind::MinSensitivity => "min_sensitivity_mv_per_n",
            LimitKind::MaxStress => "max_stress_mpa",
            LimitKind::MinSafetyFactor => "min_safety_factor",
            LimitKind::MaxDeflection => "max_deflection_um",
        }
    }

    /// A lower bound (the value must reach it) rather than an upper one.
    pub fn is_minimum(self) -> bool {
        matches!(self, LimitKind::MinSensitivity | LimitKind::MinSafetyFactor)
    }
}

impl Serialize for LimitKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.yaml_name())
    }
}

/// One GDS layer/datatype pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GdsLayer {
    pub layer: i16,
    pub datatype: i16,
}

/// GDS layer numbers of the mask set (layout-conventions.md defaults).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LayerMap {
    #[serde(default = "d::layer_front_si")]
    pub front_si: GdsLayer,
    #[serde(default = "d::layer_back_si")]
    pub back_si: GdsLayer,
    #[serde(default = "d::layer_pvdf")]
    pub pvdf: GdsLayer,
    #[serde(default = "d::layer_marks")]
    pub marks: GdsLayer,
    #[serde(default = "d::layer_annotation")]
    pub annotation: GdsLayer,
    #[serde(default = "d::layer_outline")]
    pub outline: GdsLayer,
    #[serde(default = "d::layer_wafer_outline")]
    pub wafer_outline: GdsLayer,
}

impl Default for LayerMap {
    fn default() -> Self {
        LayerMap {
            front_si: d::layer_front_si(),
            back_si: d::layer_back_si(),
            pvdf: d::layer_pvdf(),
            marks: d::layer_marks(),
            annotation: d::layer_annotation(),
            outline: d::layer_outline(),
            wafer_outline: d::layer_wafer_outline(),
        }
    }
}

/// Mask-layout choices that are not device geometry: layers, wafer edge, label size.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Layout {
    #[serde(default)]
    pub layers: LayerMap,
    /// Ring at the wafer edge where no die is placed.
    #[serde(default = "d::edge_exclusion_mm")]
    pub edge_exclusion_mm: f64,
    /// Pixel of the 5x7 label font; a capital is 7 pixels high.
    #[serde(default = "d::label_pixel_um")]
    pub label_pixel_um: f64,
    /// How far a corner-attached compensator reaches into its tooth, so that tooth and square
    /// form one simple polygon instead of touching at a single vertex.
    #[serde(default = "d::compensation_overlap_um")]
    pub compensation_overlap_um: f64,
    /// A test die on the wafer with a ladder of compensated teeth (issue 19, item 4).
    #[serde(default)]
    pub test_die: TestDie,
}

/// The compensation test die: one row of teeth like the device's, on the front mask, whose
/// compensators step through a = centre - span .. centre + span, each labelled with its a, so
/// the fab can measure the etched corners and feed the rates back (`etchants`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TestDie {
    #[serde(default)]
    pub enabled: bool,
    /// The ladder's middle a (um); none: the front etch's a = h / ratio (the rule, or a ratio
    /// sized by `tactfab etch --simulate --size-compensation`), or the rule a = h / 0.544 when
    /// the front etch draws no compensation.
    #[serde(default)]
    pub centre_a_um: Option<f64>,
    /// The ladder reaches this far below and above the centre.
    #[serde(default = "d::test_die_span_um")]
    pub span_um: f64,
    /// Step of a between neighbouring teeth.
    #[serde(default = "d::test_die_step_um")]
    pub step_um: f64,
}

impl Default for TestDie {
    fn default() -> Self {
        TestDie {
            enabled: false,
            centre_a_um: None,
            span_um: d::test_die_span_um(),
            step_um: d::test_die_step_um(),
        }
    }
}

impl Default for Layout {
    fn default() -> Self {
        Layout {
            layers: LayerMap::default(),
            edge_exclusion_mm: d::edge_exclusion_mm(),
            label_pixel_um: d::label_pixel_um(),
            compensation_overlap_um: d::compensation_overlap_um(),
            test_die: TestDie::default(),
        }
    }
}

/// Design-rule limits of the mask set and the rules the designer waives on purpose.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Drc {
    /// Rule codes to report but not fail on, e.g. `[STREET_TOO_NARROW]`.
    #[serde(default)]
    pub waive: Vec<String>,
    #[serde(default = "d::drc_min_width_um")]
    pub min_width_um: f64,
    #[serde(default = "d::drc_min_space_um")]
    pub min_space_um: f64,
    #[serde(default = "d::drc_max_vertices")]
    pub max_vertices: usize,
    /// Smallest gap between two electrode islands (isolation, Al wet-etch undercut, epoxy spread).
    #[serde(default = "d::drc_min_electrode_gap_um")]
    pub min_electrode_gap_um: f64,
    /// Smallest distance from a middle island to the U-channel's etched {111} wall (it must lie on
    /// the flat channel floor, bonded under the plate) and from a support island to its support's
    /// etched footprint edge.
    #[serde(default = "d::drc_min_wall_margin_um")]
    pub min_wall_margin_um: f64,
}

impl Default for Drc {
    fn default() -> Self {
        Drc {
            waive: Vec::new(),
            min_width_um: d::drc_min_width_um(),
            min_space_um: d::drc_min_space_um(),
            max_vertices: d::drc_max_vertices(),
            min_electrode_gap_um: d::drc_min_electrode_gap_um(),
            min_wall_margin_um: d::drc_min_wall_margin_um(),
        }
    }
}

/// What turns an electrode's charge into the voltage that is recorded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrontEnd {
    /// A charge amplifier per channel: feedback capacitor C_f in parallel with R_f (the papers'
    /// Kistler Type 5010).
    ChargeAmplifier,
    /// The electrode wired straight to a voltage input: the electrode and cable capacitance
    /// discharge through the input resistance.
    VoltageReadout,
}

/// The read-out electronics of every channel; units in the names. Only the fields of the chosen
/// front end are used, all are validated.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ReadoutElectronics {
    #[serde(default = "d::front_end")]
    pub front_end: FrontEnd,
    /// Charge amplifier: the feedback capacitor C_f (gain -1 / C_f).
    #[serde(default = "d::feedback_capacitance_pf")]
    pub feedback_capacitance_pf: f64,
    /// Charge amplifier: the feedback resistor R_f (tau = R_f C_f).
    #[serde(default = "d::feedback_resistance_gohm")]
    pub feedback_resistance_gohm: f64,
    /// Voltage read-out: the input resistance of the amplifier or DAQ.
    #[serde(default = "d::input_resistance_mohm")]
    pub input_resistance_mohm: f64,
    /// Voltage read-out: the cable's capacitance, in parallel with the electrode's.
    #[serde(default = "d::cable_capacitance_pf")]
    pub cable_capacitance_pf: f64,
}

impl Default for ReadoutElectronics {
    fn default() -> Self {
        ReadoutElectronics {
            front_end: d::front_end(),
            feedback_capacitance_pf: d::feedback_capacitance_pf(),
            feedback_resistance_gohm: d::feedback_resistance_gohm(),
            input_resistance_mohm: d::input_resistance_mohm(),
            cable_capacitance_pf: d::cable_capacitance_pf(),
        }
    }
}
