//! Appending timing rows to a CSV file: header written once, every row
//! flushed, so the rows of an interrupted sweep survive.

use anyhow::{bail, Context, Result};
use std::io::{Read, Seek, Write};
use std::path::Path;

/// Formats a float for a CSV cell; a NaN or infinity never reaches a CSV.
pub fn cell(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6}")
    } else {
        "0".to_string()
    }
}

/// Checks, before any work is done, that `path` is absent, empty or has
/// exactly these columns.
pub fn check_header(path: &Path, header: &[&str]) -> Result<()> {
    match std::fs::read_to_string(path) {
        Ok(text) => {
            let first = text.lines().next().unwrap_or("");
            if !text.trim().is_empty() && first != header.join(",") {
                bail!("{}: its columns `{first}` are not this mode's `{}`; use another file", path.display(), header.join(","));
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e).with_context(|| format!("cannot read timing file {}", path.display())),
    }
}

/// Appends `row` under `header`; refuses a file whose header differs.
pub fn append_row(path: &Path, header: &[&str], row: &[String]) -> Result<()> {
    assert_eq!(header.len(), row.len(), "timing row and header differ in length");
    let mut file =
        std::fs::OpenOptions::new().create(true).read(true).append(true).open(path).with_context(|| format!("cannot open timing file {}", path.display()))?;
    let mut existing = String::new();
    file.read_to_string(&mut existing).with_context(|| format!("cannot read timing file {}", path.display()))?;
    check_header(path, header)?;
    let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
    if existing.trim().is_empty() {
        w.write_record(header)?;
    }
    w.write_record(row)?;
    let mut bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    if !existing.is_empty() && !existing.ends_with('\n') {
        bytes.insert(0, b'\n');
    }
    file.seek(std::io::SeekFrom::End(0))?;
    file.write_all(&bytes)?;
    file.flush()?;
    Ok(())
}
