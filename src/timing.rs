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

/// Appends `row` under `header`; refuses a file whose header differs.
pub fn append_row(path: &Path, header: &[&str], row: &[String]) -> Result<()> {
    assert_eq!(header.len(), row.len(), "timing row and header differ in length");
    let mut file =
        std::fs::OpenOptions::new().create(true).read(true).append(true).open(path).with_context(|| format!("cannot open timing file {}", path.display()))?;
    let mut existing = String::new();
    file.read_to_string(&mut existing).with_context(|| format!("cannot read timing file {}", path.display()))?;
    let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(Vec::new());
    if existing.trim().is_empty() {
        w.write_record(header)?;
    } else {
        let first = existing.lines().next().unwrap_or("");
        if first != header.join(",") {
            bail!("{}: its columns `{first}` are not this mode's `{}`; use another file", path.display(), header.join(","));
        }
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
