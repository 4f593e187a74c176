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
    // (Run images are named by their parameters; any one of them.)
    let image = before.keys().find(|k| k.starts_with("images")).expect("the record has run images").clone();
    assert_eq!(std::fs::read(committed.join("images.1").join(image.file_name().unwrap())).unwrap(), before[&image]);
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
    assert!((2..20).contains(&saved), "{saved} rows");
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

/// A lock file as refract writes it, for an owner like this process with
/// the given pid, start time and pid namespace.
fn lock_text(pid: u32, start: u64, pidns: u64) -> String {
    let me = refract::owner::Owner::me();
    format!(
        "refract lock\nhost={}\nboot={}\npidns={pidns}\npid={pid}\nstart={start}\nsince=1795574400\ntoken=0123456789abcdef\ncommand=refract sweep other.toml\n",
        me.host, me.boot
    )
}

#[test]
fn two_sweeps_started_together_exactly_one_runs_and_the_other_names_the_holder() {
    let dir = tempfile::tempdir().unwrap();
    let file = slow_experiment(dir.path());
    for trial in 0..3 {
        let out = dir.path().join(format!("out{trial}"));
        let start = || {
            bin()
                .args(["sweep", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--max-runs", "2"])
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (start(), start());
        let ids = [a.id(), b.id()];
        let outs = [a.wait_with_output().unwrap(), b.wait_with_output().unwrap()];
        let won: Vec<usize> = (0..2).filter(|&i| outs[i].status.success()).collect();
        assert_eq!(won.len(), 1, "trial {trial}: {} and {}", stderr(&outs[0]), stderr(&outs[1]));
        let lost = &outs[1 - won[0]];
        assert_clean_failure(lost, &format!("{}: held by pid {} on host", out.join(".lock").display(), ids[won[0]]));
        assert!(stderr(lost).contains("--break-lock"), "{}", stderr(lost));
        assert_eq!(row_count(&out), 2);
        assert!(!out.join(".lock").exists());
    }
}

#[test]
fn a_lock_is_taken_over_only_when_its_owner_is_provably_gone_here() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let me = refract::owner::Owner::me();
    let lock = out.join(".lock");
    let tiny = repo("tests/data/tiny.toml").display().to_string();
    let sweep = |extra: &[&str]| {
        let mut args = vec!["sweep", &tiny, "--out", out.to_str().unwrap(), "--fresh"];
        args.extend(extra);
        run(&args, "", &repo(""))
    };
    // A pid alive here (pid 1) but not the owner: another pid namespace
    // (a container, or `unshare --pid`), where that pid may be a live sweep.
    std::fs::write(&lock, lock_text(1, 12345, me.pidns + 1)).unwrap();
    let o = sweep(&[]);
    assert_clean_failure(&o, &format!("{}: held by pid 1 on host {} (in another container or pid namespace", lock.display(), me.host));
    assert!(stderr(&o).contains("since 2026-11-25 02:40 UTC: refract sweep other.toml") && stderr(&o).contains("--break-lock"), "{}", stderr(&o));
    // Another boot or host: the same.
    std::fs::write(&lock, lock_text(4_000_000, 12345, me.pidns).replace(&me.boot, "another-boot")).unwrap();
    assert_clean_failure(&sweep(&[]), "(another host, or before a reboot: this process cannot see it)");
    // A lock that is empty, or not refract's (an older version wrote a bare pid).
    for text in ["", "1"] {
        std::fs::write(&lock, text).unwrap();
        assert_clean_failure(&sweep(&[]), &format!("{}: cannot tell who holds it", lock.display()));
    }
    // --break-lock removes it, naming what it removed.
    let o = sweep(&["--break-lock"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("broke the lock of an unreadable lock (1 bytes)"), "{}", stderr(&o));
    // Pid 1 in this namespace with another start time: provably gone (the
    // pid was reused), so taken over without a flag.
    std::fs::write(&lock, lock_text(1, 1, me.pidns)).unwrap();
    let o = sweep(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("took over the lock of pid 1 on host") && stderr(&o).contains("which is gone"), "{}", stderr(&o));
    assert!(!lock.exists(), "the lock is removed at the end");
}

/// A sweep in another pid namespace (`unshare --pid`, as a container
/// would be) holds the folder: a sweep outside cannot see it and waits.
#[test]
fn a_sweep_in_another_pid_namespace_keeps_its_lock() {
    let probe = std::process::Command::new("unshare").args(["--pid", "--fork", "--mount-proc", "true"]).output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: unshare --pid is not allowed here");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let file = slow_experiment(dir.path());
    let out = dir.path().join("out");
    let inner = std::process::Command::new("unshare")
        .args([
            "--pid",
            "--fork",
            "--mount-proc",
            env!("CARGO_BIN_EXE_refract"),
            "sweep",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--max-runs",
            "3",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while !out.join(".lock").exists() {
        assert!(start.elapsed().as_secs() < 60);
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let o = run(&["sweep", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--resume"], "", dir.path());
    let done = inner.wait_with_output().unwrap();
    assert!(done.status.success(), "{}", stderr(&done));
    assert_clean_failure(&o, "held by pid 1 on host");
    assert_eq!(row_count(&out), 3, "no row lost");
}

/// Temporary files a killed refract left (`.NAME.TOKEN.tmp`, the token
/// naming a refract here that is gone) are removed by the next run into
/// the folder; another program's files named alike, a live process's and
/// those of a refract it cannot see stay.
#[test]
fn the_next_run_removes_only_its_own_kind_of_stale_temporary_files() {
    use refract::owner::Owner;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(out.join("images")).unwrap();
    let me = Owner::me();
    let gone = Owner { pid: 4_000_000, ..me.clone() }.token();
    let stale = [out.join(format!(".runs.csv.{gone}.tmp")), out.join("images").join(format!(".3.png.{gone}.tmp"))];
    let keep = [
        out.join(format!(".runs.csv.{}.tmp", me.token())),
        out.join(".notes.txt.999999999.tmp"),
        out.join(format!(".runs.csv.{}.tmp", Owner { pid: 4_000_000, pidns: me.pidns + 1, ..me.clone() }.token())),
    ];
    for p in stale.iter().chain(&keep) {
        std::fs::write(p, b"partial").unwrap();
    }
    let o = run(&["sweep", repo("tests/data/tiny.toml").to_str().unwrap(), "--out", out.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    for p in &stale {
        assert!(!p.exists(), "{} left", p.display());
    }
    for p in &keep {
        assert!(p.exists(), "{} removed", p.display());
    }
    // A single render does the same beside its output, and so do figures.
    let img = dir.path().join(format!(".one.png.{gone}.tmp"));
    std::fs::write(&img, b"partial").unwrap();
    let o = run(&["interior", "--off", "off/cube.off", "--size", "16,16", "--out", dir.path().join("one.png").to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!img.exists());
    let figs = dir.path().join("figs");
    std::fs::create_dir_all(figs.join("figures")).unwrap();
    let left = figs.join("figures").join(format!(".css552-p2.png.{gone}.tmp"));
    std::fs::write(&left, b"partial").unwrap();
    let o = run(&["figures", "--quick", "--only", "css552-p2", "--out", figs.to_str().unwrap()], "", &repo(""));
    assert!(!left.exists(), "figures left its own stale file: {}", stderr(&o));
}

/// A reference run that fails is named, the metrics against it are marked,
/// their plot is not drawn empty, and the sweep ends with a non-zero
/// status; a sweep whose every run fails too.
#[test]
fn a_failed_reference_or_failed_runs_end_the_sweep_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.off");
    std::fs::write(&bad, "PLY\n").unwrap();
    let cube = repo("off/cube.off").display().to_string();
    let file = dir.path().join("r.toml");
    let text = format!(
        "name = \"r\"\nmode = \"interior\"\n[fixed]\noff = \"{cube}\"\nsize = [16, 16]\n[sweep]\ntrace = [0, 2]\n[reference]\noff = \"{}\"\n[[outputs.plot]]\nx = \"param_trace\"\ny = \"rmse\"\nfile = \"rmse-vs-trace\"\n[[outputs.plot]]\nx = \"param_trace\"\ny = \"rays\"\nfile = \"rays-vs-trace\"\n",
        bad.display()
    );
    std::fs::write(&file, &text).unwrap();
    let out = dir.path().join("o");
    let o = run(&["sweep", file.to_str().unwrap(), "--out", out.to_str().unwrap()], "", dir.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.lines().next().unwrap().starts_with("refract: the reference run failed: ") && err.contains("bad.off:1: expected the keyword OFF"), "{err}");
    assert!(err.contains("note: plot rmse-vs-trace not drawn: no run has a value of rmse (the reference run failed)"), "{err}");
    let last = err.trim_end().lines().last().unwrap();
    assert!(last.starts_with("refract: error: r: 2 of 2 runs in") && last.contains("(0 failed); the reference run failed: "), "{last}");
    let text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    for row in r.records() {
        let row = row.unwrap();
        for m in ["rmse", "psnr", "rel_rmse"] {
            assert_eq!(&row[h.iter().position(|c| c == m).unwrap()], "no reference");
        }
    }
    assert!(!out.join("rmse-vs-trace.png").exists() && !out.join("rmse-vs-trace.svg").exists(), "no empty plot");
    assert!(out.join("rays-vs-trace.png").exists());
    // Every run failing: non-zero, the first error named.
    std::fs::write(&file, text_all_fail(&bad)).unwrap();
    let o = run(&["sweep", file.to_str().unwrap(), "--out", dir.path().join("o2").to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "r: 2 of 2 runs in ");
    assert!(stderr(&o).contains("(2 failed); the first failed run, 0: ") && stderr(&o).contains("bad.off:1"), "{}", stderr(&o));
}

fn text_all_fail(bad: &Path) -> String {
    format!("name = \"r\"\nmode = \"interior\"\n[fixed]\noff = \"{}\"\nsize = [16, 16]\n[sweep]\ntrace = [0, 2]\n", bad.display())
}

/// Merge refuses a shard whose last row was cut inside a number (it would
/// read as another number), a shard still being written, and names a run
/// a shard holds twice; it never replaces a record it does not contain.
#[test]
fn merge_refuses_cut_locked_and_doubled_shards() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n);
    let tiny = repo("tests/data/tiny.toml").display().to_string();
    for s in ["0/2", "1/2"] {
        let o = run(&["sweep", &tiny, "--out", d(&format!("s{}", &s[..1])).to_str().unwrap(), "--shard", s], "", &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let merge = |shards: [&str; 2], extra: &[&str]| {
        let (a, b, m) = (d(shards[0]).display().to_string(), d(shards[1]).display().to_string(), d("merged").display().to_string());
        let mut args = vec!["sweep", "merge", &a, &b, "--out", &m, "--experiment", &tiny];
        args.extend(extra);
        run(&args, "", &repo(""))
    };
    // The last cell cut short (`0.757080` -> `0.757`): a whole-looking row.
    let whole = std::fs::read_to_string(d("s1/runs.csv")).unwrap();
    std::fs::create_dir(d("cut")).unwrap();
    std::fs::write(d("cut/runs.csv"), &whole[..whole.len() - 4]).unwrap();
    let o = merge(["s0", "cut"], &[]);
    assert_clean_failure(&o, &format!("cut/runs.csv:{}: the last line does not end in a newline", whole.lines().count()));
    assert!(!d("merged/runs.csv").exists());
    // A shard still being written (a live owner's lock).
    let me = refract::owner::Owner::me();
    let lock = format!(
        "refract lock\nhost={}\nboot={}\npidns={}\npid={}\nstart={}\nsince=1795574400\ntoken=ab\ncommand=refract sweep tiny.toml --shard 1/2\n",
        me.host, me.boot, me.pidns, me.pid, me.start
    );
    std::fs::write(d("s1/.lock"), lock).unwrap();
    let o = merge(["s0", "s1"], &[]);
    assert_clean_failure(&o, &format!("s1: this shard is still being written (its lock is held by pid {} on host", me.pid));
    std::fs::remove_file(d("s1/.lock")).unwrap();
    // A run twice in one shard.
    let mut lines: Vec<&str> = whole.lines().collect();
    lines.push(lines[1]);
    std::fs::create_dir(d("twice")).unwrap();
    std::fs::write(d("twice/runs.csv"), lines.join("\n") + "\n").unwrap();
    let o = merge(["s0", "twice"], &[]);
    let id = lines[1].split(',').next().unwrap();
    assert_clean_failure(&o, &format!("twice/runs.csv: run {id} is twice (lines 2 and {}); each run is one row", lines.len()));
    // The good merge; again into the same folder is fine (it holds every
    // row there); a record it does not contain is refused, or with
    // --fresh moved aside.
    assert!(merge(["s0", "s1"], &[]).status.success());
    assert!(merge(["s0", "s1"], &[]).status.success());
    let merged = std::fs::read(d("merged/runs.csv")).unwrap();
    let edited = String::from_utf8(merged.clone()).unwrap().replacen(",ok,", ",okay,", 1);
    std::fs::write(d("merged/runs.csv"), &edited).unwrap();
    assert_clean_failure(&merge(["s0", "s1"], &[]), "merged/runs.csv:2: holds run 0 as the merge does not");
    let o = merge(["s0", "s1"], &["--fresh"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(d("merged/runs.csv.1")).unwrap(), edited);
    assert_eq!(std::fs::read(d("merged/runs.csv")).unwrap(), merged);
}

/// `--resume` names what it will not go on from: a row that is no run of
/// the experiment, a run twice with different cells (a run twice the same
/// is kept once, said so), and a last line cut off mid-write.
#[test]
fn resume_names_bad_and_doubled_rows() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let tiny = repo("tests/data/tiny.toml").display().to_string();
    let sweep = |extra: &str| run(&["sweep", &tiny, "--quick", "--out", out.to_str().unwrap(), extra], "", &repo(""));
    assert!(sweep("--fresh").status.success());
    let text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let garbage = lines[1].replacen(&format!("{},", lines[1].split(',').next().unwrap()), "999,", 1);
    std::fs::write(out.join("runs.csv"), format!("{text}{garbage}\n")).unwrap();
    assert_clean_failure(&sweep("--resume"), &format!("runs.csv:{}: `999` is not a run of this experiment (its runs are 0 to 3)", lines.len() + 1));
    let other = lines[2].replacen(",ok,", ",okay,", 1);
    std::fs::write(out.join("runs.csv"), format!("{text}{other}\n")).unwrap();
    assert_clean_failure(&sweep("--resume"), "runs.csv: run 1 is twice, with different cells (lines 3 and 6)");
    // The same row twice, and a torn last line (run 3's, cut off).
    let partial = &lines[4][..lines[4].len() / 2];
    let kept: Vec<&str> = lines[..4].to_vec();
    std::fs::write(out.join("runs.csv"), format!("{}\n{}\n{partial}", kept.join("\n"), lines[2])).unwrap();
    let o = sweep("--resume");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("runs.csv: run 1 is twice (lines 3 and 5), the same both times; kept once"), "{}", stderr(&o));
    assert!(stderr(&o).contains("runs.csv:6: the last line was cut off mid-write (no newline); that run runs again"), "{}", stderr(&o));
    assert!(stderr(&o).contains("4 of 4 runs"), "{}", stderr(&o));
    assert_eq!(row_count(&out), 4);
}
