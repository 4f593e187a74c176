//! The parameters of an interior run (report 004: `refract interior`, its
//! prompts, interior scene files and experiments): one row each. Defaults
//! come from `InteriorConfig::with_defaults`.

use super::{choices, never, pick, Kind, Param, Value, ValueError};
use crate::geometry::AccelKind;
use crate::interior::config::{InteriorConfig, SceneKind, SpecularOpacity};
use crate::interior::tone::Tone;
use crate::mesh::source::MeshSource;
use std::path::PathBuf;

fn mesh(s: &str) -> Result<(), ValueError> {
    MeshSource::parse(s)?;
    Ok(())
}

fn f32s(v: &Value) -> glam::Vec3 {
    glam::DVec3::from(v.triple()).as_vec3()
}

fn f64s(v: glam::Vec3) -> Value {
    Value::Triple(v.to_array().map(wide))
}

/// An `f32` field as the real its shortest text names (1.4, not the
/// 1.399999976158142 that `as f64` gives): help prints defaults as the
/// table writes them, and the value sets back to the same `f32`.
fn wide(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(x as f64)
}

fn real(x: f32) -> Value {
    Value::Real(wide(x))
}

/// Why opacity and its compositing change nothing at trace count 0: the
/// first hit is drawn opaque (`interior::trace`, the report's
/// `if (cc == max_ray_trace_count) tmp.a = 100`).
fn trace_zero(c: &InteriorConfig, what: &str) -> Option<String> {
    (c.max_trace == 0).then(|| format!("at trace count 0 the first hit is drawn opaque, so {what} changes nothing; it needs a trace count above 0"))
}

/// Why the critical-angle keys change nothing at index 1 or below.
fn no_critical_angle(c: &InteriorConfig) -> Option<String> {
    (c.ior <= 1.0).then(|| "below index 1 light from inside always gets out: there is no critical angle".to_string())
}

/// Why the Fresnel weight of the light leaving a face changes nothing: an
/// opaque object lets no light out through its faces, and at index 1 all
/// of it gets out (T = 1).
fn no_fresnel_exit(c: &InteriorConfig) -> Option<String> {
    if c.opacity >= 100.0 {
        Some("an opaque object (opacity 100) lets no light out through its faces".to_string())
    } else {
        (c.ior == 1.0).then(|| "at index 1 all the light gets out (Fresnel transmittance 1)".to_string())
    }
}

/// The report's prompts (asked in this order, after the trace count).
pub const PROMPTS: &str = "The report's prompts";
const PHONG: &str = "Extended Phong model";
const SCENE: &str = "Scene and image";
const RUN: &str = "Run";

