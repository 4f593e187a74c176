//! Progress of a long computation, reported through a trait so the
//! renderers know nothing of terminals: the command line draws bars, tests
//! and sweeps pass `Silent`.

/// Receives a run's progress. Stages are named by the renderer ("light",
/// "eye"); `total` and `advance` count its own units (photons, rows).
/// Called from worker threads, so implementations must be `Sync`.
pub trait Progress: Sync {
    fn start(&self, _stage: &'static str, _total: u64) {}
    fn advance(&self, _stage: &'static str, _n: u64) {}
    fn finish(&self, _stage: &'static str) {}
}

/// Reports nothing.
pub struct Silent;

impl Progress for Silent {}
