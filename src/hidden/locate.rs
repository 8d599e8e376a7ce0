//! The inverse: where the hidden feature is and what it is, from the nine voltages with the
//! feature minus those of the background grasp.
//!
//! Model: dV = a t(c), t(c) the nine voltages of the reference disturbance ([`Disturbance`],
//! the feature's size and depth assumed: \[choice\], only position and kind are sought) centred
//! at c, a its amplitude. For each c the least-squares a is (t . dV) / (t . t) and the residual
//! |dV|^2 - (t . dV)^2 / (t . t): the best c maximises the matched-filter statistic
//! (t . dV)^2 / (t . t). Candidates on a grid over the die face, then a compass search
//! (Kolda, Lewis & Torczon, SIAM Rev. 45, 2003) refines c continuously. The kind is the sign of
//! a against the reference's own (a lump raises the pressure, a void lowers it). With Gaussian
//! noise sigma per channel, SNR = |t . dV| / (|t| sigma) is N(0, 1) at a fixed c without a
//! feature; the feature is reported only when the best SNR reaches a threshold (default 5
//! \[choice\]: the maximum over candidate positions of a noise-only record has at most 9
//! independent looks, so 5 sigma keeps false alarms under ~1e-5).
//!
//! The mirror ambiguity: the nine electrodes are nearly symmetric along the jaw, so a feature
//! and its mirror image about the die's middle read nearly alike. The best fit in the other
//! half along the jaw, at least [`MIRROR_SEPARATION_UM`] from the best (grid, then a compass
//! search kept there), is the second candidate;
//! its residual exceeds the best's by Delta chi^2 = (score_best - score_second) / sigma^2 (the
//! residual is |dV|^2 - score). Below [`AMBIGUITY_CHI2`] the noise cannot tell them apart: both
//! positions are reported and `ambiguous` is set, rather than one confident answer that may be
//! the wrong half.

use serde::Serialize;

use super::cells::UnitResponses;
use super::field::{Background, Disturbance, Shape};
use super::HiddenError;

/// Default detection threshold on the matched-filter SNR \[choice\].
pub const SNR_THRESHOLD: f64 = 5.0;

/// Delta chi^2 under which the best fit and the best in the other half are indistinguishable
/// \[choice\]: 4, a likelihood ratio of e^2 (about 7:1) between them.
pub const AMBIGUITY_CHI2: f64 = 4.0;

/// The second candidate lies at least this far along the jaw from the best (um) \[choice\]:
/// 2 mm, the lump's radius; closer candidates are the same answer.
pub const MIRROR_SEPARATION_UM: f64 = 2000.0;

/// What the voltages say.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Lump,
    Void,
    /// The best fit stays under the threshold.
    NoneDetected,
}

/// The inverse's answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Located {
    pub verdict: Verdict,
    /// Best centre (um, die coordinates); y is None for a cylinder (not observable).
    pub x_um: f64,
    pub y_um: Option<f64>,
    /// Fitted amplitude against the reference feature (1: the reference itself).
    pub amplitude: f64,
    pub snr: f64,
    /// RMS over the channels of dV - a t(c) (mV).
    pub residual_mv: f64,
    /// Template evaluations spent (grid + refinement).
    pub evaluations: usize,
    /// The best fit in the other half along the jaw (x, y um; y None for a cylinder), and how
    /// much worse it fits: Delta chi^2 = (residual^2 sum there - here) / sigma^2.
    pub alternative: Option<(f64, Option<f64>)>,
    pub delta_chi2: Option<f64>,
    /// The alternative is within [`AMBIGUITY_CHI2`]: the noise cannot tell the two apart.
    pub ambiguous: bool,
}

/// How to search.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Search {
    /// Candidate grid step (um).
    pub step_um: f64,
    /// Noise per channel (mV, standard deviation) and the SNR threshold.
    pub noise_mv: f64,
    pub threshold_snr: f64,
}

