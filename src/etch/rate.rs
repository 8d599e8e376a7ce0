//! Etch-rate models: Arrhenius scaling of measured TMAH rates and the Seidel KOH formula.

use crate::units::{kelvin, BOLTZMANN_EV_PER_K};

/// R(T) = R_ref exp(-Ea/k (1/T - 1/T_ref)) (Arrhenius; reference/process-physics.md).
pub fn arrhenius(rate_ref: f64, temp_ref_c: f64, temp_c: f64, ea_ev: f64) -> f64 {
    rate_ref
        * (-ea_ev / BOLTZMANN_EV_PER_K * (1.0 / kelvin(temp_c) - 1.0 / kelvin(temp_ref_c))).exp()
}

/// A (100) rate from a table of measured points: linear in wt % between the neighbouring rows,
/// each first scaled to `temp_c` by [`arrhenius`]. Returns the rate and whether it extrapolated.
pub fn tmah_rate_100(
    table: &[(f64, f64, f64)],
    wt_pct: f64,
    temp_c: f64,
    ea_ev: f64,
) -> (f64, bool) {
    let mut rows: Vec<(f64, f64)> = table
        .iter()
        .map(|&(c, r, t)| (c, arrhenius(r, t, temp_c, ea_ev)))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    let tol = 1e-9;
    if wt_pct <= first.0 + tol {
        return (first.1, wt_pct < first.0 - tol);
    }
    if wt_pct >= last.0 - tol {
        return (last.1, wt_pct > last.0 + tol);
    }
    for w in rows.windows(2) {
        let ((c0, r0), (c1, r1)) = (w[0], w[1]);
        if wt_pct >= c0 && wt_pct <= c1 {
            return (r0 + (r1 - r0) * (wt_pct - c0) / (c1 - c0), false);
        }
    }
    unreachable!("wt_pct lies between the first and last rows")
}

/// KOH solution density in g/cm3 by wt % (reference/process-physics.md), linear in between,
/// end slopes beyond (Seidel's fit covers 10-60 wt %).
pub fn koh_density_g_per_cm3(wt_pct: f64) -> f64 {
    const T: [(f64, f64); 6] = [
        (20.0, 1.186),
        (25.0, 1.238),
        (30.0, 1.288),
        (35.0, 1.344),
        (40.0, 1.398),
        (45.0, 1.456),
    ];
    let seg = if wt_pct <= T[0].0 {
        (T[0], T[1])
    } else if wt_pct >= T[5].0 {
        (T[4], T[5])
    } else {
        let i = T
            .iter()
            .position(|&(c, _)| c >= wt_pct)
            .expect("inside the table");
        (T[i - 1], T[i])
    };
    let ((c0, d0), (c1, d1)) = seg;
    d0 + (d1 - d0) * (wt_pct - c0) / (c1 - c0)
}

/// Seidel et al., J. Electrochem. Soc. 137 (1990) 3612, Eq. 10:
/// R = k0 \[H2O\]^4 \[KOH\]^(1/4) exp(-Ea/kT), concentrations in mol/L.
pub fn koh_seidel(k0_um_per_h: f64, ea_ev: f64, wt_pct: f64, temp_c: f64) -> f64 {
    const M_KOH_G_PER_MOL: f64 = 56.106;
    const M_H2O_G_PER_MOL: f64 = 18.015;
    let rho_g_per_l = koh_density_g_per_cm3(wt_pct) * 1000.0;
    let koh = wt_pct / 100.0 * rho_g_per_l / M_KOH_G_PER_MOL;
    let h2o = (1.0 - wt_pct / 100.0) * rho_g_per_l / M_H2O_G_PER_MOL;
    k0_um_per_h
        * h2o.powi(4)
        * koh.powf(0.25)
        * (-ea_ev / (BOLTZMANN_EV_PER_K * kelvin(temp_c))).exp()
}

/// Seidel (100): k0 = 2480 um/h (mol/L)^-4.25, Ea = 0.595 eV.
pub fn koh_rate_100(wt_pct: f64, temp_c: f64) -> f64 {
    koh_seidel(2480.0, 0.595, wt_pct, temp_c)
}

/// Seidel (110): k0 = 4500 um/h (mol/L)^-4.25, Ea = 0.60 eV.
pub fn koh_rate_110(wt_pct: f64, temp_c: f64) -> f64 {
    koh_seidel(4500.0, 0.60, wt_pct, temp_c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tmah_arrhenius_matches_reference_band() {
        // reference/process-physics.md: 24 um/h at 80 C gives 14-15 at 70 C and 38-41 at 90 C.
        let t = [(25.0, 24.0, 80.0)];
        let (r70, _) = tmah_rate_100(&t, 25.0, 70.0, 0.55);
        let (r90, _) = tmah_rate_100(&t, 25.0, 90.0, 0.55);
        assert!((14.0..15.5).contains(&r70), "{r70}");
        assert!((37.0..41.0).contains(&r90), "{r90}");
        assert_eq!(tmah_rate_100(&t, 25.0, 80.0, 0.55), (24.0, false));
        assert!(tmah_rate_100(&t, 20.0, 80.0, 0.55).1);
    }

    #[test]
    fn tmah_interpolates_between_rows() {
        let t = [(20.0, 30.0, 80.0), (25.0, 20.0, 80.0)];
        let (r, x) = tmah_rate_100(&t, 22.5, 80.0, 0.55);
        assert!((r - 25.0).abs() < 1e-12 && !x);
    }

    #[test]
    fn seidel_koh_30pct_80c() {
        // reference: ~81 um/h at 30 %, 80 C.
        let r = koh_rate_100(30.0, 80.0);
        assert!((r - 81.0).abs() < 1.5, "{r}");
        assert!(koh_rate_110(30.0, 80.0) > r);
    }
}
