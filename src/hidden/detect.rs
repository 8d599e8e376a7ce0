//! The detectability map (issue 17, item 2): which lumps the design sees above the noise, over
//! size x depth (and stiffness ratio).
//!
//! For each lump (radius, centre height above the sensor, E_lump / E_tissue) at one place on
//! the face, the nine-voltage difference dV against the background through the unit responses,
//! and the ideal matched-filter SNR |dV| / sigma (the statistic of [`super::locate`] with the
//! right template: the best any linear detector does with white noise sigma per channel). A
//! lump is detectable when that reaches the threshold. Cost: one slab solve per lump (the
//! background is solved once), then a dot product: the plate is never solved again.

use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;

use crate::softness::inclusion::Feature;

use super::cells::UnitResponses;
use super::field::{Background, Disturbance, Shape};
use super::HiddenError;

/// Most lumps in one map \[choice\]: 2,000 slab solves.
pub const MAX_LUMPS: usize = 2_000;

/// What to map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapSpec {
    pub radii_m: Vec<f64>,
    /// Heights of the lump's centre above the sensor face.
    pub heights_m: Vec<f64>,
    /// E_lump / E_tissue.
    pub stiffness_ratios: Vec<f64>,
    pub lump_nu: f64,
    pub shape: Shape,
    /// Where the lump sits on the face (um).
    pub centre_um: (f64, f64),
    pub noise_mv: f64,
    pub threshold_snr: f64,
}

/// One lump of the map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapRow {
    pub radius_m: f64,
    pub height_m: f64,
    pub stiffness_ratio: f64,
    /// Peak P / P0 of the section.
    pub peak_ratio: f64,
    /// |dV| over the nine channels (mV) and the SNR.
    pub dv_mv: f64,
    pub snr: f64,
    pub detectable: bool,
}

/// The map and, per stiffness ratio and height, the smallest detectable radius of the grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetectMap {
    pub spec: MapSpec,
    pub rows: Vec<MapRow>,
    /// (stiffness ratio, height m, smallest detectable radius m or None).
    pub smallest: Vec<(f64, f64, Option<f64>)>,
    /// Lumps that do not fit in the slab at their height (skipped).
    pub skipped: usize,
}

/// Maps every lump of `spec` that fits in the background's slab.
pub fn detectability(
    ur: &UnitResponses,
    bg: &Background,
    spec: &MapSpec,
) -> Result<DetectMap, HiddenError> {
    let n = spec.radii_m.len() * spec.heights_m.len() * spec.stiffness_ratios.len();
    if n == 0 || n > MAX_LUMPS {
        return Err(HiddenError::Input {
            problem: format!("{n} lumps to map"),
            hint: "give 1-2,000 lumps (radii x heights x stiffness ratios)",
        });
    }
    if !(spec.noise_mv > 0.0 && spec.noise_mv.is_finite()) {
        return Err(HiddenError::Input {
            problem: format!("noise {} mV", spec.noise_mv),
            hint: "a positive noise level (mV rms per channel)",
        });
    }
    let h_slab = bg.slab.thickness_m;
    let mut lumps = Vec::with_capacity(n);
    let mut skipped = 0;
    for &k in &spec.stiffness_ratios {
        for &h in &spec.heights_m {
            for &r in &spec.radii_m {
                if r > 0.0 && h - r > 0.0 && h + r < h_slab && 2.0 * r < bg.slab.width_m {
                    lumps.push((r, h, k));
                } else {
                    skipped += 1;
                }
            }
        }
    }
    let rows: Vec<MapRow> = lumps
        .par_iter()
        .map(|&(r, h, k)| {
            let feature = Feature::Lump {
                e_pa: k * bg.slab.tissue_e_pa,
                nu: spec.lump_nu,
            };
            let d = Disturbance::new(bg, feature, r, h, spec.shape)?;
            let dv = ur.voltages_mv(&d.cells(bg, &ur.grid, spec.centre_um));
            let norm = dv.iter().map(|v| v * v).sum::<f64>().sqrt();
            let snr = norm / spec.noise_mv;
            Ok(MapRow {
                radius_m: r,
                height_m: h,
                stiffness_ratio: k,
                peak_ratio: d.peak_ratio,
                dv_mv: norm,
                snr,
                detectable: snr >= spec.threshold_snr,
            })
        })
        .collect::<Result<_, HiddenError>>()?;
    let mut smallest = Vec::new();
    for &k in &spec.stiffness_ratios {
        for &h in &spec.heights_m {
            let r = rows
                .iter()
                .filter(|w| w.stiffness_ratio == k && w.height_m == h && w.detectable)
                .map(|w| w.radius_m)
                .fold(None, |a: Option<f64>, r| Some(a.map_or(r, |a| a.min(r))));
            smallest.push((k, h, r));
        }
    }
    Ok(DetectMap {
        spec: spec.clone(),
        rows,
        smallest,
        skipped,
    })
}

impl DetectMap {
    /// `detectability.csv`: one row per lump, units in the header.
    pub fn csv(&self) -> String {
        let mut s = String::from(
            "radius_mm,height_mm,stiffness_ratio,peak_P_over_P0,dV_norm_mv,snr,detectable\n",
        );
        for r in &self.rows {
            let _ = writeln!(
                s,
                "{:.4},{:.4},{:.4},{:.5},{:.6e},{:.4},{}",
                r.radius_m * 1e3,
                r.height_m * 1e3,
                r.stiffness_ratio,
                r.peak_ratio,
                r.dv_mv,
                r.snr,
                u8::from(r.detectable)
            );
        }
        s
    }

    /// `detectability.svg`: the smallest detectable radius against the height, one line per
    /// stiffness ratio (a height with no detectable lump in the grid is left out).
    pub fn svg(&self) -> String {
        use crate::plot::{tick, xy_svg, Axis, Series, Style, XyPlot};
        let series = self
            .spec
            .stiffness_ratios
            .iter()
            .map(|&k| Series {
                name: format!("E_lump / E_tissue = {}", tick(k)),
                points: self
                    .smallest
                    .iter()
                    .filter(|s| s.0 == k)
                    .filter_map(|s| s.2.map(|r| (s.1 * 1e3, r * 1e3)))
                    .collect(),
                style: Style::LineAndMarkers,
            })
            .collect();
        xy_svg(
            &XyPlot {
                title: format!(
                    "Smallest detectable lump (SNR {} at {} mV per channel)",
                    tick(self.spec.threshold_snr),
                    tick(self.spec.noise_mv)
                ),
                x: Axis::linear("height of the lump's centre above the sensor (mm)"),
                y: Axis::linear("smallest detectable radius (mm)"),
                series,
            },
            800,
            480,
        )
    }
}
