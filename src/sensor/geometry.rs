//! What the FE model takes from the process, the etch plan and the PVDF mask.

use serde::Serialize;

use crate::design::Design;
use crate::fe::{DieEdge, PlateMaterial, ThicknessRegion};
pub use crate::layout::ElectrodeSide;
use crate::layout::MaskSet;
use crate::process::{Axis, Direction, Process, SiliconModel};

/// One electrode island as the FE model sees it: its bounding rectangle and metallised area.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElectrodeArea {
    pub name: String,
    pub side: ElectrodeSide,
    pub x0_um: f64,
    pub y0_um: f64,
    pub x1_um: f64,
    pub y1_um: f64,
    /// Metallised area including the wire pad (sets the capacitance).
    pub area_um2: f64,
}

/// The sensor as the FE model needs it (die coordinates, um).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensorGeometry {
    pub length_um: f64,
    pub width_um: f64,
    /// The channel floor as etched ([`crate::etch::EtchPlan::channel_floor_y_um`]): the plate
    /// spans y in [y0_um, y1_um] and is clamped there, where the {111} walls meet it.
    pub plate_y0_um: f64,
    pub plate_y1_um: f64,
    /// Plate thickness the recipe leaves (from the etch plan, not the drawing's target).
    pub plate_thickness_um: f64,
    /// Teeth footprints over the plate with their total thickness.
    pub teeth: Vec<ThicknessRegion>,
    pub electrodes: Vec<ElectrodeArea>,
    pub material: PlateMaterial,
    /// PVDF: E (Pa), nu, d31/d32/d33 (pC/N), eps_r, film thickness (um), drawn axis.
    pub pvdf_e_pa: f64,
    pub pvdf_nu: f64,
    pub d31_pc_per_n: f64,
    pub d32_pc_per_n: f64,
    pub d33_pc_per_n: f64,
    pub eps_r: f64,
    pub film_thickness_um: f64,
    pub drawn_axis: Axis,
    pub fracture_strength_mpa: f64,
    /// K_Ic, with the strength the critical distance of the edge stresses.
    pub fracture_toughness_mpa_sqrt_m: f64,
    pub safety_factor: f64,
    /// Mass densities (kg/m^3) of the silicon (plate and teeth) and of the PVDF film, which
    /// moves with the plate but adds no stiffness to the plate model (the natural frequencies).
    pub si_density_kg_per_m3: f64,
    pub film_density_kg_per_m3: f64,
    /// Room under the plate before it touches the channel floor: the channel depth the back etch
    /// achieves (the etch plan; the drawn depth without one) less the PVDF film bonded under the
    /// plate.
    pub gap_um: f64,
    /// The etched 3D shape the solid rung builds (the plate rungs use `teeth` and the clamp).
    pub etched: EtchedShape,
    /// Silicon's elastic constants as the process gives them (the solid rung rotates them).
    pub silicon: SiliconStiffness,
    /// What the sensor stands on (the solid rung models it; the plate rungs clamp the plate or
    /// put it on the supports' elastic footing, `support_model`).
    pub base: Base,
    /// How the plate rungs hold the plate where the etched walls meet it.
    pub support_model: crate::process::SupportModel,
    /// The supports' plane-strain sections and their stiffness along the wall (`support_model:
    /// solid_section`), solved once here.
    #[serde(skip)]
    pub support_section:
        Option<Result<super::support_section::SupportSections, crate::fe::FeError>>,
}

/// What the etch leaves in 3D, in die coordinates (um).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EtchedShape {
    /// Drawn tooth tops `[x0, y0, x1, y1]`: the top faces of the {111} frusta.
    pub tooth_tops_um: Vec<[f64; 4]>,
    /// Tooth height (the front etch depth) and its {111} sidewall run-out.
    pub tooth_height_um: f64,
    pub tooth_run_out_um: f64,
    /// Where the plate rungs' step stands, as a fraction of the run-out from the base edge
    /// ([`super::frustum_step::inset`]).
    pub tooth_step_inset: f64,
    /// Support height (the back etch depth) and support 1's footprint edge: the back mask's
    /// edge less its undercut, where the etched wall leaves the support's bottom face. The wall
    /// runs from there to the channel floor's edge (`plate_y0_um`); support 2 mirrors it.
    pub support_height_um: f64,
    pub support_edge_y_um: f64,
}

