//! Default constants, each from `../shared/reference` with its provenance tag.
//!
//! The serde defaults call these functions; [`DEFAULTS`] names the same values with their source
//! so the loader can report every default a file relied on.

use super::schema::{FrontEnd, GdsLayer, SiliconModel, Substrate, TmahRate};

/// A default value the process file may override, and where it comes from.
#[derive(Debug, Clone, Copy)]
pub struct DefaultSource {
    /// Field path relative to its parent, e.g. `materials.silicon.c11_gpa`; `steps[].x` applies to
    /// every step that has the field.
    pub path: &'static str,
    /// `[paper]`, `[lit]`, `[derived]` or `[est]` with the citation.
    pub source: &'static str,
}

pub fn wafer_thickness_tolerance_um() -> f64 {
    20.0
}
pub fn wafer_diameter_mm() -> f64 {
    100.0
}
pub fn lot_wafers() -> u32 {
    1
}
pub fn dicing_street_um() -> f64 {
    200.0
}
pub fn silicon_model() -> SiliconModel {
    SiliconModel::Anisotropic
}
pub fn c11_gpa() -> f64 {
    165.7
}
pub fn c12_gpa() -> f64 {
    63.9
}
pub fn c44_gpa() -> f64 {
    79.6
}
pub fn si_e_gpa() -> f64 {
    169.1
}
pub fn si_nu() -> f64 {
    0.064
}
pub fn fracture_strength_mpa() -> f64 {
    4000.0
}
/// The lowest measured: {111} cleavage, the plane a crack from a {111} sidewall runs on.
pub fn fracture_toughness_mpa_sqrt_m() -> f64 {
    0.72
}
pub fn safety_factor() -> f64 {
    3.0
}
pub fn si_density_g_per_cm3() -> f64 {
    2.329
}
pub fn front_end() -> FrontEnd {
    FrontEnd::ChargeAmplifier
}
pub fn feedback_capacitance_pf() -> f64 {
    1000.0
}
pub fn feedback_resistance_gohm() -> f64 {
    10.0
}
pub fn input_resistance_mohm() -> f64 {
    1.0
}
pub fn cable_capacitance_pf() -> f64 {
    100.0
}
pub fn pvdf_thickness_um() -> f64 {
    25.0
}
pub fn pvdf_e_gpa() -> f64 {
    3.0
}
pub fn pvdf_nu() -> f64 {
    0.35
}
pub fn pvdf_density_g_per_cm3() -> f64 {
    1.76
}
pub fn base_kind() -> super::schema::BaseKind {
    super::schema::BaseKind::Plexiglas
}
pub fn support_model() -> super::schema::SupportModel {
    super::schema::SupportModel::Clamped
}
pub fn base_thickness_um() -> f64 {
    2000.0
}
pub fn base_e_gpa() -> f64 {
    3.0
}
pub fn base_nu() -> f64 {
    0.37
}
pub fn d31_pc_per_n() -> f64 {
    20.0
}
pub fn d32_pc_per_n() -> f64 {
    2.0
}
pub fn d33_pc_per_n() -> f64 {
    -18.0
}
pub fn eps_r() -> f64 {
    12.0
}
pub fn tmah_table() -> Vec<TmahRate> {
    vec![TmahRate {
        concentration_wt_pct: 25.0,
        rate_100_um_per_h: 24.0,
        temp_c: 80.0,
        source: "[paper] 002 sec. VI.A, measured".into(),
    }]
}
pub fn tmah_ea_ev() -> f64 {
    0.55
}
pub fn tmah_r110_over_r100() -> f64 {
    1.75
}
pub fn tmah_r100_over_r111() -> f64 {
    30.0
}
/// \[est\] no TMAH {311} rate in ../shared; 1.3 (band 0.9-1.75, the top at R110 so that the
/// convex-corner planes stay near {110} as reference/process-physics.md says for TMAH).
pub fn tmah_r311_over_r100() -> f64 {
    1.3
}
/// \[lit\] Sato et al. 1998, 30 % KOH 70 C: 1.436 / 0.797 um/min.
pub fn koh_r311_over_r100() -> f64 {
    1.436 / 0.797
}
/// \[choice\] 25 um along the diagonal: about the corner rounding an optical inspection of a
/// 2 mm tooth top tells apart.
pub fn etched_corner_tolerance_um() -> f64 {
    25.0
}
pub fn koh_r100_over_r111() -> f64 {
    // Sato 1998: 0.797 / 0.005 um/min.
    159.4
}
pub fn tmah_oxide_rate_um_per_h() -> f64 {
    0.06
}
pub fn koh_oxide_rate_um_per_h() -> f64 {
    0.43
}
pub fn boe_rate_um_per_min() -> f64 {
    0.075
}
pub fn substrate_wafer() -> Substrate {
    Substrate::Wafer
}
pub fn s1813_ref_thickness_um() -> f64 {
    1.4
}
pub fn s1813_ref_speed_rpm() -> f64 {
    3915.0
}
pub fn s1813_spin_exponent() -> f64 {
    // ln(2.0/1.4) / ln(3915/1950): the two McGill MicroFab points.
    (2.0f64 / 1.4).ln() / (3915.0f64 / 1950.0).ln()
}
pub fn overetch_pct() -> f64 {
    20.0
}
pub fn compensation_ratio() -> f64 {
    0.544
}

