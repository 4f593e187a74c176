//! Density estimation: the filter kernels that turn photons into
//! irradiance (filtering the photon map's colour was report 000's named
//! problem). Each kernel is normalised over a disc of radius r
//! (docs/physics.md §9).

use std::f64::consts::PI;

const GAUSS_ALPHA: f64 = 0.918;
const GAUSS_BETA: f64 = 1.953;

crate::named_enum! {
    pub enum Filter {
        /// Constant over the disc: 1 / (pi r^2).
        Box = "box",
        /// Jensen's cone filter (k = 1): weight 1 - d/r, normalised by 3 / (pi r^2).
        Cone = "cone",
        /// Jensen's Gaussian shape (alpha 0.918, beta 1.953), normalised here
        /// exactly over the disc (his 1 / (pi r^2) leaves it at 0.53).
        Gaussian = "gaussian",
    }
}

impl Filter {
    /// Unnormalised weight at distance `d` for radius `r` (0 outside).
    pub fn weight(self, d: f64, r: f64) -> f64 {
        if !(d <= r) || r <= 0.0 {
            return 0.0;
        }
        match self {
            Filter::Box => 1.0,
            Filter::Cone => 1.0 - d / r,
            Filter::Gaussian => GAUSS_ALPHA * (1.0 - (1.0 - (-GAUSS_BETA * d * d / (2.0 * r * r)).exp()) / (1.0 - (-GAUSS_BETA).exp())),
        }
    }

    /// Factor making `weight` integrate to 1 over the disc.
    pub fn norm(self, r: f64) -> f64 {
        match self {
            Filter::Box => 1.0 / (PI * r * r),
            Filter::Cone => 3.0 / (PI * r * r),
            Filter::Gaussian => {
                // Mean weight over the disc, in closed form (substitute t = (d/r)^2).
                let (a, b) = (GAUSS_ALPHA, GAUSS_BETA);
                let mean = a * (1.0 - (1.0 - 2.0 / b * (1.0 - (-b / 2.0).exp())) / (1.0 - (-b).exp()));
                1.0 / (mean * PI * r * r)
            }
        }
    }
}

/// Which photons an estimate uses.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Lookup {
    /// All photons within this radius (m).
    Radius(f64),
    /// The k nearest photons (kd-tree only); the radius adapts.
    Nearest(usize),
}

impl Lookup {
    /// The fixed radius, or 0 for k-nearest.
    pub fn radius(self) -> f64 {
        match self {
            Lookup::Radius(r) => r,
            Lookup::Nearest(_) => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernels_integrate_to_one() {
        for f in [Filter::Box, Filter::Cone, Filter::Gaussian] {
            let r = 0.7;
            let n = 4000;
            let integral: f64 = (0..n).map(|i| (i as f64 + 0.5) / n as f64 * r).map(|d| f.weight(d, r) * f.norm(r) * 2.0 * PI * d * (r / n as f64)).sum();
            assert!((integral - 1.0).abs() < 1e-3, "{f:?}: {integral}");
            assert_eq!(f.weight(r * 1.01, r), 0.0);
        }
    }
}
