//! Field paths (`steps[3].depth_um`, `geometry.teeth.pattern`) over YAML values and marked nodes.

use serde_yaml::Value;

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// Parses `a.b[2].c` into segments; `.` or empty is the document root.
pub fn parse(path: &str) -> Result<Vec<Seg>, String> {
    let mut segs = Vec::new();
    if path.is_empty() || path == "." {
        return Ok(segs);
    }
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if key.is_empty() && rest.is_empty() {
            return Err(format!("empty segment in `{path}`"));
        }
        if !key.is_empty() {
            segs.push(Seg::Key(key.to_string()));
        }
        while !rest.is_empty() {
            let close = rest
                .find(']')
                .ok_or_else(|| format!("unclosed `[` in `{path}`"))?;
            let idx: usize = rest[1..close]
                .parse()
                .map_err(|_| format!("`{}` is not an index in `{path}`", &rest[1..close]))?;
            segs.push(Seg::Index(idx));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(format!("unexpected `{rest}` in `{path}`"));
            }
        }
    }
    Ok(segs)
}

/// Formats segments back into the canonical path string.
pub fn format(segs: &[Seg]) -> String {
    let mut s = String::new();
    for seg in segs {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    if s.is_empty() {
        ".".into()
    } else {
        s
    }
}

/// Joins a base path and a relative one (serde_path_to_error's `.` means "here").
pub fn join(base: &str, rel: &str) -> String {
    match (base, rel) {
        ("." | "", r) => r.to_string(),
        (b, "." | "") => b.to_string(),
        (b, r) if r.starts_with('[') => format!("{b}{r}"),
        (b, r) => format!("{b}.{r}"),
    }
}

/// True when `path` is `prefix` or lies inside it.
pub fn is_within(path: &str, prefix: &str) -> bool {
    prefix == "."
        || path == prefix
        || path
            .strip_prefix(prefix)
            .is_some_and(|r| r.starts_with('.') || r.starts_with('['))
}

pub fn get_mut<'a>(root: &'a mut Value, segs: &[Seg]) -> Option<&'a mut Value> {
    let mut cur = root;
    for seg in segs {
        cur = match (seg, cur) {
            (Seg::Key(k), Value::Mapping(m)) => m.get_mut(k.as_str())?,
            (Seg::Index(i), Value::Sequence(s)) => s.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

pub fn get<'a>(root: &'a Value, segs: &[Seg]) -> Option<&'a Value> {
    let mut cur = root;
    for seg in segs {
        cur = match (seg, cur) {
            (Seg::Key(k), Value::Mapping(m)) => m.get(k.as_str())?,
            (Seg::Index(i), Value::Sequence(s)) => s.get(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

/// Line and column (1-based) of the deepest node on `segs` that exists in the marked tree.
/// A key that exists points at its value (an empty value at its key); a missing key points at
/// the key of the mapping it is missing from (`geometry:` for `geometry.die_width_um`), at the
/// list item it is missing from, or at 1:1 for a missing top-level section.
pub fn locate(root: &marked_yaml::Node, segs: &[Seg]) -> Option<(usize, usize)> {
    let at = |m: &marked_yaml::Marker| (m.line(), m.column());
    let mut cur = root;
    let mut best = cur.span().start().copied();
    // Where a missing key of `cur` is reported.
    let mut missing_here = Some((1, 1));
    for seg in segs {
        let next = match (seg, cur) {
            (Seg::Key(k), marked_yaml::Node::Mapping(m)) => {
                match m.iter().find(|(key, _)| key.as_str() == k) {
                    Some((key, v)) => {
                        // Empty values (`geometry:` with nothing under it) have no useful span:
                        // theirs is wherever the next token is. Point at the key.
                        let empty = v
                            .as_scalar()
                            .is_some_and(|s| s.as_str().is_empty() && s.may_coerce());
                        if empty {
                            return key.span().start().map(at);
                        }
                        missing_here = key.span().start().map(at);
                        best = v.span().start().or(key.span().start()).copied();
                        Some(v)
                    }
                    None => return missing_here.or(best.as_ref().map(at)),
                }
            }
            (Seg::Index(i), marked_yaml::Node::Sequence(s)) => {
                let item = s.get(*i);
                missing_here = item.and_then(|n| n.span().start()).map(at);
                item
            }
            _ => None,
        };
        match next {
            Some(n) => {
                if let Some(m) = n.span().start() {
                    best = Some(*m);
                }
                cur = n;
            }
            None => break,
        }
    }
    best.map(|m| at(&m))
}

/// Location of a mapping key itself (for unknown fields).
pub fn locate_key(root: &marked_yaml::Node, parent: &[Seg], key: &str) -> Option<(usize, usize)> {
    let mut cur = root;
    for seg in parent {
        cur = match (seg, cur) {
            (Seg::Key(k), marked_yaml::Node::Mapping(m)) => {
                m.iter().find(|(kk, _)| kk.as_str() == k).map(|(_, v)| v)?
            }
            (Seg::Index(i), marked_yaml::Node::Sequence(s)) => s.get(*i)?,
            _ => return None,
        };
    }
    let m = cur.as_mapping()?;
    let (k, _) = m.iter().find(|(kk, _)| kk.as_str() == key)?;
    k.span().start().map(|m| (m.line(), m.column()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        for p in ["a", "a.b", "steps[3].depth_um", "a[1][2].b", "."] {
            assert_eq!(format(&parse(p).unwrap()), p);
        }
        assert!(parse("a[x]").is_err());
        assert!(parse("a..b").is_err());
    }

    #[test]
    fn within() {
        assert!(is_within("steps[3].x", "steps[3]"));
        assert!(is_within("steps[3]", "steps[3]"));
        assert!(!is_within("steps[30]", "steps[3]"));
        assert!(is_within("anything", "."));
    }
}
