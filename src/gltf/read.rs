//! A glTF 2.0 file as a world: every mesh of the scene with its node
//! transform, a camera, the lights, and materials as refract's surfaces:
//!
//! - transmission (`KHR_materials_transmission`) > 0: a glass of n_d =
//!   `KHR_materials_ior` (default 1.5) and V_d = 20 / `dispersion`
//!   (`KHR_materials_dispersion`, read from the material's own JSON), by
//!   `glass::khr_model` or the nearest catalogue glass; a triangle two
//!   glasses share (one solid's face, the other's reversed) is one
//!   cemented interface;
//! - emissive: a Lambertian area light (parallelograms: two triangles of
//!   a quad);
//! - metallic: a mirror of the base colour's mean reflectance;
//! - anything else: a matte surface of the base colour (a reflectance
//!   spectrum, docs/physics.md §12);
//! - `KHR_lights_punctual`: a directional light is a collimated beam (its
//!   width from `extras.refract.beam`, `--beam-width`, or the whole
//!   scene), point lights are point lights, spot lights point lights.
//!
//! What the file holds and the world does not model is listed, not
//! dropped in silence (`Imported::unmodelled`).

use super::{from_gltf, glass, AddedLight, ContentError, GlassChoice, GltfError, GltfOptions, LUMENS_PER_WATT};
use crate::optics::glass as catalogue;
use crate::optics::ior::IorModel;
use crate::spectrum::Spectrum;
use crate::world::{Albedo, Camera, Emission, Face, Light, Medium, Sphere, Surface, World};
use glam::{DMat4, DVec2, DVec3};
use serde_json::Value as Json;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// A world read from a file, and what the file holds that it leaves out.
pub struct Imported {
    pub world: World,
    /// Each kind of thing not modelled, with how many or which.
    pub unmodelled: Vec<String>,
    /// The camera's aspect ratio, where the file gives one.
    pub aspect: Option<f64>,
}

impl Imported {
    /// The one warning line for what was left out, if anything was.
    pub fn warning(&self, path: &Path) -> Option<String> {
        (!self.unmodelled.is_empty()).then(|| format!("{}: not modelled, left out: {}", path.display(), self.unmodelled.join("; ")))
    }
}

/// What a material becomes.
#[derive(Clone, Debug)]
enum Mat {
    Glass(usize),
    Matte([f64; 3]),
    Mirror(f64),
    /// Radiance in nits (linear sRGB, emissive factor times strength).
    Emit([f64; 3]),
}

/// What the reader gathers before the world is put together.
#[derive(Default)]
struct Gather {
    media: Vec<Medium>,
    faces: Vec<Face>,
    spheres: Vec<Sphere>,
    /// Lights with their order key (`extras.refract.light`, else after
    /// those, in the order met) and the emitting face or sphere.
    lights: Vec<(f64, Light, Option<Emitting>)>,
    unmodelled: BTreeMap<String, usize>,
    /// Glass triangles by their corners (rounded): face index.
    glass_tris: HashMap<Vec<[i64; 3]>, usize>,
    quantum: f64,
}

#[derive(Clone, Copy)]
enum Emitting {
    Face(usize),
    Sphere(usize),
}

impl Gather {
    fn note(&mut self, what: impl Into<String>) {
        *self.unmodelled.entry(what.into()).or_default() += 1;
    }
}

/// The `refract` object of a part's extras, if it has one.
fn refract_extras(extras: &gltf::json::Extras) -> Option<Json> {
    let raw = extras.as_ref()?;
    let v: Json = serde_json::from_str(raw.get()).ok()?;
    v.get("refract").cloned()
}

fn num(v: &Json, key: &str) -> Option<f64> {
    v.get(key).and_then(Json::as_f64).filter(|x| x.is_finite())
}

fn vec3(v: &Json, key: &str) -> Option<DVec3> {
    let a = v.get(key)?.as_array()?;
    let x: Vec<f64> = a.iter().filter_map(Json::as_f64).collect();
    (x.len() == 3 && x.iter().all(|c| c.is_finite())).then(|| DVec3::new(x[0], x[1], x[2]))
}

/// Reads `o.path` and builds its world at `width` x `height`: the file,
/// its nodes, the meshes, the lights, the camera, then the world.
pub fn load(o: &GltfOptions, width: usize, height: usize) -> Result<Imported, GltfError> {
    let path = &o.path;
    let name = path.display().to_string();
    let content = |why: ContentError| GltfError::Content { path: name.clone(), why };
    let (doc, buffers) = open(path)?;
    let scene = doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| content(ContentError::NoScene))?;
    let nodes = scene_nodes(&scene).map_err(content)?;
    let mut g = Gather { media: vec![Medium::Air], ..Default::default() };
    read_meshes(&mut g, &nodes, &buffers, o.glass).map_err(content)?;
    let bound = bounding_sphere(&g);
    add_lights(&mut g, &nodes, o, bound).map_err(content)?;
    let (camera, aspect) = camera(&mut g, &nodes, o.camera.as_deref(), bound, width, height).map_err(content)?;
    note_unmodelled_document(&mut g, &doc);
    let mut world = assemble(&mut g, path, camera, width, height);
    if let Some(r) = refract_extras(scene.extras()) {
        settings(&mut world, &r, o.add_light.is_some()).map_err(content)?;
    }
    world.build_accel();
    let unmodelled = g.unmodelled.iter().map(|(k, n)| if *n > 1 && !k.contains('(') { format!("{k} ({n})") } else { k.clone() }).collect();
    Ok(Imported { world, unmodelled, aspect })
}

