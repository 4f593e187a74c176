//! The committed timing charts under results/ measure what they say: each
//! point the median of repeats with error bars, a fitted line where the
//! plot claims a slope, and the report's claim judged on the chart.

use crate::common::*;
use refract::experiment::charts::is_timing;
use refract::experiment::spec::{Experiment, PlotKind};

#[test]
fn every_committed_timing_chart_has_error_bars_and_its_fitted_line() {
    let mut checked = 0;
    let mut files: Vec<_> =
        std::fs::read_dir(repo("experiments")).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|x| x == "toml")).collect();
    files.sort();
    for file in files {
        let e = Experiment::load(&file, false).unwrap();
        let dir = repo("results").join(&e.name);
        for p in e.plots.iter().filter(|p| p.kind == PlotKind::Line && (is_timing(&p.x) || is_timing(&p.y))) {
            let svg_path = dir.join(format!("{}.svg", p.file));
            let svg = std::fs::read_to_string(&svg_path).unwrap_or_else(|err| panic!("{}: {err}", svg_path.display()));
            assert!(dir.join(format!("{}.png", p.file)).is_file(), "{}: no PNG beside the SVG", svg_path.display());
            assert!(e.repeats >= 3, "{}: timings need repeats (has {})", file.display(), e.repeats);
            assert!(svg.contains("error bars: least to greatest of the repeats"), "{}: no error bars", svg_path.display());
            assert!(svg.contains(&format!("median of {} repeats", e.repeats)), "{}: does not say its points are medians", svg_path.display());
            if p.fit {
                assert!(
                    svg.contains("fitted line (least squares)") && svg.contains("slope") && svg.contains("R²"),
                    "{}: claims a slope but draws no fit",
                    svg_path.display()
                );
            }
            if !p.claim.is_empty() {
                assert!(svg.contains(&p.claim) && svg.contains("HOLD"), "{}: the report's claim is not judged", svg_path.display());
            }
            assert!(!svg.contains("quick run"), "{}: a quick run's chart is committed", svg_path.display());
            checked += 1;
        }
    }
    assert!(checked >= 6, "only {checked} timing charts found");
}

/// The committed bench charts say how their times were taken (wall or
/// CPU, the date, the commit, the machine's load), and are what their
/// records draw: `bench prism --redraw` on a copy of the record gives the
/// committed SVG again; a record without its about file is refused, naming it.
#[test]
fn committed_bench_charts_are_drawn_from_their_records() {
    for dir in ["results/bench", "results/bench/mitsuba-2026-11-25"] {
        let svg = std::fs::read_to_string(repo(dir).join("prism-error-vs-time.svg")).unwrap_or_else(|e| panic!("{dir}: {e}"));
        for says in ["wall-clock seconds", "measured 2026-11-25", "at commit ", "machine load (1-minute load average)", "each point one run"] {
            assert!(svg.contains(says), "{dir}: the chart does not say `{says}`");
        }
        let copy = tempfile::tempdir().unwrap();
        for f in ["prism-error-vs-time.csv", "prism-error-vs-time.about.csv"] {
            std::fs::copy(repo(dir).join(f), copy.path().join(f)).unwrap();
        }
        let out = copy.path().to_str().unwrap();
        let o = run(&["bench", "prism", "--redraw", "--out", out], "", copy.path());
        assert!(o.status.success(), "{dir}: {}", stderr(&o));
        assert_eq!(std::fs::read_to_string(copy.path().join("prism-error-vs-time.svg")).unwrap(), svg, "{dir}: the committed chart is not its record's");
        std::fs::remove_file(copy.path().join("prism-error-vs-time.about.csv")).unwrap();
        let o = run(&["bench", "prism", "--redraw", "--out", out], "", copy.path());
        assert_clean_failure(&o, "prism-error-vs-time.about.csv: cannot read it");
    }
}
