//! Reports 001 and 003's scenes against closed-form optics: a glass ball
//! focuses a collimated beam where the paraxial ball-lens formula says, and
//! the Cornell box's laser lands on the wall where `refract prism trace`
//! (the probe) says.

use glam::DVec3;
use refract::optics::ior::IorModel;
use refract::photon::emit::{light_pass, Batch, Keep};
use refract::scenes::{build, SceneKind, SceneOptions};
use refract::spectrum::colormap::ColorMap;
use refract::spectrum::spectra::NamedSpectrum;
use refract::world::probe::probe;
use refract::world::{Medium, Sphere, Surface, World};

/// A glass ball of index `n` and radius `r` at the origin, and the axis
/// distance from its centre where a ray entering parallel to the axis at
/// height `h` crosses the axis after two refractions.
fn ball_focus(n: f64, r: f64, h: f64) -> f64 {
    let mut w = World::new("ball", vec![Medium::Air, Medium::Glass { name: "n".into(), ior: IorModel::Constant(n) }], 8, 8);
    w.spheres.push(Sphere { name: "ball".into(), centre: DVec3::ZERO, radius: r, surface: Surface::Interface { front: 0, back: 1 } });
    w.probe = (DVec3::new(-3.0 * r, h, 0.0), DVec3::X);
    let p = probe(&w, 550.0);
    assert_eq!(p.faces, 2, "in and out of the ball");
    assert!(!p.tir);
    // Where the exit ray meets y = 0.
    let t = -p.exit_point.y / p.exit_dir.y;
    (p.exit_point + t * p.exit_dir).x
}

#[test]
fn a_glass_ball_focuses_at_the_paraxial_focal_length() {
    for (n, r) in [(1.5, 1.0), (1.5168, 0.5), (1.8, 0.38), (1.33, 2.0)] {
        // Effective focal length from the centre: f = n R / (2 (n - 1)).
        let f = n * r / (2.0 * (n - 1.0));
        let paraxial = ball_focus(n, r, 1e-3 * r);
        assert!((paraxial / f - 1.0).abs() < 1e-5, "n {n}, R {r}: focus {paraxial} vs {f}");
        // Spherical aberration: rays farther out focus closer to the ball.
        let marginal = ball_focus(n, r, 0.3 * r);
        assert!(marginal < paraxial - 1e-3 * r, "n {n}: marginal {marginal} vs paraxial {paraxial}");
    }
}

#[test]
fn the_cornell_laser_lands_where_the_probe_says() {
    for nm in [450.0, 532.0, 650.0] {
        let mut o = SceneOptions::new(SceneKind::CornellLaser);
        o.light = Some(NamedSpectrum::parse(&format!("laser:{nm}")).unwrap());
        let mut scene = build(&o).unwrap();
        // The laser alone, stored where it first lands.
        scene.lights.truncate(1);
        scene.bounces = 0;
        let p = probe(&scene, nm);
        assert_eq!(p.faces, 2, "through the prism: in and out");
        // Just past the exit face, so the ray does not meet it again.
        let start = p.exit_point + 1e-9 * p.exit_dir;
        let hit = scene.intersect(start, p.exit_dir, None).expect("the beam reaches a wall");
        let spot = start + hit.t * p.exit_dir;
        let Surface::Diffuse { map, .. } = *scene.surface(hit.face) else { panic!("the beam lands on a matte wall, not {}", scene.name(hit.face)) };
        let face = &scene.faces[hit.face];
        let (_, eu, ev) = face.frame.unwrap();
        let uv = face.uv(spot).unwrap();
        let want = glam::DVec2::new(uv.x * eu.length(), uv.y * ev.length());
        let pass = light_pass(&scene, Batch::new(40_000, 7, ColorMap::Cie), Keep, &refract::progress::Silent);
        // Photon-weighted centre of what landed within 5 cm of the prediction.
        let (mut sum, mut weight) = (glam::DVec2::ZERO, 0.0);
        for ph in &pass.photons[map] {
            let q = glam::DVec2::new(ph.pos[0] as f64, ph.pos[1] as f64);
            if (q - want).length() < 0.05 {
                sum += q * ph.xyz()[1] as f64;
                weight += ph.xyz()[1] as f64;
            }
        }
        assert!(weight > 0.0, "{nm} nm: nothing landed near {want}");
        let centre = sum / weight;
        assert!((centre - want).length() < 5e-4, "{nm} nm on {}: photons centred at {centre}, probe says {want}", scene.name(hit.face));
    }
}

