//! Report 001's scenes: glass spheres (the Fraunhofer-line index model by
//! default in its figures) before black-body lights. Light travels along
//! +x; z is up.
//!
//! - `sphere-arealight`: a glass sphere hanging before a spherical
//!   black-body light, slightly off centre and hidden behind it: the
//!   sphere shows the light, magnified, as an off-centre patch,
//!   violet-blue-fringed on the edge toward the sphere's centre and
//!   orange-red on the outer one (blue bends more, so its image of the
//!   light lies nearer the centre; docs/physics.md §22), against a glowing checkerboard that shows the
//!   glass itself, inverted in it with every edge fringed the same way.
//! - `sphere-metal`: the sphere before a polished, neutral metal plate (a
//!   grey mirror) that reflects a window and a white strip softbox: the
//!   sphere shows the strip's band inverted, fringed blue inside and yellow
//!   to red outside; with no colour in the plate or the lights, the colour
//!   is the dispersion.
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
    // which is slightly off center" (report 001): a 6500 K black body
    // of 7 cm radius, 0.75 m behind the sphere's centre (1.5 of its
    // radius) and 0.1 m up and to the left of its axis, so that from the
    // camera it is hidden behind the sphere and shows only through it, as
    // an off-centre patch down and to the right, fringed violet-blue on
    // the edge toward the sphere's centre and orange-red on the outer one
    // (docs/physics.md §22). An edge at a distance d behind the centre
    // appears where the ray through the glass reaches it; the colours'
    // images of it lie apart by (d dD/dn) dn / (d dD/db - 1), D the
    // deviation and b the height on the sphere: close behind the sphere
    // (d near 1.5 radii, just beyond the ball's focus) the denominator is
    // small and the edge's red and violet images lie about 4 % of the
    // radius apart (400-700 nm, N-SF11), against under 3 % for a light
    // far behind it: fringes about 8 px wide at 1:1 (docs/physics.md §22).
    let (behind, off, radius) = (0.75f64, 0.1, 0.07);
    let (distance, angle) = (behind.hypot(off), (off / behind).atan());
    let dir = DVec3::new(angle.cos(), angle.sin() * 0.8, angle.sin() * 0.6);
    sphere_light(s, o, DVec3::new(3.0, 0.0, 0.0) + distance * dir, radius, "blackbody:6500")?;
    // So that the glass itself is seen (a clear sphere before black
    // shows only what it refracts): a light box 1.6 m behind the
    // sphere, a checkerboard of 30 cm squares glowing at 1.6 % of the
    // lamp's radiance, dim so the light stays the subject (a dimmer plane behind them, at 15 % of that,
    // makes the dark squares), offset half a square from the axis.
    // The sphere shows it inverted and minified, every edge of it
    // fringed like the lamp's; a photographer's backlit pattern.
    // Emitters only (no matte surface, no photons): no sampling
    // noise outside the glass. Where rays bent near the rim miss the
    // box (3.6 m square), the ball shows a dark ring as real ones do.
    let (wall, tile, n) = (4.6, 0.3, 6i32);
    let bright = 0.016 * tile * tile / (4.0 * std::f64::consts::PI * radius * radius);
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
    // A 21 degree field on the sphere's centre: the whole sphere in
    // frame, as large as the frame allows (its disc about 90 % of the
    // frame's height), so the fringes, which scale with its image, are
    // 3-5 px wide at 1:1 with no inset.
    s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 21.0, o.width, o.height);
    Ok(())
}

/// A rectangle (corner and two edges) glowing white (6500 K, unless the
/// options name a light) with `radiance` (relative: a light's power is its
/// radiance times its area), seen by the eye only.
fn glow(s: &mut World, o: &SceneOptions, name: &str, [corner, eu, ev]: [DVec3; 3], radiance: f64) -> Result<()> {
    let light = s.lights.len();
    s.faces.push(Face::rect(name, corner, eu, ev, Surface::Emitter { light }));
    s.lights.push(Light {
        name: name.into(),
        emission: Emission::Area { face: s.faces.len() - 1 },
        spectrum: light_spectrum(o, "blackbody:6500")?,
        power: radiance * eu.cross(ev).length(),
    });
    Ok(())
}