/// The parsed file and its buffers, every buffer view and accessor checked
/// to lie inside its buffer (what the reader would not survive).
fn open(path: &Path) -> Result<(gltf::Gltf, Vec<Vec<u8>>), GltfError> {
    let name = path.display().to_string();
    let content = |why: ContentError| GltfError::Content { path: name.clone(), why };
    let bytes = std::fs::read(path).map_err(|e| GltfError::Io { path: name.clone(), why: e.to_string() })?;
    let doc = gltf::Gltf::from_slice(&bytes).map_err(|e| GltfError::Parse { path: name.clone(), why: e.to_string().replace('\n', " ") })?;
    let buffers = read_buffers(&doc, path).map_err(content)?;
    for v in doc.views() {
        let len = buffers[v.buffer().index()].len();
        if v.offset() + v.length() > len {
            return Err(content(ContentError::View { view: v.index(), offset: v.offset(), length: v.length(), bytes: len }));
        }
    }
    for a in doc.accessors() {
        if let Some(v) = a.view() {
            let stride = v.stride().unwrap_or(a.size());
            let need = if a.count() == 0 { 0 } else { a.offset() + (a.count() - 1) * stride + a.size() };
            if need > v.length() {
                return Err(content(ContentError::Accessor { accessor: a.index(), need, length: v.length() }));
            }
        }
    }
    Ok((doc, buffers))
}

/// Every node of the scene with its world matrix (glTF's axes).
fn scene_nodes<'a>(scene: &gltf::Scene<'a>) -> Result<Vec<(gltf::Node<'a>, DMat4)>, ContentError> {
    fn walk<'a>(n: gltf::Node<'a>, parent: DMat4, depth: usize, out: &mut Vec<(gltf::Node<'a>, DMat4)>) -> Result<(), ContentError> {
        if depth > 64 {
            return Err(ContentError::Deep);
        }
        let m = parent * DMat4::from_cols_array_2d(&n.transform().matrix().map(|c| c.map(f64::from)));
        out.push((n.clone(), m));
        for c in n.children() {
            walk(c, m, depth + 1, out)?;
        }
        Ok(())
    }
    let mut nodes = Vec::new();
    for n in scene.nodes() {
        walk(n, DMat4::IDENTITY, 0, &mut nodes)?;
    }
    Ok(nodes)
}

/// Every mesh of the scene as faces and spheres of `g`, their materials
/// read once each.
fn read_meshes(g: &mut Gather, nodes: &[(gltf::Node, DMat4)], buffers: &[Vec<u8>], glass: GlassChoice) -> Result<(), ContentError> {
    // The scene's size, for rounding shared corners.
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    let mut meshes: Vec<(&gltf::Node, DMat4, gltf::Mesh)> = Vec::new();
    for (n, m) in nodes {
        if let Some(mesh) = n.mesh() {
            for p in mesh.primitives() {
                let b = p.bounding_box();
                for corner in [b.min, b.max] {
                    let w = from_gltf(m.transform_point3(DVec3::from(corner.map(f64::from))));
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
            }
            meshes.push((n, *m, mesh));
        }
        if n.skin().is_some() {
            g.note("skins");
        }
    }
    if meshes.is_empty() {
        return Err(ContentError::NoMesh);
    }
    g.quantum = (hi - lo).max_element().max(1e-6) * 1e-7;
    let mut mats: HashMap<Option<usize>, Mat> = HashMap::new();
    for (node, m, mesh) in &meshes {
        let sphere = refract_extras(node.extras())
            .and_then(|r| r.get("sphere").cloned())
            .or_else(|| refract_extras(mesh.extras()).and_then(|r| r.get("sphere").cloned()));
        for (k, prim) in mesh.primitives().enumerate() {
            let key = prim.material().index();
            let mat = match mats.get(&key) {
                Some(m) => m.clone(),
                None => {
                    let m = material(g, &prim.material(), glass);
                    mats.insert(key, m.clone());
                    m
                }
            };
            let label = format!("{} {k}", mesh.name().or(node.name()).unwrap_or("mesh"));
            read_primitive(g, &prim, &label, m, &mat, sphere.as_ref(), buffers)?;
        }
    }
    if g.faces.is_empty() && g.spheres.is_empty() {
        return Err(ContentError::NoTriangle);
    }
    Ok(())
}

/// One primitive of a mesh placed by `m`: an analytic sphere refract
/// wrote, or its triangles (degenerate ones dropped).
fn read_primitive(
    g: &mut Gather,
    prim: &gltf::Primitive,
    label: &str,
    m: &DMat4,
    mat: &Mat,
    sphere: Option<&Json>,
    buffers: &[Vec<u8>],
) -> Result<(), ContentError> {
    if prim.mode() != gltf::mesh::Mode::Triangles {
        g.note(format!("{:?} primitives (only triangles are read)", prim.mode()).to_lowercase());
        return Ok(());
    }
    if prim.morph_targets().len() > 0 {
        g.note("morph targets");
    }
    // An analytic sphere refract wrote: centre and radius from the node.
    if let (Some(s), Mat::Glass(_) | Mat::Emit(_)) = (sphere, mat) {
        if let Some(r) = num(s, "radius").filter(|r| *r > 0.0) {
            let centre = from_gltf(m.transform_point3(DVec3::ZERO));
            let scale = m.determinant().abs().cbrt();
            add_sphere(g, label, centre, r * scale, mat, prim.material().extras());
            return Ok(());
        }
    }
    // What the reader would not survive: positions that are not three
    // floats, indices that are not unsigned integers.
    use gltf::accessor::{DataType, Dimensions};
    match prim.get(&gltf::Semantic::Positions) {
        Some(a) if a.dimensions() == Dimensions::Vec3 && a.data_type() == DataType::F32 && a.view().is_some() => {}
        Some(a) => return Err(ContentError::Positions { label: label.into(), accessor: a.index() }),
        None => return Err(ContentError::NoPositions(label.into())),
    }
    if let Some(a) = prim.indices() {
        if a.dimensions() != Dimensions::Scalar || !matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32) || a.view().is_none() {
            return Err(ContentError::Indices { label: label.into(), accessor: a.index() });
        }
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let Some(positions) = reader.read_positions() else {
        return Err(ContentError::NoPositions(label.into()));
    };
    let pos: Vec<DVec3> = positions.map(|p| from_gltf(m.transform_point3(DVec3::from(p.map(f64::from))))).collect();
    if pos.iter().any(|p| !p.is_finite()) {
        return Err(ContentError::NotFinite(label.into()));
    }
    let idx: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..pos.len() as u32).collect(),
    };
    if let Some(bad) = idx.iter().find(|&&i| i as usize >= pos.len()) {
        return Err(ContentError::Index { label: label.into(), index: *bad, vertices: pos.len() });
    }
    let flip = m.determinant() < 0.0;
    let tris: Vec<[DVec3; 3]> = idx
        .chunks_exact(3)
        .map(|t| {
            let (a, b, c) = (pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]);
            if flip {
                [a, c, b]
            } else {
                [a, b, c]
            }
        })
        .filter(|[a, b, c]| (*b - *a).cross(*c - *a).length_squared() > 0.0)
        .collect();
    add_triangles(g, label, &tris, mat, prim.material().extras());
    if prim.material().double_sided() && matches!(mat, Mat::Matte(_)) {
        g.note("double-sided matte surfaces (lit on their front side only)");
    }
    Ok(())
}

