//! Why a benchmark refused to start or stopped: a flag, a disagreement
//! between the structures it times, or an error of what it runs.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("--out: {0}")]
    Out(crate::image_io::WriteError),
    #[error("--out: {0}")]
    OutFile(crate::data::NotRegularFile),
    #[error("--only: {bad} is not one of the photograph-like figures ({figures})")]
    Only { bad: String, figures: String },
    #[error("bvh and linear disagree on {triangles} triangles: {bvh} vs {linear} hits")]
    RowHits { triangles: usize, bvh: u64, linear: u64 },
    #[error("bvh and linear disagree on incoherent rays: {bvh} vs {linear} hits")]
    IncoherentHits { bvh: u64, linear: u64 },
    #[error("the benchmark sphere is not in view")]
    NotInView,
    #[error("cannot write {}: {error}", .path.display())]
    CannotWrite { path: PathBuf, error: crate::image_io::WriteError },
    #[error("writing the error CSV: {0}")]
    ErrorCsv(std::io::Error),
    #[error(transparent)]
    Scene(#[from] crate::scenes::SceneError),
    #[error(transparent)]
    Render(#[from] crate::spectral::RunError),
    #[error(transparent)]
    Exact(#[from] crate::spectral::exact::ExactError),
    #[error(transparent)]
    Mode(#[from] crate::modes::ModeError),
    #[error(transparent)]
    Experiment(#[from] crate::experiment::error::ExperimentError),
    #[error(transparent)]
    Chart(#[from] super::error_chart::ChartError),
    #[error(transparent)]
    Peer(#[from] super::mitsuba::PeerError),
    #[cfg(feature = "embree")]
    #[error(transparent)]
    Embree(#[from] crate::geometry::embree::EmbreeError),
    #[error(transparent)]
    Threads(#[from] rayon::ThreadPoolBuildError),
    #[error(transparent)]
    Csv(#[from] csv::Error),
    #[error(transparent)]
    Utf8(#[from] std::string::FromUtf8Error),
    /// Text formatted into a report.
    #[error(transparent)]
    Fmt(#[from] std::fmt::Error),
}
