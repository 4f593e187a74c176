//! The modes' flags, made from the parameter tables (`crate::params`): each
//! row becomes one clap argument with its help, unit, range, default and
//! (for choices) every possible value with its description. What the user
//! typed comes back as checked values, applied to the mode's defaults by
//! the same row that scene files use.

use crate::modes::{self, ModeKind};
use crate::params::given::{Given, Source};
use crate::params::{self, Kind, Param, Value};
use clap::builder::{PossibleValue, TypedValueParser};
use clap::parser::ValueSource;
use clap::{Arg, ArgAction, ArgMatches, Command};
use std::marker::PhantomData;

/// A flag the run it is given to would ignore: refused, with why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{at}: {why}")]
pub struct IgnoredFlag {
    /// The flag as `Given::at` names it (`--photons`).
    pub at: String,
    pub why: String,
}

/// A set of rows offered as flags.
pub trait ParamSet: 'static {
    type Config: 'static;
    /// The mode's whole table, which every given key belongs to.
    fn table() -> &'static [Param<Self::Config>];
    /// The rows offered as flags (all of the table unless narrowed).
    fn params() -> Vec<&'static Param<Self::Config>> {
        Self::table().iter().collect()
    }
    fn defaults() -> Self::Config;
    /// Flags that must be given (when the mode's rule says so) rather than
    /// defaulted: their help says so, and shows no default.
    fn required() -> &'static [&'static str] {
        &[]
    }
}

/// Every parameter of a spectral run.
#[derive(Clone, Debug)]
pub struct Prism;
/// The parameters that shape a prism scene (for `prism trace`).
#[derive(Clone, Debug)]
pub struct PrismScene;
/// Every parameter of an interior run.
#[derive(Clone, Debug)]
pub struct Interior;

impl ParamSet for Prism {
    type Config = <modes::prism::Prism as ModeKind>::Config;
    fn table() -> &'static [Param<Self::Config>] {
        modes::prism::Prism::params()
    }
    fn defaults() -> Self::Config {
        modes::prism::Prism::defaults()
    }
}

impl ParamSet for PrismScene {
    type Config = <modes::prism::Prism as ModeKind>::Config;
    fn table() -> &'static [Param<Self::Config>] {
        modes::prism::Prism::params()
    }
    fn params() -> Vec<&'static Param<Self::Config>> {
        Self::table().iter().filter(|p| params::prism::is_scene(p)).collect()
    }
    fn defaults() -> Self::Config {
        modes::prism::Prism::defaults()
    }
}

impl ParamSet for Interior {
    type Config = <modes::interior::Interior as ModeKind>::Config;
    fn table() -> &'static [Param<Self::Config>] {
        modes::interior::Interior::params()
    }
    fn defaults() -> Self::Config {
        modes::interior::Interior::defaults()
    }
    fn required() -> &'static [&'static str] {
        &["off"]
    }
}

/// The parameters given on the command line, each from its flag
/// (defaults are not listed: the configuration already has them).
#[derive(Clone, Debug)]
pub struct Flags<S> {
    pub given: Vec<Given>,
    set: PhantomData<S>,
}

impl<S: ParamSet> Flags<S> {
    /// Sets every given value on `c`.
    pub fn apply(&self, c: &mut S::Config) {
        params::given::apply(S::table(), c, &self.given);
    }

    /// The defaults with the given values set.
    pub fn config(&self) -> S::Config {
        let mut c = S::defaults();
        self.apply(&mut c);
        c
    }

    /// Refuses a flag that `c` (the run these flags describe) would ignore,
    /// naming it and why.
    pub fn check_used(&self, c: &S::Config) -> Result<(), IgnoredFlag> {
        match params::given::first_ignored(S::table(), &self.given, c, &S::defaults()) {
            Some((g, why)) => Err(IgnoredFlag { at: g.at(), why }),
            None => Ok(()),
        }
    }