/// What the support film stands on (`materials.base`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Base {
    /// A rigid base: the film's bottom face is held.
    Rigid,
    /// An elastic base plate held on its bottom face (paper 002: 2 mm Plexiglas).
    Elastic {
        thickness_um: f64,
        e_pa: f64,
        nu: f64,
    },
}

/// Silicon stiffness as given: a cubic crystal with the die-edge direction, or isotropic.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum SiliconStiffness {
    Cubic {
        c11_pa: f64,
        c12_pa: f64,
        c44_pa: f64,
        die_edge: DieEdge,
    },
    Isotropic {
        e_pa: f64,
        nu: f64,
    },
}

/// The channel depth the recipe etches from the back (the back-side silicon steps of the etch
/// plan), or the drawn depth when the plan has none.
fn channel_depth_um(design: &Design) -> f64 {
    let back: Vec<f64> = design
        .plan
        .steps
        .iter()
        .filter(|s| s.side == crate::process::Side::Back)
        .map(|s| s.achieved_depth_um)
        .collect();
    if back.is_empty() {
        design.process.geometry.channel_depth_um
    } else {
        back.iter().sum()
    }
}

impl SensorGeometry {
    /// The sensor of a design: the teeth and electrodes the mask set draws, the plate the recipe
    /// leaves. A tooth is a square with the full tooth height on top of the plate, clipped to the
    /// plate between the supports. Its edges stand at the {111} frustum's mid-height (the etch
    /// plan's run-out) on the clamp and the footing, and under `support_model: solid_section`
    /// where the step bends as the sidewall does ([`super::frustum_step::inset`]).
    pub fn new(design: &Design) -> Self {
        let (p, plan) = (&design.process, &design.plan);
        let g = &p.geometry;
        // Clamped where the U-channel's {111} walls meet the plate, as etched.
        let [py0, py1] = plan.channel_floor_y_um;
        let plate = plan.plate_thickness_um;
        let t = &g.teeth;
        let front = plan.steps.iter().find(|s| s.mesa_base_um.is_some());
        let (height, run_out) = match front {
            Some(s) => (s.achieved_depth_um, s.sidewall_run_out_um),
            None => (t.height_um, t.height_um / 2f64.sqrt()),
        };
        // With the supports' sections, the sidewall's measured step and the teeth standing on
        // the top face (their mid-plane risen by half the tooth height, so the large-deflection
        // plate couples their bending to its stretching); the clamp and the footing keep the
        // centred mid-height step their validation tables were measured with.
        let (inset, rise) = match p.materials.base.support_model {
            crate::process::SupportModel::SolidSection => (
                super::frustum_step::inset(plate, height, run_out, silicon_stiffness(p)),
                0.5 * height,
            ),
            _ => (0.5, 0.0),
        };
        let teeth = tooth_footprints(
            &design.masks,
            (run_out, inset),
            (plate + height, rise),
            (py0, py1),
        );
        let top = design.masks.tooth_top_um;
        let etched = EtchedShape {
            tooth_tops_um: match design.masks.tooth_cell {
                Some(_) => design
                    .masks
                    .teeth
                    .iter()
                    .map(|t| [t.x_um, t.y_um, t.x_um + top, t.y_um + top])
                    .collect(),
                None => Vec::new(),
            },
            tooth_height_um: height,
            tooth_run_out_um: run_out,
            tooth_step_inset: inset,
            support_height_um: channel_depth_um(design),
            support_edge_y_um: plan.channel_wall_y_um[0],
        };
        let electrodes = Self::electrodes_from_masks(&design.masks);
        let si = &p.materials.silicon;
        let material = silicon_material(p);
        let f = &p.materials.pvdf;
        let mut g = SensorGeometry {
            length_um: g.die_length_um,
            width_um: g.die_width_um,
            plate_y0_um: py0,
            plate_y1_um: py1,
            plate_thickness_um: plate,
            teeth,
            electrodes,
            material,
            pvdf_e_pa: f.e_gpa * 1e9,
            pvdf_nu: f.nu,
            d31_pc_per_n: f.d31_pc_per_n,
            d32_pc_per_n: f.d32_pc_per_n,
            d33_pc_per_n: f.d33_pc_per_n,
            eps_r: f.eps_r,
            film_thickness_um: f.thickness_um,
            drawn_axis: g.electrodes.drawn_axis,
            fracture_strength_mpa: si.fracture_strength_mpa,
            fracture_toughness_mpa_sqrt_m: si.fracture_toughness_mpa_sqrt_m,
            safety_factor: si.safety_factor,
            si_density_kg_per_m3: si.density_g_per_cm3 * 1000.0,
            film_density_kg_per_m3: f.density_g_per_cm3 * 1000.0,
            gap_um: channel_depth_um(design) - f.thickness_um,
            etched,
            silicon: silicon_stiffness(p),
            base: match p.materials.base.kind {
                crate::process::BaseKind::Rigid => Base::Rigid,
                crate::process::BaseKind::Plexiglas => Base::Elastic {
                    thickness_um: p.materials.base.thickness_um,
                    e_pa: p.materials.base.e_gpa * 1e9,
                    nu: p.materials.base.nu,
                },
            },
            support_model: p.materials.base.support_model,
            support_section: None,
        };
        if g.support_model == crate::process::SupportModel::SolidSection {
            g.support_section = Some(super::support_section::SupportSections::new(&g, 0));
        }
        g
    }

