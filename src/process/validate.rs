//! Range and cross-field rules: non-physical values are input errors (exit 2), all reported at
//! once. Process judgements (a time that gives the wrong depth, colliding compensators) are not
//! here: they are checks of the etch plan.

use super::schema::*;

pub struct Invalid {
    pub path: String,
    pub message: String,
    pub expected: String,
}

/// Allowed bath temperatures per etchant [est: practical bath limits; TMAH 25 % boils near 100 C].
pub fn etchant_temp_range_c(e: Etchant) -> (f64, f64) {
    match e {
        Etchant::Tmah => (40.0, 95.0),
        Etchant::Koh => (20.0, 100.0),
    }
}

/// Concentrations the rate models cover: Seidel's KOH fit 10-60 wt %; TMAH tables up to 30 wt %.
pub fn etchant_concentration_range_wt_pct(e: Etchant) -> (f64, f64) {
    match e {
        Etchant::Tmah => (1.0, 30.0),
        Etchant::Koh => (10.0, 60.0),
    }
}

struct V {
    out: Vec<Invalid>,
}

impl V {
    fn push(
        &mut self,
        path: impl Into<String>,
        message: impl Into<String>,
        expected: impl Into<String>,
    ) {
        self.out.push(Invalid {
            path: path.into(),
            message: message.into(),
            expected: expected.into(),
        });
    }
    /// lo < x <= hi style checks with open/closed ends spelled out in the message.
    fn range(&mut self, path: &str, x: f64, lo: f64, hi: f64, lo_open: bool, unit: &str) {
        let bad_lo = if lo_open { x <= lo } else { x < lo };
        if !x.is_finite() || bad_lo || x > hi {
            let l = if lo_open { "(" } else { "[" };
            self.push(
                path,
                format!("{x} {unit} is out of range"),
                format!("a number in {l}{lo}, {hi}] {unit}"),
            );
        }
    }
    fn positive(&mut self, path: &str, x: f64, hi: f64, unit: &str) {
        self.range(path, x, 0.0, hi, true, unit);
    }
}

