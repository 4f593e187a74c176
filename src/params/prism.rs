//! The parameters of a spectral run (`refract prism`, prism scene files and
//! experiments): one row each. Defaults come from `SpectralConfig::new`.

use super::{choices, never, pick, End, Kind, Param, Value, ValueError};
use crate::image_io::openexr::ExrSample;
use crate::optics::glass;
use crate::optics::ior::IorKind;
use crate::photon::gather::Filter;
use crate::photon::map::MapKind;
use crate::scenes::{SceneKind, SceneOptions, View};
use crate::spectral::options::EyeMode;
use crate::spectral::SpectralConfig;
use crate::spectrum::cie::GamutMap;
use crate::spectrum::colormap::ColorMap;
use crate::spectrum::spectra::NamedSpectrum;
use std::path::PathBuf;

fn glasses() -> Vec<(&'static str, &'static str)> {
    static ABOUT: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    let about =
        ABOUT.get_or_init(|| glass::catalogue().iter().map(|g| format!("n_d {:.5}, Abbe number {:.2}", g.sellmeier(glass::lines::LD), g.abbe())).collect());
    glass::catalogue().iter().zip(about).map(|(g, a)| (g.name.as_str(), a.as_str())).collect()
}

fn glass_of(v: &Value) -> &'static glass::Glass {
    let all = glass::catalogue();
    match v {
        Value::Choice(i, _) => all.get(*i).unwrap_or(&all[0]),
        _ => &all[0],
    }
}

fn inset_text(s: &str) -> Result<(), ValueError> {
    crate::spectral::inset::Inset::parse(s)?;
    Ok(())
}

fn light_name(s: &str) -> Result<(), ValueError> {
    NamedSpectrum::parse(s)?;
    Ok(())
}

fn glass_value(g: &glass::Glass) -> Value {
    let i = glass::catalogue().iter().position(|c| c.name == g.name).unwrap_or(0);
    Value::Choice(i, glass::catalogue()[i].name.as_str())
}

/// `ignored` rules: why a parameter set by the user would change nothing.
fn builtin_only(c: &SpectralConfig) -> Option<String> {
    c.scene.gltf_file().map(|g| format!("the scene is the glTF file {}: its own meshes, materials, camera and lights", g.path.display()))
}

fn gltf_only(c: &SpectralConfig) -> Option<String> {
    c.scene.gltf_file().is_none().then(|| "only a glTF scene (--gltf FILE, or `refract render FILE.glb`) uses it".to_string())
}

fn gltf_glass_used(c: &SpectralConfig) -> Option<String> {
    gltf_only(c).or_else(|| c.scene.no_prism.then(|| "--no-prism leaves no glass in the scene".to_string()))
}

fn gltf_of(c: &mut SpectralConfig) -> &mut crate::gltf::GltfOptions {
    c.scene.gltf.get_or_insert_with(|| crate::gltf::GltfOptions::new(PathBuf::new()))
}

fn added_light(s: &str) -> Result<(), ValueError> {
    crate::gltf::AddedLight::parse(s).map(|_| ()).map_err(ValueError::from)
}

fn amici_only(c: &SpectralConfig) -> Option<String> {
    if let Some(why) = builtin_only(c) {
        return Some(why);
    }
    let amici = matches!(c.scene.kind, SceneKind::AmiciScreen | SceneKind::AmiciLamp | SceneKind::AmiciBench);
    (!amici).then(|| format!("the {} scene has no Amici prism (amici-screen, amici-lamp and amici-bench have one)", c.scene.kind.name()))
}

fn has_faces(c: &SpectralConfig) -> Option<String> {
    if let Some(why) = builtin_only(c) {
        return Some(why);
    }
    let sphere = matches!(c.scene.kind, SceneKind::SphereArealight | SceneKind::SphereMetal | SceneKind::SpheresFinal);
    sphere.then(|| format!("the {} scene's glass is a sphere: it has no entry face to set an angle of incidence on", c.scene.kind.name()))
}

