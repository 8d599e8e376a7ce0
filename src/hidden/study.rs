//! `tactfab tissue --through-sensor` as one library call: the slab's background and feature,
//! the nine voltages with and without the feature on the linear plate, and optionally the
//! inverse on them (with seeded noise), the detectability map and the pulsating vessel.
//!
//! The cells' unit responses ([`super::cells`], one scene per cell) are solved only when the
//! inverse or the map needs them (they move the feature for free); otherwise the background and
//! the feature are two patches scenes of one linear-plate batch ([`cells_answers`]), which is
//! the same superposition at a fraction of the cost.

use serde::Serialize;
use std::fmt::Write as _;

use crate::analysis::noise::Gaussian;
use crate::process::{Limits, ReadoutElectronics, RegionUm, Scene, SceneLoad};
use crate::sensor::{evaluate_many_with, Accuracy, MeshOptions, ModelChoice, SensorGeometry};
use crate::softness::inclusion::{Feature, Slab};

use super::cells::{unit_responses, CellGrid, UnitResponses};
use super::detect::{detectability, DetectMap, MapSpec};
use super::field::{Background, Disturbance, Shape};
use super::locate::{locate, Located, Search};
use super::scenes::{cells_answers, full_scenes, FullScenes};
use super::vessel::{cycle, vessel, vessel_fields, Pulse, Vessel};
use super::HiddenError;

/// What to run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spec {
    /// The slab with its feature (its `centre_x_m` is ignored: the feature's place on the die is
    /// `centre_um`).
    pub slab: Slab,
    pub elements: (usize, usize),
    pub shape: Shape,
    /// The feature's centre on the die face (um): x along the jaw, y across.
    pub centre_um: (f64, f64),
    pub cell_um: f64,
    pub accuracy: Accuracy,
    /// Noise per channel (mV rms) for the inverse and the map; the inverse's SNR threshold.
    pub noise_mv: f64,
    pub threshold_snr: f64,
    /// Run the inverse on the difference plus seeded noise.
    pub locate: Option<u64>,
    /// The detectability map's axes (None: no map).
    pub map: Option<(Vec<f64>, Vec<f64>, Vec<f64>)>,
    /// A pulsating vessel (the slab's feature must be a void) and the front end to read it.
    pub vessel: Option<(Pulse, ReadoutElectronics)>,
    /// Also solve the background and the with-feature grasp as full scenes on `accuracy`'s rung
    /// ([`super::scenes`]); the unit responses, the inverse, the map and the vessel stay on the
    /// linear plate (they superpose).
    pub full_scenes: bool,
    /// The 3-D slab's face field (`softness::slab3d`, the slab centred on the die; its sphere
    /// at `centre_um`): when given, the cells take P0(x, y) and P(x, y) from it
    /// ([`super::face3d`]) for the voltages and the full scenes; the inverse, the map and the
    /// vessel keep the 2-D background and disturbance.
    pub face3d: Option<crate::softness::slab3d::FaceField>,
}

/// How the linear plate answered the background and the feature.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearPlate {
    /// True: through each cell's unit response; false: as two patches scenes.
    pub unit_responses: bool,
    pub levels: usize,
    pub dofs: usize,
    /// The worst estimated discretisation error (None before three levels).
    pub discretisation: Option<f64>,
}

/// Everything the study reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Study {
    pub electrodes: Vec<String>,
    pub background_mv: Vec<f64>,
    pub feature_mv: Vec<f64>,
    pub grid: CellGrid,
    pub linear: LinearPlate,
    /// The cells' unit responses, when the inverse or the map asked for them.
    pub unit: Option<UnitResponses>,
    pub peak_ratio: f64,
    pub min_ratio: f64,
    /// Total force of the background on the die (N) and the linear plate's model error at it
    /// (a uniform pressure of that total: its membrane stiffening, which superposition omits).
    pub background_force_n: f64,
    pub model_error_at_load: Option<f64>,
    pub located: Option<Located>,
    pub map: Option<DetectMap>,
    pub vessel: Option<Vessel>,
    /// The two grasps solved as full scenes on the rung asked for.
    pub scenes: Option<FullScenes>,
    #[serde(skip)]
    cells: (Vec<f64>, Vec<f64>),
}

