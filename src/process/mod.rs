//! The process model: one YAML file, loaded, overridden (`--set`), checked and resolved.
//!
//! serde_yaml (deprecated upstream) and marked_yaml stay inside this module: the rest of the crate
//! sees only [`Process`], [`Provenance`] and [`LoadError`].

mod collect;
pub mod defaults;
mod error;
mod input;
mod locate;
mod overrides;
mod path;
pub mod schema;
mod validate;
mod walk;

use std::path::Path;

use serde::Serialize;
use serde_yaml::Value;

pub use error::{LoadError, Location, Problem, MAX_PROBLEMS_SHOWN};
pub use input::MAX_FILE_BYTES;
pub use schema::*;
pub use validate::{
    MAX_DIES_PER_WAFER, MAX_MASKS, MAX_SCENES, MAX_STEPS, MAX_TEETH, MIN_PLATE_SPAN_UM,
};

use collect::{deserialize_all, RawProblem};
use locate::Locator;

/// A default the file relied on, with its value and source.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Provenance {
    pub path: String,
    pub value: String,
    pub source: String,
}

/// A validated process and what it took from defaults and overrides.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Loaded {
    pub process: Process,
    /// Defaults the file did not override, with their source.
    pub defaults_used: Vec<Provenance>,
    /// `--set` overrides as applied, canonical path first.
    pub overrides: Vec<(String, String)>,
    /// SHA-256 of the text read (the file's bytes, hashed once, as they were loaded).
    pub source_sha256: String,
}

/// Reads, overrides, deserialises and validates a process file. At most [`MAX_FILE_BYTES`] + 1
/// bytes are read.
pub fn load(file: &Path, overrides: &[String]) -> Result<Loaded, LoadError> {
    let text = input::read(file)?;
    load_str(&text, &file.display().to_string(), overrides)
}

/// As [`load`], from text; `file` names it in messages.
pub fn load_str(text: &str, file: &str, overrides: &[String]) -> Result<Loaded, LoadError> {
    input::check_size(text.len(), file)?;
    let (marked, mut value) = parse(text, file)?;
    let unaddressable = walk::take_unaddressable_keys(&mut value);
    let applied = overrides::apply(&mut value, overrides)?;
    let locator = Locator {
        file,
        marked: &marked,
        applied: &applied,
        tree: &value,
    };
    let mut problems: Vec<Problem> = unaddressable
        .iter()
        .map(|(parent, key)| unaddressable_key_problem(&locator, parent, key))
        .collect();

    let mut raw = Vec::new();
    let mut placeholders = Vec::new();
    let process = deserialize_process(value.clone(), &mut raw, &mut placeholders);
    if let Some(p) = &process {
        raw.extend(non_finite_problems(p, &mut placeholders));
    }
    problems.extend(raw.iter().map(|r| Problem {
        location: locator.raw(&r.path, r.key_of_parent.as_ref()),
        path: r.path.clone(),
        message: r.message.clone(),
        expected: r.expected.clone(),
        hint: r.hint.clone(),
    }));
    if let Some(p) = &process {
        problems.extend(rule_problems(p, &placeholders, &locator));
    }
    if !problems.is_empty() {
        problems.sort_by(|a, b| {
            sort_key(&a.location)
                .cmp(&sort_key(&b.location))
                .then(a.path.cmp(&b.path))
        });
        problems.dedup();
        return Err(LoadError::Invalid(problems));
    }
    let process = process.expect("no problems means the process deserialised");
    let defaults_used = defaults_used(&value, &process);
    Ok(Loaded {
        process,
        defaults_used,
        overrides: applied.into_iter().map(|a| (a.path, a.arg)).collect(),
        source_sha256: crate::digest::sha256_hex(text.as_bytes()),
    })
}