/// The bounding sphere of what was read (centre, radius), for lights and
/// cameras the file leaves to us.
fn bounding_sphere(g: &Gather) -> (DVec3, f64) {
    let (mut blo, mut bhi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for v in g.faces.iter().flat_map(|f| f.verts.iter()) {
        blo = blo.min(*v);
        bhi = bhi.max(*v);
    }
    for s in &g.spheres {
        blo = blo.min(s.centre - s.radius);
        bhi = bhi.max(s.centre + s.radius);
    }
    ((blo + bhi) / 2.0, ((bhi - blo).length() / 2.0).max(1e-6))
}

/// The file's `KHR_lights_punctual` lights and the one the command line
/// adds; a scene left with no light is refused.
fn add_lights(g: &mut Gather, nodes: &[(gltf::Node, DMat4)], o: &GltfOptions, bound: (DVec3, f64)) -> Result<(), ContentError> {
    for (n, m) in nodes {
        if let Some(l) = n.light() {
            add_light(g, o, &l, m, n.extras(), bound);
        }
    }
    if let Some(a) = o.add_light {
        let order = 1e12 + g.lights.len() as f64;
        let light = match a {
            AddedLight::Sun(d) => {
                beam_over(from_gltf(d).normalize(), o.beam_width.map(|w| w / 2.0), bound, 1.0, Spectrum::light("D65").expect("D65 is known"), "added sun")
            }
            AddedLight::Point(p) => Light {
                name: "added point".into(),
                emission: Emission::Point { pos: from_gltf(p) },
                spectrum: Spectrum::light("D65").expect("D65 is known"),
                power: 1.0,
            },
        };
        g.lights.push((order, light, None));
    }
    if g.lights.is_empty() {
        return Err(ContentError::NoLight);
    }
    Ok(())
}

/// The camera: the one named `want`, else the first met, else a
/// perspective view of the whole scene along glTF's -z; with the file's
/// aspect ratio where it gives one.
fn camera(
    g: &mut Gather,
    nodes: &[(gltf::Node, DMat4)],
    want: Option<&str>,
    (centre, radius): (DVec3, f64),
    width: usize,
    height: usize,
) -> Result<(Camera, Option<f64>), ContentError> {
    let cams: Vec<(String, gltf::Camera, DMat4)> =
        nodes.iter().filter_map(|(n, m)| n.camera().map(|c| (n.name().unwrap_or_default().to_string(), c, *m))).collect();
    let chosen = match want {
        Some(want) => Some(cams.iter().find(|(node, c, _)| c.name() == Some(want) || node == want).ok_or_else(|| {
            let names: Vec<String> = cams.iter().map(|(node, c, _)| c.name().unwrap_or(node).to_string()).collect();
            ContentError::NoCamera { want: want.into(), cameras: if names.is_empty() { "none".into() } else { names.join(", ") } }
        })?),
        None => cams.first(),
    };
    match chosen.map(|(_, c, m)| (c.projection(), m)) {
        Some((gltf::camera::Projection::Perspective(p), m)) => {
            let aspect = p.aspect_ratio().map(f64::from).filter(|a| a.is_finite() && *a > 0.0);
            let yfov = f64::from(p.yfov());
            if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
                return Err(ContentError::Yfov(yfov));
            }
            let pos = from_gltf(m.transform_point3(DVec3::ZERO));
            let forward = from_gltf(m.transform_vector3(DVec3::NEG_Z)).normalize();
            let up = from_gltf(m.transform_vector3(DVec3::Y)).normalize();
            if !(forward.is_finite() && up.is_finite() && forward.cross(up).length() > 1e-9) {
                return Err(ContentError::Degenerate);
            }
            Ok((Camera::look_at(pos, pos + forward, up, yfov.to_degrees(), width, height), aspect))
        }
        other => {
            if other.is_some() {
                g.note("orthographic cameras (a perspective view of the whole scene instead)");
            }
            // Looking along glTF's -z at the whole scene, from far enough to see it.
            let vfov = 40f64;
            let dist = radius / (vfov.to_radians() / 2.0).sin() * 1.1;
            let forward = from_gltf(DVec3::NEG_Z);
            Ok((Camera::look_at(centre - forward * dist, centre, from_gltf(DVec3::Y), vfov, width, height), None))
        }
    }
}

/// What the document holds beyond its scene that is not modelled:
/// animations, extensions the reader does not read.
fn note_unmodelled_document(g: &mut Gather, doc: &gltf::Gltf) {
    if doc.animations().len() > 0 {
        g.note(format!("animations ({})", doc.animations().len()));
    }
    let modelled = [
        "KHR_materials_transmission",
        "KHR_materials_ior",
        "KHR_materials_dispersion",
        "KHR_materials_volume",
        "KHR_materials_emissive_strength",
        "KHR_lights_punctual",
    ];
    for e in doc.extensions_used().filter(|e| !modelled.contains(e)) {
        g.note(format!("extension {e}"));
    }
}

