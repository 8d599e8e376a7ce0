//! Value parsers: every flag's value is checked here, with its range, so clap reports a bad one
//! as `error: invalid value '…' for '--flag <…>': what was expected` (exit 2) and no command
//! sees NaN, a zero step or a size that would exhaust the machine. The bounds are documented in
//! each flag's help.

/// A value with the reason it was refused (clap prefixes the flag and the value).
type Parsed<T> = Result<T, String>;

fn number(s: &str) -> Parsed<f64> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a number, got `{s}`"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("expected a finite number, got `{s}`"))
    }
}

fn within(s: &str, lo: f64, hi: f64, what: &str) -> Parsed<f64> {
    let v = number(s)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("expected {what} in [{lo}, {hi}], got {v}"))
    }
}

fn numbers(s: &str, n: std::ops::RangeInclusive<usize>, form: &str) -> Parsed<Vec<f64>> {
    let v: Vec<f64> = s.split(',').map(number).collect::<Result<_, _>>()?;
    if n.contains(&v.len()) {
        Ok(v)
    } else {
        Err(format!("expected {form}"))
    }
}

/// Largest electrode voltage `locate` reads (mV): a kilovolt is far beyond any PVDF charge
/// amplifier's output, so a larger value is a typo or a unit slip.
pub const MAX_VOLTAGE_MV: f64 = 1e6;

/// An electrode voltage in mV, within +/- [`MAX_VOLTAGE_MV`].
pub fn voltage_mv(s: &str) -> Parsed<f64> {
    let v = number(s)?;
    if v.abs() <= MAX_VOLTAGE_MV {
        Ok(v)
    } else {
        Err(format!(
            "expected a voltage in mV within +/- {MAX_VOLTAGE_MV:e}, got {v}"
        ))
    }
}

/// A relative tolerance in (0, 1).
pub fn tolerance(s: &str) -> Parsed<f64> {
    let v = number(s)?;
    if v > 0.0 && v < 1.0 {
        Ok(v)
    } else {
        Err(format!(
            "expected a relative error between 0 and 1 (exclusive), e.g. 0.01, got {v}"
        ))
    }
}

/// Largest force a load may carry (N): far beyond fracture of any plate tactfab models, small
/// enough that nothing overflows.
pub const MAX_FORCE_N: f64 = 1000.0;

/// A force in N, either sign, 0 < |F| <= [`MAX_FORCE_N`], as the process file's scenes: a zero
/// load has no sensitivity, safety factor or load limit to report.
pub fn force_n(s: &str) -> Parsed<f64> {
    let v = within(s, -MAX_FORCE_N, MAX_FORCE_N, "a force in N")?;
    if v == 0.0 {
        Err(format!(
            "expected a non-zero force in N, |F| in (0, {MAX_FORCE_N}], got 0"
        ))
    } else {
        Ok(v)
    }
}

/// A distributed load pressing on the tissue (N), 1 mN to [`MAX_FORCE_N`]: the softness study
/// reads E_t from voltage / force, which a zero force leaves undefined.
pub fn pressing_force_n(s: &str) -> Parsed<f64> {
    within(s, 1e-3, MAX_FORCE_N, "a pressing force in N")
}

/// Seconds since 1970 up to the end of year 9999 (the GDS header stores the year in 16 bits;
/// four-digit years keep every reader happy).
pub fn source_date_epoch(s: &str) -> Parsed<i64> {
    let v: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected whole seconds since 1970, got `{s}`"))?;
    const END_OF_9999: i64 = 253_402_300_799;
    if (0..=END_OF_9999).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "expected seconds in [0, {END_OF_9999}] (years 1970-9999), got {v}"
        ))
    }
}

/// A calibration grid spacing: 0.1-30 mm (a finer grid is millions of FE loads).
pub fn grid_step_mm(s: &str) -> Parsed<f64> {
    within(s, 0.1, 30.0, "a grid step in mm")
}

/// The etch simulation's grid step: 1-50 um.
pub fn sim_grid_um(s: &str) -> Parsed<f64> {
    within(s, 1.0, 50.0, "a grid step in um")
}

/// A contact radius: 0.01-5 mm.
/// A slab dimension or feature size, 0.01-1000 mm.
pub fn length_mm(s: &str) -> Parsed<f64> {
    within(s, 0.01, 1000.0, "a length in mm")
}

