//! One home per parameter. Each run parameter of the two modes is written
//! once, as a row of a table (`prism::PARAMS`, `interior::PARAMS`): its
//! name, unit, valid range and help text, and how to read and set it on the
//! mode's configuration. Defaults are the configuration's own
//! (`SpectralConfig::new`, `InteriorConfig::with_defaults`), read through
//! the row. The command line builds its flags from these rows, scene and
//! experiment files are checked and applied through them, and sweeps start
//! from the same defaults, so a parameter means the same everywhere. What
//! a user gives is a [`given::Given`]: the checked value with where it came
//! from, so a refusal names the flag, the file's line or the prompt.

pub mod given;
pub mod interior;
pub mod prism;
pub mod prompts;

use crate::names::Named;
use std::fmt;
use std::path::PathBuf;

/// Why a parameter's value is refused: one line, for the caller to prefix
/// with where the value came from (the flag, the file's line, the prompt).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ValueError {
    #[error("`{0}` is not a number")]
    NotNumber(String),
    #[error("`{0}` is not a finite number")]
    NotFinite(String),
    #[error("`{0}` is not a whole number >= 0")]
    NotCount(String),
    #[error("`{0}` is not true or false")]
    NotFlag(String),
    #[error("`{0}` is not 0 (no) or 1 (yes)")]
    NotYesNo(String),
    #[error("`{0}` is not a string")]
    NotString(String),
    #[error("`{0}` is not W,H")]
    NotSize(String),
    #[error("`{0}` is not three comma-separated values")]
    NotThree(String),
    #[error("`{value}` is not a list of {len} numbers")]
    NotList { value: String, len: usize },
    #[error("`{0}` is not a whole number 0-255")]
    NotChannel(String),
    #[error("{0} is outside 0-255")]
    ChannelRange(i64),
    /// A real outside its kind's range, both as written (`short_real`).
    #[error("{value} is not {range}")]
    OutOfRange { value: String, range: String },
    #[error("{n} is not between {min} and {max}")]
    CountRange { n: u64, min: u64, max: u64 },
    #[error("`{shown}`: width and height must be whole numbers from 1 to {max}")]
    BadSize { shown: String, max: usize },
    /// Not among the choices: the nearest (`names::did_you_mean`) and every one.
    #[error("`{name}` is not one of {choices}{hint}")]
    NotOneOf { name: String, choices: String, hint: String },
    #[error("the file name is empty")]
    EmptyPath,
    #[error("{}: no such file", .0.display())]
    NoSuchFile(PathBuf),
    #[error("{n} is more than four times the {cores} cores of this machine (at most {})", 4 * .cores)]
    TooManyThreads { n: usize, cores: usize },
    #[error(transparent)]
    Mesh(#[from] crate::mesh::source::SourceError),
    #[error(transparent)]
    Inset(#[from] crate::spectral::inset::InsetError),
    #[error(transparent)]
    Light(#[from] crate::spectrum::spectra::UnknownSpectrum),
    #[error(transparent)]
    AddedLight(#[from] crate::gltf::BadAddedLight),
}

/// Why `key = value` of a file is refused (the caller adds the file and line).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KeyError {
    /// A key that is no parameter: the nearest one and every one.
    #[error("unknown {mode}parameter{hint}; expected one of {expected}")]
    Unknown { mode: String, hint: String, expected: String },
    #[error(transparent)]
    Value(#[from] ValueError),
}

/// One end of a real range.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum End {
    /// The value itself is allowed.
    Closed(f64),
    /// Only values beyond it are.
    Open(f64),
    /// No limit but finiteness.
    None,
}

/// An end's bound written out (`short_real`), for messages.
enum EndText {
    Closed(String),
    Open(String),
    None,
}

impl End {
    fn map(self, f: impl Fn(f64) -> String) -> EndText {
        match self {
            End::Closed(a) => EndText::Closed(f(a)),
            End::Open(a) => EndText::Open(f(a)),
            End::None => EndText::None,
        }
    }
}

/// What values a parameter takes.
#[derive(Copy, Clone)]
pub enum Kind {
    /// A whole number in `min..=max`.
    Count { min: u64, max: u64 },
    /// A finite real number within the two ends.
    Real { lo: End, hi: End },
    /// On or off (a flag without a value on the command line).
    Flag,
    /// A path to a file.
    Path,
    /// One of a list of names (with descriptions).
    Choice(fn() -> Vec<(&'static str, &'static str)>),
    /// Free text checked by a function (e.g. a light spectrum's name).
    Text(fn(&str) -> Result<(), ValueError>),
    /// Width and height in pixels, each 1 to `max`.
    Size { max: usize },
    /// Three finite reals, `X,Y,Z`.
    Triple,
    /// Three whole numbers 0-255, `R,G,B`.
    Rgb,
}

/// A parameter's value, checked against its kind.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Count(u64),
    Real(f64),
    Flag(bool),
    Path(PathBuf),
    /// The index into the kind's choices, and the name.
    Choice(usize, &'static str),
    Text(String),
    Size([usize; 2]),
    Triple([f64; 3]),
    Rgb([u8; 3]),
}

impl fmt::Display for Value {
    /// As a user would type it on the command line.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Value::Count(n) => write!(f, "{n}"),
            Value::Real(x) => write!(f, "{x}"),
            Value::Flag(b) => write!(f, "{b}"),
            Value::Path(p) => write!(f, "{}", p.display()),
            Value::Choice(_, name) => f.write_str(name),
            Value::Text(t) => f.write_str(t),
            Value::Size([w, h]) => write!(f, "{w},{h}"),
            Value::Triple([a, b, c]) => write!(f, "{a},{b},{c}"),
            Value::Rgb([r, g, b]) => write!(f, "{r},{g},{b}"),
        }
    }
}

