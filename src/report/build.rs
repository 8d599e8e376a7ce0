//! Everything for one process file, in memory: etch plan, masks (GDS, .lyp, SVG), DRC, the FE
//! checks the file declares, the traveler (Markdown and HTML). Nothing is written here: the
//! caller writes [`Built::files`] atomically, so a failure leaves no partial output.

use geo::BoundingRect;

use crate::design::Design;
use crate::drc::DrcReport;
use crate::etch::EtchPlan;
use crate::export::gds::GdsOptions;
use crate::export::svg::path_data;
use crate::export::{nm, um_text, ExportError};
use crate::layout::{LayerKind, LayoutError, MaskSet};
use crate::process::Loaded;
use crate::sensor::support_stiffness::SupportStiffness;
use crate::sensor::{
    evaluate_many, plate_modes, Accuracy, SceneReport, SensorGeometry, MODAL_LEVELS, MODES_REPORTED,
};

use super::fe::{summarise, FeSummary};
use super::html::{html, Figures};
use super::inventory::{inventory, Inventory};
use super::markdown::markdown;
use super::traveler::{traveler, Traveler, TravelerInput};

/// Why nothing could be built.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("layout: {0}")]
    Layout(#[from] LayoutError),
    #[error(
        "export: {0}\n  hint: a coordinate or file could not be written; check the geometry and \
         the output path"
    )]
    Export(#[from] ExportError),
    #[error("finite-element solve failed: {0}")]
    Fe(#[from] crate::fe::FeError),
    #[error("{0}")]
    Sensor(#[from] crate::sensor::SensorError),
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
    #[error("the traveler's tissue section: {0}")]
    Tissue(#[from] crate::hidden::HiddenError),
}

/// What to build.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// The process file, its SHA-256 and the overrides (printed in the traveler and build.json).
    pub origin: super::Origin,
    /// How accurately the declared scenes are solved; None: skip FE (the traveler says so).
    pub fe: Option<Accuracy>,
    /// GDS modification/access dates; None writes zeros (reproducible).
    pub gds_epoch_s: Option<i64>,
    /// Report scenes that did not reach the tolerance without failing the build.
    pub allow_unconverged: bool,
    /// Solve each declared scene on the solid rung too and fail where the plate rung the ladder
    /// picks differs from it by more than the tolerance.
    pub verify_solid: Option<SolidCheck>,
}

/// How `build --verify-solid` runs the solid rung.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolidCheck {
    /// Mesh levels (in plane, each sqrt 2 finer).
    pub levels: usize,
    /// Every level graded at the tooth base edges (`--graded`: about 4x the dofs; the uniform
    /// levels can leave the edges' stresses and the deflection low).
    pub graded: bool,
    /// The bricks' transverse shears tied (the default; `--plain-shear` unties them).
    pub tied_shear: bool,
    /// How the solid's levels are graded at the hot teeth (`--solid-grading`).
    pub grading: crate::sensor::solid::SolidGrading,
}

/// Stages, for progress reporting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    Masks,
    Drc,
    /// FE solve of this many scenes (the long one).
    Fe(usize),
    /// The solid rung on this many scenes (`--verify-solid`).
    Solid(usize),
    Traveler,
}

impl Stage {
    pub fn label(self) -> String {
        match self {
            Stage::Masks => "etch plan and masks".into(),
            Stage::Drc => "DRC".into(),
            Stage::Fe(n) => format!("FE: {n} scenes"),
            Stage::Solid(n) => format!("solid rung: {n} scenes"),
            Stage::Traveler => "traveler".into(),
        }
    }
}

/// Everything computed.
#[derive(Debug, Clone)]
pub struct Built {
    pub plan: EtchPlan,
    pub set: MaskSet,
    pub drc: DrcReport,
    /// `<device>.gds`, `<device>.lyp`, `<device>-<mask>.svg` in inventory order.
    pub mask_files: Vec<(String, Vec<u8>)>,
    pub inventory: Inventory,
    /// Full FE reports (with timings) and their deterministic summary.
    pub fe_reports: Vec<SceneReport>,
    pub fe: Option<FeSummary>,
    pub traveler: Traveler,
    pub markdown: String,
    pub html: String,
    /// `tactfab etch --json` of the plan.
    pub plan_json: String,
    /// The solid rung beside the linear plate per declared scene (`--verify-solid`), and the
    /// tolerance it was checked at.
    pub solid_check: Vec<crate::sensor::solid::SolidReport>,
    /// Each solid report's scene limits checked against the solid's values.
    pub solid_limits: Vec<Vec<super::LimitCheck>>,
    pub solid_tol: f64,
}