fn bench_only(c: &SpectralConfig) -> Option<String> {
    if let Some(why) = builtin_only(c) {
        return Some(why);
    }
    let fits = match c.scene.kind {
        SceneKind::AmiciBench => c.scene.view != View::Wall,
        SceneKind::CornellLaser => matches!(c.scene.view, View::Scene | View::Wall),
        _ => false,
    };
    (!fits).then(|| {
        format!(
            "the {} scene has no {} view (amici-bench has scene, screen and overview; cornell-laser scene and wall)",
            c.scene.kind.name(),
            c.scene.view.name()
        )
    })
}

fn has_glass(c: &SpectralConfig) -> Option<String> {
    c.scene.no_prism.then(|| "--no-prism leaves no glass in the scene".to_string())
}

fn builtin_glass(c: &SpectralConfig) -> Option<String> {
    builtin_only(c).or_else(|| has_glass(c))
}

fn photons_used(c: &SpectralConfig) -> Option<String> {
    c.exact.then(|| "--exact computes the image without photons or eye samples".to_string())
}

fn seed_used(c: &SpectralConfig) -> Option<String> {
    c.exact.then(|| "--exact draws nothing at random: it is the same image whatever the seed".to_string())
}

/// The scenes with no matte surface, so no photon map: the camera sees the
/// lights through the glass directly (checked against the built scenes in
/// a test below).
fn no_matte_surface(kind: SceneKind) -> bool {
    matches!(kind, SceneKind::AmiciLamp | SceneKind::SphereArealight | SceneKind::SphereMetal)
}

fn light_pass_used(c: &SpectralConfig) -> Option<String> {
    photons_used(c).or_else(|| {
        no_matte_surface(c.scene.kind)
            .then(|| format!("the {} scene has no matte surface to store photons on: the camera sees its lights through the glass", c.scene.kind.name()))
    })
}

fn exact_only(c: &SpectralConfig) -> Option<String> {
    (!c.exact).then(|| "only --exact uses it".to_string())
}

fn film_kernel_used(c: &SpectralConfig) -> Option<String> {
    light_pass_used(c).or_else(|| match (c.map, c.passes) {
        (MapKind::Film, 0 | 1) => None,
        (MapKind::Film, _) => Some("under --passes the film has no kernel (the passes' shrinking radius does its work)".to_string()),
        (m, _) => Some(format!("only --map film has a kernel; --map {} gathers with --radius and --filter", m.name())),
    })
}

fn split_used(c: &SpectralConfig) -> Option<String> {
    photons_used(c).or_else(|| (c.eye == EyeMode::Hero).then(|| "--eye hero takes one wavelength; only --eye split and --eye lines split a ray".to_string()))
}

fn exr_used(c: &SpectralConfig) -> Option<String> {
    let exr = c.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    (!exr).then(|| format!("only an .exr output has samples to choose, and {} is not one", c.out.display()))
}

fn gain_used(c: &SpectralConfig) -> Option<String> {
    c.exposure.map(|_| "--exposure sets the exposure; the gain multiplies only the automatic one".to_string())
}

const SCENE: &str = "Scene";
const LIGHT: &str = "Light pass (photon map)";
const EYE: &str = "Eye pass";
const DISPLAY: &str = "Display";
const RUN: &str = "Run";

