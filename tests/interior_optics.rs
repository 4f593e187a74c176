//! The rendered image against closed-form optics. With ambient and diffuse
//! off, only light refracted out of the mesh is left: for a cube with the
//! light at its centre, each face lets light out only inside the circle of
//! radius d tan(asin(1/n)) round the foot of the perpendicular (beyond it
//! total internal reflection traps it; docs/physics.md §1).

use crate::common::*;

/// Lit pixels of the front face, and the circle's radius in pixels.
fn front_face(ior: f64, size: usize) -> (Vec<(f64, f64)>, f64) {
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    let s = format!("{size},{size}");
    let o = run(
        &[
            "interior",
            "--off",
            cube.to_str().unwrap(),
            "--out",
            "c.ppm",
            "--size",
            &s,
            "--ior",
            &ior.to_string(),
            "--ka",
            "0",
            "--kd",
            "0",
            "--ks",
            "1",
            "--shininess",
            "1",
            "--atten",
            "0",
        ],
        "",
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (w, h, px) = ppm(&dir.path().join("c.ppm"));
    // Independent geometry: the cube (half-size 1) is normalised to a
    // bounding radius of 1, so half-size 1/sqrt(3), centred at z = -2; the
    // eye is at z = 3 and the image plane z = 0 spans y in [-1, 1].
    let half = 1.0 / 3f64.sqrt();
    let d = half;
    let r_face = d * (1.0 / ior).asin().tan();
    let z_face = -2.0 + half;
    let r_plane = r_face * 3.0 / (3.0 - z_face);
    let r_px = r_plane / (2.0 / h as f64);
    let mut lit = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let i = 3 * (y * w + x);
            if px[i] > 0 || px[i + 1] > 0 || px[i + 2] > 0 {
                lit.push((x as f64 + 0.5 - w as f64 / 2.0, y as f64 + 0.5 - h as f64 / 2.0));
            }
        }
    }
    (lit, r_px)
}

#[test]
fn light_leaves_the_cube_only_inside_the_tir_circle() {
    for ior in [3.0, 1.8] {
        let (lit, r) = front_face(ior, 301);
        let outside = lit.iter().filter(|(x, y)| (x * x + y * y).sqrt() > r + 1.0).count();
        assert_eq!(outside, 0, "ior {ior}: {outside} lit pixels outside the circle of {r:.1} px");
        let area = std::f64::consts::PI * r * r;
        assert!(lit.len() as f64 > 0.8 * area, "ior {ior}: only {} of {area:.0} pixels of the circle are lit", lit.len());
    }
    // A higher index traps more: its circle is smaller.
    assert!(front_face(3.0, 101).0.len() < front_face(1.8, 101).0.len());
}

#[test]
fn a_pfm_holds_the_model_colours_that_the_8_bit_image_clamps() {
    // The same run written as .ppm and .pfm: where the PPM shows 0-254 the
    // PFM's value (bottom row first) rounds to it; the hot spot (Ks 3) is
    // past white in the PFM, 255 in the PPM.
    let dir = tempfile::tempdir().unwrap();
    let cube = repo("off/cube.off");
    let args = |out: &'static str| ["interior", "--off", cube.to_str().unwrap(), "--out", out, "--size", "41,41", "--ks", "3"].map(str::to_string);
    for out in ["c.ppm", "c.pfm"] {
        let a = args(out);
        let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>(), "", dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let (w, h, px) = ppm(&dir.path().join("c.ppm"));
    let bytes = std::fs::read(dir.path().join("c.pfm")).unwrap();
    let header = b"PF\n41 41\n-1.0\n";
    assert_eq!(&bytes[..header.len()], header);
    let floats: Vec<f32> = bytes[header.len()..].chunks(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect();
    assert_eq!(floats.len(), w * h * 3);
    let mut past_white = 0;
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let v = floats[((h - 1 - y) * w + x) * 3 + c];
                let shown = px[(y * w + x) * 3 + c];
                assert_eq!(shown, (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8, "pixel {x},{y} channel {c}: {v} shown as {shown}");
                past_white += (v > 1.0) as usize;
            }
        }
    }
    assert!(past_white > 0, "no value past white in the PFM");
}
