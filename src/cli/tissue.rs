//! `tactfab tissue FILE -o DIR`: the contact pressure a hidden lump or void puts on the sensor face
//! ([`tactfab::softness::inclusion`]), its P / P0 peak, and `DIR/tissue.csv` + `DIR/tissue.svg`.

use tactfab::hidden::field::Shape;
use tactfab::hidden::locate::Verdict;
use tactfab::hidden::study::{run as through_sensor, Spec};
use tactfab::hidden::vessel::{Pulse, PA_PER_MMHG};
use tactfab::sensor::{Accuracy, SensorGeometry};
use tactfab::softness::axislab::sphere_convergence;
use tactfab::softness::inclusion::{pressure_profile, Feature, Slab};

use tactfab::softness::slab3d::{face_field, FaceField, Mesh3d, Slab3d};

use super::args::{FeatureArg, ModelArg, ShapeArg, SlabArg, TissueArgs};
use super::output::f;
use super::{check_out, design, write_dir, Outcome};

pub fn run(a: &TissueArgs) -> anyhow::Result<Outcome> {
    // The process file is validated (and names the output) as for every study.
    let (_, design) = design(&a.process)?;
    super::warn_process_errors(&a.process, &design);
    check_out(&a.out, a.replace, &a.process)?;
    let sensor = a.through_sensor || a.locate || a.detectability || a.vessel;
    if a.vessel && a.feature != FeatureArg::Void {
        anyhow::bail!(
            "--vessel: a vessel is a void whose wall carries the pressure: add --feature void"
        );
    }
    if a.vessel && a.shape == ShapeArg::Sphere {
        anyhow::bail!(
            "--vessel: a vessel is a tube, not a sphere: add --shape cylinder (across the jaw) or \
             --shape rotated-section"
        );
    }
    if sensor && matches!(a.model, ModelArg::Beam | ModelArg::Solid) {
        anyhow::bail!(
            "--model: the tissue's pressure field loads the plate rungs only: use auto, plate or \
             large-deflection"
        );
    }
    let slab = Slab {
        width_m: a.width_mm * 1e-3,
        thickness_m: a.thickness_mm * 1e-3,
        tissue_e_pa: a.tissue_e_kpa * 1e3,
        tissue_nu: 0.49,
        compression: a.compression,
        feature: match a.feature {
            FeatureArg::Lump => Feature::Lump {
                e_pa: a.lump_e_kpa * 1e3,
                nu: 0.4,
            },
            FeatureArg::Void => Feature::Void,
        },
        centre_x_m: a.x_mm.unwrap_or(0.5 * a.width_mm) * 1e-3,
        centre_height_m: a.height_mm * 1e-3,
        radius_m: a.radius_mm * 1e-3,
    };
    let p =
        pressure_profile(&slab, usize::from(a.across), usize::from(a.through)).map_err(|e| {
            // Name the flags the user typed rather than the model's SI fields.
            match e {
                tactfab::softness::SoftnessError::BadInput { field, hint, .. } => anyhow::anyhow!(
                    "{}: {hint} (--width-mm {}, --thickness-mm {}, --x-mm {}, --height-mm {}, \
                 --radius-mm {})",
                    match field {
                        "radius_m" => "--radius-mm",
                        "lump e_pa" => "--lump-e-kpa",
                        "compression" => "--compression",
                        "tissue_e_pa" => "--tissue-e-kpa",
                        _ => "the slab",
                    },
                    a.width_mm,
                    a.thickness_mm,
                    slab.centre_x_m * 1e3,
                    a.height_mm,
                    a.radius_mm
                ),
                other => other.into(),
            }
        })?;
    let mut files = vec![
        ("tissue.csv".to_string(), p.csv().into_bytes()),
        ("tissue.svg".to_string(), p.svg(&slab).into_bytes()),
    ];
    let mut after = Vec::new();
    // The same feature as a sphere (axisymmetric) on three fitted meshes.
    let sc = sphere_convergence(
        &slab,
        usize::from(a.across).div_ceil(2),
        usize::from(a.through),
    )?;
    files.push(("tissue-sphere.csv".into(), sc.profile_csv().into_bytes()));
    files.push((
        "tissue-sphere-convergence.csv".into(),
        sc.convergence_csv().into_bytes(),
    ));
    after.push(format!(
        "  as a sphere (axisymmetric, on the axis of a {} mm radius tissue cylinder; meshes \
         fitted to it): {} P / P0 {}, {}, {} on {}, {}, {} elements{}",
        f(0.5 * a.width_mm, 2),
        if a.feature == FeatureArg::Void {
            "minimum"
        } else {
            "peak"
        },
        f(sc.extreme[0], 4),
        f(sc.extreme[1], 4),
        f(sc.extreme[2], 4),
        sc.elements[0],
        sc.elements[1],
        sc.elements[2],
        match (sc.estimate, sc.order, sc.error) {
            (Some(e), Some(o), Some(err)) => format!(
                " (order {}); Richardson estimate {}, the finest's error {err:.1e}",
                f(o, 2),
                f(e, 4)
            ),
            _ => "; not monotone: no Richardson estimate".into(),
        }
    ));
    let face3d = if a.slab == SlabArg::Block {
        let g = SensorGeometry::new(&design);
        let (face, lines) = block(a, &slab, &g)?;
        files.push(("tissue-3d.csv".into(), face.csv().into_bytes()));
        files.push((
            "tissue-3d.svg".into(),
            face.svg("3-D tissue slab: P / P0 on the sensor face")
                .into_bytes(),
        ));
        after.extend(lines);
        Some(face)
    } else {
        None
    };
    if sensor {
        let g = SensorGeometry::new(&design);
        // The 3-D slab is centred on the die: its sphere's place on the die.
        let centre3d = face3d.as_ref().map(|f| {
            let w_um = f.y_m.last().copied().unwrap_or(0.0) * 1e6;
            (
                0.5 * (g.length_um - a.width_mm * 1e3) + slab.centre_x_m * 1e6,
                0.5 * (g.width_um - w_um) + a.y_mm.map_or(0.5 * w_um, |y| y * 1e3),
            )
        });
        let mm = |v: &[f64]| v.iter().map(|x| x * 1e-3).collect::<Vec<_>>();
        let spec = Spec {
            slab,
            elements: (usize::from(a.across), usize::from(a.through)),
            shape: match a.shape {
                ShapeArg::Sphere => Shape::Sphere,
                ShapeArg::Cylinder => Shape::Cylinder,
                ShapeArg::RotatedSection => Shape::RotatedSection,
            },
            centre_um: centre3d.unwrap_or((
                a.x_mm.map_or(0.5 * g.length_um, |x| x * 1e3),
                a.y_mm.map_or(0.5 * g.width_um, |y| y * 1e3),
            )),
            face3d: face3d.clone(),
            cell_um: a.cell_mm * 1e3,
            accuracy: Accuracy::new(a.tol, usize::from(a.max_levels)).with_model(a.model.into()),
            full_scenes: true,
            noise_mv: a.noise_mv,
            threshold_snr: a.snr,
            locate: a.locate.then_some(a.seed),
            vessel: a.vessel.then(|| {
                let mut p = Pulse::default_pulse();
                p.freq_hz = a.pulse_hz;
                p.mean_pa = a.mean_mmhg * PA_PER_MMHG;
                p.amplitude_pa = 0.5 * a.pulse_mmhg * PA_PER_MMHG;
                (p, design.process.readout.clone())
            }),
            map: a.detectability.then(|| {
                (
                    mm(&a.map_radii_mm),
                    mm(&a.map_heights_mm),
                    a.map_stiffness.clone(),
                )
            }),
        };
        let s = through_sensor(&g, &spec)?;
        files.push(("through-sensor.csv".into(), s.csv().into_bytes()));
        if let Some(c) = s.full_csv() {
            files.push(("through-sensor-full.csv".into(), c.into_bytes()));
        }
        files.push(("face-pressure.csv".into(), s.face_csv().into_bytes()));
        files.push(("through-sensor.svg".into(), s.svg().into_bytes()));
        let (u, lp) = (&s.grid, &s.linear);
        after.push(format!(
            "through the sensor on the linear plate ({}): {} x {} cells of {} x {} mm ({} \
             levels, {} dofs, discretisation error {}); the feature at x {} mm, y {} mm as a {}",
            if lp.unit_responses {
                "each cell's unit response, superposed"
            } else {
                "the background and the feature as two patches scenes of one batch"
            },
            u.nx,
            u.ny,
            f(u.size_um().0 * 1e-3, 3),
            f(u.size_um().1 * 1e-3, 3),
            lp.levels,
            lp.dofs,
            lp.discretisation
                .map_or_else(|| "not estimated".into(), |e| format!("{e:.1e}")),
            f(spec.centre_um.0 * 1e-3, 2),
            f(spec.centre_um.1 * 1e-3, 2),
            match spec.shape {
                _ if spec.face3d.is_some() =>
                    "sphere in the 3-D slab (P0(x, y) and P(x, y) from it)",
                Shape::Sphere => "sphere (axisymmetric: on the axis of a tissue cylinder)",
                Shape::Cylinder => "cylinder across the jaw",
                Shape::RotatedSection =>
                    "sphere (the section's disturbance rotated about its centre)",
            }
        ));
        after.push(format!(
            "  the grasp puts {} N on the die; the linear plate's membrane (model) error at that \
             force, as a uniform pressure: {}",
            f(s.background_force_n, 3),
            s.model_error_at_load
                .map_or_else(|| "not estimated".into(), |e| format!("{e:.1e}"))
        ));
        after.push("  electrode   background_mv   feature_mv   difference_mv".into());
        for (i, e) in s.electrodes.iter().enumerate() {
            let (b, w) = (s.background_mv[i], s.feature_mv[i]);
            after.push(format!(
                "  {e:<9} {:>15} {:>12} {:>15}",
                f(b, 3),
                f(w, 3),
                f(w - b, 3)
            ));
        }
        if let Some(fs) = &s.scenes {
            let rung = |x: &tactfab::hidden::scenes::SceneAnswer| {
                format!(
                    "{} ({} levels, {} dofs; error: discretisation {}, model {})",
                    x.rung,
                    x.levels,
                    x.dofs,
                    x.error
                        .discretisation
                        .map_or_else(|| "not estimated".into(), |e| format!("{e:.1e}")),
                    match (x.error.model, x.rung) {
                        (Some(e), _) => format!("{e:.1e}"),
                        (None, tactfab::sensor::ModelKind::LargeDeflectionPlate) => {
                            "none above it on the ladder".into()
                        }
                        _ => "not estimated".into(),
                    }
                )
            };
            after.push(format!(
                "  full scenes (--model {}): the background on the {}, with the feature on the {}",
                fs.model,
                rung(&fs.background),
                rung(&fs.feature)
            ));
            after.push(
                "  electrode   background_mv   feature_mv   difference_mv   minus superposition \
                 (background, feature)"
                    .into(),
            );
            let d = fs.difference_mv();
            for (i, e) in s.electrodes.iter().enumerate() {
                after.push(format!(
                    "  {e:<9} {:>15} {:>12} {:>15}   {}, {}",
                    f(fs.background.voltages_mv[i], 3),
                    f(fs.feature.voltages_mv[i], 3),
                    f(d[i], 3),
                    f(fs.background.minus_superposition_mv[i], 3),
                    f(fs.feature.minus_superposition_mv[i], 3)
                ));
            }
        }
        if let Some(l) = &s.located {
            after.push(format!(
                "  inverse on the linear plate's superposition (dV + {} mV noise, seed {}): {} at x {} mm{}, SNR {} (threshold {}), \
                 amplitude {} of the reference, residual {} mV rms",
                f(a.noise_mv, 3),
                a.seed,
                match l.verdict {
                    Verdict::Lump => "lump",
                    Verdict::Void => "void",
                    Verdict::NoneDetected => "none detected (best fit)",
                },
                f(l.x_um * 1e-3, 2),
                l.y_um
                    .map_or_else(String::new, |y| format!(", y {} mm", f(y * 1e-3, 2))),
                f(l.snr, 2),
                f(a.snr, 2),
                f(l.amplitude, 3),
                f(l.residual_mv, 3)
            ));
            if let (Some((x, y)), Some(d)) = (l.alternative, l.delta_chi2) {
                after.push(format!(
                    "  ambiguous: {}; the best fit in the other half along the jaw is at x {} \
                     mm{}, Delta chi^2 {} (threshold {})",
                    l.ambiguous,
                    f(x * 1e-3, 2),
                    y.map_or_else(String::new, |y| format!(", y {} mm", f(y * 1e-3, 2))),
                    f(d, 2),
                    f(tactfab::hidden::locate::AMBIGUITY_CHI2, 1)
                ));
            }
        }
        if let Some(v) = &s.vessel {
            files.push(("vessel.csv".into(), v.csv().into_bytes()));
            files.push(("vessel-readout.csv".into(), v.readout_csv().into_bytes()));
            files.push(("vessel.svg".into(), v.svg().into_bytes()));
            let m2 = v.electrodes.iter().position(|e| e == "M2").unwrap_or(0);
            let ch = &v.channels[m2];
            let swing = |xs: &[f64]| {
                xs.iter().fold(f64::MIN, |a, &b| a.max(b))
                    - xs.iter().fold(f64::MAX, |a, &b| a.min(b))
            };
            let qs: Vec<f64> = v.instants.iter().map(|i| i.2[m2]).collect();
            let err = |x: &tactfab::hidden::scenes::SceneAnswer| {
                format!(
                    "discretisation {}, model {}",
                    x.error
                        .discretisation
                        .map_or_else(|| "not estimated".into(), |e| format!("{e:.1e}")),
                    x.error
                        .model
                        .map_or_else(|| "not estimated".into(), |e| format!("{e:.1e}"))
                )
            };
            after.push(format!(
                "  vessel on the linear plate: the grasp (vessel at 0 Pa) and 1 Pa in the vessel as \
                 two patches scenes of one batch ({} levels, {} dofs; errors: grasp {}; per pascal \
                 {}){}",
                v.grasp.levels.max(v.unit.levels),
                v.grasp.dofs.max(v.unit.dofs),
                err(&v.grasp),
                err(&v.unit),
                if v.auto_climbs {
                    format!(
                        "; the grasp's model error is over --tol {}: auto answers the grasp on the \
                         large-deflection plate (the full scenes above), the vessel's small-signal \
                         part is the linear plate's",
                        f(v.tol_rel, 3)
                    )
                } else {
                    String::new()
                }
            ));
            after.push(format!(
                "  vessel: {} Hz, {} +/- {} mmHg; {} instants per cycle: {} {} mV at vessel \
                 pressure 0, {} mV per kPa, swinging {} mV peak to peak (quasi-static); through \
                 the {} (tau {} s, corner {} Hz): {} mV peak to peak in the last cycle",
                f(v.pulse.freq_hz, 3),
                f(v.pulse.mean_pa / PA_PER_MMHG, 1),
                f(v.pulse.amplitude_pa / PA_PER_MMHG, 1),
                v.instants.len(),
                v.electrodes[m2],
                f(v.grasp_mv[m2], 3),
                f(v.per_pa_mv[m2] * 1e3, 4),
                f(swing(&qs), 3),
                v.amplifier.name(),
                f(ch.tau_s, 4),
                f(ch.corner_hz, 4),
                f(
                    1e3 * swing(
                        &ch.voltage_v[ch.voltage_v.len()
                            - ((1.0 / (v.pulse.freq_hz * v.pulse.dt_s)).round() as usize)
                                .min(ch.voltage_v.len())..]
                    ),
                    3
                )
            ));
            after.push(format!(
                "  quasi-static: the plate's first natural frequency {} Hz is {}x the pulse; the \
                 tissue is taken as elastic (its viscoelastic relaxation is not modelled), and \
                 at these pressures a bare void strains 20 kPa tissue far beyond the linear range: \
                 the magnitudes are the linear model's",
                f(v.f1_hz, 0),
                f(v.f1_over_pulse, 0)
            ));
        }
        if let Some(m) = &s.map {
            files.push(("detectability.csv".into(), m.csv().into_bytes()));
            files.push(("detectability.svg".into(), m.svg().into_bytes()));
            after.push(format!(
                "  detectability (linear plate, superposed) at {} mV per channel, SNR {} ({} lumps, {} that do not fit \
                 skipped): smallest detectable radius (mm) by height of the centre (mm)",
                f(a.noise_mv, 3),
                f(a.snr, 2),
                m.rows.len(),
                m.skipped
            ));
            for &k in &m.spec.stiffness_ratios {
                let line: Vec<String> = m
                    .smallest
                    .iter()
                    .filter(|w| w.0 == k)
                    .map(|w| {
                        format!(
                            "{}: {}",
                            f(w.1 * 1e3, 2),
                            w.2.map_or_else(|| "-".into(), |r| f(r * 1e3, 2))
                        )
                    })
                    .collect();
                after.push(format!("    E ratio {}: {}", f(k, 2), line.join(", ")));
            }
        }
    }
    write_dir(&a.out, &files, a.replace, &a.process)?;
    println!(
        "tissue {} x {} mm, E {} kPa, nu 0.49, squeezed {} %; {} of radius {} mm at x {} mm, {} mm \
         above the sensor; {} x {} Q2/P1 elements",
        f(a.width_mm, 2),
        f(a.thickness_mm, 2),
        f(a.tissue_e_kpa, 3),
        f(100.0 * a.compression, 1),
        match a.feature {
            FeatureArg::Lump => format!("lump (E {} kPa, nu 0.4)", f(a.lump_e_kpa, 3)),
            FeatureArg::Void => "void".to_string(),
        },
        f(a.radius_mm, 2),
        f(slab.centre_x_m * 1e3, 2),
        f(a.height_mm, 2),
        a.across,
        a.through
    );
    println!(
        "  P / P0 on the sensor face: up to {} at x {} mm, down to {} at x {} mm (P0 {} kPa at \
         the middle)",
        f(p.peak_ratio, 3),
        f(p.peak_x_m * 1e3, 2),
        f(p.min_ratio, 3),
        f(p.min_x_m * 1e3, 2),
        f(p.p0_pa[p.p0_pa.len() / 2] * 1e-3, 3)
    );
    for line in after {
        println!("{line}");
    }
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    println!("wrote {} into {}", names.join(", "), a.out.display());
    Ok(Outcome::Ok)
}

