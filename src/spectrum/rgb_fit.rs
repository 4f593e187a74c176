//! RGB to a smooth spectrum: Jakob & Hanika, "A Low-Dimensional Function
//! Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2),
//! 2019. The spectrum is s(l) = S(c0 x^2 + c1 x + c2) with the sigmoid
//! S(z) = 1/2 + z / (2 sqrt(1 + z^2)) and x the wavelength scaled to [0, 1],
//! so it is smooth and bounded in [0, 1] (a valid reflectance).
//!
//! The paper precomputes a table of coefficients over the RGB cube by
//! Gauss-Newton; we run the same Gauss-Newton per colour when a scene is
//! built (a handful of colours), continuing from grey toward the target as
//! the paper does for saturated colours.

use super::cie::{cmf, XYZ_TO_SRGB};
use glam::{DMat3, DVec3};

/// The white a reflectance is seen under: the illuminant times the CIE
/// functions at 5 nm over 380-780 nm, and its Y for normalisation.
pub struct White {
    weights: Vec<(f64, DVec3)>,
    norm: f64,
}

impl White {
    /// `illuminant` in relative units (D65 for sRGB).
    pub fn new(illuminant: impl Fn(f64) -> f64) -> White {
        let weights: Vec<(f64, DVec3)> = (0..=80).map(|i| 380.0 + 5.0 * i as f64).map(|l| (l, illuminant(l) * cmf(l))).collect();
        let norm = weights.iter().map(|(_, w)| w.y).sum();
        White { weights, norm }
    }
}

#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    pub c: [f64; 3],
}

fn x_of(nm: f64) -> f64 {
    (nm - 360.0) / (830.0 - 360.0)
}

fn sigmoid(z: f64) -> f64 {
    if z.is_infinite() {
        return if z > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + z / (2.0 * (1.0 + z * z).sqrt())
}

impl SigmoidPolynomial {
    pub fn eval(&self, nm: f64) -> f64 {
        let x = x_of(nm);
        sigmoid((self.c[0] * x + self.c[1]) * x + self.c[2])
    }

    /// Linear sRGB of this reflectance under `white` (D65 for sRGB),
    /// normalised so a perfect white reflector is about (1, 1, 1).
    pub fn rgb(&self, white: &White) -> DVec3 {
        let sum: DVec3 = white.weights.iter().map(|&(l, w)| w * self.eval(l)).sum();
        XYZ_TO_SRGB * (sum / white.norm)
    }

    /// Fits a reflectance to linear sRGB `target` (components clamped to
    /// [0.001, 0.999]: 0 and 1 need infinite coefficients). Returns the fit
    /// and its largest remaining RGB error.
    pub fn fit(target: DVec3, white: &White) -> (SigmoidPolynomial, f64) {
        let target = target.clamp(DVec3::splat(1e-3), DVec3::splat(0.999));
        let mut c = DVec3::ZERO; // grey 0.5
        let grey = SigmoidPolynomial { c: [0.0; 3] }.rgb(white);
        for step in 1..=8 {
            let goal = grey.lerp(target, step as f64 / 8.0);
            for _ in 0..30 {
                let p = SigmoidPolynomial { c: c.to_array() };
                let r = goal - p.rgb(white);
                if r.abs().max_element() < 1e-6 {
                    break;
                }
                // Jacobian by central differences.
                let h = 1e-4;
                let mut cols = [DVec3::ZERO; 3];
                for (k, col) in cols.iter_mut().enumerate() {
                    let mut a = c;
                    let mut b = c;
                    a[k] += h;
                    b[k] -= h;
                    *col = (SigmoidPolynomial { c: a.to_array() }.rgb(white) - SigmoidPolynomial { c: b.to_array() }.rgb(white)) / (2.0 * h);
                }
                let j = DMat3::from_cols(cols[0], cols[1], cols[2]);
                if j.determinant().abs() < 1e-14 {
                    break;
                }
                let mut delta = j.inverse() * r;
                // Damped: never jump too far in one step.
                let len = delta.length();
                if len > 20.0 {
                    delta *= 20.0 / len;
                }
                c += delta;
            }
        }
        let fit = SigmoidPolynomial { c: c.to_array() };
        let err = (fit.rgb(white) - target).abs().max_element();
        (fit, err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d65() -> White {
        let d = crate::spectrum::spectra::d65();
        White::new(|l| d.eval(l))
    }

    #[test]
    fn fits_round_trip_over_the_rgb_cube() {
        let levels = [0.02, 0.2, 0.5, 0.8, 0.98];
        let mut worst: f64 = 0.0;
        let white = d65();
        for &r in &levels {
            for &g in &levels {
                for &b in &levels {
                    let (fit, err) = SigmoidPolynomial::fit(DVec3::new(r, g, b), &white);
                    worst = worst.max(err);
                    assert!((360..=830).all(|l| (0.0..=1.0).contains(&fit.eval(l as f64))));
                }
            }
        }
        assert!(worst < 2e-3, "worst round-trip error {worst}");
    }

    #[test]
    fn grey_is_flat() {
        let (fit, _) = SigmoidPolynomial::fit(DVec3::splat(0.5), &d65());
        let v: Vec<f64> = (400..=700).step_by(50).map(|l| fit.eval(l as f64)).collect();
        assert!(v.iter().all(|x| (x - v[0]).abs() < 0.02), "{v:?}");
    }
}
