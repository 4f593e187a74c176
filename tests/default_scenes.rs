//! Every shipped scene kind, at its defaults (tiny sizes; prism scenes at
//! --quick, which keeps the exposure), gives a visible image: neither black
//! nor white. The rooms fill the frame, so there half the pixels must show
//! the walls (the Cornell box at the old attenuation c = 1 had a median of
//! 31 of 255 and failed).

use crate::common::*;

/// Grey levels of a PNG, sorted.
fn greys(path: &std::path::Path) -> Vec<u8> {
    let mut g = image::open(path).unwrap().to_luma8().into_raw();
    g.sort_unstable();
    g
}

fn check(what: &str, args: &[&str], room: bool) {
    let dir = tempfile::tempdir().unwrap();
    let mut full = args.to_vec();
    full.extend(["--out", "x.png"]);
    let o = run(&full, "", dir.path());
    assert!(o.status.success(), "{what}: {}", stderr(&o));
    let g = greys(&dir.path().join("x.png"));
    let n = g.len();
    let (median, bright) = (g[n / 2], g[n * 995 / 1000]);
    assert!(bright >= 64, "{what}: black (the brightest 0.5 % at {bright} of 255)");
    assert!(median < 250, "{what}: white (median {median})");
    if room {
        // The mirror tube's narrow mouth sends its light forward, so the
        // walls beside and behind it are lit by bounces alone, and the
        // automatic exposure is set by the tube's bright beam (median 39 at
        // its defaults, with the lamp filling the tube's end): 34 there.
        let least = if what == "cornell-mirror-tube" { 34 } else { 48 };
        assert!(median >= least, "{what}: the room is nearly black (median {median} of 255)");
    }
}

#[test]
fn interior_scene_kinds_are_visible_at_their_defaults() {
    let cube = repo("off/cube.off");
    for (scene, room) in [("mesh", false), ("cornell", true), ("cornell-tiled", true)] {
        check(scene, &["interior", "--off", cube.to_str().unwrap(), "--scene", scene, "--size", "48,48"], room);
    }
}

#[test]
fn prism_scene_kinds_are_visible_at_their_defaults() {
    let rooms = ["cornell-pointlight", "cornell-mirror-tube", "cornell-laser"];
    for scene in [
        "amici-screen",
        "amici-bench",
        "single-prism",
        "sphere-arealight",
        "sphere-metal",
        "spheres-final",
        "cornell-pointlight",
        "cornell-mirror-tube",
        "cornell-laser",
        "dark-side",
    ] {
        check(scene, &["prism", "--scene", scene, "--quick", "--size", "64,48"], rooms.contains(&scene));
    }
    // The lamp has no photons to cut; one sample a pixel (--quick) misses
    // its thin lines, so it keeps its samples, at a size where each copy of
    // the lamp (0.057 degrees) is a dozen pixels wide and its copies light
    // 0.75 % of the frame (0.23 % at 320 x 80, under the 0.5 % the check reads).
    check("amici-lamp", &["prism", "--scene", "amici-lamp", "--size", "960,100"], false);
}
