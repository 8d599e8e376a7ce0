//! Splitting the sweep into shards (a scheduler job array), the CSV format and the merge step.
//!
//! Shard i of n (1-based, like `SLURM_ARRAY_TASK_ID` with `--array=1-n`) takes the contiguous index
//! range [N (i-1) / n, N i / n). Each shard writes `sweep-i-of-n.csv`: the same header and the same
//! fixed-format rows as the unsharded `sweep.csv`, so the merge is a checked concatenation and
//! gives the unsharded file byte for byte.

use std::path::{Path, PathBuf};

use crate::sweep::design::Design;
use crate::sweep::run::Row;
use crate::sweep::SweepError;

/// Shard i of n (1 <= i <= n).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// Parse "i/n".
    pub fn parse(text: &str) -> Result<Self, SweepError> {
        let bad = || SweepError::BadShard {
            text: text.to_string(),
            hint: "expected i/n with 1 <= i <= n, e.g. --shard 3/8",
        };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if count == 0 || index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
    /// Design indices of this shard out of `total` (in 128 bits: i and n as large as `usize`
    /// lose no design to overflow).
    pub fn range(&self, total: usize) -> std::ops::Range<usize> {
        let at = |i: usize| (total as u128 * i as u128 / self.count as u128) as usize;
        at(self.index - 1)..at(self.index)
    }
    /// `sweep-i-of-n.csv`.
    pub fn file_name(&self) -> String {
        format!("sweep-{}-of-{}.csv", self.index, self.count)
    }
}

/// Name of the unsharded CSV.
pub const UNSHARDED: &str = "sweep.csv";

/// The prototype the family is matched against, written by every run (shards write the same
/// bytes) so a merge can mark it on the plot as the unsharded run does.
pub const PROTOTYPE: &str = "sweep-prototype.csv";

/// [`PROTOTYPE`]'s header (units in the names).
pub const PROTOTYPE_HEADER: &str = "length_um,width_um,thickness_um";

/// [`PROTOTYPE`]'s text: one design, units in the header.
pub fn prototype_csv(d: &Design) -> String {
    format!(
        "{PROTOTYPE_HEADER}\n{:.3},{:.3},{:.3}\n",
        d.length_um, d.width_um, d.thickness_um
    )
}

/// The prototype a sweep in `dir` wrote, if it wrote one (older shards did not).
pub fn read_prototype(dir: &Path) -> Result<Option<Design>, SweepError> {
    let path = dir.join(PROTOTYPE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(cause) => return Err(SweepError::Io { path, cause }),
    };
    let v: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap_or("")
        .split(',')
        .filter_map(|x| x.parse().ok())
        .collect();
    match v.as_slice() {
        [l, w, t] if v.iter().all(|x| x.is_finite() && *x > 0.0) => Ok(Some(Design {
            index: usize::MAX,
            length_um: *l,
            width_um: *w,
            thickness_um: *t,
        })),
        _ => Err(SweepError::Merge {
            detail: format!("{}: not length_um,width_um,thickness_um", path.display()),
            hint: "rerun one shard to rewrite it",
        }),
    }
}

/// CSV header (units in the names).
pub const HEADER: &str = "index,length_um,width_um,thickness_um,deflection_um,elongation_um,\
                          max_stress_mpa,elongation_ratio,matches,within_strength";

/// The CSV text of rows (fixed decimals, index order as given).
pub fn csv(rows: &[Row]) -> String {
    let mut s = String::with_capacity(96 * (rows.len() + 1));
    s.push_str(HEADER);
    s.push('\n');
    for r in rows {
        let (d, p) = (&r.design, &r.response);
        s.push_str(&format!(
            "{},{:.3},{:.3},{:.3},{:.4},{:.4},{:.3},{:.6},{},{}\n",
            d.index,
            d.length_um,
            d.width_um,
            d.thickness_um,
            p.deflection_um,
            p.elongation_um,
            p.max_stress_mpa,
            r.elongation_ratio,
            u8::from(r.matches),
            u8::from(r.within_strength)
        ));
    }
    s
}

/// A merged sweep: the CSV bytes and the designs of the matching family.
#[derive(Debug, Clone)]
pub struct Merged {
    pub csv: String,
    pub total: usize,
    pub family: Vec<Design>,
}

fn shard_files(dir: &Path) -> Result<Vec<(Shard, PathBuf)>, SweepError> {
    let io = |cause| SweepError::Io {
        path: dir.to_path_buf(),
        cause,
    };
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let entry = entry.map_err(io)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(core) = name
            .strip_prefix("sweep-")
            .and_then(|n| n.strip_suffix(".csv"))
        else {
            continue;
        };
        let Some((i, n)) = core.split_once("-of-") else {
            continue;
        };
        if let (Ok(index), Ok(count)) = (i.parse(), n.parse()) {
            out.push((Shard { index, count }, entry.path()));
        }
    }
    out.sort_by_key(|(s, _)| (s.count, s.index));
    Ok(out)
}

