//! What a run prints: off a terminal no bar, a plain progress line every
//! few seconds (`REFRACT_PROGRESS_SECS`), rates with units as people write
//! them, and one summary line with the size, what was traced, the
//! exposure and each stage's wall time, adding up to the total.

use crate::common::*;
use std::process::{Command, Stdio};

fn run_env(args: &[&str], dir: &std::path::Path, every: &str) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_refract")).args(args).current_dir(dir).env("REFRACT_PROGRESS_SECS", every).stdin(Stdio::null()).output().unwrap()
}

/// The stage times of a summary line (`name 1.23 s`), and its total (a
/// scene file's labels, drawn after the run, follow it: `, with its
/// labels; 1.24 s in all`).
fn times(line: &str) -> (f64, f64) {
    let line = line.split(", with its").next().unwrap();
    let tail = line.rsplit_once("; ").unwrap().1.trim_end_matches(')');
    let mut sum = 0.0;
    let mut total = f64::NAN;
    for part in tail.split(", ") {
        let mut w = part.split_whitespace();
        let (name, secs) = (w.next().unwrap(), w.next().unwrap().parse::<f64>().unwrap());
        if name == "total" {
            total = secs;
        } else {
            sum += secs;
        }
    }
    (sum, total)
}

/// A rate as people write it: a number of at most three digits, maybe a
/// k, M or G, and a unit per second.
fn human_rates(text: &str) {
    for (i, _) in text.match_indices("/s") {
        let before: Vec<&str> = text[..i].rsplit(['(', ',']).next().unwrap().split_whitespace().collect();
        let number = before[0];
        assert!(number.len() <= 5 && number.parse::<f64>().is_ok(), "rate `{}` in: {text}", before.join(" "));
        assert!(before.len() == 2 || ["k", "M", "G"].contains(&before[1]), "rate `{}` in: {text}", before.join(" "));
    }
}

#[test]
fn a_piped_prism_run_prints_plain_progress_and_one_summary() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_env(&["prism", "--scene", "single-prism", "--size", "64,48", "--photons", "40000", "--out", "x.png"], dir.path(), "0");
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains('\r') && !err.contains("\x1b["), "no bar drawn off a terminal: {err:?}");
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines.iter().any(|l| l.starts_with("light ") && l.contains("% (") && l.contains(" photons/s), ")), "{err}");
    let last = lines.last().unwrap();
    assert!(last.starts_with("wrote x.png (64x48, 40000 photons (") && last.contains(", exposure ") && last.contains(" photons/s)"), "{err}");
    human_rates(&err);
    let (sum, total) = times(last);
    assert!((sum - total).abs() <= 0.011 && total > 0.0, "the stages add up to the total: {sum} against {total}: {last}");
}

#[test]
fn render_and_interior_summaries_give_size_rays_exposure_and_stages() {
    let dir = tempfile::tempdir().unwrap();
    let lab = repo("scenes/lab-ior1.4.toml");
    let o = run_env(&["render", lab.to_str().unwrap(), "--set", "size=40,30", "--set", "bulb=0", "--out", "r.png"], dir.path(), "5");
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let last = err.lines().last().unwrap();
    assert!(last.starts_with("wrote r.png (40x30, 12 triangles, 9600 rays, exposure 1.5; "), "{err}");
    let (sum, total) = times(last);
    assert!((sum - total).abs() <= 0.011, "{last}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
}

#[test]
fn piped_figures_say_each_figure_as_it_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_env(&["figures", "--quick", "--only", "lab-ior1.4", "--out", "f", "--scene-dir", repo("scenes").to_str().unwrap()], dir.path(), "5");
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.lines().any(|l| l.starts_with("figure 1/1 lab-ior1.4: 301x301, 12 triangles, 264993 rays, exposure 1.5; ")), "{err}");
}
