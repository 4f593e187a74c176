//! Several wavelengths carried along one path, with their pdfs, in the style
//! of pbrt-v4's `SampledWavelengths` (src/pbrt/util/spectrum.h): a hero
//! wavelength plus others spread evenly through the range; where a surface
//! disperses, only the hero goes on (`terminate_secondary`).

use super::cie::{cmf, Xyz};
use super::{LAMBDA_MAX, LAMBDA_MIN};
use glam::DVec3;
use std::ops::{Add, AddAssign, Div, Mul};

pub const N_SAMPLES: usize = 4;

#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SampledWavelengths {
    /// Wavelengths in nm; `lambda[0]` is the hero.
    pub lambda: [f32; N_SAMPLES],
    /// Probability density of each (0 once terminated).
    pub pdf: [f32; N_SAMPLES],
}

impl SampledWavelengths {
    /// Hero uniform in [min, max], the others at equal steps, wrapping round.
    pub fn sample_uniform(u: f32, min: f32, max: f32) -> Self {
        let span = max - min;
        let mut lambda = [0.0; N_SAMPLES];
        lambda[0] = min + u.clamp(0.0, 1.0) * span;
        let step = span / N_SAMPLES as f32;
        for i in 1..N_SAMPLES {
            let mut l = lambda[i - 1] + step;
            if l > max {
                l -= span;
            }
            lambda[i] = l;
        }
        SampledWavelengths { lambda, pdf: [1.0 / span; N_SAMPLES] }
    }

    /// Importance sampling of the visible range (pbrt-v4's
    /// `SampleVisibleWavelengths`, a fit to the CIE Y curve): fewer samples
    /// where the eye sees little, so less colour noise.
    pub fn sample_visible(u: f32) -> Self {
        let mut lambda = [0.0; N_SAMPLES];
        let mut pdf = [0.0; N_SAMPLES];
        for i in 0..N_SAMPLES {
            let mut up = u + i as f32 / N_SAMPLES as f32;
            if up > 1.0 {
                up -= 1.0;
            }
            lambda[i] = sample_visible_wavelength(up);
            pdf[i] = visible_wavelength_pdf(lambda[i]);
        }
        SampledWavelengths { lambda, pdf }
    }

    /// One wavelength with all weight (e.g. a photon, or a laser).
    pub fn single(nm: f32, pdf: f32) -> Self {
        let mut s = SampledWavelengths { lambda: [nm; N_SAMPLES], pdf: [0.0; N_SAMPLES] };
        s.pdf[0] = pdf;
        s
    }

    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }

    /// Keep only the hero wavelength; its pdf is divided by the number of
    /// samples, as pbrt-v4 does, so the estimate stays unbiased.
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for p in &mut self.pdf[1..] {
            *p = 0.0;
        }
        self.pdf[0] /= N_SAMPLES as f32;
    }

    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1..].iter().all(|&p| p == 0.0)
    }
}

/// pdf of `sample_visible_wavelength` (0 outside 360-830 nm).
pub fn visible_wavelength_pdf(nm: f32) -> f32 {
    if !(LAMBDA_MIN as f32..=LAMBDA_MAX as f32).contains(&nm) {
        return 0.0;
    }
    0.003_939_804 / (0.0072 * (nm - 538.0)).cosh().powi(2)
}

pub fn sample_visible_wavelength(u: f32) -> f32 {
    538.0 - 138.888_89 * (0.856_910_6 - 1.827_502 * u).atanh()
}

/// Radiance (or any spectral quantity) at the sampled wavelengths.
#[derive(Copy, Clone, Debug, PartialEq, Default)]
pub struct SampledSpectrum(pub [f32; N_SAMPLES]);

impl SampledSpectrum {
    pub fn splat(v: f32) -> Self {
        SampledSpectrum([v; N_SAMPLES])
    }

    pub fn from_fn(f: impl Fn(usize) -> f32) -> Self {
        SampledSpectrum(std::array::from_fn(f))
    }

    pub fn is_zero(&self) -> bool {
        self.0.iter().all(|&v| v == 0.0)
    }

    /// Monte Carlo estimate of XYZ: mean over samples of S cmf / pdf.
    /// Samples with pdf 0 (terminated) contribute nothing.
    pub fn to_xyz(&self, w: &SampledWavelengths) -> Xyz {
        let mut sum = DVec3::ZERO;
        for i in 0..N_SAMPLES {
            if w.pdf[i] > 0.0 {
                sum += cmf(w.lambda[i] as f64) * (self.0[i] / w.pdf[i]) as f64;
            }
        }
        Xyz(sum / N_SAMPLES as f64)
    }
}

impl Add for SampledSpectrum {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::from_fn(|i| self.0[i] + o.0[i])
    }
}

impl AddAssign for SampledSpectrum {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Mul for SampledSpectrum {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self::from_fn(|i| self.0[i] * o.0[i])
    }
}

impl Mul<f32> for SampledSpectrum {
    type Output = Self;
    fn mul(self, k: f32) -> Self {
        Self::from_fn(|i| self.0[i] * k)
    }
}

impl Div<f32> for SampledSpectrum {
    type Output = Self;
    fn div(self, k: f32) -> Self {
        Self::from_fn(|i| if k != 0.0 { self.0[i] / k } else { 0.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_samples_stay_in_range_and_spread_evenly() {
        for k in 0..=20 {
            let w = SampledWavelengths::sample_uniform(k as f32 / 20.0, 380.0, 780.0);
            assert!(w.lambda.iter().all(|l| (380.0..=780.0).contains(l)), "{w:?}");
            let mut l = w.lambda;
            l.sort_by(f32::total_cmp);
            for i in 1..N_SAMPLES {
                assert!((l[i] - l[i - 1] - 100.0).abs() < 1e-3);
            }
        }
    }

    #[test]
    fn terminate_secondary_keeps_the_estimate_unbiased() {
        // A constant spectrum: the estimate with all four wavelengths and
        // with only the hero (pdf / 4) average to the same XYZ over u.
        let s = SampledSpectrum::splat(1.0);
        let (mut all, mut hero) = (DVec3::ZERO, DVec3::ZERO);
        let n = 4000;
        for k in 0..n {
            let mut w = SampledWavelengths::sample_uniform((k as f32 + 0.5) / n as f32, 360.0, 830.0);
            all += s.to_xyz(&w).0;
            w.terminate_secondary();
            assert!(w.secondary_terminated());
            hero += s.to_xyz(&w).0;
        }
        assert!((all - hero).abs().max_element() / all.max_element() < 1e-3);
        // And both estimate the integral of the CMFs.
        let y = all.y / n as f64;
        assert!((y - crate::spectrum::cie::cie_y_integral()).abs() / y < 2e-3, "{y}");
    }

    #[test]
    fn visible_sampling_pdf_integrates_to_one_and_matches_samples() {
        let total: f32 = (360..830).map(|l| visible_wavelength_pdf(l as f32 + 0.5)).sum();
        assert!((total - 1.0).abs() < 2e-3, "{total}");
        // The sample at u is where the CDF reaches u.
        let mut cdf = 0.0;
        for l in 360..830 {
            cdf += visible_wavelength_pdf(l as f32 + 0.5);
            if (l - 360) % 47 == 0 {
                let s = sample_visible_wavelength(cdf);
                assert!((s - (l as f32 + 1.0)).abs() < 1.5, "{l}: {s}");
            }
        }
    }
}
