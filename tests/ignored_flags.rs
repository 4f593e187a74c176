//! A flag, a scene key, a `--set` or an experiment axis that cannot change
//! the image is refused with the reason before any work, and nothing is
//! written: opacity at trace count 0, `--quick` without [quick] settings,
//! a shard that would hold no run. A scene file's key that its output
//! leaves unused (the tone of a .pfm) is warned about.

use crate::common::*;

const OPACITY: &str = "at trace count 0 the first hit is drawn opaque, so the opacity changes nothing; it needs a trace count above 0";
const SPECULAR: &str = "at trace count 0 the first hit is drawn opaque, so how specular light is composited changes nothing; it needs a trace count above 0";

/// Runs `args` in `dir`, expecting exit 1 with `first` as stderr's first
/// line and no file changed.
fn refused(args: &[&str], stdin: &str, dir: &std::path::Path, first: &str) {
    let before = snapshot(dir);
    let o = run(args, stdin, dir);
    assert_fails_with(&o, 1, first);
    assert_eq!(snapshot(dir), before, "{args:?} changed a file");
}

#[test]
fn opacity_at_trace_zero_is_refused_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    let cube = cube.to_str().unwrap();
    refused(&["interior", "--off", cube, "--opacity", "90", "--out", "x.png", "--size", "8,8"], "", d, &format!("refract: error: --opacity: {OPACITY}"));
    refused(&["interior", "--off", cube, "--specular-opacity", "fixed", "--out", "x.png"], "", d, &format!("refract: error: --specular-opacity: {SPECULAR}"));
    // At the prompts the trace count is known once answered.
    let answers = format!("0\n25\n255\n255\n255\np.ppm\n{cube}\n0\n1\n0\n0\n0\n1.4\n");
    refused(&["interior", "--specular-opacity", "fixed", "--size", "8,8"], &answers, d, &format!("refract: error: --specular-opacity: {SPECULAR}"));
    // A scene file's key, on its line; `--set` on a shipped scene.
    std::fs::write(d.join("s.toml"), format!("id = \"s\"\nmode = \"interior\"\n[params]\noff = \"{cube}\"\nsize = [8, 8]\nopacity = 90\n")).unwrap();
    refused(&["render", "s.toml", "--out", "y.png"], "", d, &format!("refract: error: s.toml:6: `opacity`: {OPACITY}"));
    let lab = repo("scenes/lab-ior1.4.toml");
    refused(&["render", lab.to_str().unwrap(), "--set", "opacity=90", "--out", "y.png"], "", d, &format!("refract: error: --set opacity: {OPACITY}"));
    // An experiment axis over opacity at trace 0: three identical lines.
    std::fs::write(
        d.join("e.toml"),
        format!("name = \"e\"\nmode = \"interior\"\n[fixed]\noff = \"{cube}\"\nsize = [8, 8]\n[sweep]\nior = [1.2, 1.5]\nopacity = [10, 25, 90]\n"),
    )
    .unwrap();
    refused(&["sweep", "e.toml", "--out", "o"], "", d, &format!("refract: error: e.toml:8: `opacity`: no run of the experiment uses it: {OPACITY}"));

    // Used above trace 0; the default restated at trace 0 is let be.
    for (args, out) in [(vec!["--trace", "2", "--opacity", "90"], "a.png"), (vec!["--trace", "0", "--opacity", "25"], "b.png")] {
        let mut full = vec!["interior", "--off", cube, "--size", "8,8", "--out", out];
        full.extend(args);
        let o = run(&full, "", d);
        assert!(o.status.success(), "{full:?}: {}", stderr(&o));
    }
    let o = run(&["sweep", "e.toml", "--out", "o"], "", d);
    assert!(!o.status.success());
}

#[test]
fn quick_without_quick_settings_and_an_empty_shard_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    std::fs::write(d.join("s.toml"), format!("id = \"s\"\nmode = \"interior\"\n[params]\noff = \"{}\"\nsize = [8, 8]\n", cube.display())).unwrap();
    refused(
        &["render", "s.toml", "--quick", "--out", "y.png"],
        "",
        d,
        "refract: error: --quick: s.toml has no [quick] settings, so the render would be the full one; add a [quick] table or leave --quick out",
    );
    std::fs::write(
        d.join("f.toml"),
        format!("name = \"f\"\nmode = \"interior\"\n[fixed]\noff = \"{}\"\nsize = [8, 8]\n[sweep]\nior = [1.2, 1.5]\n", cube.display()),
    )
    .unwrap();
    refused(
        &["sweep", "f.toml", "--quick", "--out", "o"],
        "",
        d,
        "refract: error: --quick: f.toml has no [quick] settings, so the sweep would be the full one; add a [quick] table or leave --quick out",
    );
    refused(
        &["sweep", "f.toml", "--shard", "1/2", "--out", "o"],
        "",
        d,
        "refract: error: --shard 1/2: shard 1 would run nothing: the grid holds 1 chain(s) of runs (the runs along its first sweep axis stay in one shard); use at most 1 shard(s)",
    );
    // Shard 0 of 2 holds the one chain and runs it.
    let o = run(&["sweep", "f.toml", "--shard", "0/2", "--out", "o"], "", d);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_scene_files_tone_is_pointed_out_when_its_output_is_a_pfm() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    let scene = format!("id = \"s\"\nmode = \"interior\"\n[params]\noff = \"{}\"\nsize = [8, 8]\ntone = \"shoulder\"\n", cube.display());
    std::fs::write(d.join("s.toml"), scene).unwrap();
    let warning = "warning: s: `tone` does not change";
    // A .pfm holds the model's colours: the scene's tone is its picture's
    // choice, so the run goes on and says the tone is not used.
    let o = run(&["render", "s.toml", "--out", "x.pfm"], "", d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains(warning), "{}", stderr(&o));
    assert!(d.join("x.pfm").exists());
    // The same from `--set`, and nothing said where the tone is used.
    std::fs::write(d.join("t.toml"), format!("id = \"s\"\nmode = \"interior\"\n[params]\noff = \"{}\"\nsize = [8, 8]\n", cube.display())).unwrap();
    let o = run(&["render", "t.toml", "--set", "tone=shoulder", "--out", "y.pfm"], "", d);
    assert!(o.status.success() && stderr(&o).contains(warning), "{}", stderr(&o));
    let o = run(&["render", "s.toml", "--out", "z.png"], "", d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("does not change"), "{}", stderr(&o));
}

/// The Fresnel weight of the light leaving a face needs light to leave:
/// refused on an opaque object and at index 1, used on glass.
#[test]
fn the_fresnel_exit_on_an_opaque_object_or_at_index_1_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    let cube = cube.to_str().unwrap();
    let base = ["interior", "--off", cube, "--size", "8,8", "--out", "x.png", "--fresnel-exit"];
    let with = |extra: &[&'static str]| base.iter().copied().chain(extra.iter().copied()).collect::<Vec<_>>();
    refused(
        &with(&["--opacity", "100", "--trace", "1"]),
        "",
        d,
        "refract: error: --fresnel-exit: an opaque object (opacity 100) lets no light out through its faces",
    );
    refused(&with(&["--ior", "1"]), "", d, "refract: error: --fresnel-exit: at index 1 all the light gets out (Fresnel transmittance 1)");
    let o = run(&with(&["--ior", "1.4"]), "", d);
    assert!(o.status.success(), "{}", stderr(&o));
}
