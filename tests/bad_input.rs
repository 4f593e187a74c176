use crate::common::*;

/// (file content, text the one-line error must contain, with the line).
const CASES: &[(&[u8], &str)] = &[
    (b"", "bad.off:1: expected the keyword OFF or COFF"),
    (b"PLY\n", "bad.off:1: expected the keyword OFF or COFF, found `PLY`"),
    (b"OFFX 1 0 0\n", "bad.off:1: expected the keyword"),
    (b"NOFF\n3 1 0\n", "bad.off:1: unsupported OFF variant `NOFF`"),
    (b"OFF BINARY\n", "bad.off:1: unsupported OFF variant"),
    (b"4OFF\n", "bad.off:1: unsupported"),
    (b"OFF\n3 1\n", "bad.off:2: file ends early: expected edge count"),
    (b"OFF\n3 1 0\n0 0 0\n1 0 0\n", "bad.off:4: file ends early: expected x of vertex 3 of 3"),
    (b"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "bad.off:6: file ends early: expected face 2 of 2"),
    (b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", "bad.off:7: extra data"),
    (b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n", "bad.off:6: face 1 refers to vertex 9, but the file has 3 vertices"),
    (b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "bad.off:6: face 1 refers to vertex -1"),
    (b"OFF\n1 0 0\n0 NaN 0\n", "bad.off:3: y of vertex 1 of 1 `NaN` is not a finite number"),
    (b"OFF\n1 0 0\n0 0 -inf\n", "bad.off:3: z of vertex 1 of 1 `-inf` is not a finite"),
    (b"OFF\n1 0 0\n1e300 0 0\n", "bad.off:3: x of vertex 1 of 1 `1e300` is not a finite"),
    (b"OFF\n1 0 0\n0 0 1x\n", "bad.off:3: expected z of vertex 1 of 1 (a number), found `1x`"),
    (b"OFF\n2000000000 2000000000 0\n0 0 0\n", "bad.off:3: file ends early"),
    (b"OFF\n\x00\x01\x02\x03", "bad.off:2: non-text data"),
    (b"OFF\n3 1 0\n\x89PNG", "bad.off:3: non-text data"),
    (b"COFF\n1 0 0\n0 0 0 1 2\n", "bad.off:3: COFF vertex 1 of 1 needs 3 or 4 colour components"),
];

#[test]
fn malformed_off_files_fail_cleanly_with_no_output() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (content, needle)) in CASES.iter().enumerate() {
        std::fs::write(dir.path().join("bad.off"), content).unwrap();
        let out = format!("out{i}.ppm");
        let o = run(&["interior", "--off", "bad.off", "--out", &out, "--size", "8,8"], "", dir.path());
        assert_clean_failure(&o, needle);
        assert!(!dir.path().join(&out).exists(), "case {i} left an output file");
    }
    // Nothing half-written either: no temporary files left behind.
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("bad.off")]);
}

#[test]
fn impossible_parameters_name_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    let c = cube.to_str().unwrap();
    for (args, needle) in [
        (vec!["--ior", "0"], "invalid value '0' for '--ior <X>': 0 is not greater than 0 and at most 100"),
        (vec!["--ior", "nan"], "`nan` is not a finite number"),
        (vec!["--opacity", "120"], "120 is not between 0 and 100"),
        (vec!["--color", "1,2"], "`1,2` is not three comma-separated values"),
        (vec!["--size", "0,10"], "width and height must be whole numbers"),
        (vec!["--scale", "-1"], "-1 is not greater than 0"),
        (vec!["--atten", "-1"], "for '--atten <X>': -1 is not between 0 and 1000000"),
        (vec!["--spp", "0"], "for '--spp <N>': 0 is not between 1 and 4096"),
        (vec!["--out", "no/such/dir/x.ppm"], "--out: folder no/such/dir does not exist"),
    ] {
        let mut full = vec!["interior", "--off", c];
        if !args.contains(&"--size") {
            full.extend(["--size", "8,8"]);
        }
        full.extend(args.iter().copied());
        let o = run(&full, "", dir.path());
        assert!(!o.status.success(), "{args:?} should fail");
        let err = stderr(&o);
        assert!(err.contains(needle) && !err.contains("panicked"), "{args:?}: {err}");
    }
    let o = run(&["interior", "--ior", "1.5"], "", dir.path());
    assert_clean_failure(&o, "--off is required");
    let o = run(&["interior", "--off", "nowhere.off"], "", dir.path());
    assert_clean_failure(&o, "nowhere.off: cannot read the file");
    // A seed with one sample a pixel would change nothing: refused before
    // any question is asked.
    let o = run(&["interior", "--seed", "3"], "", dir.path());
    assert_clean_failure(&o, "--seed: one sample a pixel looks through its centre");
}