    /// Electrode rectangles of the PVDF mask: what is drawn is what the model reads. Each island's
    /// bounding box and its metallised area (pad included).
    pub fn electrodes_from_masks(masks: &MaskSet) -> Vec<ElectrodeArea> {
        use geo::{Area, BoundingRect};
        let mut by_name: std::collections::BTreeMap<String, ElectrodeArea> =
            std::collections::BTreeMap::new();
        for e in &masks.electrodes {
            let Some(b) = e.polygon.bounding_rect() else {
                continue;
            };
            let side = e.side;
            let a = e.polygon.unsigned_area();
            let entry = by_name.entry(e.name.clone()).or_insert(ElectrodeArea {
                name: e.name.clone(),
                side,
                x0_um: b.min().x,
                y0_um: b.min().y,
                x1_um: b.max().x,
                y1_um: b.max().y,
                area_um2: 0.0,
            });
            entry.x0_um = entry.x0_um.min(b.min().x);
            entry.y0_um = entry.y0_um.min(b.min().y);
            entry.x1_um = entry.x1_um.max(b.max().x);
            entry.y1_um = entry.y1_um.max(b.max().y);
            entry.area_um2 += a;
        }
        // Mask order: S1k, Mk, S2k.
        let mut out: Vec<ElectrodeArea> = by_name.into_values().collect();
        out.sort_by(|a, b| a.side.cmp(&b.side).then(a.name.cmp(&b.name)));
        out
    }

    /// The supports' sections under `support_model: solid_section`: their solve's error if it
    /// failed, an error if the geometry was not built by [`Self::new`] (which solves them).
    pub fn support_sections(
        &self,
    ) -> crate::fe::FeResult<&super::support_section::SupportSections> {
        match &self.support_section {
            Some(s) => s.as_ref().map_err(Clone::clone),
            None => Err(crate::fe::FeError::SolidInput {
                detail: "support_model solid_section without its section".into(),
                hint: "build the sensor with SensorGeometry::new, which solves the section",
            }),
        }
    }

    /// Lines every mesh keeps exactly: plate edges, electrode edges.
    pub fn exact_lines(&self) -> (Vec<f64>, Vec<f64>) {
        let mut xs = vec![0.0, self.length_um];
        let mut ys = vec![self.plate_y0_um, self.plate_y1_um];
        for e in &self.electrodes {
            xs.extend([e.x0_um, e.x1_um]);
            if e.side == ElectrodeSide::Middle {
                ys.extend([e.y0_um, e.y1_um]);
            }
        }
        // Where the supports' section changes (a tooth standing on the support).
        if let Some(Ok(s)) = &self.support_section {
            xs.extend(s.x_lines_um());
        }
        (xs, ys)
    }

