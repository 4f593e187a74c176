//! The glass catalogue: Sellmeier coefficients from `data/glasses.csv`
//! (SCHOTT optical glass catalogue 2018 via PyPI opticalglass 1.1.1; fused
//! silica from Malitson, JOSA 55, 1205 (1965)).

use crate::data::{Table, GLASSES};
use std::sync::OnceLock;

/// Line wavelengths in air, nm, as `data/fraunhofer_lines.csv` lists them:
/// the glass industry's (SCHOTT TIE-29) and two solar Fraunhofer lines.
pub mod lines {
    pub const C: f64 = 656.2725;
    pub const D: f64 = 589.294;
    pub const LD: f64 = 587.5618;
    pub const E: f64 = 546.074;
    pub const F: f64 = 486.1327;
    /// Fraunhofer B and G (solar), used by report 001's model.
    pub const B_SOLAR: f64 = 686.719;
    pub const G_SOLAR: f64 = 430.79;
}

/// What a dispersion formula asks of a number: an f64, or f64 lanes
/// (`photon::lanes`) doing each lane's IEEE operation.
pub trait Real: Copy + std::ops::Add<Output = Self> + std::ops::Sub<Output = Self> + std::ops::Mul<Output = Self> + std::ops::Div<Output = Self> {
    fn splat(x: f64) -> Self;
    /// `f64::max`: `self` where `other` is NaN, `other` where `self` is.
    fn max(self, other: Self) -> Self;
    fn sqrt(self) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn max(self, other: f64) -> f64 {
        f64::max(self, other)
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Glass {
    pub name: String,
    pub b: [f64; 3],
    /// C1..C3 in um^2.
    pub c: [f64; 3],
    /// The table's own n_C, n_d, n_F and Abbe number nu_d (for checks).
    pub table_n_c: f64,
    pub table_n_d: f64,
    pub table_n_f: f64,
    pub table_nu_d: f64,
    pub source: String,
}

impl Glass {
    /// Sellmeier: n^2 = 1 + sum B_i l^2 / (l^2 - C_i), l in um.
    pub fn sellmeier(&self, nm: f64) -> f64 {
        self.sellmeier_of(nm)
    }

    /// The same formula for any `Real`: an f64, or several wavelengths in
    /// lanes (the light pass's four photons), each lane's bits the f64's.
    #[inline(always)]
    pub fn sellmeier_of<T: Real>(&self, nm: T) -> T {
        let l = nm * T::splat(1e-3);
        let l2 = l * l;
        let term = |i: usize| T::splat(self.b[i]) * l2 / (l2 - T::splat(self.c[i]));
        // Summed as `Iterator::sum` sums f64s: from -0, in order (written
        // out: a call to `fold` would not be compiled for AVX).
        let n2 = T::splat(1.0) + (T::splat(-0.0) + term(0) + term(1) + term(2));
        n2.max(T::splat(0.0)).sqrt()
    }

    /// Abbe number nu_d = (n_d - 1) / (n_F - n_C).
    pub fn abbe(&self) -> f64 {
        (self.sellmeier(lines::LD) - 1.0) / (self.sellmeier(lines::F) - self.sellmeier(lines::C))
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("unknown glass `{name}`{hint}; valid: {valid}")]
pub struct UnknownGlass {
    pub name: String,
    /// ` (did you mean ...?)` or nothing.
    pub hint: String,
    pub valid: String,
}

pub fn catalogue() -> &'static [Glass] {
    static G: OnceLock<Vec<Glass>> = OnceLock::new();
    G.get_or_init(|| {
        let t = Table::parse(GLASSES);
        let col = |n: &str| t.column(n).unwrap_or_else(|| panic!("glasses.csv lacks {n}"));
        let num = |r: &Vec<String>, n: &str| r[col(n)].parse::<f64>().unwrap_or(f64::NAN);
        t.rows
            .iter()
            .map(|r| Glass {
                name: r[col("glass")].replace('_', " "),
                b: [num(r, "B1"), num(r, "B2"), num(r, "B3")],
                c: [num(r, "C1"), num(r, "C2"), num(r, "C3")],
                table_n_c: num(r, "n_C"),
                table_n_d: num(r, "n_d"),
                table_n_f: num(r, "n_F"),
                table_nu_d: num(r, "nu_d"),
                source: r[col("source")..].join(", "),
            })
            .collect()
    })
}

/// A glass by name, ignoring case, spaces, `-` and `_` (`n-bk7`, `NBK7`,
/// `fused silica`).
pub fn by_name(name: &str) -> Result<&'static Glass, UnknownGlass> {
    use crate::names::key;
    catalogue().iter().find(|g| key(&g.name) == key(name)).ok_or_else(|| UnknownGlass {
        name: name.to_string(),
        hint: crate::names::did_you_mean(name, names()),
        valid: names().join(", "),
    })
}

pub fn names() -> Vec<&'static str> {
    catalogue().iter().map(|g| g.name.as_str()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sellmeier_matches_the_table_for_every_glass() {
        assert_eq!(catalogue().len(), 9);
        for g in catalogue() {
            for (nm, want) in [(lines::C, g.table_n_c), (lines::LD, g.table_n_d), (lines::F, g.table_n_f)] {
                assert!((g.sellmeier(nm) - want).abs() < 1e-5, "{} at {nm}: {} vs {want}", g.name, g.sellmeier(nm));
            }
            assert!((g.abbe() - g.table_nu_d).abs() < 0.01, "{}: abbe {}", g.name, g.abbe());
        }
        assert!((by_name("n-bk7").unwrap().sellmeier(lines::LD) - 1.5168).abs() < 1e-6);
        assert!(by_name("fused silica").is_ok());
        let e = by_name("BK8").unwrap_err().to_string();
        assert!(e.contains("N-BK7") && e.contains("N-SF11"), "{e}");
    }

    #[test]
    fn line_constants_are_the_tables() {
        let t = crate::data::Table::parse(crate::data::FRAUNHOFER);
        let (name, nm, conv) = (t.column("line").unwrap(), t.column("wavelength_nm").unwrap(), t.column("convention").unwrap());
        let find =
            |line: &str, convention: &str| -> f64 { t.rows.iter().find(|r| r[name] == line && r[conv] == convention).map(|r| r[nm].parse().unwrap()).unwrap() };
        for (value, line, convention) in [
            (lines::C, "C", "glass"),
            (lines::D, "D", "glass"),
            (lines::LD, "d", "glass"),
            (lines::E, "e", "glass"),
            (lines::F, "F", "glass"),
            (lines::B_SOLAR, "B", "solar"),
            (lines::G_SOLAR, "G", "solar"),
        ] {
            assert!((value - find(line, convention)).abs() < 1e-3, "{line} ({convention}): {value}");
        }
    }
}
