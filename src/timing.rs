//! Appending timing rows to a CSV file: each mode's row is a serde record
//! (its field names are the columns), the header is written once, every
//! row flushed, so the rows of an interrupted run survive. And the calling
//! thread's CPU time, for per-thread rates.

use serde::Serialize;
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// Why a timing file is refused or could not be written.
#[derive(Debug, thiserror::Error)]
pub enum TimingError {
    #[error(transparent)]
    NotRegular(#[from] crate::data::NotRegularFile),
    #[error("folder {} does not exist", .0.display())]
    NoFolder(PathBuf),
    #[error("{}: its columns `{found}` are not this mode's `{header}`; use another file", .path.display())]
    Columns { path: PathBuf, found: String, header: String },
    #[error("cannot {what} timing file {}: {source}", .path.display())]
    Io { what: &'static str, path: PathBuf, source: std::io::Error },
    #[error("a timing row: {0}")]
    Csv(#[from] csv::Error),
}

type Result<T> = std::result::Result<T, TimingError>;

/// An I/O error on the timing file at `path` while doing `what`.
fn io(what: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> TimingError {
    let path = path.to_path_buf();
    move |source| TimingError::Io { what, path, source }
}

/// A finished CSV writer's bytes.
fn bytes_of(w: csv::Writer<Vec<u8>>) -> Result<Vec<u8>> {
    w.into_inner().map_err(|e| TimingError::Csv(e.into_error().into()))
}

/// A measured number in a CSV cell: six decimals, and an empty cell (no
/// value) for a NaN or an infinity, which never reach a CSV.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Real(pub f64);

impl Serialize for Real {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(&cell(self.0))
    }
}

/// The columns of a record type, as its header line.
pub fn header_of<T: Serialize + Default>() -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(T::default())?;
    let bytes = bytes_of(w)?;
    Ok(String::from_utf8_lossy(&bytes).lines().next().unwrap_or_default().to_string())
}

/// Formats a float for a CSV cell; a NaN or infinity never reaches a CSV:
/// its cell is left empty, the usual mark of a missing value (0 would read
/// as a measurement, and as a perfect one for an error).
pub fn cell(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6}")
    } else {
        String::new()
    }
}

/// Checks, before any work is done, that `path` is in a folder that
/// exists and is absent, or a regular file that is empty or has exactly
/// the columns of record type `T` (a FIFO or device is never read).
pub fn check_header<T: Serialize + Default>(path: &Path) -> Result<()> {
    crate::data::check_regular(path)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
        return Err(TimingError::NoFolder(dir.to_path_buf()));
    }
    check_line(path, &header_of::<T>()?)
}

fn check_line(path: &Path, header: &str) -> Result<()> {
    match std::fs::read_to_string(path) {
        Ok(text) => {
            let first = text.lines().next().unwrap_or("");
            if !text.trim().is_empty() && first != header {
                return Err(TimingError::Columns { path: path.to_path_buf(), found: first.to_string(), header: header.to_string() });
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(io("read", path)(e)),
    }
}

/// Appends `record` (with the header line first if the file is new or
/// empty); refuses a file whose header differs.
pub fn append<T: Serialize + Default>(path: &Path, record: &T) -> Result<()> {
    let header = header_of::<T>()?;
    let mut file = std::fs::OpenOptions::new().create(true).read(true).append(true).open(path).map_err(io("open", path))?;
    let mut existing = String::new();
    file.read_to_string(&mut existing).map_err(io("read", path))?;
    check_line(path, &header)?;
    let mut w = csv::WriterBuilder::new().has_headers(existing.trim().is_empty()).from_writer(Vec::new());
    w.serialize(record)?;
    let mut bytes = bytes_of(w)?;
    if !existing.is_empty() && !existing.ends_with('\n') {
        bytes.insert(0, b'\n');
    }
    file.seek(std::io::SeekFrom::End(0)).map_err(io("write", path))?;
    file.write_all(&bytes).map_err(io("write", path))?;
    file.flush().map_err(io("write", path))?;
    Ok(())
}

/// CPU time the calling thread has run, in seconds (`CLOCK_THREAD_CPUTIME_ID`):
/// unlike the wall clock it stops while other threads or processes have
/// the core. It does not see a virtual machine's host taking the core
/// away. `None` where the system does not say.
pub fn thread_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    return cpu_clock(libc::CLOCK_THREAD_CPUTIME_ID);
    #[cfg(not(unix))]
    None
}

/// CPU time the whole process has run, every thread, in seconds
/// (`CLOCK_PROCESS_CPUTIME_ID`): the work a multi-threaded render did,
/// which other processes on a shared machine slow but do not add to.
/// `None` where the system does not say.
pub fn process_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    return cpu_clock(libc::CLOCK_PROCESS_CPUTIME_ID);
    #[cfg(not(unix))]
    None
}

