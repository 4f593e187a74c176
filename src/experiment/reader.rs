//! Reading experiment files (TOML), one per figure family in `experiments/`,
//! into an [`Experiment`]:
//!
//! ```toml
//! name = "lab-ior"                 # results go to results/<name>/
//! mode = "interior"                # interior | prism
//! figures = ["lab-ior1.4"]         # figure ids the experiment backs (optional)
//! repeats = 1                      # runs of each point (timings: their median)
//! min_time = 0.05                  # seconds a timing must last (optional; under --quick at most 0.05)
//! [fixed]                          # parameters every run shares
//! off = "off/cube.off"
//! size = [201, 201]
//! [sweep]                          # axes, the first outermost; a list or a range
//! ior = { from = 1.1, to = 3.0, step = 0.1 }
//! trace = [0, 5, 10]
//! [[case]]                         # optional named cases (stability), times the sweep
//! name = "low ior"
//! ior = 0.5
//! expect = "error"                 # its runs are meant to fail (optional; "ok" by default)
//! [reference]                      # overrides for the reference image (RMSE, PSNR)
//! photons = 20000000
//! [quick]                          # replaces fixed/sweep/repeats keys under --quick
//! fixed = { size = [64, 64] }
//! [outputs]
//! images = true
//! [[outputs.plot]]
//! x = "param_trace"; y = "render_s"; series = ["param_specular_opacity"]; log_x = false; fit = false
//! claim = "time is linear in the trace count"   # judged by the fit (needs fit)
//! claim_slope = 1.0                # the slope the claim predicts (log-log)
//! claim_series = "linear"          # judge only series whose name holds this
//! note = "..."                     # a sentence printed on the chart
//! ```
//!
//! A plot whose axis cannot be drawn (y a column of text, a log or fitted
//! x of text) is refused here, before any run. An x of text is drawn as
//! a dot plot.
//!
//! Parameter names are the mode's flag names with `_` for `-`. Errors name
//! the key and its line.

use super::error::{ExperimentError, Result};
use super::key_lines::KeyLines;
use super::spec::{fnv1a, Case, Expect, Experiment, Places, PlotKind, PlotSpec, MAX_RUNS};
use crate::modes::Mode;
use crate::names::Named;
use std::path::Path;
use toml::{Table, Value};

/// Parses TOML text; a syntax error names `file` and its line.
pub fn parse_toml(text: &str, file: &str) -> Result<Table> {
    text.parse::<Table>().map_err(|e| {
        let line = e.span().map_or(1, |s| text[..s.start.min(text.len())].lines().count().max(1));
        ExperimentError::Syntax { file: file.into(), line, why: e.message().into() }
    })
}

impl Experiment {
    pub fn load(path: &Path, quick: bool) -> Result<Experiment> {
        let text = crate::data::read_settings_text(path).map_err(|io| ExperimentError::Read { path: path.into(), io })?;
        Experiment::parse(&text, &path.display().to_string(), quick)
    }

    pub fn parse(text: &str, file: &str, quick: bool) -> Result<Experiment> {
        let p = FileParser::new(text, file, quick)?;
        let (name, mode) = p.name_and_mode()?;
        let sweep = p.sweep(mode)?;
        let mut cases = p.cases(mode, &sweep)?;
        p.shorten_case_axes(&mut cases);
        let outputs = p.table("outputs")?;
        let images = p.images(&outputs)?;
        let fingerprint = format!("{name}@{:016x}{}", fnv1a(judged_apart(text).as_bytes()), if quick { "-quick" } else { "" });
        let e = Experiment {
            name,
            mode,
            description: p.root.get("description").and_then(Value::as_str).unwrap_or_default().to_string(),
            figures: p.figures()?,
            repeats: p.repeats()?,
            min_time: p.min_time(quick)?,
            fixed: p.checked(mode, "fixed")?,
            sweep,
            cases,
            reference: match p.root.get("reference") {
                None => None,
                Some(Value::Table(_)) => Some(p.checked(mode, "reference")?),
                Some(_) => return Err(p.err("", 0, "reference", "must be a table")),
            },
            images,
            plots: p.plots(&outputs)?,
            quick,
            fingerprint,
            places: p.places(),
        };
        p.check_names_once(&e)?;
        p.check_plot_columns(&e)?;
        p.check_run_count(&e)?;
        let grid = super::grid::expand(&e)?;
        check_configurations(&e, &grid)?;
        p.check_keys_used(&e, &grid)?;
        p.check_plot_axes(&e, &grid)?;
        p.check_reference(&e)?;
        // The [quick] version is checked too, with or without --quick: a
        // mistake there is found now, not when someone first runs it.
        if !quick && p.root.contains_key("quick") {
            Experiment::parse(text, file, true).map_err(|err| ExperimentError::Quick(Box::new(err)))?;
        }
        Ok(e)
    }
}

