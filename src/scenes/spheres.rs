//! Report 001's scenes: glass spheres (the Fraunhofer-line index model by
//! default in its figures) before black-body lights. Light travels along
//! +x; z is up.
//!
//! - `sphere-arealight`: a glass sphere hanging before a spherical
//!   black-body light, slightly off centre and hidden behind it: the
//!   sphere shows the light as an off-centre patch, violet-blue-fringed on
//!   the edge toward the sphere's centre and orange-red on the outer one
//!   (blue bends more, so its image of the light lies nearer the centre;
//!   docs/physics.md §22), against a glowing checkerboard that shows the
//!   glass itself, inverted in it with every edge fringed the same way.
//! - `sphere-metal`: the sphere before a brass plate grazed from the right
//!   by a warm (2000 K) black-body light out of view: the plate's glow falls
//!   off from right to left, the sphere shows it inverted, and where the
//!   display clips the bright end to yellow the sphere runs from yellow on
//!   its left to red-orange on its right (report 001's description).
//! - `spheres-final`: where the wavelength effects show at a glance: a
//!   white beam through a hole in a card onto a glass sphere, which sends
//!   back a rainbow ring round the hole (one reflection inside;
//!   docs/physics.md §21), and shows the card and ring inverted in itself.

use super::Result;
use super::{glass_medium, light_spectrum, matte, SceneKind, SceneOptions};
use crate::world::{Camera, Emission, Face, Light, Sphere, Surface, World};
use glam::DVec3;

/// A glass sphere (the scene's medium 1 inside, air outside).
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

/// Builds the sphere scene `o.kind` names.
pub fn build(o: &SceneOptions) -> Result<World> {
    let glass = glass_medium(o.crown, o.ior, o.no_dispersion);
    let mut s = super::with_glass(o, glass);
    match o.kind {
        SceneKind::SphereArealight => area_light(&mut s, o)?,
        SceneKind::SphereMetal => metal_plate(&mut s, o)?,
        _ => rainbow_card(&mut s, o)?,
    }
    s.probe = (DVec3::ZERO, DVec3::X);
    Ok(s)
}

/// Report 001's sphere before a spherical area light, with a light box
/// of squares behind it to show the glass.
fn area_light(s: &mut World, o: &SceneOptions) -> Result<()> {
    if !o.no_prism {
        glass_sphere(s, "glass sphere", DVec3::new(3.0, 0.0, 0.0), 0.5);
    }
    // The sphere "hanging in front of a spherical area light source,
    // which is slightly off center" (report 001): a 6500 K black
    // body of 12 cm radius, 1.2 m behind the sphere and 12 degrees
    // up and to the left of its axis, so that from the camera it is
    // hidden behind the sphere (1.7-5.1 degrees off the camera's
    // axis; the sphere covers 9.6) and shows only through it, as an
    // off-centre patch down and to the right, fringed violet-blue
    // on the edge toward the sphere's centre and orange-red on the
    // outer one (docs/physics.md §22).
    let (angle, distance, radius) = (12f64.to_radians(), 1.2, 0.12);
    let dir = DVec3::new(angle.cos(), angle.sin() * 0.8, angle.sin() * 0.6);
    sphere_light(s, o, DVec3::new(3.0, 0.0, 0.0) + distance * dir, radius, "blackbody:6500")?;
    // So that the glass itself is seen (a clear sphere before black
    // shows only what it refracts): a light box 1.6 m behind the
    // sphere, a checkerboard of 30 cm squares glowing at 10 % of the
    // lamp's radiance (a dimmer plane behind them, at 15 % of that,
    // makes the dark squares), offset half a square from the axis.
    // The sphere shows it inverted and minified, every edge of it
    // fringed like the lamp's; a photographer's backlit pattern.
    // Emitters only (no matte surface, no photons): no sampling
    // noise outside the glass. Where rays bent near the rim miss the
    // box (3.6 m square), the ball shows a dark ring as real ones do.
    let (wall, tile, n) = (4.6, 0.3, 6i32);
    let bright = 0.1 * tile * tile / (4.0 * std::f64::consts::PI * radius * radius);
    let half = n as f64 * tile;
    let light = s.lights.len();
    s.faces.push(Face::rect(
        "light box",
        DVec3::new(wall + 0.001, half, -half),
        DVec3::new(0.0, -2.0 * half, 0.0),
        DVec3::new(0.0, 0.0, 2.0 * half),
        Surface::Emitter { light },
    ));
    s.lights.push(Light {
        name: "light box".into(),
        emission: Emission::Area { face: s.faces.len() - 1 },
        spectrum: light_spectrum(o, "blackbody:6500")?,
        power: 0.15 * bright * (2 * n * 2 * n) as f64,
    });
    for i in -n..n {
        for j in -n..n {
            if (i + j).rem_euclid(2) == 0 {
                continue;
            }
            let light = s.lights.len();
            let corner = DVec3::new(wall, (i as f64 + 1.5) * tile, (j as f64 + 0.5) * tile);
            s.faces.push(Face::rect("light box square", corner, DVec3::new(0.0, -tile, 0.0), DVec3::new(0.0, 0.0, tile), Surface::Emitter { light }));
            s.lights.push(Light {
                name: "light box square".into(),
                emission: Emission::Area { face: s.faces.len() - 1 },
                spectrum: light_spectrum(o, "blackbody:6500")?,
                power: bright,
            });
        }
    }
    // A 21.7 degree field: the whole sphere in the frame's height
    // (its image 158 px in radius at 640x360), room beside it for
    // the inset that magnifies a fringe (`inset` in the scene file).
    s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 21.7, o.width, o.height);
    Ok(())
}

