//! Fresnel equations for a dielectric interface, unpolarised light, s and
//! p kept apart for paths through several faces (docs/physics.md §2).

/// Polarisation a path keeps from light to screen: through a prism train
/// (faces sharing one plane of incidence) s and p stay separate, and the
/// average of the two gives the unpolarised answer (docs/physics.md §2).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Polarisation {
    S,
    P,
}

impl Polarisation {
    /// The shares of s and p in light of polarisation `p` (`None`:
    /// natural light, half of each).
    pub fn shares(p: Option<Polarisation>) -> (f64, f64) {
        match p {
            None => (0.5, 0.5),
            Some(Polarisation::S) => (1.0, 0.0),
            Some(Polarisation::P) => (0.0, 1.0),
        }
    }
}

/// Reflectances of the two polarisations at one interface.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Fresnel {
    pub rs: f64,
    pub rp: f64,
}

impl Fresnel {
    /// From the cosine of the incidence angle (sign ignored), `n1 -> n2`.
    /// Both reflectances are 1 under total internal reflection.
    pub fn dielectric(cos_i: f64, n1: f64, n2: f64) -> Fresnel {
        let cos_i = cos_i.abs().min(1.0);
        let sin_t = n1 / n2 * (1.0 - cos_i * cos_i).max(0.0).sqrt();
        if sin_t >= 1.0 {
            return Fresnel { rs: 1.0, rp: 1.0 };
        }
        Fresnel::from_cosines(cos_i, (1.0 - sin_t * sin_t).sqrt(), n1, n2)
    }

    /// From the cosines of the angles of incidence and refraction (both
    /// in [0, 1]), `n1 -> n2`: for a tracer that has just refracted and
    /// knows both (`snell::refract_cos_f64`).
    #[inline]
    pub fn from_cosines(cos_i: f64, cos_t: f64, n1: f64, n2: f64) -> Fresnel {
        let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
        let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
        Fresnel { rs: rs * rs, rp: rp * rp }
    }

    /// Unpolarised reflectance R = (Rs + Rp) / 2.
    pub fn reflectance(&self) -> f64 {
        0.5 * (self.rs + self.rp)
    }

    /// Unpolarised transmittance T = 1 - R.
    pub fn transmittance(&self) -> f64 {
        1.0 - self.reflectance()
    }
}

/// Transmittance through interfaces sharing one plane of incidence:
/// (prod Ts + prod Tp) / 2, not the product of unpolarised values.
pub fn train_transmittance(faces: &[Fresnel]) -> f64 {
    let ts: f64 = faces.iter().map(|f| 1.0 - f.rs).product();
    let tp: f64 = faces.iter().map(|f| 1.0 - f.rp).product();
    0.5 * (ts + tp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_energy_and_brewster() {
        let (n1, n2) = (1.0, 1.5168);
        let f = Fresnel::dielectric(1.0, n1, n2);
        let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
        assert!((f.reflectance() - r0).abs() < 1e-15);
        assert!((r0 - 0.042).abs() < 5e-4, "N-BK7 in air reflects about 4.2 %");
        for i in 0..90 {
            let f = Fresnel::dielectric((i as f64).to_radians().cos(), n1, n2);
            assert!((f.reflectance() + f.transmittance() - 1.0).abs() < 1e-15);
            assert!((0.0..=1.0).contains(&f.rs) && (0.0..=1.0).contains(&f.rp));
        }
        let brewster = (n2 / n1).atan();
        assert!(Fresnel::dielectric(brewster.cos(), n1, n2).rp < 1e-20);
        // Glass to air: total internal reflection past the critical angle.
        assert_eq!(Fresnel::dielectric(0.2, n2, n1).reflectance(), 1.0);
    }

    #[test]
    fn from_refractions_cosines_as_from_the_incidence_angle_alone() {
        // The tracer's route (Snell's k, one square root) against
        // `dielectric`'s (sin theta_t, then cos theta_t), air to glass and
        // glass to air, up to just short of the critical angle.
        use crate::optics::snell::refract_cos_f64;
        use glam::DVec3;
        let normal = DVec3::Z;
        let mut worst: f64 = 0.0;
        for (n1, n2) in [(1.0, 1.5168), (1.5168, 1.0), (1.7847, 1.5168), (1.0, 3.0)] {
            for i in 0..=4000 {
                let cos_i = i as f64 / 4000.0;
                let d = DVec3::new((1.0 - cos_i * cos_i).sqrt(), 0.0, -cos_i);
                let whole = Fresnel::dielectric(cos_i, n1, n2);
                match refract_cos_f64(d, normal, n1 / n2) {
                    Some((_, ci, ct)) => {
                        let f = Fresnel::from_cosines(ci, ct, n1, n2);
                        // Where cos theta_t is under 1e-4 (grazing
                        // refraction), its own rounding is amplified;
                        // above it both routes must agree.
                        if ct > 1e-4 {
                            worst = worst.max((f.rs - whole.rs).abs()).max((f.rp - whole.rp).abs());
                        }
                    }
                    None => assert_eq!(whole, Fresnel { rs: 1.0, rp: 1.0 }, "TIR at cos_i {cos_i} for {n1} -> {n2}"),
                }
            }
        }
        assert!(worst < 1e-12, "worst difference {worst:e}");
    }

    #[test]
    fn train_differs_from_product_of_unpolarised() {
        let f = Fresnel::dielectric(0.6, 1.0, 1.8);
        let train = train_transmittance(&[f, f, f]);
        let naive = f.transmittance().powi(3);
        assert!(train > naive && (train - naive) > 1e-6);
    }
}