/// Runs the study on the sensor `g`.
pub fn run(g: &SensorGeometry, spec: &Spec) -> Result<Study, HiddenError> {
    let (cx, cy) = spec.centre_um;
    let on = |v: f64, hi: f64| v.is_finite() && (0.0..=hi).contains(&v);
    if !(on(cx, g.length_um) && on(cy, g.width_um)) {
        return Err(HiddenError::Input {
            problem: format!(
                "the feature's centre ({:.3}, {:.3}) mm is not on the die (0-{:.3} x 0-{:.3} mm)",
                cx * 1e-3,
                cy * 1e-3,
                g.length_um * 1e-3,
                g.width_um * 1e-3
            ),
            hint: "place it with --x-mm (along the jaw) and --y-mm (across) inside the die",
        });
    }
    let (nx, ny) = spec.elements;
    let bg = Background::new(&spec.slab, nx, ny, g.length_um)?;
    let grid = CellGrid::new(g, spec.cell_um)?;
    let dist = Disturbance::new(
        &bg,
        spec.slab.feature,
        spec.slab.radius_m,
        spec.slab.centre_height_m,
        spec.shape,
    )?;
    if matches!(spec.accuracy.model, ModelChoice::Beam | ModelChoice::Solid) {
        return Err(HiddenError::Input {
            problem: format!(
                "the {} rung cannot carry the tissue's pressure field",
                spec.accuracy.model.as_str()
            ),
            hint: "use --model auto, plate or large-deflection",
        });
    }
    let (p0, dp) = match &spec.face3d {
        Some(f) => super::face3d::cells(f, &grid),
        None => (bg.cells(&grid), dist.cells(&bg, &grid, spec.centre_um)),
    };
    let mut vessel_done = None;
    let ur = if spec.locate.is_some() || spec.map.is_some() {
        Some(unit_responses(g, grid, spec.accuracy)?)
    } else {
        None
    };
    let (background_mv, feature_mv, linear) = match &ur {
        Some(ur) => {
            let b = ur.voltages_mv(&p0);
            let dv = ur.voltages_mv(&dp);
            let f = b.iter().zip(&dv).map(|(a, b)| a + b).collect();
            let info = LinearPlate {
                unit_responses: true,
                levels: ur.levels,
                dofs: ur.dofs,
                discretisation: ur.discretisation,
            };
            (b, f, info)
        }
        None => {
            let with: Vec<f64> = p0.iter().zip(&dp).map(|(a, b)| a + b).collect();
            let mut fields = vec![
                ("tissue-background", &p0[..]),
                ("tissue-feature", &with[..]),
            ];
            // The vessel's grasp is the feature's field: its unit field joins the same batch.
            let wall = match &spec.vessel {
                Some(_) => Some(vessel_fields(&bg, &dist, &grid, spec.centre_um)?.1),
                None => None,
            };
            if let Some(w) = &wall {
                fields.push(("vessel-per-pa", w));
            }
            // The vessel stays on the 2-D slab: with the 3-D face its grasp is solved apart.
            let grasp_2d: Option<Vec<f64>> = match (&spec.vessel, &spec.face3d) {
                (Some(_), Some(_)) => {
                    let b = bg.cells(&grid);
                    let d = dist.cells(&bg, &grid, spec.centre_um);
                    Some(b.iter().zip(&d).map(|(a, b)| a + b).collect())
                }
                _ => None,
            };
            if let Some(w) = &grasp_2d {
                fields.push(("vessel-grasp", w));
            }
            let plate = spec.accuracy.with_model(ModelChoice::Plate);
            let a = cells_answers(g, &grid, &fields, plate, MeshOptions::READINGS)?;
            if let (Some((pulse, electronics)), Some(unit)) = (&spec.vessel, a.get(2)) {
                let grasp = a.get(3).unwrap_or(&a[1]).clone();
                let tol = spec.accuracy.tol_rel;
                vessel_done = Some(cycle(g, grasp, unit.clone(), *pulse, electronics, tol)?);
            }
            let worse = |x: Option<f64>, y: Option<f64>| x.zip(y).map(|(x, y)| x.max(y));
            let info = LinearPlate {
                unit_responses: false,
                levels: a[0].levels.max(a[1].levels),
                dofs: a[0].dofs.max(a[1].dofs),
                discretisation: worse(a[0].error.discretisation, a[1].error.discretisation),
            };
            (a[0].voltages_mv.clone(), a[1].voltages_mv.clone(), info)
        }
    };
    let dv: Vec<f64> = feature_mv
        .iter()
        .zip(&background_mv)
        .map(|(a, b)| a - b)
        .collect();
    let scenes = if spec.full_scenes {
        Some(full_scenes(
            g,
            &grid,
            &p0,
            &dp,
            (&background_mv, &feature_mv),
            spec.accuracy,
        )?)
    } else {
        None
    };
    let background_force_n: f64 = p0.iter().sum::<f64>() * grid.area_m2();
    let model_error_at_load = if background_force_n > 0.0 {
        let scene = Scene {
            name: "tissue-background".into(),
            load: SceneLoad::Pressure {
                force_n: background_force_n,
                region: Some(RegionUm {
                    x0_um: 0.0,
                    y0_um: 0.0,
                    x1_um: g.length_um,
                    y1_um: g.width_um,
                }),
            },
            limits: Limits::default(),
        };
        let coarse = Accuracy {
            max_levels: 1,
            ..spec.accuracy.with_model(ModelChoice::Plate)
        };
        evaluate_many_with(
            g,
            std::slice::from_ref(&scene),
            coarse,
            MeshOptions::READINGS,
        )?
        .remove(0)
        .error
        .model
    } else {
        None
    };
    let located = match spec.locate {
        Some(seed) => {
            let mut noise = Gaussian::new(seed);
            let measured: Vec<f64> = dv
                .iter()
                .map(|v| v + spec.noise_mv * noise.sample())
                .collect();
            // References of the assumed size and depth: a lump of the slab's lump modulus (or
            // paper 002's 10x tissue when the feature is a void) and a void.
            let lump = match spec.slab.feature {
                Feature::Lump { .. } => spec.slab.feature,
                _ => Feature::Lump {
                    e_pa: 10.0 * spec.slab.tissue_e_pa,
                    nu: 0.4,
                },
            };
            let r = (spec.slab.radius_m, spec.slab.centre_height_m);
            let refs = [
                Disturbance::new(&bg, lump, r.0, r.1, spec.shape)?,
                Disturbance::new(&bg, Feature::Void, r.0, r.1, spec.shape)?,
            ];
            let search = Search {
                step_um: 500.0,
                noise_mv: spec.noise_mv,
                threshold_snr: spec.threshold_snr,
            };
            let ur = ur.as_ref().expect("unit responses for the inverse");
            Some(locate(ur, &bg, &[&refs[0], &refs[1]], &measured, search)?)
        }
        None => None,
    };
    let map = match &spec.map {
        Some((radii_m, heights_m, ratios)) => {
            let m = MapSpec {
                radii_m: radii_m.clone(),
                heights_m: heights_m.clone(),
                stiffness_ratios: ratios.clone(),
                lump_nu: match spec.slab.feature {
                    Feature::Lump { nu, .. } => nu,
                    _ => 0.4,
                },
                shape: spec.shape,
                centre_um: spec.centre_um,
                noise_mv: spec.noise_mv,
                threshold_snr: spec.threshold_snr,
            };
            let ur = ur.as_ref().expect("unit responses for the map");
            Some(detectability(ur, &bg, &m)?)
        }
        None => None,
    };
    let vessel = match (&spec.vessel, vessel_done) {
        (_, Some(v)) => Some(v),
        (Some((pulse, electronics)), None) => Some(vessel(
            g,
            &grid,
            &bg,
            &dist,
            spec.centre_um,
            *pulse,
            electronics,
            spec.accuracy,
        )?),
        (None, None) => None,
    };
    Ok(Study {
        vessel,
        scenes,
        electrodes: g.electrodes.iter().map(|e| e.name.clone()).collect(),
        background_mv,
        feature_mv,
        grid,
        linear,
        unit: ur,
        peak_ratio: spec
            .face3d
            .as_ref()
            .map_or(dist.peak_ratio, |f| f.peak_ratio),
        min_ratio: spec.face3d.as_ref().map_or(dist.min_ratio, |f| f.min_ratio),
        background_force_n,
        model_error_at_load,
        located,
        map,
        cells: (p0, dp),
    })
}

