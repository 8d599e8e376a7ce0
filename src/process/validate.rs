//! Range and cross-field rules: non-physical values are input errors (exit 2), all reported at
//! once. Process judgements (a time that gives the wrong depth, colliding compensators) are not
//! here: they are checks of the etch plan.
//!
//! One function per section of the file, in file order; each pushes its problems into [`V`].

use std::collections::BTreeSet;

use super::schema::*;

/// One range or cross-field problem, before its location is attached.
pub struct Invalid {
    pub path: String,
    pub message: String,
    pub expected: String,
    /// What to do about it; empty when the expected text says it all.
    pub hint: String,
}

/// Narrowest plate between the two supports (`die_width_um - 2 support_width_um`): the plate is
/// what the sensor measures, the middle electrodes sit on it and the FE mesh keeps lines at least
/// 250 um apart. At zero width the FE mesh has no plate at all (it used to panic).
pub const MIN_PLATE_SPAN_UM: f64 = 500.0;

/// Most teeth on a die (`count_x * count_y`): each is a GDS placement, a DRC polygon and an FE
/// thickness region. The papers' dies have 50.
pub const MAX_TEETH: u64 = 10_000;

/// Most dies on a wafer (wafer area over die pitch area): each is drawn and stepped. A 30 x 15 mm
/// die gives 15 on a 100 mm wafer; tens of thousands mean a die size typed in mm, not um.
pub const MAX_DIES_PER_WAFER: f64 = 10_000.0;

/// Most masks in `masks`: each is a GDS layer, an SVG and a DRC pass. The device needs three.
pub const MAX_MASKS: usize = 16;

/// Most scenes in `checks.scenes`: each is a finite-element solve at several mesh levels.
pub const MAX_SCENES: usize = 64;

/// Most steps in `steps`: each is a traveler row and an etch-plan entry. The bundled files have
/// about twenty.
pub const MAX_STEPS: usize = 500;

/// Most rows in the `etchants.tmah` rate table.
pub const MAX_TMAH_RATES: usize = 100;

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

/// The problems found so far.
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
        self.push_hint(path, message, expected, "");
    }
    fn push_hint(
        &mut self,
        path: impl Into<String>,
        message: impl Into<String>,
        expected: impl Into<String>,
        hint: impl Into<String>,
    ) {
        self.out.push(Invalid {
            path: path.into(),
            message: message.into(),
            expected: expected.into(),
            hint: hint.into(),
        });
    }
    /// lo < x <= hi style checks with open/closed ends spelled out in the message.
    fn range(&mut self, path: &str, x: f64, lo: f64, hi: f64, lo_open: bool, unit: &str) {
        let bad_lo = if lo_open { x <= lo } else { x < lo };
        if !x.is_finite() || bad_lo || x > hi {
            let l = if lo_open { "(" } else { "[" };
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" {unit}")
            };
            self.push(
                path,
                format!("{x}{unit} is out of range"),
                format!("a number in {l}{lo}, {hi}]{unit}"),
            );
        }
    }
    fn positive(&mut self, path: &str, x: f64, hi: f64, unit: &str) {
        self.range(path, x, 0.0, hi, true, unit);
    }
}

/// Letters, digits, `-` and `_`, not empty: names that become file names or `--set` keys.
fn safe(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
}

/// Every range and cross-field rule of a deserialised process. `is_placeholder` says which paths
/// hold a stand-in for a value already reported as malformed (their rules are skipped).
pub fn validate(p: &Process, is_placeholder: &dyn Fn(&str) -> bool) -> Vec<Invalid> {
    let mut v = V { out: Vec::new() };
    counts(&mut v, p);
    device(&mut v, &p.device);
    wafer(&mut v, &p.wafer);
    geometry(&mut v, p);
    materials(&mut v, &p.materials);
    masks(&mut v, &p.masks, p.geometry.teeth.pattern);
    etchants(&mut v, &p.etchants);
    scenes(&mut v, p);
    steps(&mut v, p, is_placeholder);
    layout(&mut v, p);
    drc(&mut v, p);
    readout(&mut v, &p.readout);
    v.out
}