#[test]
fn the_laser_spectrum_on_the_back_wall_is_long_enough_to_read() {
    // Where 400 and 700 nm land (the probe's optics), projected through the
    // figure's camera (pm-laser-prism is 480x360): at least 50 px apart,
    // both on the back wall. (57 px: the laser now comes in from the right
    // wall, its beam seen entering the prism, and the fan meets the back
    // wall's far left half; the spectrum there is a band 6 cm tall, not the
    // 80 px hairline of a beam from the front; `figure_content` measures
    // the band in the image.)
    let mut o = SceneOptions::new(SceneKind::CornellLaser);
    o.crown = refract::optics::glass::by_name("N-SF11").unwrap();
    o.ior = refract::optics::ior::IorKind::Musgrave;
    [o.width, o.height] = [480, 360];
    let scene = build(&o).unwrap();
    let land = |nm: f64| {
        let p = probe(&scene, nm);
        assert!(!p.tir && p.faces == 2, "{nm} nm must pass through the prism");
        let start = p.exit_point + 1e-9 * p.exit_dir;
        let hit = scene.intersect(start, p.exit_dir, None).expect("the fan reaches a wall");
        assert_eq!(scene.name(hit.face), "back wall", "{nm} nm");
        scene.camera.project(start + hit.t * p.exit_dir).expect("in view")
    };
    let length = (land(400.0) - land(700.0)).length();
    assert!(length >= 50.0, "the spectrum is {length:.1} px long");
}

/// A matte wall of `albedo` 1 m before the camera, lit from the side by a
/// wide beam of `light` (which never meets the glass, so both renders
/// share one photon map); with `plate`, a 1 cm N-SF11 plate stands in
/// between, face-on. Returns the mean XYZ over the image.
fn wall_through_plate(albedo: [f64; 3], light: &str, plate: bool) -> DVec3 {
    use refract::photon::gather::{Filter, Lookup};
    use refract::spectral::options::{EyeMode, RenderOptions};
    use refract::world::{Albedo, Emission, Face, Light};
    let glass = refract::optics::glass::by_name("N-SF11").unwrap();
    let ior = IorModel::for_glass(glass, refract::optics::ior::IorKind::Sellmeier);
    let mut w = World::new("plate", vec![Medium::Air, Medium::Glass { name: "N-SF11".into(), ior }], 24, 16);
    let v = DVec3::new;
    // Normal -x (toward the camera): u along +z, v along +y.
    w.faces.push(refract::world::Face::rect(
        "wall",
        v(1.0, -0.5, -0.5),
        v(0.0, 0.0, 1.0),
        v(0.0, 1.0, 0.0),
        Surface::Diffuse { albedo: Albedo::new(albedo), map: 0 },
    ));
    w.maps.push(0);
    if plate {
        // Normals point out of the glass.
        w.faces.push(Face::rect("plate front", v(0.4, -0.3, -0.3), v(0.0, 0.6, 0.0), v(0.0, 0.0, 0.6), Surface::Interface { front: 0, back: 1 }));
        w.faces.push(Face::rect("plate back", v(0.41, -0.3, -0.3), v(0.0, 0.0, 0.6), v(0.0, 0.6, 0.0), Surface::Interface { front: 0, back: 1 }));
    }
    let dir = v(0.6, 0.8, 0.0).normalize();
    let u = DVec3::Z.cross(dir).normalize();
    w.lights.push(Light {
        name: "beam".into(),
        emission: Emission::Beam {
            centre: v(1.0, 0.0, 0.0) - dir * 0.5,
            dir,
            u,
            v: DVec3::Z,
            half: glam::DVec2::new(0.2, 0.2),
            disc: false,
            polarisation: None,
        },
        spectrum: NamedSpectrum::parse(light).unwrap().spectrum,
        power: 1.0,
    });
    w.camera = refract::world::Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 6.0, 24, 16);
    let o = RenderOptions {
        photons: 400_000,
        map: refract::photon::map::MapKind::Kdtree,
        filter: Filter::Cone,
        lookup: Lookup::Radius(0.02),
        spp: 16,
        seed: 3,
        eye: EyeMode::Hero,
        split: 8,
        colours: ColorMap::Cie,
        film_kernel: None,
    };
    let r = refract::spectral::render::render(&w, &o, &refract::progress::Silent);
    r.image.xyz.iter().sum::<DVec3>() / r.image.xyz.len() as f64
}