/// The text as a marked tree (for locations) and a value tree (for serde): one document, valid
/// YAML, unique keys, a mapping at the top.
fn parse(text: &str, file: &str) -> Result<(marked_yaml::Node, Value), LoadError> {
    let invalid = |p: Problem| LoadError::Invalid(vec![p]);
    if let Some(line) = input::second_document(text) {
        return Err(invalid(input::second_document_problem(line, file)));
    }
    let marked = marked_yaml::parse_yaml_with_options(
        0,
        text,
        marked_yaml::LoaderOptions::default().error_on_duplicate_keys(true),
    )
    .map_err(|e| invalid(syntax_problem(&e, file)))?;
    let value: Value = serde_yaml::from_str(text).map_err(|e| {
        let location = e
            .location()
            .map(|l| Location::File {
                file: file.into(),
                line: l.line(),
                column: l.column(),
            })
            .unwrap_or(Location::Unknown { file: file.into() });
        invalid(Problem {
            location,
            path: ".".into(),
            message: format!("YAML syntax: {e}"),
            expected: "valid YAML".into(),
            hint: String::new(),
        })
    })?;
    if value.is_null() {
        return Err(invalid(Problem {
            location: Location::File {
                file: file.into(),
                line: 1,
                column: 1,
            },
            path: ".".into(),
            message: "the process file is empty".into(),
            expected: "a mapping with device, wafer, geometry, materials, masks and steps".into(),
            hint: String::new(),
        }));
    }
    Ok((marked, value))
}

/// A key containing `.` or `[`, at the key.
fn unaddressable_key_problem(locator: &Locator, parent: &[path::Seg], key: &str) -> Problem {
    let parent_path = path::format(parent);
    let location = path::locate_key(locator.marked, parent, key)
        .map(|(line, column)| Location::File {
            file: locator.file.into(),
            line,
            column,
        })
        .unwrap_or_else(|| locator.raw(&parent_path, None));
    Problem {
        location,
        path: path::join(&parent_path, &format!("\"{key}\"")),
        message: format!("the key `{key}` contains `.` or `[`"),
        expected: "a field name: letters, digits, `_` and `-`".into(),
        hint: "no field name has a `.`: write the nesting as indentation (`a:` then `  b:` \
               below it); --set paths use `.` to separate fields, so such a key could not be \
               addressed"
            .into(),
    }
}

/// NaN or an infinity in any float field; those paths become placeholders so the range rules
/// do not report them again.
fn non_finite_problems(p: &Process, placeholders: &mut Vec<String>) -> Vec<RawProblem> {
    let mut out = Vec::new();
    for (at, x) in walk::non_finite(p) {
        if placeholders.iter().any(|h| path::is_within(&at, h)) {
            continue;
        }
        out.push(RawProblem {
            path: at.clone(),
            key_of_parent: None,
            message: format!("{x} is not a finite number"),
            expected: "a finite number".into(),
            hint: "`.nan`, `.inf` and numbers beyond 1.8e308 are not measurements; write the \
                   value in the field's unit"
                .into(),
        });
        placeholders.push(at);
    }
    out
}

/// The range and cross-field rules, each placed by [`Locator::rule`] (a default's problem goes
/// to its section, with its source in the hint).
fn rule_problems(p: &Process, placeholders: &[String], locator: &Locator) -> Vec<Problem> {
    let is_placeholder = |path: &str| placeholders.iter().any(|h| path::is_within(path, h));
    let mut out = Vec::new();
    for v in validate::validate(p, &is_placeholder) {
        if is_placeholder(&v.path) {
            continue;
        }
        let (location, default) = locator.rule(&v.path);
        let hint = match default {
            Some(source) => {
                let d = locate::default_hint(&v.path, source);
                if v.hint.is_empty() {
                    d
                } else {
                    format!("{}; {d}", v.hint)
                }
            }
            None => v.hint,
        };
        out.push(Problem {
            location,
            path: v.path,
            message: v.message,
            expected: v.expected,
            hint,
        });
    }
    out
}

/// File order: `--set` arguments first, then by line and column, then problems with no line.
fn sort_key(l: &Location) -> (u8, usize, usize, String) {
    match l {
        Location::Override { arg } => (0, 0, 0, arg.clone()),
        Location::File { line, column, .. }
        | Location::Default {
            section: Some((line, column)),
            ..
        } => (1, *line, *column, String::new()),
        Location::Default { section: None, .. } => (2, 0, 0, String::new()),
        Location::Unknown { .. } => (3, 0, 0, String::new()),
    }
}