/// The world put together: lights in their order, emitters pointed at
/// them, a photon map for every diffuse face, the probe on the first beam.
fn assemble(g: &mut Gather, path: &Path, camera: Camera, width: usize, height: usize) -> World {
    let mut lights = std::mem::take(&mut g.lights);
    lights.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut world = World::new(path.file_stem().and_then(|s| s.to_str()).unwrap_or("gltf"), std::mem::take(&mut g.media), width, height);
    world.faces = std::mem::take(&mut g.faces);
    world.spheres = std::mem::take(&mut g.spheres);
    for (i, (_, light, at)) in lights.into_iter().enumerate() {
        match at {
            Some(Emitting::Face(f)) => world.faces[f].surface = Surface::Emitter { light: i },
            Some(Emitting::Sphere(s)) => world.spheres[s].surface = Surface::Emitter { light: i },
            None => {}
        }
        world.lights.push(light);
    }
    world.maps = world.faces.iter().enumerate().filter(|(_, f)| matches!(f.surface, Surface::Diffuse { .. })).map(|(i, _)| i).collect();
    for (slot, &f) in world.maps.clone().iter().enumerate() {
        if let Surface::Diffuse { map, .. } = &mut world.faces[f].surface {
            *map = slot;
        }
    }
    world.camera = camera;
    world.bounces = 2;
    world.direct_lighting = true;
    world.probe = world
        .lights
        .iter()
        .find_map(|l| match l.emission {
            Emission::Beam { centre, dir, .. } => Some((centre, dir)),
            _ => None,
        })
        .unwrap_or((world.camera.pos, world.camera.forward));
    world
}

/// The photon mapper's settings refract wrote into the scene's extras.
fn settings(w: &mut World, r: &Json, added: bool) -> Result<(), ContentError> {
    if let Some(b) = r.get("bounces").and_then(Json::as_u64) {
        w.bounces = b.min(64) as u32;
    }
    if let Some(d) = r.get("direct_lighting").and_then(Json::as_bool) {
        w.direct_lighting = d;
    }
    if let Some(g) = num(r, "indirect_gather").filter(|g| *g >= 1.0) {
        w.indirect_gather = g;
    }
    if let Some(h) = num(r, "haze").filter(|h| *h >= 0.0) {
        w.haze = h;
    }
    if let Some(s) = r.get("haze_skip").and_then(Json::as_array) {
        w.haze_skip = s.iter().filter_map(Json::as_u64).map(|i| i as usize).filter(|&i| i < w.lights.len()).collect();
    }
    if let Some(s) = r.get("photon_shares").and_then(Json::as_array) {
        let mut shares: Vec<f64> = s.iter().filter_map(Json::as_f64).collect();
        if added && shares.len() + 1 == w.lights.len() {
            // The light added on the command line (the last) gets the
            // file's lights' mean share.
            shares.push(shares.iter().sum::<f64>() / shares.len().max(1) as f64);
        }
        if shares.len() != w.lights.len() || shares.iter().any(|x| !(x.is_finite() && *x >= 0.0)) || shares.iter().sum::<f64>() <= 0.0 {
            return Err(ContentError::Shares { shares: shares.len(), lights: w.lights.len() });
        }
        w.photon_shares = Some(shares);
    }
    if let (Some(o), Some(d)) = (r.get("probe").and_then(|p| vec3(p, "origin")), r.get("probe").and_then(|p| vec3(p, "dir"))) {
        w.probe = (o, d.normalize());
    }
    Ok(())
}

/// The buffers' bytes: the GLB's binary chunk, a data URI, or a file
/// beside the glTF.
fn read_buffers(doc: &gltf::Gltf, path: &Path) -> Result<Vec<Vec<u8>>, ContentError> {
    use base64::Engine;
    let mut out = Vec::new();
    for b in doc.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => doc.blob.clone().ok_or(ContentError::NoBinaryChunk(b.index()))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let (_, text) = uri.split_once(',').ok_or(ContentError::DataUri(b.index()))?;
                base64::engine::general_purpose::STANDARD.decode(text).map_err(|why| ContentError::Base64 { buffer: b.index(), why })?
            }
            gltf::buffer::Source::Uri(uri) => {
                let file = path.parent().unwrap_or(Path::new("")).join(percent_decode(uri));
                std::fs::read(&file).map_err(|io| ContentError::BufferFile { buffer: b.index(), file: file.clone(), io })?
            }
        };
        if data.len() < b.length() {
            return Err(ContentError::BufferSize { buffer: b.index(), bytes: data.len(), says: b.length() });
        }
        out.push(data);
    }
    Ok(out)
}