#[test]
fn a_glass_plate_keeps_the_colour_of_the_wall_behind_it() {
    let xy = |c: DVec3| glam::DVec2::new(c.x, c.y) / (c.x + c.y + c.z);
    // At normal incidence each face of N-SF11 (n = 1.76-1.81) reflects
    // 7.6-8.3 %: the plate passes 84-86 % whatever the colour.
    for light in ["d65", "cfl-lines", "laser:532"] {
        for albedo in [[0.12, 0.55, 0.12], [0.75, 0.12, 0.1], [0.1, 0.2, 0.8], [0.75; 3]] {
            let (bare, seen) = (wall_through_plate(albedo, light, false), wall_through_plate(albedo, light, true));
            let shift = (xy(seen) - xy(bare)).length();
            assert!(shift < 0.005, "{light}, albedo {albedo:?}: the plate moves the chromaticity by {shift:.4}");
            if light == "laser:532" {
                // Laser light off any wall is still 532 nm light: the wall's
                // reflectance spectrum scales it (an RGB product would
                // shift its colour, even below zero).
                let line = xy(refract::spectrum::cie::cmf(532.0));
                assert!((xy(bare) - line).length() < 0.005, "albedo {albedo:?}: 532 nm comes back at {:?}, not {line:?}", xy(bare));
            }
            let t = seen.y / bare.y;
            assert!((0.82..0.88).contains(&t), "{light}, albedo {albedo:?}: the plate passes {t:.3} of the luminance");
        }
    }
}

#[test]
fn the_album_cover_is_level_with_the_beam_from_the_left_and_the_fan_to_the_right() {
    let mut o = SceneOptions::new(SceneKind::DarkSide);
    o.crown = refract::optics::glass::by_name("N-SF11").unwrap();
    [o.width, o.height] = [480, 360];
    let scene = build(&o).unwrap();
    let cam = &scene.camera;
    let project = |p: DVec3| cam.project(p).expect("in view");
    // The glowing outline's three strips: the base (lowest in the picture)
    // is level to a pixel, the apex above it.
    let mut ends: Vec<(glam::DVec2, glam::DVec2)> =
        scene.faces.iter().filter(|f| f.name.starts_with("outline")).map(|f| (project(f.verts[0]), project(f.verts[1]))).collect();
    assert_eq!(ends.len(), 3, "three outline strips");
    // Image y grows downward: the base has the largest y.
    ends.sort_by(|a, b| (b.0.y + b.1.y).total_cmp(&(a.0.y + a.1.y)));
    let base = ends[0];
    assert!((base.0.y - base.1.y).abs() < 1.0, "the base is level: {base:?}");
    assert!(ends[1].0.y.min(ends[1].1.y) < base.0.y - 50.0, "the apex stands above the base");
    // The beam comes in from the left, rising; the fan leaves to the right.
    let Some(beam) = scene.lights.iter().find(|l| l.name == "white beam") else { panic!("no beam") };
    let refract::world::Emission::Beam { centre, dir, .. } = beam.emission else { panic!("the beam is a beam") };
    let (from, to) = (project(centre), project(centre + dir * 0.5));
    assert!(to.x > from.x && to.y < from.y, "the beam goes right and up the picture: {from:?} -> {to:?}");
    let p = probe(&scene, 550.0);
    let (a, b) = (project(p.exit_point.with_z(0.0)), project((p.exit_point + p.exit_dir * 0.3).with_z(0.0)));
    assert!(b.x > a.x + 20.0 && b.y > a.y, "the fan goes right and down the picture: {a:?} -> {b:?}");
}

#[test]
fn direct_lighting_by_shadow_rays_matches_the_photon_map() {
    // Report 003's Cornell box lit by its point light: the eye pass's
    // shadow rays (direct light) plus the maps' caustic and bounced light
    // against the maps alone, which hold it all. The same brightness per
    // wall, to within the photon noise. (Report 001's metal plate is a
    // mirror under glowing surfaces now: nothing matte to compare.)
    for kind in [SceneKind::CornellPointlight, SceneKind::CornellLaser] {
        same_light_both_ways(kind);
    }
}

