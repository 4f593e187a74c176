//! `refract figures` and `refract render`: images of the right size that are
//! not blank, and a gallery listing every figure of FIGURES.md.

use crate::common::*;

#[test]
fn quick_figures_render_and_the_gallery_lists_every_id() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let o = run(&["figures", "--quick", "--only", "css552-p5,lab-ior3.0,pm-dark-side,css552-p2", "--out", out.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    for (id, w, h) in [("css552-p5", 480, 270), ("lab-ior3.0", 301, 301), ("pm-dark-side", 480, 360), ("css552-p2", 900, 520)] {
        let img = image::open(out.join("figures").join(format!("{id}.png"))).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (w, h), "{id}");
        let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        colours.sort();
        colours.dedup();
        assert!(colours.len() > 20, "{id} is blank or uniform ({} colours)", colours.len());
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let ids = refract::experiment::figures::figure_ids(&std::fs::read_to_string(repo("scenes/FIGURES.md")).unwrap());
    assert_eq!(ids.len(), 30);
    for id in &ids {
        assert!(html.contains(&format!("id=\"{id}\"")), "index.html lacks {id}");
    }
    // Every file the page links to exists.
    for attr in ["src=\"", "href=\""] {
        for part in html.split(attr).skip(1) {
            let link = part.split('"').next().unwrap();
            if let Some(anchor) = link.strip_prefix('#') {
                assert!(html.contains(&format!("id=\"{anchor}\"")) || ["spectral"].contains(&anchor), "broken anchor {link}");
                continue;
            }
            assert!(out.join(link).exists(), "broken link {link}");
        }
    }
    assert!(html.contains("not rendered yet"), "figures left out by --only are marked");
    assert!(html.contains("Quick set"), "the quick gallery says it is quick");
    // Render times are kept out of the committed files, the page included.
    assert!(!html.contains("render time on this machine"));
    assert!(!std::fs::read_to_string(out.join("figures/figures.csv")).unwrap().contains("render_s"));
    assert!(std::fs::read_to_string(out.join("timings/figures.csv")).unwrap().starts_with("id,render_s"));
}

#[test]
fn render_takes_a_scene_file_and_names_a_bad_line() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["render", repo("scenes/lab-ior1.4.toml").to_str().unwrap(), "--quick", "--out", dir.path().join("x.png").to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(image::open(dir.path().join("x.png")).unwrap().width(), 301);
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "id = \"b\"\nmode = \"prism\"\n[params]\nscene = \"amici-screen\"\nphotons = \"many\"\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "bad.toml:5: `photons`: `\"many\"` is not a whole number");
    std::fs::write(&bad, "id = \"b\"\nmode = \"prism\"\ncolour = 1\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "bad.toml:3: `colour`: unknown key");
    // A key the scene would ignore is refused on its own line, in
    // [params] or [quick].
    std::fs::write(&bad, "id = \"b\"\nmode = \"prism\"\n[params]\nscene = \"single-prism\"\nflint_apex = 80\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "bad.toml:5: `flint_apex`: the single-prism scene has no Amici prism");
    std::fs::write(&bad, "id = \"b\"\nmode = \"prism\"\n[params]\nexact = true\n[quick]\nspp = 1\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap(), "--quick"], "", dir.path());
    assert_clean_failure(&o, "bad.toml:6: `spp`: --exact computes the image without photons");
    std::fs::write(&bad, "id = \"b\"\nmode = \"interior\"\n[params]\nseed = 3\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "bad.toml:4: `seed`: one sample a pixel looks through its centre");
    // A value the scene builder refuses names the key's line, not a flag.
    std::fs::write(&bad, "id = \"b\"\nmode = \"prism\"\n[params]\nscene = \"sphere-metal\"\n[quick]\nhaze = 0.2\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap(), "--quick"], "", dir.path());
    assert_clean_failure(&o, "bad.toml:6: `haze`: the sphere-metal scene has no collimated beam, and haze shows only beams");
    std::fs::write(&bad, "id = \"b\"\nmode = \"prism\"\n[params]\nscene = \"single-prism\"\nincidence = 10\n").unwrap();
    let o = run(&["render", bad.to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "bad.toml:5: `incidence`: at 10.000 degrees the d line is totally reflected inside the prism");
}

/// `render --set KEY=VALUE` overrides a scene file's parameters through the
/// mode's table; a bad key or value is a one-line error before any work.
#[test]
fn render_overrides_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("scenes/css552-p5.toml");
    let out = dir.path().join("small.png");
    let o = run(&["render", scene.to_str().unwrap(), "--set", "photons=20000", "--set", "size=160,60", "--out", out.to_str().unwrap()], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(image::open(&out).unwrap().to_rgb8().dimensions(), (160, 60));
    let o = run(&["render", scene.to_str().unwrap(), "--set", "photons=0", "--out", "x.png"], "", dir.path());
    assert_clean_failure(&o, "--set photons: 0 is not between 1 and 2000000000");
    let o = run(&["render", scene.to_str().unwrap(), "--set", "colour=1", "--out", "x.png"], "", dir.path());
    assert_clean_failure(&o, "--set `colour`: unknown prism parameter (did you mean `colour_map`?); expected one of scene, glass,");
    let o = run(&["render", scene.to_str().unwrap(), "--set", "film_kernel=2", "--out", "x.png"], "", dir.path());
    assert_clean_failure(&o, "--set film_kernel: only --map film has a kernel; --map kdtree gathers with --radius and --filter");
    assert!(!dir.path().join("x.png").exists());
}

/// The documented figures command, run twice into one folder, writes the
/// same bytes the second time (machine-dependent timings go only to the
/// ignored timings/ folders): following the README leaves `git status`
/// clean. The second run keeps the complete sweeps instead of re-running them.
#[test]
fn figures_twice_write_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("quick");
    let snapshot = |root: &std::path::Path| -> std::collections::BTreeMap<String, Vec<u8>> {
        fn walk(p: &std::path::Path, root: &std::path::Path, m: &mut std::collections::BTreeMap<String, Vec<u8>>) {
            for e in std::fs::read_dir(p).unwrap() {
                let p = e.unwrap().path();
                if p.file_name().is_some_and(|n| n == "timings") {
                    continue;
                }
                if p.is_dir() {
                    walk(&p, root, m);
                } else {
                    m.insert(p.strip_prefix(root).unwrap().display().to_string(), std::fs::read(&p).unwrap());
                }
            }
        }
        let mut m = Default::default();
        walk(root, root, &mut m);
        m
    };
    let mut runs = Vec::new();
    for _ in 0..2 {
        let o = run(&["figures", "--quick", "--out", out.to_str().unwrap()], "", &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
        runs.push(snapshot(&out));
    }
    assert!(runs[0].keys().any(|k| k.ends_with("runs.csv")) && runs[0].contains_key("index.html"));
    assert_eq!(runs[0].keys().collect::<Vec<_>>(), runs[1].keys().collect::<Vec<_>>(), "the same files");
    let changed: Vec<&String> = runs[0].iter().filter(|(k, v)| runs[1][*k] != **v).map(|(k, _)| k).collect();
    assert!(changed.is_empty(), "changed on the second run: {changed:?}");
}

/// `bench prism --quick` is a smoke run: it writes its CSV and plot to the
/// ignored `results/quick/bench`, never over the measurement recorded in
/// `results/bench`; the CSV has the columns, a row per measured
/// point, and finite errors.
#[test]
fn a_quick_prism_bench_leaves_the_recorded_one_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = run(&["bench", "prism", "--quick"], "", d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!d.join("results/bench").exists(), "a quick run wrote into results/bench");
    let csv = std::fs::read_to_string(d.join("results/quick/bench/prism-error-vs-time.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("method,photons,seconds,rel_error"));
    let rows: Vec<&str> = lines.collect();
    assert!(rows.len() >= 10, "{} rows", rows.len());
    for row in rows {
        let err: f64 = row.rsplit(',').next().unwrap().parse().unwrap();
        assert!(err.is_finite() && err > 0.0, "{row}");
    }
    assert!(d.join("results/quick/bench/prism-error-vs-time.png").is_file());
}