/// A URI's %XX escapes decoded (file names with spaces).
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            if let Ok(v) = u8::from_str_radix(&s[i + 1..i + 3], 16) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// What material `m` becomes (a glass is added to the media).
fn material(g: &mut Gather, m: &gltf::Material, choice: GlassChoice) -> Mat {
    let label = m.name().map_or_else(|| format!("material {}", m.index().map_or("default".into(), |i| i.to_string())), |n| format!("\"{n}\""));
    let pbr = m.pbr_metallic_roughness();
    let base = pbr.base_color_factor();
    let rgb = [base[0], base[1], base[2]].map(|c| f64::from(c).clamp(0.0, 1.0));
    if m.index().is_none() {
        g.note("the default material (meshes without one: matte grey)");
        return Mat::Matte([0.8; 3]);
    }
    let textures = [
        pbr.base_color_texture().is_some(),
        pbr.metallic_roughness_texture().is_some(),
        m.normal_texture().is_some(),
        m.occlusion_texture().is_some(),
        m.emissive_texture().is_some(),
        m.transmission().is_some_and(|t| t.transmission_texture().is_some()),
    ];
    if textures.iter().any(|t| *t) {
        g.note("textures (their materials' factors are used)");
    }
    if m.alpha_mode() != gltf::material::AlphaMode::Opaque && !(m.alpha_mode() == gltf::material::AlphaMode::Blend && base[3] >= 1.0) {
        g.note("alpha blending and masks (surfaces drawn opaque)");
    }
    let strength = f64::from(m.emissive_strength().unwrap_or(1.0));
    let emit = m.emissive_factor().map(|c| f64::from(c) * strength);
    let transmission = m.transmission().map_or(0.0, |t| f64::from(t.transmission_factor()));
    let rough = f64::from(pbr.roughness_factor());
    if transmission > 0.0 {
        if transmission < 1.0 {
            g.note("partial transmission (clear glass instead)");
        }
        if rough > 0.0 {
            g.note(format!("roughness above 0 ({label}: smooth glass instead)"));
        }
        if m.volume().is_some_and(|v| v.attenuation_distance().is_finite()) {
            g.note("volume absorption (KHR_materials_volume attenuation: clear glass instead)");
        }
        if rgb.iter().any(|c| *c < 0.999) && rgb != [rgb[0]; 3] {
            g.note("tinted glass (base colour of a transmissive material)");
        }
        let n_d = f64::from(m.ior().unwrap_or(1.5));
        let dispersion = m.extension_value("KHR_materials_dispersion").and_then(|v| v.get("dispersion")).and_then(Json::as_f64).unwrap_or(0.0);
        let abbe = (dispersion > 0.0).then(|| 20.0 / dispersion);
        let own = refract_extras(m.extras()).and_then(|r| r.get("glass").cloned());
        let (name, ior) = glass_model(n_d, abbe, own.as_ref(), choice, m.name());
        g.media.push(Medium::Glass { name, ior });
        return Mat::Glass(g.media.len() - 1);
    }
    if emit.iter().any(|c| *c > 0.0) {
        return Mat::Emit(emit);
    }
    if pbr.metallic_factor() >= 0.5 {
        if rough > 0.0 {
            g.note(format!("roughness above 0 ({label}: a smooth mirror instead)"));
        }
        return Mat::Mirror((rgb[0] + rgb[1] + rgb[2]) / 3.0);
    }
    if pbr.metallic_factor() > 0.0 {
        g.note("partly metallic materials (matte instead)");
    }
    Mat::Matte(rgb)
}

/// The index model of a glass of (n_d, V_d): refract's own model where the
/// file's extras name one that still gives the file's n_d and V_d (the
/// file is as refract wrote it), else by `choice`.
fn glass_model(n_d: f64, abbe: Option<f64>, own: Option<&Json>, choice: GlassChoice, name: Option<&str>) -> (String, IorModel) {
    let agrees = |m: &IorModel| {
        let (n, v) = glass::nd_abbe(m);
        (n - n_d).abs() < 1e-4
            && match (v, abbe) {
                (Some(v), Some(a)) => ((v - a) / a).abs() < 1e-4,
                (None, None) => true,
                _ => false,
            }
    };
    if let Some(model) = own.and_then(own_model).filter(|(_, m)| agrees(m)) {
        return model;
    }
    let fallback = || name.map_or_else(|| format!("n_d {n_d:.4}"), str::to_string);
    match (choice, abbe) {
        (GlassChoice::Nearest, Some(v)) => {
            let g = glass::nearest(n_d, v);
            (g.name.clone(), IorModel::Sellmeier(g.clone()))
        }
        _ => (fallback(), glass::khr_model(n_d, abbe)),
    }
}

/// The index model refract wrote into a glass material's extras.
fn own_model(j: &Json) -> Option<(String, IorModel)> {
    let name = j.get("name").and_then(Json::as_str)?.to_string();
    let model = match j.get("model").and_then(Json::as_str)? {
        "constant" => IorModel::Constant(num(j, "n")?),
        "cauchy" => IorModel::Cauchy { a: num(j, "a")?, b_um2: num(j, "b_um2")? },
        "sellmeier" => IorModel::Sellmeier(catalogue::by_name(j.get("glass").and_then(Json::as_str)?).ok()?.clone()),
        "fraunhofer" => IorModel::Fraunhofer { n_d: num(j, "n_d")?, slope_per_nm: num(j, "slope_per_nm")? },
        "musgrave" => IorModel::Musgrave { n_d: num(j, "n_d")?, k: num(j, "k")? },
        _ => return None,
    };
    Some((name, model))
}

/// A spectrum refract wrote (`write::spectrum_json`).
pub(crate) fn spectrum_of(j: &Json) -> Option<Spectrum> {
    Some(match j.get("kind").and_then(Json::as_str)? {
        "constant" => Spectrum::Constant(num(j, "value")?),
        "table" => {
            let values: Vec<f64> = j.get("values")?.as_array()?.iter().filter_map(Json::as_f64).collect();
            (!values.is_empty()).then_some(())?;
            Spectrum::Tabulated { start: num(j, "start")?, step: num(j, "step")?.max(1e-9), values: values.into() }
        }
        "blackbody" => Spectrum::Blackbody { kelvin: num(j, "kelvin")? },
        "lines" => {
            let lines = j.get("lines")?.as_array()?.iter().filter_map(|l| Some((l.get(0)?.as_f64()?, l.get(1)?.as_f64()?))).collect();
            Spectrum::Lines { lines, fwhm: num(j, "fwhm")? }
        }
        "rgb" => {
            let c = j.get("fit")?.as_array()?.iter().filter_map(Json::as_f64).collect::<Vec<_>>();
            let &[c0, c1, c2] = c.as_slice() else { return None };
            Spectrum::Rgb {
                fit: crate::spectrum::rgb_fit::SigmoidPolynomial { c: [c0, c1, c2] },
                scale: num(j, "scale")?,
                illuminant: j.get("illuminant")?.as_bool()?,
            }
        }
        "sum" => Spectrum::Sum(j.get("parts")?.as_array()?.iter().map(spectrum_of).collect::<Option<_>>()?),
        _ => return None,
    })
}

