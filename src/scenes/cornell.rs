//! Report 003's scenes (z up; prisms stand on the floor):
//!
//! - `cornell-pointlight`, `cornell-mirror-tube`, `cornell-laser`: a glass
//!   prism on the floor of a Cornell box lit by a bare point light (a faint
//!   rainbow), by the same light at the end of a mirror tube (brighter),
//!   and by a laser (a bright fan).
//! - `dark-side`: a white beam grazing a dark backdrop through a prism
//!   standing on it, fanning into a spectrum, seen from above: the album
//!   cover, with the prism level and its top edges glowing white.

use super::Result;
use super::{glass_medium, light_spectrum, matte, rotate_z, SceneKind, SceneOptions, View};
use crate::spectrum::Spectrum;
use crate::world::interface::Polarisation;
use crate::world::{Camera, Emission, Face, Light, Surface, World};
use glam::{DVec2, DVec3};

/// An equilateral prism's cross-section centred at `c`, turned so that
/// light of index `n` passing at minimum deviation leaves along `exit`
/// (radians from +x). Unturned, the apex points +y and that light leaves
/// at 30 deg - theta1, with sin theta1 = n sin 30 deg.
fn prism_cross_section(c: DVec2, side: f64, n: f64, exit: f64) -> [DVec2; 3] {
    let tall = side * 3f64.sqrt() / 2.0;
    let theta1 = (n * 0.5f64).min(1.0).asin();
    let turn = DVec2::from_angle(exit - (30f64.to_radians() - theta1));
    [DVec2::new(-side / 2.0, -tall / 3.0), DVec2::new(side / 2.0, -tall / 3.0), DVec2::new(0.0, 2.0 * tall / 3.0)].map(|p| c + turn.rotate(p))
}

/// Direction (in the xy plane) that meets the left face of a prism of
/// `cross` at incidence `incidence` (radians).
fn into_left_face(cross: [DVec2; 3], incidence: f64) -> (DVec3, DVec3) {
    let (apex, left) = (cross[2], cross[0]);
    let edge = (left - apex).normalize();
    let inward = DVec2::new(-edge.y, edge.x); // rotate the edge +90 deg: into the prism
    let angle = inward.y.atan2(inward.x);
    let dir = rotate_z(DVec3::X, angle + incidence);
    let mid = (apex + left) / 2.0;
    (DVec3::new(mid.x, mid.y, 0.0), dir)
}

/// The Cornell box: x in [-1, 1], y in [-1, 1] (back wall at y = 1), z in
/// [0, 2], open toward the camera at y = -1.
fn cornell_box(s: &mut World) {
    let (white, red, green) = ([0.75; 3], [0.75, 0.12, 0.1], [0.12, 0.55, 0.12]);
    let v = DVec3::new;
    matte(s, "floor", v(-1.0, -1.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0), white);
    matte(s, "ceiling", v(-1.0, -1.0, 2.0), v(0.0, 2.0, 0.0), v(2.0, 0.0, 0.0), white);
    matte(s, "back wall", v(-1.0, 1.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 0.0, 2.0), white);
    matte(s, "left wall", v(-1.0, -1.0, 0.0), v(0.0, 2.0, 0.0), v(0.0, 0.0, 2.0), red);
    matte(s, "right wall", v(1.0, -1.0, 0.0), v(0.0, 0.0, 2.0), v(0.0, 2.0, 0.0), green);
}