#[test]
fn files_from_other_tools_load() {
    // Quirks seen in the wild: comments before the keyword, counts glued to
    // it (ModelNet), CRLF, every number on its own line, int colours + alpha.
    let dir = tempfile::tempdir().unwrap();
    let modelnet = "# exported\r\nOFF8 6 0\r\n-1 -1 -1\r\n1 -1 -1\r\n-1 1 -1\r\n1 1 -1\r\n-1 -1 1\r\n1 -1 1\r\n-1 1 1\r\n1 1 1\r\n4 0 2 3 1\r\n4 4 5 7 6\r\n4 0 1 5 4\r\n4 2 6 7 3\r\n4 0 4 6 2\r\n4 1 3 7 5\r\n";
    let own_lines: String = std::fs::read_to_string(repo("off/cube.off"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .flat_map(|l| l.split_whitespace().map(|t| format!("{t}\n")).collect::<Vec<_>>())
        .collect();
    let coloured = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 255 0 0 255\n3 0 2 3 0 0 255 128\n";
    let mut images = Vec::new();
    for (name, text, extra) in [("modelnet.off", modelnet, None), ("own.off", own_lines.as_str(), None), ("col.off", coloured, Some("--coff"))] {
        std::fs::write(dir.path().join(name), text).unwrap();
        let out = format!("{name}.ppm");
        let mut args = vec!["interior", "--off", name, "--out", &out, "--size", "32,32"];
        args.extend(extra);
        let o = run(&args, "", dir.path());
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        images.push(ppm(&dir.path().join(&out)));
    }
    assert_eq!(images[0], images[1], "the same cube, written two ways, renders the same");
}

/// A mesh with nothing to render is refused (as an OBJ is), not drawn as
/// a silent image of the background.
#[test]
fn empty_and_single_point_meshes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, counts) in [
        ("empty.off", "OFF\n0 0 0\n", "0 in the file: 0 with fewer than 3 vertices, 0 triangles of zero area"),
        ("point.off", "OFF\n1 1 0\n1 2 3\n1 0\n", "1 in the file: 1 with fewer than 3 vertices, 0 triangles of zero area"),
        ("flat.off", "OFF\n3 1 0\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n", "1 in the file: 0 with fewer than 3 vertices, 1 triangles of zero area"),
    ] {
        std::fs::write(dir.path().join(name), text).unwrap();
        let o = run(&["interior", "--off", name, "--out", "o.ppm", "--size", "8,8", "--background", "10,20,30", "--trace", "3"], "", dir.path());
        assert_clean_failure(&o, &format!("{name}: no faces to render ({counts})"));
        assert!(!dir.path().join("o.ppm").exists(), "{name}: no image");
    }
}

