//! The Amici direct-vision prism: crown | flint | crown, cemented, the crown
//! apices solved so the design wavelength leaves parallel to its entry
//! (docs/physics.md §4; Hagen & Tkaczyk, Appl. Opt. 50, 4998 (2011)).
//!
//! Geometry in the xy plane, extruded along z; light travels along +x. The
//! flint's apex points -y, the crowns' apices +y. With h = alpha2 / 2 the
//! outward normals of the four faces a ray crosses make these angles with
//! +x: entry (h - alpha1), crown|flint +h, flint|crown -h, exit (alpha1 - h).
//!
//! Report 000's scenes: `amici-screen`, a white slit beam (2 mm x 2 cm)
//! through the prism onto a matte screen 2 m away, the rainbow strip
//! (Picture 5; `--no-prism` gives Picture 4, `--no-dispersion` Picture 6);
//! `amici-lamp`, the camera looks through the prism at a fluorescent tube
//! 1 m away: one image of the tube per spectral line (Picture 1).

use super::{glass_medium, light_spectrum, rotate_z, SceneKind, SceneOptions};
use crate::optics::ior::IorKind;
use crate::world::probe::{probe, probe_ray, ProbeRay};
use crate::world::{Albedo, Camera, Emission, Face, Light, Medium, Surface, World};
use anyhow::{bail, Result};
use glam::{DVec2, DVec3};

/// The d line (He, 587.5618 nm), the usual design wavelength.
pub const DESIGN_NM: f64 = 587.5618;

/// Crown apex angle (radians) that makes the design wavelength leave
/// undeviated, given the crown and flint indices there and the flint apex.
/// `None` if no such crown exists (the flint's face would reflect totally).
pub fn solve_crown_apex(n_crown: f64, n_flint: f64, flint_apex: f64) -> Option<f64> {
    let h = flint_apex / 2.0;
    // Snell at the cemented face, with the ray parallel to the flint's base.
    let s = n_flint / n_crown * h.sin();
    if !(s.abs() < 1.0) {
        return None;
    }
    let beta = s.asin();
    // tan a1 = (sin h - n_c sin b) / (cos h - n_c cos b), a1 in (0, pi).
    let a1 = (h.sin() - n_crown * beta.sin()).atan2(h.cos() - n_crown * beta.cos());
    let a1 = if a1 <= 0.0 { a1 + std::f64::consts::PI } else { a1 };
    (a1 > 0.0 && a1 < std::f64::consts::PI && a1 > h).then_some(a1)
}

/// The three cross-sections (counter-clockwise triangles in the xy plane)
/// of an Amici prism of height `height` along y, centred on the origin:
/// left crown, flint, right crown.
pub fn cross_sections(crown_apex: f64, flint_apex: f64, height: f64) -> [[DVec2; 3]; 3] {
    let h = flint_apex / 2.0;
    let (y0, y1) = (-height / 2.0, height / 2.0);
    let top = height * h.tan(); // half-width of the flint's top
    let reach = height * (crown_apex - h).tan(); // how far a crown's base extends past the flint
    let flint = [DVec2::new(0.0, y0), DVec2::new(top, y1), DVec2::new(-top, y1)];
    let left = [DVec2::new(-top, y1), DVec2::new(-top - reach, y0), DVec2::new(0.0, y0)];
    let right = [DVec2::new(top, y1), DVec2::new(0.0, y0), DVec2::new(top + reach, y0)];
    [left, flint, right]
}

