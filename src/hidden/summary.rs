//! The traveler's tissue section: paper 002's default lump and void (a 2 mm sphere 4 mm above the
//! die centre in the 30 x 10 mm slab squeezed 10 %) through the sensor, cheaply: one slab solve
//! per feature (plus the background), and the background and each feature as full plate scenes
//! on the build's rung, in one batch ([`super::scenes`]): no cell unit responses.

use serde::Serialize;

use crate::sensor::{evaluate_many_with, Accuracy, MeshOptions, ModelKind, SensorGeometry};
use crate::softness::inclusion::{Feature, Slab};

use super::cells::CellGrid;
use super::field::{Background, Disturbance, Shape};
use super::scenes::cells_scene;
use super::HiddenError;

/// Slab elements along and through \[choice\]: the `tissue` defaults (0.25 mm).
pub const SLAB_ELEMENTS: (usize, usize) = (120, 40);
/// Cell side on the face (um), as `tissue --cell-mm 1`.
pub const CELL_UM: f64 = 1000.0;

/// One feature through the sensor.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeatureLine {
    /// "lump" or "void".
    pub feature: &'static str,
    /// The extreme P / P0 on the face (the peak for a lump, the minimum for a void).
    pub extreme_ratio: f64,
    pub m2_background_mv: f64,
    pub m2_feature_mv: f64,
    /// The electrode that changes most and by how much (mV).
    pub largest_electrode: String,
    pub largest_dv_mv: f64,
    pub rung: ModelKind,
    /// The worst total error (discretisation + model) of the two answers; None when unknown.
    pub error: Option<f64>,
}

/// The section's numbers.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TissueSummary {
    pub background_force_n: f64,
    pub features: Vec<FeatureLine>,
}

/// Paper 002's lump (200 kPa, nu 0.4) and a void, default geometry, at the die centre, on `acc`.
pub fn tissue_summary(g: &SensorGeometry, acc: Accuracy) -> Result<TissueSummary, HiddenError> {
    let lump = Feature::Lump {
        e_pa: 200e3,
        nu: 0.4,
    };
    let slab = Slab::paper_002(Feature::None);
    let (nx, ny) = SLAB_ELEMENTS;
    let bg = Background::new(&slab, nx, ny, g.length_um)?;
    let grid = CellGrid::new(g, CELL_UM)?;
    let centre = (0.5 * g.length_um, 0.5 * g.width_um);
    let p0 = bg.cells(&grid);
    let mut scenes = vec![cells_scene("tissue-background", &grid, &p0)];
    let mut dists = Vec::new();
    for (name, f) in [("lump", lump), ("void", Feature::Void)] {
        let d = Disturbance::new(&bg, f, slab.radius_m, slab.centre_height_m, Shape::Sphere)?;
        let with: Vec<f64> = p0
            .iter()
            .zip(d.cells(&bg, &grid, centre))
            .map(|(a, b)| a + b)
            .collect();
        scenes.push(cells_scene(&format!("tissue-{name}"), &grid, &with));
        dists.push((name, d));
    }
    let reports = evaluate_many_with(g, &scenes, acc, MeshOptions::READINGS)?;
    let names: Vec<&str> = g.electrodes.iter().map(|e| e.name.as_str()).collect();
    let volts = |k: usize| -> Vec<f64> {
        names
            .iter()
            .map(|n| {
                reports[k]
                    .electrodes
                    .iter()
                    .find(|e| e.name == *n)
                    .map_or(0.0, |e| e.voltage_mv)
            })
            .collect()
    };
    let base = volts(0);
    let m2 = names.iter().position(|n| *n == "M2").unwrap_or(0);
    let features = dists
        .iter()
        .enumerate()
        .map(|(j, (name, d))| {
            let v = volts(j + 1);
            let (k, dv) = v.iter().zip(&base).map(|(a, b)| a - b).enumerate().fold(
                (0, 0.0f64),
                |a, (k, x)| if x.abs() > a.1.abs() { (k, x) } else { a },
            );
            let r = &reports[j + 1];
            FeatureLine {
                feature: name,
                extreme_ratio: if *name == "void" {
                    d.min_ratio
                } else {
                    d.peak_ratio
                },
                m2_background_mv: base[m2],
                m2_feature_mv: v[m2],
                largest_electrode: names[k].to_string(),
                largest_dv_mv: dv,
                rung: r.model.kind,
                error: r
                    .error
                    .total
                    .zip(reports[0].error.total)
                    .map(|(a, b)| a.max(b)),
            }
        })
        .collect();
    Ok(TissueSummary {
        background_force_n: reports[0].force_n,
        features,
    })
}
