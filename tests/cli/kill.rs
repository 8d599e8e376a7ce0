//! Output directories survive SIGKILL: a complete revision A is in DIR, revision B is written
//! into the same DIR and killed at pseudo-random moments; after every kill DIR holds exactly a
//! complete A or a complete B (every file listed in `tactfab.sha256` with its hash, nothing
//! else), the parent holds only the killed process's hidden `.DIR.tactfab-*` directories beside
//! DIR, and the next complete run removes them.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

use super::harness::{command, sha256_hex, REFERENCE};

const MANIFEST: &str = "tactfab.sha256";

/// Kills per command: enough to land before, during and after the write, few enough that the
/// three tests stay within seconds.
const KILLS: usize = 24;

/// splitmix64: the kill moments are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The command line of `sub` writing revision `rev` into `out` (fast options). The build runs
/// without FE scenes: they only add time before the first file is written (3 to 6 s per run of
/// the tooth-base section and one mesh level, 5 minutes over the test's 55 runs), and the kills
/// are to land around the write.
fn args(sub: &str, rev: &str, out: &Path) -> Vec<String> {
    let out = out.to_str().expect("a UTF-8 temp path").to_string();
    let set = format!("device.revision={rev}");
    let mut a: Vec<String> = vec![sub.into(), REFERENCE.into(), "-o".into(), out];
    a.extend(["--set".into(), set]);
    match sub {
        "build" => a.extend(["--set", "checks.scenes=[]"].map(String::from)),
        "traveler" => a.push("--no-fe".into()),
        _ => {}
    }
    a
}

/// Runs `sub` for revision `rev` into `out` to completion (exit 0); how long it took.
fn run_to_end(sub: &str, rev: &str, out: &Path) -> Duration {
    let a = args(sub, rev, out);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let t = Instant::now();
    let o = command(&a).output().expect("run tactfab");
    let took = t.elapsed();
    assert!(
        o.status.success(),
        "tactfab {}: {}\n{}",
        a.join(" "),
        o.status,
        String::from_utf8_lossy(&o.stderr)
    );
    took
}

/// The names in `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The files of a complete output directory (name -> bytes), or what is wrong with it: a missing
/// or unparsable manifest, a listed file missing or with another hash, an entry not listed.
fn complete(dir: &Path) -> Result<BTreeMap<String, Vec<u8>>, String> {
    let rd = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut files = BTreeMap::new();
    for e in rd {
        let e = e.map_err(|e| e.to_string())?;
        let name = e.file_name().to_string_lossy().into_owned();
        if !e.file_type().map_err(|e| e.to_string())?.is_file() {
            return Err(format!("`{name}` is not a file"));
        }
        let bytes = std::fs::read(e.path()).map_err(|e| format!("{name}: {e}"))?;
        files.insert(name, bytes);
    }
    let manifest = files
        .get(MANIFEST)
        .ok_or_else(|| format!("no {MANIFEST} among {:?}", files.keys().collect::<Vec<_>>()))?;
    let manifest = String::from_utf8(manifest.clone()).map_err(|e| e.to_string())?;
    let mut listed = BTreeSet::new();
    for line in manifest.lines() {
        let (hash, name) = line
            .split_once("  ")
            .ok_or_else(|| format!("manifest line `{line}` is not `<sha256>  <name>`"))?;
        let bytes = files
            .get(name)
            .ok_or_else(|| format!("`{name}` is listed but missing"))?;
        if sha256_hex(bytes) != hash {
            return Err(format!(
                "`{name}` ({} bytes) does not match its hash",
                bytes.len()
            ));
        }
        listed.insert(name.to_string());
    }
    let extra: Vec<&String> = files
        .keys()
        .filter(|n| *n != MANIFEST && !listed.contains(*n))
        .collect();
    if !extra.is_empty() {
        return Err(format!("not listed in the manifest: {extra:?}"));
    }
    Ok(files)
}

