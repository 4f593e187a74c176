//! Index-of-refraction models behind one interface, each n(lambda) for a
//! wavelength in nm (in air):
//! - constant (no dispersion: report 000's Picture 6);
//! - Cauchy, n = A + B / l^2 (two terms, l in um), fitted through a glass's
//!   n_C and n_F;
//! - Sellmeier with the glass catalogue (the reference);
//! - report 001's model, linear in wavelength between Fraunhofer lines:
//!   n = n_D + (n_B - n_G) (l - l_D) / (l_B - l_G). The report prints the
//!   first sign as minus, which would make red bend more than blue; we use
//!   the other: the line through n_D with the slope of the chord from n_B
//!   to n_G (docs/physics.md §7; it misses n_B and n_G themselves, by up to
//!   0.002 for N-BK7 and 0.009 for N-SF11);
//! - report 003's Musgrave model ("Prisms and Rainbows", 1989): n linear in
//!   normalised frequency nu in [0, 1] (700 nm -> 0, 380 nm -> 1, report 003's
//!   sampling range), n = n_d + K (nu - nu_d), with K calibrated so the model
//!   gives the glass's n_F - n_C (report 003 set K by hand; 0.5 "works well").

use super::glass::{lines, Glass};
use std::fmt;

#[derive(Clone, Debug, PartialEq)]
pub enum IorModel {
    Constant(f64),
    Cauchy { a: f64, b_um2: f64 },
    Sellmeier(Glass),
    Fraunhofer { n_d: f64, slope_per_nm: f64 },
    Musgrave { n_d: f64, k: f64 },
}

crate::named_enum! {
    /// Which model to build for a glass.
    pub enum IorKind {
        /// n_d at every wavelength: no dispersion.
        Constant = "constant",
        /// Two-term Cauchy through n_C and n_F.
        Cauchy = "cauchy",
        /// Sellmeier from the catalogue (the reference).
        Sellmeier = "sellmeier",
        /// Report 001: linear in wavelength through the Fraunhofer B and G lines.
        Fraunhofer = "fraunhofer",
        /// Report 003: Musgrave's model, linear in normalised frequency.
        Musgrave = "musgrave",
    }
}

impl IorKind {
    pub const ALL: [IorKind; 5] = [IorKind::Sellmeier, IorKind::Cauchy, IorKind::Fraunhofer, IorKind::Musgrave, IorKind::Constant];
}

/// Musgrave's normalised frequency: 0 at 700 nm, 1 at 380 nm.
pub fn normalised_frequency(nm: f64) -> f64 {
    (1.0 / nm - 1.0 / 700.0) / (1.0 / 380.0 - 1.0 / 700.0)
}

impl IorModel {
    pub fn for_glass(glass: &Glass, kind: IorKind) -> IorModel {
        let n = |l: f64| glass.sellmeier(l);
        match kind {
            IorKind::Constant => IorModel::Constant(n(lines::LD)),
            IorKind::Sellmeier => IorModel::Sellmeier(glass.clone()),
            IorKind::Cauchy => {
                let (c, f) = (lines::C * 1e-3, lines::F * 1e-3);
                let b = (n(lines::F) - n(lines::C)) / (1.0 / (f * f) - 1.0 / (c * c));
                IorModel::Cauchy { a: n(lines::C) - b / (c * c), b_um2: b }
            }
            IorKind::Fraunhofer => {
                IorModel::Fraunhofer { n_d: n(lines::D), slope_per_nm: (n(lines::B_SOLAR) - n(lines::G_SOLAR)) / (lines::B_SOLAR - lines::G_SOLAR) }
            }
            IorKind::Musgrave => {
                let k = (n(lines::F) - n(lines::C)) / (normalised_frequency(lines::F) - normalised_frequency(lines::C));
                IorModel::Musgrave { n_d: n(lines::LD), k }
            }
        }
    }

    /// Index at wavelength `nm` (docs/physics.md §7).
    pub fn n(&self, nm: f64) -> f64 {
        match self {
            IorModel::Constant(n) => *n,
            IorModel::Cauchy { a, b_um2 } => a + b_um2 / (nm * 1e-3).powi(2),
            IorModel::Sellmeier(g) => g.sellmeier(nm),
            IorModel::Fraunhofer { n_d, slope_per_nm } => n_d + slope_per_nm * (nm - lines::D),
            IorModel::Musgrave { n_d, k } => n_d + k * (normalised_frequency(nm) - normalised_frequency(lines::LD)),
        }
    }

    /// Whether the index varies with wavelength (then a refraction keeps
    /// only the hero wavelength, as pbrt-v4's dielectric).
    pub fn is_dispersive(&self) -> bool {
        !matches!(self, IorModel::Constant(_))
    }
}

impl fmt::Display for IorModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IorModel::Constant(n) => write!(f, "constant n = {n:.6}"),
            IorModel::Cauchy { a, b_um2 } => write!(f, "Cauchy A = {a:.6}, B = {b_um2:.6} um^2"),
            IorModel::Sellmeier(g) => write!(f, "Sellmeier {}", g.name),
            IorModel::Fraunhofer { n_d, slope_per_nm } => write!(f, "Fraunhofer-linear n_D = {n_d:.6}, dn/dl = {slope_per_nm:.3e}/nm"),
            IorModel::Musgrave { n_d, k } => write!(f, "Musgrave n_d = {n_d:.6}, K = {k:.6}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Table;
    use crate::optics::glass::by_name;

    #[test]
    fn cauchy_two_point_fit_matches_the_published_fits() {
        let t = Table::parse(include_str!("../../data/cauchy_fits.csv"));
        let (fit, a, b) = (t.column("fit").unwrap(), t.numbers("A").unwrap(), t.numbers("B_um2").unwrap());
        let mut checked = 0;
        for (i, row) in t.rows.iter().enumerate() {
            if row[fit] != "two_point_C_F" {
                continue;
            }
            let IorModel::Cauchy { a: ma, b_um2: mb } = IorModel::for_glass(by_name(&row[0]).unwrap(), IorKind::Cauchy) else { unreachable!() };
            assert!((ma - a[i]).abs() < 2e-6 && (mb - b[i]).abs() < 2e-6, "{}: {ma} {mb}", row[0]);
            checked += 1;
        }
        assert_eq!(checked, 3);
    }

    #[test]
    fn every_model_agrees_at_its_anchor_and_disperses_normally() {
        let g = by_name("N-BK7").unwrap();
        for kind in IorKind::ALL {
            let m = IorModel::for_glass(g, kind);
            assert!((m.n(lines::LD) - g.sellmeier(lines::LD)).abs() < 2e-4, "{kind:?} at d: {}", m.n(lines::LD));
            if kind != IorKind::Constant {
                assert!(m.n(450.0) > m.n(650.0), "{kind:?}: blue must bend more than red");
                assert!(m.is_dispersive());
            }
        }
        // Musgrave and Cauchy reproduce n_F - n_C by construction.
        for kind in [IorKind::Cauchy, IorKind::Musgrave] {
            let m = IorModel::for_glass(g, kind);
            let want = g.sellmeier(lines::F) - g.sellmeier(lines::C);
            assert!((m.n(lines::F) - m.n(lines::C) - want).abs() < 1e-12, "{kind:?}");
        }
        assert!(!IorModel::for_glass(g, IorKind::Constant).is_dispersive());
    }
}
