//! No saved work is lost: a sweep's record is never overwritten, truncated
//! or taken by another sweep; quick runs keep out of the committed folder.

use crate::common::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Every file under `dir`, with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

fn row_count(dir: &Path) -> usize {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    csv::Reader::from_reader(text.as_bytes()).records().count()
}

/// A folder like the repository's: the tiny experiment and its mesh, so
/// that `results/` there is the "committed" one.
fn project() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("off")).unwrap();
    std::fs::copy(repo("off/cube.off"), dir.path().join("off/cube.off")).unwrap();
    std::fs::copy(repo("tests/data/tiny.toml"), dir.path().join("tiny.toml")).unwrap();
    dir
}

#[test]
fn a_quick_sweep_or_plan_leaves_the_committed_record_byte_identical() {
    let p = project();
    let o = run(&["sweep", "tiny.toml"], "", p.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let committed = p.path().join("results/tiny");
    assert_eq!(row_count(&committed), 6);
    let before = snapshot(&committed);
    let o = run(&["sweep", "tiny.toml", "--quick"], "", p.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("results/quick/tiny/runs.csv"), "{}", stderr(&o));
    assert_eq!(row_count(&p.path().join("results/quick/tiny")), 4);
    let o = run(&["sweep", "plan", "tiny.toml", "--quick", "--engine", "parallel"], "", p.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(p.path().join("results/quick/tiny/merge.sh").exists());
    assert_eq!(snapshot(&committed), before, "results/tiny changed");
    // Told to write the quick version into the full record's folder, it
    // refuses, naming the flag that would move the record aside ...
    let o = run(&["sweep", "tiny.toml", "--quick", "--out", "results/tiny"], "", p.path());
    assert_clean_failure(&o, "results/tiny/runs.csv: holds 6 runs (6 of experiment tiny@");
    assert!(stderr(&o).contains("--quick version") && stderr(&o).contains("--fresh"), "{}", stderr(&o));
    assert_eq!(snapshot(&committed), before, "a refused sweep wrote");
    // ... and so does another experiment's sweep, or an edited file's.
    std::fs::write(p.path().join("edited.toml"), std::fs::read_to_string(p.path().join("tiny.toml")).unwrap() + "# edited\n").unwrap();
    let o = run(&["sweep", "edited.toml", "--out", "results/tiny", "--resume"], "", p.path());
    assert_clean_failure(&o, "results/tiny/runs.csv: holds 6 runs");
    assert_eq!(snapshot(&committed), before, "a refused sweep wrote");
    // With --fresh the old record is moved aside whole.
    let o = run(&["sweep", "tiny.toml", "--quick", "--out", "results/tiny", "--fresh"], "", p.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("moved it aside to results/tiny/runs.csv.1"), "{}", stderr(&o));
    assert_eq!(std::fs::read(committed.join("runs.csv.1")).unwrap(), before[Path::new("runs.csv")]);
    assert_eq!(std::fs::read(committed.join("images.1/5.png")).unwrap(), before[Path::new("images/5.png")]);
    assert_eq!(std::fs::read(committed.join("reference.png.1")).unwrap(), before[Path::new("reference.png")]);
    assert_eq!(row_count(&committed), 4);
}
