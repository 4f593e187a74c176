//! glTF 2.0 in and out: a built-in scene exported and read back renders
//! as the scene itself; a file's glass keeps its n_d and Abbe number; a
//! directional light lands where the probe says; what refract does not
//! model is named in one warning; a bad file is one error line.

use crate::common::*;
use refract::gltf::{read, write, GltfOptions};
use refract::scenes::{build, SceneKind, SceneOptions};
use refract::spectral::SpectralConfig;
use refract::world::{Medium, Surface, World};
use std::path::Path;

fn config(size: [usize; 2], photons: u64, spp: u32, seed: u64) -> SpectralConfig {
    let mut o = SceneOptions::new(SceneKind::SinglePrism);
    [o.width, o.height] = size;
    let mut c = SpectralConfig::new(o, Default::default());
    (c.photons, c.spp, c.seed, c.threads) = (photons, spp, seed, 2);
    c
}

fn render(w: &World, c: &SpectralConfig) -> Vec<glam::DVec3> {
    refract::spectral::render_world(c, w, &refract::progress::Silent).unwrap().render.image.xyz
}

/// Mean absolute difference of luminance over the mean luminance.
fn differ(a: &[glam::DVec3], b: &[glam::DVec3]) -> f64 {
    let mean = a.iter().map(|v| v.y).sum::<f64>() / a.len() as f64;
    assert!(mean > 0.0, "black image");
    a.iter().zip(b).map(|(x, y)| (x.y - y.y).abs()).sum::<f64>() / a.len() as f64 / mean
}

fn read_back(w: &World, path: &Path, size: [usize; 2]) -> World {
    write::write(w, path).unwrap();
    read::load(&GltfOptions::new(path.to_path_buf()), size[0], size[1]).unwrap().world
}

/// Export, import, render: the same image as the built-in scene's at the
/// same seed, within the noise (the difference between two seeds of the
/// built-in scene), for a prism, the cemented Amici prism on its bench,
/// a Cornell box and report 001's sphere.
#[test]
fn an_exported_scene_renders_as_the_built_in_one() {
    let dir = tempfile::tempdir().unwrap();
    let size = [160, 90];
    for (kind, ext) in
        [(SceneKind::SinglePrism, "glb"), (SceneKind::AmiciBench, "gltf"), (SceneKind::CornellPointlight, "glb"), (SceneKind::SpheresFinal, "glb")]
    {
        let mut o = SceneOptions::new(kind);
        [o.width, o.height] = size;
        let built = build(&o).unwrap();
        let back = read_back(&built, &dir.path().join(format!("{}.{ext}", kind.name())), size);
        let count = |w: &World| {
            (
                w.faces.iter().filter(|f| matches!(f.surface, Surface::Interface { .. })).count(),
                w.faces.iter().filter(|f| matches!(f.surface, Surface::Interface { front, .. } if front != 0)).count(),
                w.maps.len(),
                w.spheres.len(),
                w.lights.len(),
                w.media.len(),
            )
        };
        assert_eq!(count(&back), count(&built), "{kind:?}: glass faces, cemented faces, matte faces, spheres, lights, media");
        let c = config(size, 200_000, 2, 1);
        let (a, b) = (render(&built, &c), render(&back, &c));
        let noise = differ(&a, &render(&built, &config(size, 200_000, 2, 2)));
        let d = differ(&a, &b);
        // (The file's faces take the general light pass, not the built-in
        // prism cells' shortcut: another draw of the same photons.)
        assert!(d < 1.5 * noise, "{kind:?}: read back differs by {d:.4} of the mean; two seeds by {noise:.4}");
        let mean = |x: &[glam::DVec3]| x.iter().map(|v| v.y).sum::<f64>() / x.len() as f64;
        assert!((mean(&a) / mean(&b) - 1.0).abs() < 0.03, "{kind:?}: mean luminance {} against {}", mean(&b), mean(&a));
    }
}