/// Checks one row: every field a number of its column's kind (the flags 0 or 1), and the family
/// flag agrees with `tol` wherever the 6-decimal ratio decides it.
fn check_row(f: &[&str], tol: f64) -> Result<(), String> {
    for (j, v) in f.iter().enumerate() {
        let ok = match j {
            0 => v.parse::<usize>().is_ok(),
            8 | 9 => *v == "0" || *v == "1",
            _ => v.parse::<f64>().is_ok_and(f64::is_finite),
        };
        if !ok {
            let column = HEADER.split(',').nth(j).unwrap_or("?");
            return Err(format!("`{v}` is not a valid {column}"));
        }
    }
    let off = (f[7].parse::<f64>().unwrap_or(f64::NAN) - 1.0).abs();
    if (off - tol).abs() > 1e-6 && (off <= tol) != (f[8] == "1") {
        return Err(format!(
            "`matches` is {} but the elongation ratio {} is {} the tolerance {tol}: the shards ran \
             with another --tol",
            f[8],
            f[7],
            if off <= tol { "within" } else { "beyond" }
        ));
    }
    Ok(())
}

/// Merge `DIR/sweep-i-of-n.csv` (all i = 1..n, one n) into the unsharded CSV, checking the headers,
/// every value, that the indices run 0, 1, ... without gaps or repeats, and that the family was
/// chosen with `tol`.
pub fn merge_dir(dir: &Path, tol: f64) -> Result<Merged, SweepError> {
    let files = shard_files(dir)?;
    let Some(&(first, _)) = files.first() else {
        return Err(SweepError::Merge {
            detail: format!("no sweep-i-of-n.csv files in {}", dir.display()),
            hint: "run `tactfab sweep FILE -o DIR --shard i/n` for every i first",
        });
    };
    let n = first.count;
    if files.iter().any(|(s, _)| s.count != n) {
        return Err(SweepError::Merge {
            detail: "shard files with different n".into(),
            hint: "keep one sweep's shards per directory",
        });
    }
    let have: Vec<usize> = files.iter().map(|(s, _)| s.index).collect();
    if have != (1..=n).collect::<Vec<_>>() {
        let missing: Vec<String> = (1..=n)
            .filter(|i| !have.contains(i))
            .map(|i| format!("{i}/{n}"))
            .collect();
        return Err(SweepError::Merge {
            detail: format!("missing shards {}", missing.join(", ")),
            hint: "rerun the missing array tasks",
        });
    }
    let mut csv = format!("{HEADER}\n");
    let mut next = 0usize;
    let mut family = Vec::new();
    for (s, path) in &files {
        let text = std::fs::read_to_string(path).map_err(|cause| SweepError::Io {
            path: path.clone(),
            cause,
        })?;
        let mut lines = text.lines();
        if lines.next() != Some(HEADER) {
            return Err(SweepError::Merge {
                detail: format!("{}: header differs", path.display()),
                hint: "all shards must come from the same tactfab version",
            });
        }
        for (k, line) in lines.enumerate() {
            let f: Vec<&str> = line.split(',').collect();
            let index: Option<usize> = f.first().and_then(|v| v.parse().ok());
            if f.len() != HEADER.split(',').count() || index != Some(next) {
                return Err(SweepError::Merge {
                    detail: format!(
                        "{}:{}: expected design {next} ({} of shard {}/{})",
                        path.display(),
                        k + 2,
                        f.len(),
                        s.index,
                        s.count
                    ),
                    hint: "a shard file is truncated or from another sweep: rerun that shard",
                });
            }
            if let Err(why) = check_row(&f, tol) {
                return Err(SweepError::Merge {
                    detail: format!("{}:{}: {why}", path.display(), k + 2),
                    hint: "rerun that shard, or merge with the --tol the shards ran with",
                });
            }
            if f[8] == "1" {
                let num = |j: usize| f[j].parse::<f64>().unwrap_or(f64::NAN);
                family.push(Design {
                    index: next,
                    length_um: num(1),
                    width_um: num(2),
                    thickness_um: num(3),
                });
            }
            csv.push_str(line);
            csv.push('\n');
            next += 1;
        }
    }
    Ok(Merged {
        csv,
        total: next,
        family,
    })
}