impl Value {
    /// As a TOML value, as a scene file would write it.
    pub fn to_toml(&self) -> toml::Value {
        use toml::Value as T;
        match self {
            Value::Count(n) => T::Integer(*n as i64),
            Value::Real(x) => T::Float(*x),
            Value::Flag(b) => T::Boolean(*b),
            Value::Path(p) => T::String(p.display().to_string()),
            Value::Choice(_, name) => T::String(name.to_string()),
            Value::Text(t) => T::String(t.clone()),
            Value::Size([w, h]) => T::Array(vec![T::Integer(*w as i64), T::Integer(*h as i64)]),
            Value::Triple(t) => T::Array(t.iter().map(|x| T::Float(*x)).collect()),
            Value::Rgb(c) => T::Array(c.iter().map(|x| T::Integer(*x as i64)).collect()),
        }
    }

    pub fn count(&self) -> u64 {
        match self {
            Value::Count(n) => *n,
            _ => 0,
        }
    }
    pub fn real(&self) -> f64 {
        match self {
            Value::Real(x) => *x,
            Value::Count(n) => *n as f64,
            _ => f64::NAN,
        }
    }
    pub fn flag(&self) -> bool {
        matches!(self, Value::Flag(true))
    }
    pub fn text(&self) -> &str {
        match self {
            Value::Text(t) => t,
            Value::Choice(_, name) => name,
            _ => "",
        }
    }
    pub fn path(&self) -> PathBuf {
        match self {
            Value::Path(p) => p.clone(),
            Value::Text(t) => PathBuf::from(t),
            _ => PathBuf::new(),
        }
    }
    /// The chosen value of a `Named` enum (its first value if this is not
    /// a choice, which the kind check rules out).
    pub fn choice<T: Named>(&self) -> T {
        match self {
            Value::Choice(i, _) => T::VALUES.get(*i).unwrap_or(&T::VALUES[0]).0,
            _ => T::VALUES[0].0,
        }
    }
    pub fn size(&self) -> [usize; 2] {
        match self {
            Value::Size(s) => *s,
            _ => [0, 0],
        }
    }
    pub fn triple(&self) -> [f64; 3] {
        match self {
            Value::Triple(t) => *t,
            _ => [f64::NAN; 3],
        }
    }
    pub fn rgb(&self) -> [u8; 3] {
        match self {
            Value::Rgb(c) => *c,
            _ => [0; 3],
        }
    }
}