/// A light's spectrum: refract's own from the extras, else its colour
/// (white is D65, sRGB's white; another colour a smooth illuminant of it).
fn light_spectrum(extras: Option<&Json>, rgb: [f64; 3]) -> Spectrum {
    if let Some(s) = extras.and_then(|r| r.get("spectrum")).and_then(spectrum_of) {
        return s;
    }
    if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        Spectrum::light("D65").expect("D65 is known")
    } else {
        Spectrum::from_rgb(DVec3::from(rgb), true)
    }
}

fn add_sphere(g: &mut Gather, label: &str, centre: DVec3, radius: f64, mat: &Mat, extras: &gltf::json::Extras) {
    let k = g.spheres.len();
    match mat {
        Mat::Glass(m) => g.spheres.push(Sphere { name: label.into(), centre, radius, surface: Surface::Interface { front: 0, back: *m } }),
        Mat::Emit(rgb) => {
            g.spheres.push(Sphere { name: label.into(), centre, radius, surface: Surface::Emitter { light: 0 } });
            let r = refract_extras(extras);
            let area = 4.0 * std::f64::consts::PI * radius * radius;
            let power = r.as_ref().and_then(|r| num(r, "power")).unwrap_or_else(|| emitted_watts(*rgb, area));
            if !(power.is_finite() && power > 0.0) {
                g.spheres.pop();
                g.note("emitters of no finite power");
                return;
            }
            let order = r.as_ref().and_then(|r| num(r, "light")).unwrap_or(1e9 + g.lights.len() as f64);
            let light = Light { name: label.into(), emission: Emission::Sphere { sphere: k }, spectrum: light_spectrum(r.as_ref(), norm(*rgb)), power };
            g.lights.push((order, light, Some(Emitting::Sphere(k))));
        }
        _ => unreachable!("spheres are glass or emitters"),
    }
}

/// Watts a Lambertian surface of radiance `nits` (per channel) and area
/// `area` emits: pi L A at 683 lm/W, L the colour's luminance.
fn emitted_watts(nits: [f64; 3], area: f64) -> f64 {
    let l = DVec3::from(nits).dot(crate::spectrum::cie::SRGB_LUMA);
    std::f64::consts::PI * l * area / LUMENS_PER_WATT
}

/// A colour scaled to a largest channel of 1.
fn norm(rgb: [f64; 3]) -> [f64; 3] {
    let m = rgb.iter().copied().fold(0.0, f64::max);
    if m > 0.0 {
        rgb.map(|c| c / m)
    } else {
        [1.0; 3]
    }
}

fn quantise(g: &Gather, poly: &[DVec3]) -> Vec<[i64; 3]> {
    let mut k: Vec<[i64; 3]> =
        poly.iter().map(|v| [(v.x / g.quantum).round() as i64, (v.y / g.quantum).round() as i64, (v.z / g.quantum).round() as i64]).collect();
    k.sort();
    k
}

/// Consecutive triangles in one plane that share an edge, joined while
/// the polygon stays convex: a face written as a fan is one face again (a
/// ray that refracts at one triangle must not meet its coplanar
/// neighbour across the diagonal).
fn merge_coplanar(tris: &[[DVec3; 3]]) -> Vec<Vec<DVec3>> {
    let mut out: Vec<Vec<DVec3>> = Vec::new();
    let mut normal = DVec3::ZERO;
    for t in tris {
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let size = (t[1] - t[0]).length().max((t[2] - t[0]).length());
        let same = |a: DVec3, b: DVec3| (a - b).length() <= 1e-6 * size;
        let merged = out.last().filter(|_| n.dot(normal) > 1.0 - 1e-9).and_then(|p| {
            let k = p.len();
            // An edge p[i] -> p[i + 1] that the triangle runs the other way.
            (0..k).find_map(|i| {
                let (a, b) = (p[i], p[(i + 1) % k]);
                (0..3).find_map(|j| (same(t[j], b) && same(t[(j + 1) % 3], a)).then(|| t[(j + 2) % 3])).map(|apex| {
                    let mut q = p.clone();
                    q.insert(i + 1, apex);
                    q
                })
            })
        });
        match merged.filter(|q| {
            let k = q.len();
            (0..k).all(|i| (q[(i + 1) % k] - q[i]).cross(q[(i + 2) % k] - q[(i + 1) % k]).dot(n) > 1e-12 * size * size)
        }) {
            Some(q) => *out.last_mut().expect("merged into the last") = q,
            None => {
                out.push(t.to_vec());
                normal = n;
            }
        }
    }
    out
}

/// The parallelogram two triangles make, if they make one: corner and
/// the two edges, normal along the first triangle's.
fn parallelogram(a: &[DVec3; 3], b: &[DVec3; 3]) -> Option<(DVec3, DVec3, DVec3)> {
    let near = |p: DVec3, q: DVec3, tol: f64| (p - q).length() <= tol;
    let tol = 1e-5 * (a[1] - a[0]).length().max((a[2] - a[0]).length());
    let shared: Vec<DVec3> = a.iter().copied().filter(|p| b.iter().any(|q| near(*p, *q, tol))).collect();
    if shared.len() != 2 {
        return None;
    }
    let c = *a.iter().find(|p| !shared.iter().any(|s| near(**p, *s, tol)))?;
    let d = *b.iter().find(|p| !shared.iter().any(|s| near(**p, *s, tol)))?;
    if !near(c + d, shared[0] + shared[1], 2.0 * tol) {
        return None;
    }
    let n = (a[1] - a[0]).cross(a[2] - a[0]);
    let (eu, ev) = (shared[0] - c, shared[1] - c);
    Some(if eu.cross(ev).dot(n) > 0.0 { (c, eu, ev) } else { (c, ev, eu) })
}

