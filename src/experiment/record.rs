//! A sweep folder's record: its runs.csv (with the run images and the
//! reference image that go with its rows), read back whole and checked
//! before a sweep writes the folder, and moved aside, never truncated,
//! when a sweep starts afresh.

use super::error::{ExperimentError, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a folder already holds.
#[derive(Debug)]
pub enum Found {
    /// No runs.csv, or one with no rows.
    Nothing,
    /// Rows with the experiment's columns: each with its line in the file,
    /// and how many rows have each fingerprint; `torn`, the line number of
    /// a last line cut off mid-write (no newline), which is left out.
    Rows { rows: Vec<(u64, Vec<String>)>, fingerprints: BTreeMap<String, usize>, torn: Option<u64> },
    /// A runs.csv with other columns (another experiment, or one written
    /// by another version of refract) and its row count.
    OtherColumns(usize),
}

/// Reads `dir`/runs.csv's complete rows (a torn last line is left out and
/// its line number kept).
pub fn inspect(dir: &Path, header: &[String]) -> Result<Found> {
    let path = dir.join("runs.csv");
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Found::Nothing),
        Err(e) => return Err(ExperimentError::io(format!("cannot read {}", path.display()))(e)),
    };
    let complete = match text.rfind('\n') {
        Some(i) => &text[..=i],
        None => "",
    };
    let torn = (complete.len() < text.len()).then(|| complete.matches('\n').count() as u64 + 1);
    let mut r = csv::ReaderBuilder::new().flexible(true).from_reader(complete.as_bytes());
    let h: Vec<String> = r.headers().map(|h| h.iter().map(str::to_string).collect()).unwrap_or_default();
    let mut rows = Vec::new();
    for x in r.records() {
        let x = x.map_err(|csv| ExperimentError::UnreadableRow { path: path.clone(), line: csv.position().map_or(0, |p| p.line()), csv })?;
        rows.push((x.position().map_or(0, |p| p.line()), x.iter().map(str::to_string).collect::<Vec<_>>()));
    }
    if rows.is_empty() {
        return Ok(Found::Nothing);
    }
    if h != header {
        return Ok(Found::OtherColumns(rows.len()));
    }
    if let Some((line, r)) = rows.iter().find(|(_, r)| r.len() != header.len()) {
        return Err(ExperimentError::PartRow { path, line: *line, cells: r.len(), columns: header.len() });
    }
    let fp = header.iter().position(|c| c == "experiment");
    let mut fingerprints = BTreeMap::new();
    for (_, r) in &rows {
        *fingerprints.entry(fp.and_then(|c| r.get(c)).cloned().unwrap_or_default()).or_insert(0) += 1;
    }
    Ok(Found::Rows { rows, fingerprints, torn })
}

/// The rows a resumed sweep goes on from: each a run of the experiment's
/// `total`, each run once. A row naming no run of the experiment, or a run
/// twice with different cells, is refused with its lines; a run twice with
/// the same cells is kept once, and said so (in the returned notes).
pub fn check_rows(path: &Path, rows: Vec<(u64, Vec<String>)>, total: usize) -> Result<(Vec<Vec<String>>, Vec<String>)> {
    let mut first: BTreeMap<usize, (u64, Vec<String>)> = BTreeMap::new();
    let mut notes = Vec::new();
    for (line, r) in rows {
        let id = match r[0].parse::<usize>() {
            Ok(id) if id < total => id,
            _ => return Err(ExperimentError::NotARun { path: path.into(), line, id: r[0].clone(), last: total.saturating_sub(1) }),
        };
        match first.get(&id) {
            None => {
                first.insert(id, (line, r));
            }
            Some((l0, r0)) if *r0 == r => notes.push(format!("{}: run {id} is twice (lines {l0} and {line}), the same both times; kept once", path.display())),
            Some((l0, _)) => return Err(ExperimentError::RunTwice { path: path.into(), id, first: *l0, second: line }),
        }
    }
    Ok((first.into_values().map(|(_, r)| r).collect(), notes))
}

/// The files of a record, in the order they are moved aside.
const PARTS: [&str; 3] = ["runs.csv", "images", "reference.png"];

