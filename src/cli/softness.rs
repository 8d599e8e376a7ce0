//! `tactfab softness FILE`: middle-electrode voltage against the tissue modulus (paper 001 Fig. 24)
//! from the composite beam (Eq. 7-12) and the tissue FE side by side, their disagreement, cost and
//! the FE's discretisation error; optionally E_t from a measured voltage and force (`--invert`).
//! Writes `DIR/softness.csv` and `DIR/softness.svg` with `-o DIR`. Times (terminal only) are wall
//! clock.

use std::time::Instant;

use anyhow::{bail, Context};
use tactfab::export::write_atomic;
use tactfab::fe::richardson;
use tactfab::softness::{
    composite_beam,
    inverse::invert,
    plot::softness_svg,
    tissue_fe::{TissueEnds, TissueMesh, TissueModel},
    SoftnessSetup,
};

use super::{electrodes, load, Outcome, SoftnessArgs};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

pub fn run(a: &SoftnessArgs) -> anyhow::Result<Outcome> {
    let loaded = load(&a.process)?;
    let p = &loaded.process;
    let plan = tactfab::etch::plan(p);
    let g = tactfab::sensor::SensorGeometry::new(p, &plan, electrodes(p, &plan)?);
    let setup = SoftnessSetup::from_sensor(&g, a.tissue_thickness_um, a.tissue_nu)?;
    let (e_lo, e_hi, n) = parse_range(&a.e_range_pa)?;
    if a.forces_n.is_empty() || a.forces_n.iter().any(|f| !(*f > 0.0 && f.is_finite())) {
        bail!("--forces-n: expected positive forces in N, e.g. 1,2,3,4,5");
    }
    let es: Vec<f64> = (0..n)
        .map(|k| {
            if n == 1 {
                e_lo
            } else {
                e_lo * (e_hi / e_lo).powf(k as f64 / (n - 1) as f64)
            }
        })
        .collect();

    let t = Instant::now();
    let fe = TissueModel::new(&setup, TissueMesh::standard())?;
    let assemble_ms = t.elapsed().as_secs_f64() * 1e3;
    let (mut fe_ms, mut cb_us) = (Vec::new(), Vec::new());
    let mut rows = Vec::new(); // (E, V_fe per N, V_cb per N)
    for &e in &es {
        let t = Instant::now();
        let vf = fe.voltage_v(e, 1.0)?;
        fe_ms.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        let mut vc = 0.0;
        for _ in 0..1000 {
            vc = std::hint::black_box(composite_beam::voltage_v(
                std::hint::black_box(&setup),
                e,
                1.0,
            ));
        }
        cb_us.push(t.elapsed().as_secs_f64() * 1e3);
        rows.push((e, vf, vc));
    }

    let mut out = String::new();
    out.push_str(&format!(
        "softness: electrode {} over s = {:.3}-{:.3} mm of the {:.3} mm span, plate {} um (Q22 \
         {:.2} GPa), tissue {} um, nu {} ({}), load over {:.1} x {:.1} mm\n",
        setup.electrode_name,
        setup.electrode_s0_m * 1e3,
        setup.electrode_s1_m * 1e3,
        setup.span_m * 1e3,
        setup.plate_thickness_m * 1e6,
        setup.plate_modulus_pa * 1e-9,
        a.tissue_thickness_um,
        a.tissue_nu,
        if a.tissue_thickness_um == tactfab::softness::TISSUE_THICKNESS_UM {
            "thickness [choice]: paper 001 gives none"
        } else {
            "thickness from --tissue-thickness-um"
        },
        setup.span_m * 1e3,
        setup.loaded_length_m * 1e3
    ));
    out.push_str(&format!("{:>12}", "E_t_pa"));
    for f in &a.forces_n {
        out.push_str(&format!(
            " {:>11} {:>11}",
            format!("fe_{f}N_mv"),
            format!("cb_{f}N_mv")
        ));
    }
    out.push_str(&format!(" {:>10}\n", "cb/fe-1"));
    for &(e, vf, vc) in &rows {
        out.push_str(&format!("{e:>12.4e}"));
        for f in &a.forces_n {
            out.push_str(&format!(" {:>11.4} {:>11.4}", 1e3 * f * vf, 1e3 * f * vc));
        }
        out.push_str(&format!(" {:>9.1}%\n", 100.0 * (vc / vf - 1.0)));
    }
    let worst = rows
        .iter()
        .map(|r| (r.2 / r.1 - 1.0).abs())
        .fold(0.0, f64::max);
    out.push_str(&format!(
        "disagreement composite beam vs FE: up to {:.1} % over the range (both linear in F, so \
         the same for every force)\n",
        100.0 * worst
    ));
    // The composite beam builds the whole section in at the supports; the FE above clamps only the
    // plate. With the tissue's end faces clamped too, the FE tests the beam model's other
    // assumptions.
    let clamped = TissueModel::with_ends(&setup, TissueMesh::standard(), TissueEnds::Clamped)?;
    let mut worst_c: f64 = 0.0;
    for &(e, _, vc) in &rows {
        worst_c = worst_c.max((vc / clamped.voltage_v(e, 1.0)? - 1.0).abs());
    }
    out.push_str(&format!(
        "with the tissue's ends clamped as the composite beam assumes: disagreement up to {:.1} % \
         (plane sections fail in a {:.1} mm deep layer on a {:.1} mm span; the bonded base \
         restrains the nu = {} tissue's bulging)\n",
        100.0 * worst_c,
        setup.tissue_thickness_m * 1e3,
        setup.span_m * 1e3,
        setup.tissue_nu
    ));
    out.push_str(&format!(
        "cost: FE {} unknowns (Q2/P1 B-bar {} x {} + frame), assembly + symbolic {:.1} ms, {:.2} \
         ms per E (median, numeric Cholesky + solve); composite beam {:.3} us per E\n",
        fe.n_unknowns,
        TissueMesh::standard().across,
        TissueMesh::standard().through,
        assemble_ms,
        median(fe_ms),
        median(cb_us)
    ));

    // Discretisation error of the FE (three nested meshes around the standard one).
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
    .map(|m| TissueModel::new(&setup, m))
    .collect::<Result<_, _>>()?;
    for e in [e_lo, (e_lo * e_hi).sqrt(), e_hi] {
        let v: Vec<f64> = levels
            .iter()
            .map(|m| m.voltage_v(e, 1.0))
            .collect::<Result<_, _>>()?;
        let r = richardson(v[0], v[1], v[2], 2.0);
        let rel = (v[1] - r.extrapolated).abs().max(r.error_estimate) / r.extrapolated.abs();
        out.push_str(&format!(
            "FE error at E_t = {e:.3e} Pa: {:.4} % (meshes 20x6, 40x12, 80x24; {:?})\n",
            100.0 * rel,
            r.kind
        ));
    }

    // Round trip of the inverse on the FE curve, and the requested inversion.
    let (e_true, f_true) = ((e_lo * e_hi).sqrt(), a.forces_n[a.forces_n.len() / 2]);
    let v_meas = fe.voltage_v(e_true, f_true)?;
    let mut g_fe = |e: f64| fe.voltage_v(e, 1.0);
    let back = invert(&mut g_fe, v_meas / f_true, e_lo, e_hi, 1e-7)?;
    out.push_str(&format!(
        "inverse round trip (FE): E_t {e_true:.4e} Pa at {f_true} N -> {:.3} mV -> E_t {:.4e} Pa \
         ({:.1e} relative, {} FE solves); d ln E / d ln V = {:.2} there\n",
        1e3 * v_meas,
        back.tissue_e_pa,
        (back.tissue_e_pa / e_true - 1.0).abs(),
        back.evaluations,
        back.e_rel_per_v_rel
    ));
    if let Some(text) = &a.invert {
        let (vm, fnn) = text
            .split_once(',')
            .and_then(|(v, f)| Some((v.trim().parse::<f64>().ok()?, f.trim().parse::<f64>().ok()?)))
            .filter(|(_, f)| *f > 0.0)
            .context("--invert: expected VOLTAGE_MV,FORCE_N with a positive force, e.g. 12.5,3")?;
        let fe_inv = invert(&mut g_fe, vm * 1e-3 / fnn, e_lo, e_hi, 1e-7)?;
        let mut g_cb = |e: f64| Ok(composite_beam::voltage_v(&setup, e, 1.0));
        let cb_inv = invert(&mut g_cb, vm * 1e-3 / fnn, e_lo, e_hi, 1e-9);
        out.push_str(&format!(
            "invert {vm} mV at {fnn} N: FE E_t = {:.4e} Pa (1 % in V -> {:.1} % in E)",
            fe_inv.tissue_e_pa, fe_inv.e_rel_per_v_rel
        ));
        match cb_inv {
            Ok(c) => out.push_str(&format!(
                ", composite beam E_t = {:.4e} Pa\n",
                c.tissue_e_pa
            )),
            Err(e) => out.push_str(&format!(", composite beam: {e}\n")),
        }
    }
    print!("{out}");

    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let mut csv = String::from(
            "tissue_e_pa,force_n,fe_voltage_mv,composite_voltage_mv,composite_over_fe_minus_1\n",
        );
        let mut curves = Vec::new();
        for f in &a.forces_n {
            for &(e, vf, vc) in &rows {
                csv.push_str(&format!(
                    "{e:.6e},{f:.3},{:.6},{:.6},{:.6}\n",
                    1e3 * f * vf,
                    1e3 * f * vc,
                    vc / vf - 1.0
                ));
            }
            curves.push((
                format!("FE {f} N"),
                rows.iter().map(|r| (r.0, 1e3 * f * r.1)).collect(),
                true,
            ));
            curves.push((
                format!("composite beam {f} N"),
                rows.iter().map(|r| (r.0, 1e3 * f * r.2)).collect(),
                false,
            ));
        }
        write_atomic(&dir.join("softness.csv"), csv.as_bytes())?;
        write_atomic(&dir.join("softness.svg"), softness_svg(&curves).as_bytes())?;
        println!(
            "wrote {} and {}",
            dir.join("softness.csv").display(),
            dir.join("softness.svg").display()
        );
    }
    Ok(Outcome::Ok)
}

fn parse_range(text: &str) -> anyhow::Result<(f64, f64, usize)> {
    let v: Vec<&str> = text.split(',').collect();
    let bad = || {
        anyhow::anyhow!(
            "--e-range-pa '{text}': expected LO,HI,POINTS with 0 < LO < HI and POINTS >= 2 (e.g. \
             1e4,1e8,17)"
        )
    };
    if v.len() != 3 {
        return Err(bad());
    }
    let (lo, hi): (f64, f64) = (
        v[0].trim().parse().map_err(|_| bad())?,
        v[1].trim().parse().map_err(|_| bad())?,
    );
    let n: usize = v[2].trim().parse().map_err(|_| bad())?;
    if !(lo > 0.0 && hi > lo && hi.is_finite() && n >= 2) {
        return Err(bad());
    }
    Ok((lo, hi, n))
}
