//! Spectra of lights and surfaces, evaluated at any wavelength in nm:
//! constants, CIE tables (D65, FL1-FL12, FL3.1-FL3.15), black bodies
//! (Planck; report 001's lights), narrow emission lines (a CFL's mercury and
//! phosphor lines, a laser) and smooth spectra fitted to RGB colours.

use super::rgb_fit::{SigmoidPolynomial, White};
use crate::data::{Table, CFL_MODEL, D65, FL, FL3};
use std::fmt;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value everywhere (equal energy "E" is 1).
    Constant(f64),
    /// Samples from `start` nm every `step` nm, linear between, 0 outside.
    Tabulated { start: f64, step: f64, values: Arc<Vec<f64>> },
    /// Planck's law at `kelvin`, scaled so its peak is 1.
    Blackbody { kelvin: f64 },
    /// Gaussian lines (centre nm, power), each of full width at half maximum
    /// `fwhm` nm and unit area times its power.
    Lines { lines: Vec<(f64, f64)>, fwhm: f64 },
    /// A smooth spectrum from an RGB colour (Jakob & Hanika 2019), times
    /// `scale`, times D65 for an illuminant (so RGB white is D65).
    Rgb { fit: SigmoidPolynomial, scale: f64, illuminant: bool },
    /// The sum of several spectra.
    Sum(Vec<Spectrum>),
}

/// A light's spectrum with the name it was chosen by (for records).
#[derive(Clone, Debug)]
pub struct NamedSpectrum {
    pub name: String,
    pub spectrum: Spectrum,
}

impl NamedSpectrum {
    /// Parses a light's name once (see `Spectrum::light`).
    pub fn parse(name: &str) -> Result<NamedSpectrum, UnknownSpectrum> {
        Ok(NamedSpectrum { name: name.trim().to_string(), spectrum: Spectrum::light(name)? })
    }
}

/// Planck's law: spectral radiance of a black body, W / (m^2 sr m), at
/// wavelength `nm` and temperature `kelvin`.
pub fn planck(nm: f64, kelvin: f64) -> f64 {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    if kelvin <= 0.0 || nm <= 0.0 {
        return 0.0;
    }
    let l = nm * 1e-9;
    2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * kelvin)).exp_m1()))
}

/// Wien's displacement law: wavelength of peak emission, nm.
pub fn wien_peak_nm(kelvin: f64) -> f64 {
    2.897_771_955e-3 / kelvin * 1e9
}

/// The light spectra `Spectrum::light` knows.
const LIGHT_NAMES: &str = "E, D65, FL1..FL12, FL3.1..FL3.15, blackbody:K (e.g. blackbody:6500), cfl-lines, laser:NM (e.g. laser:532)";

/// A light spectrum's name that names none: unknown, or a black body or a
/// laser whose number is not one (or out of range).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnknownSpectrum {
    #[error("unknown light spectrum `{0}`; valid: {LIGHT_NAMES}")]
    Name(String),
    #[error("light spectrum `{name}`: {what} `{value}` is not a number from {range}")]
    Number { name: String, what: &'static str, value: String, range: &'static str },
}

impl Spectrum {
    pub fn eval(&self, nm: f64) -> f64 {
        match self {
            Spectrum::Constant(c) => *c,
            Spectrum::Tabulated { start, step, values } => {
                let f = (nm - start) / step;
                if !(f >= 0.0 && f <= (values.len() - 1) as f64) {
                    return 0.0;
                }
                let i = (f as usize).min(values.len().saturating_sub(2));
                let w = f - i as f64;
                if values.len() == 1 {
                    values[0]
                } else {
                    values[i] * (1.0 - w) + values[i + 1] * w
                }
            }
            Spectrum::Blackbody { kelvin } => planck(nm, *kelvin) / planck(wien_peak_nm(*kelvin), *kelvin),
            Spectrum::Lines { lines, fwhm } => {
                let sigma = fwhm / (8.0 * std::f64::consts::LN_2).sqrt();
                let norm = 1.0 / (sigma * (2.0 * std::f64::consts::PI).sqrt());
                lines.iter().map(|&(c, p)| p * norm * (-0.5 * ((nm - c) / sigma).powi(2)).exp()).sum()
            }
            Spectrum::Rgb { fit, scale, illuminant } => {
                let v = scale * fit.eval(nm);
                if *illuminant {
                    v * d65().eval(nm) / 100.0
                } else {
                    v
                }
            }
            Spectrum::Sum(parts) => parts.iter().map(|s| s.eval(nm)).sum(),
        }
    }