    /// Tooth footprint edges (kept unless they nearly coincide with an exact line).
    pub fn tooth_lines(&self) -> (Vec<f64>, Vec<f64>) {
        let xs = self.teeth.iter().flat_map(|t| [t.x0_um, t.x1_um]).collect();
        let ys = self.teeth.iter().flat_map(|t| [t.y0_um, t.y1_um]).collect();
        (xs, ys)
    }

    /// Film capacitance C = eps0 eps_r A / t (parallel plate) in farads.
    pub fn capacitance_f(&self, area_um2: f64) -> f64 {
        crate::units::EPS0_F_PER_M * self.eps_r * area_um2 * 1e-12 / (self.film_thickness_um * 1e-6)
    }
}

/// Footprints of the drawn teeth over the plate: the mask's tooth tops grown by the run-out less
/// the step's `inset` on each side, `thickness_um` thick, clipped to the die in x and to the
/// plate `(y0, y1)` in y.
fn tooth_footprints(
    masks: &MaskSet,
    (run_out_um, inset): (f64, f64),
    (thickness_um, rise_um): (f64, f64),
    (py0, py1): (f64, f64),
) -> Vec<ThicknessRegion> {
    if masks.tooth_cell.is_none() {
        return Vec::new();
    }
    let top = masks.tooth_top_um;
    let side = top + 2.0 * run_out_um * (1.0 - inset);
    masks
        .teeth
        .iter()
        .filter_map(|t| {
            let (cx, cy) = (t.x_um + top / 2.0, t.y_um + top / 2.0);
            let (x0, x1) = (
                (cx - side / 2.0).max(0.0),
                (cx + side / 2.0).min(masks.die_length_um),
            );
            let (y0, y1) = ((cy - side / 2.0).max(py0), (cy + side / 2.0).min(py1));
            (x1 > x0 && y1 > y0).then_some(ThicknessRegion {
                x0_um: x0,
                y0_um: y0,
                x1_um: x1,
                y1_um: y1,
                thickness_um,
                rise_um,
            })
        })
        .collect()
}

/// Silicon's stiffness as the process file gives it.
pub fn silicon_stiffness(p: &Process) -> SiliconStiffness {
    let si = &p.materials.silicon;
    match si.model {
        SiliconModel::Anisotropic => SiliconStiffness::Cubic {
            c11_pa: si.c11_gpa * 1e9,
            c12_pa: si.c12_gpa * 1e9,
            c44_pa: si.c44_gpa * 1e9,
            die_edge: match p.wafer.die_edge {
                Direction::D110 => DieEdge::Along110,
                Direction::D100 => DieEdge::Along100,
            },
        },
        SiliconModel::Isotropic => SiliconStiffness::Isotropic {
            e_pa: si.e_gpa * 1e9,
            nu: si.nu,
        },
    }
}

/// The silicon plate material the process asks for: orthotropic in die axes from C11, C12, C44
/// and the die-edge direction, or the isotropic override.
pub fn silicon_material(p: &Process) -> PlateMaterial {
    let si = &p.materials.silicon;
    match si.model {
        SiliconModel::Anisotropic => PlateMaterial::from_cubic(
            si.c11_gpa * 1e9,
            si.c12_gpa * 1e9,
            si.c44_gpa * 1e9,
            match p.wafer.die_edge {
                Direction::D110 => DieEdge::Along110,
                Direction::D100 => DieEdge::Along100,
            },
        ),
        SiliconModel::Isotropic => PlateMaterial::isotropic(si.e_gpa * 1e9, si.nu),
    }
}

/// The bundled design with `sets` applied (`--set` spelling), for the sensor's unit tests.
#[cfg(test)]
pub(crate) fn bundled(sets: &[&str]) -> SensorGeometry {
    let text = std::fs::read_to_string("process/mis-grasper.yaml").expect("bundled file");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let p = crate::process::load_str(&text, "mis-grasper.yaml", &sets)
        .expect("valid process")
        .process;
    SensorGeometry::new(&crate::design::Design::new(p).expect("design"))
}
