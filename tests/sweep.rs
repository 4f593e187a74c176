//! The experiment runner: rows, plots, resume, shards, failures as rows.

use crate::common::*;
use std::path::Path;

fn rows(dir: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    (h, r.records().map(|x| x.unwrap().iter().map(str::to_string).collect()).collect())
}

/// The rows without the columns that measure time (they differ run to run).
/// The rows without what depends on the machine and the moment: timings
/// and where the run ran.
fn stable(dir: &Path) -> Vec<Vec<String>> {
    stable_without(dir, &[])
}

fn stable_without(dir: &Path, also: &[&str]) -> Vec<Vec<String>> {
    let (h, rows) = rows(dir);
    let machine = ["host", "cpu", "cores", "load_1min"];
    let keep: Vec<usize> = h
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.ends_with("_s") && !c.ends_with("per_s") && !machine.contains(&c.as_str()) && !also.contains(&c.as_str()))
        .map(|(i, _)| i)
        .collect();
    rows.iter().map(|r| keep.iter().map(|&i| r[i].clone()).collect()).collect()
}

fn sweep(args: &[&str], dir: &Path) -> std::process::Output {
    let mut full = vec!["sweep"];
    full.extend(args);
    run(&full, "", dir)
}

fn tiny() -> String {
    repo("tests/data/tiny.toml").display().to_string()
}

#[test]
fn tiny_experiment_gives_rows_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    let o = sweep(&[&tiny(), "--out", dir.path().join("out").to_str().unwrap()], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.path().join("out");
    let (h, r) = rows(&out);
    assert_eq!(r.len(), 6);
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    for (i, row) in r.iter().enumerate() {
        assert_eq!(row[col("run_id")], i.to_string());
        assert_eq!(row[col("status")], "ok");
        assert_eq!(row[col("nan_count")], "0");
        assert!(row[col("rays")].parse::<u64>().unwrap() >= 24 * 24);
    }
    // Traces 0 and 2 differ; the reference (trace 10, fixed) is close to trace 4.
    assert!(r[2][col("changed_px")].parse::<u64>().unwrap() > 0);
    assert!(r[5][col("rmse")].parse::<f64>().unwrap() < r[1][col("rmse")].parse::<f64>().unwrap());
    for p in ["time-vs-trace.png", "change-vs-trace.png", "reference.png", "images/trace-2_specular-opacity-fixed.png"] {
        let img = image::open(out.join(p)).unwrap().to_rgb8();
        let first = *img.get_pixel(0, 0);
        assert!(img.pixels().any(|q| *q != first), "{p} is blank");
    }
    assert!(std::fs::read_to_string(out.join("time-vs-trace.svg")).unwrap().contains("<svg"));
}