/// Lists that drive allocation later (masks, scenes, steps, rate rows) within their bounds, and
/// at least one step.
fn counts(v: &mut V, p: &Process) {
    for (path, n, max, what, hint) in [
        (
            "masks",
            p.masks.len(),
            MAX_MASKS,
            "masks",
            "the device needs three (front Si, back Si, PVDF); each mask is drawn and checked",
        ),
        (
            "checks.scenes",
            p.checks.scenes.len(),
            MAX_SCENES,
            "scenes",
            "each scene is a finite-element solve; keep the declared checks to the ones that \
             decide the design",
        ),
        (
            "steps",
            p.steps.len(),
            MAX_STEPS,
            "steps",
            "a process has tens of steps; is a list repeated?",
        ),
        (
            "etchants.tmah",
            p.etchants.tmah.len(),
            MAX_TMAH_RATES,
            "rate rows",
            "the table is interpolated by concentration; a few measured rows suffice",
        ),
    ] {
        if n > max {
            v.push_hint(
                path,
                format!("{n} {what} is too many"),
                format!("at most {max} {what}"),
                hint,
            );
        }
    }
    if p.steps.is_empty() {
        v.push_hint(
            "steps",
            "the process has no steps",
            "at least one process step",
            "the etch plan, the plate thickness and the traveler come from the steps; list them \
             in the order the cleanroom runs them",
        );
    }
}

/// `device`: a file-name-safe name and a revision label.
fn device(v: &mut V, d: &Device) {
    if !safe(&d.name) {
        v.push(
            "device.name",
            format!("`{}` is not a file-name-safe name", d.name),
            "letters, digits, `-` and `_`",
        );
    }
    if d.revision.is_empty() {
        v.push(
            "device.revision",
            "empty revision",
            "a revision label such as `A`",
        );
    }
}

/// `wafer`: (100) only, thickness, tolerance and diameter in range.
fn wafer(v: &mut V, w: &Wafer) {
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
    v.range(
        "wafer.lot_wafers",
        f64::from(w.lot_wafers),
        1.0,
        25.0,
        false,
        "wafers",
    );
}

/// `geometry`: the die on the wafer, then its teeth and electrodes.
fn geometry(v: &mut V, p: &Process) {
    let (g, w) = (&p.geometry, &p.wafer);
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
    plate_span(v, g);
    let street = g.dicing_street_um;
    if !(street > 0.0 && street <= 5000.0) {
        v.push_hint(
            "geometry.dicing_street_um",
            format!("{street} um is out of range"),
            "a number in (0, 5000] um",
            "the saw needs a street between dies; at 0 the supports of neighbouring dies touch, \
             which the DRC (STREET_TOO_NARROW) does not report as a street",
        );
    }
    die_count(v, g, w);
    teeth(v, g, wafer_um);
    electrodes(v, g);
}

/// The plate between the supports at least [`MIN_PLATE_SPAN_UM`] wide (supports already in
/// (0, die_width / 2]).
fn plate_span(v: &mut V, g: &Geometry) {
    let (s, w) = (g.support_width_um, g.die_width_um);
    let span = w - 2.0 * s;
    if s > 0.0 && s <= w / 2.0 && span < MIN_PLATE_SPAN_UM {
        v.push_hint(
            "geometry.support_width_um",
            format!("two {s} um supports leave a {span} um plate on the {w} um die"),
            format!(
                "support_width_um <= (die_width_um - {MIN_PLATE_SPAN_UM}) / 2 = {} um",
                (w - MIN_PLATE_SPAN_UM) / 2.0
            ),
            format!(
                "the plate between the supports is the sensor; it needs at least \
                 {MIN_PLATE_SPAN_UM} um (MIN_PLATE_SPAN_UM) for its electrodes and FE mesh"
            ),
        );
    }
}

/// About how many dies the wafer holds: at most [`MAX_DIES_PER_WAFER`] (checked only for a valid
/// die size and wafer diameter).
fn die_count(v: &mut V, g: &Geometry, w: &Wafer) {
    let (l, wd, st) = (g.die_length_um, g.die_width_um, g.dicing_street_um);
    let r_um = w.diameter_mm * 500.0;
    let valid = l > 0.0 && wd > 0.0 && st >= 0.0 && (25.0..=450.0).contains(&w.diameter_mm);
    if !valid {
        return;
    }
    let dies = std::f64::consts::PI * r_um * r_um / ((l + st) * (wd + st));
    if dies > MAX_DIES_PER_WAFER {
        v.push_hint(
            "geometry.die_length_um",
            format!(
                "a {l} x {wd} um die at a {st} um street gives about {dies:.0} dies on the {} mm \
                 wafer",
                w.diameter_mm
            ),
            format!("at most {MAX_DIES_PER_WAFER} dies per wafer"),
            "die sizes are in um (30 mm is 30000); every die of the wafer is drawn",
        );
    }
}