/// (The laser's box is lit by a ceiling lamp: an area light.)
fn same_light_both_ways(kind: SceneKind) {
    use refract::photon::gather::{Filter, Lookup};
    use refract::spectral::options::{EyeMode, RenderOptions};
    let mut o = SceneOptions::new(kind);
    [o.width, o.height] = [64, 48];
    let mut with = build(&o).unwrap();
    assert!(with.direct_lighting, "{kind:?} lights directly");
    if kind == SceneKind::CornellLaser {
        // The figure's camera is framed on the prism and its fan; the bands
        // below are the left, back and right walls as the box's front view
        // (the other boxes' camera) shows them.
        with.camera = refract::world::Camera::look_at(DVec3::new(0.0, -3.3, 1.0), DVec3::new(0.0, 0.0, 0.9), DVec3::Z, 38.0, o.width, o.height);
    }
    let mut without = with.clone();
    without.direct_lighting = false;
    let opts = RenderOptions {
        photons: 2_000_000,
        map: refract::photon::map::MapKind::Kdtree,
        filter: Filter::Cone,
        lookup: Lookup::Radius(0.06),
        spp: 4,
        seed: 5,
        eye: EyeMode::Hero,
        split: 8,
        colours: ColorMap::Cie,
        film_kernel: None,
    };
    let render = |w: &World| refract::spectral::render::render(w, &opts, &refract::progress::Silent).image;
    let (a, b) = (render(&with), render(&without));
    // Column bands: left (red) wall, back wall, right (green) wall.
    let band = |img: &refract::spectral::film::XyzImage, x0: usize, x1: usize| -> DVec3 {
        (8..40).flat_map(|y| (x0..x1).map(move |x| (x, y))).map(|(x, y)| img.xyz[y * img.width + x]).sum::<DVec3>()
    };
    for (x0, x1) in [(2, 8), (20, 44), (56, 62)] {
        let (p, q) = (band(&a, x0, x1), band(&b, x0, x1));
        for c in 0..3 {
            assert!((p[c] / q[c] - 1.0).abs() < 0.05, "{kind:?}, columns {x0}-{x1}, XYZ[{c}]: {:.4} with shadow rays, {:.4} from the maps", p[c], q[c]);
        }
    }
}

