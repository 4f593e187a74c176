//! Builders of the worlds the spectral renderer draws, one file per
//! report: `amici` (report 000: the Amici prism before a screen or a lamp),
//! `single_prism` (the 60 degree anchor scene), `spheres` (report 001's
//! glass spheres) and `cornell` (report 003's Cornell boxes and the album
//! cover). Units are metres.

pub mod amici;
pub mod cornell;
pub mod examples;
pub mod single_prism;
pub mod spheres;

use crate::optics::glass::{self, Glass};
use crate::optics::ior::{IorKind, IorModel};
use crate::spectrum::spectra::NamedSpectrum;
use crate::spectrum::Spectrum;
use crate::world::{Albedo, Emission, Face, Medium, Surface, World};

/// Why a scene cannot be built from its options: the parameter (by its
/// key) or the glasses that make no scene, a mesh that makes no prism, a
/// light spectrum that names none. Shown with the flag's spelling of the
/// key; the key is kept for a caller that names it otherwise.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("--{}: {why}", .key.replace('_', "-"))]
    Param { key: &'static str, why: String },
    /// The glasses and the flint's apex together (the Amici designs).
    #[error("--glass {crown} / --flint {flint} / --flint-apex {apex}: {why}")]
    Design { crown: String, flint: String, apex: f64, why: String },
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    #[error(transparent)]
    Light(#[from] crate::spectrum::spectra::UnknownSpectrum),
    #[error(transparent)]
    Gltf(#[from] crate::gltf::GltfError),
}

impl SceneError {
    pub(crate) fn param(key: &'static str, why: impl Into<String>) -> SceneError {
        SceneError::Param { key, why: why.into() }
    }

    pub(crate) fn design(o: &SceneOptions, why: impl Into<String>) -> SceneError {
        SceneError::Design { crown: o.crown.name.clone(), flint: o.flint.name.clone(), apex: o.flint_apex_deg, why: why.into() }
    }
}

type Result<T> = std::result::Result<T, SceneError>;
use glam::DVec3;

crate::named_enum! {
    pub enum SceneKind {
        /// Report 000: a white slit beam through an Amici prism onto a screen.
        AmiciScreen = "amici-screen",
        /// Report 000: a fluorescent tube seen through an Amici prism.
        AmiciLamp = "amici-lamp",
        /// Report 000: the slit beam, the Amici prism and the screen on a lit table, seen from behind the prism.
        AmiciBench = "amici-bench",
        /// The anchor: a 60 degree prism, a 2 cm beam, a screen 4 m behind.
        SinglePrism = "single-prism",
        /// Report 001: a glass sphere before a spherical black-body light, off centre.
        SphereArealight = "sphere-arealight",
        /// Report 001: a glass sphere before a metal plate grazed by a warm lamp (yellow to red across the sphere).
        SphereMetal = "sphere-metal",
        /// Report 001's final image: a white beam through a hole in a card onto a glass sphere, which rings the hole with a rainbow.
        SpheresFinal = "spheres-final",
        /// Report 003: a point light and a glass prism in a Cornell box (a faint rainbow).
        CornellPointlight = "cornell-pointlight",
        /// Report 003: the point light at the end of a mirror tube (a brighter rainbow).
        CornellMirrorTube = "cornell-mirror-tube",
        /// Report 003: a laser into a glass prism in a Cornell box.
        CornellLaser = "cornell-laser",
        /// Report 003's album-cover remake: a white beam through a prism fanning into a spectrum.
        DarkSide = "dark-side",
    }
}

impl SceneKind {}

crate::named_enum! {
    /// Where the camera stands (amici-bench has three views, cornell-laser
    /// two; every other scene has its own one).
    pub enum View {
        /// The scene's own camera (amici-bench: behind the lamp, above the table, down the bench).
        Scene = "scene",
        /// amici-bench: the screen close up, square on.
        Screen = "screen",
        /// amici-bench: the whole bench from high above its side.
        Overview = "overview",
        /// cornell-laser: the band of spectrum on the back wall, close up and square on.
        Wall = "wall",
    }
}

/// Everything that shapes a scene.
#[derive(Clone, Debug)]
pub struct SceneOptions {
    pub kind: SceneKind,
    /// Crown glass (the single prism's, the spheres' and the Cornell prism's glass).
    pub crown: &'static Glass,
    pub flint: &'static Glass,
    pub flint_apex_deg: f64,
    pub ior: IorKind,
    /// The lights' spectrum; `None` = the scene's own.
    pub light: Option<NamedSpectrum>,
    /// Angle of incidence on the first face, degrees; `None` = the design
    /// (Amici: along the axis; single prism: minimum deviation at d).
    pub incidence_deg: Option<f64>,
    pub no_prism: bool,
    pub no_dispersion: bool,
    pub view: View,
    /// Haze in the air, per metre; `None` = the scene's own.
    pub haze: Option<f64>,
    /// Gather factor for bounced and mirrored light; `None` = the scene's.
    pub indirect_gather: Option<f64>,
    /// A user's OBJ mesh (metres) of `crown` glass in place of the prism.
    pub obj: Option<std::path::PathBuf>,
    /// A glTF 2.0 file that is the whole scene (`crate::gltf::read`), in
    /// place of `kind`.
    pub gltf: Option<crate::gltf::GltfOptions>,
    pub width: usize,
    pub height: usize,
}

impl SceneOptions {
    /// The glTF file that is the scene, if one is named.
    pub fn gltf_file(&self) -> Option<&crate::gltf::GltfOptions> {
        self.gltf.as_ref().filter(|g| !g.path.as_os_str().is_empty())
    }

    pub fn new(kind: SceneKind) -> Self {
        SceneOptions {
            kind,
            crown: glass::by_name("N-BK7").expect("N-BK7 is in the catalogue"),
            flint: glass::by_name("N-SF11").expect("N-SF11 is in the catalogue"),
            flint_apex_deg: 90.0,
            ior: IorKind::Sellmeier,
            light: None,
            incidence_deg: None,
            no_prism: false,
            no_dispersion: false,
            view: View::Scene,
            haze: None,
            indirect_gather: None,
            obj: None,
            gltf: None,
            width: 640,
            height: 240,
        }
    }
}

pub(crate) fn glass_medium(g: &Glass, kind: IorKind, no_dispersion: bool) -> Medium {
    let kind = if no_dispersion { IorKind::Constant } else { kind };
    Medium::Glass { name: g.name.clone(), ior: IorModel::for_glass(g, kind) }
}

/// An empty world of air and one glass, of the options' image size.
fn with_glass(o: &SceneOptions, glass: Medium) -> World {
    World::new(o.kind.name(), vec![Medium::Air, glass], o.width, o.height)
}

/// A matte parallelogram with its own photon map.
pub(crate) fn matte(s: &mut World, name: &str, corner: DVec3, eu: DVec3, ev: DVec3, albedo: [f64; 3]) {
    let map = s.maps.len();
    s.faces.push(Face::rect(name, corner, eu, ev, Surface::Diffuse { albedo: Albedo::new(albedo), map }));
    s.maps.push(s.faces.len() - 1);
}

pub(crate) fn rotate_z(v: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// Builds the scene the options describe.
pub fn build(o: &SceneOptions) -> Result<World> {
    if o.width == 0 || o.height == 0 {
        return Err(SceneError::param("size", "width and height must be at least 1"));
    }
    if let Some(g) = o.gltf_file() {
        // The file is the whole scene; the options that shape the built-in
        // ones are refused by the parameter table where a file is given.
        let mut scene = crate::gltf::read::load(g, o.width, o.height)?.world;
        if let Some(l) = &o.light {
            for light in &mut scene.lights {
                light.spectrum = l.spectrum.clone();
            }
        }
        if let Some(h) = o.haze {
            if h > 0.0 && !scene.lights.iter().any(|l| matches!(l.emission, Emission::Beam { .. })) {
                return Err(SceneError::param("haze", format!("{} has no collimated beam (directional light), and haze shows only beams", g.path.display())));
            }
            scene.haze = h;
        }
        if let Some(gather) = o.indirect_gather {
            scene.indirect_gather = gather;
        }
        if o.no_dispersion {
            for m in &mut scene.media {
                if let Medium::Glass { ior, .. } = m {
                    *ior = IorModel::Constant(ior.n(glass::lines::LD));
                }
            }
        }
        if o.no_prism {
            scene.faces.retain(|f| !matches!(f.surface, Surface::Interface { .. }));
            scene.spheres.retain(|s| !matches!(s.surface, Surface::Interface { .. }));
            reindex(&mut scene);
        }
        scene.build_accel();
        return Ok(scene);
    }
    let mut scene = match o.kind {
        SceneKind::AmiciScreen | SceneKind::AmiciLamp | SceneKind::AmiciBench => amici::build(o)?,
        SceneKind::SinglePrism => single_prism::build(o)?,
        SceneKind::SphereArealight | SceneKind::SphereMetal | SceneKind::SpheresFinal => spheres::build(o)?,
        SceneKind::CornellPointlight | SceneKind::CornellMirrorTube | SceneKind::CornellLaser => cornell::build(o)?,
        SceneKind::DarkSide => cornell::dark_side(o)?,
    };
    if let Some(h) = o.haze {
        // Haze shows beams only (`spectral::haze`): elsewhere it would
        // change nothing.
        if h > 0.0 && !scene.lights.iter().any(|l| matches!(l.emission, Emission::Beam { .. })) {
            return Err(SceneError::param("haze", format!("the {} scene has no collimated beam, and haze shows only beams", o.kind.name())));
        }
        scene.haze = h;
    }
    if let Some(g) = o.indirect_gather {
        scene.indirect_gather = g;
    }
    if let Some(path) = &o.obj {
        // The user's mesh replaces the prism; beam, screen and camera stay
        // where the built-in prism put them.
        let mesh = crate::mesh::obj::read_obj(path)?;
        if mesh.triangles.is_empty() {
            return Err(SceneError::param("obj", format!("{} has no usable faces to make a prism of", path.display())));
        }
        let keep: Vec<Face> = scene.faces.drain(..).filter(|f| !matches!(f.surface, Surface::Interface { .. })).collect();
        for (i, t) in mesh.triangles.iter().enumerate() {
            let v: Vec<DVec3> = t.iter().map(|&k| mesh.positions[k as usize].as_dvec3()).collect();
            let n = (v[1] - v[0]).cross(v[2] - v[0]);
            scene.faces.push(Face::polygon(&format!("obj triangle {i}"), v, n, Surface::Interface { front: 0, back: 1 }));
        }
        scene.faces.extend(keep);
        reindex(&mut scene);
    }
    if o.no_prism {
        scene.faces.retain(|f| !matches!(f.surface, Surface::Interface { .. }));
        reindex(&mut scene);
    }
    scene.build_accel();
    Ok(scene)
}

/// After faces were removed or added: the matte-surface list and the area
/// lights' face indices follow the faces.
fn reindex(scene: &mut World) {
    scene.maps = scene.faces.iter().enumerate().filter(|(_, f)| matches!(f.surface, Surface::Diffuse { .. })).map(|(i, _)| i).collect();
    for (li, l) in scene.lights.iter_mut().enumerate() {
        if let Emission::Area { face } = &mut l.emission {
            *face = scene.faces.iter().position(|f| f.surface == Surface::Emitter { light: li }).expect("each area light keeps its face");
        }
        if let Emission::Sphere { sphere } = &mut l.emission {
            *sphere = scene.spheres.iter().position(|s| s.surface == Surface::Emitter { light: li }).expect("each spherical light keeps its sphere");
        }
    }
}

pub(crate) fn light_spectrum(o: &SceneOptions, default: &str) -> Result<Spectrum> {
    match &o.light {
        Some(l) => Ok(l.spectrum.clone()),
        None => Ok(Spectrum::light(default)?),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_build_with_consistent_faces() {
        for kind in [SceneKind::AmiciScreen, SceneKind::AmiciLamp, SceneKind::SinglePrism] {
            let s = build(&SceneOptions::new(kind)).unwrap();
            // Amici: 3 parts x 3 sides - 2 cemented + 6 caps = 13; single: 5.
            let interfaces = s.faces.iter().filter(|f| matches!(f.surface, Surface::Interface { .. })).count();
            assert_eq!(interfaces, if kind == SceneKind::SinglePrism { 5 } else { 13 }, "{kind:?}");
            let mut o = SceneOptions::new(kind);
            o.no_prism = true;
            let s = build(&o).unwrap();
            assert!(s.faces.iter().all(|f| !matches!(f.surface, Surface::Interface { .. })));
        }
        let mut o = SceneOptions::new(SceneKind::AmiciScreen);
        o.flint_apex_deg = 150.0;
        assert!(build(&o).unwrap_err().to_string().contains("--flint-apex"));
        o.flint_apex_deg = 90.0;
    }
}