// One body (over 80 lines): the box, the prism, the light and the camera of one scene family, each variant's choices commented where they are made.
pub fn build(o: &SceneOptions) -> Result<World> {
    let glass = glass_medium(o.crown, o.ior, o.no_dispersion);
    let mut s = super::with_glass(o, glass);
    cornell_box(&mut s);
    s.bounces = 4;
    s.direct_lighting = true;
    // Bounced and mirrored light varies over tens of centimetres in a 2 m
    // room: gathered over 8 times the radius (about 10 cm here).
    s.indirect_gather = 8.0;
    let n_d = o.crown.sellmeier(crate::optics::glass::lines::LD);
    let min_deviation = (n_d * 0.5f64).asin();
    // The laser's prism stands at the front right, wholly in view, lit from
    // the right by a laser on the right wall: its beam crosses the picture
    // level, seen entering the prism's face. The fan crosses the box to the
    // left half of the back wall, meets it at 35 degrees and paints the
    // spectrum there, about 36 cm long. The laser is polarised in the plane
    // of incidence and meets the prism 2 degrees short of minimum
    // deviation, at Brewster's angle (atan n = 61 degrees for N-SF11): its
    // entry and exit reflect almost nothing, so no stray laser spots dot
    // the walls (docs/physics.md §2); the fan spreads a little wider than at
    // minimum deviation (§11: 9.3 instead of 8.6 degrees over 400-700 nm).
    // The other boxes' fan leaves toward the back wall, a little right.
    let laser = o.kind == SceneKind::CornellLaser;
    let (centre, exit, default_incidence) = if laser {
        (DVec2::new(0.5, -0.5), 125f64.to_radians(), min_deviation - 2f64.to_radians())
    } else {
        (DVec2::new(-0.1, -0.3), 70f64.to_radians(), min_deviation)
    };
    let cross = prism_cross_section(centre, 0.3, n_d, exit);
    if !o.no_prism {
        s.add_extruded("prism", &[(cross, 1)], 0.0, 0.5);
    }
    let incidence = o.incidence_deg.map_or(default_incidence, f64::to_radians);
    let (aim, dir) = into_left_face(cross, incidence);
    let aim = aim + DVec3::Z * 0.25;
    // The probe ray starts on the light's way in (the laser's: at its
    // aperture, clear of its housing).
    let mut probe_from = aim - dir * 0.5;
    match o.kind {
        SceneKind::CornellPointlight => {
            let pos = aim - dir * 0.55;
            s.lights.push(Light { name: "point light".into(), emission: Emission::Point { pos }, spectrum: light_spectrum(o, "d65")?, power: 1.0 });
        }
        SceneKind::CornellMirrorTube => {
            // A square mirror tube 2.5 cm across and 45 cm long along the
            // light's way into the prism, lit by a frosted lamp that fills
            // its closed end (an opal diffuser 2.5 cm square, lit from
            // behind). Its mirrors make a lattice of images of that end, a
            // tube's width apart, and each wall point sees the part of the
            // lattice framed by the mouth, a window about one image wide
            // sliding by the tube's width per w D / L of wall (9 cm at
            // 1.6 m). A small bulb (a sphere 1.6 cm across) left dark gaps
            // between its images, so that window took in more or less
            // bulb as it slid: a regular grid of blotches about 12 px
            // apart on the walls (the kaleidoscope's, not the gather's).
            // A diffuser filling the end tiles the lattice without gaps,
            // so the walls are lit smoothly; and the narrow mouth, seen
            // from the prism, is a small source (about 5 degrees), so the
            // arcs stay sharp and coloured.
            let (len, half) = (0.45, 0.0125);
            let start = aim - dir * 0.75;
            let u = DVec3::Z.cross(dir).normalize();
            let w = DVec3::Z;
            let corner = |a: f64, b: f64| start + u * (a * half) + w * (b * half);
            let sides = [
                (corner(-1.0, -1.0), u * (2.0 * half)),
                (corner(-1.0, 1.0), u * (2.0 * half)),
                (corner(-1.0, -1.0), w * (2.0 * half)),
                (corner(1.0, -1.0), w * (2.0 * half)),
            ];
            for (i, (c, e)) in sides.into_iter().enumerate() {
                s.faces.push(Face::rect(&format!("mirror tube {i}"), c, dir * len, e, Surface::Mirror { reflectance: 0.95 }));
            }

            // The tube's body as the camera sees it: a metal
            // sleeve, an eight-sided cylinder 4.4 cm across round the
            // square bore, closed by a cap behind the end mirror (a
            // choice: the bare 2.5 cm bore read as a stick). It lies
            // outside the bore, so the light the tube sends is unchanged.
            // Eight sides and no ring at the mouth (which faces away from
            // the camera): each face costs every photon a test, and at 16
            // sides and a ring the light pass took 8 times as long.
            let (sides_n, radius, sleeve) = (8, 0.022, Surface::Mirror { reflectance: 0.6 });
            let round = |k: usize| {
                let (sn, cs) = (k as f64 * std::f64::consts::TAU / sides_n as f64).sin_cos();
                u * (radius * cs) + w * (radius * sn)
            };
            // The sides matte grey (brushed metal, a choice): as a polished
            // mirror they showed the red wall and the dark room in bands,
            // and the tube read as a red-and-black stick; matte, each side
            // takes the room's light by its slope, shaded as a cylinder.
            for k in 0..sides_n {
                let (c0, c1) = (round(k), round(k + 1));
                // Normal (c1 - c0) x dir: outward, the lit side.
                matte(&mut s, &format!("tube sleeve {k}"), start + c0, c1 - c0, dir * len, [0.55; 3]);
            }
            let cap = (0..sides_n).map(|k| start - dir * 1e-4 + round(k)).collect();
            s.faces.push(Face::polygon("tube cap", cap, -dir, sleeve));
            // The lamp: the tube's end, emitting into the bore (its normal,
            // u x w, is the light's way).
            let light = s.lights.len();
            s.faces.push(Face::rect("mirror tube lamp", corner(-1.0, -1.0), u * (2.0 * half), w * (2.0 * half), Surface::Emitter { light }));
            let emission = Emission::Area { face: s.faces.len() - 1 };
            s.lights.push(Light { name: "lamp in a mirror tube".into(), emission, spectrum: light_spectrum(o, "d65")?, power: 1.0 });
        }
        _ => {
            // The laser's aperture 16 cm from the right wall (the beam
            // leaves it heading left, a little toward the camera); its
            // housing, a dark box 5 cm wide and 14 cm tall (tall enough to
            // catch the little the prism sends back), reaches back into
            // the wall.
            let start = aim - dir * ((0.84 - aim.x) / -dir.x);
            probe_from = start + dir * 0.01;
            let u = DVec3::Z.cross(dir).normalize();
            let (hu, hw, w, dark) = (0.025, 0.07, DVec3::Z, [0.05; 3]);
            let front = start - dir * 0.001;
            let body = dir * ((1.0 - front.x) / -dir.x + 0.01);
            let back = front - body;
            // Each face's normal (eu x ev) outward.
            matte(&mut s, "laser top", back - u * hu + w * hw, body, u * (2.0 * hu), dark);
            matte(&mut s, "laser bottom", back - u * hu - w * hw, u * (2.0 * hu), body, dark);
            matte(&mut s, "laser side", back + u * hu - w * hw, w * (2.0 * hw), body, dark);
            matte(&mut s, "laser side", back - u * hu - w * hw, body, w * (2.0 * hw), dark);
            matte(&mut s, "laser front", front - u * hu - w * hw, u * (2.0 * hu), w * (2.0 * hw), dark);
            s.lights.push(Light {
                name: "laser".into(),
                emission: Emission::Beam {
                    centre: start,
                    dir,
                    u,
                    v: DVec3::Z,
                    // 2.4 cm wide and 6 cm tall (a line laser's sheet): the
                    // spectrum it paints is a band, not a hairline, and
                    // each point of it mixes a few nanometres more (at 8
                    // mm its hues changed in steps).
                    half: DVec2::new(0.012, 0.03),
                    disc: false,
                    polarisation: Some(Polarisation::P),
                },
                spectrum: light_spectrum(o, "d65")?,
                power: 1.0,
            });
            // A thin haze (as chalk dust or smoke in a lab) shows the beam on
            // its way to the prism and the fan beyond it.
            // 0.8 per metre (a choice; at 0.05 the beam was a hundredth of
            // the band it paints, and no exposure showed both).
            s.haze = 0.8;
            // A lamp in the ceiling so the room shows round the fan, 60
            // times the laser's power (a choice): the band of spectrum the
            // fan paints, exposed so that it rolls only a little toward
            // white (`scenes/pm-laser-prism.toml`), is then about 25 times
            // as bright as the walls, as a prism's spectrum is in a lit
            // room, and not 1500 times (at 1.2, the room showed only when
            // the band was blown out into flat blocks).
            let light = s.lights.len();
            s.faces.push(Face::rect(
                "ceiling lamp",
                DVec3::new(-0.25, -0.25, 1.995),
                DVec3::new(0.0, 0.5, 0.0),
                DVec3::new(0.5, 0.0, 0.0),
                Surface::Emitter { light },
            ));
            s.lights.push(Light {
                name: "ceiling lamp".into(),
                emission: Emission::Area { face: s.faces.len() - 1 },
                spectrum: Spectrum::light("d65")?,
                power: 60.0,
            });
            // The photons shared as when the lamp was 1.2 times the laser:
            // the laser's fan keeps its share (power would give it 2 %).
            s.photon_shares = Some(vec![1.0, 1.2]);
        }
    }
    s.probe = (probe_from, dir);
    s.camera = if laser && o.view == View::Wall {
        // The band of spectrum on the back wall, close up: square on from
        // 70 cm, 42 cm of wall across the frame (the band is about 36 cm
        // long), centred between where 420 and 680 nm land; in clear air,
        // as the haze between the camera and the wall would veil it.
        s.haze = 0.0;
        let lands = |nm: f64| {
            let p = crate::world::probe::probe(&s, nm);
            let start = p.exit_point + p.exit_dir * 1e-9;
            s.intersect(start, p.exit_dir, None).map_or(DVec3::new(-0.5, 1.0, 0.6), |hit| start + p.exit_dir * hit.t)
        };
        let centre = (lands(420.0) + lands(680.0)) / 2.0;
        let (across, from) = (0.42, 0.7);
        let vfov = 2.0 * (across / 2.0 * o.height as f64 / o.width as f64 / from).atan().to_degrees();
        Camera::look_at(centre - DVec3::Y * from, centre, DVec3::Z, vfov, o.width, o.height)
    } else if laser {
        // Framed on the laser, the prism, the fan and the band on the back
        // wall, from a little left of centre (from in front, the prism's
        // entry face looked a dark block).
        Camera::look_at(DVec3::new(-0.5, -3.0, 1.1), DVec3::new(0.15, 0.0, 0.45), DVec3::Z, 30.0, o.width, o.height)
    } else {
        // The box's front edges just outside the frame (35.5 degrees: at
        // 38 the dark outside showed down both sides); aimed 3.1 degrees
        // below level, so the prism's foot stands clear of the frame's
        // bottom (aimed at 0.9 m it nearly touched it) while the light's
        // bright pool on the floor stays out of view (aimed at 0.75 m it
        // showed, and the exposure chosen on the frame dimmed the arcs).
        Camera::look_at(DVec3::new(0.0, -3.3, 1.0), DVec3::new(0.0, 0.0, 0.82), DVec3::Z, 35.5, o.width, o.height)
    };
    Ok(s)
}