#[test]
fn the_glass_sphere_rings_the_card_with_a_rainbow() {
    // Report 001's final image: a white beam through a hole in a card onto
    // a glass sphere 2.5 m away. Photons that reflect once inside the
    // sphere land on the card round the hole at Descartes's rainbow angle
    // theta = 180 deg - D_min(n), cos^2 i = (n^2 - 1) / 3: at
    // R sin i / cos theta + L tan theta from the hole's centre
    // (docs/physics.md §21): the density peaks there, and red photons land
    // farther out than blue ones.
    use refract::photon::emit::{light_pass, Batch, Keep};
    let mut o = SceneOptions::new(SceneKind::SpheresFinal);
    [o.width, o.height] = [64, 48];
    o.crown = refract::optics::glass::by_name("N-SF11").unwrap();
    let s = build(&o).unwrap();
    let pass = light_pass(&s, Batch::new(400_000, 3, ColorMap::Cie), Keep, &refract::progress::Silent);
    // Radius from the hole's centre of every photon on the card's four
    // pieces (each map's origin is its face's corner), with its colour.
    let mut hits: Vec<(f64, [f32; 3])> = Vec::new();
    for (slot, photons) in pass.photons.iter().enumerate() {
        let f = &s.faces[s.slot_face(slot)];
        let (c, eu, ev) = f.frame.unwrap();
        for p in photons {
            let q = c + eu.normalize() * p.pos[0] as f64 + ev.normalize() * p.pos[1] as f64;
            hits.push((q.y.hypot(q.z), p.xyz()));
        }
    }
    assert!(hits.len() > 20_000, "{} photons on the card", hits.len());
    let glass = o.crown;
    let radius = |nm: f64| {
        let n = glass.sellmeier(nm);
        let i = ((n * n - 1.0) / 3.0).sqrt().acos();
        let r = (i.sin() / n).asin();
        let theta = std::f64::consts::PI - (std::f64::consts::PI + 2.0 * i - 4.0 * r);
        // The ray leaves along a line R sin i from the sphere's centre, on
        // the far side of the axis, and tilts outward by theta on its way
        // back to the card.
        0.15 * i.sin() / theta.cos() + 2.5 * theta.tan()
    };
    // Photon density per unit area in 5 mm rings: its peak.
    let mut bins = vec![0f64; 80];
    for &(rho, xyz) in &hits {
        let b = (rho / 0.005) as usize;
        if b < bins.len() {
            bins[b] += (xyz[1] as f64) / (2.0 * std::f64::consts::PI * (b as f64 + 0.5));
        }
    }
    let peak = (0..bins.len()).max_by(|&a, &b| bins[a].total_cmp(&bins[b])).unwrap();
    let peak_rho = (peak as f64 + 0.5) * 0.005;
    let (r_red, r_blue, r_mid) = (radius(650.0), radius(450.0), radius(560.0));
    assert!(r_red > r_blue, "{r_red} {r_blue}");
    assert!(
        peak_rho > r_blue - 0.005 && peak_rho < r_red + 0.005,
        "density peaks at {peak_rho:.3} m; the rainbow runs {r_blue:.3}-{r_red:.3} m (560 nm: {r_mid:.3})"
    );
    // Colour order: in the ring, the redder photons (X over Z) land farther out.
    let ring: Vec<&(f64, [f32; 3])> = hits.iter().filter(|h| h.0 > r_blue - 0.02 && h.0 < r_red + 0.02).collect();
    let mean = |f: &dyn Fn(&[f32; 3]) -> bool| {
        let v: Vec<f64> = ring.iter().filter(|h| f(&h.1)).map(|h| h.0).collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let (red, blue) = (mean(&|c| c[0] > 2.0 * c[2] && c[0] > c[1]), mean(&|c| c[2] > 2.0 * c[0]));
    assert!(red > blue + 0.01, "red photons at {red:.3} m, blue at {blue:.3} m");
}

/// The light the mirror tube's mirrors send to the wall it faces (no
/// prism in the way; its straight light is not stored as photons): per
/// 2 cm cell of that wall's photon map, the flux's departure from the
/// mean of the 7 x 7 cells round it, over the cells whose surroundings
/// are lit to at least a third of the brightest, as an RMS, and the RMS
/// that photon noise alone would give (from each cell's photon weights).
fn tube_wall_ripple(photons: u64) -> (f64, f64, usize) {
    let scene = build(&SceneOptions { no_prism: true, ..SceneOptions::new(SceneKind::CornellMirrorTube) }).unwrap();
    let pass = light_pass(&scene, Batch::new(photons, 3, ColorMap::Cie), Keep, &refract::progress::Silent);
    let total = |m: &Vec<refract::photon::map::Photon>| m.iter().map(|p| p.xyz()[1] as f64).sum::<f64>();
    let wall = pass.photons.iter().max_by(|a, b| total(a).total_cmp(&total(b))).unwrap();
    let cell = 0.02;
    let (nu, nv) = (110, 110);
    let (mut sum, mut sq) = (vec![0.0; nu * nv], vec![0.0; nu * nv]);
    for p in wall {
        let (iu, iv) = ((p.pos[0] as f64 / cell) as usize, (p.pos[1] as f64 / cell) as usize);
        if iu < nu && iv < nv {
            let y = p.xyz()[1] as f64;
            sum[iv * nu + iu] += y;
            sq[iv * nu + iu] += y * y;
        }
    }
    let around = |u: usize, v: usize| (v - 3..=v + 3).flat_map(|y| (u - 3..=u + 3).map(move |x| (x, y))).map(|(x, y)| sum[y * nu + x]).sum::<f64>() / 49.0;
    let inner = || (3..nv - 3).flat_map(|v| (3..nu - 3).map(move |u| (u, v)));
    let most = inner().map(|(u, v)| around(u, v)).fold(0.0, f64::max);
    let (mut dev, mut noise, mut n) = (0.0, 0.0, 0);
    for (u, v) in inner() {
        let (s, around) = (sum[v * nu + u], around(u, v));
        if around >= most / 3.0 {
            dev += ((s - around) / around).powi(2);
            noise += sq[v * nu + u] / (around * around);
            n += 1;
        }
    }
    ((dev / n as f64).sqrt(), (noise / n as f64).sqrt(), n)
}

#[test]
fn the_mirror_tube_lights_its_wall_without_a_grid_of_blotches() {
    // The tube's mirrors make a lattice of images of its lamp; a small
    // bulb (a sphere 1.6 cm across in the 2.5 cm bore) left gaps between
    // them, and the mouth framed more or less bulb from point to point of
    // the wall: a regular grid of blotches (with it, 5.3 % RMS beyond the
    // photons' 7.9 % on 2 cm cells). The lamp filling the tube's end tiles
    // the lattice without gaps: the ripple is the photons' noise (10.7 %
    // against 10.7 %).
    let (ripple, noise, cells) = tube_wall_ripple(4_000_000);
    let excess = (ripple * ripple - noise * noise).max(0.0).sqrt();
    eprintln!("mirror tube's wall: {cells} cells, ripple {ripple:.4}, photon noise {noise:.4}, beyond the noise {excess:.4}");
    assert!(cells >= 100, "only {cells} lit cells");
    assert!(excess < 0.03, "a ripple of {excess:.3} beyond the photons' noise ({ripple:.3} in all, {noise:.3} noise)");
}
