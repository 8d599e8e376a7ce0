//! Deserialisation that reports every structural problem, not just the first.
//!
//! serde stops at the first error. We retry: each error is recorded, then the offending node is
//! removed (unknown field) or replaced by a placeholder of the expected type (wrong type, missing
//! field), and errors inside a replaced node are suppressed as consequences of the first.

use serde::de::DeserializeOwned;
use serde_yaml::{Mapping, Value};

use super::path::{self, Seg};

/// A structural problem before locations are attached.
#[derive(Debug, Clone)]
pub struct RawProblem {
    pub path: String,
    /// Set for unknown fields: point at the key, not the value.
    pub key_of_parent: Option<(String, String)>,
    pub message: String,
    pub expected: String,
    pub hint: String,
}

/// Deserialisation attempts per call: each finds one problem, so this bounds the problems one
/// section can report (and the work a pathological file can cause).
const MAX_ROUNDS: usize = 2000;

/// Deserialises `value` as `T`, collecting all problems under `base`.
/// Returns the value with placeholders where problems were (so range rules can still run on the
/// rest); `placeholders` receives the paths that hold one. `None` when no placeholder fits.
pub fn deserialize_all<T: DeserializeOwned>(
    mut value: Value,
    base: &str,
    problems: &mut Vec<RawProblem>,
    placeholders: &mut Vec<String>,
) -> Option<T> {
    let mut suppressed: Vec<String> = Vec::new();
    for _ in 0..MAX_ROUNDS {
        let err = match serde_path_to_error::deserialize::<_, T>(value.clone()) {
            Ok(t) => {
                placeholders.extend(suppressed);
                return Some(t);
            }
            Err(e) => e,
        };
        let rel = err.path().to_string();
        let msg = err.inner().to_string();
        let segs = match path::parse(&rel) {
            Ok(s) => s,
            Err(_) => {
                problems.push(raw(path::join(base, &rel), msg, String::new()));
                return None;
            }
        };
        let is_suppressed = |p: &str| suppressed.iter().any(|s| path::is_within(p, s));

        if let Some(field) = between(&msg, "unknown field `", "`") {
            // serde_path_to_error reports the unknown key's own path.
            let parent = if segs.last() == Some(&Seg::Key(field.clone())) {
                &segs[..segs.len() - 1]
            } else {
                &segs[..]
            };
            let full = path::join(base, &path::format(&with_key(parent, &field)));
            if !is_suppressed(&full) {
                problems.push(unknown_field(&msg, &field, full, base, parent));
            }
            match path::get_mut(&mut value, parent) {
                Some(Value::Mapping(m)) => {
                    m.remove(field.as_str());
                }
                _ => return None,
            }
            continue;
        }
        if let Some(field) = between(&msg, "missing field `", "`") {
            let here = with_key(&segs, &field);
            let full = path::join(base, &path::format(&here));
            if !is_suppressed(&full) {
                problems.push(raw(
                    full.clone(),
                    format!("missing field `{field}`"),
                    "it to be present".into(),
                ));
            }
            suppressed.push(full);
            let parent = path::get_mut(&mut value, &segs)?;
            // An empty section (`geometry:`) is null: serde reads it as a mapping with every
            // field missing, so fill it in as one and report each missing field.
            if parent.is_null() {
                *parent = Value::Mapping(Mapping::new());
            }
            match parent {
                Value::Mapping(m) => {
                    m.insert(Value::String(field), Value::Null);
                }
                _ => return None,
            }
            continue;
        }
        // Wrong type or value at `rel`.
        let full = path::join(base, &rel);
        let expected = msg
            .split_once(", expected ")
            .map(|(_, e)| e.to_string())
            .unwrap_or_default();
        if !is_suppressed(&full) {
            problems.push(wrong_type(&msg, &expected, full.clone()));
        }
        suppressed.push(full);
        let slot = path::get_mut(&mut value, &segs)?;
        match placeholder(&expected, slot) {
            Some(v) => *slot = v,
            None => return None,
        }
    }
    None
}

