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
    // body of 15 cm radius, 1.2 m behind the sphere and 16 degrees
    // up and to the left of its axis, so that from the camera it is
    // hidden behind the sphere (2.5-6.6 degrees off the camera's
    // axis; the sphere covers 9.6) and shows only through it, as an
    // off-centre patch down and to the right, fringed violet-blue
    // on the edge toward the sphere's centre and orange-red on the
    // outer one (docs/physics.md §22). The fringes' width grows with
    // the patch's distance from the sphere's centre (the index
    // changes the sphere's power, so the image of an edge a distance
    // b from the centre moves by about b dn / (n (n - 1))): 16 degrees
    // puts the patch at about 0.6 of the radius, still wide.
    let (angle, distance, radius) = (16f64.to_radians(), 1.2, 0.15);
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
    // A 15 degree field aimed a little below and right of the
    // sphere's centre: the sphere fills the frame as a lens ball does
    // in a close-up (its image about 270 px in radius at 560x420, its
    // rim in view left and right), and the fringes, which scale with
    // it, are 3-4 px wide at 1:1 with no inset.
    s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, -0.06, -0.03), DVec3::Z, 15.0, o.width, o.height);
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
    // A white card 1.2 m by 0.9 m (its edges in view, so it reads as
    // a card; the ring, about 0.3 m in radius, lies well inside it)
    // in four pieces round the hole, facing the sphere (+x).
    let (hole, beam) = (0.11, 0.7 * r);
    let (half_w, half_h) = (0.6, 0.45);
    for (name, y0, y1, z0, z1) in [
        ("card left of the hole", -half_w, -hole, -half_h, half_h),
        ("card right of the hole", hole, half_w, -half_h, half_h),
        ("card below the hole", -hole, hole, -half_h, -hole),
        ("card above the hole", -hole, hole, hole, half_h),
    ] {
        matte(s, name, DVec3::new(0.0, y0, z0), DVec3::new(0.0, y1 - y0, 0.0), DVec3::new(0.0, 0.0, z1 - z0), [0.8; 3]);
    }
    // A dark grey wall 1 m behind the card (albedo 0.2 against the
    // card's 0.8): the card stands out from it, and the sphere shows
    // the room, not a void, round the card's inverted image.
    matte(s, "back wall", DVec3::new(-1.0, -5.0, -3.0), DVec3::new(0.0, 10.0, 0.0), DVec3::new(0.0, 0.0, 6.0), [0.2; 3]);
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
    // A lamp in the ceiling over the card, so the card, the wall and
    // the sphere show (the card about 95 of 255, the wall 50): its direct light by shadow rays (the sphere
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
    s.lights.push(Light {
        name: "ceiling lamp".into(),
        emission: Emission::Area { face: s.faces.len() - 1 },
        spectrum: light_spectrum(o, "d65")?,
        power: 12.0,
    });
    // The beam's source seen through the hole, as the sun or a
    // projector is from the sphere's side of a card: a bright face
    // behind the card, lighting nothing the camera sees but the
    // hole (it sends no photons; its direct light falls on the
    // card's back and, through the hole, on the glass, which takes
    // none). The glass shows it, and the ring, a second time, faint
    // and small, above and right of its centre: the light that
    // reflects twice inside the sphere (Fresnel R^2, about 0.6 % at
    // N-SF11) before it leaves toward the camera. On the old dark
    // card that copy showed as a ghost circle; on the lit card and
    // wall it is under 5 of 255 levels.
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