#[test]
fn an_interrupted_sweep_resumes_to_the_same_csv() {
    let dir = tempfile::tempdir().unwrap();
    let (full, part) = (dir.path().join("full"), dir.path().join("part"));
    assert!(sweep(&[&tiny(), "--out", full.to_str().unwrap()], &repo("")).status.success());
    let o = sweep(&[&tiny(), "--out", part.to_str().unwrap(), "--max-runs", "2"], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"));
    assert_eq!(rows(&part).1.len(), 2);
    // A run killed while writing leaves a torn line.
    let mut text = std::fs::read_to_string(part.join("runs.csv")).unwrap();
    text.push_str("2,interior,,0,2,rep");
    std::fs::write(part.join("runs.csv"), text).unwrap();
    let o = sweep(&[&tiny(), "--out", part.to_str().unwrap(), "--resume"], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stable(&part), stable(&full));
}

#[test]
fn shards_merged_equal_the_unsharded_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n).display().to_string();
    assert!(sweep(&[&tiny(), "--out", &d("all")], &repo("")).status.success());
    for s in ["0/2", "1/2"] {
        let o = sweep(&[&tiny(), "--out", &d(&format!("shard{}", &s[..1])), "--shard", s], &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains(&format!("3 of 3 runs of shard {s}")), "{}", stderr(&o));
    }
    // A shard stopped part-way says how to finish it.
    let o = sweep(&[&tiny(), "--out", &d("stopped"), "--shard", "1/2", "--max-runs", "1"], &repo(""));
    assert!(stderr(&o).contains("1 of 3 runs of shard 1/2") && stderr(&o).contains("run this shard again with --resume"), "{}", stderr(&o));
    assert_eq!(rows(Path::new(&d("shard0"))).1.len(), 3);
    let o = sweep(&["merge", &d("shard0"), &d("shard1"), "--out", &d("merged"), "--experiment", &tiny()], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    // Shards hold whole chains along the first axis, so even changed_px
    // (against the previous trace's image) equals the unsharded run's.
    assert_eq!(stable(Path::new(&d("merged"))), stable(Path::new(&d("all"))));
    assert_eq!(
        std::fs::read(Path::new(&d("merged")).join("images/trace-4_specular-opacity-fixed.png")).unwrap(),
        std::fs::read(Path::new(&d("all")).join("images/trace-4_specular-opacity-fixed.png")).unwrap()
    );
    assert!(Path::new(&d("merged")).join("time-vs-trace.png").exists());
    // Every row says where it ran.
    let (h, r) = rows(Path::new(&d("merged")));
    let host = h.iter().position(|c| c == "host").unwrap();
    assert!(r.iter().all(|r| !r[host].is_empty() && !r[h.iter().position(|c| c == "cores").unwrap()].is_empty()));

    // Merge checks what it joins. A folder given twice:
    let o = sweep(&["merge", &d("shard0"), &d("shard0"), "--out", &d("twice")], &repo(""));
    assert_clean_failure(&o, &format!("{} is given twice", d("shard0")));
    // A run in two shards:
    std::fs::create_dir(d("copy0")).unwrap();
    std::fs::copy(Path::new(&d("shard0")).join("runs.csv"), Path::new(&d("copy0")).join("runs.csv")).unwrap();
    let o = sweep(&["merge", &d("shard0"), &d("copy0"), "--out", &d("twice")], &repo(""));
    assert_clean_failure(&o, &format!("run 0 is in both {} and {}; each run belongs to one shard", d("shard0"), d("copy0")));
    // A shard cut off mid-row (its last row loses its last cells), and a
    // file that is not a runs.csv:
    let text = std::fs::read_to_string(Path::new(&d("shard1")).join("runs.csv")).unwrap();
    let cut = &text[..text.trim_end().rfind(',').unwrap()];
    std::fs::write(Path::new(&d("copy0")).join("runs.csv"), cut).unwrap();
    let o = sweep(&["merge", &d("shard0"), &d("copy0"), "--out", &d("twice")], &repo(""));
    assert_clean_failure(&o, &format!("{}/runs.csv:{}: the last line does not end in a newline", d("copy0"), text.trim_end().lines().count()));
    std::fs::write(Path::new(&d("copy0")).join("runs.csv"), format!("{cut}\n")).unwrap();
    let o = sweep(&["merge", &d("shard0"), &d("copy0"), "--out", &d("twice")], &repo(""));
    assert_clean_failure(&o, &format!("{}/runs.csv:{}: not a whole run", d("copy0"), text.trim_end().lines().count()));
    std::fs::write(Path::new(&d("copy0")).join("runs.csv"), "x,y\n1,2\n").unwrap();
    let o = sweep(&["merge", &d("shard0"), &d("copy0"), "--out", &d("twice")], &repo(""));
    assert_clean_failure(&o, &format!("{}/runs.csv:1: not a sweep's runs.csv (its first column is `x`, not run_id)", d("copy0")));
    // A shard missing:
    let o = sweep(&["merge", &d("shard0"), "--out", &d("half"), "--experiment", &tiny()], &repo(""));
    assert_clean_failure(
        &o,
        "runs 1, 3, 5 are in no shard (3 of 6); run them into a shard's folder with `refract sweep FILE --resume --out DIR`, or merge with --resume to run them here, then merge again",
    );
    // ... or runs them here with --resume.
    let o = sweep(&["merge", &d("shard0"), "--out", &d("resumed"), "--experiment", &tiny(), "--resume"], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("ran the 3 missing here"), "{}", stderr(&o));
    assert_eq!(stable(Path::new(&d("resumed"))), stable(Path::new(&d("all"))));
    // A shard of another version of the experiment file:
    let other = dir.path().join("tiny2.toml");
    std::fs::write(&other, moved(&tiny()) + "\n# edited\n").unwrap();
    let o = sweep(&[other.to_str().unwrap(), "--out", &d("other"), "--shard", "1/2"], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = sweep(&["merge", &d("shard0"), &d("other"), "--out", &d("mixed")], &repo(""));
    let first = stderr(&o);
    assert_clean_failure(&o, &format!("{}/runs.csv: run 1 is from experiment tiny@", d("other")));
    assert!(first.contains("(another experiment, or another version of its file); merge only shards of one run"), "{first}");
    for out in ["twice", "half", "mixed"] {
        assert!(!Path::new(&d(out)).join("runs.csv").exists(), "{out}: nothing written");
    }
}

#[test]
fn failing_runs_are_rows_and_bad_files_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("e.toml");
    // A mesh that is there but malformed fails its run, as a row.
    let bad = dir.path().join("bad.off");
    std::fs::write(&bad, "PLY\n").unwrap();
    let text = "name = \"e\"\nmode = \"interior\"\n[fixed]\nsize = [8, 8]\n[[case]]\nname = \"fine\"\noff = \"OFF_OK\"\n[[case]]\nname = \"malformed mesh\"\noff = \"OFF_BAD\"\n[[case]]\nname = \"prism, few photons\"\nmode = \"prism\"\nphotons = 10\nsize = [16, 8]\n"
        .replace("OFF_OK", &repo("off/cube.off").display().to_string())
        .replace("OFF_BAD", &bad.display().to_string());
    std::fs::write(&file, &text).unwrap();
    let o = sweep(&[file.to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()], &repo(""));
    // Every row is saved; the status and the first error say one failed.
    assert_clean_failure(&o, "e: 3 of 3 runs in ");
    assert!(
        stderr(&o).contains("(1 failed); the first failed run, 1 (malformed mesh): ") && stderr(&o).contains("bad.off:1: expected the keyword OFF"),
        "{}",
        stderr(&o)
    );
    let (h, r) = rows(&dir.path().join("o"));
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    assert_eq!(r.len(), 3);
    assert_eq!((r[0][col("status")].as_str(), r[1][col("status")].as_str(), r[2][col("status")].as_str()), ("ok", "error", "ok"));
    assert!(r[1][col("error")].contains("bad.off:1: expected the keyword OFF or COFF"), "{}", r[1][col("error")]);
    assert_eq!(r[2][col("mode")], "prism");
    // A mesh that is not there is a mistake in the file: refused before any run.
    std::fs::write(&file, text.replace(&bad.display().to_string(), "nowhere.off")).unwrap();
    let o = sweep(&[file.to_str().unwrap(), "--out", dir.path().join("o2").to_str().unwrap()], &repo(""));
    assert_clean_failure(&o, "e.toml:10: `off`: nowhere.off: no such file");
    assert!(!dir.path().join("o2").exists());

    std::fs::write(&file, "name = \"e\"\nmode = \"interior\"\n[sweep]\nior = [1.4, \"glass\"]\n").unwrap();
    let o = sweep(&[file.to_str().unwrap()], dir.path());
    assert_clean_failure(&o, "e.toml:4: `ior`: `\"glass\"` is not a number");
    std::fs::write(&file, "name = \"e\"\nmode = \"interior\"\nrepeat = 2\n").unwrap();
    let o = sweep(&[file.to_str().unwrap()], dir.path());
    assert_clean_failure(&o, "e.toml:3: `repeat`: unknown key");
}

