//! What the contrasting figures must show, measured on renders of their
//! own scene files (scenes/*.toml, at their quick size): report 004's pairs
//! differ where their captions say, the Cornell box's walls appear in the
//! sphere at trace count 10 but not at 0, and report 000's Pictures 4-6
//! differ where theirs do.

use crate::common::repo;
use refract::experiment::params::interior_config;
use refract::experiment::scene_file::SceneFile;
use refract::image_io::Image;

/// The figure's image, rendered in memory as `refract figures --quick` does.
fn figure(id: &str) -> Image {
    let s = SceneFile::load(&repo(&format!("scenes/{id}.toml")), true).unwrap();
    let mut cfg = interior_config(&s.params).unwrap();
    cfg.off = refract::mesh::source::MeshSource::parse(&repo(&cfg.off.to_string()).display().to_string()).unwrap();
    let mesh = cfg.off.load().unwrap();
    refract::interior::render_mesh(mesh, &cfg).unwrap().image
}

fn grey(img: &Image) -> Vec<f64> {
    img.to_rgb8().chunks(3).map(|c| (c[0] as f64 + c[1] as f64 + c[2] as f64) / 3.0).collect()
}

#[test]
fn report_004_pairs_differ_where_their_captions_say() {
    // Attenuation: at least 10 grey levels apart on average over the object.
    let (a, b) = (grey(&figure("lab-ior1.1-noatten")), grey(&figure("lab-ior1.1-atten")));
    let object: Vec<(f64, f64)> = a.iter().zip(&b).filter(|(x, y)| **x > 0.0 || **y > 0.0).map(|(x, y)| (*x, *y)).collect();
    let mean = object.iter().map(|(x, y)| (x - y).abs()).sum::<f64>() / object.len() as f64;
    assert!(mean >= 10.0, "attenuation pair differs by {mean:.1} grey levels");
    // Shininess 8 against 16: a highlight (luminance >= 0.75) at least 30 % larger.
    let area = |img: &Image| grey(img).iter().filter(|v| **v >= 0.75 * 255.0).count() as f64;
    let (n16, n8) = (area(&figure("lab-ior1.4")), area(&figure("lab-ior1.4-n8")));
    assert!(n8 >= 1.3 * n16, "highlight {n8} px at shininess 8 against {n16} px at 16");
}

#[test]
fn the_cornell_walls_show_in_the_sphere_only_when_rays_are_followed() {
    // Red or green excess (one channel over the mean of the other two) inside
    // the sphere's disc (centred, a quarter of the width in radius).
    let tinted = |img: &Image| -> usize {
        let (w, h) = (img.width, img.height);
        let px = img.to_rgb8();
        let mut n = 0;
        let r2 = (0.26 * w as f64).powi(2);
        for y in 0..h {
            for x in (0..w).filter(|&x| (x as f64 - w as f64 / 2.0).powi(2) + (y as f64 - h as f64 / 2.0).powi(2) < r2) {
                let c = &px[(y * w + x) * 3..(y * w + x) * 3 + 3];
                let (r, g, b) = (c[0] as i32, c[1] as i32, c[2] as i32);
                if r - (g + b) / 2 > 25 || g - (r + b) / 2 > 25 {
                    n += 1;
                }
            }
        }
        n
    };
    let (t0, t10) = (tinted(&figure("lab-cornell-trace0")), tinted(&figure("lab-cornell-trace10")));
    assert_eq!(t0, 0, "at trace 0 the sphere shows no wall");
    assert!(t10 > 100, "at trace 10 the walls show in the sphere: {t10} tinted pixels");
}

/// A prism-mode figure's display pixels, rendered in memory at quick size.
fn prism_figure(id: &str) -> (usize, usize, Vec<u8>) {
    let s = SceneFile::load(&repo(&format!("scenes/{id}.toml")), true).unwrap();
    let cfg = refract::experiment::params::prism_config(&s.params).unwrap();
    let r = refract::spectral::render_config(&cfg, &refract::progress::Silent).unwrap();
    let img = &r.render.image;
    (img.width, img.height, img.to_srgb8(r.exposure, cfg.gamut))
}