/// A parameter of configuration type `C`.
pub struct Param<C: 'static> {
    /// Its name in scene and experiment files; the flag is `--` and the
    /// name with `-` for `_`.
    pub key: &'static str,
    /// Older names still accepted (hidden from help).
    pub aliases: &'static [&'static str],
    /// Help heading it is listed under.
    pub section: &'static str,
    pub help: &'static str,
    /// Unit of the value ("" for none).
    pub unit: &'static str,
    pub kind: Kind,
    /// The default where the configuration has none (computed at run time).
    pub auto: &'static str,
    /// The configuration's value (`None` = `auto`).
    pub get: fn(&C) -> Option<Value>,
    /// Sets a value that passed the kind's checks.
    pub set: fn(&mut C, &Value),
    /// Why, in configuration `c`, setting this parameter would change
    /// nothing (a flag the run ignores is refused, not silently dropped);
    /// `None` where it is used.
    pub ignored: fn(&C) -> Option<String>,
}

/// A parameter every configuration uses.
pub fn never<C>(_: &C) -> Option<String> {
    None
}

/// The first of `set` (the parameters a user set) that `c` would ignore,
/// and why: the caller names it as its input does (a flag, a file's line).
pub fn first_ignored<C>(set: impl IntoIterator<Item = &'static Param<C>>, c: &C) -> Option<(&'static Param<C>, String)> {
    set.into_iter().find_map(|p| (p.ignored)(c).map(|why| (p, why)))
}

/// As `first_ignored`, but a parameter set to its default is let be: the
/// run is then exactly what was written (files restate the report's values
/// for the record, as `opacity = 25` at trace count 0), while any other
/// value would be expected to change the image and is refused.
pub fn first_ignored_change<C>(set: impl IntoIterator<Item = &'static Param<C>>, c: &C, defaults: &C) -> Option<(&'static Param<C>, String)> {
    first_ignored(set.into_iter().filter(|p| (p.get)(c) != (p.get)(defaults)), c)
}

impl<C> Param<C> {
    pub fn flag(&self) -> String {
        self.key.replace('_', "-")
    }

    /// Whether `name` (a file key or a flag without dashes) names this parameter.
    pub fn is(&self, name: &str) -> bool {
        let n = name.replace('-', "_");
        self.key == n || self.aliases.contains(&n.as_str())
    }

    /// The default shown in help: the configuration's value, or `auto`.
    pub fn default_text(&self, defaults: &C) -> Option<String> {
        match (self.get)(defaults) {
            Some(Value::Flag(false)) => None,
            Some(v) => Some(v.to_string()),
            None if self.auto.is_empty() => None,
            None => Some(self.auto.to_string()),
        }
    }

    /// Checks and sets a value from a TOML file.
    pub fn apply_toml(&self, c: &mut C, v: &toml::Value) -> Result<(), ValueError> {
        let v = self.kind.parse_toml(v)?;
        (self.set)(c, &v);
        Ok(())
    }
}

/// A real as people write it: plain where that is short, else in
/// scientific notation (1e-155, not 155 zeros).
pub fn short_real(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-4..1e7).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn range_text(lo: End, hi: End) -> String {
    match (lo.map(short_real), hi.map(short_real)) {
        (EndText::Closed(a), EndText::Closed(b)) => format!("between {a} and {b}"),
        (EndText::Open(a), EndText::Open(b)) => format!("strictly between {a} and {b}"),
        (EndText::Open(a), EndText::Closed(b)) => format!("greater than {a} and at most {b}"),
        (EndText::Closed(a), EndText::Open(b)) => format!("at least {a} and less than {b}"),
        (EndText::Closed(a), EndText::None) => format!("at least {a}"),
        (EndText::Open(a), EndText::None) => format!("greater than {a}"),
        (EndText::None, EndText::Closed(b)) => format!("at most {b}"),
        (EndText::None, EndText::Open(b)) => format!("less than {b}"),
        (EndText::None, EndText::None) => "finite".into(),
    }
}