/// A case may declare that its runs fail (`expect = "error"`): such a
/// failure ends the sweep well and is counted apart; a run meant to fail
/// that renders, or an undeclared failure, ends it non-zero. The record
/// made before the declaration is the same experiment's.
#[test]
fn a_case_that_declares_its_failure_ends_the_sweep_well() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("e.toml");
    let bad = dir.path().join("bad.off");
    std::fs::write(&bad, "PLY\n").unwrap();
    let text = format!(
        "name = \"e\"\nmode = \"interior\"\n[fixed]\nsize = [8, 8]\n[[case]]\nname = \"fine\"\noff = \"{}\"\n[[case]]\nname = \"malformed mesh\"\noff = \"{}\"\n",
        repo("off/cube.off").display(),
        bad.display()
    );
    let out = dir.path().join("o");
    let o_arg = out.to_str().unwrap();
    std::fs::write(&file, &text).unwrap();
    let o = sweep(&[file.to_str().unwrap(), "--out", o_arg], &repo(""));
    assert_clean_failure(&o, "e: 2 of 2 runs in ");
    assert!(stderr(&o).contains("(1 failed); the first failed run, 1 (malformed mesh)"), "{}", stderr(&o));
    // Declared: the same record, now judged as the file says.
    let declared = text.replace("bad.off\"\n", "bad.off\"\nexpect = \"error\"\n");
    std::fs::write(&file, &declared).unwrap();
    let o = sweep(&[file.to_str().unwrap(), "--out", o_arg, "--resume"], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("e: 2 of 2 runs in ") && stderr(&o).contains("(0 failed, and 1 as its case declares (expect = \"error\"))"), "{}", stderr(&o));
    let o = sweep(&[file.to_str().unwrap(), "--out", dir.path().join("o2").to_str().unwrap()], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    // A run meant to fail that renders is the sweep's failure.
    std::fs::write(&file, declared.replace("name = \"fine\"\n", "name = \"fine\"\nexpect = \"error\"\n")).unwrap();
    let o = sweep(&[file.to_str().unwrap(), "--out", dir.path().join("o3").to_str().unwrap()], &repo(""));
    assert_clean_failure(&o, "e: 2 of 2 runs in ");
    assert!(
        stderr(&o).contains("(0 failed, and 1 as its case declares (expect = \"error\"); 1 meant to fail rendered); run 0 (fine) rendered, but its case declares expect = \"error\""),
        "{}",
        stderr(&o)
    );
    // Checked when the file is read, on its line.
    std::fs::write(&file, declared.replace("expect = \"error\"", "expect = \"failure\"")).unwrap();
    let o = sweep(&[file.to_str().unwrap(), "--out", dir.path().join("o4").to_str().unwrap()], &repo(""));
    assert_clean_failure(&o, "e.toml:11: `expect`: must be \"error\"");
    assert!(!dir.path().join("o4").exists());
}

