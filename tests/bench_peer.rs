//! `refract bench prism` prints a ratio against Mitsuba only from a
//! Mitsuba run in the same bench: without `--peer`, or with a peer that is
//! not installed, it prints refract's own numbers and no ratio (and says
//! why), and its CSV holds refract's rows alone.

use crate::common::*;

fn assert_no_ratio(o: &std::process::Output, out: &std::path::Path) {
    assert!(o.status.success(), "{}", stderr(o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("film, chosen kernel"), "{table}");
    assert!(!table.contains("xMi") && !table.contains("Mitsuba"), "{table}");
    assert!(table.contains("no peer ran"), "{table}");
    let csv = std::fs::read_to_string(out.join("prism-error-vs-time.csv")).unwrap();
    assert!(csv.lines().count() > 2 && !csv.contains("Mitsuba"), "{csv}");
}

#[test]
fn the_prism_bench_without_its_peer_prints_no_ratio() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench");
    let o = run(&["bench", "prism", "--quick", "--film-only", "--out", out.to_str().unwrap()], "", dir.path());
    assert_no_ratio(&o, &out);
    // Asked for, but not installed: a warning naming the folder, then the same.
    let venv = dir.path().join("no-venv");
    let o = run(
        &["bench", "prism", "--quick", "--film-only", "--peer", "mitsuba", "--peer-venv", venv.to_str().unwrap(), "--out", out.to_str().unwrap()],
        "",
        dir.path(),
    );
    assert!(stderr(&o).contains(&format!("warning: --peer mitsuba: no Python environment at {}", venv.display())), "{}", stderr(&o));
    assert_no_ratio(&o, &out);
    // An unknown peer is refused before any work.
    let o = run(&["bench", "prism", "--quick", "--peer", "pbrt", "--out", dir.path().join("x").to_str().unwrap()], "", dir.path());
    assert!(!o.status.success() && stderr(&o).contains("pbrt"), "{}", stderr(&o));
    assert!(!dir.path().join("x").exists());
}
