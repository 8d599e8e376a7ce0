//! `--set path=value`: what-if overrides applied to the YAML tree before it is checked.

use serde_yaml::Value;

use super::error::LoadError;
use super::path::{self, Seg};

/// One applied override: the canonical path it resolved to and the argument as typed.
#[derive(Debug, Clone)]
pub struct Applied {
    pub path: String,
    pub arg: String,
    /// The first mapping key the override created (`geometry.x` for `geometry.x.y=1` when the
    /// file has no `x`): every problem inside it is the override's.
    pub created: Option<String>,
}

/// Applies `path=value` overrides in order. A step may be named instead of indexed:
/// `steps.tmah-etch.temp_c=85` is `steps[9].temp_c=85` when step 9 is named `tmah-etch`.
/// The value is parsed as YAML (`85`, `matrix`, `true`, `[a, b]`).
pub fn apply(root: &mut Value, args: &[String]) -> Result<Vec<Applied>, LoadError> {
    let mut applied = Vec::new();
    for arg in args {
        let bad = |message: String| LoadError::BadOverride {
            arg: arg.clone(),
            message,
        };
        let (p, v) = arg
            .split_once('=')
            .ok_or_else(|| bad("missing `=`".into()))?;
        let value: Value =
            serde_yaml::from_str(v).map_err(|e| bad(format!("value is not YAML: {e}")))?;
        let segs = path::parse(p.trim()).map_err(bad)?;
        if segs.is_empty() {
            return Err(bad("empty path".into()));
        }
        let (resolved, created) = set(root, &segs, value).map_err(bad)?;
        applied.push(Applied {
            path: path::format(&resolved),
            arg: arg.clone(),
            created: created.map(|n| path::format(&resolved[..n])),
        });
    }
    Ok(applied)
}

/// Sets the value, creating missing mapping keys; returns the path with step names resolved and
/// how many of its segments lead to the first key it created (if it created one).
fn set(root: &mut Value, segs: &[Seg], value: Value) -> Result<(Vec<Seg>, Option<usize>), String> {
    let mut resolved = Vec::new();
    let mut created = None;
    let mut cur = root;
    for (i, seg) in segs.iter().enumerate() {
        let last = i + 1 == segs.len();
        let seg = match (seg, &*cur) {
            (Seg::Key(name), Value::Sequence(items)) => {
                let idx = items
                    .iter()
                    .position(|it| it.get("name").and_then(Value::as_str) == Some(name.as_str()))
                    .ok_or_else(|| {
                        format!("no element named `{name}` in `{}`", path::format(&resolved))
                    })?;
                Seg::Index(idx)
            }
            (s, _) => s.clone(),
        };
        resolved.push(seg.clone());
        cur = match (seg, cur) {
            (Seg::Key(k), Value::Mapping(m)) => {
                if !m.contains_key(k.as_str()) {
                    created.get_or_insert(resolved.len());
                    let fill = if last {
                        Value::Null
                    } else {
                        Value::Mapping(Default::default())
                    };
                    m.insert(Value::String(k.clone()), fill);
                }
                m.get_mut(k.as_str()).expect("inserted above")
            }
            (Seg::Index(idx), Value::Sequence(s)) => {
                let n = s.len();
                s.get_mut(idx)
                    .ok_or_else(|| format!("index {idx} is out of range (the list has {n})"))?
            }
            (_, other) => {
                let what = match other {
                    Value::Mapping(_) => "a mapping (name a field, not an index)",
                    Value::Sequence(_) => "a list (name an index or a step name)",
                    _ => "a single value, not a mapping or list",
                };
                return Err(format!(
                    "`{}` is {what}",
                    path::format(&resolved[..resolved.len() - 1])
                ));
            }
        };
    }
    *cur = value;
    Ok((resolved, created))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_by_index_name_and_creates_keys() {
        let mut v: Value =
            serde_yaml::from_str("a: {b: 1}\nsteps: [{name: x, t: 1}, {name: y, t: 2}]").unwrap();
        let a = apply(
            &mut v,
            &["a.b=2".into(), "steps.y.t=5".into(), "a.c.d=true".into()],
        )
        .unwrap();
        assert_eq!(a[1].path, "steps[1].t");
        assert_eq!(v["a"]["b"], Value::from(2));
        assert_eq!(v["steps"][1]["t"], Value::from(5));
        assert_eq!(v["a"]["c"]["d"], Value::from(true));
        assert!(apply(&mut v, &["steps.z.t=1".into()]).is_err());
        assert!(apply(&mut v, &["nonsense".into()]).is_err());
    }
}
