//! What an experiment is: its cases, sweep axes, repeats, reference and
//! plots, as read from an experiment file (`reader` reads one; the format
//! is in its module doc), and what follows from them without running
//! anything (its parameter columns, its runs.csv columns, its run count).
//! `grid` expands an experiment into its runs.

use crate::modes::{Given, Mode, ModeError, Source};
use toml::Value;

/// A named case of an experiment (stability conditions, timing groups).
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub name: String,
    pub mode: Mode,
    pub params: Vec<(String, Value)>,
    /// How its runs are meant to end (`expect = "error"`: a condition the
    /// experiment records a method failing under).
    pub expect: Expect,
}

crate::named_enum! {
    /// How a case's runs are meant to end.
    pub enum Expect {
        /// Each run renders (the default).
        Ok = "ok",
        /// Each run fails: the sweep counts such a failure as expected, and
        /// a run that renders after all as a failure of the sweep.
        Error = "error",
    }
}

/// One line chart drawn from the runs' CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSpec {
    pub x: String,
    pub y: String,
    pub series: Vec<String>,
    pub log_x: bool,
    pub log_y: bool,
    /// Fit a least-squares line on the axes as drawn (log-log where both
    /// are log): drawn, its slope with a 95 % interval and R² in the legend.
    pub fit: bool,
    /// The report's claim the fit tests, in words ("render time is linear
    /// in the trace count"); judged on the chart unless the run is quick.
    pub claim: String,
    /// The slope the claim predicts (1 for "linear" on log-log axes); none:
    /// the claim is a positive slope on linear axes.
    pub claim_slope: Option<f64>,
    /// Only the series whose legend contains this are judged (all if empty).
    pub claim_series: String,
    /// A sentence the chart prints under its subtitle (what a reader must
    /// know to read it right).
    pub note: String,
    pub title: String,
    pub file: String,
    pub kind: PlotKind,
}

crate::named_enum! {
    /// What a plot draws.
    pub enum PlotKind {
        /// y against x, a line per series (the default).
        Line = "line",
        /// A pass/fail grid of the cases (stability experiments).
        Table = "table",
    }
}

#[derive(Clone, Debug)]
pub struct Experiment {
    pub name: String,
    pub mode: Mode,
    pub description: String,
    pub figures: Vec<String>,
    pub repeats: u32,
    /// Seconds a timing must last: a run that renders faster is rendered
    /// again inside the same timing until the renders together take this
    /// long, and its times are per render (0: once).
    pub min_time: f64,
    pub fixed: Vec<(String, Value)>,
    pub sweep: Vec<(String, Vec<Value>)>,
    /// Named cases: their mode (the file's unless they say) and overrides;
    /// a list under a sweep axis's name narrows that axis for the case.
    pub cases: Vec<Case>,
    pub reference: Option<Vec<(String, Value)>>,
    pub images: bool,
    pub plots: Vec<PlotSpec>,
    /// Read with its [quick] settings: small runs whose times are noise.
    pub quick: bool,
    /// What each row records of the file it came from: its name, and a
    /// fingerprint of its text and quick flag (FNV-1a, 64 bits), so merge
    /// can refuse shards of another experiment or another version of it.
    pub fingerprint: String,
    /// Where each parameter is written, so a run's values carry their lines.
    pub places: Places,
}

/// The file and line of each parameter key of an experiment file.
#[derive(Clone, Debug, Default)]
pub struct Places {
    pub file: String,
    /// Section (`fixed`, `sweep`, `case`, `reference`), entry, key, line.
    pub lines: Vec<(&'static str, usize, String, usize)>,
}

impl Places {
    /// Where `key` of the `nth` `[section]` was given.
    pub fn source(&self, section: &str, nth: usize, key: &str) -> Source {
        let line = self.lines.iter().find(|(s, n, k, _)| *s == section && *n == nth && k == key).map_or(1, |l| l.3);
        Source::File { path: self.file.clone(), line, key: key.into() }
    }
}

/// FNV-1a over bytes: a stable 64-bit fingerprint (not a secure hash).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

impl Experiment {
    /// The folder a sweep (or a plan) writes unless told: `results/NAME`,
    /// or `results/quick/NAME` for the quick version, so that a quick run
    /// never touches the committed full-quality record.
    pub fn default_folder(&self) -> std::path::PathBuf {
        let results = std::path::Path::new("results");
        if self.quick {
            results.join("quick").join(&self.name)
        } else {
            results.join(&self.name)
        }
    }

