//! A world as a glTF 2.0 file (`refract export`): faces as triangle
//! meshes, one per glass (a cemented face in both glasses' meshes, so each
//! is a closed solid), per matte colour, per mirror and per area light;
//! analytic spheres as meshes with their radius in the node's extras; the
//! camera; beams as directional lights and point lights as point lights
//! (`KHR_lights_punctual`); glasses with `KHR_materials_transmission`,
//! `_ior` (n_d), `_volume` and `_dispersion` (20 / V_d), so a viewer that
//! renders dispersion shows it. What glTF cannot say goes in
//! `extras.refract` (see `gltf` for the units).

use super::{to_gltf, GltfError, LUMENS_PER_WATT};
use crate::optics::ior::IorModel;
use crate::spectrum::Spectrum;
use crate::world::{Emission, Medium, Surface, World};
use glam::{DMat3, DQuat, DVec3};
use serde_json::{json, Value as Json};
use std::path::Path;

/// A spectrum as `read::spectrum_of` reads it back.
pub(crate) fn spectrum_json(s: &Spectrum) -> Json {
    match s {
        Spectrum::Constant(v) => json!({"kind": "constant", "value": v}),
        Spectrum::Tabulated { start, step, values } => json!({"kind": "table", "start": start, "step": step, "values": values.as_slice()}),
        Spectrum::Blackbody { kelvin } => json!({"kind": "blackbody", "kelvin": kelvin}),
        Spectrum::Lines { lines, fwhm } => json!({"kind": "lines", "lines": lines.iter().map(|(c, p)| json!([c, p])).collect::<Vec<_>>(), "fwhm": fwhm}),
        Spectrum::Rgb { fit, scale, illuminant } => json!({"kind": "rgb", "fit": fit.c, "scale": scale, "illuminant": illuminant}),
        Spectrum::Sum(parts) => json!({"kind": "sum", "parts": parts.iter().map(spectrum_json).collect::<Vec<_>>()}),
    }
}

/// A glass's index model as `read::own_model` reads it back.
fn model_json(name: &str, m: &IorModel) -> Json {
    match m {
        IorModel::Constant(n) => json!({"name": name, "model": "constant", "n": n}),
        IorModel::Cauchy { a, b_um2 } => json!({"name": name, "model": "cauchy", "a": a, "b_um2": b_um2}),
        IorModel::Sellmeier(g) => json!({"name": name, "model": "sellmeier", "glass": g.name}),
        IorModel::Fraunhofer { n_d, slope_per_nm } => json!({"name": name, "model": "fraunhofer", "n_d": n_d, "slope_per_nm": slope_per_nm}),
        IorModel::Musgrave { n_d, k } => json!({"name": name, "model": "musgrave", "n_d": n_d, "k": k}),
    }
}

/// A light's colour for a viewer: its spectrum's linear sRGB, largest
/// channel 1.
fn colour(s: &Spectrum) -> [f64; 3] {
    let rgb = s.to_xyz().to_linear_srgb().0.max(DVec3::ZERO);
    let m = rgb.max_element();
    if m > 0.0 && m.is_finite() {
        (rgb / m).to_array()
    } else {
        [1.0; 3]
    }
}

fn luma(c: [f64; 3]) -> f64 {
    DVec3::from(c).dot(crate::spectrum::cie::SRGB_LUMA).max(1e-9)
}

/// The document under construction: JSON arrays and the binary buffer.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<Json>,
    accessors: Vec<Json>,
    meshes: Vec<Json>,
    materials: Vec<Json>,
    nodes: Vec<Json>,
    lights: Vec<Json>,
}

impl Doc {
    /// A mesh of triangles (refract's axes) with material `material`; returns its index.
    fn mesh(&mut self, name: &str, tris: &[[DVec3; 3]], material: usize, extras: Option<Json>) -> usize {
        let first = self.bin.len();
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for t in tris {
            for v in t {
                let p = to_gltf(*v).as_vec3().to_array();
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                    self.bin.extend_from_slice(&p[k].to_le_bytes());
                }
            }
        }
        self.views.push(json!({"buffer": 0, "byteOffset": first, "byteLength": self.bin.len() - first, "target": 34962}));
        self.accessors.push(json!({"bufferView": self.views.len() - 1, "componentType": 5126, "count": tris.len() * 3, "type": "VEC3", "min": lo, "max": hi}));
        let mut mesh = json!({"name": name, "primitives": [{"attributes": {"POSITION": self.accessors.len() - 1}, "material": material, "mode": 4}]});
        if let Some(e) = extras {
            mesh["extras"] = e;
        }
        self.meshes.push(mesh);
        self.meshes.len() - 1
    }
}