/// Builds `amici-screen` or `amici-lamp`.
pub fn build(o: &SceneOptions) -> Result<World> {
    let prism = AmiciPrism::design(o)?;
    let mut scene = World::new(
        o.kind.name(),
        vec![Medium::Air, glass_medium(o.crown, o.ior, o.no_dispersion), glass_medium(o.flint, o.ior, o.no_dispersion)],
        o.width,
        o.height,
    );
    scene.add_extruded("amici", &[(prism.parts[0], 1), (prism.parts[1], 2), (prism.parts[2], 1)], -0.015, 0.015);
    scene.probe = (prism.start, prism.dir);
    // Screen and camera are placed from the glasses' Sellmeier dispersion
    // whatever index model is chosen, so --no-prism, --no-dispersion and
    // every model frame the same view (report 000's Pictures 4, 5 and 6).
    let mut design = scene.clone();
    design.media = vec![Medium::Air, glass_medium(o.crown, IorKind::Sellmeier, false), glass_medium(o.flint, IorKind::Sellmeier, false)];
    let d_line = probe(&design, DESIGN_NM);
    if d_line.tir {
        match o.incidence_deg {
            Some(_) => bail!("--incidence: at {:.3} degrees the d line is totally reflected inside the prism", prism.incidence.to_degrees()),
            None => bail!(
                "--glass {} / --flint {} / --flint-apex {}: the d line, entering along the design's axis ({:.3} degrees), is totally reflected inside the prism after {} faces (it meets a face beyond the critical angle)",
                o.crown.name,
                o.flint.name,
                o.flint_apex_deg,
                prism.incidence.to_degrees(),
                d_line.faces
            ),
        }
    }
    match o.kind {
        SceneKind::AmiciScreen => add_screen(&mut scene, o, &prism, &design, &d_line, 2.0)?,
        SceneKind::AmiciBench => {
            add_screen(&mut scene, o, &prism, &design, &d_line, BENCH_SCREEN_DISTANCE)?;
            add_bench(&mut scene, o)?;
        }
        _ => add_lamp(&mut scene, o, &prism, &design, &d_line)?,
    }
    Ok(scene)
}

/// The prism designed for the options, and the beam aimed at it.
struct AmiciPrism {
    /// Left crown, flint, right crown cross-sections.
    parts: [[DVec2; 3]; 3],
    /// Crown apex and half the flint apex, radians.
    a1: f64,
    h: f64,
    /// Angle of incidence on the entry face, radians.
    incidence: f64,
    start: DVec3,
    dir: DVec3,
}

impl AmiciPrism {
    fn design(o: &SceneOptions) -> Result<AmiciPrism> {
        // The prism is designed from the catalogue (Sellmeier), whatever
        // model the renderer then uses for its index.
        let (nc, nf) = (o.crown.sellmeier(DESIGN_NM), o.flint.sellmeier(DESIGN_NM));
        if !(0.0 < o.flint_apex_deg && o.flint_apex_deg < 180.0) {
            bail!("--flint-apex: {} degrees is not between 0 and 180", o.flint_apex_deg);
        }
        let a2 = o.flint_apex_deg.to_radians();
        let Some(a1) = solve_crown_apex(nc, nf, a2) else {
            bail!(
                "--flint-apex: no crown apex makes {} / {} direct-vision with a {} degree flint (the cemented face would reflect totally)",
                o.crown.name,
                o.flint.name,
                o.flint_apex_deg
            );
        };
        let parts = cross_sections(a1, a2, 0.03);
        // Incidence on the entry face, whose inward normal is at h - a1 from +x.
        let h = a2 / 2.0;
        let incidence = o.incidence_deg.map_or(a1 - h, f64::to_radians);
        let dir = rotate_z(DVec3::X, h - a1 + incidence);
        // Aim the beam at the middle of the entry face.
        let entry_mid = (parts[0][0] + parts[0][1]) / 2.0;
        let start = DVec3::new(entry_mid.x, entry_mid.y, 0.0) - dir * 0.3;
        Ok(AmiciPrism { parts, a1, h, incidence, start, dir })
    }
}