/// Report 001's sphere before a brass plate lit by a lamp out of view.
fn metal_plate(s: &mut World, o: &SceneOptions) -> Result<()> {
    if !o.no_prism {
        glass_sphere(s, "glass sphere", DVec3::new(3.0, 0.0, 0.0), 0.5);
    }
    // A brass plate behind the sphere, grazed from the right by a
    // warm lamp out of view: its light falls off from right to left
    // (from 0.5 m to 5 m away), and the sphere shows it inverted.
    matte(s, "metal plate", DVec3::new(5.5, 3.5, -2.5), DVec3::new(0.0, -5.7, 0.0), DVec3::new(0.0, 0.0, 5.0), [0.95, 0.4, 0.15]);
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
    Ok(())
}

/// Report 001's final scene: a beam through a hole in a card onto a glass
/// sphere, which rings the hole with a rainbow.
fn rainbow_card(s: &mut World, o: &SceneOptions) -> Result<()> {
    // A white beam through a square hole in a white card onto a
    // glass sphere 2.5 m away: light that reflects once inside the
    // sphere comes back at the rainbow angle (about 4.7 degrees off
    // the beam for N-SF11, 21 for N-BK7) and rings the hole with a
    // rainbow, red outside (Descartes; docs/physics.md §21). The beam
    // is 0.7 of the sphere's radius wide: the rainbow's rays enter
    // at about half the radius.
    let r = 0.15;
    let centre = DVec3::new(2.5, 0.0, 0.0);
    if !o.no_prism {
        glass_sphere(s, "glass sphere", centre, r);
    }
    let (hole, beam) = (0.11, 0.7 * r);
    // Four pieces round the hole, facing the sphere (+x).
    for (name, y0, y1, z0, z1) in [
        ("card left of the hole", -1.6, -hole, -1.2, 1.2),
        ("card right of the hole", hole, 1.6, -1.2, 1.2),
        ("card below the hole", -hole, hole, -1.2, -hole),
        ("card above the hole", -hole, hole, hole, 1.2),
    ] {
        matte(s, name, DVec3::new(0.0, y0, z0), DVec3::new(0.0, y1 - y0, 0.0), DVec3::new(0.0, 0.0, z1 - z0), [0.8; 3]);
    }
    s.lights.push(Light {
        name: "white beam".into(),
        emission: Emission::Beam {
            centre: DVec3::new(-0.01, 0.0, 0.0),
            dir: DVec3::X,
            u: DVec3::Y,
            v: DVec3::Z,
            half: glam::DVec2::new(beam, beam),
            disc: true,
            polarisation: None,
        },
        spectrum: light_spectrum(o, "d65")?,
        power: 1.0,
    });
    card_lamps(s, o)?;
    s.photon_shares = Some(vec![1.0, 1e-9, 1e-9]);
    s.direct_lighting = true;
    s.camera = Camera::look_at(DVec3::new(4.6, 0.45, 0.3), DVec3::new(0.0, -0.15, 0.0), DVec3::Z, 20.0, o.width, o.height);
    Ok(())
}

/// The spheres-final card's two lamps, which send no photons: one over the
/// card and one behind its hole.
fn card_lamps(s: &mut World, o: &SceneOptions) -> Result<()> {
    // A dim lamp in the ceiling over the card, so the card and the
    // sphere show: its direct light by shadow rays (the sphere
    // cannot shade the card from it), and no photons (the sphere
    // meets about 0.2 % of its light and reflects a few per cent of
    // that, over all directions: about 1e-4 of what the lamp gives
    // the card directly).
    let lamp = s.lights.len();
    s.faces.push(Face::rect(
        "ceiling lamp",
        DVec3::new(0.3, -1.5, 3.0),
        DVec3::new(0.0, 3.0, 0.0),
        DVec3::new(1.5, 0.0, 0.0),
        Surface::Emitter { light: lamp },
    ));
    s.lights.push(Light { name: "ceiling lamp".into(), emission: Emission::Area { face: s.faces.len() - 1 }, spectrum: light_spectrum(o, "d65")?, power: 1.2 });
    // The beam's source seen through the hole, as the sun or a
    // projector is from the sphere's side of a card: a bright face
    // behind the card, lighting nothing the camera sees but the
    // hole (it sends no photons; its direct light falls on the
    // card's back and, through the hole, on the glass, which takes
    // none).
    let source = s.lights.len();
    s.faces.push(Face::rect(
        "beam source",
        DVec3::new(-0.3, -0.4, -0.4),
        DVec3::new(0.0, 0.8, 0.0),
        DVec3::new(0.0, 0.0, 0.8),
        Surface::Emitter { light: source },
    ));
    s.lights.push(Light { name: "beam source".into(), emission: Emission::Area { face: s.faces.len() - 1 }, spectrum: light_spectrum(o, "d65")?, power: 0.5 });
    Ok(())
}