pub(crate) fn parse_real(s: &str) -> Result<f64, ValueError> {
    let t = s.trim();
    let v: f64 = t.parse().map_err(|_| ValueError::NotNumber(t.into()))?;
    if !v.is_finite() {
        return Err(ValueError::NotFinite(t.into()));
    }
    Ok(v)
}

/// An output image for the interior mode (.png, .ppm or .pfm) whose folder
/// exists, and where nothing but a regular file stands.
pub fn out_path(s: &str) -> Result<PathBuf, crate::image_io::OutputError> {
    let s = s.trim();
    if s.is_empty() {
        return Err(crate::image_io::OutputError::Unnamed);
    }
    let p = PathBuf::from(s);
    crate::image_io::check_output(&p, &[crate::image_io::ImageFormat::Png, crate::image_io::ImageFormat::Ppm, crate::image_io::ImageFormat::Pfm]).map(|_| p)
}

/// A thread count for this machine: 0 (all cores) up to four times its
/// cores, so a mistyped count cannot spawn thousands of threads.
pub fn check_threads(n: usize) -> Result<(), ValueError> {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    if n > 4 * cores {
        return Err(ValueError::TooManyThreads { n, cores });
    }
    Ok(())
}

/// An existing file.
pub fn in_path(s: &str) -> Result<PathBuf, ValueError> {
    let s = s.trim();
    let p = PathBuf::from(s);
    if s.is_empty() {
        Err(ValueError::EmptyPath)
    } else if !p.is_file() {
        Err(ValueError::NoSuchFile(p))
    } else {
        Ok(p)
    }
}

/// Three comma-separated parts.
fn three<T>(s: &str, one: impl Fn(&str) -> Result<T, ValueError>) -> Result<[T; 3], ValueError> {
    let parts: Vec<&str> = s.split(',').collect();
    let [a, b, c] = parts.as_slice() else { return Err(ValueError::NotThree(s.into())) };
    Ok([one(a)?, one(b)?, one(c)?])
}

/// A colour channel as typed: a whole number 0-255.
pub fn channel(s: &str) -> Result<u8, ValueError> {
    let t = s.trim();
    let v: i64 = t.parse().map_err(|_| ValueError::NotChannel(t.into()))?;
    u8::try_from(v).map_err(|_| ValueError::ChannelRange(v))
}

impl Kind {
    /// A real in [a, b].
    pub const fn closed(a: f64, b: f64) -> Kind {
        Kind::Real { lo: End::Closed(a), hi: End::Closed(b) }
    }
    /// A real greater than `a` and at most `b`.
    pub const fn above(a: f64, b: f64) -> Kind {
        Kind::Real { lo: End::Open(a), hi: End::Closed(b) }
    }
    /// A finite real at least 0.
    pub const NON_NEGATIVE: Kind = Kind::Real { lo: End::Closed(0.0), hi: End::None };