/// One of the system's CPU-time clocks, in seconds.
#[cfg(unix)]
fn cpu_clock(clock: libc::clockid_t) -> Option<f64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid timespec for the call to fill.
    let ok = unsafe { libc::clock_gettime(clock, &mut ts) } == 0;
    ok.then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

#[cfg(all(test, unix))]
mod tests {
    use super::thread_cpu_seconds;
    use std::time::{Duration, Instant};

    /// The thread's CPU time stands still while it sleeps and runs on
    /// while it works.
    #[test]
    fn thread_cpu_time_counts_work_not_sleep() {
        let before = thread_cpu_seconds().expect("a CPU clock");
        std::thread::sleep(Duration::from_millis(300));
        let slept = thread_cpu_seconds().unwrap() - before;
        assert!(slept < 0.1, "{slept} s of CPU time in a 0.3 s sleep");
        let (start, wall) = (thread_cpu_seconds().unwrap(), Instant::now());
        let mut x = 1u64;
        while thread_cpu_seconds().unwrap() - start < 0.05 {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
            assert!(wall.elapsed() < Duration::from_secs(20), "no CPU time counted in 20 s of work");
        }
    }
}

/// A rate as people read it: `5.3 M photons/s`, `812 rows/s`,
/// `42.0 k rays/s` (three significant digits at most).
pub fn rate(per_s: f64, unit: &str) -> String {
    let (v, prefix) = match per_s.abs() {
        x if x >= 1e9 => (per_s / 1e9, "G "),
        x if x >= 1e6 => (per_s / 1e6, "M "),
        x if x >= 1e4 => (per_s / 1e3, "k "),
        _ => (per_s, ""),
    };
    let digits = if v.abs() >= 100.0 || prefix.is_empty() && v.abs() >= 10.0 { 0 } else { 1 };
    format!("{v:.digits$} {prefix}{unit}/s")
}

/// A duration as people say it: `40 s`, `14 minutes`, `9.2 hours`, `3.1 days`.
pub fn spoken_seconds(s: f64) -> String {
    match s {
        s if s < 90.0 => format!("{s:.0} s"),
        s if s < 5400.0 => format!("{:.0} minutes", s / 60.0),
        s if s < 172_800.0 => format!("{:.1} hours", s / 3600.0),
        s => format!("{:.1} days", s / 86_400.0),
    }
}

#[cfg(test)]
mod rate_tests {
    use super::{rate, spoken_seconds};

    #[test]
    fn durations_read_as_people_say_them() {
        assert_eq!(spoken_seconds(40.2), "40 s");
        assert_eq!(spoken_seconds(840.0), "14 minutes");
        assert_eq!(spoken_seconds(33_120.0), "9.2 hours");
        assert_eq!(spoken_seconds(267_840.0), "3.1 days");
    }

    #[test]
    fn rates_read_as_people_write_them() {
        assert_eq!(rate(5.3e6, "photons"), "5.3 M photons/s");
        assert_eq!(rate(64.9494, "rows"), "65 rows/s");
        assert_eq!(rate(3.27, "rows"), "3.3 rows/s");
        assert_eq!(rate(812.0, "rows"), "812 rows/s");
        assert_eq!(rate(42_000.0, "rays"), "42.0 k rays/s");
        assert_eq!(rate(123.4e6, "rays"), "123 M rays/s");
        assert_eq!(rate(2.5e9, "photons"), "2.5 G photons/s");
    }
}