/// Every built-in scene exports to a file the `gltf` crate validates and
/// reads back with its glass, cemented and matte faces, spheres, lights,
/// glasses and the photon mapper's settings.
#[test]
fn every_built_in_scene_exports_and_reads_back() {
    use refract::names::Named;
    let dir = tempfile::tempdir().unwrap();
    for &(kind, name, _) in SceneKind::VALUES {
        let built = build(&SceneOptions::new(kind)).unwrap();
        let back = read_back(&built, &dir.path().join(format!("{name}.glb")), [640, 240]);
        let faces = |w: &World, f: fn(&Surface) -> bool| w.faces.iter().filter(|x| f(&x.surface)).count();
        for (what, f) in [
            ("glass", (|s: &Surface| matches!(s, Surface::Interface { .. })) as fn(&Surface) -> bool),
            ("cemented", |s: &Surface| matches!(s, Surface::Interface { front, .. } if *front != 0)),
            ("matte", |s: &Surface| matches!(s, Surface::Diffuse { .. })),
            ("mirror", |s: &Surface| matches!(s, Surface::Mirror { .. })),
            ("emitting", |s: &Surface| matches!(s, Surface::Emitter { .. })),
        ] {
            assert_eq!(faces(&back, f), faces(&built, f), "{name}: {what} faces");
        }
        assert_eq!((back.spheres.len(), back.lights.len(), back.media.len()), (built.spheres.len(), built.lights.len(), built.media.len()), "{name}");
        assert_eq!(
            (back.bounces, back.direct_lighting, back.indirect_gather, back.haze, &back.haze_skip, &back.photon_shares),
            (built.bounces, built.direct_lighting, built.indirect_gather, built.haze, &built.haze_skip, &built.photon_shares),
            "{name}: settings"
        );
        for (a, b) in built.lights.iter().zip(&back.lights) {
            assert!((a.power - b.power).abs() <= 1e-9 * a.power, "{name}: {} power {} against {}", a.name, b.power, a.power);
        }
        assert!((back.camera.pos - built.camera.pos).length() < 1e-5 && back.camera.forward.dot(built.camera.forward) > 1.0 - 1e-9, "{name}: camera");
    }
}

/// A glTF glass of n_d 1.519 and V_d 64.0 (dispersion 20/64) is read as a
/// glass with those numbers to 1e-4 (the KHR Cauchy model); with
/// `nearest`, as the catalogue's N-BK7 (n_d 1.5168, V_d 64.17); and a glass
/// refract wrote keeps its catalogue glass and model.
#[test]
fn a_files_glass_keeps_its_n_d_and_abbe_number() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("glass.gltf");
    std::fs::write(&file, minimal(r#"{"name": "flint", "pbrMetallicRoughness": {"roughnessFactor": 0}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.519}, "KHR_materials_dispersion": {"dispersion": 0.3125}}}"#, "", "")).unwrap();
    let mut o = GltfOptions::new(file.clone());
    o.add_light = Some(refract::gltf::AddedLight::Sun(glam::DVec3::NEG_Y));
    let w = read::load(&o, 64, 48).unwrap().world;
    let Medium::Glass { ior, .. } = &w.media[1] else { panic!("no glass") };
    let (n_d, abbe) = refract::gltf::glass::nd_abbe(ior);
    assert!((n_d - 1.519).abs() < 1e-4 && (abbe.unwrap() - 64.0).abs() < 1e-4, "n_d {n_d}, V_d {abbe:?}");
    o.glass = refract::gltf::GlassChoice::Nearest;
    let w = read::load(&o, 64, 48).unwrap().world;
    let Medium::Glass { name, ior } = &w.media[1] else { panic!("no glass") };
    assert_eq!(name, "N-BK7");
    assert!(matches!(ior, refract::optics::ior::IorModel::Sellmeier(_)));
    // refract's own: N-SF11 by Sellmeier comes back as N-SF11 by Sellmeier.
    let mut s = SceneOptions::new(SceneKind::SinglePrism);
    s.crown = refract::optics::glass::by_name("N-SF11").unwrap();
    let back = read_back(&build(&s).unwrap(), &dir.path().join("sf11.glb"), [64, 48]);
    let Medium::Glass { name, ior } = &back.media[1] else { panic!("no glass") };
    assert_eq!((name.as_str(), ior), ("N-SF11", &refract::optics::ior::IorModel::Sellmeier(s.crown.clone())));
}

/// The example's sunbeam (a directional light, its width in the extras)
/// through the prism: the spectrum on the table is centred, in the image,
/// where the probe's d-line ray meets the table (the luminance centroid
/// of the photons' light within 3 % of the image's width).
#[test]
fn a_directional_light_lands_where_the_probe_says() {
    let path = repo("scenes/gltf/prism-table.glb");
    let size = [240, 180];
    let mut w = read::load(&GltfOptions::new(path), size[0], size[1]).unwrap().world;
    assert!(matches!(w.lights[0].emission, refract::world::Emission::Beam { .. }), "the sunbeam is a beam");
    let d = refract::world::probe::probe(&w, refract::optics::glass::lines::LD);
    assert!(!d.tir && d.exit_dir.z < 0.0, "the d line leaves the prism downward");
    let land = d.exit_point + d.exit_dir * (d.exit_point.z / -d.exit_dir.z);
    let want = w.camera.project(land).expect("the landing point is in front of the camera");
    // The beam alone (the lamp would light the whole table).
    w.lights.truncate(1);
    w.photon_shares = None;
    let r = refract::spectral::render_world(&config(size, 300_000, 1, 1), &w, &refract::progress::Silent).unwrap();
    let img = &r.render.image;
    let (mut sum, mut total) = (glam::DVec2::ZERO, 0.0);
    for y in 0..img.height {
        for x in 0..img.width {
            let v = img.xyz[y * img.width + x].y;
            sum += v * glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            total += v;
        }
    }
    let got = sum / total;
    assert!((got - want).length() < 0.03 * size[0] as f64, "the light's centroid is at {got}, the probe's landing point at {want}");
    // A light added on the command line joins the file's, with a share of the photons.
    let mut o = GltfOptions::new(repo("scenes/gltf/prism-table.glb"));
    o.add_light = Some(refract::gltf::AddedLight::parse("point:0,1,0").unwrap());
    let w = read::load(&o, 64, 48).unwrap().world;
    assert_eq!((w.lights.len(), w.photon_shares.as_ref().map(Vec::len)), (3, Some(3)));
    // An added sun is --beam-width wide, else as wide as the scene.
    o.add_light = Some(refract::gltf::AddedLight::parse("sun:0,-1,0").unwrap());
    let half = |o: &GltfOptions| match read::load(o, 64, 48).unwrap().world.lights[2].emission {
        refract::world::Emission::Beam { half, .. } => half.x,
        _ => panic!("the sun is a beam"),
    };
    assert!(half(&o) > 0.3, "over the whole table: {}", half(&o));
    o.beam_width = Some(0.05);
    assert_eq!(half(&o), 0.025);
}

/// A minimal glTF: one triangle (a floor, or a glass given its material),
/// with `material`, extra top-level keys `more` and a node's extras.
fn minimal(material: &str, more: &str, node_more: &str) -> String {
    use base64::Engine;
    let pos: [f32; 9] = [-1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0, -1.0];
    let bytes: Vec<u8> = pos.iter().flat_map(|p| p.to_le_bytes()).collect();
    let data = base64::engine::general_purpose::STANDARD.encode(&bytes);
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"mesh": 0{node_more}}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
        "materials": [{material}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{data}"}}]{more}}}"#
    )
}