/// The text an experiment's fingerprint is taken of: the file without its
/// cases' `expect` lines, which judge how runs end and change no run, so
/// declaring a case's expected failure keeps the record made before.
fn judged_apart(text: &str) -> String {
    let expect = |l: &str| l.trim_start().strip_prefix("expect").is_some_and(|r| r.trim_start().starts_with('='));
    text.split_inclusive('\n').filter(|l| !expect(l)).collect()
}

/// The longest a timing lasts under --quick where `[quick]` does not say.
const QUICK_MIN_TIME: f64 = 0.05;

/// Columns of runs.csv that hold text whatever the experiment.
const TEXT_COLUMNS: [&str; 7] = ["mode", "case", "experiment", "host", "cpu", "status", "error"];

const TOP_KEYS: [&str; 12] = ["name", "mode", "description", "figures", "repeats", "min_time", "fixed", "sweep", "case", "reference", "quick", "outputs"];
const PLOT_KEYS: [&str; 13] = ["x", "y", "series", "log_x", "log_y", "fit", "title", "file", "kind", "claim", "claim_slope", "claim_series", "note"];

/// An experiment file being read: its text (for line numbers), its table,
/// and the [quick] overrides in force.
struct FileParser<'a> {
    keys: KeyLines<'a>,
    file: &'a str,
    root: Table,
    quick: Table,
}