/// Triangles of a convex face, fanned from its first vertex; a
/// parallelogram's two as `read::parallelogram` finds its corner and edges
/// again: (c, c + eu, c + ev) and (c + eu, c + eu + ev, c + ev).
fn face_triangles(f: &crate::world::Face) -> Vec<[DVec3; 3]> {
    if let (Some((c, eu, ev)), 4) = (f.frame, f.verts.len()) {
        return vec![[c, c + eu, c + ev], [c + eu, c + eu + ev, c + ev]];
    }
    (1..f.verts.len() - 1).map(|i| [f.verts[0], f.verts[i], f.verts[i + 1]]).collect()
}

/// A UV sphere of `radius` about the origin (refract's axes).
fn sphere_triangles(radius: f64) -> Vec<[DVec3; 3]> {
    let (rings, segs) = (24, 48);
    let p = |i: usize, j: usize| {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        let ph = 2.0 * std::f64::consts::PI * j as f64 / segs as f64;
        DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()) * radius
    };
    let mut t = Vec::new();
    for i in 0..rings {
        for j in 0..segs {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            if i > 0 {
                t.push([a, b, d]);
            }
            if i + 1 < rings {
                t.push([b, c, d]);
            }
        }
    }
    t
}

/// The node rotation whose x, y and -z axes are `x`, `y` and `back`'s
/// opposite (glTF's axes), as [x, y, z, w].
fn rotation(x: DVec3, y: DVec3) -> [f64; 4] {
    let (x, y) = (x.normalize(), y.normalize());
    let q = DQuat::from_mat3(&DMat3::from_cols(x, y, x.cross(y))).normalize();
    q.to_array()
}

fn vec(v: DVec3) -> [f64; 3] {
    v.to_array()
}

