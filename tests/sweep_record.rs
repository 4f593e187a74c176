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

/// A prism sweep of 20 runs, each long enough to be stopped in the middle.
fn slow_experiment(dir: &Path) -> PathBuf {
    let photons: Vec<String> = (0..20).map(|i| (400_000 + i).to_string()).collect();
    let file = dir.join("slow.toml");
    std::fs::write(
        &file,
        format!(
            "name = \"slow\"\nmode = \"prism\"\n[fixed]\nscene = \"single-prism\"\nsize = [80, 60]\n[sweep]\nphotons = [{}]\n[outputs]\nimages = true\n",
            photons.join(", ")
        ),
    )
    .unwrap();
    file
}

/// Starts `refract ARGS`, waits until runs.csv holds `rows` rows, sends
/// `signal`, and returns the output.
fn stop_after(args: &[&str], dir: &Path, out: &Path, rows: usize, signal: &str) -> std::process::Output {
    let child = bin().args(args).current_dir(dir).stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::piped()).spawn().unwrap();
    let start = std::time::Instant::now();
    while std::fs::read_to_string(out.join("runs.csv")).map_or(0, |t| t.lines().count().saturating_sub(1)) < rows {
        assert!(start.elapsed().as_secs() < 120, "no rows after 2 minutes");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = std::process::Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    child.wait_with_output().unwrap()
}

fn no_temporary_files(dir: &Path) {
    let left: Vec<PathBuf> = snapshot(dir).into_keys().filter(|p| p.to_string_lossy().ends_with(".tmp")).collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

#[test]
fn ctrl_c_then_a_plain_rerun_keeps_every_saved_row_and_the_lock_is_gone() {
    let dir = tempfile::tempdir().unwrap();
    let file = slow_experiment(dir.path());
    let out = dir.path().join("out");
    let args = ["sweep", file.to_str().unwrap(), "--out", out.to_str().unwrap()];
    let o = stop_after(&args, dir.path(), &out, 2, "-INT");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{err}");
    let saved = row_count(&out);
    assert!(saved >= 2 && saved < 20, "{saved} rows");
    assert!(err.contains(&format!("stopped by Ctrl-C (SIGINT): {saved} of 20 runs saved in {}", out.join("runs.csv").display())), "{err}");
    assert!(err.contains(&format!("to finish, run: refract sweep {} --out {} --resume", file.display(), out.display())), "{err}");
    assert!(!out.join(".lock").exists(), "the lock is released");
    no_temporary_files(&out);
    let kept = std::fs::read(out.join("runs.csv")).unwrap();
    assert!(kept.ends_with(b"\n"), "no half-written row");
    // The up-arrow and Enter: refused, naming both ways on, every row kept.
    let o = run(&args, "", dir.path());
    assert_clean_failure(&o, &format!("already holds {saved} of the 20 runs of this experiment; run again with --resume"));
    assert!(stderr(&o).contains("--fresh"), "{}", stderr(&o));
    assert_eq!(std::fs::read(out.join("runs.csv")).unwrap(), kept);
    // SIGTERM (a batch system's time limit) stops it the same way.
    let mut resume = args.to_vec();
    resume.push("--resume");
    let o = stop_after(&resume, dir.path(), &out, saved + 1, "-TERM");
    assert_eq!(o.status.code(), Some(143), "{}", stderr(&o));
    let now = row_count(&out);
    assert!(stderr(&o).contains(&format!("stopped by SIGTERM: {now} of 20 runs saved")), "{}", stderr(&o));
    assert!(now > saved && !out.join(".lock").exists());
    // --fresh moves the record aside before starting again.
    let before = std::fs::read(out.join("runs.csv")).unwrap();
    let o = run(&["sweep", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--fresh", "--max-runs", "1"], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(out.join("runs.csv.1")).unwrap(), before);
    assert_eq!(row_count(&out), 1);
}
