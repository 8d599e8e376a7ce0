//! The solid rung's model of one scene at one mesh level, written out for an independent code
//! (issue 16: `benches/solid_peer.py` re-solves it with scikit-fem). Built exactly as
//! `fe --model solid` builds that level (both start from the rung's scene model: the same loads,
//! mirrors and [`super::solid_mesh::build`]), then solved and read by tactfab, whose results
//! travel with the model.
//!
//! The file is one JSON object ([`SolidExport`]); units are in the field names (um, Pa, N, m,
//! pC/N). Node order of an element: tactfab's [`hex27`] local order, node `a + 3 b + 9 c` at the
//! reference point (xi, eta, zeta) = (a - 1, b - 1, c - 1), each axis running along the die's x,
//! y, z before the map. Voigt order of the stiffness matrices: xx, yy, zz, yz, xz, xy with
//! engineering shear strains (sigma = C eps).

use std::time::Instant;

use serde::Serialize;

use crate::fe::solid::dofs::SolidDofs;
use crate::fe::solid::{hex27, Axis3, Outward, SolidLoad, SolidModel, TransverseShear};
use crate::process::{Axis, Scene};

use super::check::SensorError;
use super::geometry::{ElectrodeSide, SensorGeometry};
use super::solid::{SceneModel, COARSE_ELEMENT_UM, MAX_SOLID_LEVELS};
use super::solid_mesh::{Base, SolidMeshOptions, BASE, PVDF, SILICON};

/// One material of the model.
#[derive(Debug, Clone, Serialize)]
pub struct ExportMaterial {
    /// "silicon", "pvdf" or "base" (the id is the index in [`SolidExport::materials`]).
    pub name: &'static str,
    /// 6 x 6 stiffness in die axes, Voigt order (module doc), Pa.
    pub c_pa: [[f64; 6]; 6],
}

/// A uniform pressure on one element face (positive pushing into the material).
#[derive(Debug, Clone, Serialize)]
pub struct ExportPressure {
    pub element: usize,
    /// The face: "+x", "-x", "+y", "-y", "+z" or "-z" (the local face xi_axis = +-1, whose
    /// outward normal points that way before the map).
    pub face: String,
    pub pressure_pa: f64,
}

/// A force on one node.
#[derive(Debug, Clone, Serialize)]
pub struct ExportPoint {
    pub node: usize,
    pub force_n: [f64; 3],
}

/// One electrode: where its film is and which elements of that film it reads.
#[derive(Debug, Clone, Serialize)]
pub struct ExportElectrode {
    pub name: String,
    /// "middle" (the film bonded under the plate) or "support1" / "support2" (the film under
    /// that support).
    pub side: &'static str,
    /// Metallised area (um^2), for the capacitance.
    pub area_um2: f64,
    /// The drawn rectangle (x0, y0, x1, y1) and its mirror images clipped to the part solved,
    /// um; a film point inside k images counts k times.
    pub images_um: Vec<[f64; 4]>,
    /// +1 for the middle electrodes, -1 for the support ones (read with the plate rungs'
    /// polarity, Q = d33 x compression): Q = sign (1/t) integral of D3 dV.
    pub sign: f64,
    /// tactfab's film elements of this electrode with the number of images holding each, where
    /// every Gauss point of the element lies in the same number of images.
    pub elements: Vec<[usize; 2]>,
    /// Film elements whose Gauss points lie in different numbers of images (an electrode edge
    /// inside the element; none on the bundled design): tactfab counts each point.
    pub cut_elements: Vec<usize>,
}

/// The piezoelectric film.
#[derive(Debug, Clone, Serialize)]
pub struct ExportFilm {
    pub thickness_um: f64,
    pub d31_pc_per_n: f64,
    pub d32_pc_per_n: f64,
    pub d33_pc_per_n: f64,
    /// The film's axis 1 in die axes: "x" or "y" (D3 = d31 s11 + d32 s22 + d33 s33 in the
    /// film's axes; axis 3 is z).
    pub drawn_axis: &'static str,
    /// The support film is z in [0, support_film_top_um]; the film under the plate z in
    /// [floor_film_bottom_um, plate_bottom_um].
    pub support_film_top_um: f64,
    pub floor_film_bottom_um: f64,
    pub plate_bottom_um: f64,
    /// y of the die's centre line: support film elements below it belong to support 1.
    pub die_centre_y_um: f64,
}

