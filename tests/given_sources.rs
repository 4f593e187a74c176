//! One check of a given value, reported where the value came from: a
//! scene file's line, the flag, `--set KEY`, the prompt's question.

use crate::common::*;

/// A scene file of the interior mode setting `extra` after its mesh and size.
fn scene(dir: &std::path::Path, name: &str, extra: &str) {
    let off = repo("off/cube.off");
    let text = format!("id = \"s\"\nmode = \"interior\"\n[params]\noff = \"{}\"\nsize = [8, 8]\n{extra}", off.display());
    std::fs::write(dir.join(name), text).unwrap();
}

const RANGE: &str = "150 is not between 0 and 100";

#[test]
fn a_bad_value_is_named_where_it_was_given() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "bad.toml", "opacity = 150\n");
    scene(d, "ok.toml", "");
    let off = repo("off/cube.off");
    let off = off.to_str().unwrap();
    // The file's line of the key.
    assert_clean_failure(&run(&["render", "bad.toml", "--out", "o.png"], "", d), &format!("bad.toml:6: `opacity`: {RANGE}"));
    // The flag.
    assert_clean_failure(&run(&["interior", "--off", off, "--opacity", "150", "--out", "o.png"], "", d), &format!("'--opacity <X>': {RANGE}"));
    // --set KEY.
    assert_clean_failure(&run(&["render", "ok.toml", "--set", "opacity=150", "--out", "o.png"], "", d), &format!("--set opacity: {RANGE}"));
    // The prompt's question, and the line of standard input it was answered on.
    let o = run(&["interior"], "2\n150\n", d);
    assert_clean_failure(&o, &format!("line 2 of standard input: `150` is no answer to \"Opacity of object (0-100)\": {RANGE}"));
    assert!(!d.join("o.png").exists(), "nothing written");
}

/// A value the run would ignore is refused where it was given, whichever
/// value made it unused.
#[test]
fn an_ignored_value_is_named_where_it_was_given() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let why = "at trace count 0 the first hit is drawn opaque, so the opacity changes nothing";
    scene(d, "both.toml", "trace = 0\nopacity = 50\n");
    scene(d, "trace0.toml", "trace = 0\n");
    scene(d, "opacity.toml", "opacity = 50\n");
    let off = repo("off/cube.off");
    assert_clean_failure(&run(&["render", "both.toml", "--out", "o.png"], "", d), &format!("both.toml:7: `opacity`: {why}"));
    assert_clean_failure(&run(&["render", "trace0.toml", "--set", "opacity=50", "--out", "o.png"], "", d), &format!("--set opacity: {why}"));
    // --set trace=0 leaves the file's opacity unused: the file's line is named.
    assert_clean_failure(&run(&["render", "opacity.toml", "--set", "trace=0", "--out", "o.png"], "", d), &format!("opacity.toml:6: `opacity`: {why}"));
    let flags = ["interior", "--off", off.to_str().unwrap(), "--trace", "0", "--opacity", "50", "--out", "o.png"];
    assert_clean_failure(&run(&flags, "", d), &format!("--opacity: {why}"));
}

/// A whole configuration the prism mode refuses (k below 4; k with passes)
/// is named at each value's place: the file's line, the flag, `--set`; an
/// experiment refuses it before any run.
#[test]
fn a_refused_combination_is_named_where_its_values_were_given() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let few = "k = 2 is below 4: the k-nearest estimate";
    std::fs::write(d.join("k.toml"), "id = \"k\"\nmode = \"prism\"\n[params]\nmap = \"kdtree\"\nsize = [8, 8]\nk = 2\n").unwrap();
    assert_clean_failure(&run(&["render", "k.toml", "--out", "o.png"], "", d), &format!("k.toml:6: `k`: {few}"));
    std::fs::write(d.join("k6.toml"), "id = \"k\"\nmode = \"prism\"\n[params]\nmap = \"kdtree\"\nsize = [8, 8]\nk = 6\n").unwrap();
    assert_clean_failure(&run(&["render", "k6.toml", "--set", "passes=3", "--out", "o.png"], "", d), "--set passes, k6.toml:6: `k`: passes above 1");
    let flags = ["prism", "--size", "8,8", "--map", "kdtree", "--k", "6", "--passes", "3", "--out", "o.png"];
    assert_clean_failure(&run(&flags, "", d), "--passes, --k: passes above 1 need a gather radius");
    let sweep = "name = \"k\"\nmode = \"prism\"\n[fixed]\nmap = \"kdtree\"\nsize = [8, 8]\nk = 2\n[sweep]\nphotons = [1000, 2000]\n";
    std::fs::write(d.join("k-sweep.toml"), sweep).unwrap();
    assert_clean_failure(&run(&["sweep", "k-sweep.toml", "--out", "runs"], "", d), &format!("k-sweep.toml:6: `k`: {few}"));
    assert!(!d.join("o.png").exists() && !d.join("runs").exists(), "nothing written, no run started");
}