    pub fn has(&self, key: &str) -> bool {
        self.given.iter().any(|g| g.key == key)
    }
}

/// One row as a clap argument.
fn arg<C>(p: &'static Param<C>, defaults: &C, required: bool) -> Arg {
    let mut help = p.help.to_string();
    if !p.unit.is_empty() {
        help.push_str(&format!(" [unit: {}]", p.unit));
    }
    let range = p.kind.range();
    if !range.is_empty() {
        help.push_str(&format!(" [range: {range}]"));
    }
    // Old spellings (`aliases`) are not clap's: `cli::modern_args` rewrites
    // them first, so a typo hint never points at one.
    let mut a = Arg::new(p.key).long(p.flag()).help_heading(p.section);
    let kind = p.kind;
    a = match kind {
        Kind::Flag => a.action(ArgAction::SetTrue),
        Kind::Choice(list) => a.value_parser(Choices { names: list(), parse: move |s: &str| kind.parse_text(s) }).value_name("NAME"),
        _ => a.value_parser(move |s: &str| kind.parse_text(s)).value_name(kind.value_name()).allow_hyphen_values(true),
    };
    match ((p.get)(defaults), p.default_text(defaults)) {
        _ if required => help.push_str(" [required with any of the report's flags; otherwise asked]"),
        (Some(Value::Flag(_)), _) | (_, None) => {}
        (Some(_), Some(d)) => a = a.default_value(d),
        (None, Some(auto)) => help.push_str(&format!(" [default: {auto}]")),
    }
    a.help(help)
}

impl<S: ParamSet> clap::FromArgMatches for Flags<S> {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut given = Vec::new();
        for p in S::params() {
            if m.value_source(p.key) != Some(ValueSource::CommandLine) {
                continue;
            }
            let v = match p.kind {
                Kind::Flag => Some(Value::Flag(m.get_flag(p.key))),
                _ => m.get_one::<Value>(p.key).cloned(),
            };
            if let Some(value) = v {
                given.push(Given { key: p.key, value, from: Source::Flag(p.flag()) });
            }
        }
        Ok(Flags { given, set: PhantomData })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl<S: ParamSet> clap::Args for Flags<S> {
    fn augment_args(cmd: Command) -> Command {
        let defaults = S::defaults();
        S::params().into_iter().fold(cmd, |cmd, p| cmd.arg(arg(p, &defaults, S::required().contains(&p.key))))
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// A clap value parser for a `Named` enum: its names as possible values,
/// each with its description, matched as every name is (`names::key`).
pub fn named<T: crate::names::Named + Send + Sync>() -> impl TypedValueParser<Value = T> {
    Choices {
        names: T::choices(),
        parse: |s: &str| {
            T::from_name(s).ok_or_else(|| {
                let names = T::choices().into_iter().map(|c| c.0);
                format!("`{}` is not one of {}{}", s.trim(), names.clone().collect::<Vec<_>>().join(", "), crate::names::did_you_mean(s, names))
            })
        },
    }
}

/// A choice among names: shown in help as its possible values, each with
/// its description, and parsed by `parse` (case and separators aside, a
/// miss naming the nearest name), not by clap's exact match.
#[derive(Clone)]
struct Choices<F> {
    names: Vec<(&'static str, &'static str)>,
    parse: F,
}

impl<T, E, F> TypedValueParser for Choices<F>
where
    T: Clone + Send + Sync + 'static,
    E: Into<Box<dyn std::error::Error + Send + Sync + 'static>>,
    F: Fn(&str) -> Result<T, E> + Clone + Send + Sync + 'static,
{
    type Value = T;

    fn parse_ref(&self, cmd: &Command, arg: Option<&Arg>, value: &std::ffi::OsStr) -> Result<T, clap::Error> {
        TypedValueParser::parse_ref(&self.parse, cmd, arg, value)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.names.iter().map(|(name, about)| PossibleValue::new(*name).help(*about))))
    }
}