/// `geometry.teeth`: sizes, counts and a grid that stays on the die (skipped for `pattern: none`).
fn teeth(v: &mut V, g: &Geometry, wafer_um: f64) {
    let t = &g.teeth;
    if t.pattern == TeethPattern::None {
        return;
    }
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
    let n = u64::from(t.count_x) * u64::from(t.count_y);
    if n > MAX_TEETH {
        v.push_hint(
            "geometry.teeth",
            format!("{} x {} = {n} teeth", t.count_x, t.count_y),
            format!("at most {MAX_TEETH} teeth (count_x * count_y)"),
            "each tooth is drawn, checked and meshed; use a coarser pitch or `pattern: none`",
        );
    }
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

/// `geometry.electrodes`: unit count and sizes relative to the supports.
fn electrodes(v: &mut V, g: &Geometry) {
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
}

/// `materials`: silicon stiffness and strength, PVDF film constants.
fn materials(v: &mut V, m: &Materials) {
    let si = &m.silicon;
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
        "materials.silicon.fracture_toughness_mpa_sqrt_m",
        si.fracture_toughness_mpa_sqrt_m,
        0.01,
        100.0,
        false,
        "MPa m^1/2",
    );
    v.range(
        "materials.silicon.safety_factor",
        si.safety_factor,
        1.0,
        100.0,
        false,
        "",
    );
    v.positive(
        "materials.silicon.density_g_per_cm3",
        si.density_g_per_cm3,
        30.0,
        "g/cm3",
    );
    let f = &m.pvdf;
    // Floor [choice]: below 0.1 um a film is not a piezoelectric layer, and at 1e-9 um the
    // solid rung's film bricks (aspect 1e11) kept one scene's solve running past 400 s where
    // 0.1 and 0.001 um take the usual 65 s.
    v.range(
        "materials.pvdf.thickness_um",
        f.thickness_um,
        0.1,
        1000.0,
        false,
        "um",
    );
    v.positive("materials.pvdf.e_gpa", f.e_gpa, 100.0, "GPa");
    v.range("materials.pvdf.nu", f.nu, 0.0, 0.499, false, "");
    let b = &m.base;
    // Floors [choice]: the supports' section meshes the base; a base thinner than 1 um is a
    // typo (1e-9 um collapsed the section's lines), and one softer than 1 MPa (soft rubber) lets
    // the supports punch into it: at 1e-12 GPa the section was singular, at 1 kPa the solid
    // rung's Newton ground on past 300 s, at 1 MPa it converges in the usual minute.
    v.range(
        "materials.base.thickness_um",
        b.thickness_um,
        1.0,
        100_000.0,
        false,
        "um",
    );
    v.range("materials.base.e_gpa", b.e_gpa, 1e-3, 1000.0, false, "GPa");
    v.range("materials.base.nu", b.nu, 0.0, 0.499, false, "");
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
}