/// Paths and counts are checked before any work: one line naming the flag,
/// exit 1, and no output file appears.
#[test]
fn outputs_threads_and_csv_paths_are_checked_before_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = repo("off/cube.off");
    let c = cube.to_str().unwrap();
    let scene_dir = repo("scenes");
    let scenes = scene_dir.to_str().unwrap();
    std::fs::create_dir(d.join("folder.png")).unwrap();
    std::fs::write(d.join("plain"), "a file, not a folder").unwrap();
    std::fs::create_dir_all(d.join("taken/prism-error-vs-time.png")).unwrap();
    assert!(std::process::Command::new("mkfifo").arg(d.join("fifo.png")).status().unwrap().success());
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (vec!["interior", "--off", c, "--out", "x.jpg"], "--out: `x.jpg` does not end in an image extension refract writes here (.png, .ppm, .pfm)", "x.jpg"),
        (vec!["interior", "--off", c, "--out", "noext"], "--out: `noext` does not end in an image extension", "noext"),
        (vec!["interior", "--off", c, "--out", "x.pfm", "--tone", "shoulder"], "--tone: a .pfm output holds the model's colours, before any tone", "x.pfm"),
        (vec!["interior", "--off", c, "--out", "folder.png"], "--out: folder.png is a folder", ""),
        (vec!["interior", "--off", c, "--out", "fifo.png"], "--out: fifo.png is not a regular file", ""),
        (vec!["interior", "--off", c, "--out", "o.png", "--timing-csv", "no/such/t.csv"], "--timing-csv: folder no/such does not exist", "o.png"),
        (vec!["interior", "--off", c, "--out", "o.png", "--threads", "1000"], "--threads: 1000 is more than four times the", "o.png"),
        (
            vec!["prism", "--photons", "1000", "--size", "8,8", "--out", "p.jpg"],
            "--out: `p.jpg` does not end in an image extension refract writes here (.png, .ppm, .pfm, .exr)",
            "p.jpg",
        ),
        (vec!["prism", "--photons", "1000", "--size", "8,8", "--out", "p.png", "--threads", "999"], "--threads: 999 is more than four times the", "p.png"),
        (
            vec!["prism", "--photons", "1000", "--size", "8,8", "--out", "p.png", "--timing-csv", "folder.png"],
            "--timing-csv: folder.png is not a regular file",
            "p.png",
        ),
        (vec!["prism", "trace", "--scene", "sphere-metal"], "prism trace: the sphere-metal scene has no prism to trace through", ""),
        // The bench's folder and files, before its minute of work.
        (vec!["bench", "prism", "--quick", "--out", "plain"], "--out: plain is not a folder", ""),
        (vec!["bench", "prism", "--quick", "--out", "plain/sub"], "--out: cannot create the folder plain/sub", ""),
        (vec!["bench", "prism", "--quick", "--out", "taken"], "--out: taken/prism-error-vs-time.png is not a regular file", ""),
        // Every output folder: a file in the way is named.
        (vec!["figures", "--quick", "--only", "css552-p2", "--scene-dir", scenes, "--out", "plain"], "--out: plain is not a folder", ""),
        (vec!["spectrum", "accuracy", "--out", "plain"], "plain is not a folder", ""),
        (vec!["spectrum", "accuracy", "--out", "plain/sub"], "cannot create the folder plain/sub", ""),
        (vec!["meshes", "plain"], "plain is not a folder", ""),
    ];
    for (args, needle, output) in cases {
        let o = run(&args, "", d);
        assert_clean_failure(&o, needle);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        if !output.is_empty() {
            assert!(!d.join(output).exists(), "{args:?} left {output}");
        }
    }
    // A radius whose disc's area would underflow is refused by the parser.
    let o = run(&["prism", "--photons", "1000", "--size", "8,8", "--radius", "1e-160", "--out", "nan.png"], "", d);
    assert_clean_failure(&o, "1e-160 is not between 1e-9 and 1000");
    assert!(!d.join("nan.png").exists());
    assert!(d.join("folder.png").is_dir(), "the folder is untouched");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::symlink_metadata(d.join("fifo.png")).unwrap().file_type().is_fifo(), "the FIFO is untouched");
}

/// `refract` alone prints the usage and the commands on stderr; a mistyped
/// flag is one line with the nearest option and where the help is.
#[test]
fn bare_command_and_typos_help_the_user() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&[], "", dir.path());
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("Usage: refract") && err.contains("Commands:") && err.contains("figures") && err.contains("interior"), "{err}");
    let o = run(&["prism", "--photon", "5"], "", dir.path());
    assert_fails_with(&o, 1, "refract: error: unexpected argument '--photon' found; a similar argument exists: '--photons' (see `refract prism --help`)");
    let o = run(&["prism", "--map", "octree"], "", dir.path());
    assert_fails_with(&o, 1, "refract: error: invalid value 'octree' for '--map <NAME>': `octree` is not one of buffer, kdtree, film (did you mean `kdtree`?) (see `refract prism --help`)");
}