/// The problem of an unknown `field` in the mapping at `parent`, from serde's message.
fn unknown_field(msg: &str, field: &str, full: String, base: &str, parent: &[Seg]) -> RawProblem {
    let allowed = msg
        .split_once(", expected ")
        .map(|(_, e)| e.to_string())
        .unwrap_or_default();
    let names: Vec<String> = allowed
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    RawProblem {
        path: full,
        hint: String::new(),
        key_of_parent: Some((path::join(base, &path::format(parent)), field.to_string())),
        message: format!("unknown field `{field}`{}", did_you_mean(field, &names)),
        expected: if allowed.is_empty() {
            "no fields here".into()
        } else {
            allowed
        },
    }
}

/// The problem of a value of the wrong type or an unknown variant at `full`.
fn wrong_type(msg: &str, expected: &str, full: String) -> RawProblem {
    let what = msg
        .split_once(", expected ")
        .map(|(w, _)| w.to_string())
        .unwrap_or(msg.to_string());
    let variants: Vec<String> = expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    let hint = between(&what, "unknown variant `", "`")
        .map(|v| did_you_mean(&v, &variants))
        .unwrap_or_default();
    raw(full, format!("{what}{hint}"), readable(expected))
}

/// ` (did you mean `x`?)` when one allowed name is within two edits of `got`.
pub fn did_you_mean(got: &str, allowed: &[String]) -> String {
    allowed
        .iter()
        .map(|a| (edit_distance(got, a), a))
        .filter(|(d, _)| *d <= 2)
        .min()
        .map(|(_, a)| format!(" (did you mean `{a}`?)"))
        .unwrap_or_default()
}

/// Levenshtein distance (Wagner-Fischer).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// serde's type names in words a process engineer reads.
fn readable(expected: &str) -> String {
    match expected {
        "f64" | "f32" => "a number".into(),
        "u32" | "u16" | "u64" | "usize" => "a whole number >= 0".into(),
        "a boolean" => "true or false".into(),
        e if e.starts_with("struct ") => format!("a mapping ({})", &e[7..]),
        e => e.to_string(),
    }
}

fn raw(path: String, message: String, expected: String) -> RawProblem {
    RawProblem {
        path,
        key_of_parent: None,
        message,
        expected,
        hint: String::new(),
    }
}

fn with_key(segs: &[Seg], key: &str) -> Vec<Seg> {
    let mut v = segs.to_vec();
    v.push(Seg::Key(key.to_string()));
    v
}

fn between(s: &str, start: &str, end: &str) -> Option<String> {
    let i = s.find(start)? + start.len();
    let j = s[i..].find(end)? + i;
    Some(s[i..j].to_string())
}

/// A value of the type serde expected, so the remaining fields can still be checked.
fn placeholder(expected: &str, current: &Value) -> Option<Value> {
    let e = expected;
    if let Some(first) = between(e, "`", "`") {
        // An enum: "`a`, `b` or `c`" / "one of `a`, ...".
        if current.as_str() != Some(first.as_str()) {
            return Some(Value::String(first));
        }
    }
    // NaN makes every cross-field comparison with this field false: no consequential errors.
    if e.contains("f64") || e.contains("f32") || e.contains("number") {
        return Some(Value::Number(f64::NAN.into()));
    }
    if e.contains("u32")
        || e.contains("u16")
        || e.contains("usize")
        || e.contains("i64")
        || e.contains("u64")
        || e.contains("i32")
        || e.contains("integer")
    {
        return Some(Value::Number(0.into()));
    }
    if e.contains("string") {
        return Some(Value::String(String::new()));
    }
    if e.contains("bool") {
        return Some(Value::Bool(false));
    }
    if e.contains("sequence") {
        return Some(Value::Sequence(Vec::new()));
    }
    if e.contains("struct") || e.contains("map") {
        return Some(Value::Mapping(Mapping::new()));
    }
    if e.contains("enum") && !current.is_string() {
        // Unit enum given as a non-string: try a string; the next round names the variants.
        return Some(Value::String(String::new()));
    }
    None
}