/// `masks`: safe, unique names.
/// `masks`: names usable as file names, each purpose drawn by one mask, and the teeth the
/// geometry asks for drawn by a front_si mask (else the FE would model teeth no mask makes).
fn masks(v: &mut V, masks: &[Mask], teeth: TeethPattern) {
    for purpose in [MaskPurpose::FrontSi, MaskPurpose::BackSi, MaskPurpose::Pvdf] {
        let with: Vec<usize> = (0..masks.len())
            .filter(|&i| masks[i].purpose == purpose)
            .collect();
        if let [_, second, ..] = with[..] {
            v.push(
                format!("masks[{second}].purpose"),
                format!(
                    "two masks have purpose `{}`: `{}` and `{}`",
                    crate::spelling::yaml(&purpose),
                    masks[with[0]].name,
                    masks[second].name
                ),
                "one mask per purpose",
            );
        }
    }
    let has_front = masks.iter().any(|m| m.purpose == MaskPurpose::FrontSi);
    if teeth != TeethPattern::None && !has_front && !masks.is_empty() {
        v.push(
            "masks",
            format!(
                "geometry.teeth.pattern is `{}` but no mask has purpose `front_si` to draw the \
                 teeth",
                crate::spelling::yaml(&teeth)
            ),
            "a mask with purpose front_si, or geometry.teeth.pattern: none",
        );
    }
    let mut names = BTreeSet::new();
    for (i, m) in masks.iter().enumerate() {
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
}

/// `etchants`: the TMAH rate table and the rate ratios the etch model uses.
fn etchants(v: &mut V, et: &Etchants) {
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
    for (path, r) in [
        ("etchants.tmah_r311_over_r100", Some(et.tmah_r311_over_r100)),
        ("etchants.tmah_r411_over_r100", et.tmah_r411_over_r100),
        ("etchants.koh_r311_over_r100", Some(et.koh_r311_over_r100)),
        ("etchants.koh_r411_over_r100", et.koh_r411_over_r100),
    ] {
        if let Some(r) = r {
            v.range(path, r, 0.0, 10.0, true, "");
        }
    }
    v.range(
        "etchants.etched_corner_tolerance_um",
        et.etched_corner_tolerance_um,
        0.0,
        10_000.0,
        true,
        "um",
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
}

/// `checks.scenes`: unique names, loads on the die, positive limits.
fn scenes(v: &mut V, p: &Process) {
    let mut scene_names = BTreeSet::new();
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
        scene_load(v, &b, &sc.load, &p.geometry);
        for (kind, x) in sc.limits.entries() {
            if let Some(x) = x {
                v.positive(&format!("{b}.limits.{}", kind.yaml_name()), x, 1e9, "");
            }
        }
    }
}

/// One scene's load (`b` is the scene's path): positions on the die, sizes and force in range.
fn scene_load(v: &mut V, b: &str, load: &SceneLoad, g: &Geometry) {
    let (l, w) = (g.die_length_um, g.die_width_um);
    // The magnitude: a negative force pushes up (pulls), which is allowed.
    let force = |v: &mut V, kind: &str, f: f64| {
        v.range(
            &format!("{b}.load.{kind}.force_n"),
            f.abs(),
            0.0,
            1000.0,
            true,
            "N (magnitude)",
        )
    };
    // A rectangle must be non-empty and lie on the die.
    let region_on_die = |v: &mut V, path: String, r: &RegionUm| {
        if !(r.x0_um >= 0.0
            && r.x1_um <= l
            && r.y0_um >= 0.0
            && r.y1_um <= w
            && r.x0_um < r.x1_um
            && r.y0_um < r.y1_um)
        {
            v.push(
                path,
                "the region is empty or leaves the die",
                format!("0 <= x0_um < x1_um <= {l}, 0 <= y0_um < y1_um <= {w}"),
            );
        }
    };
    let on_die = |v: &mut V, kind: &str, axis: &str, x: f64, hi: f64| {
        v.range(
            &format!("{b}.load.{kind}.{axis}"),
            x,
            0.0,
            hi,
            false,
            "um (on the die)",
        )
    };
    match load {
        SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        } => {
            on_die(v, "point", "x_um", *x_um, l);
            on_die(v, "point", "y_um", *y_um, w);
            v.positive(
                &format!("{b}.load.point.radius_um"),
                *radius_um,
                w / 2.0,
                "um",
            );
            force(v, "point", *force_n);
        }
        SceneLoad::Pressure { force_n, region } => {
            force(v, "pressure", *force_n);
            if let Some(r) = region {
                region_on_die(v, format!("{b}.load.pressure.region"), r);
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
            on_die(v, "probe", "x_um", *x_um, l);
            on_die(v, "probe", "y_um", *y_um, w);
            v.positive(&format!("{b}.load.probe.width_um"), *width_um, 1e5, "um");
            v.positive(&format!("{b}.load.probe.height_um"), *height_um, 1e5, "um");
            force(v, "probe", *force_n);
        }
        SceneLoad::Line { y_um, force_n } => {
            on_die(v, "line", "y_um", *y_um, w);
            force(v, "line", *force_n);
        }
        SceneLoad::Patches { patches } => {
            if patches.is_empty() || patches.len() > crate::sensor::MAX_PATCHES {
                v.push(
                    format!("{b}.load.patches"),
                    format!("{} patches", patches.len()),
                    "1 to 5000 patches".to_string(),
                );
            }
            for (k, p) in patches.iter().enumerate().take(crate::sensor::MAX_PATCHES) {
                // A patch may carry nothing (tissue ends short of the die): [0, 1000] N.
                v.range(
                    &format!("{b}.load.patches[{k}].force_n"),
                    p.force_n.abs(),
                    0.0,
                    1000.0,
                    false,
                    "N (magnitude)",
                );
                region_on_die(v, format!("{b}.load.patches[{k}].region"), &p.region);
            }
        }
    }
}

/// `steps`: unique names, then each step's parameters by kind.
fn steps(v: &mut V, p: &Process, is_placeholder: &dyn Fn(&str) -> bool) {
    let mut step_names = BTreeSet::new();
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
            StepParams::Oxidation(o) => oxidation(v, &b, o),
            StepParams::SpinCoat(c) => spin_coat(v, &b, c),
            StepParams::Bake(k) => {
                v.range(&format!("{b}.temp_c"), k.temp_c, 15.0, 400.0, false, "C");
                v.positive(&format!("{b}.time_min"), k.time_min, 24.0 * 60.0, "min");
            }
            StepParams::Expose(x) if !is_placeholder("masks") => expose(v, &b, x, &p.masks),
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
                silicon_etch(v, &b, s, p.wafer.thickness_um, p.geometry.teeth.top_um)
            }
            StepParams::MetalEtch(m) => {
                v.range(&format!("{b}.temp_c"), m.temp_c, 10.0, 90.0, false, "C");
                v.positive(&format!("{b}.time_min"), m.time_min, 600.0, "min");
            }
            StepParams::Clean(gn) | StepParams::Mount(gn) => {
                optional_temp_time(v, &b, gn.temp_c, gn.time_min, 400.0)
            }
            StepParams::Assemble(a) => optional_temp_time(v, &b, a.temp_c, a.time_min, 200.0),
            StepParams::Strip(_) | StepParams::SiliconEtch(_) | StepParams::Expose(_) => {}
        }
    }
}

