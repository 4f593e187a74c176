//! Report 004's extended Phong model for a point light inside a translucent
//! object ("Illumination Model"; docs/physics.md §10):
//!
//! Color = Ka * Ambient + (Diffuse + Specular) / (1 + c d^2)
//! Diffuse  = Kd * |cos beta| * ObjectColor * LightColor   (translucent)
//! Specular = Ks * cos^n(alpha) * ObjectColor * LightColor, alpha measured
//!            from the light ray *refracted* out through the surface when
//!            the light and the viewer are on opposite sides (none under
//!            total internal reflection), from the mirrored ray otherwise.
//!
//! The ambient term is Ka * Ambient * ObjectColor, Phong's usual one, where
//! the report writes Ka * Ambient_Color alone (docs/physics.md §10 says why).
//!
//! Opaque surfaces (the Cornell box) use plain Phong: no light from behind.
//! There is no shadow test, as in the report.

use crate::color::Rgb;
use crate::optics::fresnel::Fresnel;
use crate::optics::{reflect, refract};
use glam::Vec3;

/// Surface properties at a hit.
#[derive(Copy, Clone, Debug)]
pub struct Material {
    pub color: Rgb,
    /// Opacity as a fraction, 0 (clear) to 1 (opaque).
    pub alpha: f32,
    /// Index of the object's inside (outside is air, 1.0).
    pub ior: f32,
    /// Light passes through (the mesh) or not (the walls).
    pub translucent: bool,
}

/// The model's constants: the report's Ka, Kd, Ks, n and c.
#[derive(Copy, Clone, Debug)]
pub struct Phong {
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub shininess: f32,
    pub atten: f32,
    pub light_color: Rgb,
    pub ambient: Rgb,
    /// The diffuse of a light behind a translucent face only where that
    /// light gets out through it (a choice, not the report's term).
    pub diffuse_tir: bool,
    /// The diffuse and specular of a light behind a translucent face
    /// weighted by the Fresnel transmittance of its way out, which falls
    /// to 0 at the critical angle (a choice, not the report's terms).
    pub fresnel_exit: bool,
}

/// A hit's colour split in two, because the report's fix composites the
/// specular part differently from the rest.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Shade {
    /// Ambient plus attenuated diffuse.
    pub lit: Rgb,
    /// Attenuated specular.
    pub specular: Rgb,
}

/// Direction in which light from a point on one side of the surface leaves
/// toward the other side: `light_dir` travels from the light to the surface
/// point, from index `n_from` into `n_to`. `None` under total internal
/// reflection, when no light gets out.
pub fn transmitted(light_dir: Vec3, normal: Vec3, n_from: f32, n_to: f32) -> Option<Vec3> {
    refract(light_dir, normal, n_from / n_to)
}

