//! Paths inside scene and experiment files are resolved from the file's
//! own folder (then the folders above it), not from where refract runs.

use crate::common::*;
use std::path::Path;

#[test]
fn a_shipped_scene_renders_from_another_folder() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("scenes/lab-ior1.4.toml");
    let o = run(&["render", scene.to_str().unwrap(), "--set", "size=24,24", "--out", "x.png"], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("x.png").is_file());
}

#[test]
fn a_users_scene_finds_its_mesh_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let mine = dir.path().join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::copy(repo("off/cube.off"), mine.join("box.off")).unwrap();
    let scene = "id = \"mine\"\nmode = \"interior\"\n[params]\noff = \"box.off\"\nsize = [16, 16]\n";
    std::fs::write(mine.join("s.toml"), scene).unwrap();
    let o = run(&["render", "mine/s.toml", "--out", "x.png"], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("x.png").is_file());

    // A mesh that is nowhere: the path and the folder, before any work.
    std::fs::write(mine.join("bad.toml"), scene.replace("box.off", "nope.off")).unwrap();
    let before = snapshot(dir.path());
    let o = run(&["render", "mine/bad.toml", "--out", "y.png"], "", dir.path());
    assert_fails_with(
        &o,
        1,
        "refract: error: mine/bad.toml:4: `off`: nope.off: no such file in mine or any folder above it (paths in a file are from its own folder)",
    );
    assert_eq!(snapshot(dir.path()), before, "no file changed");
}

#[test]
fn an_experiment_finds_its_mesh_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let exp = dir.path().join("exp");
    std::fs::create_dir(&exp).unwrap();
    std::fs::copy(repo("off/cube.off"), exp.join("box.off")).unwrap();
    let text = "name = \"e\"\nmode = \"interior\"\n[fixed]\noff = \"box.off\"\nsize = [8, 8]\n[sweep]\nior = [1.2, 1.5]\n";
    std::fs::write(exp.join("e.toml"), text).unwrap();
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    let o = run(&["sweep", "../exp/e.toml", "--out", "out"], "", &elsewhere);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(elsewhere.join("out/runs.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(csv.contains("../exp/box.off"), "the mesh as found from the folder refract runs in: {csv}");
    assert!(!Path::new(&elsewhere.join("box.off")).exists());
}