/// Every parameter of a spectral run.
pub static PARAMS: &[Param<SpectralConfig>] = &[
    Param {
        key: "scene",
        aliases: &[],
        section: SCENE,
        help: "Scene to build (reports 000, 001 and 003, and the single-prism anchor)",
        unit: "",
        kind: Kind::Choice(choices::<SceneKind>),
        auto: "",
        get: |c| Some(pick(c.scene.kind)),
        set: |c, v| c.scene.kind = v.choice(),
        ignored: builtin_only,
    },
    Param {
        key: "glass",
        aliases: &[],
        section: SCENE,
        help: "Crown glass: the Amici prism's crowns, the single prism, the spheres, the Cornell prism (`refract glass --list`)",
        unit: "",
        kind: Kind::Choice(glasses),
        auto: "",
        get: |c| Some(glass_value(c.scene.crown)),
        set: |c, v| c.scene.crown = glass_of(v),
        ignored: builtin_only,
    },
    Param {
        key: "flint",
        aliases: &[],
        section: SCENE,
        help: "Flint glass of the Amici prism",
        unit: "",
        kind: Kind::Choice(glasses),
        auto: "",
        get: |c| Some(glass_value(c.scene.flint)),
        set: |c, v| c.scene.flint = glass_of(v),
        ignored: amici_only,
    },
    Param {
        key: "flint_apex",
        aliases: &[],
        section: SCENE,
        help: "Flint apex angle of the Amici prism (the crown apex is then solved for no deviation at the d line)",
        unit: "degrees",
        kind: Kind::Real { lo: End::Open(0.0), hi: End::Open(180.0) },
        auto: "",
        get: |c| Some(Value::Real(c.scene.flint_apex_deg)),
        set: |c, v| c.scene.flint_apex_deg = v.real(),
        ignored: amici_only,
    },
    Param {
        key: "ior_model",
        aliases: &[],
        section: SCENE,
        help: "Index-of-refraction model of the glasses",
        unit: "",
        kind: Kind::Choice(choices::<IorKind>),
        auto: "",
        get: |c| Some(pick(c.scene.ior)),
        set: |c, v| c.scene.ior = v.choice(),
        ignored: builtin_glass,
    },
    Param {
        key: "light_spectrum",
        aliases: &["light"],
        section: SCENE,
        help: "Light spectrum: d65, e, fl1..fl12, fl3.1..fl3.15, cfl-lines, blackbody:K, laser:NM",
        unit: "",
        kind: Kind::Text(light_name),
        auto: "the scene's own (d65 beams, cfl-lines lamp, black bodies for report 001)",
        get: |c| c.scene.light.as_ref().map(|l| Value::Text(l.name.clone())),
        set: |c, v| c.scene.light = NamedSpectrum::parse(v.text()).ok(),
        ignored: never,
    },
    Param {
        key: "incidence",
        aliases: &[],
        section: SCENE,
        help: "Angle of incidence on the first face",
        unit: "degrees",
        kind: Kind::Real { lo: End::Open(-90.0), hi: End::Open(90.0) },
        auto: "the design: along the Amici's axis; minimum deviation at d for the other prisms",
        get: |c| c.scene.incidence_deg.map(Value::Real),
        set: |c, v| c.scene.incidence_deg = Some(v.real()),
        ignored: has_faces,
    },
    Param {
        key: "haze",
        aliases: &[],
        section: SCENE,
        help: "Scattering coefficient of a thin haze in the air, which shows the beams' paths (single scattering, isotropic)",
        unit: "per metre",
        kind: Kind::Real { lo: End::Closed(0.0), hi: End::Closed(10.0) },
        auto: "the scene's: clear air, except the laser's Cornell box (cornell-laser)",
        get: |c| c.scene.haze.map(Value::Real),
        set: |c, v| c.scene.haze = Some(v.real()),
        ignored: never,
    },
    Param {
        key: "view",
        aliases: &[],
        section: SCENE,
        help: "Where the camera stands in amici-bench (scene, screen, overview) and cornell-laser (scene, wall: the band of spectrum close up)",
        unit: "",
        kind: Kind::Choice(choices::<View>),
        auto: "",
        get: |c| Some(pick(c.scene.view)),
        set: |c, v| c.scene.view = v.choice(),
        ignored: bench_only,
    },
    Param {
        key: "indirect_gather",
        aliases: &[],
        section: SCENE,
        help: "Where the scene computes direct light by shadow rays (report 003's rooms), light that reached a surface by a diffuse bounce or by mirrors alone is kept in a second photon map and gathered over this many times the radius (under --map film, in every scene, all light but the caustics is); light through glass keeps the radius. 1: one map for all",
        unit: "times the radius",
        kind: Kind::Real { lo: End::Closed(1.0), hi: End::Closed(100.0) },
        auto: "the scene's: 8 in report 003's Cornell boxes, else 1",
        get: |c| c.scene.indirect_gather.map(Value::Real),
        set: |c, v| c.scene.indirect_gather = Some(v.real()),
        ignored: never,
    },
    Param {
        key: "no_prism",
        aliases: &[],
        section: SCENE,
        help: "Leave the prism out (report 000's \"image before dispersion\")",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.scene.no_prism)),
        set: |c, v| c.scene.no_prism = v.flag(),
        ignored: never,
    },
    Param {
        key: "no_dispersion",
        aliases: &[],
        section: SCENE,
        help: "Hold the index at n_d for every wavelength (\"image with no dispersion effect\")",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.scene.no_dispersion)),
        set: |c, v| c.scene.no_dispersion = v.flag(),
        ignored: has_glass,
    },
    Param {
        key: "obj",
        aliases: &[],
        section: SCENE,
        help: "A Wavefront OBJ mesh (in metres) of --glass that replaces the prism; its winding is made consistent and outward",
        unit: "",
        kind: Kind::Path,
        auto: "none: the scene's own prism",
        get: |c| c.scene.obj.clone().map(Value::Path),
        set: |c, v| c.scene.obj = Some(v.path()),
        ignored: builtin_glass,
    },
    Param {
        key: "gltf",
        aliases: &[],
        section: SCENE,
        help: "A glTF 2.0 scene (.gltf or .glb) in place of the built-in ones: its meshes, camera, lights and materials (README: glTF scenes)",
        unit: "",
        kind: Kind::Path,
        auto: "none: the built-in --scene",
        get: |c| c.scene.gltf.as_ref().map(|g| Value::Path(g.path.clone())),
        set: |c, v| gltf_of(c).path = v.path(),
        ignored: never,
    },
    Param {
        key: "camera",
        aliases: &[],
        section: SCENE,
        help: "The glTF file's camera (or its node) by name",
        unit: "",
        kind: Kind::Text(|_| Ok(())),
        auto: "the first camera in the file's scene, else a view of the whole scene",
        get: |c| c.scene.gltf.as_ref().and_then(|g| g.camera.clone()).map(Value::Text),
        set: |c, v| gltf_of(c).camera = Some(v.text().to_string()),
        ignored: gltf_only,
    },
    Param {
        key: "beam_width",
        aliases: &[],
        section: SCENE,
        help: "Width of the collimated beam a glTF directional light becomes, where its extras give none",
        unit: "metres",
        kind: Kind::above(0.0, 1e6),
        auto: "the whole scene's width",
        get: |c| c.scene.gltf.as_ref().and_then(|g| g.beam_width).map(Value::Real),
        set: |c, v| gltf_of(c).beam_width = Some(v.real()),
        ignored: gltf_only,
    },
    Param {
        key: "gltf_glass",
        aliases: &[],
        section: SCENE,
        help: "Index model of the glTF file's transmissive materials",
        unit: "",
        kind: Kind::Choice(choices::<crate::gltf::GlassChoice>),
        auto: "",
        get: |c| Some(pick(c.scene.gltf.as_ref().map_or(crate::gltf::GlassChoice::File, |g| g.glass))),
        set: |c, v| gltf_of(c).glass = v.choice(),
        ignored: gltf_glass_used,
    },
    Param {
        key: "gltf_light",
        aliases: &[],
        section: SCENE,
        help: "A light added to the glTF file's: sun:X,Y,Z (a white beam travelling along X,Y,Z in the file's axes, over the whole scene or --beam-width wide) or point:X,Y,Z (a point light there)",
        unit: "",
        kind: Kind::Text(added_light),
        auto: "none: the file's own lights",
        get: |c| c.scene.gltf.as_ref().and_then(|g| g.add_light).map(|l| Value::Text(l.text())),
        set: |c, v| gltf_of(c).add_light = crate::gltf::AddedLight::parse(v.text()).ok(),
        ignored: gltf_only,
    },
    Param {
        key: "size",
        aliases: &[],
        section: SCENE,
        help: "Image size",
        unit: "pixels",
        kind: Kind::Size { max: 16384 },
        auto: "",
        get: |c| Some(Value::Size([c.scene.width, c.scene.height])),
        set: |c, v| [c.scene.width, c.scene.height] = v.size(),
        ignored: never,
    },
    Param {
        key: "photons",
        aliases: &[],
        section: LIGHT,
        help: "Photons traced in the light pass",
        unit: "photons",
        kind: Kind::Count { min: 1, max: 2_000_000_000 },
        auto: "",
        get: |c| Some(Value::Count(c.photons)),
        set: |c, v| c.photons = v.count(),
        ignored: light_pass_used,
    },
    Param {
        key: "passes",
        aliases: &[],
        section: LIGHT,
        help: "Progressive photon mapping: this many passes of --photons and --spp each, the gather radius shrinking pass by pass from --radius (by default one pixel's footprint; Knaus and Zwicker); 1 is the report's single pass",
        unit: "passes",
        kind: Kind::Count { min: 1, max: 1_000_000 },
        auto: "",
        get: |c| Some(Value::Count(c.passes as u64)),
        set: |c, v| c.passes = v.count() as u32,
        ignored: photons_used,
    },
    Param {
        key: "exact",
        aliases: &[],
        section: LIGHT,
        help: "The exact image instead of photon mapping, for scenes where one collimated beam crosses only planar faces onto one matte screen (single-prism, amici-screen): deterministic, no photons",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.exact)),
        set: |c, v| c.exact = v.flag(),
        ignored: never,
    },
    Param {
        key: "exact_wavelengths",
        aliases: &[],
        section: LIGHT,
        help: "With --exact: wavelengths summed, at the midpoints of equal steps of the light's cumulative spectrum",
        unit: "wavelengths",
        kind: Kind::Count { min: 16, max: 1_000_000 },
        auto: "",
        get: |c| Some(Value::Count(c.exact_wavelengths as u64)),
        set: |c, v| c.exact_wavelengths = v.count() as usize,
        ignored: exact_only,
    },
    Param {
        key: "exact_subsamples",
        aliases: &[],
        section: LIGHT,
        help: "With --exact: subsamples per pixel side where a footprint's edge crosses a pixel",
        unit: "per side",
        kind: Kind::Count { min: 1, max: 64 },
        auto: "",
        get: |c| Some(Value::Count(c.exact_subsamples as u64)),
        set: |c, v| c.exact_subsamples = v.count() as usize,
        ignored: exact_only,
    },
    Param {
        key: "map",
        aliases: &[],
        section: LIGHT,
        help: "Photon map",
        unit: "",
        kind: Kind::Choice(choices::<MapKind>),
        auto: "",
        get: |c| Some(pick(c.map)),
        set: |c, v| c.map = v.choice(),
        ignored: light_pass_used,
    },
    Param {
        key: "filter",
        aliases: &[],
        section: LIGHT,
        help: "Density-estimation filter",
        unit: "",
        kind: Kind::Choice(choices::<Filter>),
        auto: "",
        get: |c| Some(pick(c.filter)),
        set: |c, v| c.filter = v.choice(),
        ignored: light_pass_used,
    },
    Param {
        key: "radius",
        aliases: &[],
        section: LIGHT,
        help: "Gather radius (from a nanometre: a smaller disc's area underflows)",
        unit: "metres",
        kind: Kind::Real { lo: End::Closed(1e-9), hi: End::Closed(1e3) },
        auto: "two pixels' footprint on the screen",
        get: |c| c.radius.map(Value::Real),
        set: |c, v| c.radius = Some(v.real()),
        ignored: light_pass_used,
    },
    Param {
        key: "k",
        aliases: &[],
        section: LIGHT,
        help: "Gather the k nearest photons instead of a fixed radius (kd-tree only; the k-th sets the radius, the k - 1 inside it are counted)",
        unit: "photons",
        kind: Kind::Count { min: 1, max: 1_000_000 },
        auto: "none: all photons within --radius",
        get: |c| c.k.map(|k| Value::Count(k as u64)),
        set: |c, v| c.k = Some(v.count() as usize),
        ignored: light_pass_used,
    },
    Param {
        key: "film_kernel",
        aliases: &[],
        section: LIGHT,
        help: "Under --map film: the caustics' kernel on the film, a tent of this radius (0: none, the unbiased film); under --passes, 0",
        unit: "pixels",
        kind: Kind::Real { lo: End::Closed(0.0), hi: End::Closed(16.0) },
        auto: "chosen from the film's two halves of the photons (hold-out; docs/physics.md §20)",
        get: |c| c.film_kernel.map(Value::Real),
        set: |c, v| c.film_kernel = Some(v.real()),
        ignored: film_kernel_used,
    },
    Param {
        key: "spp",
        aliases: &[],
        section: EYE,
        help: "Samples per pixel of the eye pass",
        unit: "samples",
        kind: Kind::Count { min: 1, max: 65536 },
        auto: "",
        get: |c| Some(Value::Count(c.spp as u64)),
        set: |c, v| c.spp = v.count() as u32,
        ignored: photons_used,
    },
    Param {
        key: "eye",
        aliases: &[],
        section: EYE,
        help: "Eye rays at a dispersive face",
        unit: "",
        kind: Kind::Choice(choices::<EyeMode>),
        auto: "",
        get: |c| Some(pick(c.eye)),
        set: |c, v| c.eye = v.choice(),
        ignored: photons_used,
    },
    Param {
        key: "split",
        aliases: &[],
        section: EYE,
        help: "Monochromatic rays a split makes with --eye split, and for the continuum with --eye lines",
        unit: "rays",
        kind: Kind::Count { min: 1, max: 1024 },
        auto: "",
        get: |c| Some(Value::Count(c.split as u64)),
        set: |c, v| c.split = v.count() as u32,
        ignored: split_used,
    },
    Param {
        key: "exposure",
        aliases: &[],
        section: DISPLAY,
        help: "Exposure: multiplies linear sRGB before display",
        unit: "per W/m^2",
        kind: Kind::above(0.0, 1e20),
        auto: "automatic, the 99.5th percentile at full scale",
        get: |c| c.exposure.map(Value::Real),
        set: |c, v| c.exposure = Some(v.real()),
        ignored: never,
    },
    Param {
        key: "exposure_gain",
        aliases: &[],
        section: DISPLAY,
        help: "Multiplies the automatic exposure (over-expose like a photograph: dim lines show, bright ones saturate)",
        unit: "times",
        kind: Kind::above(0.0, 1e6),
        auto: "",
        get: |c| Some(Value::Real(c.exposure_gain)),
        set: |c, v| c.exposure_gain = v.real(),
        ignored: gain_used,
    },
    Param {
        key: "gamut",
        aliases: &[],
        section: DISPLAY,
        help: "Colours outside the sRGB gamut",
        unit: "",
        kind: Kind::Choice(choices::<GamutMap>),
        auto: "",
        get: |c| Some(pick(c.gamut)),
        set: |c, v| c.gamut = v.choice(),
        ignored: never,
    },
    Param {
        key: "exr",
        aliases: &[],
        section: DISPLAY,
        help: "Sample type of an .exr output: 32-bit float (exact) or 16-bit half",
        unit: "",
        kind: Kind::Choice(choices::<ExrSample>),
        auto: "",
        get: |c| Some(pick(c.exr)),
        set: |c, v| c.exr = v.choice(),
        ignored: exr_used,
    },
    Param {
        key: "inset",
        aliases: &[],
        section: DISPLAY,
        help: "A magnified detail drawn into the PNG: x,y,w,h (the region, fractions of the frame), zoom, corner (tl, tr, bl, br)",
        unit: "",
        kind: Kind::Text(inset_text),
        auto: "none",
        get: |c| c.inset.map(|i| Value::Text(format!("{},{},{},{},{},{}", i.x, i.y, i.w, i.h, i.zoom, ["tl", "tr", "bl", "br"][i.corner as usize]))),
        set: |c, v| c.inset = crate::spectral::inset::Inset::parse(v.text()).ok(),
        ignored: never,
    },
    Param {
        key: "colour_map",
        aliases: &["colours"],
        section: DISPLAY,
        help: "Wavelength to colour: CIE (physical) or one of reports 001/003's maps",
        unit: "",
        kind: Kind::Choice(choices::<ColorMap>),
        auto: "",
        get: |c| Some(pick(c.colours)),
        set: |c, v| c.colours = v.choice(),
        ignored: never,
    },
    Param {
        key: "seed",
        aliases: &[],
        section: RUN,
        help: "Seed of every random choice (same seed, same image, any thread count)",
        unit: "",
        kind: Kind::Count { min: 0, max: i64::MAX as u64 },
        auto: "",
        get: |c| Some(Value::Count(c.seed)),
        set: |c, v| c.seed = v.count(),
        ignored: seed_used,
    },
    Param {
        key: "threads",
        aliases: &[],
        section: RUN,
        help: "Worker threads; 0 = all cores",
        unit: "threads",
        kind: Kind::Count { min: 0, max: 1024 },
        auto: "",
        get: |c| Some(Value::Count(c.threads as u64)),
        set: |c, v| c.threads = v.count() as usize,
        ignored: never,
    },
];