/// Designs of the family in rows (for the plot of an unsharded run).
pub fn family(rows: &[Row]) -> Vec<Design> {
    rows.iter()
        .filter(|r| r.matches)
        .map(|r| r.design)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{DieEdge, PlateMaterial};
    use crate::sweep::design::{DesignModel, Grid, MeshSpec, Range};
    use crate::sweep::run::{run_range, Matching, Mode};

    #[test]
    fn huge_shard_numbers_lose_no_design() {
        let n = usize::MAX;
        let parts: usize = [1, 2, n - 1, n]
            .iter()
            .map(|&i| Shard { index: i, count: n }.range(1000).len())
            .sum();
        assert!(parts <= 1000);
        let all: usize = (1..=7)
            .map(|i| Shard { index: i, count: 7 }.range(usize::MAX / 3).len())
            .sum();
        assert_eq!(all, usize::MAX / 3);
    }

    #[test]
    fn parse_and_ranges_partition() {
        assert_eq!(Shard::parse("2/5").unwrap(), Shard { index: 2, count: 5 });
        for bad in ["0/3", "4/3", "1/0", "a/2", "3", "1/2/3"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
        for total in [0usize, 1, 7, 15_000] {
            for n in [1usize, 3, 8] {
                let mut next = 0;
                for i in 1..=n {
                    let r = Shard { index: i, count: n }.range(total);
                    assert_eq!(r.start, next);
                    next = r.end;
                }
                assert_eq!(next, total);
            }
        }
    }

    /// A 3 x 3 x 2 grid in 4 shards merges to the unsharded CSV byte for byte; runs are
    /// deterministic; a missing shard is an error naming it.
    #[test]
    fn shards_merge_to_the_unsharded_bytes() {
        let grid = Grid {
            length_um: Range {
                lo: 20_000.0,
                hi: 35_000.0,
                steps: 3,
            },
            width_um: Range {
                lo: 12_000.0,
                hi: 18_000.0,
                steps: 3,
            },
            thickness_um: Range {
                lo: 90.0,
                hi: 110.0,
                steps: 2,
            },
        };
        let model = DesignModel {
            material: PlateMaterial::silicon(DieEdge::Along110),
            force_n: 4.0,
            contact_radius_um: 250.0,
            mesh: MeshSpec::standard(),
        };
        let proto = crate::sweep::Design {
            index: 0,
            length_um: 30_000.0,
            width_um: 15_000.0,
            thickness_um: 100.0,
        };
        let matching = Matching::new(proto, &model, 0.2, 4000.0 / 3.0).unwrap();
        let all = run_range(
            &grid,
            &model,
            &matching,
            0..grid.len(),
            Mode::ScaledThickness,
            &|_| {},
        )
        .unwrap();
        let whole = csv(&all);
        assert_eq!(
            whole,
            csv(&run_range(
                &grid,
                &model,
                &matching,
                0..grid.len(),
                Mode::ScaledThickness,
                &|_| {}
            )
            .unwrap())
        );
        // The direct per-design path agrees with the thickness scaling (same CSV text at its
        // precision).
        let direct = run_range(
            &grid,
            &model,
            &matching,
            0..grid.len(),
            Mode::Direct,
            &|_| {},
        )
        .unwrap();
        for (a, b) in all.iter().zip(&direct) {
            assert!(
                (a.response.elongation_um / b.response.elongation_um - 1.0).abs() < 1e-8,
                "{a:?} {b:?}"
            );
            assert!(
                (a.response.max_stress_mpa / b.response.max_stress_mpa - 1.0).abs() < 1e-8,
                "{a:?} {b:?}"
            );
        }
        assert!(all.iter().any(|r| r.matches) && all.iter().any(|r| !r.matches));
        let dir = tempfile::tempdir().unwrap();
        let n = 4; // 18 designs in 4 shards: cuts fall inside thickness groups
        for i in (1..=n).rev() {
            let s = Shard { index: i, count: n };
            let rows = run_range(
                &grid,
                &model,
                &matching,
                s.range(grid.len()),
                Mode::ScaledThickness,
                &|_| {},
            )
            .unwrap();
            std::fs::write(dir.path().join(s.file_name()), csv(&rows)).unwrap();
        }
        let merged = merge_dir(dir.path(), 0.2).unwrap();
        assert_eq!(merged.csv, whole);
        assert_eq!(merged.total, grid.len());
        assert_eq!(
            merged.family.len(),
            all.iter().filter(|r| r.matches).count()
        );
        // Another tolerance than the shards': the family flags contradict it.
        let e = merge_dir(dir.path(), 0.01).unwrap_err().to_string();
        assert!(e.contains("another --tol"), "{e}");
        // A value that is not a number is refused, not copied.
        let third = dir.path().join("sweep-3-of-4.csv");
        let text = std::fs::read_to_string(&third).unwrap();
        let bad = text.replacen(",0,", ",x,", 1).replacen(",1,", ",x,", 1);
        std::fs::write(&third, bad).unwrap();
        let e = merge_dir(dir.path(), 0.2).unwrap_err().to_string();
        assert!(e.contains("`x` is not a valid"), "{e}");
        std::fs::remove_file(&third).unwrap();
        let e = merge_dir(dir.path(), 0.2).unwrap_err().to_string();
        assert!(e.contains("missing shards 3/4"), "{e}");
    }
}