/// `--slab 3d`: the block across the jaw with its sphere, and the lines to print. Bad sizes
/// name the flags.
fn block(
    a: &TissueArgs,
    slab: &Slab,
    g: &SensorGeometry,
) -> anyhow::Result<(FaceField, Vec<String>)> {
    let w_mm = a.jaw_width_mm.unwrap_or(g.width_um * 1e-3);
    let y_mm = a.y_mm.unwrap_or(0.5 * w_mm);
    let s = Slab3d::from_slab(slab, w_mm * 1e-3, y_mm * 1e-3);
    let mesh = Mesh3d {
        near_m: a.near_mm * 1e-3,
        far_m: a.far_mm * 1e-3,
    };
    let face = face_field(&s, &mesh).map_err(|e| match e {
        tactfab::softness::SoftnessError::BadInput { field, hint, .. } => anyhow::anyhow!(
            "{}: {hint} (--slab 3d: --width-mm {} along, --jaw-width-mm {} across, \
             --thickness-mm {}; sphere --x-mm {}, --y-mm {}, --height-mm {}, --radius-mm {})",
            match field {
                "radius_m" => "--radius-mm",
                "lump e_pa" => "--lump-e-kpa",
                "compression" => "--compression",
                "tissue_e_pa" => "--tissue-e-kpa",
                "mesh near_m" | "elements" => "--near-mm / --far-mm",
                "width_m" => "--jaw-width-mm",
                _ => "the slab",
            },
            f(a.width_mm, 2),
            f(w_mm, 2),
            f(a.thickness_mm, 2),
            f(slab.centre_x_m * 1e3, 2),
            f(y_mm, 2),
            f(a.height_mm, 2),
            f(a.radius_mm, 2)
        ),
        other => other.into(),
    })?;
    let (lx, ly) = (s.length_m, s.width_m);
    let mid = face.p0_at_pa(0.5 * lx, 0.5 * ly);
    let lines = vec![
        format!(
            "3-D slab {} x {} x {} mm (along x across x thick; free sides), sphere at x {} mm, y \
             {} mm: {} x {} x {} Q2/P1 bricks ({} unknowns{}), near {} mm, far {} mm",
            f(lx * 1e3, 2),
            f(ly * 1e3, 2),
            f(s.thickness_m * 1e3, 2),
            f(slab.centre_x_m * 1e3, 2),
            f(y_mm, 2),
            face.elements[0],
            face.elements[1],
            face.elements[2],
            face.unknowns,
            match face.mirrored {
                [true, true] => ", a quarter by symmetry",
                [true, false] | [false, true] => ", a half by symmetry",
                [false, false] => "",
            },
            f(a.near_mm, 3),
            f(a.far_mm, 3)
        ),
        format!(
            "  3-D P / P0: up to {} at ({}, {}) mm, down to {} at ({}, {}) mm; P0 {} kPa at the \
             middle, {} kPa at the jaw's edge (y = 0) and {} kPa at the slab's end (x = 0) on \
             the middle lines",
            f(face.peak_ratio, 3),
            f(face.peak_at_m[0] * 1e3, 2),
            f(face.peak_at_m[1] * 1e3, 2),
            f(face.min_ratio, 3),
            f(face.min_at_m[0] * 1e3, 2),
            f(face.min_at_m[1] * 1e3, 2),
            f(mid * 1e-3, 3),
            f(face.p0_at_pa(0.5 * lx, 0.0) * 1e-3, 3),
            f(face.p0_at_pa(0.0, 0.5 * ly) * 1e-3, 3)
        ),
    ];
    Ok((face, lines))
}