fn add_triangles(g: &mut Gather, label: &str, tris: &[[DVec3; 3]], mat: &Mat, extras: &gltf::json::Extras) {
    match *mat {
        Mat::Glass(m) => {
            for (i, poly) in merge_coplanar(tris).into_iter().enumerate() {
                let key = quantise(g, &poly);
                let n = (poly[1] - poly[0]).cross(poly[2] - poly[0]);
                if let Some(&f) = g.glass_tris.get(&key) {
                    // Another glass's solid has this face: one cemented face.
                    if let Surface::Interface { front: 0, back } = g.faces[f].surface {
                        if g.faces[f].normal.dot(n) < 0.0 {
                            g.faces[f].surface = Surface::Interface { front: m, back };
                            continue;
                        }
                    }
                }
                let face = Face::polygon(&format!("{label} face {i}"), poly, n, Surface::Interface { front: 0, back: m });
                g.glass_tris.insert(key, g.faces.len());
                g.faces.push(face);
            }
        }
        Mat::Mirror(r) => {
            for (i, poly) in merge_coplanar(tris).into_iter().enumerate() {
                let n = (poly[1] - poly[0]).cross(poly[2] - poly[0]);
                g.faces.push(Face::polygon(&format!("{label} face {i}"), poly, n, Surface::Mirror { reflectance: r }));
            }
        }
        Mat::Matte(rgb) => {
            let albedo = Albedo::new(rgb);
            let surface = Surface::Diffuse { albedo, map: 0 };
            let mut i = 0;
            while i < tris.len() {
                if let Some((c, eu, ev)) = tris.get(i + 1).and_then(|b| parallelogram(&tris[i], b)) {
                    g.faces.push(Face::rect(&format!("{label} quad {i}"), c, eu, ev, surface.clone()));
                    i += 2;
                } else {
                    let [a, b, c] = tris[i];
                    g.faces.push(Face::triangle(&format!("{label} triangle {i}"), a, b, c, surface.clone()));
                    i += 1;
                }
            }
        }
        Mat::Emit(rgb) => {
            let r = refract_extras(extras);
            let mut i = 0;
            let mut quads = Vec::new();
            while i < tris.len() {
                if let Some(q) = tris.get(i + 1).and_then(|b| parallelogram(&tris[i], b)) {
                    quads.push(q);
                    i += 2;
                } else {
                    g.note("emissive triangles that are not halves of a parallelogram");
                    i += 1;
                }
            }
            let total: f64 = quads.iter().map(|(_, eu, ev)| eu.cross(*ev).length()).sum();
            for (k, (c, eu, ev)) in quads.iter().enumerate() {
                let area = eu.cross(*ev).length();
                // refract's power is the whole mesh's; shared by area.
                let power = r.as_ref().and_then(|r| num(r, "power")).map_or_else(|| emitted_watts(rgb, area), |p| p * area / total);
                if !(power.is_finite() && power > 0.0) {
                    g.note("emitters of no finite power");
                    continue;
                }
                let f = g.faces.len();
                g.faces.push(Face::rect(&format!("{label} emitter {k}"), *c, *eu, *ev, Surface::Emitter { light: 0 }));
                let order = r.as_ref().and_then(|r| num(r, "light")).map_or(1e9 + g.lights.len() as f64, |o| o + k as f64 * 1e-6);
                let light =
                    Light { name: format!("{label} {k}"), emission: Emission::Area { face: f }, spectrum: light_spectrum(r.as_ref(), norm(rgb)), power };
                g.lights.push((order, light, Some(Emitting::Face(f))));
            }
        }
    }
}

/// A collimated beam along `dir` over the scene's bounding ball (or of
/// `half`-width round the ball's centre's line), from outside it, carrying
/// `irradiance` W/m^2.
fn beam_over(dir: DVec3, half: Option<f64>, (centre, radius): (DVec3, f64), irradiance: f64, spectrum: Spectrum, name: &str) -> Light {
    let half = half.unwrap_or(radius);
    let u = dir.any_orthonormal_vector();
    let v = dir.cross(u);
    Light {
        name: name.into(),
        emission: Emission::Beam { centre: centre - dir * (2.0 * radius), dir, u, v, half: DVec2::splat(half), disc: true, polarisation: None },
        spectrum,
        power: irradiance * std::f64::consts::PI * half * half,
    }
}