#[test]
fn report_000_pictures_4_to_6_differ_where_their_captions_say() {
    let (p4, p5, p6) = (prism_figure("css552-p4"), prism_figure("css552-p5"), prism_figure("css552-p6"));
    let (w, h) = (p4.0, p4.1);
    let px = |img: &(usize, usize, Vec<u8>), x: usize, y: usize| -> [i32; 3] {
        let i = (y * w + x) * 3;
        [img.2[i] as i32, img.2[i + 1] as i32, img.2[i + 2] as i32]
    };
    // The slit's image: pixels near white on the screen (upper third),
    // against the grey table and screen. Its centroid is the same without
    // the prism (4) and with it at constant index (6), to a pixel.
    let white = |img: &(usize, usize, Vec<u8>)| -> (f64, usize) {
        let (mut sx, mut n) = (0.0, 0);
        for y in 0..h / 3 {
            for x in 0..w {
                if px(img, x, y).iter().all(|&c| c > 200) {
                    sx += x as f64;
                    n += 1;
                }
            }
        }
        (if n > 0 { sx / n as f64 } else { f64::NAN }, n)
    };
    let ((x4, n4), (x6, n6), (_, n5)) = (white(&p4), white(&p6), white(&p5));
    assert!(n4 > 5 && n6 > 5, "a white slit image in Pictures 4 and 6: {n4}, {n6} px");
    assert!((x4 - x6).abs() < 1.0, "the d line lands where it would without the prism: column {x4:.1} against {x6:.1}");
    assert!(n5 < n4 / 4, "in Picture 5 the light is spread into colours, not white: {n5} white px");
    // Picture 5's strip: saturated pixels of at least five distinct hues
    // (sextants of the hue circle and violet) on the screen.
    let mut hues = std::collections::BTreeSet::new();
    for y in 0..h / 3 {
        for x in 0..w {
            let [r, g, b] = px(&p5, x, y);
            let (max, min) = (r.max(g).max(b), r.min(g).min(b));
            if max > 120 && max - min > 80 {
                let hue = if max == r {
                    (60 * (g - b) / (max - min) + 360) % 360
                } else if max == g {
                    60 * (b - r) / (max - min) + 120
                } else {
                    60 * (r - g) / (max - min) + 240
                };
                hues.insert(hue / 45);
            }
        }
    }
    assert!(hues.len() >= 5, "the strip's colours fill {} of 8 hue sectors: {hues:?}", hues.len());
    // The prism is seen: Pictures 4 and 6 differ over at least 1 % of the
    // frame (by more than 30 levels in some channel), below the screen.
    let differ = (h / 3..h).flat_map(|y| (0..w).map(move |x| (x, y))).filter(|&(x, y)| {
        let (a, b) = (px(&p4, x, y), px(&p6, x, y));
        (0..3).any(|c| (a[c] - b[c]).abs() > 30)
    });
    let n = differ.count();
    assert!(n > w * h / 100, "the prism must show in Picture 6: {n} px differ from Picture 4");
}