impl Built {
    /// What makes the build fail, one line each: etch-plan errors, unwaived DRC violations,
    /// declared FE limits.
    pub fn failures(&self) -> Vec<String> {
        let mut f = super::sheet::failures(&self.traveler);
        for (r, checks) in self.solid_check.iter().zip(&self.solid_limits) {
            for c in checks.iter().filter(|c| !c.passed) {
                f.push(format!("scene `{}` on the solid rung: {c}", r.scene));
            }
            for (name, d) in r.disagreements(self.solid_tol) {
                let rung = if r.nonlinear {
                    "large-deflection"
                } else {
                    "linear"
                };
                f.push(format!(
                    "scene `{}`: the {rung} plate's {name} differs from the solid rung's by {d:.1e} \
                     (> {:.0e}; difference plus the solid's own estimate where it has one)",
                    r.scene, self.solid_tol
                ));
            }
        }
        f
    }

    /// File names of the traveler.
    pub fn traveler_names(&self) -> (String, String) {
        (
            format!("{}-traveler.md", self.set.device),
            format!("{}-traveler.html", self.set.device),
        )
    }

    /// Every output file except the summary: masks, etch plan, DRC report, traveler.
    pub fn files(&self) -> Vec<(String, Vec<u8>)> {
        let mut files = self.mask_files.clone();
        let d = &self.set.device;
        files.push((
            format!("{d}-etch-plan.json"),
            self.plan_json.clone().into_bytes(),
        ));
        files.push((
            format!("{d}-drc.txt"),
            self.drc.summary(usize::MAX).into_bytes(),
        ));
        files.push((
            format!("{d}-drc.lyrdb"),
            crate::export::lyrdb::to_lyrdb(&self.drc, &self.set).into_bytes(),
        ));
        let (md, html) = self.traveler_names();
        files.push((md, self.markdown.clone().into_bytes()));
        files.push((html, self.html.clone().into_bytes()));
        if !self.solid_check.is_empty() {
            let v = serde_json::json!({
                "tol": self.solid_tol,
                "scenes": self.solid_check,
                "limits": self.solid_limits,
            });
            let text = serde_json::to_string_pretty(&v).unwrap_or_default() + "\n";
            files.push((format!("{d}-solid-check.json"), text.into_bytes()));
        }
        files
    }
}

