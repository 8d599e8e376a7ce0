//! `tactfab softness FILE`: the softness study ([`tactfab::softness::study`]) as a table, its
//! disagreement, cost, error and inverse; `DIR/softness.csv` and `DIR/softness.svg` with `-o DIR`.
//! Times (terminal only) are wall clock.

use std::fmt::Write as _;

use tactfab::sensor::SensorGeometry;
use tactfab::softness::study::{study, Study, StudySpec};
use tactfab::softness::tissue_fe::TissueMesh;
use tactfab::softness::TISSUE_THICKNESS_UM;

use super::args::SoftnessArgs;
use super::{check_out, design, write_dir, Outcome};

pub fn run(a: &SoftnessArgs) -> anyhow::Result<Outcome> {
    let (_, design) = design(&a.process)?;
    super::warn_process_errors(&a.process, &design);
    if let Some(dir) = &a.out {
        check_out(dir, a.replace, &a.process)?;
    }
    let spec = StudySpec {
        tissue_thickness_um: a.tissue_thickness_um,
        tissue_nu: a.tissue_nu,
        forces_n: a.forces_n.clone(),
        e_lo_pa: a.e_range_pa.lo,
        e_hi_pa: a.e_range_pa.hi,
        points: a.e_range_pa.n,
        invert: a.invert,
    };
    let s = study(&SensorGeometry::new(&design), &spec)?;
    print!("{}", text(&s, a.tissue_thickness_um));
    if let Some(dir) = &a.out {
        let files = [
            ("softness.csv".to_string(), s.csv().into_bytes()),
            ("softness.svg".to_string(), s.svg().into_bytes()),
        ];
        write_dir(dir, &files, a.replace, &a.process)?;
        println!(
            "wrote {} and {}",
            dir.join("softness.csv").display(),
            dir.join("softness.svg").display()
        );
    }
    Ok(Outcome::Ok)
}

fn text(s: &Study, tissue_thickness_um: f64) -> String {
    let st = &s.setup;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "softness: electrode {} over s = {:.3}-{:.3} mm of the {:.3} mm span, plate {} um (Q22 \
         {:.2} GPa), tissue {} um, nu {} ({}), load over {:.1} x {:.1} mm",
        st.electrode_name,
        st.electrode_s0_m * 1e3,
        st.electrode_s1_m * 1e3,
        st.span_m * 1e3,
        st.plate_thickness_m * 1e6,
        st.plate_modulus_pa * 1e-9,
        tissue_thickness_um,
        st.tissue_nu,
        if tissue_thickness_um == TISSUE_THICKNESS_UM {
            "thickness [choice]: paper 001 gives none"
        } else {
            "thickness from --tissue-thickness-um"
        },
        st.span_m * 1e3,
        st.loaded_length_m * 1e3
    );
    let _ = write!(out, "{:>12}", "E_t_pa");
    for f in &s.forces_n {
        let _ = write!(
            out,
            " {:>11} {:>11}",
            format!("fe_{f}N_mv"),
            format!("cb_{f}N_mv")
        );
    }
    let _ = writeln!(out, " {:>10}", "cb/fe-1");
    for r in &s.rows {
        let _ = write!(out, "{:>12.4e}", r.tissue_e_pa);
        for f in &s.forces_n {
            let _ = write!(
                out,
                " {:>11.4} {:>11.4}",
                1e3 * f * r.fe_v_per_n,
                1e3 * f * r.composite_v_per_n
            );
        }
        let _ = writeln!(
            out,
            " {:>9.1}%",
            100.0 * (r.composite_v_per_n / r.fe_v_per_n - 1.0)
        );
    }
    let _ = writeln!(
        out,
        "disagreement composite beam vs FE: up to {:.1} % over the range (both linear in F, so \
         the same for every force)",
        100.0 * s.disagreement
    );
    let _ = writeln!(
        out,
        "with the tissue's ends clamped as the composite beam assumes: disagreement up to {:.1} % \
         (plane sections fail in a {:.1} mm deep layer on a {:.1} mm span; the bonded base \
         restrains the nu = {} tissue's bulging)",
        100.0 * s.disagreement_clamped_ends,
        st.tissue_thickness_m * 1e3,
        st.span_m * 1e3,
        st.tissue_nu
    );
    let m = TissueMesh::standard();
    let c = &s.cost;
    let _ = writeln!(
        out,
        "cost: FE {} unknowns (Q2/P1 B-bar {} x {} + frame), assembly + symbolic {:.1} ms, {:.2} \
         ms per E (median, numeric Cholesky + solve); composite beam {:.3} us per E",
        c.fe_unknowns,
        m.across,
        m.through,
        c.assemble_ms,
        c.fe_ms_per_modulus,
        c.composite_us_per_modulus
    );
    for e in &s.fe_errors {
        let _ = writeln!(
            out,
            "FE error at E_t = {:.3e} Pa: {:.4} % (meshes 20x6, 40x12, 80x24; {})",
            e.tissue_e_pa,
            100.0 * e.relative,
            e.estimate.richardson.kind
        );
    }
    let (e_true, f_true, v_mv, back) = &s.round_trip;
    let _ = writeln!(
        out,
        "inverse round trip (FE): E_t {e_true:.4e} Pa at {f_true} N -> {v_mv:.3} mV -> E_t {:.4e} \
         Pa ({:.1e} relative, {} FE solves); d ln E / d ln V = {:.2} there",
        back.tissue_e_pa,
        (back.tissue_e_pa / e_true - 1.0).abs(),
        back.evaluations,
        back.e_rel_per_v_rel
    );
    if let Some(inv) = &s.inversion {
        let _ = write!(
            out,
            "invert {} mV at {} N: FE E_t = {:.4e} Pa (1 % in V -> {:.1} % in E)",
            inv.voltage_mv, inv.force_n, inv.fe.tissue_e_pa, inv.fe.e_rel_per_v_rel
        );
        let _ = match &inv.composite {
            Ok(c) => writeln!(out, ", composite beam E_t = {:.4e} Pa", c.tissue_e_pa),
            Err(e) => writeln!(out, ", composite beam: {e}"),
        };
    }
    out
}
