//! Where a problem goes: a `--set` argument, a line and column of the file, or the section of a
//! default the file never wrote.

use serde_yaml::Value;

use super::defaults::DEFAULTS;
use super::error::Location;
use super::overrides::Applied;
use super::path::{self, Seg};

/// Places problems for one loaded file.
pub struct Locator<'a> {
    pub file: &'a str,
    pub marked: &'a marked_yaml::Node,
    pub applied: &'a [Applied],
    /// The tree after `--set`: what the user wrote, one way or the other.
    pub tree: &'a Value,
}

impl Locator<'_> {
    fn at(&self, (line, column): (usize, usize)) -> Location {
        Location::File {
            file: self.file.to_string(),
            line,
            column,
        }
    }

    /// The `--set` argument that wrote `p` (or created a mapping `p` lies in), the last one wins.
    fn override_of(&self, p: &str) -> Option<Location> {
        self.applied
            .iter()
            .rev()
            .find(|a| {
                path::is_within(p, &a.path)
                    || a.created.as_deref().is_some_and(|c| path::is_within(p, c))
            })
            .map(|a| Location::Override { arg: a.arg.clone() })
    }

    /// A structural problem at `p`; `key` = (parent path, key) points at an unknown key itself.
    pub fn raw(&self, p: &str, key: Option<&(String, String)>) -> Location {
        if let Some(l) = self.override_of(p) {
            return l;
        }
        let found = match key {
            Some((parent, k)) => path::parse(parent)
                .ok()
                .and_then(|s| path::locate_key(self.marked, &s, k)),
            None => path::parse(p)
                .ok()
                .and_then(|s| path::locate(self.marked, &s)),
        };
        match found {
            Some(at) => self.at(at),
            None => Location::Unknown {
                file: self.file.to_string(),
            },
        }
    }

    /// A range or cross-field problem at `p`, and the default's source when the file (and every
    /// `--set`) left `p` out: then the problem goes to the section where the user would write
    /// the value, never to an unrelated line.
    pub fn rule(&self, p: &str) -> (Location, Option<&'static str>) {
        if let Some(l) = self.override_of(p) {
            return (l, None);
        }
        let segs = path::parse(p).unwrap_or_default();
        if path::get(self.tree, &segs).is_some() {
            return (self.raw(p, None), None);
        }
        let Some(source) = default_source(p) else {
            return (self.raw(p, None), None);
        };
        let section = (1..segs.len()).rev().find_map(|n| {
            let (parent, last) = (&segs[..n - 1], &segs[n - 1]);
            match last {
                Seg::Key(k) => path::locate_key(self.marked, parent, k),
                Seg::Index(_) => path::locate(self.marked, &segs[..n]),
            }
        });
        let location = Location::Default {
            file: self.file.to_string(),
            section,
        };
        (location, Some(source))
    }
}

/// The source of the default at `p` (`steps[3].overetch_pct` matches `steps[].overetch_pct`;
/// `layout.layers.pvdf` matches `layout.layers`).
fn default_source(p: &str) -> Option<&'static str> {
    let generic = match p.strip_prefix("steps[") {
        Some(rest) => format!("steps[]{}", &rest[rest.find(']')? + 1..]),
        None => p.to_string(),
    };
    DEFAULTS
        .iter()
        .find(|d| path::is_within(&generic, d.path))
        .map(|d| d.source)
}

/// The hint for a problem with a default's value.
pub fn default_hint(p: &str, source: &str) -> String {
    format!(
        "the file does not set `{p}`: this is tactfab's default ({source}); set it in the file \
         or with --set to change it"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_found_for_steps_and_nested_paths() {
        assert!(default_source("steps[3].overetch_pct").is_some());
        assert!(default_source("layout.layers.pvdf").is_some());
        assert!(default_source("geometry.die_width_um").is_none());
    }
}