#[test]
fn shipped_experiments_parse_and_stability_records_failures_as_rows() {
    let mut n = 0;
    for entry in std::fs::read_dir(repo("experiments")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            for quick in [false, true] {
                let e = refract::experiment::spec::Experiment::load(&p, quick).unwrap_or_else(|e| panic!("{e:#}"));
                // The count checked before the grid is built is the grid's size.
                assert_eq!(e.run_count(), refract::experiment::grid::expand(&e).unwrap().len() as u128, "{}", p.display());
            }
            n += 1;
        }
    }
    assert!(n >= 7, "{n} experiment files");
    // A grid too large to build is refused before it is built.
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.toml");
    std::fs::write(
        &big,
        format!(
            "name = \"big\"\nmode = \"interior\"\n[fixed]\noff = \"{}\"\n[sweep]\nior = {{ from = 1.0, to = 3.0, step = 0.0001 }}\ntrace = {{ from = 0, to = 100, step = 1 }}\n",
            repo("off/cube.off").display()
        ),
    )
    .unwrap();
    let o = sweep(&[big.to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()], &repo(""));
    assert_clean_failure(&o, "big.toml:5: `sweep`: the experiment has 2020101 runs (cases x sweep values x repeats); at most 100000");
    let dir = tempfile::tempdir().unwrap();
    // (stability.toml has no [quick] settings: --quick would be refused.)
    let o = sweep(&[repo("experiments/stability.toml").to_str().unwrap(), "--out", dir.path().to_str().unwrap()], &repo(""));
    // Its runs fail on purpose, as its cases declare: each a row, and the
    // summary says so.
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("stability: 18 of 18 runs in ") && stderr(&o).contains("(0 failed, and 1 as its case declares"), "{}", stderr(&o));
    let (h, r) = rows(dir.path());
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let tir = r.iter().find(|x| x[col("case")].contains("totally reflected")).unwrap();
    assert_eq!(tir[col("status")], "error");
    assert!(tir[col("error")].contains("totally reflected"));
    assert!(r.iter().all(|x| x[col("nan_count")] == "0" || x[col("status")] == "error"), "no NaN may reach an image");
    assert!(dir.path().join("stability.png").exists());
}

