//! What the contrasting figures must show, measured on renders of their
//! own scene files (scenes/*.toml, at their quick size): report 004's pairs
//! differ where their captions say, and the Cornell box's walls appear in
//! the sphere at trace count 10 but not at 0.

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