fn add_light(g: &mut Gather, o: &GltfOptions, l: &gltf::khr_lights_punctual::Light, m: &DMat4, node_extras: &gltf::json::Extras, ball: (DVec3, f64)) {
    use gltf::khr_lights_punctual::Kind;
    let r = refract_extras(l.extras()).or_else(|| refract_extras(node_extras));
    let rgb = l.color().map(f64::from);
    let spectrum = light_spectrum(r.as_ref(), rgb);
    let order = r.as_ref().and_then(|r| num(r, "light")).unwrap_or(1e9 + g.lights.len() as f64);
    let luma = DVec3::from(rgb).dot(crate::spectrum::cie::SRGB_LUMA);
    let intensity = f64::from(l.intensity()) * luma;
    let name = l.name().unwrap_or("light").to_string();
    let pos = from_gltf(m.transform_point3(DVec3::ZERO));
    let light = match l.kind() {
        Kind::Directional => {
            let dir = from_gltf(m.transform_vector3(DVec3::NEG_Z)).normalize();
            let beam = r.as_ref().and_then(|r| r.get("beam"));
            match beam.and_then(|b| b.get("half")).and_then(Json::as_array).map(|h| h.iter().filter_map(Json::as_f64).collect::<Vec<_>>()) {
                Some(h) if h.len() == 2 && h.iter().all(|x| x.is_finite() && *x > 0.0) => {
                    let b = beam.expect("read above");
                    let u = from_gltf(m.transform_vector3(DVec3::X)).normalize();
                    let v = from_gltf(m.transform_vector3(DVec3::Y)).normalize();
                    let disc = b.get("disc").and_then(Json::as_bool).unwrap_or(true);
                    let polarisation = match b.get("polarisation").and_then(Json::as_str) {
                        Some("s") => Some(crate::world::interface::Polarisation::S),
                        Some("p") => Some(crate::world::interface::Polarisation::P),
                        _ => None,
                    };
                    let area = if disc { std::f64::consts::PI * h[0] * h[1] } else { 4.0 * h[0] * h[1] };
                    let power = r.as_ref().and_then(|r| num(r, "power")).unwrap_or(intensity / LUMENS_PER_WATT * area);
                    Light { name, emission: Emission::Beam { centre: pos, dir, u, v, half: DVec2::new(h[0], h[1]), disc, polarisation }, spectrum, power }
                }
                _ => beam_over(dir, o.beam_width.map(|w| w / 2.0), ball, intensity / LUMENS_PER_WATT, spectrum, &name),
            }
        }
        Kind::Point | Kind::Spot { .. } => {
            if matches!(l.kind(), Kind::Spot { .. }) {
                g.note("spot lights' cones (lit as point lights)");
            }
            let power = r.as_ref().and_then(|r| num(r, "power")).unwrap_or(4.0 * std::f64::consts::PI * intensity / LUMENS_PER_WATT);
            Light { name, emission: Emission::Point { pos }, spectrum, power }
        }
    };
    if light.power > 0.0 && light.power.is_finite() {
        g.lights.push((order, light, None));
    } else {
        g.note("lights of zero intensity");
    }
}

/// An image size `width` wide with the file's camera's aspect ratio (4:3
/// where it gives none).
pub fn default_size(o: &GltfOptions, width: usize) -> [usize; 2] {
    let aspect = aspect_of(&o.path, o.camera.as_deref()).unwrap_or(4.0 / 3.0);
    [width, ((width as f64 / aspect).round() as usize).clamp(1, 16384)]
}

/// The camera's aspect ratio in a file, if it names one (for a default
/// image size); errors are left to `load`.
pub fn aspect_of(path: &Path, camera: Option<&str>) -> Option<f64> {
    let doc = gltf::Gltf::open(path).ok()?;
    let cams: Vec<gltf::Camera> =
        doc.nodes().filter_map(|n| n.camera().filter(|c| camera.is_none_or(|w| c.name() == Some(w) || n.name() == Some(w)))).collect();
    match cams.first()?.projection() {
        gltf::camera::Projection::Perspective(p) => p.aspect_ratio().map(f64::from).filter(|a| a.is_finite() && *a > 0.0),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A convex polygon written as a fan comes back whole; a reversed fan
    /// comes back reversed; a bent pair stays two triangles.
    #[test]
    fn a_fan_in_one_plane_is_one_face_again() {
        let v = DVec3::new;
        let poly = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.5, 1.0, 0.0), v(0.5, 1.5, 0.0), v(-0.5, 1.0, 0.0)];
        let fan: Vec<[DVec3; 3]> = (1..4).map(|i| [poly[0], poly[i], poly[i + 1]]).collect();
        let merged = merge_coplanar(&fan);
        assert_eq!(merged.len(), 1);
        assert_eq!(merged[0], poly.to_vec());
        let back: Vec<[DVec3; 3]> = fan.iter().map(|[a, b, c]| [*a, *c, *b]).collect();
        let merged = merge_coplanar(&back);
        assert_eq!(merged.len(), 1);
        assert_eq!(merged[0].len(), 5);
        // Folded along the shared edge: not one plane.
        let bent = [[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)], [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(1.0, 1.0, 0.5)]];
        assert_eq!(merge_coplanar(&bent).len(), 2);
    }

    /// Two triangles of a parallelogram give its corner and edges (normal
    /// kept); two of a kite do not.
    #[test]
    fn a_quads_triangles_are_its_parallelogram() {
        let v = DVec3::new;
        let (c, eu, ev) = (v(1.0, 2.0, 0.0), v(2.0, 0.0, 0.0), v(0.5, 1.0, 0.0));
        let (p, u, w) = parallelogram(&[c, c + eu, c + ev], &[c + eu, c + eu + ev, c + ev]).unwrap();
        assert!((p - c).length() < 1e-12 && (u - eu).length() < 1e-12 && (w - ev).length() < 1e-12);
        assert!(u.cross(w).z > 0.0);
        let kite = [[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)], [v(1.0, 0.0, 0.0), v(2.0, 2.0, 0.0), v(0.0, 1.0, 0.0)]];
        assert!(parallelogram(&kite[0], &kite[1]).is_none());
    }

    #[test]
    fn uris_are_percent_decoded() {
        assert_eq!(percent_decode("my%20scene.bin"), "my scene.bin");
        assert_eq!(percent_decode("a%2"), "a%2");
        assert_eq!(percent_decode("plain.bin"), "plain.bin");
    }

    /// Every spectrum kind refract's lights use comes back from its JSON.
    #[test]
    fn spectra_come_back_from_their_json() {
        for name in ["D65", "E", "blackbody:3200", "cfl-lines", "laser:532", "FL11"] {
            let s = Spectrum::light(name).unwrap();
            let back = spectrum_of(&super::super::write::spectrum_json(&s)).unwrap();
            for nm in [400.0, 532.0, 546.1, 611.0, 700.0] {
                assert_eq!(s.eval(nm), back.eval(nm), "{name} at {nm} nm");
            }
        }
        let rgb = Spectrum::from_rgb(DVec3::new(0.9, 0.3, 0.1), true);
        assert_eq!(spectrum_of(&super::super::write::spectrum_json(&rgb)).unwrap().eval(600.0), rgb.eval(600.0));
    }
}
