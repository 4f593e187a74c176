//! The anchor scene (not from a report): a 60 degree prism of `--glass`, a
//! 2 cm round beam at minimum deviation for the d line, and a matte screen
//! 4 m behind, perpendicular to the d line; the camera looks at the screen.
//! Minimum deviation: docs/physics.md §3.

use super::{glass_medium, light_spectrum, rotate_z, SceneOptions};
use super::{Result, SceneError};
use crate::optics::glass::lines;
use crate::optics::ior::IorKind;
use crate::world::probe::probe;
use crate::world::{Albedo, Camera, Emission, Face, Light, Medium, Surface, World};
use glam::{DVec2, DVec3};

pub fn build(o: &SceneOptions) -> Result<World> {
    let g = glass_medium(o.crown, o.ior, o.no_dispersion);
    let apex = 60f64.to_radians();
    let side = 0.05;
    let tall = side * (apex / 2.0).cos();
    let c = tall / 3.0;
    let tri = [DVec2::new(-side / 2.0, -c), DVec2::new(side / 2.0, -c), DVec2::new(0.0, tall - c)];
    let mut scene = World::new(o.kind.name(), vec![Medium::Air, g], o.width, o.height);
    scene.add_extruded("prism", &[(tri, 1)], -0.025, 0.025);
    // Placed from the catalogue (Sellmeier) whatever index model renders it.
    let n_d = o.crown.sellmeier(lines::LD);
    let min_dev_incidence = (n_d * (apex / 2.0).sin()).asin();
    let incidence = o.incidence_deg.map_or(min_dev_incidence, f64::to_radians);
    // The left face's inward normal points at -apex/2 from +x.
    let dir = rotate_z(DVec3::X, -apex / 2.0 + incidence);
    let face_mid = (tri[2] + tri[0]) / 2.0;
    let start = DVec3::new(face_mid.x, face_mid.y, 0.0) - dir * 0.3;
    scene.probe = (start, dir);
    let mut design = scene.clone();
    design.media[1] = glass_medium(o.crown, IorKind::Sellmeier, false);
    let d_line = probe(&design, lines::LD);
    if d_line.tir {
        return Err(SceneError::param("incidence", format!("at {:.3} degrees the d line is totally reflected inside the prism", incidence.to_degrees())));
    }
    let out = d_line.exit_dir;
    let centre = d_line.exit_point + out * 4.0;
    let (width, high) = (0.24, 0.24 * o.height as f64 / o.width as f64);
    let u = out.cross(DVec3::Z).normalize(); // in the xy plane, across the strip
    let corner = centre - u * (width / 2.0) - DVec3::Z * (high / 2.0);
    // Normal u x z = -out: facing the prism.
    scene.faces.push(Face::rect("screen", corner, u * width, DVec3::Z * high, Surface::Diffuse { albedo: Albedo::new([0.8; 3]), map: 0 }));
    scene.maps.push(scene.faces.len() - 1);
    let cam = centre - out * 1.0;
    let vfov = 2.0 * ((high / 2.0) / 1.0).atan().to_degrees();
    scene.camera = Camera::look_at(cam, centre, DVec3::Z, vfov, o.width, o.height);
    let bu = DVec3::Z.cross(dir).normalize();
    scene.lights.push(Light {
        name: "beam".into(),
        emission: Emission::Beam { centre: start, dir, u: bu, v: DVec3::Z, half: DVec2::new(0.01, 0.01), disc: true, polarisation: None },
        spectrum: light_spectrum(o, "D65")?,
        power: 1.0,
    });
    Ok(scene)
}
