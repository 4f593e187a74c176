//! Sweeps spread by real engines: the plans of `refract sweep plan` run
//! through GNU parallel and through a Slurm job array, and their merged
//! results equal the unsharded sweep's (apart from timings and where each
//! run ran). These need the engines, so they are ignored by default; CI
//! installs GNU parallel and starts a one-node Slurm
//! (`scripts/local-slurm.sh`) and runs them with
//! `cargo test --release --test integration scale_out -- --ignored`.
//! A missing engine fails the test, saying what is missing.

use crate::common::*;
use std::path::Path;
use std::process::Command;

/// The rows of runs.csv without timings and the machine's columns.
fn stable(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    let machine = ["host", "cpu", "cores", "load_1min"];
    let keep: Vec<usize> = h.iter().enumerate().filter(|(_, c)| !c.ends_with("_s") && !machine.contains(&c.as_str())).map(|(i, _)| i).collect();
    let mut out = vec![keep.iter().map(|&i| h[i].clone()).collect::<Vec<_>>()];
    out.extend(r.records().map(|x| {
        let x = x.unwrap();
        keep.iter().map(|&i| x[i].to_string()).collect()
    }));
    out
}

/// Every run image and the reference image, byte for byte.
fn images(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir.join("images"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v.push(("reference.png".into(), std::fs::read(dir.join("reference.png")).unwrap()));
    v
}

fn have(program: &str) -> bool {
    Command::new("sh").args(["-c", &format!("command -v {program}")]).output().is_ok_and(|o| o.status.success())
}

/// Plans the spread experiment for `engine` in 4 shards, runs the plan
/// with `args`, and compares it with the unsharded sweep.
fn plan_equals_unsharded(engine: &str, script: &str, args: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let file = repo("tests/data/spread.toml");
    let (all, planned) = (dir.path().join("all"), dir.path().join("planned"));
    let o = run(&["sweep", file.to_str().unwrap(), "--out", all.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&["sweep", "plan", file.to_str().unwrap(), "--engine", engine, "--shards", "4", "--out", planned.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(said.contains(&format!("bash {}", planned.join(script).display())), "{said}");
    // Cost-balanced: every shard has work (8 chains in 4 shards).
    assert_eq!(said.matches(" runs, about ").count(), 4, "{said}");
    assert!(!said.contains("shard 3: 0 runs"), "{said}");
    let o = Command::new("bash").arg(planned.join(script)).args(args).current_dir(dir.path()).output().unwrap();
    assert!(o.status.success(), "{script} failed: {}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
    for i in 0..4 {
        assert!(planned.join(format!("shards/{i}/runs.csv")).is_file(), "shard {i} ran");
    }
    assert_eq!(stable(&planned), stable(&all));
    assert_eq!(stable(&planned).len(), 25);
    assert!(images(&planned) == images(&all), "the merged images differ from the unsharded run's");
    assert!(planned.join("rmse-vs-trace.png").is_file());
}

#[test]
#[ignore = "needs GNU parallel (Debian package `parallel`); CI runs it"]
fn scale_out_gnu_parallel_plan_equals_the_unsharded_sweep() {
    assert!(have("parallel"), "GNU parallel is not installed (apt-get install parallel)");
    plan_equals_unsharded("parallel", "run-parallel.sh", &[]);
}

#[test]
#[ignore = "needs a running Slurm (sudo bash scripts/local-slurm.sh start); CI runs it"]
fn scale_out_slurm_plan_equals_the_unsharded_sweep() {
    assert!(have("sbatch"), "Slurm is not installed (sudo bash scripts/local-slurm.sh install)");
    let up = Command::new("sinfo").args(["-h", "-o", "%T"]).output();
    let state = up.as_ref().map(|o| String::from_utf8_lossy(&o.stdout).into_owned()).unwrap_or_default();
    assert!(
        state.lines().any(|l| ["idle", "mixed", "allocated"].contains(&l.trim())),
        "no Slurm node is up (sinfo says `{}`); start one with `sudo bash scripts/local-slurm.sh start`",
        state.trim()
    );
    plan_equals_unsharded("slurm", "submit-slurm.sh", &["--wait"]);
}
