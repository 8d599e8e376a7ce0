//! `tactfab orient FILE [--json] [-o DIR]`: the probe-orientation study of paper 000 (charge
//! against angle per electrode, Chebyshev and Fourier-in-2-theta fits with their condition
//! numbers, the inverse angle checked by FE re-runs, the normalised bivariate function).

use std::fmt::Write as _;

use anyhow::Context;

use tactfab::analysis::orientation::{study, Orientation, OrientationPlan};
use tactfab::report::orientation::files;
use tactfab::sensor::SensorGeometry;

use super::args::OrientArgs;
use super::output::f;
use super::{check_out, design, write_dir, Outcome};

pub fn run(args: &OrientArgs) -> anyhow::Result<Outcome> {
    let (_, design) = design(&args.process)?;
    super::warn_process_errors(&args.process, &design);
    if let Some(dir) = &args.out {
        check_out(dir, args.replace, &args.process)?;
    }
    let g = SensorGeometry::new(&design);
    let mut op = OrientationPlan::paper(&g, args.step_deg, args.accuracy.into());
    op.degree = usize::from(args.degree);
    op.fourier_degree = usize::from(args.fourier_degree);
    op.electrode = args.electrode.clone();
    let o = study(&g, &op).context("orientation study")?;
    if let Some(dir) = &args.out {
        write_dir(dir, &files(&o), args.replace, &args.process)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&o)?);
    } else {
        print!("{}", text(&o));
    }
    Ok(Outcome::Ok)
}

fn text(o: &Orientation) -> String {
    let p = &o.plan;
    let mut s = format!(
        "orientation: {} x {} mm probe at ({}, {}) mm, {} angles, forces {} N ({}; departure \
         from charge proportional to force {:.1e})\n",
        f(p.width_um / 1e3, 1),
        f(p.height_um / 1e3, 1),
        f(p.x_um / 1e3, 2),
        f(p.y_um / 1e3, 2),
        p.angles_deg.len(),
        p.forces_n
            .iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        if o.solved_every_force {
            "every force solved".to_string()
        } else {
            format!(
                "reference {} N solved, others scaled and checked at {} angles",
                p.reference_force_n,
                p.check_angles_deg.len()
            )
        },
        o.linearity_deviation
    );
    let c = &o.cost;
    let _ = writeln!(
        s,
        "cost: {} loads in one FE call, {} ms, {} dofs, {} levels, largest estimated error {}; \
         inverse re-runs {} loads, {} ms",
        c.scenes,
        f(c.wall_ms, 0),
        c.dofs,
        c.levels,
        c.max_error_estimate
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "n/a".into()),
        o.inverse_cost.scenes,
        f(o.inverse_cost.wall_ms, 0)
    );
    let _ = writeln!(
        s,
        "condition number of the basis at the samples: monomials in radians (paper Eq. 1) {:.2e}",
        o.monomial_condition_number
    );
    let _ = writeln!(
        s,
        "  electrode  min_pc  max_pc  rel_var  cheb_cond  cheb_rms_pc  cheb_max_pc  four_cond  \
         four_rms_pc  four_max_pc"
    );
    for (e, fit) in o.fits.iter().enumerate() {
        let iref = p
            .forces_n
            .iter()
            .position(|x| (*x - p.reference_force_n).abs() < 1e-12)
            .unwrap_or(0);
        let v: Vec<f64> = o.charge_pc[iref].iter().map(|r| r[e]).collect();
        let (mn, mx) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(*x), b.max(*x)));
        let _ = writeln!(
            s,
            "  {:<9} {:>7} {:>7} {:>8} {:>10} {:>12} {:>12} {:>10} {:>12} {:>12}",
            fit.electrode,
            f(mn, 2),
            f(mx, 2),
            f(fit.relative_variation, 4),
            f(fit.chebyshev.condition_number, 2),
            format!("{:.2e}", fit.chebyshev.rms_residual),
            format!("{:.2e}", fit.chebyshev.max_abs_residual),
            f(fit.fourier.condition_number, 2),
            format!("{:.2e}", fit.fourier.rms_residual),
            format!("{:.2e}", fit.fourier.max_abs_residual)
        );
    }
    let _ = writeln!(
        s,
        "inverse angle from {} on its monotone branch {} - {} deg (paper 000 Tables 2-3):\n  \
         force_n  assumed_pc  angle_deg  fe_charge_pc  error_%  angle_error_deg",
        o.inverse_electrode,
        f(o.branch_deg.0, 2),
        f(o.branch_deg.1, 2)
    );
    for r in &o.inverse {
        let _ = writeln!(
            s,
            "  {:>7} {:>11} {:>10} {:>13} {:>8} {:>16}",
            r.force_n,
            f(r.assumed_charge_pc, 3),
            f(r.estimated_angle_deg, 3),
            f(r.fe_charge_pc, 3),
            f(r.charge_error_pct, 4),
            f(r.angle_error_deg, 4)
        );
    }
    let _ = writeln!(
        s,
        "normalised bivariate c(angle, F) = N(angle) (k1 F + k2 F^2) (paper 000 Eq. 12-13):\n  \
         electrode  k1_pc_per_n  k2_pc_per_n2  max_residual_pc  rel_residual  \
         spread_between_forces"
    );
    for b in &o.bivariate {
        let _ = writeln!(
            s,
            "  {:<9} {:>12} {:>13} {:>16} {:>13} {:>22}",
            b.electrode,
            f(b.slope_pc_per_n, 3),
            format!("{:.3e}", b.quadratic_pc_per_n2),
            format!("{:.2e}", b.max_abs_residual_pc),
            format!("{:.2e}", b.max_rel_residual),
            format!("{:.2e}", b.normalised_spread)
        );
    }
    s
}
