//! Why an experiment, a scene file, a record or a report was refused or
//! not finished. Each message is one line naming the file (and line), the
//! flag or the figure it is about.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// A scene or experiment file that could not be read.
    #[error("{}: cannot read: {io}", .path.display())]
    Read { path: PathBuf, io: std::io::Error },
    /// A file that is not TOML, at the line of the mistake.
    #[error("{file}:{line}: {why}")]
    Syntax { file: String, line: usize, why: String },
    /// A key of a file refused, at its line.
    #[error("{file}:{line}: `{key}`: {why}")]
    Key { file: String, line: usize, key: String, why: String },
    #[error("{file}: missing `{key}`")]
    Missing { file: String, key: String },
    /// A key the file's scene refuses where no line holds it.
    #[error("{file}: `{key}`: {why}")]
    FileKey { file: String, key: String, why: String },
    /// A value refused, named where it was given (a flag, a prompt's answer).
    #[error("{at}: {why}")]
    Given { at: String, why: String },
    /// The scene a file describes cannot be built.
    #[error("{file}: {error}")]
    Scene { file: String, error: crate::scenes::SceneError },
    /// A mistake in a file's [quick] version (the mistake with its causes).
    #[error("{} (in the file's [quick] version)", chain(.0.as_ref()))]
    Quick(Box<ExperimentError>),
    /// `--set KEY=VALUE` naming no parameter.
    #[error("--set `{key}`: {error}")]
    SetUnknown { key: String, error: crate::params::KeyError },
    /// `--set KEY=VALUE` with a value the key refuses or the run ignores.
    #[error("--set {key}: {why}")]
    SetValue { key: String, why: String },
    /// A rendered image that could not be read back to draw on.
    #[error("{}: cannot {doing}: {error}", .path.display())]
    ReadBack { path: PathBuf, doing: &'static str, error: image::ImageError },
    #[error("{id}: the close-up does not fit in a {width}x{height} image")]
    CloseUpFit { id: String, width: usize, height: usize },
    /// Labels that could not be drawn on a scene's image.
    #[error("{id}: {what}: {error}")]
    Label { id: String, what: &'static str, error: super::labels::LabelError },
    /// The output folder that could not be made (its causes after it).
    #[error("--out: {}", chain(.0.as_ref()))]
    Out(Box<crate::image_io::WriteError>),
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
    /// A plot naming a column the record does not have.
    #[error("plot column `{name}` is not in runs.csv; columns: {columns}")]
    Column { name: String, columns: String },
    /// A record (a runs.csv, a shard's folder) refused, naming it.
    #[error("{}: {why}", .path.display())]
    Record { path: PathBuf, why: String },
    /// A line of a record refused.
    #[error("{}:{line}: {why}", .path.display())]
    RecordLine { path: PathBuf, line: u64, why: String },
    #[error("{}: unreadable header: {csv}", .path.display())]
    Header { path: PathBuf, csv: csv::Error },
    /// A folder named twice to merge.
    #[error("{} is given twice", .0.display())]
    GivenTwice(PathBuf),
    #[error("no folders to merge")]
    NoFolders,
    #[error("run {id} is in both {} and {}; each run belongs to one shard", .first.display(), .second.display())]
    InTwoShards { id: String, first: PathBuf, second: PathBuf },
    #[error("runs {runs} are in no shard ({missing} of {total}); run them into a shard's folder with `refract sweep FILE --resume --out DIR`, or merge with --resume to run them here, then merge again")]
    InNoShard { runs: String, missing: usize, total: usize },
    /// What was done, and why the command still fails (a run failed).
    #[error("{done}; {why}")]
    Failed { done: String, why: String },
    /// A row that could not be added to a sweep's record (with its causes).
    #[error("writing {}: {}", .dir.display(), chain(.error.as_ref()))]
    Writing { dir: PathBuf, error: Box<ExperimentError> },
    /// An I/O error whose own text says enough.
    #[error(transparent)]
    Disk(#[from] std::io::Error),
    #[error(transparent)]
    Csv(#[from] csv::Error),
    #[error(transparent)]
    Glass(#[from] crate::optics::glass::UnknownGlass),
    #[error(transparent)]
    Lock(#[from] super::lock::LockError),
    #[error(transparent)]
    Threads(#[from] rayon::ThreadPoolBuildError),
    #[error(transparent)]
    Labels(#[from] super::labels::LabelError),
    #[error(transparent)]
    Render(#[from] crate::spectral::RunError),
    #[error(transparent)]
    Plot(#[from] super::plot::PlotError),
    #[error(transparent)]
    Write(#[from] crate::image_io::WriteError),
    #[error(transparent)]
    Mode(#[from] crate::modes::ModeError),
    #[error(transparent)]
    Build(#[from] crate::scenes::SceneError),
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

/// An error and its causes, as the program prints them (`a: b: c`).
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        text.push_str(&format!(": {c}"));
        cause = c.source();
    }
    text
}

pub(crate) type Result<T, E = ExperimentError> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    /// An error that says `what` and has `cause` below it.
    #[derive(Debug)]
    struct Layer {
        what: &'static str,
        cause: Option<Box<Layer>>,
    }

    impl std::fmt::Display for Layer {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(self.what)
        }
    }

    impl std::error::Error for Layer {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            self.cause.as_deref().map(|c| c as &(dyn std::error::Error + 'static))
        }
    }

    #[test]
    fn chain_is_the_error_then_each_cause_in_order() {
        let bottom = Layer { what: "c", cause: None };
        let middle = Layer { what: "b", cause: Some(Box::new(bottom)) };
        let top = Layer { what: "a", cause: Some(Box::new(middle)) };
        assert_eq!(chain(&top), "a: b: c");
    }

    #[test]
    fn chain_of_an_error_without_causes_is_its_text() {
        assert_eq!(chain(&Layer { what: "alone", cause: None }), "alone");
    }

    #[test]
    fn a_quick_mistake_prints_its_causes_once() {
        let inner = ExperimentError::Key { file: "e.toml".into(), line: 3, key: "photons".into(), why: "not a number".into() };
        let quick = ExperimentError::Quick(Box::new(inner));
        assert_eq!(chain(&quick), "e.toml:3: `photons`: not a number (in the file's [quick] version)");
    }
}