/// A tissue or lump modulus, 0.001-1e9 kPa.
pub fn modulus_kpa(s: &str) -> Parsed<f64> {
    within(s, 0.001, 1e9, "a modulus in kPa")
}

/// A pressure-cell side, 0.25-30 mm.
pub fn cell_mm(s: &str) -> Parsed<f64> {
    within(s, 0.25, 30.0, "a cell side in mm")
}

/// A noise level that can divide: 1e-6-1e4 mV.
pub fn positive_noise_mv(s: &str) -> Parsed<f64> {
    within(s, 1e-6, 1e4, "a noise level in mV")
}

/// A detection threshold, 0.1-100 (SNR).
pub fn snr(s: &str) -> Parsed<f64> {
    within(s, 0.1, 100.0, "a signal-to-noise ratio")
}

/// A lump's stiffness over the tissue's, 1e-3-1e6.
pub fn stiffness_ratio(s: &str) -> Parsed<f64> {
    within(s, 1e-3, 1e6, "a stiffness ratio E_lump / E_tissue")
}

/// A pulse rate, 0.01-100 Hz.
pub fn pulse_hz(s: &str) -> Parsed<f64> {
    within(s, 0.01, 100.0, "a pulse rate in Hz")
}

/// A vessel pressure, 0-1000 mmHg.
pub fn mmhg(s: &str) -> Parsed<f64> {
    within(s, 0.0, 1000.0, "a pressure in mmHg")
}

/// A compression of the slab, 0.001-0.4 of its thickness.
pub fn compression(s: &str) -> Parsed<f64> {
    within(s, 0.001, 0.4, "a fraction of the thickness")
}

pub fn contact_radius_mm(s: &str) -> Parsed<f64> {
    within(s, 0.01, 5.0, "a contact radius in mm")
}

/// An ad-hoc point load of `fe --point`, in die coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLoad {
    pub x_mm: f64,
    pub y_mm: f64,
    pub force_n: f64,
    pub radius_mm: f64,
}

/// Contact radius of `--point` when the fourth value is left out (mm).
pub const POINT_RADIUS_MM: f64 = 0.25;

/// `X_MM,Y_MM,FORCE_N[,RADIUS_MM]`.
pub fn point_load(s: &str) -> Parsed<PointLoad> {
    let v = numbers(s, 3..=4, "X_MM,Y_MM,FORCE_N[,RADIUS_MM] (3 or 4 numbers)")?;
    let force_n = force_n(&v[2].to_string())?;
    let radius_mm = match v.get(3) {
        Some(r) => contact_radius_mm(&r.to_string())?,
        None => POINT_RADIUS_MM,
    };
    Ok(PointLoad {
        x_mm: v[0],
        y_mm: v[1],
        force_n,
        radius_mm,
    })
}

/// Tissue thickness: 0.1-100 mm.
pub fn tissue_thickness_um(s: &str) -> Parsed<f64> {
    within(s, 100.0, 100_000.0, "a tissue thickness in um")
}

/// Tissue Poisson's ratio: 0-0.4999 (0.5 is incompressible: the FE takes nearly so).
pub fn tissue_nu(s: &str) -> Parsed<f64> {
    within(s, 0.0, 0.4999, "a Poisson's ratio")
}

/// Standard deviation of voltage noise: 0-10^4 mV.
pub fn noise_mv(s: &str) -> Parsed<f64> {
    within(s, 0.0, 1e4, "a noise level in mV")
}

/// `VOLTAGE_MV,FORCE_N` with a positive force.
pub fn voltage_and_force(s: &str) -> Parsed<(f64, f64)> {
    let v = numbers(s, 2..=2, "VOLTAGE_MV,FORCE_N, e.g. 12.5,3")?;
    if v[1] > 0.0 && v[1] <= MAX_FORCE_N {
        Ok((v[0], v[1]))
    } else {
        Err(format!(
            "expected a force in (0, {MAX_FORCE_N}] N, got {}",
            v[1]
        ))
    }
}