/// The defaults every spectral run starts from (the command line, scene
/// files and sweeps alike).
pub fn defaults() -> SpectralConfig {
    SpectralConfig::new(SceneOptions::new(SceneKind::AmiciScreen), PathBuf::new())
}

/// The keys that shape the prism and the rays through it (all `refract
/// prism trace` takes): not the image's size, the light, the haze or the
/// gather.
pub fn is_scene(p: &Param<SpectralConfig>) -> bool {
    p.section == SCENE && !["size", "light_spectrum", "haze", "indirect_gather", "view"].contains(&p.key)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::names::Named;

    /// A built scene's faces, lights and camera, as text (or the builder's
    /// refusal, which shows it read the option too).
    fn world(o: &SceneOptions) -> Result<String, crate::scenes::SceneError> {
        let w = crate::scenes::build(o)?;
        Ok(format!("{:?} {:?} {:?}", w.faces, w.lights, w.camera))
    }

    /// The rules that refuse a scene flag agree with the scene builders: a
    /// flag called ignored leaves every face, light and the camera as they
    /// were, and a flag called used changes something.
    #[test]
    fn scene_flags_are_refused_exactly_where_the_scene_ignores_them() {
        let row = |key: &str| PARAMS.iter().find(|p| p.key == key).unwrap();
        for &(kind, name, _) in SceneKind::VALUES {
            let mut c = defaults();
            c.scene.kind = kind;
            let base = world(&c.scene).unwrap();
            type Change = fn(&mut SceneOptions);
            let changes: [(&str, Change); 3] = [
                ("flint", |o| o.flint = crate::optics::glass::by_name("F2").unwrap()),
                ("flint_apex", |o| o.flint_apex_deg = 80.0),
                ("incidence", |o| o.incidence_deg = Some(o.incidence_deg.unwrap_or(0.0) + 1.0)),
            ];
            for (key, change) in changes {
                let mut o = c.scene.clone();
                change(&mut o);
                let changed = world(&o).ok() != Some(base.clone());
                let refused = (row(key).ignored)(&c);
                assert_eq!(changed, refused.is_none(), "{name}: --{key} changes the scene: {changed}; refused: {refused:?}");
            }
        }
    }

    /// The scenes said to have no matte surface are those built without one.
    #[test]
    fn light_pass_flags_are_refused_where_nothing_stores_photons() {
        for &(kind, name, _) in SceneKind::VALUES {
            let w = crate::scenes::build(&SceneOptions::new(kind)).unwrap();
            assert_eq!(no_matte_surface(kind), w.maps.is_empty(), "{name}");
        }
    }

    #[test]
    fn exact_and_photon_flags_exclude_each_other() {
        let row = |key: &str| PARAMS.iter().find(|p| p.key == key).unwrap();
        let mut c = defaults();
        assert!((row("exact_wavelengths").ignored)(&c).is_some() && (row("photons").ignored)(&c).is_none());
        c.exact = true;
        assert!((row("exact_wavelengths").ignored)(&c).is_none());
        for key in ["photons", "passes", "map", "filter", "radius", "k", "film_kernel", "spp", "eye", "split", "seed"] {
            assert!((row(key).ignored)(&c).is_some(), "--{key} under --exact");
        }
    }
}