impl Study {
    /// `through-sensor.csv`: each electrode's voltage without and with the feature.
    pub fn csv(&self) -> String {
        let mut s = String::from("electrode,V_background_mv,V_feature_mv,dV_mv\n");
        for (i, e) in self.electrodes.iter().enumerate() {
            let (a, b) = (self.background_mv[i], self.feature_mv[i]);
            let _ = writeln!(s, "{e},{a:.6e},{b:.6e},{:.6e}", b - a);
        }
        s
    }

    /// `through-sensor-full.csv` (with full scenes): each electrode's voltage without and with
    /// the feature on the rung that answered, and each minus the linear superposition.
    pub fn full_csv(&self) -> Option<String> {
        let f = self.scenes.as_ref()?;
        let mut s = String::from(
            "electrode,V_background_mv,V_feature_mv,dV_mv,background_minus_superposition_mv,\
             feature_minus_superposition_mv\n",
        );
        let (b, w) = (&f.background, &f.feature);
        for (i, e) in self.electrodes.iter().enumerate() {
            let _ = writeln!(
                s,
                "{e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
                b.voltages_mv[i],
                w.voltages_mv[i],
                w.voltages_mv[i] - b.voltages_mv[i],
                b.minus_superposition_mv[i],
                w.minus_superposition_mv[i]
            );
        }
        Some(s)
    }