/// A file with a texture, an animation, rough glass and a spot light
/// renders, and says so in one warning line that lists each.
#[test]
fn what_refract_does_not_model_is_listed_in_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("feature.gltf");
    let material = r#"{"name": "rough", "pbrMetallicRoughness": {"roughnessFactor": 0.3, "baseColorTexture": {"index": 0}}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}}"#;
    let more = r#", "textures": [{"source": 0}], "images": [{"uri": "missing.png"}],
        "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}], "samplers": [{"input": 1, "output": 2}]}],
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_sheen"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 100, "spot": {}}]}}"#;
    // Two accessors put first for the animation: the positions again (0,
    // which POSITION reads) and a time (1).
    let text = minimal(material, more, r#", "children": [1]}, {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}"#)
        .replace(r#""accessors": [{"#, r#""accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}, {"bufferView": 0, "componentType": 5126, "count": 1, "type": "SCALAR", "min": [-1], "max": [-1]}, {"#)
        // The animation reads a time (1) and the positions as keys (0).
        .replace(r#""input": 1, "output": 2"#, r#""input": 1, "output": 0"#);
    std::fs::write(&file, text).unwrap();
    let o = run(
        &[
            "render",
            file.to_str().unwrap(),
            "--set",
            "photons=2000",
            "--set",
            "spp=1",
            "--set",
            "size=32,24",
            "--out",
            dir.path().join("f.png").to_str().unwrap(),
        ],
        "",
        dir.path(),
    );
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 1, "one warning line: {err}");
    for what in ["textures", "roughness above 0", "animations", "spot lights", "KHR_materials_sheen", "feature.gltf"] {
        assert!(warnings[0].contains(what), "the warning names {what}: {}", warnings[0]);
    }
    // A file refract wrote holds nothing it leaves out.
    let clean = read::load(&GltfOptions::new(repo("scenes/gltf/sphere-box.glb")), 32, 24).unwrap();
    assert!(clean.unmodelled.is_empty(), "{:?}", clean.unmodelled);
}

/// Bad files: one line naming the file, non-zero, nothing written.
#[test]
fn a_bad_file_is_one_error_line_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("text.gltf", b"not json at all".to_vec(), "not valid glTF 2.0"),
        ("short.glb", b"glTF\x02\x00\x00\x00\xff\x00\x00\x00".to_vec(), "not valid glTF 2.0"),
        (
            "index.gltf",
            minimal(r#"{"name": "m"}"#, "", "").replace(r#""POSITION": 0}"#, r#""POSITION": 0}, "indices": 0"#).into_bytes(),
            "are not unsigned integers",
        ),
        ("dark.gltf", minimal(r#"{"name": "m"}"#, "", "").into_bytes(), "has no light"),
        ("buffer.gltf", minimal(r#"{"name": "m"}"#, "", "").replace(r#""byteLength": 36, "uri""#, r#""byteLength": 72, "uri""#).into_bytes(), "holds 36 bytes"),
    ];
    for (name, bytes, why) in cases {
        let file = dir.path().join(name);
        std::fs::write(&file, bytes).unwrap();
        let o = run(&["render", file.to_str().unwrap(), "--out", out.to_str().unwrap()], "", dir.path());
        assert_clean_failure(&o, name);
        assert!(stderr(&o).contains(why), "{name}: {}", stderr(&o));
        assert!(!out.exists(), "{name}: nothing is written");
    }
    let o = run(&["render", dir.path().join("absent.glb").to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "absent.glb: cannot read");
    let o = run(&["export", "no-such-scene", "--out", out.with_extension("glb").to_str().unwrap()], "", dir.path());
    assert_clean_failure(&o, "`no-such-scene` is not a scene");
}

/// The shipped examples are the writer's own output, byte for byte.
#[test]
fn the_examples_are_the_writers_own() {
    for (name, _) in refract::scenes::examples::EXAMPLES {
        let path = repo(&format!("scenes/gltf/{name}.glb"));
        let w = refract::scenes::examples::by_name(name, 640, 480).unwrap();
        let bytes = write::to_bytes(&w, &path).unwrap();
        assert!(std::fs::read(&path).unwrap() == bytes, "{} differs from `refract export {name}`: write it again", path.display());
    }
}

/// The Khronos sample `DispersionTest` (KhronosGroup/glTF-Sample-Assets,
/// Models/DispersionTest, written for KHR_materials_dispersion; not
/// shipped: set REFRACT_GLTF_SAMPLES to a checkout of that repository).
/// It has no light: a sun is added, falling from the viewer's side onto
/// the 25 prisms and the backdrop behind them. Its dispersion shows: the
/// image holds at least 1.5 times the chroma of the same render with every
/// index held at n_d.
#[test]
fn the_khronos_dispersion_test_shows_its_dispersion() {
    let Some(root) = std::env::var_os("REFRACT_GLTF_SAMPLES") else {
        eprintln!("skipped: REFRACT_GLTF_SAMPLES (a glTF-Sample-Assets checkout) is not set");
        return;
    };
    let path = Path::new(&root).join("Models/DispersionTest/glTF/DispersionTest.gltf");
    if !path.is_file() {
        eprintln!("skipped: {} is absent", path.display());
        return;
    }
    let chroma = |no_dispersion: bool| {
        let mut o = SceneOptions::new(SceneKind::SinglePrism);
        [o.width, o.height] = [240, 180];
        let mut g = GltfOptions::new(path.clone());
        g.add_light = Some(refract::gltf::AddedLight::parse("sun:0,-0.3,-1").unwrap());
        o.gltf = Some(g);
        o.no_dispersion = no_dispersion;
        let w = build(&o).unwrap();
        assert!(w.media.len() > 20, "the 25 prisms' glasses");
        let mut c = config([240, 180], 1_000_000, 2, 1);
        c.scene = o;
        render(&w, &c)
            .iter()
            .map(|v| {
                let rgb = refract::spectrum::cie::Xyz(*v).to_linear_srgb().0;
                rgb.max_element() - rgb.min_element()
            })
            .sum::<f64>()
    };
    let (with, without) = (chroma(false), chroma(true));
    assert!(with > 1.5 * without, "chroma with dispersion {with:.3e}, without {without:.3e}");
}
