//! The bulb: report 004's point light drawn as a small glowing bead, so a
//! reader sees where the light inside the mesh is. The report's light is a
//! point no ray can meet; the bulb is a drawn marker, not part of its model
//! (docs/physics.md §10). A ray travelling inside the mesh that passes
//! within a few radii of the light picks up the bead's glow, a bright core
//! and a soft halo, where the glass puts the light's image: seen through a
//! face, the bead is where the refracted ray meets it.

use glam::Vec3;

/// Brightness of the core, in the model's units (a white face lit head-on
/// is about 1): past white, so the figure's tone shows it as a white bead.
pub const CORE: f32 = 6.0;
/// Brightness of the halo at one radius from the core's edge, relative to
/// the core.
pub const HALO: f32 = 0.35;

/// Distance from `light` to the segment from `o` along unit `d` for a
/// length `t_end` (infinite for a ray that leaves the scene).
pub fn closest_approach(o: Vec3, d: Vec3, t_end: f32, light: Vec3) -> f32 {
    let t = (light - o).dot(d).clamp(0.0, t_end.max(0.0));
    (o + t * d - light).length()
}

/// The bead's glow at distance `dist` from the light, for radius `r`:
/// (glow, cover), the brightness added and the fraction of what lies beyond
/// that the core hides. The core is 1/(1 + q^8) (q = dist / r: flat inside
/// the radius, a soft edge at it), the halo HALO/(1 + q^2)^2 (a falling
/// glow a few radii wide).
pub fn glow(dist: f32, r: f32) -> (f32, f32) {
    if r <= 0.0 || !dist.is_finite() {
        return (0.0, 0.0);
    }
    let q2 = (dist / r).powi(2);
    let core = 1.0 / (1.0 + q2 * q2 * q2 * q2);
    let halo = HALO / ((1.0 + q2) * (1.0 + q2));
    (CORE * (core + halo), core)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_segment_passes_the_light_at_its_nearest_point() {
        let l = Vec3::new(0.0, 1.0, -2.0);
        // Passes 1 above the light, at t = 2.
        assert!((closest_approach(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), 10.0, l) - 1.0).abs() < 1e-6);
        // Stops short at t = 1: nearest is its end, sqrt(2) away.
        assert!((closest_approach(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), 1.0, l) - 2f32.sqrt()).abs() < 1e-6);
        // Heading away: nearest is its start.
        assert!((closest_approach(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0), f32::INFINITY, l) - 5f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn the_bead_is_bright_inside_its_radius_and_fades_outside() {
        let r = 0.05;
        let (g0, c0) = glow(0.0, r);
        assert!(g0 > 1.0 && c0 > 0.99, "past white at the centre: {g0}");
        let (g1, c1) = glow(r, r);
        assert!(c1 > 0.49 && c1 < 0.51, "half covered at the radius: {c1}");
        let (g3, c3) = glow(3.0 * r, r);
        assert!(g3 < 0.05 * g0 && c3 < 1e-3, "faint at three radii: {g3}");
        assert!(g0 > g1 && g1 > g3);
        assert_eq!(glow(1.0, 0.0), (0.0, 0.0), "no bulb: nothing drawn");
        let far = glow(10.0, r).0;
        assert!(far.is_finite() && far < 1e-3);
    }
}
