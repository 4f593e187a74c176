//! Why an experiment, a scene file, a record or a report was refused or
//! not finished. Each message is one line naming the file (and line), the
//! flag or the figure it is about.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// A flag's value that makes no run (the flag, then why).
    #[error("{flag}: {why}")]
    Flag { flag: &'static str, why: String },
    /// A file or folder that could not be read, moved or named (what was
    /// being done, naming it).
    #[error("{doing}: {io}")]
    Io { doing: String, io: std::io::Error },
    /// A row of a record that cannot be read.
    #[error("{}:{line}: unreadable row: {csv}", .path.display())]
    UnreadableRow { path: PathBuf, line: u64, csv: csv::Error },
    /// A row of a record that holds part of a run.
    #[error("{}:{line}: not a whole run ({cells} of {columns} cells); delete that line, or run with --fresh to move the record aside", .path.display())]
    PartRow { path: PathBuf, line: u64, cells: usize, columns: usize },
    /// A row of a record whose run is no run of the experiment.
    #[error("{}:{line}: `{id}` is not a run of this experiment (its runs are 0 to {last}); delete that line, or run with --fresh to move the record aside", .path.display())]
    NotARun { path: PathBuf, line: u64, id: String, last: usize },
    /// A run recorded twice with different cells.
    #[error("{}: run {id} is twice, with different cells (lines {first} and {second}); delete the line you do not want, or run with --fresh to move the record aside", .path.display())]
    RunTwice { path: PathBuf, id: usize, first: u64, second: u64 },
    #[error(transparent)]
    Script(#[from] std::io::Error),
    #[error(transparent)]
    Plot(#[from] super::plot::PlotError),
    #[error(transparent)]
    Write(#[from] crate::image_io::WriteError),
    #[error(transparent)]
    Mode(#[from] crate::modes::ModeError),
    #[error(transparent)]
    Scene(#[from] crate::scenes::SceneError),
    /// Text formatted into a table or a summary.
    #[error(transparent)]
    Fmt(#[from] std::fmt::Error),
}

impl ExperimentError {
    /// A flag's refusal.
    pub(crate) fn flag(flag: &'static str, why: impl Into<String>) -> ExperimentError {
        ExperimentError::Flag { flag, why: why.into() }
    }

    /// An I/O error while `doing` something (the text names the file).
    pub(crate) fn io(doing: impl Into<String>) -> impl FnOnce(std::io::Error) -> ExperimentError {
        let doing = doing.into();
        move |io| ExperimentError::Io { doing, io }
    }
}

pub(crate) type Result<T, E = ExperimentError> = std::result::Result<T, E>;