/// Builds everything for `design` (`loaded` gives the defaults used and the overrides the
/// traveler lists); `progress` hears each stage as it starts.
pub fn build(
    loaded: &Loaded,
    design: &Design,
    opts: &Options,
    progress: &mut dyn FnMut(Stage),
) -> Result<Built, ReportError> {
    let p = &design.process;
    let (plan, set) = (design.plan.clone(), design.masks.clone());
    progress(Stage::Masks);
    let gds = set.to_gds(&GdsOptions {
        date_epoch_s: opts.gds_epoch_s,
    })?;
    let svgs: Vec<String> = set
        .masks
        .iter()
        .map(|m| set.to_svg(m))
        .collect::<Result<_, _>>()?;
    let inv = inventory(&set, &gds, &svgs);
    let mut mask_files = vec![
        (inv.gds_file.clone(), gds),
        (inv.lyp_file.clone(), set.to_lyp().into_bytes()),
    ];
    for (m, svg) in inv.masks.iter().zip(&svgs) {
        mask_files.push((m.svg_file.clone(), svg.clone().into_bytes()));
    }
    let wafer_map = set.wafer_map_svg()?;
    mask_files.push((
        format!("{}-wafer.svg", set.device),
        wafer_map.clone().into_bytes(),
    ));
    progress(Stage::Drc);
    let drc = crate::drc::check(&set, p, &plan);

    let scenes = &p.checks.scenes;
    let mut solid_check = Vec::new();
    let mut solid_limits = Vec::new();
    let (fe_reports, fe) = match opts.fe {
        Some(o) if !scenes.is_empty() && plan.has_errors() => (
            Vec::new(),
            Some(super::fe::skipped(
                o.tol_rel,
                o.max_levels,
                format!(
                    "the {} declared scenes were not solved: the etch plan has errors (see the \
                     checks), so the plate it describes cannot be made",
                    scenes.len()
                ),
            )),
        ),
        Some(o) if !scenes.is_empty() => {
            progress(Stage::Fe(scenes.len()));
            let g = SensorGeometry::new(design);
            let mut reports = evaluate_many(&g, scenes, o)?;
            if let Some(check) = opts.verify_solid {
                progress(Stage::Solid(scenes.len()));
                for (s, r) in scenes.iter().zip(reports.iter_mut()) {
                    let run = crate::sensor::solid::SolidRun {
                        base: g.base,
                        levels: check.levels,
                        tol: o.tol_rel,
                        symmetry: true,
                        nonlinear: false,
                        graded: check.graded,
                        tied_shear: check.tied_shear,
                        grading: check.grading,
                    };
                    let solid = crate::sensor::solid::solid_against_plate(&g, s, run, o, Some(r))?;
                    // The plate answer's model error is the solid's measurement of it.
                    r.take_model_error_from(&g, &solid, o.tol_rel);
                    solid_limits.push(super::limits::check_solid_limits(
                        &solid,
                        &s.limits,
                        g.fracture_strength_mpa,
                    ));
                    solid_check.push(solid);
                }
            }
            let mut summary = summarise(
                scenes,
                &reports,
                o.tol_rel,
                o.max_levels,
                !opts.allow_unconverged,
            );
            summary.modes = Some(plate_modes(&g, MODES_REPORTED, MODAL_LEVELS)?);
            summary.supports = Some(SupportStiffness::of(&g)?);
            summary.tissue = Some(crate::hidden::summary::tissue_summary(&g, o)?);
            (reports, Some(summary))
        }
        _ => (Vec::new(), None),
    };

    progress(Stage::Traveler);
    // The tooth's etch, coarse: the traveler is also made by debug-built tests.
    let sim = crate::etch::sim::simulate(p, &plan, &set, super::traveler::ETCH_SIM_GRID_UM);
    let figures = Figures {
        masks: set.masks.iter().map(|m| m.name.clone()).zip(svgs).collect(),
        tooth: tooth_svg(&set)?,
        wafer: Some(wafer_map),
        etch_plan_view: sim.as_ref().ok().map(crate::etch::sim::svg::plan_view),
        etch_section: sim
            .as_ref()
            .ok()
            .map(crate::etch::sim::section::diagonal_section),
    };
    let mut t = traveler(TravelerInput {
        process: p,
        origin: &opts.origin,
        fe_accuracy: opts.fe,
        defaults_used: &loaded.defaults_used,
        overrides: &loaded.overrides,
        plan: &plan,
        set: &set,
        drc: &drc,
        inventory: inv.clone(),
        fe: fe.clone(),
    });
    t.etch_sim = Some(match &sim {
        Ok(s) => super::traveler::EtchSimRow::of(s),
        Err(e) => super::traveler::EtchSimRow::missing(
            e.to_string().lines().next().unwrap_or_default().to_string(),
        ),
    });
    let md = markdown(&t);
    let page = html(&t, &figures);
    let mut v = serde_json::to_value(&plan)?;
    v["defaults_used"] = serde_json::to_value(&loaded.defaults_used)?;
    let plan_json = serde_json::to_string_pretty(&v)? + "\n";
    Ok(Built {
        plan,
        set,
        drc,
        mask_files,
        inventory: inv,
        fe_reports,
        fe,
        traveler: t,
        markdown: md,
        html: page,
        plan_json,
        solid_check,
        solid_limits,
        solid_tol: opts.fe.map_or(0.0, |o| o.tol_rel),
    })
}

/// One tooth of the front mask (tooth top and compensators) as a small SVG, in um.
fn tooth_svg(set: &MaskSet) -> Result<Option<String>, ExportError> {
    let Some(cell) = set.tooth_cell.as_ref() else {
        return Ok(None);
    };
    let polys = set.flatten(cell, LayerKind::FrontSi);
    let Some(r) = geo::MultiPolygon::new(polys.clone()).bounding_rect() else {
        return Ok(None);
    };
    let m = 0.05 * (r.width().max(r.height()));
    let (x0, y0) = (r.min().x - m, r.min().y - m);
    let shifted: Vec<geo::Polygon> = polys
        .iter()
        .map(|p| geo::MapCoords::map_coords(p, |c| geo::coord! { x: c.x - x0, y: c.y - y0 }))
        .collect();
    let (w, h) = (r.width() + 2.0 * m, r.height() + 2.0 * m);
    let h_nm = i64::from(nm(h)?);
    Ok(Some(format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {} {}\" \
         role=\"img\"><title>tooth with compensators</title><path d=\"{}\" fill=\"#3c6fb4\" \
         stroke=\"none\"/></svg>",
        um_text(i64::from(nm(w)?)),
        um_text(h_nm),
        path_data(&shifted, h_nm)?
    )))
}