/// tactfab's own results on this model.
#[derive(Debug, Clone, Serialize)]
pub struct ExportResults {
    pub free_dofs: usize,
    /// Entries of the Cholesky factor (f64s).
    pub factor_entries: usize,
    /// Downward deflection of the plate's mid-plane at [`SolidExport::deflection_point_um`], um.
    pub deflection_at_load_um: f64,
    /// Per electrode, in [`SolidExport::electrodes`] order, pC (the whole die).
    pub charge_pc: Vec<f64>,
    /// Compressive force through each support film (the whole die), N.
    pub support1_n: f64,
    pub support2_n: f64,
    /// K u - f summed per constraint group (the part solved), N.
    pub reactions_n: Vec<(String, [f64; 3])>,
    /// Largest principal stress over the silicon's 3x3x3 Gauss points, MPa.
    pub max_principal_mpa: f64,
    /// Displacement of every node (m), for the peer's field comparison.
    pub u_m: Vec<[f64; 3]>,
    /// tactfab's assembled load vector, nonzero entries (node, component, N), for checking the
    /// peer's own pressure integration.
    pub load_vector_n: Vec<(usize, usize, f64)>,
    /// Median wall time of build + factorisation + solve + read-out over `runs`, s.
    pub seconds: f64,
    pub runs: usize,
    /// The last run's parts, s: mesh (`build`), the model's setup (positions, checks, dofs,
    /// element matrices, pattern), assembly, symbolic analysis, numeric factorisation, solve
    /// (with one refinement step and the reactions), read-out.
    pub phases_s: Vec<(String, f64)>,
    /// Peak resident memory of the exporting process (MB), set by the caller; NaN if unknown.
    pub peak_rss_mb: f64,
}

/// The model of one scene at one level, and tactfab's answer.
#[derive(Debug, Clone, Serialize)]
pub struct SolidExport {
    pub format: &'static str,
    pub scene: String,
    pub level: usize,
    pub element_um: f64,
    /// The largest cell across the span (y between the channel walls), um
    /// ([`super::solid_mesh::SolidMeshOptions::span_element_um`]).
    pub span_element_um: f64,
    pub mirror_x_um: Option<f64>,
    pub mirror_y_um: Option<f64>,
    pub node_order: &'static str,
    /// How the bricks take their transverse shears: "displacement" (the plain brick) or "tied"
    /// (`fe::solid::shear_tying`: gamma_xz from the lines xi = +-1/sqrt 3, linear in xi,
    /// gamma_yz likewise in eta, on parallelepiped bricks only).
    pub shear: &'static str,
    pub voigt_order: [&'static str; 6],
    /// Node positions after the map (only nodes of active elements), um.
    pub nodes_um: Vec<[f64; 3]>,
    /// 27 node indices per element, in `node_order`.
    pub elements: Vec<Vec<usize>>,
    /// Material index of every element.
    pub material: Vec<u16>,
    pub materials: Vec<ExportMaterial>,
    /// tactfab's volume of every element (3x3x3 Gauss on the mapped element), um^3.
    pub element_volume_um3: Vec<f64>,
    /// Constraint group names; every constrained value is zero.
    pub groups: Vec<String>,
    /// (node, component 0..2, group) of every constrained dof.
    pub constrained: Vec<(usize, usize, usize)>,
    pub pressures: Vec<ExportPressure>,
    pub points: Vec<ExportPoint>,
    pub film: ExportFilm,
    pub electrodes: Vec<ExportElectrode>,
    /// Where the deflection is read: the load's reference point on the plate's mid-plane, um.
    pub deflection_point_um: [f64; 3],
    pub results: ExportResults,
}

/// The face's name in the export: its outward axis direction before the map.
fn face_name(axis: Axis3, outward: Outward) -> String {
    let s = if outward == Outward::Plus { "+" } else { "-" };
    format!("{s}{}", ["x", "y", "z"][axis.index()])
}

/// Which level of the rung [`export_scene`] writes, and how.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExportOptions {
    /// Mesh level, below [`MAX_SOLID_LEVELS`].
    pub level: usize,
    /// Mirrors where the die and the load allow.
    pub symmetry: bool,
    /// Timed repeats (the median is reported).
    pub runs: usize,
    /// The bricks' transverse shears tied, as `fe --model solid` does (unless `--plain-shear`).
    pub tied_shear: bool,
}

