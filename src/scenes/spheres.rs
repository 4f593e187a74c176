//! Report 001's scenes: glass spheres (the Fraunhofer-line index model by
//! default in its figures) before black-body lights. Light travels along
//! +x; z is up.
//!
//! - `sphere-arealight`: a glass sphere hanging before a large spherical
//!   black-body light off centre: the sphere shows the light as an
//!   off-centre patch, blue-fringed on the edge toward the sphere's centre
//!   and orange-red on the outer one (blue bends more, so its image of the
//!   light lies nearer the centre; the fringes are the spread of a ball's
//!   deviation over the visible, at most about 2 % of its radius for N-SF11).
//! - `sphere-metal`: the sphere before a brass plate grazed from the right
//!   by a warm (2000 K) black-body light out of view: the plate's glow falls
//!   off from right to left, the sphere shows it inverted, and where the
//!   display clips the bright end to yellow the sphere runs from yellow on
//!   its left to red-orange on its right (report 001's description).
//! - `spheres-final`: three flint spheres before two bright bar lights, where
//!   the wavelength effects show clearly.

use super::{glass_medium, light_spectrum, SceneKind, SceneOptions};
use crate::world::{Camera, Emission, Face, Light, Sphere, Surface, World};
use anyhow::Result;
use glam::DVec3;

/// A matte parallelogram with its own photon map.
fn glass_sphere(s: &mut World, name: &str, centre: DVec3, radius: f64) {
    s.spheres.push(Sphere { name: name.into(), centre, radius, surface: Surface::Interface { front: 0, back: 1 } });
}

fn sphere_light(s: &mut World, o: &SceneOptions, centre: DVec3, radius: f64, default: &str) -> Result<()> {
    let light = s.lights.len();
    s.spheres.push(Sphere { name: "light".into(), centre, radius, surface: Surface::Emitter { light } });
    s.lights.push(Light {
        name: "sphere light".into(),
        emission: Emission::Sphere { sphere: s.spheres.len() - 1 },
        spectrum: light_spectrum(o, default)?,
        power: 1.0,
    });
    Ok(())
}

/// An equilateral prism's cross-section centred at `c`, turned so that
/// light of index `n` passing at minimum deviation leaves along `exit`
/// (radians from +x). Unturned, the apex points +y and that light leaves
pub fn build(o: &SceneOptions) -> Result<World> {
    let glass = glass_medium(o.crown, o.ior, o.no_dispersion);
    let mut s = super::with_glass(o, glass);
    match o.kind {
        SceneKind::SphereArealight => {
            if !o.no_prism {
                glass_sphere(&mut s, "glass sphere", DVec3::new(3.0, 0.0, 0.0), 0.5);
            }
            // Seen from the sphere the light spans 6-56 degrees off the axis,
            // clear of it, so the sphere shows it as an off-centre patch with
            // a blue inner and an orange-red outer edge; from the camera the
            // sphere stands dark against the light's edge.
            sphere_light(&mut s, o, DVec3::new(6.0, 1.8, 0.3), 1.5, "blackbody:6500")?;
            s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 20.0, o.width, o.height);
        }
        SceneKind::SphereMetal => {
            if !o.no_prism {
                glass_sphere(&mut s, "glass sphere", DVec3::new(3.0, 0.0, 0.0), 0.5);
            }
            // A brass plate behind the sphere, grazed from the right by a
            // warm lamp out of view: its light falls off from right to left
            // (from 0.5 m to 5 m away), and the sphere shows it inverted.
            let plate = crate::world::Albedo::new([0.95, 0.4, 0.15]);
            s.faces.push(Face::rect(
                "metal plate",
                DVec3::new(5.5, 3.5, -2.5),
                DVec3::new(0.0, -5.7, 0.0),
                DVec3::new(0.0, 0.0, 5.0),
                Surface::Diffuse { albedo: plate, map: 0 },
            ));
            s.maps.push(s.faces.len() - 1);
            // A small warm lamp (a point: no highlight of it in the glass,
            // and no sampling noise in the plate's light) 0.5 m in front of
            // the plate's right end, out of the camera's view.
            s.lights.push(Light {
                name: "warm lamp".into(),
                emission: Emission::Point { pos: DVec3::new(5.0, -2.6, 0.0) },
                spectrum: light_spectrum(o, "blackbody:2000")?,
                power: 1.0,
            });
            s.direct_lighting = true;
            s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 30.0, o.width, o.height);
        }
        _ => {
            if !o.no_prism {
                glass_sphere(&mut s, "sphere 1", DVec3::new(3.0, -0.7, 0.1), 0.38);
                glass_sphere(&mut s, "sphere 2", DVec3::new(3.6, 0.15, -0.15), 0.45);
                glass_sphere(&mut s, "sphere 3", DVec3::new(3.2, 0.85, 0.2), 0.3);
            }
            // Two tall bright bars behind them: each sphere shows them
            // inverted, with coloured edges.
            for (k, y) in [-0.55, 0.35].into_iter().enumerate() {
                let light = s.lights.len();
                s.faces.push(Face::rect(
                    &format!("bar light {k}"),
                    DVec3::new(5.0, y, -1.5),
                    DVec3::new(0.0, 0.0, 3.0),
                    DVec3::new(0.0, 0.3, 0.0),
                    Surface::Emitter { light },
                ));
                s.lights.push(Light {
                    name: format!("bar {k}"),
                    emission: Emission::Area { face: s.faces.len() - 1 },
                    spectrum: light_spectrum(o, "blackbody:5500")?,
                    power: 1.0,
                });
            }
            s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 32.0, o.width, o.height);
        }
    }
    s.probe = (DVec3::ZERO, DVec3::X);
    Ok(s)
}
