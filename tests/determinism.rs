use crate::common::*;

#[test]
fn same_seed_same_bytes_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let torus = repo("off/torus.off");
    let t = torus.to_str().unwrap();
    let mut images = Vec::new();
    for (threads, seed) in [("1", "7"), ("2", "7"), ("5", "7"), ("2", "8")] {
        let out = format!("t{threads}s{seed}.ppm");
        let o = run(
            &["interior", "--off", t, "--out", &out, "--size", "64,48", "--trace", "4", "--spp", "4", "--seed", seed, "--threads", threads, "--rot", "60,10,0"],
            "",
            dir.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        images.push(ppm(&dir.path().join(out)));
    }
    assert_eq!(images[0], images[1]);
    assert_eq!(images[0], images[2]);
    assert_ne!(images[0], images[3], "a different seed jitters differently");
}

#[test]
fn timing_csv_gets_one_flushed_row_per_run() {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    for accel in ["bvh", "linear"] {
        let o =
            run(&["interior", "--off", cube.to_str().unwrap(), "--out", "x.png", "--size", "20,10", "--accel", accel, "--timing-csv", "t.csv"], "", dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let text = std::fs::read_to_string(dir.path().join("t.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "mode,mesh,triangles,width,height,trace,ior,shininess,accel,threads,load_s,build_s,render_s,rays,rays_per_s");
    assert_eq!(lines.len(), 3, "{text}");
    for (line, accel) in lines[1..].iter().zip(["bvh", "linear"]) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!((f[0], f[2], f[3], f[4], f[8]), ("interior", "12", "20", "10", accel));
        assert_eq!(f[13], "200", "one primary ray per pixel at trace 0");
        for v in &f[10..] {
            let x: f64 = v.parse().unwrap();
            assert!(x.is_finite() && x >= 0.0);
        }
    }
    // A CSV with other columns is refused rather than mixed.
    std::fs::write(dir.path().join("other.csv"), "a,b\n1,2\n").unwrap();
    let o = run(&["interior", "--off", cube.to_str().unwrap(), "--out", "y.png", "--size", "4,4", "--timing-csv", "other.csv"], "", dir.path());
    assert_clean_failure(&o, "are not this mode's");
    assert!(!dir.path().join("y.png").exists(), "checked before rendering: no image");
}

/// The prism mode too, for every photon map: the buffer map sums photons
/// straight into its texels as they land (fixed-point, so the order they
/// arrive in does not matter), the film into its pixels the same way, and
/// the kd-tree keeps them in chunk order.
/// A Cornell box (bounces, several lights) and the anchor scene.
#[test]
fn prism_renders_are_the_same_on_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    for scene in ["cornell-pointlight", "single-prism"] {
        for map in ["buffer", "kdtree", "film"] {
            let mut images = Vec::new();
            for threads in ["1", "2", "5"] {
                let out = dir.path().join(format!("{scene}-{map}-{threads}.pfm"));
                let o = run(
                    &[
                        "prism",
                        "--scene",
                        scene,
                        "--map",
                        map,
                        "--photons",
                        "60000",
                        "--size",
                        "48,32",
                        "--spp",
                        "2",
                        "--threads",
                        threads,
                        "--out",
                        out.to_str().unwrap(),
                    ],
                    "",
                    dir.path(),
                );
                assert!(o.status.success(), "{}", stderr(&o));
                images.push(std::fs::read(&out).unwrap());
            }
            assert!(images[0] == images[1] && images[0] == images[2], "{scene} {map}");
            assert!(images[0].len() > 48 * 32 * 12);
        }
    }
}