pub fn layer_front_si() -> GdsLayer {
    GdsLayer {
        layer: 1,
        datatype: 0,
    }
}
pub fn layer_back_si() -> GdsLayer {
    GdsLayer {
        layer: 2,
        datatype: 0,
    }
}
pub fn layer_pvdf() -> GdsLayer {
    GdsLayer {
        layer: 3,
        datatype: 0,
    }
}
pub fn layer_marks() -> GdsLayer {
    GdsLayer {
        layer: 10,
        datatype: 0,
    }
}
pub fn layer_annotation() -> GdsLayer {
    GdsLayer {
        layer: 63,
        datatype: 0,
    }
}
pub fn layer_outline() -> GdsLayer {
    GdsLayer {
        layer: 64,
        datatype: 0,
    }
}
pub fn layer_wafer_outline() -> GdsLayer {
    GdsLayer {
        layer: 65,
        datatype: 0,
    }
}
pub fn edge_exclusion_mm() -> f64 {
    3.0
}
pub fn label_pixel_um() -> f64 {
    25.0
}
pub fn compensation_overlap_um() -> f64 {
    10.0
}
pub fn test_die_span_um() -> f64 {
    150.0
}
pub fn test_die_step_um() -> f64 {
    50.0
}
pub fn drc_min_width_um() -> f64 {
    10.0
}
pub fn drc_min_space_um() -> f64 {
    10.0
}
pub fn drc_max_vertices() -> usize {
    4000
}
pub fn drc_min_electrode_gap_um() -> f64 {
    200.0
}

pub fn drc_min_wall_margin_um() -> f64 {
    100.0
}