#[test]
fn the_album_cover_has_no_stray_beams() {
    // pm-dark-side at quick size: above the prism's apex nothing is lit
    // (the beam rises from the lower left, the fan leaves down to the
    // right). Its beam is p-polarised, so at minimum deviation (near
    // Brewster's angle) the faces reflect under 0.2 %; natural light sends
    // 14 % up off the entry face, a grey line above the prism.
    let s = SceneFile::load(&repo("scenes/pm-dark-side.toml"), true).unwrap();
    let cfg = refract::experiment::params::prism_config(&s.params).unwrap();
    let scene = refract::scenes::build(&cfg.scene).unwrap();
    let apex = scene
        .faces
        .iter()
        .filter(|f| f.name.starts_with("outline"))
        .flat_map(|f| f.verts.clone())
        .map(|v| scene.camera.project(v).unwrap().y)
        .fold(f64::MAX, f64::min);
    let brightest_above = |scene: &refract::world::World| -> u8 {
        let r = refract::spectral::render_world(&cfg, scene, &refract::progress::Silent).unwrap();
        let (w, img) = (r.render.image.width, r.render.image.to_srgb8(r.exposure, cfg.gamut));
        let rows = (apex - 4.0) as usize;
        img[..rows * w * 3].chunks(3).map(|c| *c.iter().max().unwrap()).max().unwrap()
    };
    assert!(apex > 30.0, "the apex stands {apex:.0} px below the top");
    let polarised = brightest_above(&scene);
    assert!(polarised < 20, "stray light above the prism: {polarised} of 255");
    let mut natural = scene.clone();
    for l in &mut natural.lights {
        if let refract::world::Emission::Beam { polarisation, .. } = &mut l.emission {
            *polarisation = None;
        }
    }
    let stray = brightest_above(&natural);
    assert!(stray > 3 * polarised.max(10), "natural light shows the entry face's reflection above the prism: {stray} against {polarised}");
}

#[test]
fn the_laser_beam_shows_on_its_way_to_the_prism_and_beyond() {
    // pm-laser-prism at quick size, with its haze and in clear air: the
    // pixels half way from the laser to the prism, and half way from the
    // prism to the wall (550 nm), are lit only by the haze.
    let s = SceneFile::load(&repo("scenes/pm-laser-prism.toml"), true).unwrap();
    let cfg = refract::experiment::params::prism_config(&s.params).unwrap();
    let hazy = refract::scenes::build(&cfg.scene).unwrap();
    assert!(hazy.haze > 0.0, "the laser's box has a haze");
    let mut clear = hazy.clone();
    clear.haze = 0.0;
    let beam = hazy.lights.iter().find(|l| l.name == "laser").expect("a laser");
    let refract::world::Emission::Beam { centre, dir, .. } = beam.emission else { panic!("the laser is a beam") };
    let entry = centre + dir * hazy.intersect(centre, dir, None).expect("the laser meets the prism").t;
    let p = refract::world::probe::probe(&hazy, 550.0);
    let wall = p.exit_point + p.exit_dir * hazy.intersect(p.exit_point + p.exit_dir * 1e-9, p.exit_dir, None).unwrap().t;
    let render = |scene: &refract::world::World| {
        let r = refract::spectral::render_world(&cfg, scene, &refract::progress::Silent).unwrap();
        (r.render.image.width, r.render.image.to_srgb8(r.exposure, cfg.gamut))
    };
    let ((w, with), (_, without)) = (render(&hazy), render(&clear));
    for (what, point) in [("incoming beam", (centre + entry) / 2.0), ("fan", (p.exit_point + wall) / 2.0)] {
        let at = hazy.camera.project(point).expect("in view");
        // The brightest pixel within 2 px (the line is thin).
        let lum = |img: &[u8]| {
            let mut best = 0;
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let (x, y) = ((at.x as i64 + dx) as usize, (at.y as i64 + dy) as usize);
                    let i = (y * w + x) * 3;
                    best = best.max(img[i] as i32 + img[i + 1] as i32 + img[i + 2] as i32);
                }
            }
            best / 3
        };
        let (a, b) = (lum(&with), lum(&without));
        assert!(a > b + 40, "the {what} at {at:?} shows in the haze: {a} against {b} in clear air");
    }
}

