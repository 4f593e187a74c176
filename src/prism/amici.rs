//! The Amici direct-vision prism: crown | flint | crown, cemented, the crown
//! apices solved so the design wavelength leaves parallel to its entry
//! (PHYSICS.md §4; Hagen & Tkaczyk, Appl. Opt. 50, 4998 (2011)).
//!
//! Geometry in the xy plane, extruded along z; light travels along +x. The
//! flint's apex points -y, the crowns' apices +y. With h = alpha2 / 2 the
//! outward normals of the four faces a ray crosses make these angles with
//! +x: entry (h - alpha1), crown|flint +h, flint|crown -h, exit (alpha1 - h).

use glam::DVec2;

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