/// The template and the statistic at one centre.
struct Fit<'a> {
    ur: &'a UnitResponses,
    bg: &'a Background,
    dist: &'a Disturbance,
    dv: &'a [f64],
    evaluations: usize,
}

impl Fit<'_> {
    /// (t . dV, t . t, t) at c.
    fn at(&mut self, c: (f64, f64)) -> (f64, f64, Vec<f64>) {
        self.evaluations += 1;
        let t = self
            .ur
            .voltages_mv(&self.dist.cells(self.bg, &self.ur.grid, c));
        let td: f64 = t.iter().zip(self.dv).map(|(a, b)| a * b).sum();
        let tt: f64 = t.iter().map(|a| a * a).sum();
        (td, tt, t)
    }

    /// The statistic to maximise: (t . dV)^2 / (t . t).
    fn score(&mut self, c: (f64, f64)) -> f64 {
        let (td, tt, _) = self.at(c);
        if tt > 0.0 {
            td * td / tt
        } else {
            0.0
        }
    }
}

/// Locates and classifies the feature behind `dv_mv` (with minus without, the electrodes in
/// `ur.electrodes` order) on the background `bg`, against each reference disturbance in `refs`
/// (a lump's and a void's of the assumed size and depth: their profiles differ, a void's is
/// wider). The reference that explains dV best wins; the verdict is the sign of its amplitude
/// against its own (a negative lump is a void).
pub fn locate(
    ur: &UnitResponses,
    bg: &Background,
    refs: &[&Disturbance],
    dv_mv: &[f64],
    search: Search,
) -> Result<Located, HiddenError> {
    let mut best: Option<(f64, Located)> = None;
    let mut evaluations = 0;
    for d in refs {
        let (score, r) = locate_with(ur, bg, d, dv_mv, search)?;
        evaluations += r.evaluations;
        if best.as_ref().is_none_or(|b| score > b.0) {
            best = Some((score, r));
        }
    }
    let (_, mut r) = best.ok_or(HiddenError::Input {
        problem: "no reference feature".into(),
        hint: "give a lump's and a void's disturbance",
    })?;
    r.evaluations = evaluations;
    Ok(r)
}

