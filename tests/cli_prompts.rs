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

#[test]
fn bad_answers_are_asked_again_and_early_end_fails() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    let answers = format!("many\n0\n25\n255\n255\n255\nout.ppm\nmissing.off\n{}\n0\n1\n0\n0\n0\n-1\n1.4\n", cube.display());
    let o = run(&["interior", "--size", "16,16"], &answers, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let shown = String::from_utf8_lossy(&o.stdout);
    assert!(shown.contains("`many` is not a whole number"), "{shown}");
    assert!(shown.contains("missing.off: no such file"), "{shown}");
    assert!(shown.contains("-1 is not greater than 0 and at most 100"), "{shown}");
    assert!(dir.path().join("out.ppm").exists());

    let o = run(&["interior"], "0\n25\n255\n", dir.path());
    assert_clean_failure(&o, "input ended before an answer to \"G\"");
}
