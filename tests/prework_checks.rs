//! Every check that can be made before the work is made before it: an
//! output folder that takes no file, coefficients out of range, a mesh
//! with nothing to render; huge rotations are reduced, not a black image.

use crate::common::*;

#[test]
fn an_unwritable_output_folder_is_refused_before_the_render() {
    // /sys takes no new file, even for root (a chmod would not stop root).
    for (mode, extra) in [("prism", vec!["--photons", "50000000"]), ("interior", vec!["--off", "off/cube.off", "--size", "2000,2000", "--trace", "8"])] {
        let mut args = vec![mode, "--out", "/sys/refract-test.png"];
        args.extend(extra);
        let o = run(&args, "", &repo(""));
        assert_clean_failure(&o, "--out: cannot write in the folder /sys: ");
    }
}

#[test]
fn coefficients_are_bounded_and_named() {
    for flag in ["--ka", "--kd", "--ks", "--atten"] {
        let o = run(&["interior", "--off", "off/cube.off", flag, "1e300", "--out", "/tmp/never.png"], "", &repo(""));
        assert_clean_failure(&o, &format!("invalid value '1e300' for '{flag} <X>': 1e300 is not between 0 and "));
    }
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("k.toml");
    std::fs::write(&file, format!("name = \"k\"\nmode = \"interior\"\n[fixed]\noff = \"{}\"\nks = 1e300\n", repo("off/cube.off").display())).unwrap();
    let o = run(&["sweep", file.to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "k.toml:5: `ks`: 1e300 is not between 0 and 1000");
    assert!(!dir.path().join("o").exists());
}

#[test]
fn huge_rotations_are_reduced_not_a_black_image() {
    let dir = tempfile::tempdir().unwrap();
    let image = |rot: &str| {
        let out = dir.path().join(format!("{}.png", rot.replace(',', "_")));
        let o = run(&["interior", "--off", "off/cube.off", "--size", "24,24", "--rot", rot, "--out", out.to_str().unwrap()], "", &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
        image::open(&out).unwrap().to_rgb8().into_raw()
    };
    for rot in ["3.5e38,0,0", "1e300,1e300,1e300"] {
        assert!(image(rot).iter().any(|&b| b > 0), "--rot {rot}: a black image");
    }
    // A whole number of turns more is the same angle.
    assert_eq!(image("380,30,0"), image("20,30,0"));
}

/// A black interior image is never silent: it says why.
#[test]
fn a_black_interior_image_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.png");
    let o = run(&["interior", "--off", "off/cube.off", "--size", "16,16", "--object-colour", "0,0,0", "--out", out.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(image::open(&out).unwrap().to_rgb8().iter().all(|&b| b == 0));
    assert!(stderr(&o).contains("note: the image is black: the object colour is black (--object-colour 0,0,0)"), "{}", stderr(&o));
    let o = run(&["interior", "--off", "off/cube.off", "--size", "16,16", "--out", out.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success() && !stderr(&o).contains("black"), "{}", stderr(&o));
    // A scene file's render says it too.
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, format!("id = \"s\"\nmode = \"interior\"\n[params]\noff = \"{}\"\nsize = [16, 16]\n", repo("off/cube.off").display())).unwrap();
    let o = run(&["render", scene.to_str().unwrap(), "--set", "object_colour=0,0,0", "--out", out.to_str().unwrap()], "", &repo(""));
    assert!(o.status.success() && stderr(&o).contains("note: s: the image is black: the object colour is black"), "{}", stderr(&o));
}

#[test]
fn a_mesh_with_no_faces_is_refused_in_off_as_in_obj() {
    let dir = tempfile::tempdir().unwrap();
    let off = dir.path().join("none.off");
    std::fs::write(&off, "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n").unwrap();
    let out = dir.path().join("x.png");
    let o = run(&["interior", "--off", off.to_str().unwrap(), "--size", "16,16", "--out", out.to_str().unwrap()], "", &repo(""));
    assert_clean_failure(&o, &format!("{}: no faces to render (0 in the file", off.display()));
    assert!(!out.exists(), "no black image");
    let obj = dir.path().join("none.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let o = run(&["prism", "--obj", obj.to_str().unwrap(), "--out", out.to_str().unwrap()], "", &repo(""));
    assert_clean_failure(&o, "no usable faces");
    assert!(!out.exists());
}

/// Under a process limit (`prlimit --as`) that MemAvailable does not show,
/// a run that would not fit is refused before any work, naming the limit.
#[test]
fn a_run_over_the_process_memory_limit_is_refused_naming_it() {
    if !std::process::Command::new("prlimit").arg("--version").output().is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: no prlimit");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.png");
    let o = std::process::Command::new("prlimit")
        .args(["--as=3000000000", env!("CARGO_BIN_EXE_refract"), "prism", "--map", "kdtree", "--photons", "250000000", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_clean_failure(&o, "--photons 250000000 and --size 640x240 would need about ");
    assert!(stderr(&o).contains("the process's address-space limit (RLIMIT_AS, `ulimit -v`) leaves 2."), "{}", stderr(&o));
    assert!(!out.exists());
    let o = std::process::Command::new("prlimit")
        .args(["--data=200000000", env!("CARGO_BIN_EXE_refract"), "interior", "--off", "off/cube.off", "--size", "8000,8000", "--out", out.to_str().unwrap()])
        .current_dir(repo(""))
        .output()
        .unwrap();
    assert_clean_failure(&o, "--size 8000x8000 would need about ");
    assert!(stderr(&o).contains("data-size limit (RLIMIT_DATA, `ulimit -d`) leaves 0.2 GiB"), "{}", stderr(&o));
}

/// An experiment file's mistakes are found whatever the flags: in its
/// [quick] version without --quick, two cases or plots of one name, one
/// parameter under two names; and a scene or experiment file of more than
/// 1 MiB is refused before it is parsed.
#[test]
fn experiment_files_are_checked_whole() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off").display().to_string();
    let file = dir.path().join("e.toml");
    let head = format!("name = \"e\"\nmode = \"interior\"\n[fixed]\noff = \"{cube}\"\nsize = [8, 8]\n");
    let refused = |body: &str, needle: &str| {
        std::fs::write(&file, format!("{head}{body}")).unwrap();
        let o = run(&["sweep", file.to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()], "", dir.path());
        assert_clean_failure(&o, needle);
        assert!(!dir.path().join("o").exists(), "{needle}: nothing written");
    };
    refused("[quick]\nfixed = { size = [-1, 8] }\n", "width and height must be whole numbers from 1 to 16384 (in the file's [quick] version)");
    // The line of the key itself, from the parser's spans: not the comment
    // that names it first, nor [fixed], which [quick] overrides.
    refused(
        "[quick]\n# opacity as the report has it\nfixed = { trace = 1,\n  opacity = 120 }\n",
        "e.toml:9: `opacity`: 120 is not between 0 and 100 (in the file's [quick] version)",
    );
    refused("[[case]]\nname = \"a\"\nior = 1.2\n[[case]]\nname = \"a\"\nior = 1.4\n", "e.toml:10: `name`: `a` is also case 1's name; each case needs its own");
    refused(
        "[sweep]\ntrace = [0, 1]\n[[outputs.plot]]\nx = \"param_trace\"\ny = \"rays\"\nfile = \"p\"\n[[outputs.plot]]\nx = \"param_trace\"\ny = \"render_s\"\nfile = \"p\"\n",
        "`file`: `p` is also plot 1's file; each plot needs its own",
    );
    refused("light = [0, 0, 0]\nlight_pos = [0.1, 0, 0]\n", "e.toml:7: `light_pos`: names the same parameter as `light` (in [fixed]); use one name");
    let big = dir.path().join("big.toml");
    std::fs::write(&big, format!("{head}# {}\n", "x".repeat(1 << 20))).unwrap();
    for cmd in ["sweep", "render"] {
        let o = run(&[cmd, big.to_str().unwrap()], "", dir.path());
        assert_clean_failure(&o, "big.toml: cannot read: larger than the 1048576-byte limit on scene and experiment files");
    }
}