/// The world as a glTF document: its JSON and binary buffer.
/// The steps of `document`, each adding one kind of object.
impl Doc {
    /// Glasses: one material and one mesh each.
    fn add_glasses(&mut self, w: &World) {
        for (m, medium) in w.media.iter().enumerate() {
            let Medium::Glass { name, ior } = medium else { continue };
            let mut tris = Vec::new();
            for f in &w.faces {
                if let Surface::Interface { front, back } = f.surface {
                    if back == m {
                        tris.extend(face_triangles(f));
                    } else if front == m {
                        tris.extend(face_triangles(f).into_iter().map(|[a, b, c]| [a, c, b]));
                    }
                }
            }
            let (n_d, abbe) = super::glass::nd_abbe(ior);
            let mut ext = json!({
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": n_d},
            });
            // Thickness: a viewer's hint for refraction through a volume.
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            for v in tris.iter().flatten() {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            for s in w.spheres.iter().filter(|s| s.surface == Surface::Interface { front: 0, back: m }) {
                lo = lo.min(s.centre - s.radius);
                hi = hi.max(s.centre + s.radius);
            }
            let thick = (hi - lo).min_element();
            ext["KHR_materials_volume"] = json!({"thicknessFactor": if thick.is_finite() { thick } else { 0.05 }});
            if let Some(v) = abbe {
                ext["KHR_materials_dispersion"] = json!({"dispersion": 20.0 / v});
            }
            self.materials.push(json!({
                "name": name,
                "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.0},
                "extensions": ext,
                "extras": {"refract": {"glass": model_json(name, ior)}},
            }));
            let mat = self.materials.len() - 1;
            if !tris.is_empty() {
                let mesh = self.mesh(name, &tris, mat, None);
                self.nodes.push(json!({"name": name, "mesh": mesh}));
            }
            for s in w.spheres.iter().filter(|s| s.surface == Surface::Interface { front: 0, back: m }) {
                let mesh = self.mesh(&s.name, &sphere_triangles(s.radius), mat, None);
                self.nodes.push(
                    json!({"name": s.name, "mesh": mesh, "translation": vec(to_gltf(s.centre)), "extras": {"refract": {"sphere": {"radius": s.radius}}}}),
                );
            }
        }
    }

    /// Matte surfaces by colour, mirrors by reflectance, each in one mesh.
    fn add_surfaces(&mut self, w: &World) {
        let mut groups: Vec<(String, Json, Vec<[DVec3; 3]>)> = Vec::new();
        for f in &w.faces {
            let (key, mat) = match &f.surface {
                Surface::Diffuse { albedo, .. } => {
                    let c = albedo.rgb;
                    (
                        format!("matte {:?}", c),
                        json!({"name": format!("matte {:.3} {:.3} {:.3}", c[0], c[1], c[2]), "pbrMetallicRoughness": {"baseColorFactor": [c[0], c[1], c[2], 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}),
                    )
                }
                Surface::Mirror { reflectance } => (
                    format!("mirror {reflectance}"),
                    json!({"name": format!("mirror {reflectance:.3}"), "pbrMetallicRoughness": {"baseColorFactor": [reflectance, reflectance, reflectance, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.0}}),
                ),
                _ => continue,
            };
            match groups.iter_mut().find(|g| g.0 == key) {
                Some(g) => g.2.extend(face_triangles(f)),
                None => groups.push((key, mat, face_triangles(f))),
            }
        }
        for (_, mat, tris) in groups {
            let name = mat["name"].as_str().unwrap_or("surface").to_string();
            self.materials.push(mat);
            let mesh = self.mesh(&name, &tris, self.materials.len() - 1, None);
            self.nodes.push(json!({"name": name, "mesh": mesh}));
        }
    }

    /// Lights: punctual lights (their nodes returned, to follow the meshes'
    /// nodes) and emissive meshes for area and sphere lights.
    fn add_lights(&mut self, w: &World) -> Vec<Json> {
        let mut nodes = Vec::new();
        for (i, l) in w.lights.iter().enumerate() {
            let c = colour(&l.spectrum);
            let mut extras = json!({"refract": {"light": i, "spectrum": spectrum_json(&l.spectrum), "power": l.power}});
            match &l.emission {
                Emission::Beam { centre, dir, u, v, half, disc, polarisation } => {
                    // Local x, y across the beam and -z along it, right-handed.
                    let (gu, gv, gd) = (to_gltf(*u), to_gltf(*v), to_gltf(*dir));
                    let (x, _, hx, hy) = if gu.cross(gv).dot(-gd) > 0.0 { (gu, gv, half.x, half.y) } else { (gv, gu, half.y, half.x) };
                    let y = (-gd).cross(x).normalize();
                    let area = if *disc { std::f64::consts::PI * hx * hy } else { 4.0 * hx * hy };
                    let pol = polarisation.map(|p| match p {
                        crate::world::interface::Polarisation::S => "s",
                        crate::world::interface::Polarisation::P => "p",
                    });
                    extras["refract"]["beam"] = json!({"half": [hx, hy], "disc": disc, "polarisation": pol});
                    self.lights.push(
                        json!({"name": l.name, "type": "directional", "color": c, "intensity": l.power / area * LUMENS_PER_WATT / luma(c), "extras": extras}),
                    );
                    nodes.push(json!({"name": l.name, "translation": vec(to_gltf(*centre)), "rotation": rotation(x, y), "extensions": {"KHR_lights_punctual": {"light": self.lights.len() - 1}}}));
                }
                Emission::Point { pos } => {
                    self.lights.push(json!({"name": l.name, "type": "point", "color": c, "intensity": l.power * LUMENS_PER_WATT / (4.0 * std::f64::consts::PI) / luma(c), "extras": extras}));
                    nodes.push(
                        json!({"name": l.name, "translation": vec(to_gltf(*pos)), "extensions": {"KHR_lights_punctual": {"light": self.lights.len() - 1}}}),
                    );
                }
                Emission::Area { face } => {
                    let f = &w.faces[*face];
                    let nits = l.power / (std::f64::consts::PI * f.area()) * LUMENS_PER_WATT / luma(c);
                    self.materials.push(json!({"name": l.name, "emissiveFactor": c, "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": nits}}, "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0}, "extras": extras}));
                    let mesh = self.mesh(&l.name, &face_triangles(f), self.materials.len() - 1, None);
                    self.nodes.push(json!({"name": l.name, "mesh": mesh}));
                }
                Emission::Sphere { sphere } => {
                    let s = &w.spheres[*sphere];
                    let nits = l.power / (std::f64::consts::PI * 4.0 * std::f64::consts::PI * s.radius * s.radius) * LUMENS_PER_WATT / luma(c);
                    self.materials.push(json!({"name": l.name, "emissiveFactor": c, "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": nits}}, "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0}, "extras": extras}));
                    let mesh = self.mesh(&s.name, &sphere_triangles(s.radius), self.materials.len() - 1, None);
                    self.nodes.push(
                        json!({"name": s.name, "mesh": mesh, "translation": vec(to_gltf(s.centre)), "extras": {"refract": {"sphere": {"radius": s.radius}}}}),
                    );
                }
            }
        }
        nodes
    }
}

pub fn document(w: &World) -> (Json, Vec<u8>) {
    let mut d = Doc::default();
    d.add_glasses(w);
    d.add_surfaces(w);
    let light_nodes = d.add_lights(w);
    d.nodes.extend(light_nodes);
    // The camera: local x right, y up, looking down -z.
    let cam = &w.camera;
    let right = to_gltf(cam.forward.cross(cam.up));
    d.nodes.push(json!({"name": "camera", "camera": 0, "translation": vec(to_gltf(cam.pos)), "rotation": rotation(right, to_gltf(cam.up))}));
    let probe = json!({"origin": vec(w.probe.0), "dir": vec(w.probe.1)});
    let settings = json!({
        "bounces": w.bounces,
        "direct_lighting": w.direct_lighting,
        "indirect_gather": w.indirect_gather,
        "haze": w.haze,
        "haze_skip": w.haze_skip,
        "photon_shares": w.photon_shares,
        "probe": probe,
    });
    let mut used = vec!["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_dispersion"];
    if d.materials.iter().any(|m| m["extensions"].get("KHR_materials_emissive_strength").is_some()) {
        used.push("KHR_materials_emissive_strength");
    }
    let mut root = json!({
        "asset": {"version": "2.0", "generator": format!("refract {} (export)", env!("CARGO_PKG_VERSION"))},
        "extensionsUsed": used,
        "scene": 0,
        "scenes": [{"name": w.name, "nodes": (0..d.nodes.len()).collect::<Vec<_>>(), "extras": {"refract": settings}}],
        "nodes": d.nodes,
        "meshes": d.meshes,
        "materials": d.materials,
        "accessors": d.accessors,
        "bufferViews": d.views,
        "buffers": [{"byteLength": d.bin.len()}],
        "cameras": [{"type": "perspective", "name": "camera", "perspective": {"yfov": cam.vfov, "aspectRatio": cam.width as f64 / cam.height as f64, "znear": 0.01}}],
    });
    if !d.lights.is_empty() {
        root["extensionsUsed"].as_array_mut().expect("an array").push(json!("KHR_lights_punctual"));
        root["extensions"] = json!({"KHR_lights_punctual": {"lights": d.lights}});
    }
    (root, d.bin)
}

/// The world as a file: `.glb` (binary) or `.gltf` (JSON with the buffer
/// inline as a data URI), written through a temporary file.
pub fn write(w: &World, path: &Path) -> Result<(), GltfError> {
    let err = |why: String| GltfError::Write { path: path.display().to_string(), why };
    let bytes = to_bytes(w, path).map_err(|e| err(e.to_string()))?;
    crate::image_io::atomic_write(path, |f| std::io::Write::write_all(f, &bytes)).map_err(|e| err(e.to_string()))
}

/// Why a world could not be encoded as glTF (the caller names the file).
#[derive(Debug, thiserror::Error)]
pub enum EncodeError {
    #[error("the name must end in .glb or .gltf")]
    Extension,
    #[error("the scene is over 4 GB, more than GLB holds")]
    TooLarge,
    #[error("{0}")]
    Json(#[from] serde_json::Error),
}

/// The file's bytes, by `path`'s extension.
pub fn to_bytes(w: &World, path: &Path) -> Result<Vec<u8>, EncodeError> {
    let (mut root, bin) = document(w);
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("glb") => {
            let json = serde_json::to_vec(&root)?;
            glb(&json, &bin)
        }
        Some("gltf") => {
            use base64::Engine;
            root["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin)));
            Ok(serde_json::to_vec_pretty(&root)?)
        }
        _ => Err(EncodeError::Extension),
    }
}

/// The GLB container: header, JSON chunk (padded with spaces), binary
/// chunk (padded with zeros), each chunk 4-byte aligned.
fn glb(json: &[u8], bin: &[u8]) -> Result<Vec<u8>, EncodeError> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let (jl, bl) = (json.len() + pad(json.len()), bin.len() + pad(bin.len()));
    let total = 12 + 8 + jl + if bin.is_empty() { 0 } else { 8 + bl };
    let total = u32::try_from(total).map_err(|_| EncodeError::TooLarge)?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(jl as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    if !bin.is_empty() {
        out.extend_from_slice(&(bl as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out.extend(std::iter::repeat_n(0u8, pad(bin.len())));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::{build, SceneKind, SceneOptions};

    /// The GLB container and the JSON file are valid glTF to the `gltf`
    /// crate's own validation, with the same document in both.
    #[test]
    fn both_forms_are_valid_gltf() {
        let w = build(&SceneOptions::new(SceneKind::AmiciBench)).unwrap();
        let glb = to_bytes(&w, Path::new("x.glb")).unwrap();
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize, glb.len());
        assert_eq!(glb.len() % 4, 0);
        let a = gltf::Gltf::from_slice(&glb).unwrap();
        let b = gltf::Gltf::from_slice(&to_bytes(&w, Path::new("x.gltf")).unwrap()).unwrap();
        assert_eq!(a.meshes().count(), b.meshes().count());
        assert_eq!(a.materials().filter(|m| m.ior().is_some()).count(), 2, "the crown and the flint");
        assert_eq!(a.lights().map_or(0, |l| l.count()), 2);
        assert!(to_bytes(&w, Path::new("x.obj")).unwrap_err().to_string().contains(".glb or .gltf"));
    }
}