#[test]
fn the_glass_sphere_fringes_the_light_blue_inside_and_orange_red_outside() {
    // cs348b-sphere-arealight at its full size (fewer samples): along the
    // row through the light's image in the sphere (the right half), the
    // edge toward the sphere's centre is blue and the outer edge
    // orange-red, each fringe several pixels wide (at least 3 of
    // blue-dominated or red-dominated pixels, across 8 px of each edge);
    // with the index held constant neither edge is coloured.
    let s = SceneFile::load(&repo("scenes/cs348b-sphere-arealight.toml"), false).unwrap();
    let mut cfg = refract::experiment::params::prism_config(&s.params).unwrap();
    cfg.spp = 16;
    let fringes = |cfg: &refract::spectral::SpectralConfig| -> (usize, usize) {
        let r = refract::spectral::render_config(cfg, &refract::progress::Silent).unwrap();
        let (w, h) = (r.render.image.width, r.render.image.height);
        let img = r.render.image.to_srgb8(r.exposure, cfg.gamut);
        let px = |x: usize, y: usize| [img[(y * w + x) * 3] as i32, img[(y * w + x) * 3 + 1] as i32, img[(y * w + x) * 3 + 2] as i32];
        let bright = |p: [i32; 3]| p.iter().sum::<i32>() > 500;
        let (mut sy, mut n) = (0, 0);
        for y in 0..h {
            for x in w / 2..w {
                if bright(px(x, y)) {
                    sy += y;
                    n += 1;
                }
            }
        }
        assert!(n > 1000, "the sphere shows the light: {n} px");
        let y = sy / n;
        let inside: Vec<usize> = (w / 2..w).filter(|&x| bright(px(x, y))).collect();
        let (left, right) = (inside[0], *inside.last().unwrap());
        let count = |x0: usize, f: &dyn Fn([i32; 3]) -> bool| (x0.saturating_sub(8)..(x0 + 9).min(w)).filter(|&x| f(px(x, y))).count();
        (count(left, &|[r, _, b]| b > r + 60), count(right, &|[r, _, b]| r > b + 60))
    };
    let (blue, red) = fringes(&cfg);
    assert!(blue >= 3 && red >= 3, "a blue inner and an orange-red outer fringe, several pixels wide: {blue} and {red} px");
    cfg.scene.no_dispersion = true;
    assert_eq!(fringes(&cfg), (0, 0), "no fringes without dispersion");
}

#[test]
fn the_sphere_before_the_metal_plate_runs_from_yellow_on_its_left_to_red_on_its_right() {
    // cs348b-sphere-metal at a small size (report 001: "the far left corner
    // of the sphere appears as a bright yellow, slowly fading to a bright
    // red on the right side"): along the sphere's middle row, the hue
    // (sRGB green over red) falls from yellow (G near R) at its left to
    // red-orange (G under 0.6 R) at its right, bright on both sides.
    let s = SceneFile::load(&repo("scenes/cs348b-sphere-metal.toml"), true).unwrap();
    let mut cfg = refract::experiment::params::prism_config(&s.params).unwrap();
    (cfg.scene.width, cfg.scene.height, cfg.spp) = (160, 120, 4);
    let r = refract::spectral::render_config(&cfg, &refract::progress::Silent).unwrap();
    let (w, h) = (r.render.image.width, r.render.image.height);
    let img = r.render.image.to_srgb8(r.exposure, cfg.gamut);
    let px = |x: usize, y: usize| [img[(y * w + x) * 3] as f64, img[(y * w + x) * 3 + 1] as f64, img[(y * w + x) * 3 + 2] as f64];
    // The sphere spans about 45 % of the width, centred; sample its inner
    // 60 % at the middle row, averaged over 5 rows.
    let green_over_red = |fx: f64| -> (f64, f64) {
        let x = (fx * w as f64) as usize;
        let (mut g, mut r) = (0.0, 0.0);
        for y in h / 2 - 2..=h / 2 + 2 {
            let p = px(x, y);
            (r, g) = (r + p[0], g + p[1]);
        }
        (g / r, r / 5.0)
    };
    // Two pixels in from the dark ring at the sphere's left edge (0.3 of
    // the width): its first pixel inside shows the red fringe the glass's
    // dispersion puts on the plate's image there (docs/physics.md §12).
    let (left, left_r) = green_over_red(0.5 - 0.18);
    let (right, right_r) = green_over_red(0.5 + 0.15);
    assert!(left > 0.85 && left_r > 240.0, "yellow on the sphere's left: G/R {left:.2}, R {left_r:.0}");
    assert!(right < 0.6 && right_r > 150.0, "red-orange on its right: G/R {right:.2}, R {right_r:.0}");
}
