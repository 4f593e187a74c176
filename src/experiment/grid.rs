//! The grid of an experiment's runs: every combination of its cases, sweep
//! axes and repeats, each with an id that depends only on the experiment
//! file (so shards, engines and resumed sweeps agree on it).

use super::spec::{Case, Experiment};
use crate::modes::{Given, Mode, ModeError, Source};
use toml::Value;

/// One run of the grid.
#[derive(Clone, Debug)]
pub struct RunSpec {
    pub id: usize,
    pub mode: Mode,
    pub case: String,
    pub repeat: u32,
    /// Effective parameters as written (the runs.csv cells): fixed, then
    /// the case's, then the swept ones.
    pub params: Vec<(String, Value)>,
    /// The same values as the run takes them, each with its file and line.
    pub given: Vec<Given>,
    /// Index along each sweep axis.
    pub at: Vec<usize>,
}

/// Every run of an experiment, in a fixed order (case, then the sweep axes
/// with the first outermost, then repeats). Each value was checked when
/// the file was read; one the mode refuses after all is an error.
pub fn expand(e: &Experiment) -> Result<Vec<RunSpec>, ModeError> {
    let cases = if e.cases.is_empty() {
        vec![Case { name: String::new(), mode: e.mode, params: Vec::new(), expect: super::spec::Expect::Ok }]
    } else {
        e.cases.clone()
    };
    let mut runs = Vec::new();
    for (nth, Case { name: case, mode, params: case_params, .. }) in cases.iter().enumerate() {
        // Where a run's value is written: the case's own list or value,
        // else the sweep axis, else the fixed table.
        let from = |k: &str| -> Source {
            if case_params.iter().any(|(c, _)| c == k) {
                e.places.source("case", nth, k)
            } else if e.sweep.iter().any(|(a, _)| a == k) {
                e.places.source("sweep", 0, k)
            } else {
                e.places.source("fixed", 0, k)
            }
        };
        let axes: Vec<(String, Vec<Value>)> = e.axes_for(case_params).map(|(k, v)| (k.clone(), v.clone())).collect();
        let overrides: Vec<(String, Value)> = case_params.iter().filter(|(k, _)| !axes.iter().any(|(a, _)| a == k)).cloned().collect();
        let lens: Vec<usize> = axes.iter().map(|s| s.1.len()).collect();
        let total: usize = lens.iter().product();
        for flat in 0..total {
            // Decode the flat index, last axis fastest.
            let mut at = vec![0; lens.len()];
            let mut rest = flat;
            for k in (0..lens.len()).rev() {
                at[k] = rest % lens[k];
                rest /= lens[k];
            }
            // Fixed parameters of the file's mode that a case of the other
            // mode does not have are left out for it.
            let mut params: Vec<(String, Value)> = e.fixed.iter().filter(|(k, _)| mode.known(k)).cloned().collect();
            let swept = axes.iter().zip(&at).map(|((k, vals), &i)| (k.clone(), vals[i].clone()));
            for (k, v) in overrides.iter().cloned().chain(swept) {
                params.retain(|(p, _)| *p != k);
                params.push((k, v));
            }
            let given = mode.typed(&params, from)?;
            for repeat in 0..e.repeats {
                runs.push(RunSpec { id: runs.len(), mode: *mode, case: case.clone(), repeat, params: params.clone(), given: given.clone(), at: at.clone() });
            }
        }
    }
    Ok(runs)
}
