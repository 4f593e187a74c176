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