/// An angle step that divides 180: 1-90 deg.
pub fn angle_step_deg(s: &str) -> Parsed<f64> {
    let v = within(s, 1.0, 90.0, "an angle step in deg")?;
    let k = 180.0 / v;
    if (k - k.round()).abs() > 1e-9 {
        return Err(format!(
            "expected a step that divides 180 (e.g. 10, 15, 30), got {v}"
        ));
    }
    Ok(v)
}

/// `LO,HI,N`: N values from LO to HI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
}

fn range(s: &str, n_min: usize, n_max: usize, eg: &str) -> Parsed<Range> {
    let form = format!("LO,HI,N with 0 < LO <= HI and N in [{n_min}, {n_max}], e.g. {eg}");
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("expected {form}"));
    }
    let (lo, hi) = (number(parts[0])?, number(parts[1])?);
    let n: usize = parts[2]
        .trim()
        .parse()
        .map_err(|_| format!("expected {form}: N is a whole number"))?;
    if !(lo > 0.0 && hi >= lo && (n_min..=n_max).contains(&n)) {
        return Err(format!("expected {form}"));
    }
    Ok(Range { lo, hi, n })
}

/// `r` with LO and HI in [`lo`, `hi`] (unit `unit`).
fn bounded(r: Range, lo: f64, hi: f64, unit: &str) -> Parsed<Range> {
    if r.lo >= lo && r.hi <= hi {
        Ok(r)
    } else {
        Err(format!(
            "expected LO and HI within [{lo:e}, {hi:e}] {unit}, got {:e},{:e}",
            r.lo, r.hi
        ))
    }
}

/// Tissue modulus range (Pa, log spaced): 2-200 points, LO < HI, within 1 Pa - 1 TPa (gels to
/// diamond).
pub fn modulus_range_pa(s: &str) -> Parsed<Range> {
    let r = bounded(range(s, 2, 200, "1e4,1e8,17")?, 1.0, 1e12, "Pa")?;
    if r.hi > r.lo {
        Ok(r)
    } else {
        Err("expected LO < HI".into())
    }
}

/// Most steps on one sweep axis; the whole sweep is bounded again by the library.
pub const MAX_SWEEP_STEPS: usize = 1000;

/// One sweep axis (um): 1-[`MAX_SWEEP_STEPS`] steps, values within 1 um - 1 m.
pub fn sweep_range_um(s: &str) -> Parsed<Range> {
    bounded(
        range(s, 1, MAX_SWEEP_STEPS, "10000,40000,30")?,
        1.0,
        1e6,
        "um",
    )
}

/// A die coordinate in mm, 0-1000 (whether it is on the plate is the sensor's check).
pub fn position_mm(s: &str) -> Parsed<f64> {
    within(s, 0.0, 1000.0, "a die coordinate in mm")
}

/// A read-out sample step: 1 us - 1 s, in ms.
pub fn dt_ms(s: &str) -> Parsed<f64> {
    within(s, 0.001, 1000.0, "a time step in ms")
}

/// A read-out record length: 1 ms - 1 h, in s.
pub fn duration_s(s: &str) -> Parsed<f64> {
    within(s, 0.001, 3600.0, "a duration in s")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_would_crash_or_run_away() {
        assert!(tolerance("0").is_err() && tolerance("1").is_err() && tolerance("NaN").is_err());
        assert_eq!(tolerance("0.01"), Ok(0.01));
        assert!(grid_step_mm("0").is_err() && grid_step_mm("NaN").is_err());
        assert!(grid_step_mm("1e9").is_err() && grid_step_mm("0.000001").is_err());
        assert!(sweep_range_um("10000,40000,1000000000").is_err());
        assert!(angle_step_deg("0.001").is_err() && angle_step_deg("7").is_err());
        assert_eq!(angle_step_deg("15"), Ok(15.0));
        assert!(source_date_epoch("9999999999999").is_err());
        assert!(point_load("1,2").is_err() && point_load("1,2,nan").is_err());
        assert!(point_load("1,2,3,1e9").is_err());
        let p = point_load("10,5,1").unwrap();
        assert_eq!(p.radius_mm, POINT_RADIUS_MM);
        assert!(voltage_and_force("3,0").is_err());
        assert!(modulus_range_pa("1e8,1e4,5").is_err());
        assert!(modulus_range_pa("1e-300,1e300,2").is_err());
        assert!(sweep_range_um("1e300,1e300,1").is_err());
    }
}
