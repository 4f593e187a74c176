//! Sampling wavelengths in proportion to a spectrum (inverse CDF over
//! 0.1 nm bins, 360-830 nm), so photons and eye paths spend their samples
//! where the light has power: a line spectrum needs no luck to be found.

use super::{Spectrum, LAMBDA_MAX, LAMBDA_MIN};

const BIN_NM: f64 = 0.1;

#[derive(Clone, Debug)]
pub struct WavelengthSampler {
    /// Cumulative distribution at bin edges, 0 to 1.
    cdf: Vec<f64>,
    /// Integral of the spectrum over 360-830 nm (nm times its unit).
    integral: f64,
    /// Guide table (Chen and Asau's cutpoints): entry k is the first edge
    /// whose cdf exceeds k / GUIDE, so a search starts next to its answer.
    guide: Vec<u32>,
}

/// Entries of the guide table.
const GUIDE: usize = 4096;

impl WavelengthSampler {
    pub fn new(s: &Spectrum) -> Self {
        Self::weighted(s, |_| 1.0)
    }

    /// Sampling in proportion to the spectrum times `f(nm)` (importance:
    /// e.g. how much a wavelength shows, so few samples go where the eye
    /// sees little). `integral` is then that product's.
    pub fn weighted(s: &Spectrum, f: impl Fn(f64) -> f64) -> Self {
        let n = ((LAMBDA_MAX - LAMBDA_MIN) / BIN_NM).round() as usize;
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        let mut acc = 0.0;
        for i in 0..n {
            let nm = LAMBDA_MIN + (i as f64 + 0.5) * BIN_NM;
            let v = (s.eval(nm) * f(nm)).max(0.0);
            acc += if v.is_finite() { v * BIN_NM } else { 0.0 };
            cdf.push(acc);
        }
        if acc <= 0.0 {
            // A dark spectrum: sample uniformly so nothing divides by zero.
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f64 / n as f64;
            }
        } else {
            cdf.iter_mut().for_each(|c| *c /= acc);
        }
        let guide = (0..=GUIDE).map(|k| cdf.partition_point(|&c| c <= k as f64 / GUIDE as f64) as u32).collect();
        WavelengthSampler { cdf, integral: acc, guide }
    }

    /// A wavelength for `u` in [0, 1) and its pdf (per nm).
    pub fn sample(&self, u: f64) -> (f64, f64) {
        let [s] = self.sample_many([u]);
        s
    }

    /// `sample` of several numbers: the same answers, each table read for
    /// all of them before the next, so their cache misses overlap (a
    /// search waits on the guide's entry, and the pdf on the search).
    /// Indices go through 32-bit integers: on baseline x86-64 a 64-bit
    /// unsigned conversion takes several instructions.
    #[inline]
    pub fn sample_many<const N: usize>(&self, u: [f64; N]) -> [(f64, f64); N] {
        let u = u.map(|u| u.clamp(0.0, 1.0 - 1e-12));
        // First edge with cdf > u (between the guide's cutpoints around u);
        // the bin before it holds u.
        let k = u.map(|u| ((u * GUIDE as f64) as i32 as usize).min(GUIDE - 1));
        let range = k.map(|k| (self.guide[k] as usize, (self.guide[k + 1] as usize + 1).min(self.cdf.len())));
        let bin = std::array::from_fn::<_, N, _>(|j| {
            let (lo, hi) = range[j];
            (lo + self.cdf[lo..hi].partition_point(|&c| c <= u[j])).clamp(1, self.cdf.len() - 1) - 1
        });
        std::array::from_fn(|j| {
            let i = bin[j];
            let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
            let frac = if c1 > c0 { (u[j] - c0) / (c1 - c0) } else { 0.5 };
            let nm = LAMBDA_MIN + (f64::from(i as u32) + frac) * BIN_NM;
            (nm, (c1 - c0) / BIN_NM)
        })
    }

    pub fn pdf(&self, nm: f64) -> f64 {
        let f = (nm - LAMBDA_MIN) / BIN_NM;
        if !(f >= 0.0 && f < f64::from(self.cdf.len() as u32 - 1)) {
            return 0.0;
        }
        let i = f as i32 as usize;
        (self.cdf[i + 1] - self.cdf[i]) / BIN_NM
    }

    /// The probability of a wavelength below `nm` (the cdf, linear
    /// within each 0.1 nm bin as `sample` draws).
    pub fn cdf_at(&self, nm: f64) -> f64 {
        let f = ((nm - LAMBDA_MIN) / BIN_NM).clamp(0.0, (self.cdf.len() - 1) as f64);
        let i = (f as usize).min(self.cdf.len() - 2);
        self.cdf[i] + (self.cdf[i + 1] - self.cdf[i]) * (f - i as f64)
    }

    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// Expected colour-matching values of one sampled wavelength: the XYZ
    /// of one watt of this light (what a "white" path carries).
    pub fn mean_cmf(&self) -> glam::DVec3 {
        self.mean_weight(super::colormap::ColorMap::Cie)
    }

    /// The same with a wavelength-to-colour map's weights.
    pub fn mean_weight(&self, map: super::colormap::ColorMap) -> glam::DVec3 {
        self.mean_weight_times(map, |_| 1.0)
    }

    /// The same for this light after a reflectance `r(nm)`: the XYZ one
    /// watt of it sends on from a surface of that reflectance.
    pub fn mean_weight_times(&self, map: super::colormap::ColorMap, r: impl Fn(f64) -> f64) -> glam::DVec3 {
        (0..self.cdf.len() - 1)
            .map(|i| {
                let nm = LAMBDA_MIN + (i as f64 + 0.5) * BIN_NM;
                (self.cdf[i + 1] - self.cdf[i]) * map.xyz_weight(nm) * r(nm)
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_follow_the_spectrum() {
        let s = Spectrum::Lines { lines: vec![(450.0, 1.0), (600.0, 3.0)], fwhm: 2.0 };
        let w = WavelengthSampler::new(&s);
        assert!((w.integral() - 4.0).abs() < 1e-3);
        let n = 10000;
        let near = |c: f64| (0..n).filter(|&k| (w.sample((k as f64 + 0.5) / n as f64).0 - c).abs() < 5.0).count();
        assert!((near(450.0) as f64 / n as f64 - 0.25).abs() < 0.01);
        assert!((near(600.0) as f64 / n as f64 - 0.75).abs() < 0.01);
        let (nm, pdf) = w.sample(0.6);
        assert!((pdf - w.pdf(nm)).abs() < 1e-9 && pdf > 0.0);
        // Uniform for a dark spectrum.
        let dark = WavelengthSampler::new(&Spectrum::Constant(0.0));
        assert!((dark.sample(0.5).0 - 595.0).abs() < 0.2);
    }

    /// The guide table only shortens the search: every u finds the bin a
    /// search of the whole cdf finds, for a smooth spectrum, narrow lines
    /// (most bins empty) and a dark one, at u = 0, cutpoints and near 1.
    #[test]
    fn the_guide_table_finds_the_bin_the_whole_search_finds() {
        let spectra =
            [Spectrum::Constant(1.0), Spectrum::Lines { lines: vec![(404.7, 1.0), (546.1, 5.0), (611.0, 0.01)], fwhm: 0.05 }, Spectrum::Constant(0.0)];
        for s in spectra {
            let w = WavelengthSampler::new(&s);
            let whole = |u: f64| {
                let i = w.cdf.partition_point(|&c| c <= u).clamp(1, w.cdf.len() - 1) - 1;
                LAMBDA_MIN + i as f64 * BIN_NM
            };
            let mut rng = crate::sampling::Rng::new(1, 2, 3);
            let us = (0..20_000).map(|_| rng.f64()).chain((0..=GUIDE).map(|k| k as f64 / GUIDE as f64)).chain([0.0, 1.0 - 1e-12, 0.999_999]);
            for u in us {
                let u = u.clamp(0.0, 1.0 - 1e-12);
                let (nm, _) = w.sample(u);
                let bin = whole(u);
                assert!(nm >= bin - 1e-9 && nm <= bin + BIN_NM + 1e-9, "u {u}: {nm} outside the bin at {bin}");
            }
        }
    }
}