    /// A smooth spectrum for a linear sRGB colour (Jakob & Hanika 2019).
    /// A reflectance must lie in [0, 1]; an illuminant may be brighter and
    /// is the fitted shape times D65, so RGB (1, 1, 1) gives D65's white.
    pub fn from_rgb(rgb: glam::DVec3, illuminant: bool) -> Spectrum {
        let rgb = rgb.max(glam::DVec3::ZERO);
        // As pbrt-v4's RGBIlluminantSpectrum: fit rgb / (2 max) so the shape
        // stays well inside (0, 1), and carry the scale separately.
        let scale = if illuminant { 2.0 * rgb.max_element() } else { 1.0 };
        if scale == 0.0 {
            return Spectrum::Constant(0.0);
        }
        let d65 = d65();
        let (fit, _) = SigmoidPolynomial::fit(rgb / scale, &White::new(|l| d65.eval(l)));
        Spectrum::Rgb { fit, scale, illuminant }
    }

    /// The emission lines in this spectrum, each (centre nm, power, fwhm nm),
    /// and everything else as one spectrum (`None` when there is nothing
    /// else).
    pub fn split_lines(&self) -> (Vec<(f64, f64, f64)>, Option<Spectrum>) {
        let mut lines = Vec::new();
        let mut rest = Vec::new();
        let mut stack = vec![self];
        while let Some(s) = stack.pop() {
            match s {
                Spectrum::Sum(parts) => stack.extend(parts.iter()),
                Spectrum::Lines { lines: ls, fwhm } => lines.extend(ls.iter().map(|&(c, p)| (c, p, *fwhm))),
                other => rest.push(other.clone()),
            }
        }
        let rest = match rest.len() {
            0 => None,
            1 => rest.pop(),
            _ => Some(Spectrum::Sum(rest)),
        };
        (lines, rest)
    }

    /// A light spectrum by name: `E`, `D65`, `FL1`..`FL12`, `FL3.1`..`FL3.15`,
    /// `blackbody:K`, `cfl-lines`, `laser:NM` (case does not matter).
    pub fn light(name: &str) -> Result<Spectrum, UnknownSpectrum> {
        let unknown = || UnknownSpectrum::Name(name.to_string());
        // The number after `blackbody:` or `laser:`, within `range`.
        let number = |text: &str, what: &'static str, (lo, hi): (f64, f64), range: &'static str| match text.trim().parse::<f64>() {
            Ok(v) if (lo..=hi).contains(&v) => Ok(v),
            _ => Err(UnknownSpectrum::Number { name: name.trim().to_string(), what, value: text.to_string(), range }),
        };
        let lower = name.trim().to_ascii_lowercase();
        if let Some(k) = lower.strip_prefix("blackbody:") {
            return Ok(Spectrum::Blackbody { kelvin: number(k, "temperature", (100.0, 1e6), "100 to 1000000 K")? });
        }
        if let Some(nm) = lower.strip_prefix("laser:") {
            return Ok(laser(number(nm, "wavelength", (360.0, 830.0), "360 to 830 nm")?));
        }
        match lower.as_str() {
            "e" => Ok(Spectrum::Constant(1.0)),
            "d65" => Ok(d65()),
            "cfl-lines" => Ok(cfl_lines()),
            _ => fluorescent(&lower.to_ascii_uppercase()).ok_or_else(unknown),
        }
    }

    /// XYZ of this spectrum integrated at 5 nm over 380-780 nm, the CIE
    /// tables' own sampling (the oracles' method). Line spectra are
    /// integrated exactly instead (each line's power times the CMFs at its
    /// centre), since narrow lines fall between 5 nm samples.
    pub fn to_xyz(&self) -> super::Xyz {
        match self {
            Spectrum::Lines { lines, .. } => super::Xyz(lines.iter().map(|&(c, p)| super::cie::cmf(c) * p).sum()),
            Spectrum::Sum(parts) => super::Xyz(parts.iter().map(|p| p.to_xyz().0).sum()),
            _ => super::cie::xyz_sum_5nm(|l| self.eval(l)),
        }
    }
}

impl fmt::Display for Spectrum {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Spectrum::Constant(c) => write!(f, "constant {c}"),
            Spectrum::Tabulated { start, step, values } => write!(f, "table {start}-{} nm", start + step * (values.len() as f64 - 1.0)),
            Spectrum::Blackbody { kelvin } => write!(f, "blackbody {kelvin} K"),
            Spectrum::Lines { lines, fwhm } => write!(f, "{} lines, fwhm {fwhm} nm", lines.len()),
            Spectrum::Rgb { scale, .. } => write!(f, "rgb fit x {scale}"),
            Spectrum::Sum(p) => write!(f, "sum of {}", p.len()),
        }
    }
}