/// Builds, solves (median of `runs` timed repeats) and exports `scene` at `opts.level` as `fe
/// --model solid` does (base `base`, mirrors where the die and the load allow unless
/// `opts.symmetry` is off, graded at the base edges of `graded_teeth`: `fe` grades the plate
/// answer's [`SceneReport::hot_teeth`](crate::sensor::SceneReport::hot_teeth)).
/// Panics on a level of [`MAX_SOLID_LEVELS`] or more (misuse: callers check it); every failure of
/// the model is an error.
#[track_caller]
pub fn export_scene(
    g: &SensorGeometry,
    scene: &Scene,
    base: Base,
    opts: ExportOptions,
    graded_teeth: &[usize],
) -> Result<SolidExport, SensorError> {
    let ExportOptions {
        level,
        symmetry,
        runs,
        tied_shear,
    } = opts;
    assert!(level < MAX_SOLID_LEVELS, "level {level} over the rung's");
    let scene_model = SceneModel::new(g, scene, symmetry)?;
    let opts = SolidMeshOptions {
        shear: if tied_shear {
            TransverseShear::Tied
        } else {
            TransverseShear::Displacement
        },
        ..SolidMeshOptions::level(COARSE_ELEMENT_UM, level)
    };
    // The same sequence as one level of `evaluate_solid`, timed whole.
    let mut times = Vec::new();
    let mut last = None;
    let mut phases_s = Vec::new();
    for _ in 0..runs.max(1) {
        let t0 = Instant::now();
        let solid = scene_model.build(g, base, opts.clone(), graded_teeth)?;
        let t1 = Instant::now();
        let model = SolidModel::new(&solid.problem).map_err(SensorError::Fe)?;
        let t2 = Instant::now();
        let sol = model
            .solve(&solid.problem.load_cases)
            .map_err(SensorError::Fe)?;
        let t3 = Instant::now();
        let readout = scene_model.read(g, &solid, &sol[0])?;
        let t4 = Instant::now();
        times.push((t4 - t0).as_secs_f64());
        let b = model.timings();
        phases_s = vec![
            ("mesh".to_string(), (t1 - t0).as_secs_f64()),
            ("setup".into(), b.setup.as_secs_f64()),
            ("assembly".into(), b.assembly.as_secs_f64()),
            ("symbolic".into(), b.symbolic.as_secs_f64()),
            ("numeric".into(), b.numeric.as_secs_f64()),
            ("solve".into(), (t3 - t2).as_secs_f64()),
            ("readout".into(), (t4 - t3).as_secs_f64()),
        ];
        last = Some((solid, model, sol, readout));
    }
    times.sort_by(f64::total_cmp);
    let seconds = times[times.len() / 2];
    let (solid, model, sol, readout) = last.expect("at least one run");
    let sol = &sol[0];
    let grid = &solid.problem.grid;
    let pos = sol.node_positions_um();

    // Active nodes, renumbered in lattice order.
    let mut index = vec![usize::MAX; pos.len()];
    let mut nodes_um = Vec::new();
    let mut elements = Vec::new();
    let mut element_of = vec![usize::MAX; grid.element_count()];
    let mut material = Vec::new();
    let mut element_volume_um3 = Vec::new();
    for (e, slot) in element_of.iter_mut().enumerate() {
        let Some(m) = grid.material(e) else {
            continue;
        };
        *slot = elements.len();
        let ns = grid.element_nodes(e);
        for &n in &ns {
            if index[n] == usize::MAX {
                index[n] = usize::MAX - 1;
            }
        }
        elements.push(ns.to_vec());
        material.push(m);
        let x = ns.map(|n| pos[n]);
        element_volume_um3.push(
            hex27::gauss_points()
                .iter()
                .map(|&(xi, w)| hex27::geometry(&x, xi).det_j * w)
                .sum::<f64>(),
        );
    }
    for (n, i) in index.iter_mut().enumerate() {
        if *i != usize::MAX {
            *i = nodes_um.len();
            nodes_um.push(pos[n]);
        }
    }
    for el in &mut elements {
        for n in el.iter_mut() {
            *n = index[*n];
        }
    }

    let dofs = SolidDofs::new(grid, pos, &solid.problem.constraints).map_err(SensorError::Fe)?;
    let constrained = dofs
        .constrained
        .iter()
        .map(|&(d, v, grp)| {
            assert!(v == 0.0, "the sensor's constraints are all zero");
            (index[d / 3], d % 3, grp)
        })
        .collect();

    let mut pressures = Vec::new();
    let mut points = Vec::new();
    for load in &solid.problem.load_cases[0] {
        match load {
            SolidLoad::Pressure { face, pressure_pa } => {
                let es = crate::fe::solid::loads::face_elements(grid, face, 0, 0)
                    .map_err(SensorError::Fe)?;
                for part in es {
                    pressures.push(ExportPressure {
                        element: element_of[part.element],
                        face: face_name(face.axis, face.outward),
                        pressure_pa: *pressure_pa,
                    });
                }
            }
            SolidLoad::Point { at_um, force_n, .. } => {
                // The node the solver loaded: the nearest active one.
                let n = (0..pos.len())
                    .filter(|&n| index[n] != usize::MAX)
                    .min_by(|&a, &b| {
                        let d =
                            |n: usize| (0..3).map(|k| (pos[n][k] - at_um[k]).powi(2)).sum::<f64>();
                        d(a).total_cmp(&d(b))
                    })
                    .expect("an active node");
                points.push(ExportPoint {
                    node: index[n],
                    force_n: *force_n,
                });
            }
        }
    }
    let f = crate::fe::solid::loads::load_vector(grid, pos, &dofs, &solid.problem.load_cases[0], 0)
        .map_err(SensorError::Fe)?;
    let load_vector_n = f
        .iter()
        .enumerate()
        .filter(|(_, v)| **v != 0.0)
        .map(|(d, v)| (index[d / 3], d % 3, *v))
        .collect();

    let lay = solid.layers;
    let electrodes = g
        .electrodes
        .iter()
        .map(|el| {
            let images_um =
                super::solid_readout::images(&solid, [el.x0_um, el.y0_um, el.x1_um, el.y1_um]);
            let middle = el.side == ElectrodeSide::Middle;
            let film = |zc: f64| {
                if middle {
                    zc > lay.floor_film_bottom_um && zc < lay.plate_bottom_um
                } else {
                    zc > 0.0 && zc < lay.film_top_um
                }
            };
            let (mut els, mut cut) = (Vec::new(), Vec::new());
            for (e, &exported) in element_of.iter().enumerate() {
                if grid.material(e) != Some(PVDF) || !film(grid.element_centre_um(e)[2]) {
                    continue;
                }
                let x = grid.element_nodes(e).map(|n| pos[n]);
                let counts: Vec<usize> = hex27::gauss_points()
                    .iter()
                    .map(|&(xi, _)| {
                        let p = hex27::position(&x, xi);
                        images_um
                            .iter()
                            .filter(|r| {
                                p[0] >= r[0] && p[0] <= r[2] && p[1] >= r[1] && p[1] <= r[3]
                            })
                            .count()
                    })
                    .collect();
                if counts.iter().any(|&c| c != counts[0]) {
                    // An electrode edge that is not a grid line (two lines merged in the mesh).
                    cut.push(exported);
                } else if counts[0] > 0 {
                    els.push([exported, counts[0]]);
                }
            }
            ExportElectrode {
                name: el.name.clone(),
                side: match el.side {
                    ElectrodeSide::Middle => "middle",
                    ElectrodeSide::Support1 => "support1",
                    ElectrodeSide::Support2 => "support2",
                },
                area_um2: el.area_um2,
                images_um,
                sign: if middle { 1.0 } else { -1.0 },
                elements: els,
                cut_elements: cut,
            }
        })
        .collect();

    let names = |m: u16| match m {
        SILICON => "silicon",
        PVDF => "pvdf",
        BASE => "base",
        _ => "other",
    };
    let materials = solid
        .problem
        .materials
        .iter()
        .enumerate()
        .map(|(m, c)| ExportMaterial {
            name: names(m as u16),
            c_pa: c.c_pa,
        })
        .collect();
    let u_m = (0..pos.len())
        .filter(|&n| index[n] != usize::MAX)
        .map(|n| sol.node_displacement_m(n))
        .collect();
    Ok(SolidExport {
        format: "tactfab-solid-export 1",
        scene: scene.name.clone(),
        level,
        element_um: opts.element_um,
        span_element_um: opts.span_element_um,
        mirror_x_um: scene_model.mirror_x_um,
        mirror_y_um: scene_model.mirror_y_um,
        node_order: "a + 3 b + 9 c at (xi, eta, zeta) = (a - 1, b - 1, c - 1), xi along x",
        shear: if tied_shear { "tied" } else { "displacement" },
        voigt_order: ["xx", "yy", "zz", "yz", "xz", "xy"],
        nodes_um,
        elements,
        material,
        materials,
        element_volume_um3,
        groups: dofs.groups.clone(),
        constrained,
        pressures,
        points,
        film: ExportFilm {
            thickness_um: g.film_thickness_um,
            d31_pc_per_n: g.d31_pc_per_n,
            d32_pc_per_n: g.d32_pc_per_n,
            d33_pc_per_n: g.d33_pc_per_n,
            drawn_axis: match g.drawn_axis {
                Axis::X => "x",
                Axis::Y => "y",
            },
            support_film_top_um: lay.film_top_um,
            floor_film_bottom_um: lay.floor_film_bottom_um,
            plate_bottom_um: lay.plate_bottom_um,
            die_centre_y_um: 0.5 * g.width_um,
        },
        electrodes,
        deflection_point_um: [scene_model.at_um.0, scene_model.at_um.1, lay.plate_mid_um()],
        results: ExportResults {
            free_dofs: model.n_free_dofs(),
            factor_entries: model.factor_len(),
            deflection_at_load_um: readout.deflection_at_load_um,
            charge_pc: readout.charge_pc.clone(),
            support1_n: readout.support1_n,
            support2_n: readout.support2_n,
            reactions_n: sol
                .reactions()
                .iter()
                .map(|r| (r.group.clone(), r.force_n))
                .collect(),
            max_principal_mpa: readout.max_principal_mpa,
            u_m,
            load_vector_n,
            seconds,
            runs: runs.max(1),
            phases_s,
            peak_rss_mb: f64::NAN,
        },
    })
}