/// Moves `dir`'s record (runs.csv, images/, reference.png) aside to the
/// first free `runs.csv.N`, `images.N`, `reference.png.N`, so that a fresh
/// start loses nothing; returns where runs.csv went.
pub fn move_aside(dir: &Path) -> Result<PathBuf> {
    let n = (1..).find(|n| PARTS.iter().all(|p| !dir.join(format!("{p}.{n}")).exists())).unwrap_or(1);
    for p in PARTS {
        let from = dir.join(p);
        if from.exists() {
            let to = dir.join(format!("{p}.{n}"));
            std::fs::rename(&from, &to).map_err(ExperimentError::io(format!("cannot move {} aside to {}", from.display(), to.display())))?;
        }
    }
    Ok(dir.join(format!("runs.csv.{n}")))
}

/// "20 runs of lab-ior@0123..., 3 of lab-ior@4567..."
pub fn describe(fingerprints: &BTreeMap<String, usize>) -> String {
    let parts: Vec<String> = fingerprints.iter().map(|(f, n)| format!("{n} of experiment {}", if f.is_empty() { "(none)" } else { f })).collect();
    let total: usize = fingerprints.values().sum();
    format!("{} ({})", if total == 1 { "1 run".to_string() } else { format!("{total} runs") }, parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_moves_aside_to_the_first_free_number() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("runs.csv"), "run_id,experiment\n0,a@1\n").unwrap();
        std::fs::create_dir(d.join("images")).unwrap();
        std::fs::write(d.join("images/0.png"), "x").unwrap();
        std::fs::write(d.join("runs.csv.1"), "older").unwrap();
        let to = move_aside(d).unwrap();
        assert_eq!(to, d.join("runs.csv.2"));
        assert_eq!(std::fs::read_to_string(d.join("runs.csv.2")).unwrap(), "run_id,experiment\n0,a@1\n");
        assert!(d.join("images.2/0.png").exists() && !d.join("runs.csv").exists() && !d.join("images").exists());
        assert_eq!(std::fs::read_to_string(d.join("runs.csv.1")).unwrap(), "older");
    }

    #[test]
    fn inspect_counts_fingerprints_and_knows_other_columns() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let h: Vec<String> = ["run_id", "experiment"].iter().map(|s| s.to_string()).collect();
        assert!(matches!(inspect(d, &h).unwrap(), Found::Nothing));
        std::fs::write(d.join("runs.csv"), "run_id,experiment\n0,a@1\n1,a@2\n2,a@1\n3,a@").unwrap();
        match inspect(d, &h).unwrap() {
            Found::Rows { rows, fingerprints, torn } => {
                assert_eq!((rows.len(), rows[2].0, torn), (3, 4, Some(5)));
                assert_eq!(describe(&fingerprints), "3 runs (2 of experiment a@1, 1 of experiment a@2)");
            }
            f => panic!("{f:?}"),
        }
        std::fs::write(d.join("runs.csv"), "x,y\n1,2\n").unwrap();
        assert!(matches!(inspect(d, &h).unwrap(), Found::OtherColumns(1)));
    }

    #[test]
    fn resumed_rows_are_each_run_once() {
        let p = Path::new("r.csv");
        let row = |id: &str, v: &str| vec![id.to_string(), v.to_string()];
        let (rows, notes) = check_rows(p, vec![(2, row("1", "a")), (3, row("0", "b")), (4, row("1", "a"))], 3).unwrap();
        assert_eq!(rows, vec![row("0", "b"), row("1", "a")]);
        assert_eq!(notes, vec!["r.csv: run 1 is twice (lines 2 and 4), the same both times; kept once".to_string()]);
        let err = check_rows(p, vec![(2, row("1", "a")), (5, row("1", "c"))], 3).unwrap_err().to_string();
        assert!(err.starts_with("r.csv: run 1 is twice, with different cells (lines 2 and 5)"), "{err}");
        let err = check_rows(p, vec![(2, row("999", "a"))], 3).unwrap_err().to_string();
        assert!(err.starts_with("r.csv:2: `999` is not a run of this experiment (its runs are 0 to 2)"), "{err}");
    }
}
