//! One vocabulary: glass names match whatever their case and separators
//! in every command, a miss names the nearest name, typo hints point at
//! today's spellings (the old ones work, with a note), `--set` and scene
//! keys name the nearest key and list them all, and every error is one
//! line, `refract: error: ...`, exit status 1.

use crate::common::*;

const INTERIOR_KEYS: &str = "trace, opacity, object_colour, off, coff, scale, rot, ior, shininess, atten, light_pos, ka, kd, wall_kd, ks, specular_opacity, size, background, exposure, tone, scene, bulb, tir_circle, diffuse_tir, fresnel_exit, spp, offset, accel, seed, threads";

#[test]
fn glass_names_match_alike_in_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tiny = ["prism", "--scene", "single-prism", "--size", "16,12", "--photons", "2000"];
    let mut images = Vec::new();
    for (i, name) in ["fused-silica", "FUSED SILICA", "Fused_Silica"].iter().enumerate() {
        let out = format!("g{i}.png");
        let mut args = tiny.to_vec();
        args.extend(["--glass", name, "--out", &out]);
        let o = run(&args, "", d);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        images.push(std::fs::read(d.join(&out)).unwrap());
        let o = run(&["glass", name], "", d);
        assert!(o.status.success(), "glass {name}: {}", stderr(&o));
        images.push(o.stdout);
    }
    assert!(images[0] == images[2] && images[2] == images[4] && images[1] == images[3] && images[3] == images[5]);
    let before = snapshot(d);
    let valid = "N-BK7, N-SK16, N-SF11, N-SF10, F2, SF5, N-F2, SF11, FUSED SILICA";
    assert_fails_with(&run(&["glass", "nbk8"], "", d), 1, &format!("refract: error: unknown glass `nbk8` (did you mean `N-BK7`?); valid: {valid}"));
    let mut args = tiny.to_vec();
    args.extend(["--glass", "nbk8", "--out", "x.png"]);
    assert_fails_with(
        &run(&args, "", d),
        1,
        &format!(
            "refract: error: invalid value 'nbk8' for '--glass <NAME>': `nbk8` is not one of {valid} (did you mean `N-BK7`?) (see `refract prism --help`)"
        ),
    );
    assert_eq!(snapshot(d), before);
}

#[test]
fn hints_point_at_todays_spellings_and_old_ones_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let before = snapshot(d);
    assert_fails_with(
        &run(&["interior", "--colour", "1,2,3"], "", d),
        1,
        "refract: error: unexpected argument '--colour' found; a similar argument exists: '--object-colour' (see `refract interior --help`)",
    );
    assert_fails_with(
        &run(&["prism", "--colour", "cie"], "", d),
        1,
        "refract: error: unexpected argument '--colour' found; a similar argument exists: '--colour-map' (see `refract prism --help`)",
    );
    assert_fails_with(&run(&["sweep", "plan", "x.toml", "--engine", "paralel"], "", d), 1, "refract: error: invalid value 'paralel' for '--engine <ENGINE>': `paralel` is not one of parallel, slurm (did you mean `parallel`?) (see `refract sweep plan --help`)");
    assert_eq!(snapshot(d), before);
    let cube = repo("off/cube.off");
    let o = run(&["interior", "--off", cube.to_str().unwrap(), "--color", "10,200,30", "--size", "8,8", "--out", "c.png"], "", d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o).lines().next(), Some("note: --color is the old spelling of --object-colour"));
}

#[test]
fn set_and_scene_keys_name_the_nearest_and_every_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lab = repo("scenes/lab-ior1.4.toml");
    let before = snapshot(d);
    assert_fails_with(
        &run(&["render", lab.to_str().unwrap(), "--set", "ofset=0.1", "--out", "x.png"], "", d),
        1,
        &format!("refract: error: --set `ofset`: unknown interior parameter (did you mean `offset`?); expected one of {INTERIOR_KEYS}"),
    );
    std::fs::write(d.join("k.toml"), "id = \"s\"\nmode = \"interior\"\n[params]\nofset = 0.1\n").unwrap();
    let before_k = snapshot(d);
    assert_fails_with(
        &run(&["render", "k.toml"], "", d),
        1,
        &format!("refract: error: k.toml:4: `ofset`: unknown interior parameter (did you mean `offset`?); expected one of {INTERIOR_KEYS}"),
    );
    assert_eq!(snapshot(d), before_k);
    assert!(before.is_empty());
}
