//! A parameter's value as a user gave it: the row it sets, the checked
//! value, and where it came from (a flag, a file's line, a prompt's
//! answer, `--set`). The command line, scene files and experiment grids
//! all make these, the modes apply them to their defaults, and a refusal
//! names the value where the user wrote it.

use super::{find, unknown_key, KeyError, Param, Value};
use std::fmt;

/// Where a given value came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A command-line flag (its name, without the dashes).
    Flag(String),
    /// `key = value` in a scene or experiment file: the file, the key's
    /// line and the key as written there (an alias stays as written).
    File { path: String, line: usize, key: String },
    /// The answer to a question on standard input.
    Prompt(&'static str),
    /// `--set KEY=VALUE`.
    Set,
    /// Chosen by the program for the run, and why (the quick look's photon
    /// count, a frame fitted to a camera).
    Chosen(&'static str),
}

/// A checked value of one parameter, with where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Given {
    /// The row's key (an alias as written is kept in `from`).
    pub key: &'static str,
    pub value: Value,
    pub from: Source,
}

impl Given {
    /// Where the value was given, as a message starts with it: `--photons`,
    /// `scene.toml:7: `photons``, `--set photons`, `the answer to "Scale Factor"`.
    pub fn at(&self) -> String {
        match &self.from {
            Source::Flag(flag) => format!("--{flag}"),
            Source::File { path, line, key } => format!("{path}:{line}: `{key}`"),
            Source::Prompt(question) => format!("the answer to \"{question}\""),
            Source::Set => format!("--set {}", self.key),
            Source::Chosen(why) => format!("{} ({why})", self.key),
        }
    }

    /// The key as the user wrote it (an alias in a file stays an alias).
    pub fn written_key(&self) -> &str {
        match &self.from {
            Source::File { key, .. } => key,
            _ => self.key,
        }
    }
}

impl fmt::Display for Given {
    /// `key = value` as a scene file would write it.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{} = {}", self.written_key(), self.value.to_toml())
    }
}

/// `key = value` from a file, checked by the key's row of `params`.
pub fn from_toml<C>(params: &'static [Param<C>], key: &str, v: &toml::Value, from: Source) -> Result<Given, KeyError> {
    let p = find(params, key).ok_or_else(|| unknown_key(params, key, ""))?;
    Ok(Given { key: p.key, value: p.kind.parse_toml(v)?, from })
}

/// A value typed as text (a flag, `--set`, a prompt), checked by the row.
pub fn from_text<C>(params: &'static [Param<C>], key: &str, text: &str, from: Source) -> Result<Given, KeyError> {
    let p = find(params, key).ok_or_else(|| unknown_key(params, key, ""))?;
    Ok(Given { key: p.key, value: p.kind.parse_text(text)?, from })
}

/// Sets every given value on `c`, in order (a later one of a key wins).
pub fn apply<C>(params: &'static [Param<C>], c: &mut C, given: &[Given]) {
    for g in given {
        if let Some(p) = find(params, g.key) {
            (p.set)(c, &g.value);
        }
    }
}

/// Puts `g` last in `list`, in place of any earlier value of its key.
pub fn put(list: &mut Vec<Given>, g: Given) {
    list.retain(|o| o.key != g.key);
    list.push(g);
}

/// The first of `given` that the run `c` would ignore (one set to its
/// default is let be: `first_ignored_change`), and why.
pub fn first_ignored<'g, C>(params: &'static [Param<C>], given: &'g [Given], c: &C, defaults: &C) -> Option<(&'g Given, String)> {
    let rows = given.iter().filter_map(|g| find(params, g.key));
    let (p, why) = super::first_ignored_change(rows, c, defaults)?;
    given.iter().rev().find(|g| g.key == p.key).map(|g| (g, why))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::prism;

    #[test]
    fn each_source_names_where_the_value_was_given() {
        let g = |from| Given { key: "photons", value: Value::Count(5), from };
        assert_eq!(g(Source::Flag("photons".into())).at(), "--photons");
        assert_eq!(g(Source::File { path: "a.toml".into(), line: 7, key: "photons".into() }).at(), "a.toml:7: `photons`");
        assert_eq!(g(Source::Set).at(), "--set photons");
        assert_eq!(g(Source::Prompt("Photons")).at(), "the answer to \"Photons\"");
        assert_eq!(g(Source::Set).to_string(), "photons = 5");
    }

    #[test]
    fn text_and_toml_give_the_same_value_and_a_later_one_wins() {
        let t = from_text(prism::PARAMS, "photons", "2000", Source::Set).unwrap();
        let f = from_toml(prism::PARAMS, "photons", &toml::Value::Integer(2000), Source::Set).unwrap();
        assert_eq!(t, f);
        assert!(matches!(from_text(prism::PARAMS, "photons", "0", Source::Set), Err(KeyError::Value(_))));
        assert!(matches!(from_text(prism::PARAMS, "fotons", "1", Source::Set), Err(KeyError::Unknown { .. })));
        let mut list = vec![t, from_text(prism::PARAMS, "spp", "2", Source::Set).unwrap()];
        put(&mut list, from_text(prism::PARAMS, "photons", "3000", Source::Flag("photons".into())).unwrap());
        let mut c = prism::defaults();
        apply(prism::PARAMS, &mut c, &list);
        assert_eq!((c.photons, c.spp, list.len()), (3000, 2, 2));
    }
}