/// Picture 5: a matte screen `dist` m past the prism, across the strip
/// from 400 to 700 nm, the camera 1 m before it, and the white slit beam.
fn add_screen(scene: &mut World, o: &SceneOptions, prism: &AmiciPrism, design: &World, d_line: &ProbeRay, dist: f64) -> Result<()> {
    let land = |nm: f64| {
        let p = probe(design, nm);
        p.exit_point + p.exit_dir * ((d_line.exit_point.x + dist - p.exit_point.x) / p.exit_dir.x.max(1e-9))
    };
    let (a, b) = (land(400.0), land(700.0));
    let centre = (a + b) / 2.0;
    let width = ((a.y - b.y).abs() * 1.4).max(0.1);
    let tall = width * o.height as f64 / o.width as f64;
    // Normal -x (facing the prism), u along -y, v along +z: u x v = -x.
    let corner = centre + DVec3::new(0.0, width / 2.0, -tall / 2.0);
    scene.faces.push(Face::rect(
        "screen",
        corner,
        DVec3::new(0.0, -width, 0.0),
        DVec3::new(0.0, 0.0, tall),
        Surface::Diffuse { albedo: Albedo::new([0.8; 3]), map: 0 },
    ));
    scene.maps.push(scene.faces.len() - 1);
    let cam = centre - DVec3::X * 1.0;
    let vfov = 2.0 * ((tall / 2.0) / 1.0).atan().to_degrees();
    scene.camera = Camera::look_at(cam, centre, DVec3::Z, vfov, o.width, o.height);
    let u = rotate_z(DVec3::Y, prism.h - prism.a1 + prism.incidence);
    scene.lights.push(Light {
        name: "beam".into(),
        emission: Emission::Beam { centre: prism.start, dir: prism.dir, u, v: DVec3::Z, half: DVec2::new(0.001, 0.01), disc: false, polarisation: None },
        spectrum: light_spectrum(o, "D65")?,
        power: 1.0,
    });
    Ok(())
}

/// How far the bench view's screen stands past the prism, m: near enough
/// that prism and strip are both large in one view.
const BENCH_SCREEN_DISTANCE: f64 = 0.8;

/// Pictures 4-6 as a photograph of the bench would show them: a grey
/// table strip under the prism (which stands on it), the beam's path and
/// the screen, lit from above and behind by a broad, dim, collimated light
/// (sunlight through a window: every photon lands where the camera looks),
/// and the camera behind the prism and above the table, looking past the
/// prism at the screen, so the prism (or its absence) and the strip (or
/// the white patch) are both in view.
fn add_bench(scene: &mut World, o: &SceneOptions) -> Result<()> {
    let Some(&screen) = scene.maps.first() else { bail!("the bench view needs the screen") };
    let (corner, eu, ev) = scene.faces[screen].frame.expect("the screen is a parallelogram");
    let centre = corner + (eu + ev) / 2.0;
    // The table: just under the prism's base (z = -0.015), from behind the
    // prism to the screen's foot, normal +z.
    let z = -0.0151;
    let (x0, x1) = (-0.4, centre.x + 0.02);
    let (y0, y1) = (centre.y - 0.35, centre.y + 0.35);
    let map = scene.maps.len();
    scene.faces.push(Face::rect(
        "table",
        DVec3::new(x0, y0, z),
        DVec3::new(x1 - x0, 0.0, 0.0),
        DVec3::new(0.0, y1 - y0, 0.0),
        Surface::Diffuse { albedo: Albedo::new([0.5; 3]), map },
    ));
    scene.maps.push(scene.faces.len() - 1);
    // The screen stands on the table: stretch it down to the table top.
    let bottom = corner.z.min((corner + ev).z);
    if bottom > z && ev.z > 0.0 {
        let grow = ev.normalize() * (bottom - z);
        scene.faces[screen] = Face::rect("screen", corner - grow, eu, ev + grow, scene.faces[screen].surface.clone());
    }
    // The window light: down onto the table, 20 degrees from behind the
    // camera, so the screen's face is lit too. Its footprint covers the
    // table; photons are shared half and half with the beam.
    let dir = DVec3::new(20f64.to_radians().sin(), 0.0, -20f64.to_radians().cos());
    let mid = DVec3::new((x0 + x1) / 2.0, (y0 + y1) / 2.0, z);
    let v = DVec3::Y.cross(dir).normalize();
    let half = DVec2::new((y1 - y0) / 2.0 + 0.02, (x1 - x0) / 2.0 * dir.z.abs() + 0.05);
    scene.lights.push(Light {
        name: "window light".into(),
        emission: Emission::Beam { centre: mid - dir * 1.5, dir, u: DVec3::Y, v, half, disc: false, polarisation: None },
        spectrum: light_spectrum(o, "D65")?,
        power: 45.0,
    });
    scene.photon_shares = Some(vec![0.5, 0.5]);
    // Light straight from either beam by shadow rays (docs/physics.md
    // §13): the table and the white slit image come out without photon
    // noise; the photons carry what crosses the prism.
    scene.direct_lighting = true;
    // Above and behind the prism, looking down the bench: the prism near
    // (from above, its three glass parts and cemented faces show), the
    // screen beyond; the view is framed on both, with a margin.
    let cam = DVec3::new(-0.35, -0.12, 0.12);
    let (to_prism, to_screen) = ((DVec3::ZERO - cam).normalize(), (centre - cam).normalize());
    let fwd = (to_prism + to_screen).normalize();
    let right = fwd.cross(DVec3::Z).normalize();
    let up = right.cross(fwd);
    let angle = |d: DVec3, axis: DVec3| (d.dot(axis) / d.dot(fwd)).atan();
    let (h, v) = ((angle(to_prism, right) - angle(to_screen, right)).abs(), (angle(to_prism, up) - angle(to_screen, up)).abs());
    let aspect = o.width as f64 / o.height as f64;
    // Half the span plus room for the prism's and the screen's own size.
    let half_v = (v / 2.0 + 0.12).max((h / 2.0 + 0.14) / aspect);
    scene.camera = Camera::look_at(cam, cam + fwd, DVec3::Z, (2.0 * half_v).to_degrees(), o.width, o.height);
    Ok(())
}

