//! The softness study of `tactfab softness` (paper 001 Fig. 24): the middle-electrode voltage
//! against the tissue modulus from the composite beam and the tissue FE side by side, how far
//! they disagree, what each costs, the FE's discretisation error and the inverse's round trip.

use std::time::Instant;

use serde::Serialize;

use crate::fe::ThreeMesh;
use crate::sensor::SensorGeometry;

use super::inverse::{invert, Inverse};
use super::tissue_fe::{TissueEnds, TissueMesh, TissueModel};
use super::{composite_beam, SoftnessError, SoftnessSetup};

/// What to compute.
#[derive(Debug, Clone, PartialEq)]
pub struct StudySpec {
    pub tissue_thickness_um: f64,
    pub tissue_nu: f64,
    /// Distributed loads (N); the table and plot have one column pair per force.
    pub forces_n: Vec<f64>,
    /// Tissue moduli (Pa): `points` log-spaced values from `lo_pa` to `hi_pa`.
    pub e_lo_pa: f64,
    pub e_hi_pa: f64,
    pub points: usize,
    /// A measured (voltage mV, force N) to invert, if any.
    pub invert: Option<(f64, f64)>,
}

/// One modulus: the voltage per newton of each model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Row {
    pub tissue_e_pa: f64,
    pub fe_v_per_n: f64,
    pub composite_v_per_n: f64,
}

/// The FE's discretisation error at one modulus (meshes 20x6, 40x12, 80x24).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FeError {
    pub tissue_e_pa: f64,
    /// Relative error of the standard (40x12) mesh's voltage.
    pub relative: f64,
    pub estimate: ThreeMesh,
}

/// Wall-clock cost (varies run to run; terminal output only).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cost {
    pub fe_unknowns: usize,
    pub assemble_ms: f64,
    /// Median per modulus: numeric Cholesky + solve.
    pub fe_ms_per_modulus: f64,
    /// Median per modulus of the closed form.
    pub composite_us_per_modulus: f64,
}