fn table_column(text: &str, column: &str) -> Option<Spectrum> {
    let t = Table::parse(text);
    let l = t.numbers("wavelength_nm")?;
    let v = t.numbers(column)?;
    Some(Spectrum::Tabulated { start: l[0], step: l[1] - l[0], values: Arc::new(v) })
}

/// CIE D65 (relative, 100 at 560 nm), 300-780 nm.
pub fn d65() -> Spectrum {
    static S: std::sync::OnceLock<Spectrum> = std::sync::OnceLock::new();
    S.get_or_init(|| table_column(D65, "D65").expect("D65 table")).clone()
}

/// CIE FL1..FL12 or FL3.1..FL3.15, by upper-case name.
pub fn fluorescent(name: &str) -> Option<Spectrum> {
    table_column(FL, name).or_else(|| table_column(FL3, name))
}

/// A laser: one line 1 nm wide.
pub fn laser(nm: f64) -> Spectrum {
    Spectrum::Lines { lines: vec![(nm, 1.0)], fwhm: 1.0 }
}

/// A tri-phosphor compact fluorescent lamp (docs/physics.md §6): its Hg I
/// and Eu3+/Tb3+ lines as narrow Gaussians over the weak phosphor
/// continuum, from `data/cfl_model.csv` (positions from the line tables,
/// strengths fitted to CIE F12's 5 nm bands by `scripts/fit_cfl.py`).
pub fn cfl_lines() -> Spectrum {
    let t = Table::parse(CFL_MODEL);
    let col = |n: &str| t.column(n).expect("cfl_model.csv columns");
    let (kind, nm, power, fwhm) = (col("kind"), col("wavelength_nm"), col("power"), col("fwhm_nm"));
    let num = |r: &Vec<String>, c: usize| r[c].parse::<f64>().unwrap_or(0.0);
    // One Lines spectrum per line width, then the continuum (10 nm knots).
    let mut widths: Vec<(f64, Vec<(f64, f64)>)> = Vec::new();
    let mut knots: Vec<(f64, f64)> = Vec::new();
    for r in &t.rows {
        if r[kind] == "continuum" {
            knots.push((num(r, nm), num(r, power)));
            continue;
        }
        let (w, line) = (num(r, fwhm), (num(r, nm), num(r, power)));
        match widths.iter_mut().find(|(x, _)| *x == w) {
            Some((_, lines)) => lines.push(line),
            None => widths.push((w, vec![line])),
        }
    }
    let mut parts: Vec<Spectrum> = widths.into_iter().map(|(fwhm, lines)| Spectrum::Lines { lines, fwhm }).collect();
    if let [(start, _), (next, _), ..] = knots[..] {
        parts.push(Spectrum::Tabulated { start, step: next - start, values: Arc::new(knots.iter().map(|k| k.1).collect()) });
    }
    Spectrum::Sum(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planck_peaks_where_wien_says() {
        for k in [2000.0, 3000.0, 5778.0, 6500.0, 10000.0] {
            let peak = wien_peak_nm(k);
            // Finest search over 1 pm around and far away from the peak.
            let best = (0..40000).map(|i| 100.0 + i as f64 * 0.1).max_by(|a, b| planck(*a, k).total_cmp(&planck(*b, k))).unwrap();
            assert!((best - peak).abs() < 0.1, "{k} K: max at {best}, Wien {peak}");
            assert!((Spectrum::Blackbody { kelvin: k }.eval(peak) - 1.0).abs() < 1e-9);
        }
        // Hand computation with CODATA constants: 5778 K at 500 nm is
        // 3.811e15 / (e^4.979 - 1) = 2.641e13 W / (m^2 sr m).
        assert!((planck(500.0, 5778.0) / 2.641e13 - 1.0).abs() < 2e-3, "{}", planck(500.0, 5778.0));
    }

    #[test]
    fn named_lights_and_errors() {
        for n in ["E", "d65", "FL1", "FL12", "FL3.1", "fl3.15", "blackbody:6500", "cfl-lines", "laser:532"] {
            let s = Spectrum::light(n).unwrap();
            assert!(s.to_xyz().0.y > 0.0, "{n}");
        }
        for bad in ["FL13", "FL3.16", "sun", "laser", "black-body:6500"] {
            let e = Spectrum::light(bad).unwrap_err().to_string();
            assert!(e.contains(bad) && e.contains("D65, FL1..FL12"), "{e}");
        }
        // A known form with a bad number says which number and its range.
        for (bad, says) in [
            ("blackbody:x", "temperature `x` is not a number from 100 to 1000000 K"),
            ("blackbody:-5", "temperature `-5` is not"),
            ("blackbody:inf", "temperature `inf` is not"),
            ("laser:1000", "wavelength `1000` is not a number from 360 to 830 nm"),
            ("laser:NaN", "wavelength `nan` is not"),
        ] {
            let e = Spectrum::light(bad).unwrap_err().to_string();
            assert!(e.contains(&format!("`{bad}`")) && e.contains(says), "{e}");
        }
    }

    #[test]
    fn rgb_spectra_reproduce_their_colour() {
        use glam::DVec3;
        // A white RGB light has D65's chromaticity; a red one is red.
        let white = Spectrum::from_rgb(DVec3::ONE, true).to_xyz().normalised().xy();
        let d65_xy = d65().to_xyz().normalised().xy();
        assert!((white.0 - d65_xy.0).abs() < 2e-3 && (white.1 - d65_xy.1).abs() < 2e-3, "{white:?} vs {d65_xy:?}");
        for c in [DVec3::new(0.8, 0.2, 0.1), DVec3::new(0.1, 0.5, 0.9)] {
            let s = Spectrum::from_rgb(c, false);
            // Reflectance under D65, normalised by D65's Y.
            let xyz = crate::spectrum::cie::xyz_sum_5nm(|l| s.eval(l) * d65().eval(l)).0 / d65().to_xyz().0.y;
            let rgb = crate::spectrum::cie::XYZ_TO_SRGB * xyz;
            assert!((rgb - c).abs().max_element() < 3e-3, "{c:?} -> {rgb:?}");
        }
        assert_eq!(Spectrum::from_rgb(DVec3::ZERO, true), Spectrum::Constant(0.0));
    }

    #[test]
    fn lines_have_unit_area_times_power() {
        let s = Spectrum::Lines { lines: vec![(500.0, 2.0), (600.0, 1.0)], fwhm: 2.0 };
        let area: f64 = (0..40000).map(|i| s.eval(450.0 + i as f64 * 0.005) * 0.005).sum();
        assert!((area - 3.0).abs() < 1e-6, "{area}");
        // Half maximum at +-fwhm/2.
        assert!((s.eval(501.0) / s.eval(500.0) - 0.5).abs() < 1e-9);
    }

    /// The CFL model reproduces what it was fitted to (CIE F12's colour and
    /// band shape) and keeps its lines where the line tables put them.
    #[test]
    fn cfl_model_matches_f12_and_the_line_tables() {
        let cfl = cfl_lines();
        let f12 = fluorescent("FL12").unwrap();
        let (a, b) = (cfl.to_xyz().normalised().xy(), f12.to_xyz().normalised().xy());
        assert!((a.0 - b.0).abs() < 0.008 && (a.1 - b.1).abs() < 0.008, "xy {a:?} vs F12 {b:?}");
        // 5 nm band averages against F12's samples: relative RMS misfit.
        let band = |l: f64| (0..50).map(|k| cfl.eval(l - 2.5 + 0.1 * (k as f64 + 0.5))).sum::<f64>() / 50.0;
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..=80 {
            let l = 380.0 + 5.0 * i as f64;
            num += (band(l) - f12.eval(l)).powi(2);
            den += f12.eval(l).powi(2);
        }
        assert!((num / den).sqrt() < 0.2, "band misfit {}", (num / den).sqrt());
        let table = Table::parse(crate::data::CFL_LINES).numbers("wavelength_nm").unwrap();
        let Spectrum::Sum(parts) = &cfl else { panic!("a sum of lines and continuum") };
        let mut n = 0;
        for p in parts {
            if let Spectrum::Lines { lines, .. } = p {
                for (c, _) in lines {
                    n += 1;
                    // Eu3+ satellites are named by range in the table (587-600, 626, 650, 705-710).
                    let near = table.iter().any(|t| (t - c).abs() <= 2.0)
                        || [(587.0, 600.0), (614.0, 632.0), (650.0, 650.0), (705.0, 711.0)].iter().any(|(lo, hi)| (lo - 1.0..=hi + 1.0).contains(c));
                    assert!(near, "line {c} nm is not in data/cfl_lines.csv");
                }
            }
        }
        assert!(n >= 12, "{n} lines");
    }
}
