//! `tactfab readout` on the bundled process file: the CSV's header and rows, the voltages against
//! first-order closed forms computed here (the grasp's closing half sine, its held decay, the
//! steady 5 Hz sine), determinism, and bad input (exit 2, nothing written).

use std::f64::consts::PI;
use std::path::Path;

use super::harness::{tactfab, REFERENCE};

/// The CSV as (header, rows of numbers).
fn csv(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("readout.csv")).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// A number from the electrode table of the text output: `column` of electrode `name`'s row.
fn table(stdout: &str, name: &str, column: usize) -> f64 {
    stdout
        .lines()
        .find(|l| l.trim_start().starts_with(&format!("{name} ")))
        .and_then(|l| l.split_whitespace().nth(column))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no {name} column {column} in\n{stdout}"))
}

#[test]
fn half_sine_grasp_rises_as_the_closed_form_then_decays_as_exp() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ro");
    let r = tactfab(&["readout", REFERENCE, "-o", out.to_str().unwrap()]);
    r.expect_code(0);
    let (head, rows) = csv(&out);
    assert_eq!(
        head.join(","),
        "t_s,F_n,V_S11_v,V_S12_v,V_S13_v,V_M1_v,V_M2_v,V_M3_v,V_S21_v,V_S22_v,V_S23_v"
    );
    // 5 s every 1 ms.
    assert_eq!(rows.len(), 5001);
    assert!(rows.iter().all(|r| r.len() == 11));
    assert!((rows[5000][0] - 5.0).abs() < 1e-9 && (rows[5000][1] - 1.0).abs() < 1e-12);
    // The default charge amplifier: C_f 1 nF, R_f 10 GΩ.
    let tau = 10.0;
    assert!(r.stdout.contains("corner f_c 1.5915e-2 Hz"), "{}", r.stdout);
    let m2 = head.iter().position(|h| h == "V_M2_v").unwrap();
    let gain = table(&r.stdout, "M2", 3);
    // -Q / C_f: M2's charge per newton over 1 nF, inverted.
    let s_pc = table(&r.stdout, "M2", 1);
    assert!((gain + s_pc * 1e-12 / 1e-9).abs() < 1e-6, "{gain} {s_pc}");
    // Closing, F = sin(pi t): y(t) = pi [cos(pi t) / tau + pi sin(pi t) - e^(-t/tau) / tau] /
    // (1/tau^2 + pi^2) (variation of constants for y' + y / tau = F').
    let closing = |t: f64| {
        PI * ((PI * t).cos() / tau + PI * (PI * t).sin() - (-t / tau).exp() / tau)
            / (1.0 / (tau * tau) + PI * PI)
    };
    for k in [100, 250, 500] {
        let (t, v) = (rows[k][0], rows[k][m2]);
        let want = gain * closing(t);
        assert!((v / want - 1.0).abs() < 1e-5, "t {t}: {v} vs {want}");
    }
    // Held from 0.5 s: e^(-(t - 0.5) / tau) (the CSV keeps 7 significant digits).
    let held = rows[500][m2];
    for k in [1000, 3000, 5000] {
        let (t, v) = (rows[k][0], rows[k][m2]);
        let want = held * (-(t - 0.5) / tau).exp();
        assert!((v / want - 1.0).abs() < 1e-6, "t {t}: {v} vs {want}");
    }
    assert!(
        r.stdout.contains("held grasp: M2") && r.stdout.contains("63.76 % left"),
        "{}",
        r.stdout
    );
    super::harness::assert_svgs_fit(&out);
    // The same input gives the same bytes.
    let again = dir.path().join("again");
    tactfab(&["readout", REFERENCE, "-o", again.to_str().unwrap()]).expect_code(0);
    for f in ["readout.csv", "readout.svg"] {
        assert_eq!(
            std::fs::read(out.join(f)).unwrap(),
            std::fs::read(again.join(f)).unwrap()
        );
    }
}

#[test]
fn the_5hz_sine_settles_to_the_first_order_gain() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ro");
    // R_f 10 MΩ: tau = 10 ms, omega tau = 0.314, so the test sine is attenuated to 30 %.
    let r = tactfab(&[
        "readout",
        REFERENCE,
        "-o",
        out.to_str().unwrap(),
        "--history",
        "sine-5hz",
        "--dt-ms",
        "0.1",
        "--x-mm",
        "10",
        "--y-mm",
        "6",
        "--set",
        "readout.feedback_resistance_gohm=0.01",
    ]);
    r.expect_code(0);
    let (head, rows) = csv(&out);
    let m1 = head.iter().position(|h| h == "V_M1_v").unwrap();
    let gain = table(&r.stdout, "M1", 3);
    let wt = 2.0 * PI * 5.0 * 0.01;
    let amplitude = gain.abs() * wt / (1.0 + wt * wt).sqrt();
    // The last cycle (0.8-1 s, 80 tau after the start).
    let peak = rows
        .iter()
        .filter(|r| r[0] >= 0.8)
        .map(|r| r[m1].abs())
        .fold(0.0, f64::max);
    assert!(
        (peak / amplitude - 1.0).abs() < 1e-4,
        "{peak} vs {amplitude}"
    );
    // Phase: the output leads the force by atan(1 / (omega tau)); at the force's upward zero
    // crossing (t = 0.8 s) the output is amplitude * sin(lead) (sign of the gain).
    let at = rows.iter().find(|r| (r[0] - 0.8).abs() < 1e-9).unwrap()[m1];
    let want = gain.signum() * amplitude * (1.0 / wt).atan().sin();
    assert!((at / want - 1.0).abs() < 1e-3, "{at} vs {want}");
}

#[test]
fn bad_input_is_exit_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ro");
    let o = out.to_str().unwrap();
    for (args, says) in [
        (vec!["--x-mm", "40"], "--x-mm"),
        (vec!["--dt-ms", "0"], "--dt-ms"),
        (vec!["--history", "square"], "--history"),
        (
            vec!["--set", "readout.feedback_capacitance_pf=-1"],
            "readout.feedback_capacitance_pf",
        ),
        (
            vec!["--set", "readout.front_end=voltage"],
            "readout.front_end",
        ),
        (vec!["--duration-s", "3000", "--dt-ms", "0.001"], "2000000"),
    ] {
        let mut a = vec!["readout", REFERENCE, "-o", o];
        a.extend(&args);
        let r = tactfab(&a);
        r.expect_code(2);
        assert!(r.stderr.contains(says), "{args:?}: {}", r.stderr);
        assert!(!out.exists(), "{args:?} wrote {o}");
    }
}