/// Every default with its provenance (reference/README.md tags).
pub const DEFAULTS: &[DefaultSource] = &[
    DefaultSource {
        path: "wafer.thickness_tolerance_um",
        source: "[est] typical supplier tolerance, reference/process-physics.md",
    },
    DefaultSource {
        path: "wafer.diameter_mm",
        source: "[est] 100 mm wafer",
    },
    DefaultSource {
        path: "wafer.lot_wafers",
        source: "[choice] one wafer per traveler",
    },
    DefaultSource {
        path: "geometry.dicing_street_um",
        source: "[est] saw kerf plus margin",
    },
    DefaultSource {
        path: "materials.silicon.model",
        source: "anisotropic cubic silicon (reference/fe-validation.md)",
    },
    DefaultSource {
        path: "materials.silicon.c11_gpa",
        source: "[lit] Hopcroft, Nix, Kenny, JMEMS 19(2) 2010",
    },
    DefaultSource {
        path: "materials.silicon.c12_gpa",
        source: "[lit] Hopcroft, Nix, Kenny, JMEMS 19(2) 2010",
    },
    DefaultSource {
        path: "materials.silicon.c44_gpa",
        source: "[lit] Hopcroft, Nix, Kenny, JMEMS 19(2) 2010",
    },
    DefaultSource {
        path: "materials.silicon.e_gpa",
        source: "[derived] E<110> from Hopcroft 2010",
    },
    DefaultSource {
        path: "materials.silicon.nu",
        source: "[derived] nu<110> from Hopcroft 2010",
    },
    DefaultSource {
        path: "materials.silicon.fracture_strength_mpa",
        source: "[paper] 001, fracture 4 GPa",
    },
    DefaultSource {
        path: "materials.silicon.fracture_toughness_mpa_sqrt_m",
        source: "[lit] DelRio et al., Mater. Res. Lett. 10 (2022) 728, {111}: 0.72 +/- 0.07 \
                 (NIST SRD 138: 0.79-0.95)",
    },
    DefaultSource {
        path: "materials.silicon.safety_factor",
        source: "[paper] 001, safety factor 3",
    },
    DefaultSource {
        path: "materials.silicon.density_g_per_cm3",
        source: "[lit] 2.329 g/cm3 at room temperature, CRC Handbook of Chemistry and Physics \
                 (not in ../shared/reference)",
    },
    DefaultSource {
        path: "materials.pvdf.thickness_um",
        source: "[paper] 002 sec. III",
    },
    DefaultSource {
        path: "materials.pvdf.e_gpa",
        source: "[paper] 002 sec. VI.B",
    },
    DefaultSource {
        path: "materials.pvdf.nu",
        source: "[paper] 002 sec. VI.B",
    },
    DefaultSource {
        path: "materials.base.kind",
        source: "reference/fe-validation.md: Plexiglas base 30 x 15 x 2 mm [paper 001]",
    },
    DefaultSource {
        path: "materials.base.support_model",
        source: "[choice] clamped (paper 001); solid_section is within 1 % of the graded solid on the plain plate and, with the teeth, at 1 N (README)",
    },
    DefaultSource {
        path: "materials.base.thickness_um",
        source: "reference/fe-validation.md: Plexiglas base 30 x 15 x 2 mm [paper 001]",
    },
    DefaultSource {
        path: "materials.base.e_gpa",
        source: "[lit] PMMA (Plexiglas) datasheets, 2.4-3.3 GPa; not in reference/",
    },
    DefaultSource {
        path: "materials.base.nu",
        source: "[lit] PMMA (Plexiglas) datasheets, 0.35-0.40; not in reference/",
    },
    DefaultSource {
        path: "materials.pvdf.density_g_per_cm3",
        source: "[paper] 002 sec. VI.B",
    },
    DefaultSource {
        path: "materials.pvdf.d31_pc_per_n",
        source: "[paper] 002 sec. VI.B",
    },
    DefaultSource {
        path: "materials.pvdf.d32_pc_per_n",
        source: "[paper] 002 sec. VI.B",
    },
    DefaultSource {
        path: "materials.pvdf.d33_pc_per_n",
        source: "[paper] 002 sec. VI.B",
    },
    DefaultSource {
        path: "materials.pvdf.eps_r",
        source: "[lit] PVDF datasheets ~12 (reference/fe-validation.md)",
    },
    DefaultSource {
        path: "etchants.tmah",
        source: "[paper] 002: 25 wt %, 24 um/h at 80 C, measured",
    },
    DefaultSource {
        path: "etchants.tmah_ea_ev",
        source: "[lit] Tabata 1992, Merlos 1993, Thong 1997 (band 0.5-0.65)",
    },
    DefaultSource {
        path: "etchants.tmah_r110_over_r100",
        source: "[lit] Shikida 2000 (1.5-2)",
    },
    DefaultSource {
        path: "etchants.tmah_r100_over_r111",
        source: "[lit] Tabata 1992 (12.5-50)",
    },
    DefaultSource {
        path: "etchants.koh_r100_over_r111",
        source: "[lit] Sato 1998, 30 % KOH 70 C",
    },
    DefaultSource {
        path: "etchants.tmah_r311_over_r100",
        source: "[est] no source in ../shared; band 0.9-1.75 (below R110: TMAH's corner planes are near {110}, Shikida 2000)",
    },
    DefaultSource {
        path: "etchants.koh_r311_over_r100",
        source: "[lit] Sato 1998, 30 % KOH 70 C: 1.436 / 0.797",
    },
    DefaultSource {
        path: "etchants.etched_corner_tolerance_um",
        source: "[choice] 25 um along the diagonal of a 2 mm tooth top",
    },
    DefaultSource {
        path: "etchants.tmah_oxide_rate_um_per_h",
        source: "[lit] 0.01-0.3 nm/min; planned at 1 nm/min worst case",
    },
    DefaultSource {
        path: "etchants.koh_oxide_rate_um_per_h",
        source: "[lit] ~0.43 um/h at 30 %, 80 C",
    },
    DefaultSource {
        path: "etchants.boe_rate_um_per_min",
        source: "[lit] 75-100 nm/min at room temperature (slow end)",
    },
    DefaultSource {
        path: "steps[].ref_thickness_um",
        source: "[lit] S1813 1.4 um at 3915 rpm, McGill MicroFab",
    },
    DefaultSource {
        path: "steps[].ref_speed_rpm",
        source: "[lit] S1813 1.4 um at 3915 rpm, McGill MicroFab",
    },
    DefaultSource {
        path: "steps[].spin_exponent",
        source: "[derived] from S1813 1.4 um @ 3915 rpm and 2.0 um @ 1950 rpm",
    },
    DefaultSource {
        path: "steps[].overetch_pct",
        source: "[est] 20 % over-etch",
    },
    DefaultSource {
        path: "steps[].compensation.ratio",
        source: "[paper] 002 a = h/0.544 (a KOH rule, Sato 1998)",
    },
    DefaultSource {
        path: "layout.layers",
        source: "[est] tactfab layer map: 1/0 front Si, 2/0 back Si, 3/0 PVDF, 10/0 marks, 63/0 \
                 annotations, 64/0 die outline, 65/0 wafer outline",
    },
    DefaultSource {
        path: "layout.edge_exclusion_mm",
        source: "[est] 3 mm wafer edge exclusion (edge bead, clamp ring)",
    },
    DefaultSource {
        path: "layout.label_pixel_um",
        source: "[est] 25 um pixel: 175 um capitals, above contact-litho resolution",
    },
    DefaultSource {
        path: "layout.compensation_overlap_um",
        source: "[est] 10 um overlap: one simple polygon per tooth (a vertex-only contact is \
                 invalid, reference/layout-conventions.md)",
    },
    DefaultSource {
        path: "layout.test_die.enabled",
        source: "[choice] no test die unless the file asks for one",
    },
    DefaultSource {
        path: "layout.test_die.span_um",
        source: "[choice] +/- 150 um: 0.6-1.4 a around the rule's 368 um, the 0.8-1.5 a of \
                 process-physics.md and beyond the simulated optimum",
    },
    DefaultSource {
        path: "layout.test_die.step_um",
        source: "[choice] 50 um steps: 7 teeth over the default span",
    },
    DefaultSource {
        path: "drc.min_width_um",
        source: "[est] contact/proximity lithography on S1813, ~5 um resolution with 2x margin",
    },
    DefaultSource {
        path: "drc.min_space_um",
        source: "[est] contact/proximity lithography on S1813, ~5 um resolution with 2x margin",
    },
    DefaultSource {
        path: "drc.min_electrode_gap_um",
        source: "[est] 200 um: Al wet-etch undercut and conductive-epoxy spread between islands",
    },
    DefaultSource {
        path: "drc.min_wall_margin_um",
        source:
            "[est] 100 um: aligning the film to the die by hand under a microscope, and the epoxy \
                 fillet where the etched wall meets the plate",
    },
    DefaultSource {
        path: "readout.front_end",
        source: "[paper] 001 sec. 5 and 002 sec. VII: charge amplifiers (Kistler Type 5010)",
    },
    DefaultSource {
        path: "readout.feedback_capacitance_pf",
        source: "[choice] 1 nF: about 0.2 V/N from the ~200 pC/N middle electrodes; no amplifier \
                 datasheet in ../shared",
    },
    DefaultSource {
        path: "readout.feedback_resistance_gohm",
        source: "[choice] 10 GΩ: tau = 10 s, corner 16 mHz, far below the 1 Hz pulse and the \
                 5 Hz test; no amplifier datasheet in ../shared",
    },
    DefaultSource {
        path: "readout.input_resistance_mohm",
        source: "[choice] 1 MΩ, a common oscilloscope input; no DAQ datasheet in ../shared \
                 (set the real input's)",
    },
    DefaultSource {
        path: "readout.cable_capacitance_pf",
        source: "[choice] 100 pF, about a metre of coaxial cable; no cable datasheet in ../shared",
    },
    DefaultSource {
        path: "drc.max_vertices",
        source: "reference/layout-conventions.md: <= 4000 vertices per polygon",
    },
];