/// Shades point `p` with unit outward normal `n`, seen along unit `view`
/// (from `p` toward the viewer), lit by a point light at `light`.
pub fn shade(p: Vec3, n: Vec3, view: Vec3, light: Vec3, m: &Material, k: &Phong) -> Shade {
    let to_light = light - p;
    let d = to_light.length();
    // Facing the viewer; a light exactly on the surface lights it head-on.
    let n_view = if n.dot(view) >= 0.0 { n } else { -n };
    let l = if d > 0.0 && d.is_finite() { to_light / d } else { n_view };
    let cos_beta = n_view.dot(l);
    let mut diffuse = if m.translucent { cos_beta.abs() } else { cos_beta.max(0.0) };

    let light_behind = cos_beta < 0.0;
    let mut exit = 1.0;
    let cos_alpha = if !light_behind {
        // Same side as the viewer: the reflected ray, as in plain Phong.
        Some(reflect(-l, n_view).dot(view))
    } else if m.translucent {
        // Opposite sides: refract the light ray out toward the viewer.
        let light_inside = n.dot(to_light) < 0.0;
        let (n_from, n_to) = if light_inside { (m.ior, 1.0) } else { (1.0, m.ior) };
        let out = transmitted(-l, n, n_from, n_to);
        // Snell's law gates the diffuse too when asked: beyond the critical
        // circle r = d tan(asin(1/n)) no light crosses the face (§10).
        if k.diffuse_tir && out.is_none() {
            diffuse = 0.0;
        }
        // The share of the light that gets out, T = 1 - R (Fresnel, §2),
        // grades the circle's edge: T -> 0 as the incidence nears asin(1/n).
        if k.fresnel_exit {
            exit = out.map_or(0.0, |_| Fresnel::dielectric(cos_beta as f64, n_from as f64, n_to as f64).transmittance() as f32);
            diffuse *= exit;
        }
        out.map(|t| t.dot(view))
    } else {
        None
    };
    let spec = match cos_alpha {
        Some(c) if c > 0.0 => exit * c.powf(k.shininess),
        _ => 0.0,
    };
    let falloff = 1.0 / (1.0 + k.atten * d * d);
    let base = m.color * k.light_color;
    Shade { lit: k.ka * (k.ambient * m.color) + (k.kd * diffuse * falloff) * base, specular: (k.ks * spec * falloff) * base }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass(ior: f32) -> Material {
        Material { color: Rgb::WHITE, alpha: 0.25, ior, translucent: true }
    }

    const K: Phong =
        Phong { ka: 0.0, kd: 1.0, ks: 1.0, shininess: 16.0, atten: 0.0, light_color: Rgb::WHITE, ambient: Rgb::WHITE, diffuse_tir: false, fresnel_exit: false };

    #[test]
    fn light_at_sphere_centre_is_normal_incidence_everywhere() {
        // Points on a sphere of radius 2 round the light; normal is radial.
        for i in 0..200 {
            let (a, b) = (i as f32 * 2.399, (i as f32 / 200.0) * 2.0 - 1.0);
            let n = Vec3::new((1.0 - b * b).sqrt() * a.cos(), (1.0 - b * b).sqrt() * a.sin(), b);
            let p = 2.0 * n;
            for ior in [0.5, 1.1, 1.4, 3.0] {
                let t = transmitted((p - Vec3::ZERO).normalize(), n, ior, 1.0).expect("normal incidence never TIRs");
                assert!((t - n).length() < 1e-5, "light leaves along the normal, undeviated");
                // Viewed along the normal: full diffuse and full specular.
                let s = shade(p, n, n, Vec3::ZERO, &glass(ior), &K);
                assert!((s.lit.0 - Vec3::ONE).abs().max_element() < 1e-4);
                assert!((s.specular.0 - Vec3::ONE).abs().max_element() < 1e-3);
            }
        }
    }

    #[test]
    fn flat_face_lets_light_out_only_inside_the_tir_circle() {
        // Face z = 0 (normal +z), light inside at depth d.
        let (d, n) = (0.7f32, 1.8f32);
        let radius = d * (1.0 / n).asin().tan();
        let light = Vec3::new(0.0, 0.0, -d);
        for i in 0..400 {
            let r = i as f32 / 400.0 * 3.0 * radius;
            if (r - radius).abs() < 1e-3 * radius {
                continue;
            }
            let p = Vec3::new(r * 0.6, r * 0.8, 0.0);
            let out = transmitted((p - light).normalize(), Vec3::Z, n, 1.0);
            assert_eq!(out.is_some(), r < radius, "r = {r}, circle {radius}");
            // And the shading agrees: viewed along the exit ray there is a
            // highlight inside the circle, none outside from any view.
            let view = out.unwrap_or(Vec3::new(0.3, 0.0, 1.0).normalize());
            let s = shade(p, Vec3::Z, view, light, &glass(n), &K);
            assert_eq!(s.specular.0.x > 0.0, r < radius, "r = {r}");
        }
    }

    #[test]
    fn the_gated_diffuse_glows_only_inside_the_critical_circle() {
        // Face z = 0, light inside at depth d: with the gate, a face seen
        // head-on has diffuse exactly where r < d tan(asin(1/n)) (the
        // circle of outcoming light, with an edge); without it, everywhere.
        let (d, n) = (0.5f32, 3.0f32);
        let radius = d * (1.0 / n).asin().tan();
        let light = Vec3::new(0.0, 0.0, -d);
        let gated = Phong { ks: 0.0, diffuse_tir: true, ..K };
        let plain = Phong { ks: 0.0, ..K };
        for i in 0..300 {
            let r = i as f32 / 300.0 * 3.0 * radius;
            if (r - radius).abs() < 1e-3 * radius {
                continue;
            }
            let p = Vec3::new(r * 0.8, -r * 0.6, 0.0);
            let g = shade(p, Vec3::Z, Vec3::Z, light, &glass(n), &gated).lit.0.x;
            assert_eq!(g > 0.0, r < radius, "r = {r}, circle {radius}: {g}");
            // Inside, the edge is a step: at least cos(theta_c) of the full diffuse.
            if r < radius {
                assert!(g >= (1.0 - 1.0 / (n * n)).sqrt() - 1e-4, "r = {r}: {g}");
            }
            assert!(shade(p, Vec3::Z, Vec3::Z, light, &glass(n), &plain).lit.0.x > 0.0);
        }
    }

    #[test]
    fn the_fresnel_exit_fades_the_circle_to_nothing_at_its_edge() {
        // Face z = 0 seen head-on, light inside at depth d, index 1.4: with
        // the Fresnel weight the glow falls monotonically from the centre
        // (T = 1 - ((n-1)/(n+1))^2 = 0.972 of the ungraded there) to under
        // 0.3 of the centre's at 0.995 of the radius, and to 0 beyond, where
        // the gate alone still glows at over 0.6 of its centre's (a step).
        let (d, n) = (0.5f32, 1.4f32);
        let radius = d * (1.0 / n).asin().tan();
        let light = Vec3::new(0.0, 0.0, -d);
        let graded = Phong { ks: 0.0, diffuse_tir: true, fresnel_exit: true, ..K };
        let gated = Phong { ks: 0.0, diffuse_tir: true, ..K };
        let at = |r: f32, k: &Phong| shade(Vec3::new(r * 0.6, r * 0.8, 0.0), Vec3::Z, Vec3::Z, light, &glass(n), k).lit.0.x;
        let centre = at(0.0, &graded);
        assert!((centre / at(0.0, &gated) - (1.0 - ((n - 1.0) / (n + 1.0)).powi(2))).abs() < 1e-4, "{centre}");
        let mut last = f32::INFINITY;
        for i in 0..1000 {
            let r = i as f32 / 1000.0 * radius;
            let g = at(r, &graded);
            assert!(g <= last + 1e-6, "r = {r}: {g} after {last}");
            last = g;
        }
        let edge = 0.995 * radius;
        assert!(at(edge, &graded) < 0.3 * centre, "{} against {centre}", at(edge, &graded));
        assert!(at(edge, &gated) > 0.6 * at(0.0, &gated), "the gate alone: {}", at(edge, &gated));
        assert_eq!(at(1.01 * radius, &graded), 0.0);
        // The specular too: a view along the exit ray near the edge sees a
        // fraction T of the ungraded highlight.
        let p = Vec3::new(0.9 * radius, 0.0, 0.0);
        let out = transmitted((p - light).normalize(), Vec3::Z, n, 1.0).unwrap();
        let t = Fresnel::dielectric((p - light).normalize().z as f64, n as f64, 1.0).transmittance() as f32;
        let s = |k: &Phong| shade(p, Vec3::Z, out, light, &glass(n), &Phong { ks: 1.0, kd: 0.0, ..*k }).specular.0.x;
        assert!((s(&graded) - t * s(&gated)).abs() < 1e-5 && t < 0.9, "{} against {} x {t}", s(&graded), s(&gated));
    }

    #[test]
    fn attenuation_and_opaque_back_faces() {
        let k = Phong { atten: 0.5, ..K };
        let s = shade(Vec3::new(0.0, 0.0, 2.0), Vec3::Z, Vec3::Z, Vec3::ZERO, &glass(1.5), &k);
        assert!((s.lit.0.x - 1.0 / (1.0 + 0.5 * 4.0)).abs() < 1e-6);
        let wall = Material { translucent: false, alpha: 1.0, ..glass(1.5) };
        // Light behind an opaque wall: dark, whatever the view.
        let s = shade(Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::new(0.0, 0.0, -1.0), &wall, &K);
        assert_eq!((s.lit, s.specular), (Rgb::BLACK, Rgb::BLACK));
        // A light exactly on the surface gives finite colour.
        let s = shade(Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::ZERO, &glass(1.5), &K);
        assert!(s.lit.is_finite() && s.specular.is_finite());
    }
}
