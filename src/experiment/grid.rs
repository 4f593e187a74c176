//! The grid of an experiment's runs: every combination of its cases, sweep
//! axes and repeats, each with an id that depends only on the experiment
//! file (so shards, engines and resumed sweeps agree on it).

use super::spec::{Case, Experiment};
use crate::modes::Mode;
use toml::Value;

/// One run of the grid.
#[derive(Clone, Debug)]
pub struct RunSpec {
    pub id: usize,
    pub mode: Mode,
    pub case: String,
    pub repeat: u32,
    /// Effective parameters: fixed, then the case's, then the swept ones.
    pub params: Vec<(String, Value)>,
    /// Index along each sweep axis.
    pub at: Vec<usize>,
}

/// Every run of an experiment, in a fixed order (case, then the sweep axes
/// with the first outermost, then repeats).
pub fn expand(e: &Experiment) -> Vec<RunSpec> {
    let cases = if e.cases.is_empty() {
        vec![Case { name: String::new(), mode: e.mode, params: Vec::new(), expect: super::spec::Expect::Ok }]
    } else {
        e.cases.clone()
    };
    let mut runs = Vec::new();
    for Case { name: case, mode, params: case_params, .. } in &cases {
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
            for repeat in 0..e.repeats {
                runs.push(RunSpec { id: runs.len(), mode: *mode, case: case.clone(), repeat, params: params.clone(), at: at.clone() });
            }
        }
    }
    runs
}