/// [`locate`] against one reference; also returns its matched-filter score.
fn locate_with(
    ur: &UnitResponses,
    bg: &Background,
    dist: &Disturbance,
    dv_mv: &[f64],
    search: Search,
) -> Result<(f64, Located), HiddenError> {
    if dv_mv.len() != ur.electrodes.len() || dv_mv.iter().any(|v| !v.is_finite()) {
        return Err(HiddenError::Input {
            problem: format!(
                "{} voltages for {} electrodes",
                dv_mv.len(),
                ur.electrodes.len()
            ),
            hint: "one finite voltage difference (mV) per electrode, in the model's order",
        });
    }
    let (l, w) = (ur.grid.length_um, ur.grid.width_um);
    if !(search.step_um > 0.0 && search.step_um.is_finite())
        || (l / search.step_um) * (w / search.step_um) > 1e5
    {
        return Err(HiddenError::Input {
            problem: format!("candidate step {} um", search.step_um),
            hint: "a step giving at most 100,000 candidates, e.g. 500 um",
        });
    }
    if !(search.noise_mv > 0.0 && search.noise_mv.is_finite()) {
        return Err(HiddenError::Input {
            problem: format!("noise {} mV", search.noise_mv),
            hint: "a positive noise level (mV rms per channel)",
        });
    }
    let mut fit = Fit {
        ur,
        bg,
        dist,
        dv: dv_mv,
        evaluations: 0,
    };
    let cyl = dist.shape == Shape::Cylinder;
    let nx = (l / search.step_um).round().max(1.0) as usize;
    let ny = if cyl {
        0
    } else {
        (w / search.step_um).round().max(1.0) as usize
    };
    let mut best = ((0.5 * l, 0.5 * w), f64::NEG_INFINITY);
    let mut grid = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            let c = (
                l * i as f64 / nx as f64,
                if cyl {
                    0.5 * w
                } else {
                    w * j as f64 / ny as f64
                },
            );
            let s = fit.score(c);
            grid.push((c, s));
            if s > best.1 {
                best = (c, s);
            }
        }
    }
    let best = compass(&mut fit, best, (0.0, l), search.step_um, cyl, w);
    // The other half along the jaw, at least MIRROR_SEPARATION_UM from the best: its best grid
    // candidate, refined inside it (a feature near the middle is not ambiguous with itself).
    let mid = 0.5 * l;
    let x0 = best.0 .0;
    let other = if x0 < mid {
        (mid.max(x0 + MIRROR_SEPARATION_UM), l)
    } else {
        (0.0, mid.min(x0 - MIRROR_SEPARATION_UM))
    };
    let second = grid
        .iter()
        .filter(|(c, _)| c.0 >= other.0 && c.0 <= other.1)
        .fold(None, |a: Option<((f64, f64), f64)>, &(c, s)| match a {
            Some(b) if b.1 >= s => Some(b),
            _ => Some((c, s)),
        })
        .map(|start| compass(&mut fit, start, other, search.step_um, cyl, w));
    let (td, tt, t) = fit.at(best.0);
    let a = if tt > 0.0 { td / tt } else { 0.0 };
    let snr = if tt > 0.0 {
        td.abs() / (tt.sqrt() * search.noise_mv)
    } else {
        0.0
    };
    let residual = (t
        .iter()
        .zip(dv_mv)
        .map(|(ti, di)| (di - a * ti).powi(2))
        .sum::<f64>()
        / t.len().max(1) as f64)
        .sqrt();
    let reference_up = dist.d.first().copied().unwrap_or(0.0) >= 0.0;
    let verdict = if snr < search.threshold_snr {
        Verdict::NoneDetected
    } else if (a > 0.0) == reference_up {
        Verdict::Lump
    } else {
        Verdict::Void
    };
    let delta_chi2 = second.map(|s2| (best.1 - s2.1).max(0.0) / search.noise_mv.powi(2));
    Ok((
        best.1,
        Located {
            verdict,
            x_um: best.0 .0,
            y_um: (!cyl).then_some(best.0 .1),
            amplitude: a,
            snr,
            residual_mv: residual,
            evaluations: fit.evaluations,
            alternative: second.map(|s2| (s2.0 .0, (!cyl).then_some(s2.0 .1))),
            delta_chi2,
            ambiguous: delta_chi2.is_some_and(|d| d < AMBIGUITY_CHI2),
        },
    ))
}

/// Compass search (Kolda, Lewis & Torczon 2003) from `start` = (centre, score), x kept in
/// `xs`, y in [0, w]: halve the step when no direction improves; stops under 1 um.
fn compass(
    fit: &mut Fit<'_>,
    start: ((f64, f64), f64),
    xs: (f64, f64),
    step_um: f64,
    cyl: bool,
    w: f64,
) -> ((f64, f64), f64) {
    let mut best = start;
    let mut h = 0.5 * step_um;
    let dirs: &[(f64, f64)] = if cyl {
        &[(1.0, 0.0), (-1.0, 0.0)]
    } else {
        &[(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
    };
    let cap = fit.evaluations + 100_000;
    while h > 1.0 && fit.evaluations < cap {
        let mut moved = false;
        for d in dirs {
            let c = (
                (best.0 .0 + h * d.0).clamp(xs.0, xs.1),
                (best.0 .1 + h * d.1).clamp(0.0, w),
            );
            let s = fit.score(c);
            if s > best.1 {
                best = (c, s);
                moved = true;
                break;
            }
        }
        if !moved {
            h *= 0.5;
        }
    }
    best
}