    /// Parameter columns: the sweep axes, then case keys, then fixed keys.
    pub fn param_names(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for k in self.sweep.iter().map(|s| &s.0).chain(self.cases.iter().flat_map(|c| c.params.iter().map(|p| &p.0))).chain(self.fixed.iter().map(|p| &p.0)) {
            if !names.contains(k) {
                names.push(k.clone());
            }
        }
        names
    }

    /// The columns of the experiment's runs.csv.
    pub fn columns(&self) -> Vec<String> {
        let mut h = vec!["run_id".to_string(), "mode".into(), "case".into(), "repeat".into()];
        h.extend(self.param_names().iter().map(|n| format!("param_{n}")));
        h.extend(super::row::RunRow::columns());
        h
    }

    /// The sweep axes as a case sees them: a case may narrow an axis by
    /// listing its own values for it.
    pub fn axes_for<'a>(&'a self, case_params: &'a [(String, Value)]) -> impl Iterator<Item = (&'a String, &'a Vec<Value>)> {
        self.sweep.iter().map(move |(k, vals)| match case_params.iter().find(|(c, _)| c == k) {
            Some((_, Value::Array(own))) => (k, own),
            _ => (k, vals),
        })
    }

    /// How many runs the grid holds (each case times the product of its
    /// axes' lengths, times the repeats), without building it.
    pub fn run_count(&self) -> u128 {
        let per_case = |case_params: &[(String, Value)]| -> u128 { self.axes_for(case_params).fold(1u128, |a, (_, v)| a.saturating_mul(v.len() as u128)) };
        let cases: u128 =
            if self.cases.is_empty() { per_case(&[]) } else { self.cases.iter().map(|c| per_case(&c.params)).fold(0u128, |a, n| a.saturating_add(n)) };
        cases.saturating_mul(self.repeats as u128)
    }

    /// Whether `other` (the same file read with or without its [quick]
    /// settings) runs the same grid and reference: then --quick changes
    /// nothing.
    pub fn same_runs(&self, other: &Experiment) -> bool {
        (&self.fixed, &self.sweep, &self.cases, &self.reference, self.repeats) == (&other.fixed, &other.sweep, &other.cases, &other.reference, other.repeats)
    }

    /// The reference run's values, each with where it is written.
    pub fn reference_given(&self) -> Option<Result<Vec<Given>, ModeError>> {
        let over = self.reference.as_ref()?;
        let from = |k: &str| if over.iter().any(|(o, _)| o == k) { self.places.source("reference", 0, k) } else { self.places.source("fixed", 0, k) };
        Some(self.mode.typed(&self.reference_params()?, from))
    }

    /// The reference run's parameters: the fixed ones with the reference's
    /// overrides, if the experiment has a reference.
    pub fn reference_params(&self) -> Option<Vec<(String, Value)>> {
        let over = self.reference.as_ref()?;
        let mut p = self.fixed.clone();
        for (k, v) in over {
            p.retain(|(q, _)| q != k);
            p.push((k.clone(), v.clone()));
        }
        Some(p)
    }
}