/// The kill test of one subcommand; `seed` fixes the kill moments.
fn survives_kills(sub: &str, seed: u64) {
    let refs = tempfile::tempdir().unwrap();
    let (ref_a, ref_b) = (refs.path().join("a"), refs.path().join("b"));
    run_to_end(sub, "A", &ref_a);
    // The duration of a B run over an existing B (the case under test), the shortest of five.
    let took = (0..5).map(|_| run_to_end(sub, "B", &ref_b)).min().unwrap();
    let a = complete(&ref_a).unwrap_or_else(|e| panic!("{sub}: reference A: {e}"));
    let b = complete(&ref_b).unwrap_or_else(|e| panic!("{sub}: reference B: {e}"));
    assert_ne!(a, b, "{sub}: revisions A and B must differ in their bytes");

    let work = tempfile::tempdir().unwrap();
    let dir = work.path().join("out");
    run_to_end(sub, "A", &dir);
    let mut rng = Rng(seed);
    let (mut landed_a, mut landed_b, mut finished, mut with_leftovers) = (0, 0, 0, 0);
    let mut failures = Vec::new();
    for k in 0..KILLS {
        // One in three anywhere in up to 1.2 times the run (some come too late and the run
        // completes), one in its second half, one up to 0.5 ms after the temporary directory
        // appeared (while the files are written and swapped).
        let u = rng.unit();
        let (delay, when_tmp) = match k % 3 {
            0 => (took.mul_f64(1.2 * u), false),
            1 => (took.mul_f64(0.5 + 0.5 * u), false),
            _ => (Duration::from_micros((500.0 * u) as u64), true),
        };
        let a_args = args(sub, "B", &dir);
        let a_args: Vec<&str> = a_args.iter().map(String::as_str).collect();
        let mut child = command(&a_args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn tactfab");
        let pid = child.id();
        if when_tmp {
            let tmp = work.path().join(format!(".out.tactfab-tmp-{pid}"));
            let t = Instant::now();
            let mut polls = 0u32;
            while !tmp.exists() && t.elapsed() < 10 * took {
                polls += 1;
                if polls.is_multiple_of(256) && child.try_wait().unwrap().is_some() {
                    break;
                }
            }
        }
        std::thread::sleep(delay);
        let _ = child.kill(); // SIGKILL; an error means it had exited already
        let status = child.wait().expect("reap tactfab");
        let what = format!(
            "{sub}: kill {k} {delay:?} after {} (pid {pid}, {status})",
            if when_tmp {
                "the temporary directory appeared"
            } else {
                "the start"
            }
        );
        match complete(&dir) {
            Ok(got) if got == a => landed_a += 1,
            Ok(got) if got == b => landed_b += 1,
            Ok(got) => failures.push(format!(
                "{what}: DIR is complete but neither A nor B: {:?}",
                got.keys().collect::<Vec<_>>()
            )),
            Err(e) => failures.push(format!("{what}: DIR is torn: {e}")),
        }
        if status.success() {
            finished += 1;
            if complete(&dir).ok().as_ref() != Some(&b) {
                failures.push(format!("{what}: exit 0 but DIR is not B"));
            }
        }
        let mine = [
            format!(".out.tactfab-tmp-{pid}"),
            format!(".out.tactfab-old-{pid}"),
        ];
        let others: Vec<String> = entries(work.path())
            .into_iter()
            .filter(|n| n != "out")
            .collect();
        if !others.is_empty() {
            with_leftovers += 1;
        }
        for n in &others {
            if !mine.contains(n) {
                failures.push(format!("{what}: unexpected entry `{n}` beside DIR"));
            }
        }
        // The next complete run (back to A) replaces DIR and removes the dead run's leftovers.
        if complete(&dir).is_err() {
            // A torn DIR would be refused as foreign: start over so the test can go on.
            let _ = std::fs::remove_dir_all(&dir);
        }
        run_to_end(sub, "A", &dir);
        if complete(&dir).ok().as_ref() != Some(&a) {
            failures.push(format!("{what}: the run after the kill did not leave A"));
        }
        let left = entries(work.path());
        if left != ["out"] {
            failures.push(format!(
                "{what}: the run after the kill left {left:?} beside DIR"
            ));
            for n in left.iter().filter(|n| *n != "out") {
                let _ = std::fs::remove_dir_all(work.path().join(n));
            }
        }
    }
    eprintln!(
        "kill {sub}: {KILLS} kills over {took:?} runs: {landed_a} left A, {landed_b} left B \
         ({finished} had finished), {with_leftovers} left hidden directories beside DIR"
    );
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert_eq!(landed_a + landed_b, KILLS);
}

#[test]
fn build_killed_leaves_a_or_b() {
    survives_kills("build", 0xb011d);
}

#[test]
fn masks_killed_leaves_a_or_b() {
    survives_kills("masks", 0x3a5c5);
}

#[test]
fn traveler_killed_leaves_a_or_b() {
    survives_kills("traveler", 0x7a4e1);
}
