//! Wavefront OBJ input, as `prism --obj` and `interior --off NAME.obj` read
//! it: every refusal says OBJ and names the file and line, tobj's own
//! refusals included; a soup of overlapping triangles is warned of before
//! the light pass.

use crate::common::*;

/// (file content, text the one-line error must contain).
const CASES: &[(&[u8], &str)] = &[
    (b"v 0 0 0\n\x00\n", "bad.obj:2: non-text data (control byte 0x00); only text OBJ files are read"),
    (b"v 0 0 0\n\xff\xfe\n", "bad.obj:2: non-text data (invalid UTF-8); only text OBJ files are read"),
    (b"v 0 0 0\nv 1 0 0 1 1\n", "bad.obj:2: `v` needs 3, 4 (x y z w) or 6 (x y z r g b) numbers, found 5"),
    (b"v 0 0 0\nv 1 0 0 0\n", "bad.obj:2: a vertex's w is 0 (x y z are divided by it)"),
    (b"v 0 0 0\nvt 0.5\n", "bad.obj:2: `vt` needs 2 or 3 numbers, found 1"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl\nf 1 2 3\n", "bad.obj:5: tobj could not read the OBJ statement here: material parse error"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "bad.obj:4: face index `7` is out of range (3 defined so far)"),
];

#[test]
fn malformed_obj_files_name_the_format_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    for (content, needle) in CASES {
        std::fs::write(dir.path().join("bad.obj"), content).unwrap();
        let o = run(&["prism", "--obj", "bad.obj", "--out", "p.png", "--size", "16,8", "--photons", "10"], "", dir.path());
        assert_clean_failure(&o, needle);
        assert!(!stderr(&o).contains("OFF"), "{}", stderr(&o));
        let o = run(&["interior", "--off", "bad.obj", "--out", "i.ppm", "--size", "8,8"], "", dir.path());
        assert_clean_failure(&o, needle);
        assert!(!dir.path().join("p.png").exists() && !dir.path().join("i.ppm").exists(), "{needle}: no image");
    }
}

#[test]
fn an_obj_renders_in_the_interior_mode_comments_and_all() {
    let dir = tempfile::tempdir().unwrap();
    let tetra = "# tetrahedron\nv 0 0 0 # origin\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2 # base\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.path().join("t.obj"), tetra).unwrap();
    let o = run(&["interior", "--off", "t.obj", "--out", "t.ppm", "--size", "8,8"], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("t.ppm").exists());
    std::fs::write(dir.path().join("flat.obj"), "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n").unwrap();
    let o = run(&["interior", "--off", "flat.obj", "--out", "f.ppm", "--size", "8,8"], "", dir.path());
    assert_clean_failure(&o, "flat.obj: no faces to render (1 in the file: 0 with fewer than 3 vertices, 1 triangles of zero area)");
}

/// Large random triangles overlap everywhere: no hierarchy narrows a ray's
/// tests, so the run says so, once, before its light pass, with what the
/// pass will cost (and a closed mesh of as many faces does not).
#[test]
fn a_soup_of_large_triangles_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let mut state = 12345u64;
    let mut coord = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 0.2 - 0.1
    };
    let n = 3000;
    let mut text = String::new();
    for _ in 0..3 * n {
        text += &format!("v {:.6} {:.6} {:.6}\n", coord(), coord(), coord());
    }
    for i in 0..n {
        text += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
    }
    std::fs::write(dir.path().join("soup.obj"), text).unwrap();
    let o = run(&["prism", "--obj", "soup.obj", "--out", "s.png", "--size", "16,8", "--photons", "10"], "", dir.path());
    let err = stderr(&o);
    assert!(err.contains("warning: --obj soup.obj: its triangles overlap so much that a ray through it tests about"), "{err}");
    // With what the light pass will cost, timed before it starts, and how to stop it.
    assert!(err.contains("so the light pass of 10 photons should take about") && err.contains("Ctrl-C stops it"), "{err}");
    assert_eq!(err.matches("overlap so much").count(), 1, "{err}");
    // A sweep of three runs of the soup says it once, before its first run.
    let e = "name = \"soup\"\nmode = \"prism\"\n[fixed]\nobj = \"soup.obj\"\nsize = [16, 8]\n[sweep]\nphotons = [10, 20, 30]\n";
    std::fs::write(dir.path().join("soup.toml"), e).unwrap();
    let o = run(&["sweep", "soup.toml", "--out", "swept"], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o).matches("overlap so much").count(), 1, "{}", stderr(&o));
    let sphere = repo("off/prism60.obj");
    let o = run(&["prism", "--obj", sphere.to_str().unwrap(), "--out", "c.png", "--size", "16,8", "--photons", "10"], "", dir.path());
    assert!(!stderr(&o).contains("overlap so much"), "{}", stderr(&o));
}