// One body (over 80 lines): the album cover's prism, beam, outline strips and camera, placed from one set of measures.
pub fn dark_side(o: &SceneOptions) -> Result<World> {
    let glass = glass_medium(o.crown, o.ior, o.no_dispersion);
    let mut s = super::with_glass(o, glass);
    // A near-black backdrop the beam grazes, so its path shows (like a
    // light sheet on black card).
    matte(&mut s, "backdrop", DVec3::new(-1.2, -0.9, 0.0), DVec3::new(2.4, 0.0, 0.0), DVec3::new(0.0, 1.8, 0.0), [0.1; 3]);
    let n_d = o.crown.sellmeier(crate::optics::glass::lines::LD);
    // As on the cover: the prism level, apex up (+y, the top of the
    // picture); the beam comes up from the left at minimum deviation and
    // the fan leaves down to the right.
    let (side, tall) = (0.3, 0.12);
    let h = side * 3f64.sqrt() / 2.0;
    let cross = [DVec2::new(-side / 2.0, -h / 3.0), DVec2::new(side / 2.0, -h / 3.0), DVec2::new(0.0, 2.0 * h / 3.0)];
    if !o.no_prism {
        // The prism stands 0.2 mm above the backdrop (on three thin feet,
        // say): the beam's lower rays, descending 2.2 degrees, meet its
        // base inside the glass at grazing incidence and are totally
        // reflected, and what the exit face reflects back inside leaves by
        // the blackened side. Standing on the backdrop (its base and the
        // backdrop one plane), those rays landed on the backdrop under the
        // glass: a bright bar across the prism and a blue line crossing it.
        s.add_extruded("prism", &[(cross, 1)], 2e-4, tall);
        // The cover's white outline: the prism's top edges, ground and
        // glowing (three thin emitting strips on the top face, 4 mm wide:
        // at 8 mm they read as a white wireframe), lit from within as a
        // chamfer catches scattered light.
        let centroid = (cross[0] + cross[1] + cross[2]) / 3.0;
        let width = 0.004;
        for k in 0..3 {
            let (a, b) = (cross[k], cross[(k + 1) % 3]);
            let inward = (centroid - (a + b) / 2.0).normalize() * width;
            let at = |p: DVec2| DVec3::new(p.x, p.y, tall + 1e-4);
            // Normal +z (toward the camera above): eu x ev must point up.
            let (eu, ev) = (at(b) - at(a), (inward).extend(0.0));
            let (corner, eu, ev) = if eu.cross(ev).z > 0.0 { (at(a), eu, ev) } else { (at(a) + ev, eu, -ev) };
            let light = s.lights.len();
            s.faces.push(Face::rect(&format!("outline {k}"), corner, eu, ev, Surface::Emitter { light }));
            s.lights.push(Light {
                name: format!("outline {k}"),
                emission: Emission::Area { face: s.faces.len() - 1 },
                spectrum: Spectrum::light("d65")?,
                power: 0.04 * eu.length(),
            });
        }
    }
    if !o.no_prism {
        // The prism's base blackened, as an optical prism's unused face
        // often is (a black card 2 mm from it): the little light the exit
        // face reflects back inside leaves through the base, and would
        // otherwise draw a dim blue ghost beam down across the cover.
        let (a, b) = (cross[0], cross[1]);
        let out = DVec2::new(b.y - a.y, a.x - b.x).normalize() * 0.002;
        let (a3, b3) = ((a + out).extend(0.0), (b + out).extend(0.0));
        matte(&mut s, "black card", a3, DVec3::Z * tall, b3 - a3, [0.0; 3]);
    }
    let incidence = o.incidence_deg.map_or((n_d * 0.5f64).asin(), f64::to_radians);
    let (aim, dir) = into_left_face(cross, incidence);
    // The beam descends 2.2 degrees toward the backdrop, its rays starting
    // between 0 and 8 cm high 1 m before the prism: each ray paints the
    // backdrop where it lands, so the lower ones draw the incoming beam and
    // the higher ones enter the prism and draw the fan beyond it, over
    // about 70 cm (the whole fan in the frame). The beam is 4 mm wide, so
    // the fan opens from nearly a point as on the cover; the scene file
    // meets the prism a few degrees short of minimum deviation, where the
    // fan spreads wider (docs/physics.md §11).
    let tilt = 2.2f64.to_radians();
    let dir3 = (dir * tilt.cos() - DVec3::Z * tilt.sin()).normalize();
    let start = aim + DVec3::Z * 0.04 - dir * 1.0;
    let u = DVec3::Z.cross(dir).normalize();
    let v = u.cross(dir3).normalize();
    let beam = s.lights.len();
    s.lights.push(Light {
        name: "white beam".into(),
        // Polarised in the plane of incidence: near minimum deviation a
        // dense flint's faces meet the beam near Brewster's angle (63
        // degrees against atan(n) = 61 for N-SF11), so p light enters and
        // leaves with little reflected and no stray beams cross the cover;
        // natural light would send 14 % up off the entry face
        // (docs/physics.md §2).
        emission: Emission::Beam { centre: start, dir: dir3, u, v, half: DVec2::new(0.002, 0.04), disc: false, polarisation: Some(Polarisation::P) },
        // D65: white on an sRGB display.
        spectrum: light_spectrum(o, "d65")?,
        power: 1.0,
    });
    s.direct_lighting = true;
    // Every photon to the beam: the outline only glows toward the camera.
    let mut shares = vec![1e-9; s.lights.len()];
    shares[beam] = 1.0;
    s.photon_shares = Some(shares);
    s.probe = (aim + DVec3::Z * (tall / 2.0) - dir * 0.5, dir);
    // Framed as the cover: the prism large, in the middle of the picture
    // (its centroid 40 px above the middle: lower, the fan's violet edge
    // left by the bottom corner), the beam in from the left edge, and the whole
    // fan leaving across the right edge, its violet side clear of the
    // bottom (framed on the prism's right, the fan left by the corner).
    let centre = DVec3::new(0.03, -0.09, 0.0);
    s.camera = Camera::look_at(centre + DVec3::Z * 2.8, centre, DVec3::Y, 16.8, o.width, o.height);
    Ok(s)
}
