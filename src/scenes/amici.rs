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
//! `amici-lamp`, the camera looks through the prism at a twin-tube
//! fluorescent lamp 30 m away: one image of the lamp per spectral line
//! (Picture 1).

use super::{glass_medium, light_spectrum, rotate_z, SceneKind, SceneOptions, View};
use super::{Result, SceneError};
use crate::optics::ior::IorKind;
use crate::world::probe::{probe, probe_ray, ProbeRay};
use crate::world::{Albedo, Camera, Emission, Face, Light, Medium, Surface, World};
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
    let half = prism.size / 2.0;
    scene.add_extruded("amici", &[(prism.parts[0], 1), (prism.parts[1], 2), (prism.parts[2], 1)], -half, half);
    scene.probe = (prism.start, prism.dir);
    // Screen and camera are placed from the glasses' Sellmeier dispersion
    // whatever index model is chosen, so --no-prism, --no-dispersion and
    // every model frame the same view (report 000's Pictures 4, 5 and 6).
    let mut design = scene.clone();
    design.media = vec![Medium::Air, glass_medium(o.crown, IorKind::Sellmeier, false), glass_medium(o.flint, IorKind::Sellmeier, false)];
    let d_line = probe(&design, DESIGN_NM);
    if d_line.tir {
        match o.incidence_deg {
            Some(_) => {
                return Err(SceneError::param("incidence", format!("at {:.3} degrees the d line is totally reflected inside the prism", prism.incidence.to_degrees())))
            }
            None => {
                return Err(SceneError::design(
                    o,
                    format!(
                        "the d line, entering along the design's axis ({:.3} degrees), is totally reflected inside the prism after {} faces (it meets a face beyond the critical angle)",
                        prism.incidence.to_degrees(),
                        d_line.faces
                    ),
                ))
            }
        }
    }
    match o.kind {
        SceneKind::AmiciScreen => add_screen(&mut scene, o, &prism, &design, &d_line, 2.0)?,
        SceneKind::AmiciBench => {
            add_screen(&mut scene, o, &prism, &design, &d_line, BENCH_SCREEN_DISTANCE)?;
            add_bench(&mut scene, o, &prism)?;
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
    /// The cross-sections' height and the extrusion's depth, m.
    size: f64,
}

impl AmiciPrism {
    fn design(o: &SceneOptions) -> Result<AmiciPrism> {
        // The prism is designed from the catalogue (Sellmeier), whatever
        // model the renderer then uses for its index.
        let (nc, nf) = (o.crown.sellmeier(DESIGN_NM), o.flint.sellmeier(DESIGN_NM));
        if !(0.0 < o.flint_apex_deg && o.flint_apex_deg < 180.0) {
            return Err(SceneError::param("flint_apex", format!("{} degrees is not between 0 and 180", o.flint_apex_deg)));
        }
        let a2 = o.flint_apex_deg.to_radians();
        let Some(a1) = solve_crown_apex(nc, nf, a2) else {
            return Err(SceneError::param(
                "flint_apex",
                format!(
                    "no crown apex makes {} / {} direct-vision with a {} degree flint (the cemented face would reflect totally)",
                    o.crown.name, o.flint.name, o.flint_apex_deg
                ),
            ));
        };
        // The bench's prism is larger (5 cm), as a photograph of it needs;
        // elsewhere 3 cm.
        let size = if o.kind == SceneKind::AmiciBench { 0.05 } else { 0.03 };
        let parts = cross_sections(a1, a2, size);
        // Incidence on the entry face, whose inward normal is at h - a1 from +x.
        let h = a2 / 2.0;
        let incidence = o.incidence_deg.map_or(a1 - h, f64::to_radians);
        let dir = rotate_z(DVec3::X, h - a1 + incidence);
        // Aim the beam at the middle of the entry face.
        let entry_mid = (parts[0][0] + parts[0][1]) / 2.0;
        let start = DVec3::new(entry_mid.x, entry_mid.y, 0.0) - dir * 0.3;
        Ok(AmiciPrism { parts, a1, h, incidence, start, dir, size })
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
        Surface::Diffuse { albedo: Albedo::new([0.9; 3]), map: 0 },
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

/// How far the bench view's screen stands past the prism, m: far enough
/// that the strip (about 19 cm across) is large beside the prism seen from
/// 1.2 m behind it.
const BENCH_SCREEN_DISTANCE: f64 = 1.6;
/// The window light's power over a table-sized footprint, W: a dim fill
/// under which the room, the card under the prism and the glass's edges
/// read in the figures' display (AgX with its print look at exposure
/// 0.005; at 600 W the room sank to murk), the screen around the strip
/// mid grey.
const WINDOW_POWER: f64 = 1000.0;
/// The walls' albedo: a dark grey, as an optics lab's walls are kept so
/// that the light the prism's faces send back (a few per cent of the beam
/// per face, in colours) leaves no bright patches on them.
const BENCH_WALL_ALBEDO: f64 = 0.2;
/// The height of the room's walls around the bench, m.
const WALL_HEIGHT: f64 = 0.6;

/// Pictures 3-6 as photographs of an optics bench would show them: a grey
/// table; the prism on a white card on a dark post (a prism table), so
/// the beam runs half the screen's height above the table; a lamp housing whose slit sends the white beam (1 cm x
/// 4 cm here, wide enough to see as a patch on the screen) down the bench;
/// the beam's path shown by a thin haze, white up to the prism and a
/// narrow fan of colours after it; a white screen standing on the table
/// 1.6 m past the prism (`BENCH_SCREEN_DISTANCE`), 15 % wider than the
/// strip; dark grey walls behind the screen and along the bench's far side, so
/// the glass shows a room; the room lit from above, behind and the near
/// side by a broad collimated light (daylight through a window: every
/// photon lands where the camera looks, and the haze leaves it out). The
/// view (`View`) is the bench from beside the lamp (Pictures 4-6), the
/// screen close up, or the whole bench from above, behind the lamp and to
/// its near side (Picture 3).
// One body (over 80 lines): the bench's parts in the order they stand, sharing the beam's height and the table's size; each choice is commented where it is made.
fn add_bench(scene: &mut World, o: &SceneOptions, prism: &AmiciPrism) -> Result<()> {
    // `add_screen` has just made the screen and the slit beam (`build`).
    let screen = *scene.maps.first().expect("the bench view is built on the screen");
    let (corner, eu, ev) = scene.faces[screen].frame.expect("the screen is a parallelogram");
    let strip_centre = corner + (eu + ev) / 2.0;
    // The screen: 15 % wider than the strip (about 35 cm), 40 % as tall,
    // centred on the strip. Normal -x (facing the prism): u along -y, v up.
    let sw = eu.length() * 1.15;
    let sh = sw * 0.4;
    let surface = scene.faces[screen].surface.clone();
    // The table lies half the screen's height under the beam, so the
    // screen stands on it with the strip across its middle; the prism
    // stands on a white card on a post (a prism table) up to the beam.
    let z = -sh / 2.0;
    scene.faces[screen] =
        Face::rect("screen", DVec3::new(strip_centre.x, strip_centre.y + sw / 2.0, z), DVec3::new(0.0, -sw, 0.0), DVec3::new(0.0, 0.0, sh), surface);
    // The slit (`BENCH_SLIT`): its image on the screen large enough to
    // read from the camera of Pictures 4-6.
    // The lamp stands `BENCH_LAMP_GAP` before the prism's entry face, close
    // enough that the camera of Pictures 4-6 has it in frame with the prism.
    let Emission::Beam { centre: start, half, dir, .. } = &mut scene.lights[0].emission else { unreachable!("the bench's first light is the slit beam") };
    *half = DVec2::new(BENCH_SLIT.0 / 2.0, BENCH_SLIT.1 / 2.0);
    *start += *dir * (0.3 - BENCH_LAMP_GAP);
    let start = *start;
    // The camera of Pictures 4-6: 0.9 m behind the lamp, 33 cm to the
    // side of the beam and 15 cm above it, looking down the bench with a
    // long lens (14.4 degrees across), chosen so that the strip spans a
    // quarter of the frame: the lamp stands outside the frame's left edge
    // (the white beam comes in from it; framing the lamp whole as well
    // leaves the strip at most a sixth of the frame, the bench being 12
    // times the strip's length); the prism whole in the near left, seen a
    // little from above so its top shows; the screen whole at the top
    // right, the fan of colours reaching it from below the strip.
    let bench_cam = DVec3::new(-1.22, -0.325, 0.153);
    let (x0, x1) = (bench_cam.x - 0.5, strip_centre.x + 0.06);
    let (y0, y1) = (strip_centre.y.min(0.0) - 1.3, strip_centre.y.max(0.0) + 0.3);
    super::matte(scene, "table", DVec3::new(x0, y0, z), DVec3::new(x1 - x0, 0.0, 0.0), DVec3::new(0.0, y1 - y0, 0.0), [0.45; 3]);
    // The prism table: a white card (20 x 8 cm) just under the prism's
    // base, which the glass shows bent and fringed, on a dark post (6 x 8
    // cm) down to the table. The post's sides stand in the planes of the
    // lamp housing's, so the fan's photons, traced four at a time, cross
    // no new plane before the screen (`photon::beam`). Outward normals:
    // card +z; post front -y, back +y, ends -x / +x.
    let card = -prism.size / 2.0 - 1e-4;
    let (px, py, ph) = (0.03, 0.04, card - z);
    super::matte(scene, "prism table card", DVec3::new(-0.1, -0.04, card), DVec3::new(0.2, 0.0, 0.0), DVec3::new(0.0, 0.08, 0.0), [0.85; 3]);
    let post = [0.12; 3];
    super::matte(scene, "prism table post", DVec3::new(-px, -py, z), DVec3::new(2.0 * px, 0.0, 0.0), DVec3::new(0.0, 0.0, ph), post);
    super::matte(scene, "prism table post", DVec3::new(-px, py, z), DVec3::new(0.0, 0.0, ph), DVec3::new(2.0 * px, 0.0, 0.0), post);
    super::matte(scene, "prism table post", DVec3::new(-px, -py, z), DVec3::new(0.0, 0.0, ph), DVec3::new(0.0, 2.0 * py, 0.0), post);
    super::matte(scene, "prism table post", DVec3::new(px, -py, z), DVec3::new(0.0, 2.0 * py, 0.0), DVec3::new(0.0, 0.0, ph), post);
    // The lamp housing: a dark box whose front face (with the slit) stands
    // 1 mm behind where the beam starts, so the beam leaves through it.
    let (bx, bd, bw, bh) = (start.x - 0.001, 0.12, 0.08, 0.035 - z);
    let (by0, by1) = (start.y - bw / 2.0, start.y + bw / 2.0);
    let housing = [0.3; 3];
    // Outward normals: front +x, back -x, sides -y / +y, top +z.
    super::matte(scene, "lamp front", DVec3::new(bx, by0, z), DVec3::new(0.0, bw, 0.0), DVec3::new(0.0, 0.0, bh), housing);
    super::matte(scene, "lamp back", DVec3::new(bx - bd, by0, z), DVec3::new(0.0, 0.0, bh), DVec3::new(0.0, bw, 0.0), housing);
    super::matte(scene, "lamp side", DVec3::new(bx - bd, by0, z), DVec3::new(bd, 0.0, 0.0), DVec3::new(0.0, 0.0, bh), housing);
    super::matte(scene, "lamp side", DVec3::new(bx - bd, by1, z), DVec3::new(0.0, 0.0, bh), DVec3::new(bd, 0.0, 0.0), housing);
    super::matte(scene, "lamp top", DVec3::new(bx - bd, by0, z + bh), DVec3::new(bd, 0.0, 0.0), DVec3::new(0.0, bw, 0.0), housing);
    // The optical rail (an X95 profile, black anodised) the lamp housing,
    // the prism table and the screen stand on, from the housing's front to
    // the table's end, so the table reads as a bench. Its sides stand in
    // the planes of the post's and the housing's, with the post's albedo
    // where they overlap; its top is under the slit's lower edge, so no
    // photon of the beam or the fan crosses a new plane before the screen.
    // Outward normals: top +z, front -y, back +y; its ends are hidden.
    let rail_top = z + BENCH_RAIL_HEIGHT;
    let rail = post;
    super::matte(scene, "rail top", DVec3::new(bx, -py, rail_top), DVec3::new(x1 - bx, 0.0, 0.0), DVec3::new(0.0, 2.0 * py, 0.0), rail);
    super::matte(scene, "rail side", DVec3::new(bx, -py, z), DVec3::new(x1 - bx, 0.0, 0.0), DVec3::new(0.0, 0.0, BENCH_RAIL_HEIGHT), rail);
    super::matte(scene, "rail side", DVec3::new(bx, py, z), DVec3::new(0.0, 0.0, BENCH_RAIL_HEIGHT), DVec3::new(x1 - bx, 0.0, 0.0), rail);
    // The room's walls behind the screen and across the bench, dark grey:
    // what the prism's faces reflect and what is seen through them, so the
    // glass shows the room as a photograph's would, not black sky.
    // They reach down to the floor, a table's height (0.75 m) below.
    let (wall, floor) = ([BENCH_WALL_ALBEDO; 3], z - 0.75);
    let up = DVec3::new(0.0, 0.0, WALL_HEIGHT + 0.75);
    super::matte(scene, "back wall", DVec3::new(x1, y0, floor), up, DVec3::new(0.0, y1 - y0, 0.0), wall);
    super::matte(scene, "far side wall", DVec3::new(x0, y1, floor), DVec3::new(x1 - x0, 0.0, 0.0), up, wall);
    // The window light: down onto the table, 35 degrees from behind the
    // lamp, so the screen's face and the back wall are lit too. Its
    // footprint covers the table and reaches the back wall's top; it has
    // 35 % of the photons (all of them through the glass), the beam the rest.
    // Tipped 35 degrees from the vertical toward +x and 15 toward +y, so
    // that the back wall and the far side wall are lit as well.
    let dir = DVec3::new(35f64.to_radians().tan(), 15f64.to_radians().tan(), -1.0).normalize();
    let u = (DVec3::Y - dir * dir.y).normalize();
    let v = u.cross(dir);
    // The footprint: the table's corners and the lit walls' tops, seen
    // along the light.
    let top = z + WALL_HEIGHT;
    let corners = [(x0, y0, z), (x1, y0, z), (x0, y1, z), (x1, y1, z), (x1, y0, top), (x1, y1, top), (x0, y1, top)].map(|(x, y, z)| DVec3::new(x, y, z));
    let (lo, hi) = corners.iter().fold((DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)), |(lo, hi), c| {
        let p = DVec2::new(c.dot(u), c.dot(v));
        (lo.min(p), hi.max(p))
    });
    let (mid, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0 + 0.02);
    let table_mid = DVec3::new((x0 + x1) / 2.0, (y0 + y1) / 2.0, z);
    let centre = dir * (table_mid.dot(dir) - 1.5) + u * mid.x + v * mid.y;
    // WINDOW_POWER over a table-sized footprint (its extents plus 2 cm and
    // 5 cm); the same power per area over this larger one.
    let power = WINDOW_POWER * half.x * half.y / (((y1 - y0) / 2.0 + 0.02) * ((x1 - x0) / 2.0 * 35f64.to_radians().cos() + 0.05));
    // Its photons matter only where they cross the prism (elsewhere its
    // light is direct, by shadow rays): they leave the part of the window
    // whose light meets the prism, 2 cm to spare (a two-hundredth of the
    // window's area), so its caustics and what is seen through it are
    // gathered from that many times more photons per area.
    let glass = prism.parts.iter().flatten().flat_map(|p| [-1.0, 1.0].map(|s| DVec3::new(p.x, p.y, s * prism.size / 2.0)));
    let (glo, ghi) = glass.fold((DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)), |(lo, hi), c| {
        let p = DVec2::new((c - centre).dot(u), (c - centre).dot(v));
        (lo.min(p), hi.max(p))
    });
    scene.photon_aperture.push((scene.lights.len(), (glo + ghi) / 2.0, (ghi - glo) / 2.0 + 0.02));
    scene.haze_skip.push(scene.lights.len());
    scene.lights.push(Light {
        name: "window light".into(),
        emission: Emission::Beam { centre, dir, u, v, half, disc: false, polarisation: None },
        spectrum: light_spectrum(o, "D65")?,
        power,
    });
    scene.photon_shares = Some(vec![0.65, 0.35]);
    // Light straight from either beam by shadow rays (docs/physics.md
    // §13): the table and the white slit image come out without photon
    // noise; the photons carry what crosses the prism.
    scene.direct_lighting = true;
    // The glass is seen through two cemented faces to the card under it:
    // eye paths split at the first `BENCH_SPLIT_DEPTH` faces (no roulette
    // grain on the prism's faces).
    scene.eye_split_depth = BENCH_SPLIT_DEPTH;
    // A thin haze shows the beam (docs/physics.md §17), but for the close
    // view of the screen, which looks along the beam.
    scene.haze = if o.view == View::Screen { 0.0 } else { BENCH_HAZE };
    let aspect = o.width as f64 / o.height as f64;
    let (cam, target, hfov): (DVec3, DVec3, f64) = match o.view {
        // Beside the lamp (`bench_cam`): the prism near, the strip on the
        // screen large beyond it.
        View::Scene | View::Wall => (bench_cam, DVec3::new(0.856, 0.08, -0.024), 14.4),
        // Square on to the strip from 40 cm: the strip across the frame.
        View::Screen => (strip_centre - DVec3::new(0.4, 0.0, 0.0), strip_centre, 2.0 * (0.5 * 0.7 * sw / 0.4).atan().to_degrees()),
        // Above the bench, behind the lamp and to its near side: the camera
        // of Pictures 4-6, the lamp, the prism, the fan and the screen all
        // in view, the tripod whole, the prism as large as a view of the
        // whole bench allows (it is 16 cm of a bench 3 m long).
        View::Overview => (DVec3::new(-2.78, -1.81, 0.52), DVec3::new(-0.17, -0.02, -0.05), 28.1),
    };
    if o.view == View::Overview {
        // That camera drawn where it stands: a grey body 8 x 5 x 5 cm on a
        // post from the table.
        let (l, w, h) = (0.08, 0.05, 0.05);
        let c = bench_cam - DVec3::new(l / 2.0, w / 2.0, h / 2.0);
        let body = [0.45; 3];
        super::matte(scene, "camera top", c + DVec3::new(0.0, 0.0, h), DVec3::new(l, 0.0, 0.0), DVec3::new(0.0, w, 0.0), body);
        super::matte(scene, "camera side", c, DVec3::new(l, 0.0, 0.0), DVec3::new(0.0, 0.0, h), body);
        super::matte(scene, "camera front", c + DVec3::new(l, 0.0, 0.0), DVec3::new(0.0, w, 0.0), DVec3::new(0.0, 0.0, h), body);
        super::matte(scene, "camera back", c, DVec3::new(0.0, 0.0, h), DVec3::new(0.0, w, 0.0), body);
        // Its lens: a black barrel 3 x 3 cm, 5 cm long, from the body's
        // front toward the bench.
        let (lb, ll) = (0.03, 0.05);
        let f = c + DVec3::new(l, (w - lb) / 2.0, (h - lb) / 2.0);
        let lens = [0.05; 3];
        super::matte(scene, "camera lens top", f + DVec3::new(0.0, 0.0, lb), DVec3::new(ll, 0.0, 0.0), DVec3::new(0.0, lb, 0.0), lens);
        super::matte(scene, "camera lens side", f, DVec3::new(ll, 0.0, 0.0), DVec3::new(0.0, 0.0, lb), lens);
        super::matte(scene, "camera lens side", f + DVec3::new(0.0, lb, 0.0), DVec3::new(0.0, 0.0, lb), DVec3::new(ll, 0.0, 0.0), lens);
        super::matte(scene, "camera lens front", f + DVec3::new(ll, 0.0, 0.0), DVec3::new(0.0, lb, 0.0), DVec3::new(0.0, 0.0, lb), lens);
        // Its viewfinder hump: 3 x 3 x 2 cm on the body's top, over the lens.
        let (hl, hw, hh) = (0.03, 0.03, 0.02);
        let t = c + DVec3::new((l - hl) / 2.0, (w - hw) / 2.0, h);
        super::matte(scene, "camera hump top", t + DVec3::new(0.0, 0.0, hh), DVec3::new(hl, 0.0, 0.0), DVec3::new(0.0, hw, 0.0), body);
        super::matte(scene, "camera hump side", t, DVec3::new(hl, 0.0, 0.0), DVec3::new(0.0, 0.0, hh), body);
        super::matte(scene, "camera hump back", t, DVec3::new(0.0, 0.0, hh), DVec3::new(0.0, hw, 0.0), body);
        // A tripod: three dark legs, 1.2 cm wide, from under the body to
        // feet 14 cm out on the table, one to the far side and two toward
        // the viewer, each facing the overview camera (-y).
        let head = bench_cam - DVec3::new(0.0, 0.0, h / 2.0);
        for angle in TRIPOD_LEG_ANGLES {
            let (sin, cos) = angle.to_radians().sin_cos();
            let foot = DVec3::new(bench_cam.x + TRIPOD_SPREAD * cos, bench_cam.y + TRIPOD_SPREAD * sin, z);
            let (across, along) = (DVec3::new(0.012, 0.0, 0.0), head - foot);
            let corner = foot - across / 2.0;
            let (eu, ev) = if across.cross(along).y < 0.0 { (across, along) } else { (along, across) };
            super::matte(scene, "tripod leg", corner, eu, ev, lens);
        }
    }
    let vfov = 2.0 * ((hfov.to_radians() / 2.0).tan() / aspect).atan();
    scene.camera = Camera::look_at(cam, target, DVec3::Z, vfov.to_degrees(), o.width, o.height);
    Ok(())
}

/// The bench's slit, width and height, m: its white image on the screen
/// a patch the camera of Pictures 4-6 reads (1 cm blurs the 19 cm strip
/// by a twentieth of its length; 4 cm tall, within the prism's 5 cm, so
/// the strip is a band across the screen, not a line).
const BENCH_SLIT: (f64, f64) = (0.01, 0.04);
/// The optical rail's height above the table, m: its top 2.5 cm up, under
/// the slit's lower edge (2 cm under the beam's axis, which runs 7 cm above
/// the table).
const BENCH_RAIL_HEIGHT: f64 = 0.025;
/// The overview's tripod: its legs' directions round the camera (degrees
/// from +x, seen from above) and how far out their feet stand, m.
const TRIPOD_LEG_ANGLES: [f64; 3] = [90.0, 210.0, 330.0];
const TRIPOD_SPREAD: f64 = 0.14;
/// How far the lamp's slit stands before the prism's entry face, m: far
/// enough that the lamp housing stands wholly outside the frame of
/// Pictures 4-6 (at 15 cm its front corner was cut by the frame's edge).
const BENCH_LAMP_GAP: f64 = 0.30;
/// Faces an eye path through the bench's prism splits at (`World::
/// eye_split_depth`): top, two cemented faces, base and back; measured at
/// quick size, 4 left the prism's top grainy, 8 smooth, for 10 % more eye
/// rays.
const BENCH_SPLIT_DEPTH: usize = 8;

/// The bench's haze, per metre: enough that the beam shows over the
/// table's light, too little to veil the screen or, seen along the fan,
/// to outshine the strip (at 3 the fan in the haze was as bright as the
/// strip and veiled its violet end).
const BENCH_HAZE: f64 = 1.5;

/// Picture 1: a compact fluorescent lamp down a hall past the prism, and
/// the camera just before the entry face looking back through the prism
/// at it. The lamp is a twin-tube CFL, its two legs side by side as seen.
/// Its width as seen (`LAMP_WIDTH` at `LAMP_DISTANCE`, 0.057 degrees) is
/// under half the gap between the red 611 nm copy and the weak 599 nm one
/// with the 80 degree flint (0.117 degrees), so a dark column stands
/// between the red copies and the orange ones (587-599 nm) even with each
/// phosphor line's width smearing its copy; the Eu 615 nm copy, 0.037
/// degrees from the 611 nm one, falls beside its left leg and leaves the
/// gap between its legs open. The phosphors' continuum, whose brightness
/// at a point grows with the band of wavelengths one lamp's width spans,
/// stays a few per cent of the copies'.
fn add_lamp(scene: &mut World, o: &SceneOptions, prism: &AmiciPrism, design: &World, d_line: &ProbeRay) -> Result<()> {
    let x = d_line.exit_point.x + LAMP_DISTANCE;
    let spectrum = light_spectrum(o, "cfl-lines")?;
    let parts = twin_tube_lamp(x);
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
    // The camera frames the lamp's images from the blue mercury line to
    // the red europium lines (`FRAME_NM`; where each appears, found by
    // tracing back through the prism), with 5 % to spare on each side. The
    // violet 404.7 nm image lies beyond the blue one, outside the frame: to
    // the eye (the CIE observer) it is about 30 times fainter than the
    // 435.8 nm image (half the power, a fifteenth of the blue response;
    // its legs 1/32 of the blue copy's in linear blue, measured), black in
    // any exposure that does not lift the continuum between the copies
    // over the print's black point (6 times the figure's, where the
    // violet copy first shows, prints the continuum as a haze); framing
    // it would shrink every copy by a third for a black patch.
    let cam = DVec3::new(prism.parts[0][1].x - 0.03, 0.0, 0.0);
    let blue = lamp_image_angle(design, cam, x, FRAME_NM.0);
    let (Some(blue), Some(red)) = (blue, lamp_image_angle(design, cam, x, FRAME_NM.1)) else {
        match o.incidence_deg {
            Some(_) => return Err(SceneError::param("incidence", "the lamp cannot be seen through the prism at 436-711 nm")),
            None => return Err(SceneError::design(o, "the lamp cannot be seen through this prism at 436-711 nm")),
        }
    };
    let look = rotate_z(DVec3::X, (blue + red) / 2.0);
    let hfov = (blue - red).abs() * 1.1 + 2.0 * LAMP_WIDTH / LAMP_DISTANCE;
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

/// The wavelengths, nm, whose copies of the lamp the frame spans: the
/// blue mercury line to past the last bright europium lines (626, 631).
const FRAME_NM: (f64, f64) = (435.834, 640.0);

/// How far the lamp stands past the prism's exit face, m.
pub const LAMP_DISTANCE: f64 = 30.0;
/// The lamp's width and height and its tube's diameter, m: a twin-tube
/// ("2U") compact fluorescent lamp, two legs joined across the top.
pub const LAMP_WIDTH: f64 = 0.030;
const LAMP_HEIGHT: f64 = 0.17;
const LAMP_TUBE: f64 = 0.0085;

/// The twin-tube lamp at distance `x` along the axis, seen from the side
/// its legs stand in: as emitting rectangles facing -x (corner, edge
/// across the tube, edge along it), its two legs and the bend across
/// their tops, an upside-down U.
fn twin_tube_lamp(x: f64) -> Vec<(DVec3, DVec3, DVec3)> {
    let (w, h, t) = (LAMP_WIDTH, LAMP_HEIGHT, LAMP_TUBE);
    // Each pair's cross product is -x: the emitting side faces the prism.
    let across = DVec3::new(0.0, -t, 0.0);
    let leg = DVec3::new(0.0, 0.0, h - t);
    vec![
        (DVec3::new(x, w / 2.0, -h / 2.0), across, leg),
        (DVec3::new(x, -w / 2.0 + t, -h / 2.0), across, leg),
        (DVec3::new(x, w / 2.0, h / 2.0 - t), DVec3::new(0.0, -w, 0.0), DVec3::new(0.0, 0.0, t)),
    ]
}
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

    /// The bench (amici-bench) seen from `view`, and the height of its table.
    fn bench(view: View) -> (World, f64) {
        let mut o = SceneOptions::new(SceneKind::AmiciBench);
        o.view = view;
        let w = build(&o).unwrap();
        let table = w.faces.iter().find(|f| f.name == "table").unwrap().verts[0].z;
        (w, table)
    }

    /// The extent of the faces named `name`: lowest and highest corner.
    fn extent(w: &World, name: &str) -> (DVec3, DVec3) {
        let verts = w.faces.iter().filter(|f| f.name == name).flat_map(|f| f.verts.clone());
        verts.fold((DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)), |(lo, hi), v| (lo.min(v), hi.max(v)))
    }

    #[test]
    fn the_bench_rail_runs_from_the_lamp_to_the_screen_under_the_beam() {
        let (w, table) = bench(View::Scene);
        let (lo, hi) = extent(&w, "rail top");
        let Emission::Beam { centre, half, v, .. } = w.lights[0].emission else { panic!("the slit beam first") };
        let slit_bottom = centre.z - half.y * v.z.abs();
        assert!(
            table < lo.z && hi.z < slit_bottom,
            "the rail's top at {:.3} m, between the table ({table:.3}) and the slit's lower edge ({slit_bottom:.3})",
            hi.z
        );
        let (lamp, _) = extent(&w, "lamp side");
        let (screen, _) = extent(&w, "screen");
        assert!(
            lo.x <= lamp.x + 0.13 && hi.x >= screen.x,
            "the rail spans x {:.2}..{:.2}, the lamp to the screen ({:.2}..{:.2})",
            lo.x,
            hi.x,
            lamp.x,
            screen.x
        );
        assert!(lo.y.abs() < 0.06 && hi.y.abs() < 0.06, "the rail lies under the beam");
    }

    #[test]
    fn the_overview_camera_stands_on_three_legs() {
        let (w, table) = bench(View::Overview);
        let legs: Vec<&crate::world::Face> = w.faces.iter().filter(|f| f.name == "tripod leg").collect();
        assert_eq!(legs.len(), 3);
        let (body, _) = extent(&w, "camera side");
        let mut feet = Vec::new();
        for leg in legs {
            let (lo, hi) = leg.verts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v.z), hi.max(v.z)));
            assert!((lo - table).abs() < 1e-9 && (hi - body.z).abs() < 1e-9, "a leg from the table ({table}) to under the body ({}): {lo}..{hi}", body.z);
            assert!(leg.normal.y < 0.0, "each leg faces the overview camera");
            feet.push(leg.verts.iter().map(|v| DVec2::new(v.x, v.y)).sum::<DVec2>());
        }
        assert!(feet.iter().all(|a| feet.iter().filter(|b| (**b - *a).length() > 0.1).count() == 2), "the feet stand apart");
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
