use crate::common::*;

const ANSWERS: &str = "0\n25\n255\n255\n255\nprompted.ppm\nCUBE\n0\n1\n0\n0\n0\n1.4\n";

#[test]
fn piped_prompts_render_and_equal_the_flag_run() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    let answers = ANSWERS.replace("CUBE", cube.to_str().unwrap());
    let o = run(&["interior", "--size", "81,61"], &answers, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let prompts = String::from_utf8_lossy(&o.stdout);
    for p in [
        "Maximum ray trace count",
        "Opacity of object",
        "R:",
        "G:",
        "B:",
        "File name of output file",
        "File name of .off file",
        "color off format",
        "Scale Factor",
        "X rotation",
        "Y rotation",
        "Z rotation",
        "Refractive Index",
    ] {
        assert!(prompts.contains(p), "missing prompt {p}: {prompts}");
    }
    let flags = [
        "interior",
        "--size",
        "81,61",
        "--trace",
        "0",
        "--opacity",
        "25",
        "--color",
        "255,255,255",
        "--out",
        "flagged.ppm",
        "--off",
        cube.to_str().unwrap(),
        "--scale",
        "1",
        "--rot",
        "0,0,0",
        "--ior",
        "1.4",
    ];
    let o = run(&flags, "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (ppm(&dir.path().join("prompted.ppm")), ppm(&dir.path().join("flagged.ppm")));
    assert_eq!((a.0, a.1), (81, 61));
    assert_eq!(a, b, "prompt and flag runs differ");
    assert!(a.2.iter().any(|&v| v > 40), "the cube should be visible");
}

#[test]
fn prompts_with_rotation_colour_and_png_equal_flags() {
    let dir = tempfile::tempdir().unwrap();
    let off = repo("off/cube-coff.off");
    let answers = format!("3\n40\n10\n200\n30\np.png\n{}\n1\n0.8\n10\n-20\n30\n2.0\n", off.display());
    let o = run(&["interior", "--size", "64,64", "--specular-opacity", "fixed"], &answers, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(
        &[
            "interior",
            "--size",
            "64,64",
            "--specular-opacity",
            "fixed",
            "--trace",
            "3",
            "--opacity",
            "40",
            "--color",
            "10,200,30",
            "--out",
            "f.png",
            "--off",
            off.to_str().unwrap(),
            "--coff",
            "--scale",
            "0.8",
            "--rot",
            "10,-20,30",
            "--ior",
            "2.0",
        ],
        "",
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let a = std::fs::read(dir.path().join("p.png")).unwrap();
    let b = std::fs::read(dir.path().join("f.png")).unwrap();
    assert_eq!(&a[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(a, b);
}

/// Answers from a pipe: the first bad one stops the run before any work,
/// naming its line, the question and the answer (at a terminal it would be
/// asked again: the unit tests of `params::prompts`); a file that is not a
/// mesh is caught at the mesh's own question; input that ends early names
/// the question left.
#[test]
fn piped_answers_stop_at_the_first_bad_one() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    let good = |trace: &str, mesh: &str| format!("{trace}\n25\n255\n255\n255\nout.ppm\n{mesh}\n0\n1\n0\n0\n0\n1.4\n");
    let o = run(&["interior", "--size", "16,16"], &good("0", &cube.display().to_string()), dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("out.ppm").exists());
    std::fs::remove_file(dir.path().join("out.ppm")).unwrap();

    let o = run(&["interior", "--size", "16,16"], &good("many", &cube.display().to_string()), dir.path());
    assert_clean_failure(&o, "line 1 of standard input: `many` is no answer to \"Maximum ray trace count\": `many` is not a whole number");
    let o = run(&["interior", "--size", "16,16"], &good("0", "missing.off"), dir.path());
    assert_clean_failure(&o, "line 7 of standard input: `missing.off` is no answer to \"File name of .off file\": missing.off: no such file");
    let readme = repo("README.md").display().to_string();
    let o = run(&["interior", "--size", "16,16"], &good("0", &readme), dir.path());
    assert_clean_failure(&o, &format!("line 7 of standard input: `{readme}` is no answer to \"File name of .off file\": {readme}:3: expected the keyword OFF"));
    assert!(!dir.path().join("out.ppm").exists(), "nothing written");

    let o = run(&["interior"], "0\n25\n255\n", dir.path());
    assert_clean_failure(&o, "input ended before an answer to \"G\"");
}

/// Renamed flags keep their old spellings as hidden aliases, with the same
/// result: `--colours` is `--colour-map`, `--color` is `--object-colour`.
#[test]
fn old_spellings_still_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let pair = |a: &[&str], b: &[&str], what: &str| {
        let (x, y) = (d.join(format!("{what}-a.png")), d.join(format!("{what}-b.png")));
        for (args, out) in [(a, &x), (b, &y)] {
            let mut full: Vec<&str> = args.to_vec();
            full.extend(["--out", out.to_str().unwrap()]);
            let o = run(&full, "", d);
            assert!(o.status.success(), "{full:?}: {}", stderr(&o));
        }
        assert_eq!(std::fs::read(&x).unwrap(), std::fs::read(&y).unwrap(), "{what}");
    };
    let base = ["prism", "--size", "32,16", "--photons", "2000", "--spp", "1"];
    pair(&[&base[..], &["--colours", "gradient"]].concat(), &[&base[..], &["--colour-map", "gradient"]].concat(), "colour map");
    let cube = repo("off/cube.off").display().to_string();
    let ib = ["interior", "--size", "16,16", "--off", cube.as_str()];
    pair(&[&ib[..], &["--color", "0,0,255"]].concat(), &[&ib[..], &["--object-colour", "0,0,255"]].concat(), "object colour");
}

/// A report-era answer file, answers separated by spaces as C++ `cin >>`
/// reads them, with blank lines, replays to the same bytes as the flags; a
/// bad token names its line.
#[test]
fn space_separated_answers_replay_to_the_flags_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    let answers = format!("2 40\n\n10 200 30\n  tokens.ppm   {}\n0 1.2\n\n15 -20 5 1.6\n", cube.display());
    let o = run(&["interior", "--size", "40,30"], &answers, d);
    assert!(o.status.success(), "{}", stderr(&o));
    let flags = [
        "interior",
        "--size",
        "40,30",
        "--trace",
        "2",
        "--opacity",
        "40",
        "--object-colour",
        "10,200,30",
        "--out",
        "flags.ppm",
        "--off",
        cube.to_str().unwrap(),
        "--scale",
        "1.2",
        "--rot",
        "15,-20,5",
        "--ior",
        "1.6",
    ];
    let o = run(&flags, "", d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(d.join("tokens.ppm")).unwrap(), std::fs::read(d.join("flags.ppm")).unwrap());

    let before = snapshot(d);
    let bad = format!("2 40\n\n10 200 300\n  bad.ppm   {}\n0 1.2\n\n15 -20 5 1.6\n", cube.display());
    let o = run(&["interior", "--size", "40,30"], &bad, d);
    assert_fails_with(&o, 1, "refract: error: line 3 of standard input: `300` is no answer to \"B\": 300 is outside 0-255");
    assert_eq!(snapshot(d), before);
}
