//! Appending timing rows to a CSV file: each mode's row is a serde record
//! (its field names are the columns), the header is written once, every
//! row flushed, so the rows of an interrupted run survive.

use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::io::{Read, Seek, Write};
use std::path::Path;

/// A measured number in a CSV cell: six decimals, and 0 for a NaN or an
/// infinity, which never reach a CSV.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Real(pub f64);

impl Serialize for Real {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&cell(self.0))
    }
}

/// The columns of a record type, as its header line.
pub fn header_of<T: Serialize + Default>() -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(T::default())?;
    let bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(String::from_utf8_lossy(&bytes).lines().next().unwrap_or_default().to_string())
}

/// Formats a float for a CSV cell; a NaN or infinity never reaches a CSV.
pub fn cell(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6}")
    } else {
        "0".to_string()
    }
}

/// Checks, before any work is done, that `path` is in a folder that
/// exists and is absent, or a regular file that is empty or has exactly
/// the columns of record type `T` (a FIFO or device is never read).
pub fn check_header<T: Serialize + Default>(path: &Path) -> Result<()> {
    if std::fs::symlink_metadata(path).is_ok_and(|m| !m.is_file()) {
        bail!("{} is not a regular file", path.display());
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
        bail!("folder {} does not exist", dir.display());
    }
    check_line(path, &header_of::<T>()?)
}

fn check_line(path: &Path, header: &str) -> Result<()> {
    match std::fs::read_to_string(path) {
        Ok(text) => {
            let first = text.lines().next().unwrap_or("");
            if !text.trim().is_empty() && first != header {
                bail!("{}: its columns `{first}` are not this mode's `{header}`; use another file", path.display());
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e).with_context(|| format!("cannot read timing file {}", path.display())),
    }
}

/// Appends `record` (with the header line first if the file is new or
/// empty); refuses a file whose header differs.
pub fn append<T: Serialize + Default>(path: &Path, record: &T) -> Result<()> {
    let header = header_of::<T>()?;
    let mut file =
        std::fs::OpenOptions::new().create(true).read(true).append(true).open(path).with_context(|| format!("cannot open timing file {}", path.display()))?;
    let mut existing = String::new();
    file.read_to_string(&mut existing).with_context(|| format!("cannot read timing file {}", path.display()))?;
    check_line(path, &header)?;
    let mut w = csv::WriterBuilder::new().has_headers(existing.trim().is_empty()).from_writer(Vec::new());
    w.serialize(record)?;
    let mut bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    if !existing.is_empty() && !existing.ends_with('\n') {
        bytes.insert(0, b'\n');
    }
    file.seek(std::io::SeekFrom::End(0))?;
    file.write_all(&bytes)?;
    file.flush()?;
    Ok(())
}