/// A requested inversion of a measured voltage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Inversion {
    pub voltage_mv: f64,
    pub force_n: f64,
    pub fe: Inverse,
    /// The composite beam's answer, or why it has none (out of its range).
    pub composite: Result<Inverse, String>,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Study {
    pub setup: SoftnessSetup,
    pub forces_n: Vec<f64>,
    pub rows: Vec<Row>,
    /// Largest |composite / FE - 1| over the range (both linear in F: the same for every force).
    pub disagreement: f64,
    /// The same with the tissue's end faces clamped as the composite beam assumes.
    pub disagreement_clamped_ends: f64,
    pub cost: Cost,
    pub fe_errors: Vec<FeError>,
    /// Round trip of the inverse on the FE curve: (E_t, force, voltage mV, recovered).
    pub round_trip: (f64, f64, f64, Inverse),
    pub inversion: Option<Inversion>,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Runs the study on the sensor `g`.
#[track_caller]
pub fn study(g: &SensorGeometry, spec: &StudySpec) -> Result<Study, SoftnessError> {
    assert!(
        spec.points >= 2 && spec.e_hi_pa > spec.e_lo_pa && spec.e_lo_pa > 0.0,
        "a modulus range of at least two points"
    );
    assert!(!spec.forces_n.is_empty(), "at least one force");
    let setup = SoftnessSetup::from_sensor(g, spec.tissue_thickness_um, spec.tissue_nu)?;
    let (lo, hi) = (spec.e_lo_pa, spec.e_hi_pa);
    let es: Vec<f64> = (0..spec.points)
        .map(|k| lo * (hi / lo).powf(k as f64 / (spec.points - 1) as f64))
        .collect();
    let t = Instant::now();
    let fe = TissueModel::new(&setup, TissueMesh::standard())?;
    let assemble_ms = ms_since(t);
    let (mut fe_ms, mut cb_us, mut rows) = (Vec::new(), Vec::new(), Vec::new());
    for &e in &es {
        let t = Instant::now();
        let fe_v_per_n = fe.voltage_v(e, 1.0)?;
        fe_ms.push(ms_since(t));
        let t = Instant::now();
        let mut composite_v_per_n = 0.0;
        for _ in 0..1000 {
            composite_v_per_n = std::hint::black_box(composite_beam::voltage_v(
                std::hint::black_box(&setup),
                e,
                1.0,
            ));
        }
        cb_us.push(ms_since(t));
        rows.push(Row {
            tissue_e_pa: e,
            fe_v_per_n,
            composite_v_per_n,
        });
    }
    let disagreement = rows
        .iter()
        .map(|r| (r.composite_v_per_n / r.fe_v_per_n - 1.0).abs())
        .fold(0.0, f64::max);
    // The composite beam builds the whole section in at the supports; the FE above clamps only
    // the plate. With the tissue's end faces clamped too, the FE tests the beam's other
    // assumptions.
    let clamped = TissueModel::with_ends(&setup, TissueMesh::standard(), TissueEnds::Clamped)?;
    let mut disagreement_clamped_ends: f64 = 0.0;
    for r in &rows {
        let v = clamped.voltage_v(r.tissue_e_pa, 1.0)?;
        disagreement_clamped_ends =
            disagreement_clamped_ends.max((r.composite_v_per_n / v - 1.0).abs());
    }
    let cost = Cost {
        fe_unknowns: fe.n_unknowns,
        assemble_ms,
        fe_ms_per_modulus: median(fe_ms),
        composite_us_per_modulus: median(cb_us),
    };
    let fe_errors = fe_errors(&setup, [lo, (lo * hi).sqrt(), hi])?;
    let mut g_fe = |e: f64| fe.voltage_v(e, 1.0);
    let (e_true, f_true) = ((lo * hi).sqrt(), spec.forces_n[spec.forces_n.len() / 2]);
    let v_meas = fe.voltage_v(e_true, f_true)?;
    let back = invert(&mut g_fe, v_meas / f_true, lo, hi, 1e-7)?;
    let inversion = match spec.invert {
        None => None,
        Some((voltage_mv, force_n)) => {
            let v_per_n = voltage_mv * 1e-3 / force_n;
            let fe = invert(&mut g_fe, v_per_n, lo, hi, 1e-7)?;
            let mut g_cb = |e: f64| Ok(composite_beam::voltage_v(&setup, e, 1.0));
            let composite = invert(&mut g_cb, v_per_n, lo, hi, 1e-9).map_err(|e| e.to_string());
            Some(Inversion {
                voltage_mv,
                force_n,
                fe,
                composite,
            })
        }
    };
    Ok(Study {
        setup,
        forces_n: spec.forces_n.clone(),
        rows,
        disagreement,
        disagreement_clamped_ends,
        cost,
        fe_errors,
        round_trip: (e_true, f_true, 1e3 * v_meas, back),
        inversion,
    })
}

/// The FE's discretisation error at `moduli`: three nested meshes around the standard one and
/// the one three-mesh estimate of the standard (medium) mesh's value.
fn fe_errors(setup: &SoftnessSetup, moduli: [f64; 3]) -> Result<Vec<FeError>, SoftnessError> {
    let levels: Vec<TissueModel> = [
        TissueMesh {
            across: 20,
            through: 6,
            ..TissueMesh::standard()
        },
        TissueMesh::standard(),
        TissueMesh::standard().refined(2),
    ]
    .into_iter()
    .map(|m| TissueModel::new(setup, m))
    .collect::<Result<_, _>>()?;
    moduli
        .iter()
        .map(|&e| {
            let v: Vec<f64> = levels
                .iter()
                .map(|m| m.voltage_v(e, 1.0))
                .collect::<Result<_, _>>()?;
            let estimate = ThreeMesh::new(v[0], v[1], v[2], 2.0, 2.0);
            Ok(FeError {
                tissue_e_pa: e,
                relative: estimate.relative_error_of(v[1]),
                estimate,
            })
        })
        .collect()
}

impl Study {
    /// `softness.csv`: one row per force and modulus, units in the header.
    pub fn csv(&self) -> String {
        let mut csv = String::from(
            "tissue_e_pa,force_n,fe_voltage_mv,composite_voltage_mv,composite_over_fe_minus_1\n",
        );
        for f in &self.forces_n {
            for r in &self.rows {
                csv.push_str(&format!(
                    "{:.6e},{f:.3},{:.6},{:.6},{:.6}\n",
                    r.tissue_e_pa,
                    1e3 * f * r.fe_v_per_n,
                    1e3 * f * r.composite_v_per_n,
                    r.composite_v_per_n / r.fe_v_per_n - 1.0
                ));
            }
        }
        csv
    }

    /// `softness.svg`: voltage against modulus, FE and composite beam per force.
    pub fn svg(&self) -> String {
        let mut curves = Vec::new();
        for f in &self.forces_n {
            let curve = |v: fn(&Row) -> f64| -> Vec<(f64, f64)> {
                self.rows
                    .iter()
                    .map(|r| (r.tissue_e_pa, 1e3 * f * v(r)))
                    .collect()
            };
            curves.push((format!("FE {f} N"), curve(|r| r.fe_v_per_n), true));
            curves.push((
                format!("composite beam {f} N"),
                curve(|r| r.composite_v_per_n),
                false,
            ));
        }
        super::plot::softness_svg(&curves)
    }
}
