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