/// Report 001's sphere before a polished metal plate that reflects a
/// white softbox.
fn metal_plate(s: &mut World, o: &SceneOptions) -> Result<()> {
    if !o.no_prism {
        glass_sphere(s, "glass sphere", DVec3::new(3.0, 0.0, 0.0), 0.5);
    }
    // A polished, neutral metal plate 2.6 m by 1.9 m, 2 m behind the
    // sphere and square to the camera's axis: a mirror of flat
    // reflectance 0.9 (polished aluminium; grey, so it adds no colour).
    // Its edges stand in the frame against a near-black wall, and its
    // reflection of the sphere hides behind the sphere itself.
    let c = DVec3::new(5.0, 0.0, 0.0);
    let (w, h) = (2.6, 1.9);
    s.faces.push(Face::rect(
        "metal plate",
        c + DVec3::new(0.0, 0.5 * w, -0.5 * h),
        DVec3::new(0.0, -w, 0.0),
        DVec3::new(0.0, 0.0, h),
        Surface::Mirror { reflectance: 0.9 },
    ));
    // The room, all glowing surfaces (no matte surface, no photons, no
    // sampling noise outside the glass): a near-black wall behind the
    // plate, seen round its edges (0.4 % of the lights' radiance), and
    // behind the camera, reflected in the plate, a dim wall (5 %), a
    // window of six panes (6500 K black bodies) high on the left, which the plate
    // shows in its upper left corner cut by its edge, as a mirror does,
    // and over it a white strip softbox across the room. Both are high
    // and to the side (more than 22 degrees off the axis, from the
    // sphere) so that the glass does not show them by one reflection
    // inside (a faint, grainy copy: Fresnel's few per cent, drawn at
    // random) but only by refraction, as the plate shows them: the
    // sphere shows the plate's light inverted, the strip as a white band
    // fringed blue on the edge toward its centre and yellow to red on
    // the outer one, the window as a small inverted window, each bar
    // fringed the same way (docs/physics.md §22).
    glow(s, o, "back wall", [DVec3::new(7.0, 6.0, -4.0), DVec3::new(0.0, -12.0, 0.0), DVec3::new(0.0, 0.0, 8.0)], 0.004)?;
    glow(s, o, "front wall", [DVec3::new(-3.0, -30.0, -6.0), DVec3::new(0.0, 60.0, 0.0), DVec3::new(0.0, 0.0, 12.0)], 0.05)?;
    // The window: 2.4 m by 1.8 m centred 2.3 m left and 1.25 m up, 12 cm bars.
    let (wy, wz, ww, wh, bar, cols, rows) = (2.3, 1.25, 2.4, 1.8, 0.12, 3, 2);
    let (pw, ph) = ((ww - bar * (cols + 1) as f64) / cols as f64, (wh - bar * (rows + 1) as f64) / rows as f64);
    for i in 0..cols {
        for j in 0..rows {
            let y = wy + ww / 2.0 - bar - i as f64 * (pw + bar) - pw;
            let z = wz - wh / 2.0 + bar + j as f64 * (ph + bar);
            glow(s, o, "window pane", [DVec3::new(-2.9, y, z), DVec3::new(0.0, pw, 0.0), DVec3::new(0.0, 0.0, ph)], 1.0)?;
        }
    }
    // The softbox: a strip 1.3 m tall from 2.2 m up, across the room.
    let strip = 2.2;
    glow(s, o, "softbox", [DVec3::new(-2.9, -10.0, strip), DVec3::new(0.0, 20.0, 0.0), DVec3::new(0.0, 0.0, 1.3)], 1.0)?;
    // A 26 degree field: the sphere large (its fringes scale with its
    // image, docs/physics.md §22), whole, the plate's edges in view.
    s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 26.0, o.width, o.height);
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
    // The camera to the side, so the sphere and the card are seen
    // apart, with the beam (in the scene file's haze) between them.
    s.camera = Camera::look_at(DVec3::new(4.8, 1.9, 0.6), DVec3::new(1.3, -0.05, -0.05), DVec3::Z, 24.0, o.width, o.height);
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