/// Inputs are read only from regular files and up to a size cap, and a
/// prompt answer only up to a line's cap: a device, a FIFO or endless
/// input is a one-line error, never a read until memory runs out.
#[test]
fn inputs_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert!(std::process::Command::new("mkfifo").arg(d.join("scene.toml")).status().unwrap().success());
    for (args, needle) in [
        (vec!["interior", "--off", "/dev/zero", "--out", "o.png"], "/dev/zero: cannot read the file: not a regular file"),
        (vec!["render", "scene.toml"], "scene.toml: cannot read: not a regular file"),
        (vec!["sweep", "scene.toml"], "scene.toml: cannot read: not a regular file"),
    ] {
        let o = run(&args, "", d);
        assert_clean_failure(&o, needle);
    }
    assert!(!d.join("o.png").exists());
    let cube = repo("off/cube.off");
    let o = bin().args(["interior", "--off", cube.to_str().unwrap(), "--out", "o.png"]).current_dir(d).env("REFRACT_MAX_INPUT_BYTES", "100").output().unwrap();
    assert_clean_failure(&o, "larger than the 100-byte limit on inputs (set REFRACT_MAX_INPUT_BYTES to raise it)");
    // An endless first answer.
    let o = run(&["interior"], &"7".repeat(100_000), d);
    assert_clean_failure(&o, "the answer to \"Maximum ray trace count\" is longer than 4096 bytes");
}

/// A run that would need more memory than the machine has free is refused
/// by name before any photon is traced, and writes nothing (the free
/// memory pretended by REFRACT_AVAILABLE_MEMORY: 1 GiB).
#[test]
fn a_run_bigger_than_memory_is_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let o = bin()
        .args(["prism", "--map", "kdtree", "--photons", "200000000", "--size", "64,24", "--out", "m.png"])
        .current_dir(dir.path())
        .env("REFRACT_AVAILABLE_MEMORY", (1u64 << 30).to_string())
        .output()
        .unwrap();
    assert_clean_failure(&o, "--photons 200000000 and --size 64x24 would need about 6.0 GiB of memory; REFRACT_AVAILABLE_MEMORY allows 1.0 GiB");
    assert!(!dir.path().join("m.png").exists());
    // The film (the default map) keeps no photons, but two sums per pixel.
    let o = bin()
        .args(["prism", "--size", "8000,8000", "--photons", "1000", "--out", "m.png"])
        .current_dir(dir.path())
        .env("REFRACT_AVAILABLE_MEMORY", (1u64 << 30).to_string())
        .output()
        .unwrap();
    assert!(!o.status.success() && stderr(&o).contains("--size 8000x8000 would need about"), "{}", stderr(&o));
    // The exact image holds a partial image a thread (at 1536x1536 on 2
    // threads about 0.3 GiB; it once held 64 of them, 3.4 GiB).
    let o = bin()
        .args(["prism", "--exact", "--threads", "2", "--size", "1536,1536", "--out", "m.pfm"])
        .current_dir(dir.path())
        .env("REFRACT_AVAILABLE_MEMORY", "250000000")
        .output()
        .unwrap();
    assert_clean_failure(&o, "--exact at --size 1536x1536 would need about 0.3 GiB of memory; REFRACT_AVAILABLE_MEMORY allows 0.2 GiB");
    assert!(!dir.path().join("m.pfm").exists());
    // A run that fits goes ahead.
    let o = bin()
        .args(["prism", "--photons", "2000", "--size", "64,24", "--out", "m.png"])
        .current_dir(dir.path())
        .env("REFRACT_AVAILABLE_MEMORY", (1u64 << 30).to_string())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // The interior mode checks its image before reading the mesh.
    let o = bin()
        .args(["interior", "--off", "/nonexistent.off", "--size", "16000,16000", "--out", "i.png"])
        .current_dir(dir.path())
        .env("REFRACT_AVAILABLE_MEMORY", (1u64 << 30).to_string())
        .output()
        .unwrap();
    assert_clean_failure(&o, "--size 16000x16000 would need about 3.6 GiB of memory; REFRACT_AVAILABLE_MEMORY allows 1.0 GiB");
    assert!(!dir.path().join("i.png").exists());
}