/// A marked_yaml error as a located problem.
fn syntax_problem(e: &marked_yaml::LoadError, file: &str) -> Problem {
    use marked_yaml::LoadError as E;
    let (marker, message) = match e {
        E::ScanError(m, se) => (Some(*m), format!("YAML syntax: {}", se.info())),
        E::DuplicateKey(inner) => (
            inner.prev_key.span().start().copied().or(None),
            format!("duplicate key `{}`", inner.key.as_str()),
        ),
        E::TopLevelMustBeMapping(m) => (
            Some(*m),
            "the document must be a mapping of sections".into(),
        ),
        E::UnexpectedAnchor(m) => (
            Some(*m),
            "YAML anchors are not supported in process files".into(),
        ),
        E::MappingKeyMustBeScalar(m) => (Some(*m), "mapping keys must be plain names".into()),
        E::UnexpectedTag(m) => (
            Some(*m),
            "YAML tags are not supported in process files".into(),
        ),
        other => (None, format!("YAML: {other}")),
    };
    let location = match (e, marker) {
        (E::DuplicateKey(inner), _) => inner
            .key
            .span()
            .start()
            .map(|m| Location::File {
                file: file.into(),
                line: m.line(),
                column: m.column(),
            })
            .unwrap_or(Location::Unknown { file: file.into() }),
        (_, Some(m)) => Location::File {
            file: file.into(),
            line: m.line(),
            column: m.column(),
        },
        _ => Location::Unknown { file: file.into() },
    };
    Problem {
        location,
        path: ".".into(),
        message,
        expected: "valid YAML with unique keys".into(),
        hint: String::new(),
    }
}

/// Deserialises the top level and each step on its own (the step's `kind` picks its fields).
fn deserialize_process(
    mut value: Value,
    raw: &mut Vec<RawProblem>,
    placeholders: &mut Vec<String>,
) -> Option<Process> {
    let steps_value = match &mut value {
        Value::Mapping(m) => m.remove("steps"),
        _ => None,
    };
    let top: Option<Process> = deserialize_all(value, ".", raw, placeholders);
    let steps = match &steps_value {
        None => {
            raw.push(RawProblem {
                path: "steps".into(),
                key_of_parent: None,
                message: "missing field `steps`".into(),
                expected: "a list of process steps".into(),
                hint: String::new(),
            });
            None
        }
        Some(Value::Sequence(items)) => {
            let mut out = Vec::new();
            let mut ok = true;
            for (i, item) in items.iter().enumerate() {
                match deserialize_step(item, &format!("steps[{i}]"), raw, placeholders) {
                    Some(s) => out.push(s),
                    None => ok = false,
                }
            }
            ok.then_some(out)
        }
        Some(_) => {
            raw.push(RawProblem {
                path: "steps".into(),
                key_of_parent: None,
                message: "`steps` is not a list".into(),
                expected: "a list of process steps".into(),
                hint: String::new(),
            });
            None
        }
    };
    match (top, steps) {
        (Some(mut p), Some(s)) => {
            p.steps = s;
            Some(p)
        }
        _ => None,
    }
}

const COMMON_KEYS: &[&str] = &["name", "kind", "equipment", "notes"];