pub fn validate(p: &Process, is_placeholder: &dyn Fn(&str) -> bool) -> Vec<Invalid> {
    let mut v = V { out: Vec::new() };
    let safe = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    };
    if !safe(&p.device.name) {
        v.push(
            "device.name",
            format!("`{}` is not a file-name-safe name", p.device.name),
            "letters, digits, `-` and `_`",
        );
    }
    if p.device.revision.is_empty() {
        v.push(
            "device.revision",
            "empty revision",
            "a revision label such as `A`",
        );
    }

    let w = &p.wafer;
    if w.orientation != CrystalPlane::P100 {
        v.push(
            "wafer.orientation",
            "the etch geometry model covers (100) wafers only",
            "\"100\"",
        );
    }
    v.range(
        "wafer.thickness_um",
        w.thickness_um,
        50.0,
        2000.0,
        false,
        "um",
    );
    v.range(
        "wafer.thickness_tolerance_um",
        w.thickness_tolerance_um,
        0.0,
        w.thickness_um / 2.0,
        false,
        "um",
    );
    v.range("wafer.diameter_mm", w.diameter_mm, 25.0, 450.0, false, "mm");

    let g = &p.geometry;
    let wafer_um = w.thickness_um;
    let diam_um = w.diameter_mm * 1000.0;
    v.positive("geometry.die_length_um", g.die_length_um, diam_um, "um");
    v.positive("geometry.die_width_um", g.die_width_um, diam_um, "um");
    v.positive(
        "geometry.plate_thickness_um",
        g.plate_thickness_um,
        wafer_um,
        "um",
    );
    v.positive(
        "geometry.support_width_um",
        g.support_width_um,
        g.die_width_um / 2.0,
        "um",
    );
    v.positive(
        "geometry.channel_depth_um",
        g.channel_depth_um,
        wafer_um,
        "um",
    );
    v.range(
        "geometry.dicing_street_um",
        g.dicing_street_um,
        0.0,
        5000.0,
        false,
        "um",
    );
    let t = &g.teeth;
    if t.pattern != TeethPattern::None {
        v.positive("geometry.teeth.height_um", t.height_um, wafer_um, "um");
        v.positive(
            "geometry.teeth.top_um",
            t.top_um,
            t.pitch_x_um.min(t.pitch_y_um),
            "um (at most the smaller pitch)",
        );
        v.positive(
            "geometry.teeth.pitch_x_um",
            t.pitch_x_um,
            g.die_length_um,
            "um",
        );
        v.positive(
            "geometry.teeth.pitch_y_um",
            t.pitch_y_um,
            g.die_width_um,
            "um",
        );
        v.range(
            "geometry.teeth.count_x",
            t.count_x as f64,
            1.0,
            1000.0,
            false,
            "",
        );
        v.range(
            "geometry.teeth.count_y",
            t.count_y as f64,
            1.0,
            1000.0,
            false,
            "",
        );
        v.range(
            "geometry.teeth.origin_x_um",
            t.origin_x_um,
            0.0,
            g.die_length_um,
            false,
            "um",
        );
        v.range(
            "geometry.teeth.origin_y_um",
            t.origin_y_um,
            0.0,
            g.die_width_um,
            false,
            "um",
        );
        let end_x = t.origin_x_um + t.count_x as f64 * t.pitch_x_um;
        let end_y = t.origin_y_um + t.count_y as f64 * t.pitch_y_um;
        if end_x > g.die_length_um + 1e-6 {
            v.push(
                "geometry.teeth.count_x",
                format!("the tooth grid ends at x = {end_x} um, beyond the die"),
                format!(
                    "origin_x_um + count_x * pitch_x_um <= {} um",
                    g.die_length_um
                ),
            );
        }
        if end_y > g.die_width_um + 1e-6 {
            v.push(
                "geometry.teeth.count_y",
                format!("the tooth grid ends at y = {end_y} um, beyond the die"),
                format!(
                    "origin_y_um + count_y * pitch_y_um <= {} um",
                    g.die_width_um
                ),
            );
        }
    }
    let e = &g.electrodes;
    v.range(
        "geometry.electrodes.units",
        e.units as f64,
        1.0,
        20.0,
        false,
        "",
    );
    v.positive(
        "geometry.electrodes.gap_um",
        e.gap_um,
        g.support_width_um,
        "um",
    );
    v.range(
        "geometry.electrodes.edge_margin_um",
        e.edge_margin_um,
        0.0,
        g.support_width_um / 2.0,
        false,
        "um",
    );
    v.positive(
        "geometry.electrodes.wire_pad_um",
        e.wire_pad_um,
        g.support_width_um,
        "um",
    );

    let si = &p.materials.silicon;
    v.positive("materials.silicon.c11_gpa", si.c11_gpa, 1000.0, "GPa");
    v.positive(
        "materials.silicon.c12_gpa",
        si.c12_gpa,
        si.c11_gpa,
        "GPa (below c11)",
    );
    v.positive("materials.silicon.c44_gpa", si.c44_gpa, 1000.0, "GPa");
    v.positive("materials.silicon.e_gpa", si.e_gpa, 1000.0, "GPa");
    v.range("materials.silicon.nu", si.nu, -0.99, 0.499, false, "");
    v.positive(
        "materials.silicon.fracture_strength_mpa",
        si.fracture_strength_mpa,
        1.0e5,
        "MPa",
    );
    v.range(
        "materials.silicon.safety_factor",
        si.safety_factor,
        1.0,
        100.0,
        false,
        "",
    );
    let f = &p.materials.pvdf;
    v.positive("materials.pvdf.thickness_um", f.thickness_um, 1000.0, "um");
    v.positive("materials.pvdf.e_gpa", f.e_gpa, 100.0, "GPa");
    v.range("materials.pvdf.nu", f.nu, 0.0, 0.499, false, "");
    v.positive(
        "materials.pvdf.density_g_per_cm3",
        f.density_g_per_cm3,
        20.0,
        "g/cm3",
    );
    v.range("materials.pvdf.eps_r", f.eps_r, 1.0, 1000.0, false, "");
    for (name, d) in [
        ("d31_pc_per_n", f.d31_pc_per_n),
        ("d32_pc_per_n", f.d32_pc_per_n),
        ("d33_pc_per_n", f.d33_pc_per_n),
    ] {
        v.range(
            &format!("materials.pvdf.{name}"),
            d,
            -1000.0,
            1000.0,
            false,
            "pC/N",
        );
    }

    let mut names = std::collections::BTreeSet::new();
    for (i, m) in p.masks.iter().enumerate() {
        if !safe(&m.name) {
            v.push(
                format!("masks[{i}].name"),
                format!("`{}` is not a file-name-safe name", m.name),
                "letters, digits, `-` and `_`",
            );
        }
        if !names.insert(m.name.as_str()) {
            v.push(
                format!("masks[{i}].name"),
                format!("mask `{}` is defined twice", m.name),
                "unique mask names",
            );
        }
    }

    let et = &p.etchants;
    if et.tmah.is_empty() {
        v.push(
            "etchants.tmah",
            "empty TMAH rate table",
            "at least one measured rate",
        );
    }
    for (i, r) in et.tmah.iter().enumerate() {
        let (clo, chi) = etchant_concentration_range_wt_pct(Etchant::Tmah);
        v.range(
            &format!("etchants.tmah[{i}].concentration_wt_pct"),
            r.concentration_wt_pct,
            clo,
            chi,
            false,
            "wt %",
        );
        v.positive(
            &format!("etchants.tmah[{i}].rate_100_um_per_h"),
            r.rate_100_um_per_h,
            1000.0,
            "um/h",
        );
        let (tlo, thi) = etchant_temp_range_c(Etchant::Tmah);
        v.range(
            &format!("etchants.tmah[{i}].temp_c"),
            r.temp_c,
            tlo,
            thi,
            false,
            "C",
        );
    }
    v.range("etchants.tmah_ea_ev", et.tmah_ea_ev, 0.1, 2.0, false, "eV");
    v.range(
        "etchants.tmah_r110_over_r100",
        et.tmah_r110_over_r100,
        0.1,
        10.0,
        false,
        "",
    );
    v.range(
        "etchants.tmah_r100_over_r111",
        et.tmah_r100_over_r111,
        1.0,
        1000.0,
        true,
        "",
    );
    v.range(
        "etchants.koh_r100_over_r111",
        et.koh_r100_over_r111,
        1.0,
        1000.0,
        true,
        "",
    );
    v.range(
        "etchants.tmah_oxide_rate_um_per_h",
        et.tmah_oxide_rate_um_per_h,
        0.0,
        100.0,
        false,
        "um/h",
    );
    v.range(
        "etchants.koh_oxide_rate_um_per_h",
        et.koh_oxide_rate_um_per_h,
        0.0,
        100.0,
        false,
        "um/h",
    );
    v.positive(
        "etchants.boe_rate_um_per_min",
        et.boe_rate_um_per_min,
        10.0,
        "um/min",
    );

    let mut scene_names = std::collections::BTreeSet::new();
    for (i, sc) in p.checks.scenes.iter().enumerate() {
        let b = format!("checks.scenes[{i}]");
        if !safe(&sc.name) {
            v.push(
                format!("{b}.name"),
                format!("`{}` is not a simple name", sc.name),
                "letters, digits, `-` and `_`",
            );
        } else if !scene_names.insert(sc.name.as_str()) {
            v.push(
                format!("{b}.name"),
                format!("scene `{}` is defined twice", sc.name),
                "unique scene names",
            );
        }
        let (l, w) = (g.die_length_um, g.die_width_um);
        let force = |v: &mut V, f: f64| {
            v.range(
                &format!("{b}.load.force_n"),
                f.abs(),
                0.0,
                1000.0,
                true,
                "N (magnitude)",
            )
        };
        match &sc.load {
            SceneLoad::Point {
                x_um,
                y_um,
                force_n,
                radius_um,
            } => {
                v.range(
                    &format!("{b}.load.point.x_um"),
                    *x_um,
                    0.0,
                    l,
                    false,
                    "um (on the die)",
                );
                v.range(
                    &format!("{b}.load.point.y_um"),
                    *y_um,
                    0.0,
                    w,
                    false,
                    "um (on the die)",
                );
                v.positive(
                    &format!("{b}.load.point.radius_um"),
                    *radius_um,
                    w / 2.0,
                    "um",
                );
                force(&mut v, *force_n);
            }
            SceneLoad::Pressure { force_n, region } => {
                force(&mut v, *force_n);
                if let Some(r) = region {
                    if !(r.x0_um >= 0.0
                        && r.x1_um <= l
                        && r.y0_um >= 0.0
                        && r.y1_um <= w
                        && r.x0_um < r.x1_um
                        && r.y0_um < r.y1_um)
                    {
                        v.push(
                            format!("{b}.load.pressure.region"),
                            "the region is empty or leaves the die",
                            format!("0 <= x0_um < x1_um <= {l}, 0 <= y0_um < y1_um <= {w}"),
                        );
                    }
                }
            }
            SceneLoad::Probe {
                x_um,
                y_um,
                width_um,
                height_um,
                force_n,
                ..
            } => {
                v.range(
                    &format!("{b}.load.probe.x_um"),
                    *x_um,
                    0.0,
                    l,
                    false,
                    "um (on the die)",
                );
                v.range(
                    &format!("{b}.load.probe.y_um"),
                    *y_um,
                    0.0,
                    w,
                    false,
                    "um (on the die)",
                );
                v.positive(&format!("{b}.load.probe.width_um"), *width_um, 1e5, "um");
                v.positive(&format!("{b}.load.probe.height_um"), *height_um, 1e5, "um");
                force(&mut v, *force_n);
            }
            SceneLoad::Line { y_um, force_n } => {
                v.range(
                    &format!("{b}.load.line.y_um"),
                    *y_um,
                    0.0,
                    w,
                    false,
                    "um (on the die)",
                );
                force(&mut v, *force_n);
            }
        }
        let lim = &sc.limits;
        for (name, x) in [
            ("min_sensitivity_mv_per_n", lim.min_sensitivity_mv_per_n),
            ("max_stress_mpa", lim.max_stress_mpa),
            ("min_safety_factor", lim.min_safety_factor),
            ("max_deflection_um", lim.max_deflection_um),
        ] {
            if let Some(x) = x {
                v.positive(&format!("{b}.limits.{name}"), x, 1e9, "");
            }
        }
    }

    let mut step_names = std::collections::BTreeSet::new();
    for (i, s) in p.steps.iter().enumerate() {
        let b = format!("steps[{i}]");
        if s.name.trim().is_empty() {
            v.push(
                format!("{b}.name"),
                "empty step name",
                "a short unique name",
            );
        } else if !step_names.insert(s.name.as_str()) {
            v.push(
                format!("{b}.name"),
                format!("step `{}` is named twice", s.name),
                "unique step names (--set steps.NAME.field=... uses them)",
            );
        }
        match &s.params {
            StepParams::Oxidation(o) => {
                v.range(&format!("{b}.temp_c"), o.temp_c, 700.0, 1300.0, false, "C");
                v.positive(&format!("{b}.time_h"), o.time_h, 200.0, "h");
                v.range(
                    &format!("{b}.initial_oxide_um"),
                    o.initial_oxide_um,
                    0.0,
                    10.0,
                    false,
                    "um",
                );
                if let Some(x) = o.expected_thickness_um {
                    v.positive(&format!("{b}.expected_thickness_um"), x, 20.0, "um");
                }
            }
            StepParams::SpinCoat(c) => {
                v.range(
                    &format!("{b}.speed_rpm"),
                    c.speed_rpm,
                    300.0,
                    10000.0,
                    false,
                    "rpm",
                );
                v.positive(&format!("{b}.time_s"), c.time_s, 600.0, "s");
                v.positive(
                    &format!("{b}.ref_thickness_um"),
                    c.ref_thickness_um,
                    200.0,
                    "um",
                );
                v.range(
                    &format!("{b}.ref_speed_rpm"),
                    c.ref_speed_rpm,
                    300.0,
                    10000.0,
                    false,
                    "rpm",
                );
                v.range(
                    &format!("{b}.spin_exponent"),
                    c.spin_exponent,
                    0.1,
                    2.0,
                    false,
                    "",
                );
            }
            StepParams::Bake(k) => {
                v.range(&format!("{b}.temp_c"), k.temp_c, 15.0, 400.0, false, "C");
                v.positive(&format!("{b}.time_min"), k.time_min, 24.0 * 60.0, "min");
            }
            StepParams::Expose(x) => {
                v.positive(&format!("{b}.time_s"), x.time_s, 3600.0, "s");
                if x.masks.is_empty() {
                    v.push(
                        format!("{b}.masks"),
                        "no mask named",
                        "one or more names from `masks`",
                    );
                }
                for (j, m) in x.masks.iter().enumerate() {
                    if !p.masks.iter().any(|k| &k.name == m) {
                        let known: Vec<_> =
                            p.masks.iter().map(|k| format!("`{}`", k.name)).collect();
                        v.push(
                            format!("{b}.masks[{j}]"),
                            format!("unknown mask `{m}`"),
                            format!("one of {}", known.join(", ")),
                        );
                    }
                }
            }
            StepParams::Develop(d) => v.positive(&format!("{b}.time_s"), d.time_s, 3600.0, "s"),
            StepParams::OxideEtch(o) => v.range(
                &format!("{b}.overetch_pct"),
                o.overetch_pct,
                0.0,
                200.0,
                false,
                "%",
            ),
            StepParams::SiliconEtch(s) if !is_placeholder(&format!("{b}.etchant")) => {
                let (tlo, thi) = etchant_temp_range_c(s.etchant);
                v.range(
                    &format!("{b}.temp_c"),
                    s.temp_c,
                    tlo,
                    thi,
                    false,
                    &format!("C for {}", s.etchant.label()),
                );
                let (clo, chi) = etchant_concentration_range_wt_pct(s.etchant);
                v.range(
                    &format!("{b}.concentration_wt_pct"),
                    s.concentration_wt_pct,
                    clo,
                    chi,
                    false,
                    &format!("wt % for {}", s.etchant.label()),
                );
                v.positive(&format!("{b}.depth_um"), s.depth_um, 1.0e4, "um");
                if s.depth_um > 0.0 && s.depth_um >= wafer_um {
                    v.push(
                        format!("{b}.depth_um"),
                        format!("{} um reaches through the {wafer_um} um wafer", s.depth_um),
                        "a depth less than wafer.thickness_um",
                    );
                }
                if let Some(t) = s.time_h {
                    v.positive(&format!("{b}.time_h"), t, 200.0, "h");
                }
                if let Some(r) = s.measured_rate_um_per_h {
                    v.positive(&format!("{b}.measured_rate_um_per_h"), r, 1000.0, "um/h");
                }
                if let Some(c) = &s.compensation {
                    v.range(
                        &format!("{b}.compensation.ratio"),
                        c.ratio,
                        0.05,
                        5.0,
                        false,
                        "",
                    );
                }
            }
            StepParams::MetalEtch(m) => {
                v.range(&format!("{b}.temp_c"), m.temp_c, 10.0, 90.0, false, "C");
                v.positive(&format!("{b}.time_min"), m.time_min, 600.0, "min");
            }
            StepParams::Clean(gn) | StepParams::Mount(gn) => {
                if let Some(t) = gn.temp_c {
                    v.range(&format!("{b}.temp_c"), t, 0.0, 400.0, false, "C");
                }
                if let Some(t) = gn.time_min {
                    v.positive(&format!("{b}.time_min"), t, 24.0 * 60.0, "min");
                }
            }
            StepParams::Assemble(a) => {
                if let Some(t) = a.temp_c {
                    v.range(&format!("{b}.temp_c"), t, 0.0, 200.0, false, "C");
                }
                if let Some(t) = a.time_min {
                    v.positive(&format!("{b}.time_min"), t, 24.0 * 60.0, "min");
                }
            }
            StepParams::Strip(_) | StepParams::SiliconEtch(_) => {}
        }
    }
    let lay = &p.layout;
    v.range(
        "layout.edge_exclusion_mm",
        lay.edge_exclusion_mm,
        0.0,
        w.diameter_mm / 4.0,
        false,
        "mm",
    );
    v.positive("layout.label_pixel_um", lay.label_pixel_um, 1000.0, "um");
    v.range(
        "layout.compensation_overlap_um",
        lay.compensation_overlap_um,
        0.0,
        t.top_um / 4.0,
        false,
        "um",
    );
    let l = &lay.layers;
    let mut seen = std::collections::BTreeSet::new();
    for (name, g) in [
        ("front_si", l.front_si),
        ("back_si", l.back_si),
        ("pvdf", l.pvdf),
        ("marks", l.marks),
        ("annotation", l.annotation),
        ("outline", l.outline),
    ] {
        if !(0..=255).contains(&g.layer) || !(0..=255).contains(&g.datatype) {
            v.push(
                format!("layout.layers.{name}"),
                format!("{}/{} is out of range", g.layer, g.datatype),
                "layer and datatype in [0, 255]",
            );
        }
        if !seen.insert((g.layer, g.datatype)) {
            v.push(
                format!("layout.layers.{name}"),
                format!("{}/{} is used by two layers", g.layer, g.datatype),
                "a distinct layer/datatype per layer",
            );
        }
    }
    let d = &p.drc;
    v.positive("drc.min_width_um", d.min_width_um, 1000.0, "um");
    v.positive("drc.min_space_um", d.min_space_um, 1000.0, "um");
    v.range(
        "drc.max_vertices",
        d.max_vertices as f64,
        4.0,
        8190.0,
        false,
        "",
    );
    v.range(
        "drc.min_electrode_gap_um",
        d.min_electrode_gap_um,
        0.0,
        g.die_width_um,
        false,
        "um",
    );
    v.out
}