impl<'a> FileParser<'a> {
    fn new(text: &'a str, file: &'a str, quick: bool) -> Result<FileParser<'a>> {
        let root = parse_toml(text, file)?;
        let mut p = FileParser { keys: KeyLines::new(text), file, root, quick: Table::new() };
        for k in p.root.keys() {
            if !TOP_KEYS.contains(&k.as_str()) {
                return Err(p.err("", 0, k, format!("unknown key; expected {}", TOP_KEYS.join(", "))));
            }
        }
        // [quick] is checked whether or not --quick is given.
        let quick_all = p.table("quick")?;
        for k in quick_all.keys() {
            if !["fixed", "sweep", "repeats", "min_time", "reference"].contains(&k.as_str()) {
                return Err(p.err("quick", 0, k, "unknown key in [quick]; expected fixed, sweep, repeats, min_time or reference"));
            }
        }
        if quick {
            p.quick = quick_all;
        }
        Ok(p)
    }

    /// The file's folder: paths in it are resolved from there.
    fn base(&self) -> &Path {
        Path::new(self.file).parent().unwrap_or(Path::new(""))
    }

    /// An error at `key` of the `nth` `[section]`, with its line (under
    /// --quick, the line of `[quick.section]`'s key where that overrides it).
    fn err(&self, section: &str, nth: usize, key: &str, msg: impl std::fmt::Display) -> ExperimentError {
        ExperimentError::Key { file: self.file.into(), line: self.line(section, nth, key), key: key.into(), why: msg.to_string() }
    }

    fn table(&self, key: &str) -> Result<Table> {
        match self.root.get(key) {
            None => Ok(Table::new()),
            Some(Value::Table(t)) => Ok(t.clone()),
            Some(_) => Err(self.err("", 0, key, "must be a table")),
        }
    }

    /// A section with its [quick] overrides applied.
    fn merged(&self, key: &str) -> Result<Table> {
        let mut t = self.table(key)?;
        if let Some(q) = self.quick.get(key) {
            let Value::Table(q) = q else { return Err(self.err("quick", 0, key, "must be a table")) };
            t.extend(q.iter().map(|(k, v)| (k.clone(), v.clone())));
        }
        Ok(t)
    }

    /// A section's parameters, each checked against the mode's table.
    fn checked(&self, mode: Mode, section: &str) -> Result<Vec<(String, Value)>> {
        self.merged(section)?
            .into_iter()
            .map(|(k, v)| mode.check(&k, &v, self.base()).map(|v| (k.clone(), v)).map_err(|m| self.err(section, 0, &k, m)))
            .collect()
    }

    /// The line of every parameter key (under --quick, of `[quick.section]`'s
    /// key where that overrides it), for the runs' values to carry.
    fn places(&self) -> Places {
        let mut lines = Vec::new();
        for section in ["fixed", "sweep", "reference"] {
            for k in self.merged(section).unwrap_or_default().keys() {
                lines.push((section, 0, k.clone(), self.line(section, 0, k)));
            }
        }
        if let Some(Value::Array(list)) = self.root.get("case") {
            for (i, t) in list.iter().enumerate().filter_map(|(i, t)| t.as_table().map(|t| (i, t))) {
                lines.extend(t.keys().map(|k| ("case", i, k.clone(), self.line("case", i, k))));
            }
        }
        Places { file: self.file.into(), lines }
    }

    /// The line of `key` in the `nth` `[section]` (its [quick] override's
    /// line where --quick overrides it).
    fn line(&self, section: &str, nth: usize, key: &str) -> usize {
        let quick = format!("quick.{section}");
        let section = if self.quick.contains_key(section) && self.keys.offset(&quick, nth, key).is_some() { quick.as_str() } else { section };
        self.keys.line(section, nth, key)
    }

    fn string(&self, key: &str) -> Result<String> {
        match self.root.get(key) {
            Some(Value::String(s)) => Ok(s.clone()),
            Some(_) => Err(self.err("", 0, key, "must be a string")),
            None => Err(ExperimentError::Missing { file: self.file.into(), key: key.into() }),
        }
    }

    fn name_and_mode(&self) -> Result<(String, Mode)> {
        let name = self.string("name")?;
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
            return Err(self.err("", 0, "name", "use letters, digits, - and _ only (it names a folder)"));
        }
        let m = self.string("mode")?;
        let mode = Mode::from_name(&m).ok_or_else(|| self.err("", 0, "mode", format!("`{m}` is not interior or prism")))?;
        Ok((name, mode))
    }

    fn figures(&self) -> Result<Vec<String>> {
        let bad = || self.err("", 0, "figures", "must be a list of strings");
        match self.root.get("figures") {
            None => Ok(Vec::new()),
            Some(Value::Array(a)) => a.iter().map(|v| v.as_str().map(str::to_string).ok_or_else(bad)).collect(),
            Some(_) => Err(bad()),
        }
    }

    fn repeats(&self) -> Result<u32> {
        match self.quick.get("repeats").or(self.root.get("repeats")) {
            None => Ok(1),
            Some(Value::Integer(n)) if (1..=1000).contains(n) => Ok(*n as u32),
            Some(_) => Err(self.err("", 0, "repeats", "must be a whole number from 1 to 1000")),
        }
    }

    /// Seconds a timing must last. Under --quick, at most
    /// [`QUICK_MIN_TIME`] unless `[quick]` gives its own: a quick run checks
    /// that the sweep works and draws its charts, and a full run's long
    /// timings would make it most of `figures --quick`'s time.
    fn min_time(&self, quick: bool) -> Result<f64> {
        let t = match self.quick.get("min_time").or(self.root.get("min_time")) {
            None => 0.0,
            Some(v) => match v.as_float().or(v.as_integer().map(|i| i as f64)) {
                Some(t) if (0.0..=60.0).contains(&t) => t,
                _ => return Err(self.err("", 0, "min_time", "must be a number of seconds from 0 to 60")),
            },
        };
        Ok(if quick && !self.quick.contains_key("min_time") { t.min(QUICK_MIN_TIME) } else { t })
    }

    /// The sweep axes, in the file's order (toml::Table sorts by key).
    fn sweep(&self, mode: Mode) -> Result<Vec<(String, Vec<Value>)>> {
        let mut axes: Vec<(String, Value)> = self.merged("sweep")?.into_iter().collect();
        axes.sort_by_key(|(k, _)| self.keys.offset("sweep", 0, k).or_else(|| self.keys.offset("quick.sweep", 0, k)).unwrap_or(usize::MAX));
        let mut sweep = Vec::new();
        for (k, v) in axes {
            let values = match &v {
                Value::Array(a) if !a.is_empty() => a.clone(),
                Value::Table(t) => range(t).map_err(|m| self.err("sweep", 0, &k, m))?,
                _ => return Err(self.err("sweep", 0, &k, "must be a non-empty list or { from, to, step }")),
            };
            let values = values.iter().map(|x| mode.check(&k, x, self.base()).map_err(|m| self.err("sweep", 0, &k, m))).collect::<Result<Vec<_>>>()?;
            sweep.push((k, values));
        }
        Ok(sweep)
    }

    /// The [[case]] tables: each a name, a mode and its overrides (a list
    /// under a sweep axis's name narrows that axis).
    fn cases(&self, mode: Mode, sweep: &[(String, Vec<Value>)]) -> Result<Vec<Case>> {
        let Some(c) = self.root.get("case") else { return Ok(Vec::new()) };
        let bad = || self.err("", 0, "case", "write cases as [[case]] tables");
        let Value::Array(list) = c else { return Err(bad()) };
        let mut cases = Vec::new();
        for (i, item) in list.iter().enumerate() {
            let Value::Table(t) = item else { return Err(bad()) };
            let name = t.get("name").and_then(Value::as_str).ok_or_else(|| self.err("case", i, "name", format!("case {} needs a name", i + 1)))?.to_string();
            let case_mode = match t.get("mode") {
                None => mode,
                Some(m) => m.as_str().and_then(Mode::from_name).ok_or_else(|| self.err("case", i, "mode", "must be interior or prism"))?,
            };
            let expect = match t.get("expect") {
                None => Expect::Ok,
                Some(x) => x
                    .as_str()
                    .and_then(Expect::from_name)
                    .ok_or_else(|| self.err("case", i, "expect", "must be \"error\" (each run of the case is meant to fail) or \"ok\" (the default)"))?,
            };
            let mut set = Vec::new();
            for (k, v) in t.iter().filter(|(k, _)| !["name", "mode", "expect"].contains(&k.as_str())) {
                let check = |x: &Value| case_mode.check(k, x, self.base()).map_err(|m| self.err("case", i, k, m));
                let v = match v {
                    Value::Array(list) if sweep.iter().any(|(a, _)| a == k) => Value::Array(list.iter().map(check).collect::<Result<_>>()?),
                    _ => check(v)?,
                };
                set.push((k.clone(), v));
            }
            cases.push(Case { name, mode: case_mode, params: set, expect });
        }
        Ok(cases)
    }

    fn plots(&self, outputs: &Table) -> Result<Vec<PlotSpec>> {
        let Some(p) = outputs.get("plot") else { return Ok(Vec::new()) };
        let bad = || self.err("outputs", 0, "plot", "write plots as [[outputs.plot]] tables");
        let Value::Array(list) = p else { return Err(bad()) };
        list.iter().enumerate().map(|(i, item)| if let Value::Table(t) = item { self.plot(i, t) } else { Err(bad()) }).collect()
    }

    fn plot(&self, i: usize, t: &Table) -> Result<PlotSpec> {
        let perr = |key: &str, m: &str| self.err("outputs.plot", i, key, m.to_string());
        for k in t.keys() {
            if !PLOT_KEYS.contains(&k.as_str()) {
                return Err(perr(k, &format!("unknown plot key; expected {}", PLOT_KEYS.join(", "))));
            }
        }
        let s = |key: &str| t.get(key).and_then(Value::as_str).map(str::to_string);
        let b = |key: &str| t.get(key).and_then(Value::as_bool).unwrap_or(false);
        let kind = match s("kind") {
            None => PlotKind::Line,
            Some(k) => PlotKind::from_name(&k).ok_or_else(|| perr("kind", "must be line or table"))?,
        };
        let series = match t.get("series") {
            None => Vec::new(),
            Some(Value::String(x)) => vec![x.clone()],
            Some(Value::Array(a)) => a.iter().filter_map(Value::as_str).map(str::to_string).collect(),
            Some(_) => return Err(perr("series", "must be a column name or a list of them")),
        };
        let file = s("file").ok_or_else(|| perr("file", "each plot needs a file name"))?;
        if !file.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
            return Err(perr("file", "use letters, digits, - and _ only"));
        }
        let (x, y) = match kind {
            PlotKind::Table => (s("x").unwrap_or_default(), s("y").unwrap_or_default()),
            PlotKind::Line => (s("x").ok_or_else(|| perr("x", "a line plot needs x"))?, s("y").ok_or_else(|| perr("y", "a line plot needs y"))?),
        };
        let claim_slope = match t.get("claim_slope") {
            None => None,
            Some(v) => {
                Some(v.as_float().or(v.as_integer().map(|i| i as f64)).filter(|s| s.is_finite()).ok_or_else(|| perr("claim_slope", "must be a number"))?)
            }
        };
        let claim = s("claim").unwrap_or_default();
        if (!claim.is_empty() || claim_slope.is_some()) && !b("fit") {
            return Err(perr(if claim.is_empty() { "claim_slope" } else { "claim" }, "a claim is judged by a fitted line: add fit = true"));
        }
        Ok(PlotSpec {
            x,
            y,
            series,
            log_x: b("log_x"),
            log_y: b("log_y"),
            fit: b("fit"),
            claim,
            claim_slope,
            claim_series: s("claim_series").unwrap_or_default(),
            note: s("note").unwrap_or_default(),
            title: s("title").unwrap_or_else(|| file.clone()),
            file,
            kind,
        })
    }

    /// Under --quick, a case's own list for an axis [quick] shortens is
    /// cut to its first values, as many as the quick list has.
    fn shorten_case_axes(&self, cases: &mut [Case]) {
        if let Some(Value::Table(q)) = self.quick.get("sweep") {
            for case in cases {
                for (k, v) in &mut case.params {
                    if let (Some(Value::Array(short)), Value::Array(own)) = (q.get(k.as_str()), v) {
                        own.truncate(short.len().max(1));
                    }
                }
            }
        }
    }

    /// `[outputs] images`: whether the runs' images are kept.
    fn images(&self, outputs: &Table) -> Result<bool> {
        match outputs.get("images") {
            None => Ok(false),
            Some(Value::Boolean(b)) => Ok(*b),
            Some(_) => Err(self.err("outputs", 0, "images", "must be true or false")),
        }
    }

    /// Each name once: two cases of one name, two plots of one file
    /// (the second would overwrite the first), or one parameter under
    /// two of its names (`light` and `light_pos`: which would win?).
    fn check_names_once(&self, e: &Experiment) -> Result<()> {
        for (i, c) in e.cases.iter().enumerate() {
            if let Some(j) = e.cases[..i].iter().position(|d| d.name == c.name) {
                return Err(self.err("case", i, "name", format!("`{}` is also case {}'s name; each case needs its own", c.name, j + 1)));
            }
        }
        for (i, plot) in e.plots.iter().enumerate() {
            if let Some(j) = e.plots[..i].iter().position(|q| q.file == plot.file) {
                return Err(self.err("outputs.plot", i, "file", format!("`{}` is also plot {}'s file; each plot needs its own", plot.file, j + 1)));
            }
        }
        let mut named: Vec<(&str, &str, &str, usize)> = Vec::new();
        let sections = e
            .fixed
            .iter()
            .map(|(k, _)| (e.mode, k, "fixed", 0))
            .chain(e.sweep.iter().map(|(k, _)| (e.mode, k, "sweep", 0)))
            .chain(e.reference.iter().flatten().map(|(k, _)| (e.mode, k, "reference", 0)))
            .chain(e.cases.iter().enumerate().flat_map(|(i, c)| c.params.iter().map(move |(k, _)| (c.mode, k, "case", i))));
        for (mode, k, section, nth) in sections {
            let Some(canon) = mode.canonical(k) else { continue };
            match named.iter().find(|(c, other, _, _)| *c == canon && *other != k.as_str()) {
                Some((_, other, s2, _)) => {
                    return Err(self.err(section, nth, k, format!("names the same parameter as `{other}` (in [{s2}]); use one name")));
                }
                None => named.push((canon, k, section, nth)),
            }
        }
        Ok(())
    }

    /// A plot's columns are known before any run: a misspelt one is
    /// refused now, not after the sweep.
    fn check_plot_columns(&self, e: &Experiment) -> Result<()> {
        let columns = e.columns();
        for (i, plot) in e.plots.iter().enumerate() {
            let named = [("x", &plot.x), ("y", &plot.y)].into_iter().filter(|(_, c)| !c.is_empty()).chain(plot.series.iter().map(|c| ("series", c)));
            for (key, c) in named {
                if !columns.contains(c) {
                    return Err(self.err("outputs.plot", i, key, format!("`{c}` is not a column of runs.csv; columns: {}", columns.join(", "))));
                }
            }
        }
        Ok(())
    }

    /// At most [`MAX_RUNS`] runs.
    fn check_run_count(&self, e: &Experiment) -> Result<()> {
        let runs = e.run_count();
        if runs > MAX_RUNS as u128 {
            return Err(self.err(
                "",
                0,
                "sweep",
                format!("the experiment has {runs} runs (cases x sweep values x repeats); at most {MAX_RUNS}: split it into several files or narrow an axis"),
            ));
        }
        Ok(())
    }

    /// A key no run would use varies nothing the sweep measures: refused
    /// now, on its line. A key only some runs use is fine, since grids
    /// cross keys that apply to some of their cases only (`split` under
    /// the hero wavelength in eye-split.toml).
    /// A fixed key that restates its default is let be (see
    /// `params::first_ignored_change`); an axis never is.
    fn check_keys_used(&self, e: &Experiment, grid: &[super::grid::RunSpec]) -> Result<()> {
        let restated = |key: &str| e.fixed.iter().any(|(k, v)| k == key && e.mode.restates_default(k, v)) && !e.sweep.iter().any(|(k, _)| k == key);
        for key in e.param_names().into_iter().filter(|k| !restated(k)) {
            let mut why = None;
            let used = grid.iter().filter(|r| r.params.iter().any(|(k, _)| *k == key)).any(|r| match r.mode.ignored(&r.given, &key) {
                Some(w) => {
                    why.get_or_insert(w);
                    false
                }
                None => true,
            });
            if let (false, Some(why)) = (used, why) {
                let (section, nth) = if e.fixed.iter().any(|(k, _)| *k == key) {
                    ("fixed", 0)
                } else if e.sweep.iter().any(|(k, _)| *k == key) {
                    ("sweep", 0)
                } else {
                    ("case", e.cases.iter().position(|c| c.params.iter().any(|(k, _)| *k == key)).unwrap_or(0))
                };
                return Err(self.err(section, nth, &key, format!("no run of the experiment uses it: {why}")));
            }
        }
        Ok(())
    }

    /// Axes that cannot be drawn are refused now, before any run.
    fn check_plot_axes(&self, e: &Experiment, grid: &[super::grid::RunSpec]) -> Result<()> {
        for (i, plot) in e.plots.iter().enumerate().filter(|(_, pl)| pl.kind == PlotKind::Line) {
            let text_of = |c: &str| -> Option<String> {
                let vals: Vec<String> = match c.strip_prefix("param_") {
                    Some(key) => {
                        let mut v: Vec<String> = Vec::new();
                        for r in grid {
                            if let Some((_, x)) = r.params.iter().find(|(k, _)| k == key) {
                                if !matches!(x, Value::Integer(_) | Value::Float(_)) {
                                    let cell = super::params::cell(x);
                                    if !v.contains(&cell) {
                                        v.push(cell);
                                    }
                                }
                            }
                        }
                        v
                    }
                    None if TEXT_COLUMNS.contains(&c) => vec![format!("{c} is text")],
                    None => Vec::new(),
                };
                (!vals.is_empty()).then(|| vals.iter().take(4).cloned().collect::<Vec<_>>().join(", "))
            };
            if let Some(v) = text_of(&plot.y) {
                return Err(self.err("outputs.plot", i, "y", format!("`{}` holds text ({v}); a chart's y must be a number", plot.y)));
            }
            if let Some(v) = text_of(&plot.x) {
                for (key, on) in [("log_x", plot.log_x), ("fit", plot.fit)] {
                    if on {
                        return Err(self.err(
                            "outputs.plot",
                            i,
                            key,
                            format!(
                                "`{}` holds text ({v}): it is drawn as categories, which have no {}",
                                plot.x,
                                if key == "fit" { "line to fit" } else { "logarithm" }
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// A reference key the reference run would ignore.
    fn check_reference(&self, e: &Experiment) -> Result<()> {
        if let (Some(over), Some(given)) = (&e.reference, e.reference_given().transpose()?) {
            let keys: Vec<&str> = over.iter().map(|(k, _)| k.as_str()).collect();
            if let Ok(Some((g, why))) = e.mode.first_ignored_among(&given, &keys) {
                return Err(self.err("reference", 0, g.written_key(), format!("the reference run would ignore it: {why}")));
            }
        }
        Ok(())
    }
}

/// A run whose whole configuration its mode refuses (k below 4, k with
/// passes) is refused now, named at its values' lines, unless its case
/// expects its runs to fail.
fn check_configurations(e: &Experiment, grid: &[super::grid::RunSpec]) -> Result<(), crate::modes::ModeError> {
    let expected_to_fail = |case: &str| e.cases.iter().any(|c| c.name == case && c.expect == super::spec::Expect::Error);
    for run in grid.iter().filter(|r| r.repeat == 0 && !expected_to_fail(&r.case)) {
        run.mode.check_given(&run.given)?;
    }
    Ok(())
}

/// `{ from, to, step }` as the list of values, inclusive of `to` within
/// rounding; integers stay integers.
/// Why a `{ from, to, step }` makes no list of values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum RangeError {
    #[error("unknown range key `{0}`; expected from, to, step")]
    Key(String),
    #[error("a range needs a number `{0}`")]
    Number(&'static str),
    #[error("range from {from} to {to} step {step}: need from <= to and step > 0")]
    Order { from: f64, to: f64, step: f64 },
    #[error("range gives {0} values; at most 100000")]
    TooMany(usize),
}

fn range(t: &Table) -> Result<Vec<Value>, RangeError> {
    for k in t.keys() {
        if !["from", "to", "step"].contains(&k.as_str()) {
            return Err(RangeError::Key(k.clone()));
        }
    }
    let num = |k: &'static str| t.get(k).and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64))).ok_or(RangeError::Number(k));
    let (from, to, step) = (num("from")?, num("to")?, num("step")?);
    if !(step > 0.0) || !(to >= from) || !from.is_finite() || !to.is_finite() {
        return Err(RangeError::Order { from, to, step });
    }
    let n = ((to - from) / step + 1e-9).floor() as usize + 1;
    if n > 100_000 {
        return Err(RangeError::TooMany(n));
    }
    let ints = t.values().all(|v| v.is_integer());
    Ok((0..n)
        .map(|i| {
            let v = from + i as f64 * step;
            if ints {
                Value::Integer(v.round() as i64)
            } else {
                // Round away binary noise: 1.1 + 2 * 0.1 is written 1.3.
                Value::Float((v * 1e9).round() / 1e9)
            }
        })
        .collect())
}
