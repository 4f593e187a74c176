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
//! - `sphere-metal`: the sphere 16 cm before a lit, brushed metal plate
//!   (a strip light's line and a broad sheen on it), just short of the
//!   ball's focus: the sphere magnifies the line into a bright lens ringed
//!   by a broad band fading from yellow to red; with no colour in the
//!   plate or the lights, the colour is the dispersion.
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
    // The faint copy of the lamp seen after two reflections inside the
    // glass (R^2, near the sphere's centre) is followed whole, not by the
    // min(1, 4R) chance that printed it as coloured grain.
    s.eye_follow_reflections = 3;
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

/// Report 001's sphere before a lit, brushed metal plate.
fn metal_plate(s: &mut World, o: &SceneOptions) -> Result<()> {
    if !o.no_prism {
        glass_sphere(s, "glass sphere", DVec3::new(3.0, 0.0, 0.0), 0.5);
    }
    // The plate, 2 m by 1.5 m, stands 0.66 m behind the sphere's centre
    // (16 cm behind the glass), square to the camera. Seen from the
    // camera 3 m away, the ball (N-SF11, radius R) brings the camera's
    // rays to a focus at v behind its centre, 1/v = 1/f - 1/(3 m) with
    // f = nR / 2(n - 1) (the ball lens; docs/physics.md §22): 0.675 m at
    // 436 nm, 0.689 at 589, 0.708 at 656 nm (the paraxial foci); rays
    // through the outer zones focus nearer (spherical aberration). A ray
    // through a zone meets the plate at (1 - d / v_zone) of its height: near
    // the centre the plate is short of every colour's focus, blue's the
    // nearest, so blue's image of the line is the largest (at 0.66 m,
    // 1 - d / v is 2.2 % at 436 nm against 6.8 % at 656: a bluish centre);
    // the outer zones focus in front of the plate, blue's nearest again,
    // and there blue's image is the smallest: round the bright lens the
    // colours drop out from blue on, leaving a broad band that fades from
    // yellow through orange to red. Nearer the focus the pattern breaks
    // into rings; farther (0.75 m) the band narrows to a fringe.
    // The plate's look is light it sends (the renderer's metal is a
    // perfect mirror, which 16 cm behind the ball would show a second
    // sphere): brushed aluminium under a strip light, whose reflection
    // the brushing spreads across the grain into a vertical line with a
    // broad, soft sheen either side (plate_sheen). All lights are glowing
    // surfaces, 6500 K black bodies (no photons, no matte surface): no
    // sampling noise outside the glass, and every colour in the image is
    // the glass's dispersion.
    let (w, h) = (2.0, 1.5);
    let x = 3.66;
    for (y0, y1) in sheen_strips(0.5 * w) {
        let radiance = plate_sheen(0.5 * (y0 + y1));
        glow(s, o, "metal plate", [DVec3::new(x, y1, -0.5 * h), DVec3::new(0.0, y0 - y1, 0.0), DVec3::new(0.0, 0.0, h)], radiance)?;
    }
    // A near-black wall round the plate (1 % of the line's radiance) and a
    // dim room behind the camera (2 %), which the glass reflects faintly.
    glow(s, o, "back wall", [DVec3::new(7.0, 6.0, -4.0), DVec3::new(0.0, -12.0, 0.0), DVec3::new(0.0, 0.0, 8.0)], 0.01)?;
    glow(s, o, "front wall", [DVec3::new(-3.0, -30.0, -6.0), DVec3::new(0.0, 60.0, 0.0), DVec3::new(0.0, 0.0, 12.0)], 0.02)?;
    // A 22 degree field (vertical): the plate fills the frame edge to edge
    // (1.42 m by 1.9 m of it in view at 4:3), so the picture is all lit
    // metal with no grey border, and the sphere, whole, spans about 87 %
    // of the frame's height.
    s.camera = Camera::look_at(DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 22.0, o.width, o.height);
    Ok(())
}

/// The brushed plate's radiance at `y` metres across it (relative to the
/// line's): a dim base (3 %), a broad sheen (10 %, 0.35 m standard
/// deviation) and the strip light's line, 8 mm wide with 3 mm soft edges.
pub fn plate_sheen(y: f64) -> f64 {
    let line = 1.0 / (1.0 + ((y.abs() - 0.004) / 0.003).exp());
    0.03 + 0.1 * (-0.5 * (y / 0.35).powi(2)).exp() + line
}

/// Vertical strips (left and right edges, metres) that tile the plate
/// from -half to half: 1 mm wide over the line, widening away from it.
pub fn sheen_strips(half: f64) -> Vec<(f64, f64)> {
    let (mut edges, mut y, mut step) = (vec![0.0], 0.0, 0.001);
    while y < half {
        y = (y + step).min(half);
        edges.push(y);
        if y > 0.02 {
            step = (step * 1.25).min(0.04);
        }
    }
    let mut strips: Vec<(f64, f64)> = edges.windows(2).map(|e| (e[0], e[1])).collect();
    strips.extend(edges.windows(2).map(|e| (-e[1], -e[0])));
    strips
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
    // The source stands 0.8 m behind the card and is 0.3 m square: from
    // the sphere, on the beam's axis, it fills the hole; from the camera,
    // which looks through the hole at about 21 degrees, the line of sight
    // lands 0.2-0.4 m to the side of it, on the wall in the card's shadow,
    // so the hole reads as a hole (darker than the card), not as a lit
    // white square. Its radiance is the old 0.8 m face's (0.5 over 0.64 m^2).
    let source = s.lights.len();
    s.faces.push(Face::rect(
        "beam source",
        DVec3::new(-0.8, -0.15, -0.15),
        DVec3::new(0.0, 0.3, 0.0),
        DVec3::new(0.0, 0.0, 0.3),
        Surface::Emitter { light: source },
    ));
    s.lights.push(Light {
        name: "beam source".into(),
        emission: Emission::Area { face: s.faces.len() - 1 },
        spectrum: light_spectrum(o, "d65")?,
        power: 0.5 * 0.09 / 0.64,
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sheen_strips_tile_the_plate_finely_over_the_line() {
        let strips = sheen_strips(1.0);
        let total: f64 = strips.iter().map(|(a, b)| b - a).sum();
        assert!((total - 2.0).abs() < 1e-9, "the strips cover the plate: {total} m");
        assert!(strips.iter().all(|(a, b)| b > a), "every strip has width");
        let over_line: Vec<_> = strips.iter().filter(|(a, b)| a.abs().max(b.abs()) <= 0.008).collect();
        assert!(over_line.len() >= 14, "the line and its soft edges are drawn by at least 14 strips: {}", over_line.len());
        assert!(over_line.iter().all(|(a, b)| b - a < 0.0011), "1 mm strips over the line");
        assert!(strips.len() < 150, "few faces: {}", strips.len());
    }

    #[test]
    fn the_plate_is_brightest_on_its_line_and_never_black() {
        assert!(plate_sheen(0.0) > 0.9 && plate_sheen(0.02) < 0.2, "a sharp line");
        assert!(plate_sheen(0.3) > 2.0 * plate_sheen(1.0), "a broad sheen falling off");
        assert!(plate_sheen(1.0) >= 0.03, "the base");
    }
}