/// A scene file rendered by `refract render` and the same parameters run by
/// `refract sweep` give the same image, byte for byte, for both modes: the
/// two start from the same defaults (the parameter tables) and only the
/// given parameters are set. The parameters leave size and photons at their
/// defaults on purpose, which the two once disagreed on.
#[test]
fn render_and_sweep_make_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off").display().to_string();
    let cases = [
        ("interior", format!("off = \"{cube}\"\nrot = [20, 30, 0]\ntrace = 2\nior = 1.8\n")),
        ("prism", "scene = \"single-prism\"\nphotons = 20000\nspp = 1\n".to_string()),
    ];
    for (mode, params) in cases {
        let scene = dir.path().join(format!("{mode}.toml"));
        std::fs::write(&scene, format!("id = \"same-{mode}\"\nmode = \"{mode}\"\n[params]\n{params}")).unwrap();
        let rendered = dir.path().join(format!("{mode}.png"));
        let o = run(&["render", scene.to_str().unwrap(), "--out", rendered.to_str().unwrap()], "", dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let experiment = dir.path().join(format!("{mode}-sweep.toml"));
        std::fs::write(&experiment, format!("name = \"same-{mode}\"\nmode = \"{mode}\"\n[fixed]\n{params}[outputs]\nimages = true\n")).unwrap();
        let out = dir.path().join(format!("{mode}-out"));
        let o = sweep(&[experiment.to_str().unwrap(), "--out", out.to_str().unwrap()], dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let swept = std::fs::read(out.join("images/run-0.png")).unwrap();
        let alone = std::fs::read(&rendered).unwrap();
        assert!(swept == alone, "{mode}: the sweep's image differs from the render's");
        let size = image::open(&rendered).unwrap().to_rgb8().dimensions();
        assert_eq!(size, if mode == "interior" { (401, 401) } else { (640, 240) }, "{mode}: the defaults' size");
    }
}

/// `--resume` goes on only from rows of this version of the experiment
/// file: after an edit it refuses, and `--fresh` moves the old record
/// aside and runs every run again.
#[test]
fn resume_refuses_what_an_edited_experiment_file_made() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    assert!(sweep(&[&tiny(), "--out", out.to_str().unwrap()], &repo("")).status.success());
    let (h, r) = rows(&out);
    let c = h.iter().position(|x| x == "experiment").unwrap();
    let before = r[0][c].clone();
    let old = std::fs::read(out.join("runs.csv")).unwrap();
    let edited = dir.path().join("tiny.toml");
    std::fs::write(&edited, moved(&tiny()) + "\n# edited\n").unwrap();
    let o = sweep(&[edited.to_str().unwrap(), "--out", out.to_str().unwrap(), "--resume"], &repo(""));
    assert_clean_failure(&o, &format!("{}/runs.csv: holds 6 runs (6 of experiment {before}), not of tiny@", out.display()));
    assert_eq!(std::fs::read(out.join("runs.csv")).unwrap(), old);
    let o = sweep(&[edited.to_str().unwrap(), "--out", out.to_str().unwrap(), "--fresh"], &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, r) = rows(&out);
    let fingerprints: std::collections::BTreeSet<&str> = r.iter().map(|r| r[c].as_str()).collect();
    assert_eq!((r.len(), fingerprints.len()), (6, 1), "{fingerprints:?}");
    assert!(!fingerprints.contains(before.as_str()), "every row is of the edited file: {fingerprints:?}");
    assert_eq!(std::fs::read(out.join("runs.csv.1")).unwrap(), old, "the old record is kept aside");
}

/// A plan has no shard without work: asked for more shards than the grid
/// has chains it refuses, naming the most; by default it makes 4, or as
/// many as there are chains if fewer.
#[test]
fn plans_have_no_empty_shard() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let spread = repo("tests/data/spread.toml").display().to_string();
    let o = sweep(&["plan", &spread, "--engine", "parallel", "--shards", "9", "--out", &out("nine")], &repo(""));
    assert_clean_failure(&o, "--shards: 9 is more than the 8 chains of runs this grid holds");
    assert!(!dir.path().join("nine").exists(), "nothing written");
    let o = sweep(&["plan", &spread, "--engine", "parallel", "--shards", "8", "--out", &out("eight")], &repo(""));
    assert!(o.status.success() && String::from_utf8_lossy(&o.stdout).contains("24 runs in 8 shards"), "{}", stderr(&o));
    let lab = repo("experiments/lab-ior.toml").display().to_string();
    let o = sweep(&["plan", &lab, "--quick", "--engine", "slurm", "--out", &out("one")], &repo(""));
    assert!(o.status.success() && String::from_utf8_lossy(&o.stdout).contains("5 runs in 1 shard "), "{}", stderr(&o));
    assert!(std::fs::read_to_string(dir.path().join("one/merge.sh")).unwrap().contains("\nN=1\n"));
}

/// An experiment file's text for a copy in another folder: its mesh path,
/// which is from the file's own folder, made absolute.
fn moved(file: &str) -> String {
    std::fs::read_to_string(file).unwrap().replace("\"off/cube.off\"", &format!("\"{}\"", repo("off/cube.off").display()))
}