/// The most runs one experiment file may hold (its grid is built in memory,
/// about 0.5 kB a run).
pub const MAX_RUNS: usize = 100_000;

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
name = "t"
mode = "interior"
[fixed]
off = "off/cube.off"
size = [16, 16]
[sweep]
trace = [0, 2]
ior = { from = 1.1, to = 1.5, step = 0.2 }
[quick]
sweep = { trace = [0] }
"#;

    #[test]
    fn parses_axes_ranges_and_quick() {
        let e = Experiment::parse(GOOD, "t.toml", false).unwrap();
        assert_eq!(e.sweep[0].0, "trace", "file order kept");
        assert_eq!(e.sweep[1].1, vec![Value::Float(1.1), Value::Float(1.3), Value::Float(1.5)]);
        let q = Experiment::parse(GOOD, "t.toml", true).unwrap();
        assert_eq!(q.sweep.iter().find(|s| s.0 == "trace").unwrap().1.len(), 1);
    }

    #[test]
    fn quick_caps_a_long_min_time_unless_quick_gives_its_own() {
        let long = GOOD.replace("[fixed]", "min_time = 0.25\n[fixed]");
        assert_eq!(Experiment::parse(&long, "t.toml", false).unwrap().min_time, 0.25);
        assert_eq!(Experiment::parse(&long, "t.toml", true).unwrap().min_time, 0.05);
        let own = long.replace("[quick]", "[quick]\nmin_time = 0.5");
        assert_eq!(Experiment::parse(&own, "t.toml", true).unwrap().min_time, 0.5);
        let short = GOOD.replace("[fixed]", "min_time = 0.01\n[fixed]");
        assert_eq!(Experiment::parse(&short, "t.toml", true).unwrap().min_time, 0.01);
    }

    #[test]
    fn quick_also_cuts_a_cases_own_list_of_a_shortened_axis() {
        let text = format!("{GOOD}[[case]]\nname = \"a\"\n[[case]]\nname = \"deep\"\ntrace = [1, 3, 5]\n");
        let full = Experiment::parse(&text, "t.toml", false).unwrap();
        assert_eq!(full.run_count(), 2 * 3 + 3 * 3);
        let quick = Experiment::parse(&text, "t.toml", true).unwrap();
        assert_eq!(quick.run_count(), 3 + 3, "the case's own [1, 3, 5] is cut to [1] as [quick] cuts trace to one value");
        let deep = quick.cases.iter().find(|c| c.name == "deep").unwrap();
        assert_eq!(quick.axes_for(&deep.params).find(|(k, _)| *k == "trace").unwrap().1, &vec![Value::Integer(1)]);
    }

    /// An axis that cannot be drawn is refused when the file is read,
    /// before any run, on the plot's line; an x of text is drawable (as
    /// categories).
    #[test]
    fn an_undrawable_axis_is_refused_before_any_run() {
        let base = "name = \"g\"\nmode = \"prism\"\n[fixed]\nsize = [16, 8]\nphotons = 1000\n[sweep]\nmap = [\"buffer\", \"kdtree\"]\n[[outputs.plot]]\n";
        for (plot, needle) in [
            ("x = \"total_s\"\ny = \"param_map\"\nfile = \"a\"\n", "g.toml:10: `y`: `param_map` holds text (buffer, kdtree); a chart's y must be a number"),
            (
                "x = \"param_map\"\ny = \"total_s\"\nlog_x = true\nfile = \"a\"\n",
                "g.toml:11: `log_x`: `param_map` holds text (buffer, kdtree): it is drawn as categories, which have no logarithm",
            ),
            ("x = \"param_map\"\ny = \"total_s\"\nfit = true\nfile = \"a\"\n", "g.toml:11: `fit`: `param_map` holds text"),
            ("x = \"host\"\ny = \"cpu\"\nfile = \"a\"\n", "g.toml:10: `y`: `cpu` holds text"),
            (
                "x = \"param_photons\"\ny = \"total_s\"\nclaim = \"linear\"\nfile = \"a\"\n",
                "g.toml:11: `claim`: a claim is judged by a fitted line: add fit = true",
            ),
        ] {
            let e = Experiment::parse(&format!("{base}{plot}"), "g.toml", false).unwrap_err().to_string();
            assert!(e.starts_with(needle), "{e}\n  expected: {needle}");
        }
        // Text on x alone is a dot plot: accepted.
        Experiment::parse(&format!("{base}x = \"param_map\"\ny = \"total_s\"\nfile = \"a\"\n"), "g.toml", false).unwrap();
    }

    /// A case may declare that its runs fail; the declaration judges runs
    /// and changes none, so the file's fingerprint (its record) stays.
    #[test]
    fn a_case_declares_its_expected_failure_outside_the_fingerprint() {
        let plain = format!("{GOOD}[[case]]\nname = \"a\"\n[[case]]\nname = \"b\"\nsize = [8, 8]\n");
        let declared = plain.replace("size = [8, 8]\n", "size = [8, 8]\n  expect = \"error\"\n");
        let (p, d) = (Experiment::parse(&plain, "t.toml", false).unwrap(), Experiment::parse(&declared, "t.toml", false).unwrap());
        assert_eq!(d.cases.iter().map(|c| c.expect).collect::<Vec<_>>(), [Expect::Ok, Expect::Error]);
        assert!(d.cases[1].params.iter().all(|(k, _)| k != "expect"), "not a parameter");
        assert_eq!(p.fingerprint, d.fingerprint);
        assert_eq!(p.columns(), d.columns());
        let other = plain.replace("size = [8, 8]", "size = [9, 8]");
        assert_ne!(p.fingerprint, Experiment::parse(&other, "t.toml", false).unwrap().fingerprint);
        let bad = Experiment::parse(&declared.replace("\"error\"", "\"fail\""), "t.toml", false).unwrap_err().to_string();
        assert!(bad.starts_with("t.toml:17: `expect`: must be \"error\""), "{bad}");
    }

    #[test]
    fn errors_name_key_and_line() {
        for (bad, needle) in [
            (GOOD.replace("mode = \"interior\"", "mode = \"film\""), "t.toml:3: `mode`: `film` is not interior or prism"),
            (GOOD.replace("size = [16, 16]", "colour = [1, 2, 3]"), "t.toml:6: `colour`: unknown interior parameter"),
            (GOOD.replace("trace = [0, 2]", "trace = [0, -2]"), "t.toml:8: `trace`"),
            (GOOD.replace("step = 0.2", "step = 0"), "t.toml:9: `ior`: range from 1.1 to 1.5 step 0"),
            (GOOD.replace("[fixed]", "colour = 3\n[fixed]"), "t.toml:4: `colour`: unknown key"),
            (GOOD.replace("size = [16, 16]", "size = [16, 16"), "t.toml:6"),
            (GOOD.replace("sweep = { trace = [0] }", "swep = { trace = [0] }"), "t.toml:11: `swep`: unknown key in [quick]"),
            // A plot's columns are checked against runs.csv's before any run.
            (format!("{GOOD}[[outputs.plot]]\nx = \"param_trace\"\ny = \"render_s\"\nfile = \"a\"\n[[outputs.plot]]\nx = \"param_ior\"\ny = \"rendr_s\"\nfile = \"b\"\n"), "t.toml:18: `y`: `rendr_s` is not a column of runs.csv; columns: run_id, mode, case, repeat, param_trace, param_ior, param_off"),
            (format!("{GOOD}[[outputs.plot]]\nx = \"param_trace\"\ny = \"render_s\"\nseries = [\"param_colour\"]\nfile = \"a\"\n"), "t.toml:15: `series`: `param_colour` is not a column"),
            // A key no run uses (one sample a pixel ignores the seed).
            (GOOD.replace("size = [16, 16]", "size = [16, 16]\nseed = 3"), "t.toml:7: `seed`: no run of the experiment uses it: one sample a pixel"),
            (format!("{GOOD}[reference]\nseed = 3\n"), "t.toml:13: `seed`: the reference run would ignore it"),
        ] {
            let e = Experiment::parse(&bad, "t.toml", false).unwrap_err().to_string();
            assert!(e.starts_with(needle), "{e}\n  expected: {needle}");
        }
        // A key some runs use is kept.
        let some = GOOD.replace("size = [16, 16]", "size = [16, 16]\nseed = 3").replace("trace = [0, 2]", "trace = [0, 2]\nspp = [1, 4]");
        Experiment::parse(&some, "t.toml", false).unwrap();
    }

    /// A run's values carry the file and line they were written on (the
    /// [quick] line where --quick overrides one).
    #[test]
    fn a_runs_values_carry_their_file_and_line() {
        let at = |e: &Experiment, key: &str| super::super::grid::expand(e).unwrap()[0].given.iter().find(|g| g.key == key).unwrap().at();
        let full = Experiment::parse(GOOD, "t.toml", false).unwrap();
        assert_eq!((at(&full, "size"), at(&full, "trace")), ("t.toml:6: `size`".into(), "t.toml:8: `trace`".into()));
        let quick = Experiment::parse(GOOD, "t.toml", true).unwrap();
        assert_eq!(at(&quick, "trace"), "t.toml:11: `trace`");
    }
}
