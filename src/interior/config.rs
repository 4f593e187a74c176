//! Everything one `refract interior` render needs. Prompts, flags, scene
//! files and sweeps all fill it through `params::interior`, whose rows
//! hold each field's name, range and help; the defaults are here.

use crate::color::Rgb;
use crate::geometry::AccelKind;
use crate::mesh::source::MeshSource;
use glam::Vec3;
use std::path::PathBuf;

crate::named_enum! {
    /// How specular light is composited in the trace-count loop.
    pub enum SpecularOpacity {
        /// As first written in the report: specular scaled by the layer's
        /// opacity, which darkens highlights at trace counts above 0.
        Report = "report",
        /// The report's fix: specular keeps its intensity whatever the opacity.
        Fixed = "fixed",
    }
}

crate::named_enum! {
    /// What surrounds the mesh.
    pub enum SceneKind {
        /// The mesh alone against the background.
        Mesh = "mesh",
        /// The mesh inside a Cornell box (red left wall, green right wall).
        Cornell = "cornell",
        /// The Cornell box with a floor of dark and light tiles, so that a
        /// reflection of the room reads at a glance.
        CornellTiled = "cornell-tiled",
        /// The tiled box closed on the camera's side by a blue wall that
        /// only rays from inside the box meet (the camera sees through its
        /// back, as through a one-way mirror), so that a mirror in the box
        /// reflects a room all round.
        CornellClosed = "cornell-closed",
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct InteriorConfig {
    // The report's 13 prompts, in order.
    pub max_trace: u32,
    /// Opacity 0-100 as the report takes it.
    pub opacity: f32,
    pub color: [u8; 3],
    pub out: PathBuf,
    pub off: MeshSource,
    /// Use the colours stored in the OFF file.
    pub coff: bool,
    pub scale: f32,
    /// Rotations about X, then Y, then Z, in degrees.
    pub rot: Vec3,
    pub ior: f32,
    // What the report fixed in its code.
    pub shininess: f32,
    /// c in the attenuation 1 / (1 + c d^2); 0 = none; `None` = the
    /// scene's own (`attenuation`).
    pub atten: Option<f32>,
    /// Light position; `None` = centre of the mesh's bounding box.
    pub light: Option<Vec3>,
    pub light_color: Rgb,
    pub ka: f32,
    pub kd: f32,
    /// Kd of the Cornell walls; `None` = `kd`.
    pub wall_kd: Option<f32>,
    pub ks: f32,
    pub width: usize,
    pub height: usize,
    pub background: [u8; 3],
    /// The camera's exposure: every pixel's colour is multiplied by it
    /// before the 8-bit image is written (a display setting, not part of
    /// the report's model; 1 = the model's colour as it is).
    pub exposure: f32,
    /// How colours brighter than white are shown (a display setting).
    pub tone: super::tone::Tone,
    pub specular_opacity: SpecularOpacity,
    pub scene: SceneKind,
    pub accel: AccelKind,
    /// Worker threads; 0 = all cores.
    pub threads: usize,
    /// Samples per pixel: 1 = the pixel centre (the report); more are
    /// jittered with `seed`.
    pub spp: u32,
    pub seed: u64,
    /// Distance a secondary ray starts off its surface (scene units; the
    /// mesh is normalised to radius `scale`).
    pub offset: f32,
    /// Radius of the bulb: the point light drawn as a small glowing bead
    /// seen through the mesh's faces (`interior::bulb`; a drawn marker, not
    /// part of the report's model); 0 = not drawn, as in the report.
    pub bulb: f32,
    /// Draw, on each face the light inside meets, the circle where it meets
    /// it at the critical angle asin(1/n): the edge of the circle of
    /// outcoming light (a drawn guide, not part of the report's model).
    pub tir_circle: bool,
    /// Count the diffuse light of a light behind a translucent face only
    /// where that light gets out through the face (inside the critical
    /// circle), as the report counts its specular: a frosted face glows
    /// inside the circle of outcoming light and not beyond it (a choice,
    /// not the report's diffuse term; docs/physics.md §10).
    pub diffuse_tir: bool,
    /// Weight the diffuse and specular of a light behind a translucent
    /// face by the Fresnel transmittance T = 1 - R of the light's way out
    /// (docs/physics.md §2): the circle of outcoming light fades to 0 at
    /// its edge, the critical angle, instead of ending in a step (a
    /// choice, not the report's terms; docs/physics.md §10).
    pub fresnel_exit: bool,
}

impl InteriorConfig {
    /// The attenuation constant c in effect: as set, else 1 around the mesh
    /// alone (radius 1: the far side at about half the light) and 0.1 in the
    /// Cornell boxes, whose walls stand 1.6 to 2.5 units from the light (at
    /// c = 1 they would get a fifth of it and read nearly black; at 0.1 two
    /// thirds, as the shipped Cornell scenes set).
    pub fn attenuation(&self) -> f32 {
        self.atten.unwrap_or(match self.scene {
            SceneKind::Mesh => 1.0,
            SceneKind::Cornell | SceneKind::CornellTiled | SceneKind::CornellClosed => 0.1,
        })
    }

    /// Defaults of the report's results section (opacity 25, white mesh and
    /// light, shininess 16, trace 0) for a given mesh.
    pub fn with_defaults(off: MeshSource, out: PathBuf) -> Self {
        InteriorConfig {
            max_trace: 0,
            opacity: 25.0,
            color: [255, 255, 255],
            out,
            off,
            coff: false,
            scale: 1.0,
            rot: Vec3::ZERO,
            ior: 1.4,
            shininess: 16.0,
            atten: None,
            light: None,
            light_color: Rgb::WHITE,
            ka: 0.1,
            kd: 0.5,
            wall_kd: None,
            ks: 0.8,
            width: 401,
            height: 401,
            background: [0, 0, 0],
            exposure: 1.0,
            tone: super::tone::Tone::Clip,
            specular_opacity: SpecularOpacity::Report,
            scene: SceneKind::Mesh,
            accel: AccelKind::Bvh,
            threads: 0,
            spp: 1,
            seed: 0,
            offset: 1e-4,
            bulb: 0.0,
            tir_circle: false,
            diffuse_tir: false,
            fresnel_exit: false,
        }
    }
}
