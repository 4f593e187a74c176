//! `refract prism --out x.exr`: the R, G, B channels hold what the PFM of
//! the same render holds, bit for bit (float); XYZ.X, XYZ.Y, XYZ.Z are the
//! film's XYZ, sRGB's matrix away from R, G, B; `--exr half` keeps them
//! within half precision; `--exr` beside another format is refused.

use crate::common::*;
use refract::image_io::openexr::read_exr;
use refract::spectrum::cie::XYZ_TO_SRGB;

/// Reads a PFM (little-endian, bottom row first) as rows from the top.
fn pfm(path: &std::path::Path) -> (usize, usize, Vec<f32>) {
    let data = std::fs::read(path).unwrap();
    let mut lines = data.splitn(4, |&b| b == b'\n');
    assert_eq!(lines.next().unwrap(), b"PF");
    let size = String::from_utf8(lines.next().unwrap().to_vec()).unwrap();
    let (w, h) = size.split_once(' ').map(|(a, b)| (a.parse::<usize>().unwrap(), b.parse::<usize>().unwrap())).unwrap();
    assert_eq!(lines.next().unwrap(), b"-1.0");
    let body: Vec<f32> = lines.next().unwrap().chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect();
    let rows: Vec<f32> = (0..h).rev().flat_map(|y| body[y * w * 3..(y + 1) * w * 3].to_vec()).collect();
    (w, h, rows)
}

#[test]
fn exr_channels_match_the_pfm_and_the_films_xyz() {
    let dir = tempfile::tempdir().unwrap();
    let render = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec!["prism", "--scene", "single-prism", "--size", "64,48", "--exact", "--exact-wavelengths", "256", "--out", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = run(&args, "", &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
        (out, stderr(&o))
    };
    let (pfm_path, _) = render("a.pfm", &[]);
    let (exr_path, said) = render("a.exr", &[]);
    assert!(!said.contains("ignored"), "{said}");
    let (w, h, rgb) = pfm(&pfm_path);
    let exr = read_exr(&exr_path).unwrap();
    assert_eq!((exr.width, exr.height, exr.half), (w, h, false));
    let names: Vec<&str> = exr.channels.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(names, ["B", "G", "R", "XYZ.X", "XYZ.Y", "XYZ.Z"]);
    let exposure = exr.attributes.iter().find(|a| a.0 == "refract.exposure").expect("the exposure attribute").1;
    assert!(exposure > 0.0);
    let lit = rgb.chunks(3).filter(|p| p[1] > 0.01).count();
    assert!(lit > 50, "the strip is in view: {lit} pixels");
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        let got = exr.channel(name).unwrap();
        for (i, v) in got.iter().enumerate() {
            assert_eq!(v.to_bits(), rgb[i * 3 + c].to_bits(), "{name} at pixel {i}");
        }
    }
    // R, G, B = M (X, Y, Z): both written from the same film.
    let (x, y, z) = (exr.channel("XYZ.X").unwrap(), exr.channel("XYZ.Y").unwrap(), exr.channel("XYZ.Z").unwrap());
    let peak = rgb.iter().fold(0f32, |m, v| m.max(v.abs())) as f64;
    for i in 0..w * h {
        let m = XYZ_TO_SRGB * glam::DVec3::new(x[i] as f64, y[i] as f64, z[i] as f64);
        for (c, v) in [m.x, m.y, m.z].into_iter().enumerate() {
            assert!((v - rgb[i * 3 + c] as f64).abs() <= 1e-6 * peak, "pixel {i} channel {c}: {v} against {}", rgb[i * 3 + c]);
        }
    }
    // Half: the same values within half's precision, and a smaller file.
    let (half_path, _) = render("h.exr", &["--exr", "half"]);
    let half = read_exr(&half_path).unwrap();
    assert!(half.half);
    for name in ["R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"] {
        for (a, b) in exr.channel(name).unwrap().iter().zip(half.channel(name).unwrap()) {
            assert!((a - b).abs() <= (a.abs() * 2f32.powi(-11)).max(2f32.powi(-25)), "{name}: {a} as half {b}");
        }
    }
    assert!(std::fs::metadata(&half_path).unwrap().len() < std::fs::metadata(&exr_path).unwrap().len());
    // `--exr` with a PNG out would do nothing: refused before any work.
    let png = dir.path().join("a.png");
    let o = run(&["prism", "--size", "8,8", "--exr", "half", "--out", png.to_str().unwrap()], "", &repo(""));
    assert_clean_failure(&o, "--exr: only an .exr output has samples to choose");
    assert!(!png.exists());
}
