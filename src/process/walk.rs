//! Whole-tree checks no single field rule can make: keys a `--set` path could not address, and
//! non-finite numbers in any float field.

use serde::Serialize;
use serde_yaml::Value;

use super::path::{self, Seg};
use super::schema::Process;

/// Removes every mapping key containing `.` or `[` (a `--set` path could not address it; it is
/// never a field name) and returns each as (parent path, key).
pub fn take_unaddressable_keys(v: &mut Value) -> Vec<(Vec<Seg>, String)> {
    let mut out = Vec::new();
    walk_keys(v, &mut Vec::new(), &mut out);
    out
}

fn walk_keys(v: &mut Value, here: &mut Vec<Seg>, out: &mut Vec<(Vec<Seg>, String)>) {
    match v {
        Value::Mapping(m) => {
            let bad: Vec<Value> = m
                .keys()
                .filter(|k| k.as_str().is_some_and(|k| k.contains(['.', '['])))
                .cloned()
                .collect();
            for k in bad {
                m.remove(&k);
                out.push((here.clone(), k.as_str().unwrap_or_default().to_string()));
            }
            for (k, child) in m.iter_mut() {
                if let Some(k) = k.as_str() {
                    here.push(Seg::Key(k.to_string()));
                    walk_keys(child, here, out);
                    here.pop();
                }
            }
        }
        Value::Sequence(items) => {
            for (i, child) in items.iter_mut().enumerate() {
                here.push(Seg::Index(i));
                walk_keys(child, here, out);
                here.pop();
            }
        }
        Value::Tagged(t) => walk_keys(&mut t.value, here, out),
        _ => {}
    }
}

/// Every float field of the deserialised process that holds NaN or an infinity, by path. The
/// process is serialised and walked, so a float field added to the schema is covered without a
/// rule of its own.
pub fn non_finite(p: &Process) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    collect_non_finite(p, &mut Vec::new(), &mut out);
    for (i, s) in p.steps.iter().enumerate() {
        collect_non_finite(
            s,
            &mut vec![Seg::Key("steps".into()), Seg::Index(i)],
            &mut out,
        );
    }
    out
}

fn collect_non_finite<T: Serialize>(t: &T, base: &mut Vec<Seg>, out: &mut Vec<(String, f64)>) {
    if let Ok(v) = serde_yaml::to_value(t) {
        walk_numbers(&v, base, out);
    }
}

fn walk_numbers(v: &Value, here: &mut Vec<Seg>, out: &mut Vec<(String, f64)>) {
    match v {
        Value::Number(n) => {
            if let Some(x) = n.as_f64().filter(|x| !x.is_finite()) {
                out.push((path::format(here), x));
            }
        }
        Value::Mapping(m) => {
            for (k, child) in m {
                if let Some(k) = k.as_str() {
                    here.push(Seg::Key(k.to_string()));
                    walk_numbers(child, here, out);
                    here.pop();
                }
            }
        }
        Value::Sequence(items) => {
            for (i, child) in items.iter().enumerate() {
                here.push(Seg::Index(i));
                walk_numbers(child, here, out);
                here.pop();
            }
        }
        Value::Tagged(t) => walk_numbers(&t.value, here, out),
        _ => {}
    }
}