/// Picture 1: a compact fluorescent lamp 3 m past the prism, and the
/// camera just before the entry face looking back through the prism at it.
/// The lamp is a folded tube, as real ones are: two legs of 4 mm tubing
/// 10 mm apart joined by a bend at the top, 0.27 degrees wide in all as
/// seen through the prism, so lines farther apart than that make separate
/// images of it.
fn add_lamp(scene: &mut World, o: &SceneOptions, prism: &AmiciPrism, design: &World, d_line: &ProbeRay) -> Result<()> {
    let x = d_line.exit_point.x + LAMP_DISTANCE;
    let spectrum = light_spectrum(o, "cfl-lines")?;
    let (d, gap, tall) = (0.004, 0.006, 0.1);
    // Emitting faces toward -x (the prism): the two legs and the bend.
    let parts = [
        (DVec3::new(x, -gap / 2.0 - d, -tall / 2.0), DVec3::new(0.0, 0.0, tall), DVec3::new(0.0, d, 0.0)),
        (DVec3::new(x, gap / 2.0, -tall / 2.0), DVec3::new(0.0, 0.0, tall), DVec3::new(0.0, d, 0.0)),
        (DVec3::new(x, -gap / 2.0 - d, tall / 2.0), DVec3::new(0.0, 0.0, d), DVec3::new(0.0, gap + 2.0 * d, 0.0)),
    ];
    let area: f64 = parts.iter().map(|(_, u, v)| u.cross(*v).length()).sum();
    for (k, (corner, eu, ev)) in parts.into_iter().enumerate() {
        let light = scene.lights.len();
        scene.faces.push(Face::rect(&format!("cfl tube {k}"), corner, eu, ev, Surface::Emitter { light }));
        scene.lights.push(Light {
            name: format!("cfl tube {k}"),
            emission: Emission::Area { face: scene.faces.len() - 1 },
            spectrum: spectrum.clone(),
            // The same radiance on every part: power in proportion to area.
            power: eu.cross(ev).length() / area,
        });
    }
    // The camera frames the lamp's images from the violet mercury line to
    // the deep red europium line (where each appears, found by tracing back
    // through the prism), with 5 % to spare on each side.
    let cam = DVec3::new(prism.parts[0][1].x - 0.03, 0.0, 0.0);
    // (The violet line's copy may be lost: traced back, it meets the
    // crown's base beyond the critical angle and is totally reflected;
    // then the frame starts at the blue line.)
    let blue = lamp_image_angle(design, cam, x, 404.656).or_else(|| lamp_image_angle(design, cam, x, 435.834));
    let (Some(blue), Some(red)) = (blue, lamp_image_angle(design, cam, x, 711.0)) else {
        match o.incidence_deg {
            Some(_) => bail!("--incidence: the lamp cannot be seen through the prism at 405-711 nm"),
            None => bail!(
                "--glass {} / --flint {} / --flint-apex {}: the lamp cannot be seen through this prism at 405-711 nm",
                o.crown.name,
                o.flint.name,
                o.flint_apex_deg
            ),
        }
    };
    let look = rotate_z(DVec3::X, (blue + red) / 2.0);
    let hfov = (blue - red).abs() * 1.1 + (d + gap + d) * 2.0 / LAMP_DISTANCE;
    let vfov = 2.0 * ((hfov / 2.0).tan() * o.height as f64 / o.width as f64).atan();
    scene.camera = Camera::look_at(cam, cam + look, DVec3::Z, vfov.to_degrees(), o.width, o.height);
    scene.probe = (cam, DVec3::X);
    Ok(())
}