/// An oxidation step: furnace temperature, time, initial and claimed oxide.
fn oxidation(v: &mut V, b: &str, o: &Oxidation) {
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

/// A spin-coat step: speed, time and the spin curve.
fn spin_coat(v: &mut V, b: &str, c: &SpinCoat) {
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

/// An expose step: a time and at least one mask, each defined in `masks`.
fn expose(v: &mut V, b: &str, x: &Expose, masks: &[Mask]) {
    v.positive(&format!("{b}.time_s"), x.time_s, 3600.0, "s");
    if x.masks.is_empty() {
        v.push(
            format!("{b}.masks"),
            "no mask named",
            "one or more names from `masks`",
        );
    }
    for (j, m) in x.masks.iter().enumerate() {
        if !masks.iter().any(|k| &k.name == m) {
            let known: Vec<_> = masks.iter().map(|k| format!("`{}`", k.name)).collect();
            v.push(
                format!("{b}.masks[{j}]"),
                format!("unknown mask `{m}`"),
                format!("one of {}", known.join(", ")),
            );
        }
    }
}

/// A silicon etch: bath temperature and concentration for its etchant, a depth short of the
/// wafer, time, measured rate, compensation ratio and a bar's width (no wider than the tooth
/// top, and only for a bar).
fn silicon_etch(v: &mut V, b: &str, s: &SiliconEtch, wafer_um: f64, top_um: f64) {
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
        if let Some(w) = c.bar_width_um {
            let path = format!("{b}.compensation.bar_width_um");
            if c.geometry == CompensationGeometry::Bar110 {
                v.positive(&path, w, top_um, "um (at most geometry.teeth.top_um)");
            } else {
                v.push(
                    path,
                    format!(
                        "a bar width is given for the `{}` geometry, which draws squares",
                        crate::spelling::yaml(&c.geometry)
                    ),
                    "no bar_width_um, or geometry: bar_110",
                );
            }
        }
    }
}

/// The optional temperature (up to `max_temp_c`) and time of clean, mount and assemble steps.
fn optional_temp_time(
    v: &mut V,
    b: &str,
    temp_c: Option<f64>,
    time_min: Option<f64>,
    max_temp_c: f64,
) {
    if let Some(t) = temp_c {
        v.range(&format!("{b}.temp_c"), t, 0.0, max_temp_c, false, "C");
    }
    if let Some(t) = time_min {
        v.positive(&format!("{b}.time_min"), t, 24.0 * 60.0, "min");
    }
}

/// `layout`: edge exclusion, label pixel, compensator overlap and a valid, distinct layer map.
/// The test die's ladder: a bounded count of teeth, every a larger than the compensator's
/// overlap into its tooth, and a centre to step around.
fn test_die(v: &mut V, p: &Process) {
    let t = &p.layout.test_die;
    v.range(
        "layout.test_die.span_um",
        t.span_um,
        0.0,
        2000.0,
        false,
        "um",
    );
    v.positive("layout.test_die.step_um", t.step_um, 2000.0, "um");
    if let Some(c) = t.centre_a_um {
        v.positive("layout.test_die.centre_a_um", c, 5000.0, "um");
    }
    if !(t.enabled && t.span_um.is_finite() && t.step_um.is_finite() && t.step_um > 0.0) {
        return;
    }
    let count = 2.0 * (t.span_um / t.step_um + 1e-9).floor() + 1.0;
    if count > crate::layout::test_die::MAX_TEETH as f64 {
        v.push(
            "layout.test_die.step_um",
            format!(
                "{} um steps over +/- {} um make {count} teeth (at most {})",
                t.step_um,
                t.span_um,
                crate::layout::test_die::MAX_TEETH
            ),
            "a larger step or a smaller span",
        );
    }
    let rule = crate::layout::test_die::front_rule_a_um(p);
    match (t.centre_a_um, rule) {
        (None, None) => v.push(
            "layout.test_die.centre_a_um",
            "there is no front silicon etch, so there is no a to centre the ladder on",
            "centre_a_um in um, or a front silicon etch",
        ),
        (c, r) => {
            let centre = c.or(r).unwrap_or(0.0);
            let lowest = centre - t.span_um;
            let floor = p.layout.compensation_overlap_um;
            if c.is_some() && centre.is_finite() && lowest <= floor {
                v.push(
                    if c.is_some() {
                        "layout.test_die.centre_a_um"
                    } else {
                        "layout.test_die.span_um"
                    },
                    format!(
                        "the ladder's smallest a = {centre:.1} - {} = {lowest:.1} um is not \
                         larger than layout.compensation_overlap_um = {floor} um",
                        t.span_um
                    ),
                    "a ladder whose smallest compensator is larger than the overlap",
                );
            }
        }
    }
}

fn layout(v: &mut V, p: &Process) {
    let lay = &p.layout;
    v.range(
        "layout.edge_exclusion_mm",
        lay.edge_exclusion_mm,
        0.0,
        p.wafer.diameter_mm / 4.0,
        false,
        "mm",
    );
    v.positive("layout.label_pixel_um", lay.label_pixel_um, 1000.0, "um");
    v.range(
        "layout.compensation_overlap_um",
        lay.compensation_overlap_um,
        0.0,
        p.geometry.teeth.top_um / 4.0,
        false,
        "um",
    );
    test_die(v, p);
    let l = &lay.layers;
    let mut seen = BTreeSet::new();
    for (name, g) in [
        ("front_si", l.front_si),
        ("back_si", l.back_si),
        ("pvdf", l.pvdf),
        ("marks", l.marks),
        ("annotation", l.annotation),
        ("outline", l.outline),
        ("wafer_outline", l.wafer_outline),
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
}

/// `drc`: positive widths and spaces, a vertex limit GDS can hold, an electrode gap on the die.
fn drc(v: &mut V, p: &Process) {
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
        p.geometry.die_width_um,
        false,
        "um",
    );
    v.range(
        "drc.min_wall_margin_um",
        d.min_wall_margin_um,
        0.0,
        p.geometry.die_width_um,
        false,
        "um",
    );
}

/// `readout`: every component within what a bench amplifier can be (0.001 pF - 1 uF, 1 kΩ -
/// 1 PΩ feedback, 1 Ω - 1 PΩ input), so gains and time constants stay finite and positive; the
/// cable may be ideal (0 pF).
fn readout(v: &mut V, r: &ReadoutElectronics) {
    v.range(
        "readout.feedback_capacitance_pf",
        r.feedback_capacitance_pf,
        1e-3,
        1e6,
        false,
        "pF",
    );
    v.range(
        "readout.feedback_resistance_gohm",
        r.feedback_resistance_gohm,
        1e-6,
        1e6,
        false,
        "GΩ",
    );
    v.range(
        "readout.input_resistance_mohm",
        r.input_resistance_mohm,
        1e-6,
        1e9,
        false,
        "MΩ",
    );
    v.range(
        "readout.cable_capacitance_pf",
        r.cable_capacitance_pf,
        0.0,
        1e6,
        false,
        "pF",
    );
}
