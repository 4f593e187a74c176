//! One run's row of a sweep's runs.csv, typed: what the run measured
//! after its identity and parameters. The fields' names are the columns
//! and their order is the columns' order (serde writes both), so no list
//! of column names is kept by hand.

use crate::modes::Record;
use crate::timing::Real;
use serde::Serialize;

/// How a run ended.
#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    #[default]
    Ok,
    Error,
}

/// A metric against the reference image: its value, none (an image the
/// metric does not apply to), or [`NO_REFERENCE`] when the reference run
/// failed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Compared {
    #[default]
    None,
    NoReference,
    Value(f64),
}

/// The cell the metrics against the reference get when the reference run
/// failed.
pub const NO_REFERENCE: &str = "no reference";

impl Serialize for Compared {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Compared::None => s.serialize_str(""),
            Compared::NoReference => s.serialize_str(NO_REFERENCE),
            Compared::Value(v) => Real(*v).serialize(s),
        }
    }
}

/// What one run of a sweep recorded: where it ran, how it ended, its
/// mode's [`Record`], how often it was timed, and its image metrics.
/// Absent values are empty cells.
#[derive(Serialize, Clone, Debug, Default, PartialEq)]
pub struct RunRow {
    /// The experiment's name and fingerprint (`spec::Experiment::fingerprint`).
    pub experiment: String,
    pub host: String,
    pub cpu: String,
    pub cores: String,
    pub load_1min: String,
    pub status: Status,
    pub error: String,
    /// 1 for a run that failed, else 0.
    pub failed: u8,
    pub triangles: Option<usize>,
    pub width: Option<usize>,
    pub height: Option<usize>,
    pub load_s: Option<Real>,
    pub build_s: Option<Real>,
    pub trace_s: Option<Real>,
    pub render_s: Option<Real>,
    pub total_s: Option<Real>,
    /// How many renders the times are the mean of (`min_time`).
    pub renders: Option<u32>,
    /// The process's CPU time per render, every thread.
    pub cpu_s: Option<Real>,
    pub rays: Option<u64>,
    pub rays_per_s: Option<Real>,
    pub photons: Option<u64>,
    pub stored: Option<u64>,
    pub photons_per_s: Option<Real>,
    pub nan_count: Option<usize>,
    pub fireflies: Option<usize>,
    pub tir_fraction: Option<Real>,
    pub highlight_px: Option<usize>,
    /// Pixels changed from the run one step earlier on the first axis.
    pub changed_px: Option<usize>,
    pub rmse: Compared,
    pub psnr: Compared,
    pub rel_rmse: Compared,
    pub rel_error: Option<Real>,
}

impl RunRow {
    /// A run that rendered: its record, timed over `renders` renders.
    pub fn measured(r: &Record, renders: u32, cpu_s: Option<f64>) -> RunRow {
        let traced = r.photons.zip(r.stored);
        RunRow {
            triangles: r.triangles,
            width: Some(r.width),
            height: Some(r.height),
            load_s: r.load_s.map(Real),
            build_s: Some(Real(r.build_s)),
            trace_s: r.trace_s.map(Real),
            render_s: Some(Real(r.render_s)),
            total_s: Some(Real(r.total_s())),
            renders: Some(renders),
            cpu_s: cpu_s.map(Real),
            rays: Some(r.rays),
            rays_per_s: Some(Real(r.rays as f64 / r.render_s.max(1e-12))),
            photons: traced.map(|(p, _)| p),
            stored: traced.map(|(_, s)| s),
            photons_per_s: traced.map(|(p, _)| Real(p as f64 / r.trace_s.unwrap_or(0.0).max(1e-12))),
            tir_fraction: Some(Real(r.tir_fraction)),
            ..RunRow::default()
        }
    }

    /// A run that failed, and why.
    pub fn failed(error: String) -> RunRow {
        RunRow { status: Status::Error, error, failed: 1, ..RunRow::default() }
    }

    /// The columns, in order (the names of the fields).
    pub fn columns() -> Vec<String> {
        // A record of flat cells always has a header; the test below holds it.
        crate::timing::header_of::<RunRow>().map(|h| h.split(',').map(str::to_string).collect()).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The row's cells, as a CSV writer writes them.
    fn cells(row: &RunRow) -> Vec<String> {
        let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
        w.serialize(row).unwrap();
        let bytes = w.into_inner().unwrap();
        let mut r = csv::ReaderBuilder::new().has_headers(false).from_reader(&bytes[..]);
        r.records().next().unwrap().unwrap().iter().map(str::to_string).collect()
    }

    /// The columns of the committed records (results/*/runs.csv after the
    /// parameters): a row must keep reading back.
    const COMMITTED: &str = "experiment,host,cpu,cores,load_1min,status,error,failed,triangles,width,height,load_s,build_s,trace_s,render_s,total_s,renders,cpu_s,rays,rays_per_s,photons,stored,photons_per_s,nan_count,fireflies,tir_fraction,highlight_px,changed_px,rmse,psnr,rel_rmse,rel_error";

    #[test]
    fn the_columns_are_the_committed_records() {
        assert_eq!(RunRow::columns().join(","), COMMITTED);
    }

    #[test]
    fn a_prism_run_fills_its_light_pass_and_leaves_the_mesh_empty() {
        let r = Record {
            width: 4,
            height: 2,
            build_s: 0.5,
            trace_s: Some(2.0),
            render_s: 1.0,
            rays: 8,
            photons: Some(1000),
            stored: Some(600),
            tir_fraction: 0.25,
            ..Record::default()
        };
        let mut row = RunRow::measured(&r, 3, Some(1.5));
        row.rmse = Compared::Value(0.125);
        row.psnr = Compared::Value(f64::INFINITY);
        let cells = cells(&row);
        let at = |name: &str| cells[RunRow::columns().iter().position(|c| c == name).unwrap()].clone();
        assert_eq!(cells.len(), RunRow::columns().len());
        assert_eq!((at("status"), at("failed"), at("triangles"), at("load_s")), ("ok".into(), "0".into(), String::new(), String::new()));
        assert_eq!(
            (at("width"), at("trace_s"), at("total_s"), at("renders"), at("cpu_s")),
            ("4".into(), "2.000000".into(), "3.500000".into(), "3".into(), "1.500000".into())
        );
        assert_eq!((at("photons"), at("stored"), at("photons_per_s"), at("rays_per_s")), ("1000".into(), "600".into(), "500.000000".into(), "8.000000".into()));
        assert_eq!((at("tir_fraction"), at("rmse"), at("psnr"), at("rel_error")), ("0.250000".into(), "0.125000".into(), String::new(), String::new()));
    }

    #[test]
    fn a_failed_run_says_why_and_nothing_else() {
        let mut row = RunRow::failed("bad, \"quoted\" thing".into());
        row.rmse = Compared::NoReference;
        let cells = cells(&row);
        let columns = RunRow::columns();
        let filled: Vec<(&str, &str)> = columns.iter().map(String::as_str).zip(cells.iter().map(String::as_str)).filter(|(_, v)| !v.is_empty()).collect();
        assert_eq!(filled, vec![("status", "error"), ("error", "bad, \"quoted\" thing"), ("failed", "1"), ("rmse", NO_REFERENCE)]);
    }
}