/// Every parameter of an interior run.
pub static PARAMS: &[Param<InteriorConfig>] = &[
    Param {
        key: "trace",
        aliases: &[],
        section: PROMPTS,
        help: "Maximum ray trace count: refracted and reflected rays followed after the first hit",
        unit: "rays",
        kind: Kind::Count { min: 0, max: 1000 },
        auto: "",
        get: |c| Some(Value::Count(c.max_trace as u64)),
        set: |c, v| c.max_trace = v.count() as u32,
        ignored: never,
    },
    Param {
        key: "opacity",
        aliases: &[],
        section: PROMPTS,
        help: "Opacity of the object",
        unit: "percent",
        kind: Kind::closed(0.0, 100.0),
        auto: "",
        get: |c| Some(real(c.opacity)),
        set: |c, v| c.opacity = v.real() as f32,
        ignored: |c| trace_zero(c, "the opacity"),
    },
    Param {
        key: "object_colour",
        aliases: &["color"],
        section: PROMPTS,
        help: "Object colour (the report's \"RGB color of object\")",
        unit: "0-255",
        kind: Kind::Rgb,
        auto: "",
        get: |c| Some(Value::Rgb(c.color)),
        set: |c, v| c.color = v.rgb(),
        ignored: never,
    },
    Param {
        key: "off",
        aliases: &[],
        section: PROMPTS,
        help: "The OFF or COFF mesh to render (a Wavefront OBJ if the name ends in .obj), or a generated icosphere:S (S = 0-8 subdivisions) or torus:N",
        unit: "",
        kind: Kind::Text(mesh),
        auto: "",
        get: |c| Some(Value::Text(c.off.to_string())),
        set: |c, v| {
            if let Ok(m) = MeshSource::parse(v.text()) {
                c.off = m;
            }
        },
        ignored: never,
    },
    Param {
        key: "coff",
        aliases: &[],
        section: PROMPTS,
        help: "Use the colours stored in a COFF file (the report's \"colour OFF\" answer 1; an OBJ holds none: the object colour is used)",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.coff)),
        set: |c, v| c.coff = v.flag(),
        ignored: never,
    },
    Param {
        key: "scale",
        aliases: &[],
        section: PROMPTS,
        help: "Scale factor: the mesh is normalised to radius 1, then scaled",
        unit: "times",
        kind: Kind::above(0.0, 1e6),
        auto: "",
        get: |c| Some(real(c.scale)),
        set: |c, v| c.scale = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "rot",
        aliases: &[],
        section: PROMPTS,
        help: "Rotations about X, then Y, then Z",
        unit: "degrees",
        kind: Kind::Triple,
        auto: "",
        get: |c| Some(f64s(c.rot)),
        // A full turn or more is reduced (in f64) to within one turn: a huge
        // angle would overflow f32, or lose every digit of its fraction.
        set: |c, v| c.rot = glam::DVec3::from(v.triple().map(|a| if a.abs() >= 360.0 { a % 360.0 } else { a })).as_vec3(),
        ignored: never,
    },
    Param {
        key: "ior",
        aliases: &[],
        section: PROMPTS,
        help: "Refractive index of the object (below 1 acts like a mirror)",
        unit: "",
        kind: Kind::above(0.0, 100.0),
        auto: "",
        get: |c| Some(real(c.ior)),
        set: |c, v| c.ior = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "shininess",
        aliases: &[],
        section: PHONG,
        help: "Shininess n in cos^n(alpha)",
        unit: "",
        kind: Kind::closed(0.0, 1e4),
        auto: "",
        get: |c| Some(real(c.shininess)),
        set: |c, v| c.shininess = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "atten",
        aliases: &[],
        section: PHONG,
        help: "Distance attenuation constant c in 1/(1 + c d^2); 0 = none (the mesh has radius 1)",
        unit: "per unit^2",
        kind: Kind::closed(0.0, 1e6),
        auto: "1 around the mesh alone, 0.1 in the Cornell boxes (larger: their walls stand 1.6 to 2.5 from the light)",
        get: |c| c.atten.map(real),
        set: |c, v| c.atten = Some(v.real() as f32),
        ignored: never,
    },
    Param {
        key: "light_pos",
        aliases: &["light"],
        section: PHONG,
        help: "Light position",
        unit: "scene units",
        kind: Kind::Triple,
        auto: "the mesh's centre; (0,0,-2) in the Cornell box",
        get: |c| c.light.map(f64s),
        set: |c, v| c.light = Some(f32s(v)),
        ignored: never,
    },
    Param {
        key: "ka",
        aliases: &[],
        section: PHONG,
        help: "Ambient coefficient Ka",
        unit: "",
        kind: Kind::closed(0.0, 1000.0),
        auto: "",
        get: |c| Some(real(c.ka)),
        set: |c, v| c.ka = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "kd",
        aliases: &[],
        section: PHONG,
        help: "Diffuse coefficient Kd",
        unit: "",
        kind: Kind::closed(0.0, 1000.0),
        auto: "",
        get: |c| Some(real(c.kd)),
        set: |c, v| c.kd = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "wall_kd",
        aliases: &[],
        section: PHONG,
        help: "Diffuse coefficient Kd of the Cornell box's walls (their own material; the report gives the box none)",
        unit: "",
        kind: Kind::closed(0.0, 1000.0),
        auto: "kd, the mesh's",
        get: |c| c.wall_kd.map(real),
        set: |c, v| c.wall_kd = Some(v.real() as f32),
        ignored: |c| (c.scene == SceneKind::Mesh).then(|| "the mesh alone has no walls (--scene cornell or cornell-tiled)".to_string()),
    },
    Param {
        key: "ks",
        aliases: &[],
        section: PHONG,
        help: "Specular coefficient Ks",
        unit: "",
        kind: Kind::closed(0.0, 1000.0),
        auto: "",
        get: |c| Some(real(c.ks)),
        set: |c, v| c.ks = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "specular_opacity",
        aliases: &[],
        section: PHONG,
        help: "How specular light is composited when the trace count is above 0",
        unit: "",
        kind: Kind::Choice(choices::<SpecularOpacity>),
        auto: "",
        get: |c| Some(pick(c.specular_opacity)),
        set: |c, v| c.specular_opacity = v.choice(),
        ignored: |c| {
            trace_zero(c, "how specular light is composited")
                .or_else(|| (c.opacity >= 100.0).then(|| "an opaque object (--opacity 100) has no layers to composite".to_string()))
        },
    },
    Param {
        key: "size",
        aliases: &[],
        section: SCENE,
        help: "Image size",
        unit: "pixels",
        kind: Kind::Size { max: 16384 },
        auto: "",
        get: |c| Some(Value::Size([c.width, c.height])),
        set: |c, v| [c.width, c.height] = v.size(),
        ignored: never,
    },
    Param {
        key: "background",
        aliases: &[],
        section: SCENE,
        help: "Background colour, seen where rays leave the scene",
        unit: "0-255",
        kind: Kind::Rgb,
        auto: "",
        get: |c| Some(Value::Rgb(c.background)),
        set: |c, v| c.background = v.rgb(),
        ignored: never,
    },
    Param {
        key: "exposure",
        aliases: &[],
        section: SCENE,
        help: "Exposure: every pixel's colour is multiplied by this before the 8-bit image (a camera setting; 1 = the model's colour)",
        unit: "times",
        kind: Kind::above(0.0, 1e6),
        auto: "",
        get: |c| Some(real(c.exposure)),
        set: |c, v| c.exposure = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "tone",
        aliases: &[],
        section: SCENE,
        help: "How colours brighter than white are shown: clip (each channel at 1, the report) or shoulder (a film's roll toward white above 0.75)",
        unit: "",
        kind: Kind::Choice(choices::<Tone>),
        auto: "",
        get: |c| Some(pick(c.tone)),
        set: |c, v| c.tone = v.choice(),
        ignored: |c| {
            c.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("pfm")).then(|| "a .pfm output holds the model's colours, before any tone".to_string())
        },
    },
    Param {
        key: "scene",
        aliases: &[],
        section: SCENE,
        help: "Scene around the mesh",
        unit: "",
        kind: Kind::Choice(choices::<SceneKind>),
        auto: "",
        get: |c| Some(pick(c.scene)),
        set: |c, v| c.scene = v.choice(),
        ignored: never,
    },
    Param {
        key: "bulb",
        aliases: &[],
        section: SCENE,
        help: "Radius of the bulb: the point light drawn as a small glowing bead, seen through the faces in front of it where the glass refracts it (a drawn marker, not the report's model; 0 = not drawn)",
        unit: "scene units",
        kind: Kind::closed(0.0, 10.0),
        auto: "",
        get: |c| Some(real(c.bulb)),
        set: |c, v| c.bulb = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "tir_circle",
        aliases: &[],
        section: SCENE,
        help: "Draw on each face the circle where the light inside meets it at the critical angle asin(1/n), the edge of the circle of outcoming light (a drawn guide, not the report's model)",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.tir_circle)),
        set: |c, v| c.tir_circle = v.flag(),
        ignored: no_critical_angle,
    },
    Param {
        key: "diffuse_tir",
        aliases: &[],
        section: SCENE,
        help: "Count the diffuse light of the light behind a face only where that light gets out through it (inside the critical circle), as the specular is: a frosted face glows inside the circle of outcoming light (a choice, not the report's diffuse term)",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.diffuse_tir)),
        set: |c, v| c.diffuse_tir = v.flag(),
        ignored: no_critical_angle,
    },
    Param {
        key: "fresnel_exit",
        aliases: &[],
        section: SCENE,
        help: "Weight the light behind a face, diffuse and specular, by the Fresnel transmittance of its way out, which falls to 0 at the critical angle: the circle of outcoming light fades at its edge (a choice, not the report's terms)",
        unit: "",
        kind: Kind::Flag,
        auto: "",
        get: |c| Some(Value::Flag(c.fresnel_exit)),
        set: |c, v| c.fresnel_exit = v.flag(),
        ignored: no_fresnel_exit,
    },
    Param {
        key: "spp",
        aliases: &[],
        section: SCENE,
        help: "Samples per pixel: 1 = the pixel centre, as the report; more are jittered using --seed",
        unit: "samples",
        kind: Kind::Count { min: 1, max: 4096 },
        auto: "",
        get: |c| Some(Value::Count(c.spp as u64)),
        set: |c, v| c.spp = v.count() as u32,
        ignored: never,
    },
    Param {
        key: "offset",
        aliases: &[],
        section: SCENE,
        help: "Distance a followed ray starts off its surface",
        unit: "scene units",
        kind: Kind::closed(0.0, 1.0),
        auto: "",
        get: |c| Some(real(c.offset)),
        set: |c, v| c.offset = v.real() as f32,
        ignored: never,
    },
    Param {
        key: "accel",
        aliases: &[],
        section: RUN,
        help: "Intersection back-end (identical images)",
        unit: "",
        kind: Kind::Choice(choices::<AccelKind>),
        auto: "",
        get: |c| Some(pick(c.accel)),
        set: |c, v| c.accel = v.choice(),
        ignored: never,
    },
    Param {
        key: "seed",
        aliases: &[],
        section: RUN,
        help: "Seed of the sub-pixel jitter (used when --spp > 1)",
        unit: "",
        kind: Kind::Count { min: 0, max: i64::MAX as u64 },
        auto: "",
        get: |c| Some(Value::Count(c.seed)),
        set: |c, v| c.seed = v.count(),
        ignored: |c| (c.spp == 1).then(|| "one sample a pixel looks through its centre; --seed jitters only with --spp above 1".to_string()),
    },
    Param {
        key: "threads",
        aliases: &[],
        section: RUN,
        help: "Worker threads; 0 = all cores (the image is the same for any count)",
        unit: "threads",
        kind: Kind::Count { min: 0, max: 1024 },
        auto: "",
        get: |c| Some(Value::Count(c.threads as u64)),
        set: |c, v| c.threads = v.count() as usize,
        ignored: never,
    },
];

/// The defaults every interior run starts from (the command line, the
/// prompts, scene files and sweeps alike); the mesh is the shipped cube.
pub fn defaults() -> InteriorConfig {
    InteriorConfig::with_defaults(MeshSource::File(PathBuf::from("off/cube.off")), PathBuf::from("results/interior.png"))
}