    /// The value name shown in help (`<N>`, `<W,H>` ...).
    pub fn value_name(&self) -> &'static str {
        match self {
            Kind::Count { .. } => "N",
            Kind::Real { .. } => "X",
            Kind::Flag => "",
            Kind::Path => "FILE",
            Kind::Choice(_) => "NAME",
            Kind::Text(_) => "NAME",
            Kind::Size { .. } => "W,H",
            Kind::Triple => "X,Y,Z",
            Kind::Rgb => "R,G,B",
        }
    }

    /// The range as words, for help and errors ("" where there is none).
    pub fn range(&self) -> String {
        match *self {
            Kind::Count { min, max } => format!("{min} to {max}"),
            Kind::Real { lo, hi } => range_text(lo, hi),
            Kind::Size { max } => format!("1 to {max} each"),
            Kind::Rgb => "0-255 each".into(),
            _ => String::new(),
        }
    }

    fn check_real(&self, v: f64) -> Result<f64, ValueError> {
        let Kind::Real { lo, hi } = *self else { return Ok(v) };
        let ok_lo = match lo {
            End::Closed(a) => v >= a,
            End::Open(a) => v > a,
            End::None => true,
        };
        let ok_hi = match hi {
            End::Closed(b) => v <= b,
            End::Open(b) => v < b,
            End::None => true,
        };
        if v.is_finite() && ok_lo && ok_hi {
            Ok(v)
        } else {
            Err(ValueError::OutOfRange { value: short_real(v), range: range_text(lo, hi) })
        }
    }

    fn check_count(&self, n: u64) -> Result<u64, ValueError> {
        match *self {
            Kind::Count { min, max } if !(min..=max).contains(&n) => Err(ValueError::CountRange { n, min, max }),
            _ => Ok(n),
        }
    }

    fn check_size(&self, w: f64, h: f64, shown: &str) -> Result<[usize; 2], ValueError> {
        let max = match *self {
            Kind::Size { max } => max,
            _ => usize::MAX,
        };
        let dim = |x: f64| x.fract() == 0.0 && (1.0..=max as f64).contains(&x);
        if dim(w) && dim(h) {
            Ok([w as usize, h as usize])
        } else {
            Err(ValueError::BadSize { shown: shown.into(), max })
        }
    }

    /// A name among `list`'s choices.
    fn choose(list: fn() -> Vec<(&'static str, &'static str)>, name: &str) -> Result<Value, ValueError> {
        let key = crate::names::key;
        let names = list();
        match names.iter().position(|(n, _)| key(n) == key(name)) {
            Some(i) => Ok(Value::Choice(i, names[i].0)),
            None => Err(ValueError::NotOneOf {
                name: name.trim().into(),
                choices: names.iter().map(|n| n.0).collect::<Vec<_>>().join(", "),
                hint: crate::names::did_you_mean(name, names.iter().map(|n| n.0)),
            }),
        }
    }

    /// A value as typed on the command line or at a prompt.
    pub fn parse_text(&self, s: &str) -> Result<Value, ValueError> {
        let t = s.trim();
        match *self {
            Kind::Count { .. } => {
                let n = match t.parse::<u64>() {
                    Ok(n) => n,
                    // 2e6 is a whole number too.
                    Err(_) => match t.parse::<f64>() {
                        Ok(x) if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= u64::MAX as f64 => x as u64,
                        _ => return Err(ValueError::NotCount(t.into())),
                    },
                };
                Ok(Value::Count(self.check_count(n)?))
            }
            Kind::Real { .. } => Ok(Value::Real(self.check_real(parse_real(t)?)?)),
            Kind::Flag => match t {
                "1" | "true" | "yes" => Ok(Value::Flag(true)),
                "0" | "false" | "no" => Ok(Value::Flag(false)),
                _ => Err(ValueError::NotFlag(t.into())),
            },
            Kind::Path if t.is_empty() => Err(ValueError::EmptyPath),
            Kind::Path => Ok(Value::Path(PathBuf::from(t))),
            Kind::Choice(list) => Kind::choose(list, t),
            Kind::Text(check) => check(t).map(|_| Value::Text(t.to_string())),
            Kind::Size { .. } => {
                let parts: Vec<&str> = t.split(',').collect();
                let [w, h] = parts.as_slice() else { return Err(ValueError::NotSize(t.into())) };
                let num = |x: &str| x.trim().parse::<f64>().unwrap_or(f64::NAN);
                self.check_size(num(w), num(h), t).map(Value::Size)
            }
            Kind::Triple => three(t, parse_real).map(Value::Triple),
            Kind::Rgb => three(t, channel).map(Value::Rgb),
        }
    }

    /// A value from a TOML file: numbers must be TOML numbers, lists lists.
    pub fn parse_toml(&self, v: &toml::Value) -> Result<Value, ValueError> {
        use toml::Value as T;
        let num = |x: &T| -> Result<f64, ValueError> {
            match x {
                T::Integer(i) => Ok(*i as f64),
                T::Float(f) if f.is_finite() => Ok(*f),
                _ => Err(ValueError::NotNumber(x.to_string())),
            }
        };
        let list = |n: usize| -> Result<&Vec<T>, ValueError> {
            v.as_array().filter(|a| a.len() == n).ok_or_else(|| ValueError::NotList { value: v.to_string(), len: n })
        };
        match *self {
            Kind::Count { .. } => match v {
                T::Integer(i) if *i >= 0 => Ok(Value::Count(self.check_count(*i as u64)?)),
                T::Float(f) if f.is_finite() && *f >= 0.0 && f.fract() == 0.0 => Ok(Value::Count(self.check_count(*f as u64)?)),
                _ => Err(ValueError::NotCount(v.to_string())),
            },
            Kind::Real { .. } => Ok(Value::Real(self.check_real(num(v)?)?)),
            Kind::Flag => v.as_bool().map(Value::Flag).ok_or_else(|| ValueError::NotFlag(v.to_string())),
            Kind::Path | Kind::Choice(_) | Kind::Text(_) => match v.as_str() {
                Some(s) => self.parse_text(s),
                None => Err(ValueError::NotString(v.to_string())),
            },
            Kind::Size { .. } => {
                let a = list(2)?;
                self.check_size(num(&a[0])?, num(&a[1])?, &v.to_string()).map(Value::Size)
            }
            Kind::Triple => {
                let a = list(3)?;
                Ok(Value::Triple([num(&a[0])?, num(&a[1])?, num(&a[2])?]))
            }
            Kind::Rgb => {
                let a = list(3)?;
                let c = |x: &T| match x {
                    T::Integer(i) => u8::try_from(*i).map_err(|_| ValueError::ChannelRange(*i)),
                    _ => Err(ValueError::NotChannel(x.to_string())),
                };
                Ok(Value::Rgb([c(&a[0])?, c(&a[1])?, c(&a[2])?]))
            }
        }
    }
}

