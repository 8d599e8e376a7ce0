//! `tactfab tissue FILE -o DIR`: the contact pressure a hidden lump or void puts on the sensor face
//! ([`tactfab::softness::inclusion`]), its P / P0 peak, and `DIR/tissue.csv` + `DIR/tissue.svg`.

use tactfab::softness::inclusion::{pressure_profile, Feature, Slab};

use super::args::{FeatureArg, TissueArgs};
use super::output::f;
use super::{design, write_dir, Outcome};

pub fn run(a: &TissueArgs) -> anyhow::Result<Outcome> {
    // The process file is validated (and names the output) as for every study.
    let _ = design(&a.process)?;
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
    let files = [
        ("tissue.csv".to_string(), p.csv().into_bytes()),
        ("tissue.svg".to_string(), p.svg(&slab).into_bytes()),
    ];
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
    println!(
        "wrote {} and {}",
        a.out.join("tissue.csv").display(),
        a.out.join("tissue.svg").display()
    );
    Ok(Outcome::Ok)
}