/// The direction (radians from +x, in the xy plane) of the camera ray
/// from `cam` that, at wavelength `nm`, goes through the prism and meets
/// the lamp's axis (y = 0 at x = `lamp_x`): where the lamp's image in that
/// wavelength appears. Found by bisection with the probe's optics.
pub fn lamp_image_angle(design: &World, cam: DVec3, lamp_x: f64, nm: f64) -> Option<f64> {
    let miss = |a: f64| -> Option<f64> {
        let p = probe_ray(design, cam, rotate_z(DVec3::X, a), nm);
        (!p.tir && p.exit_dir.x > 0.0).then(|| p.exit_point.y + p.exit_dir.y / p.exit_dir.x * (lamp_x - p.exit_point.x))
    };
    // A sign change on a grid of directions, then bisection.
    let grid: Vec<(f64, f64)> = (0..=100).map(|k| -0.25 + 0.005 * k as f64).filter_map(|a| miss(a).map(|f| (a, f))).collect();
    let w = grid.windows(2).find(|w| w[0].1 * w[1].1 <= 0.0)?;
    let ((mut lo, mut f_lo), mut hi) = (w[0], w[1].0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let f = miss(mid)?;
        if (f < 0.0) == (f_lo < 0.0) {
            (lo, f_lo) = (mid, f);
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// How far the lamp stands past the prism's exit face, m.
pub const LAMP_DISTANCE: f64 = 3.0;
#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::glass::by_name;

    #[test]
    fn solves_the_worked_examples_of_physics_md() {
        let nc = by_name("N-BK7").unwrap().sellmeier(DESIGN_NM);
        for (flint, apex, want) in [("N-SF11", 90.0, 76.3881), ("F2", 90.0, 56.7834), ("N-SF11", 100.0, 88.6553)] {
            let nf = by_name(flint).unwrap().sellmeier(DESIGN_NM);
            let a1 = solve_crown_apex(nc, nf, f64::to_radians(apex)).unwrap().to_degrees();
            assert!((a1 - want).abs() < 1e-4, "{flint} {apex}: {a1} vs {want}");
        }
        assert!(solve_crown_apex(1.5, 3.0, f64::to_radians(120.0)).is_none());
    }

    #[test]
    fn cross_sections_have_the_apex_angles() {
        let (a1, a2) = (76.3881f64.to_radians(), 90f64.to_radians());
        let [l, f, r] = cross_sections(a1, a2, 0.03);
        let angle = |t: [DVec2; 3], at: usize| {
            let (p, a, b) = (t[at], t[(at + 1) % 3], t[(at + 2) % 3]);
            (a - p).angle_to(b - p).abs()
        };
        assert!((angle(f, 0) - a2).abs() < 1e-12);
        assert!((angle(l, 0) - a1).abs() < 1e-12);
        assert!((angle(r, 0) - a1).abs() < 1e-12);
        for t in [l, f, r] {
            assert!((t[1] - t[0]).perp_dot(t[2] - t[0]) > 0.0, "counter-clockwise");
        }
    }
}