fn deserialize_step(
    item: &Value,
    base: &str,
    raw: &mut Vec<RawProblem>,
    placeholders: &mut Vec<String>,
) -> Option<Step> {
    let Value::Mapping(m) = item else {
        raw.push(RawProblem {
            path: base.into(),
            key_of_parent: None,
            message: "a step must be a mapping".into(),
            expected: "name, kind and the kind's parameters".into(),
            hint: String::new(),
        });
        return None;
    };
    let mut common = serde_yaml::Mapping::new();
    let mut params = serde_yaml::Mapping::new();
    for (k, v) in m {
        if k.as_str().is_some_and(|k| COMMON_KEYS.contains(&k)) {
            common.insert(k.clone(), v.clone());
        } else {
            params.insert(k.clone(), v.clone());
        }
    }
    let common: Option<StepCommon> =
        deserialize_all(Value::Mapping(common), base, raw, placeholders);
    let common = common?;
    let params_v = Value::Mapping(params);
    macro_rules! kinds {
        ($($name:literal => $variant:ident($ty:ty)),* $(,)?) => {
            match common.kind.as_str() {
                $($name => deserialize_all::<$ty>(params_v, base, raw, placeholders).map(StepParams::$variant),)*
                _ if placeholders.iter().any(|p| p == &format!("{base}.kind")) => {
                    placeholders.push(base.to_string());
                    Some(StepParams::Clean(Generic { time_min: None, temp_c: None }))
                }
                other => {
                    let kinds: Vec<String> = schema::STEP_KINDS.iter().map(|(k, _)| k.to_string()).collect();
                    raw.push(RawProblem {
                        path: format!("{base}.kind"),
                        key_of_parent: None,
                        message: format!("unknown step kind `{other}`{}", collect::did_you_mean(other, &kinds)),
                        expected: format!("one of {}", schema::STEP_KINDS.iter().map(|(k, _)| format!("`{k}`")).collect::<Vec<_>>().join(", ")),
                        hint: String::new(),
                    });
                    placeholders.push(base.to_string());
                    Some(StepParams::Clean(Generic { time_min: None, temp_c: None }))
                }
            }
        };
    }
    let params = kinds! {
        "clean" => Clean(Generic),
        "oxidation" => Oxidation(Oxidation),
        "spin_coat" => SpinCoat(SpinCoat),
        "bake" => Bake(Bake),
        "expose" => Expose(Expose),
        "develop" => Develop(Develop),
        "oxide_etch" => OxideEtch(OxideEtch),
        "silicon_etch" => SiliconEtch(SiliconEtch),
        "strip" => Strip(Strip),
        "mount" => Mount(Generic),
        "metal_etch" => MetalEtch(MetalEtch),
        "assemble" => Assemble(Assemble),
    }?;
    Some(Step {
        name: common.name,
        equipment: common.equipment,
        notes: common.notes,
        params,
    })
}

/// Lists every default the file relied on: the path was absent from the (overridden) tree.
fn defaults_used(tree: &Value, process: &Process) -> Vec<Provenance> {
    let resolved = serde_yaml::to_value(process).unwrap_or(Value::Null);
    let steps_resolved = serde_yaml::to_value(&process.steps).unwrap_or(Value::Null);
    let mut out = Vec::new();
    for d in defaults::DEFAULTS {
        if let Some(field) = d.path.strip_prefix("steps[].") {
            let Some(Value::Sequence(items)) = tree.get("steps") else {
                continue;
            };
            for (i, item) in items.iter().enumerate() {
                let rel = path::parse(field).unwrap_or_default();
                let parent_present =
                    rel.len() < 2 || path::get(item, &rel[..rel.len() - 1]).is_some();
                let resolved_v = steps_resolved.get(i).and_then(|s| path::get(s, &rel));
                if let (true, None, Some(rv)) = (parent_present, path::get(item, &rel), resolved_v)
                {
                    out.push(Provenance {
                        path: format!("steps[{i}].{field}"),
                        value: render(rv),
                        source: d.source.into(),
                    });
                }
            }
            continue;
        }
        let isotropic_only = matches!(d.path, "materials.silicon.e_gpa" | "materials.silicon.nu");
        if isotropic_only && process.materials.silicon.model != SiliconModel::Isotropic {
            continue;
        }
        let segs = path::parse(d.path).unwrap_or_default();
        if path::get(tree, &segs).is_none() {
            if let Some(v) = path::get(&resolved, &segs) {
                out.push(Provenance {
                    path: d.path.into(),
                    value: render(v),
                    source: d.source.into(),
                });
            }
        }
    }
    out.sort_by_key(|p| natural_key(&p.path));
    out
}

/// Sorts `steps[2]` before `steps[10]`.
fn natural_key(p: &str) -> Vec<(String, usize)> {
    path::parse(p)
        .unwrap_or_default()
        .into_iter()
        .map(|s| match s {
            path::Seg::Key(k) => (k, 0),
            path::Seg::Index(i) => (String::new(), i),
        })
        .collect()
}

fn render(v: &Value) -> String {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() => format!("{}", (x * 1e6).round() / 1e6),
            _ => n.to_string(),
        },
        Value::String(s) => s.clone(),
        Value::Bool(b) => b.to_string(),
        other => serde_json::to_string(other).unwrap_or_default(),
    }
}