/// A `Named` enum's value as a choice (its index among the choices).
pub fn pick<T: Named>(t: T) -> Value {
    let i = T::VALUES.iter().position(|v| v.0 == t).unwrap_or(0);
    Value::Choice(i, T::VALUES[i].1)
}

/// The choices of a `Named` enum, for `Kind::Choice`.
pub fn choices<T: Named>() -> Vec<(&'static str, &'static str)> {
    T::choices()
}

/// The row named `name` (by key or alias).
pub fn find<C>(params: &'static [Param<C>], name: &str) -> Option<&'static Param<C>> {
    params.iter().find(|p| p.is(name))
}

/// A key that is no parameter of `params`: the nearest one and every one.
pub fn unknown_key<C>(params: &'static [Param<C>], key: &str, mode: &str) -> KeyError {
    let keys = params.iter().map(|p| p.key);
    let mode = if mode.is_empty() { String::new() } else { format!("{mode} ") };
    KeyError::Unknown { mode, hint: crate::names::did_you_mean(key, keys.clone()), expected: keys.collect::<Vec<_>>().join(", ") }
}

/// Applies `key = value` from a file to a configuration: the error names
/// the key's problem (the caller adds the file and line).
pub fn apply_toml<C>(params: &'static [Param<C>], c: &mut C, key: &str, v: &toml::Value) -> Result<(), KeyError> {
    match find(params, key) {
        Some(p) => Ok(p.apply_toml(c, v)?),
        None => Err(unknown_key(params, key, "")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks every parameter's current value against its kind: the first
    /// refused, with its flag.
    pub fn check_all<C>(params: &'static [Param<C>], c: &C) -> Result<(), (String, ValueError)> {
        let not_finite = |v: &Value| ValueError::NotFinite(v.to_string());
        for p in params {
            let Some(v) = (p.get)(c) else { continue };
            let ok = match (&p.kind, &v) {
                (k @ Kind::Count { .. }, Value::Count(n)) => k.check_count(*n).map(|_| ()),
                (k @ Kind::Real { .. }, Value::Real(x)) => k.check_real(*x).map(|_| ()),
                (k @ Kind::Size { .. }, Value::Size([w, h])) => k.check_size(*w as f64, *h as f64, &v.to_string()).map(|_| ()),
                (Kind::Triple, Value::Triple(t)) if t.iter().any(|x| !x.is_finite()) => Err(not_finite(&v)),
                _ => Ok(()),
            };
            ok.map_err(|e| (p.flag(), e))?;
        }
        Ok(())
    }

    #[test]
    fn kinds_parse_text_and_toml_alike() {
        let k = Kind::Count { min: 1, max: 100 };
        assert_eq!(k.parse_text("7"), Ok(Value::Count(7)));
        assert_eq!(k.parse_text("1e2"), Ok(Value::Count(100)));
        assert_eq!(k.parse_toml(&toml::Value::Integer(7)), Ok(Value::Count(7)));
        assert!(k.parse_text("0").unwrap_err().to_string().contains("not between 1 and 100"));
        assert!(k.parse_text("1.5").is_err() && k.parse_text("-3").is_err());
        assert!(k.parse_toml(&toml::Value::String("7".into())).is_err(), "numbers are numbers in files");
        let r = Kind::above(0.0, 100.0);
        assert_eq!(r.parse_text(" 1.4 "), Ok(Value::Real(1.4)));
        assert_eq!(r.parse_text("0").unwrap_err().to_string(), "0 is not greater than 0 and at most 100");
        assert_eq!(r.parse_text("nan").unwrap_err().to_string(), "`nan` is not a finite number");
        assert_eq!(r.parse_text("zero").unwrap_err().to_string(), "`zero` is not a number");
        assert_eq!(r.parse_toml(&toml::Value::Integer(3)), Ok(Value::Real(3.0)));
        let s = Kind::Size { max: 64 };
        assert_eq!(s.parse_text("8,4"), Ok(Value::Size([8, 4])));
        assert!(s.parse_text("0,4").is_err() && s.parse_text("65,4").is_err() && s.parse_text("8").is_err());
        assert_eq!(s.parse_toml(&toml::Value::try_from([8, 4]).unwrap()), Ok(Value::Size([8, 4])));
        assert_eq!(Kind::Rgb.parse_text("1,2,255"), Ok(Value::Rgb([1, 2, 255])));
        assert_eq!(Kind::Rgb.parse_text("1,2,256"), Err(ValueError::ChannelRange(256)));
        assert!(Kind::Triple.parse_text("1,2").unwrap_err().to_string().contains("three comma-separated"));
        let c = Kind::Choice(choices::<crate::photon::map::MapKind>);
        assert_eq!(c.parse_text("KD-tree"), Ok(Value::Choice(1, "kdtree")));
        assert!(c.parse_text("octree").unwrap_err().to_string().contains("is not one of buffer, kdtree"));
    }

    /// Every row of both tables: unique keys, a default that passes its own
    /// kind's checks, and `set` then `get` giving back what was set.
    fn rows_are_consistent<C>(params: &'static [Param<C>], defaults: impl Fn() -> C) {
        let mut keys: Vec<&str> = params.iter().flat_map(|p| std::iter::once(p.key).chain(p.aliases.iter().copied())).collect();
        let n = keys.len();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), n, "duplicate keys");
        let d = defaults();
        check_all(params, &d).unwrap();
        for p in params {
            assert!(!p.help.is_empty(), "{} has no help", p.key);
            match (p.get)(&d) {
                Some(v) => {
                    assert_eq!(p.kind.parse_text(&v.to_string()).as_ref(), Ok(&v), "{}: the default reads back", p.key);
                    let mut c = defaults();
                    (p.set)(&mut c, &v);
                    assert_eq!((p.get)(&c), Some(v), "{}: set then get", p.key);
                }
                None => assert!(!p.auto.is_empty(), "{}: a default computed at run time says how", p.key),
            }
        }
    }

    #[test]
    fn both_tables_are_consistent() {
        rows_are_consistent(prism::PARAMS, prism::defaults);
        rows_are_consistent(interior::PARAMS, interior::defaults);
    }

    #[test]
    fn check_all_names_the_flag_of_a_bad_value() {
        let mut c = prism::defaults();
        c.photons = 0;
        let said = |(flag, e): (String, ValueError)| format!("--{flag}: {e}");
        assert_eq!(check_all(prism::PARAMS, &c).map_err(said).unwrap_err(), "--photons: 0 is not between 1 and 2000000000");
        let mut c = interior::defaults();
        c.opacity = 120.0;
        assert_eq!(check_all(interior::PARAMS, &c).map_err(said).unwrap_err(), "--opacity: 120 is not between 0 and 100");
    }
}