    /// `face-pressure.csv`: each cell's centre, background and extra pressure.
    pub fn face_csv(&self) -> String {
        let g = &self.grid;
        let mut s = String::from("x_mm,y_mm,P0_pa,dP_pa\n");
        for k in 0..g.len() {
            let (x0, y0, x1, y1) = g.rect(k);
            let _ = writeln!(
                s,
                "{:.4},{:.4},{:.6e},{:.6e}",
                0.5e-3 * (x0 + x1),
                0.5e-3 * (y0 + y1),
                self.cells.0[k],
                self.cells.1[k]
            );
        }
        s
    }

    /// `through-sensor.svg`: the nine voltage differences, electrode by electrode.
    pub fn svg(&self) -> String {
        use crate::plot::{xy_svg, Axis, Series, Style, XyPlot};
        let points = |v: &[f64]| -> Vec<(f64, f64)> {
            v.iter()
                .enumerate()
                .map(|(i, y)| ((i + 1) as f64, *y))
                .collect()
        };
        let dv: Vec<f64> = self
            .feature_mv
            .iter()
            .zip(&self.background_mv)
            .map(|(a, b)| a - b)
            .collect();
        xy_svg(
            &XyPlot {
                title: format!(
                    "Feature minus background, electrodes 1-9 = {}",
                    self.electrodes.join(", ")
                ),
                x: Axis::linear("electrode (model order)"),
                y: Axis::linear("voltage difference (mV)"),
                series: vec![Series {
                    name: "dV".into(),
                    points: points(&dv),
                    style: Style::Markers,
                }],
            },
            800,
            480,
        )
    }
}
