//! A glTF glass and refract's: the index model a material's
//! `KHR_materials_ior` (n_d) and `KHR_materials_dispersion` (20 / V_d)
//! stand for, the (n_d, V_d) pair a model gives back, and the catalogue
//! glass nearest a pair.

use crate::optics::glass::{self, lines, Glass};
use crate::optics::ior::IorModel;

/// The index model of a file's glass: KHR_materials_dispersion's two-term
/// Cauchy n = A + B / l^2 through n_d with n_F - n_C = (n_d - 1) / V_d, or
/// n_d at every wavelength when the file gives no dispersion
/// (docs/physics.md §24).
pub fn khr_model(n_d: f64, abbe: Option<f64>) -> IorModel {
    match abbe {
        Some(v) if v.is_finite() && v > 0.0 && n_d > 1.0 => {
            let um = |nm: f64| nm * 1e-3;
            // B = (n_d - 1) / (V_d (l_F^-2 - l_C^-2)), A = n_d - B / l_d^2 (docs/physics.md §24).
            let b = (n_d - 1.0) / (v * (um(lines::F).powi(-2) - um(lines::C).powi(-2)));
            IorModel::Cauchy { a: n_d - b / um(lines::LD).powi(2), b_um2: b }
        }
        _ => IorModel::Constant(n_d),
    }
}

/// n_d and the Abbe number V_d = (n_d - 1) / (n_F - n_C) of a model (`None`
/// for V_d when the index does not vary).
pub fn nd_abbe(model: &IorModel) -> (f64, Option<f64>) {
    let n_d = model.n(lines::LD);
    let spread = model.n(lines::F) - model.n(lines::C);
    (n_d, (model.is_dispersive() && spread != 0.0).then(|| (n_d - 1.0) / spread))
}

/// The catalogue glass nearest (n_d, V_d), by the distance
/// sqrt((100 dn_d)^2 + dV_d^2): 0.01 in index weighs as one Abbe unit, as
/// a glass map's axes are commonly read (a glass's six-digit code holds
/// n_d to 0.001 and V_d to 0.1).
pub fn nearest(n_d: f64, abbe: f64) -> &'static Glass {
    let d = |g: &Glass| ((g.sellmeier(lines::LD) - n_d) * 100.0).hypot(g.abbe() - abbe);
    glass::catalogue().iter().min_by(|a, b| d(a).total_cmp(&d(b))).expect("the catalogue is not empty")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The KHR model gives back the file's n_d and V_d, matches the
    /// specification's closed form n_d + (n_d - 1)/V_d (523655/l^2 - 1.5168),
    /// and without dispersion is constant.
    #[test]
    fn the_khr_model_keeps_n_d_and_the_abbe_number() {
        for (n_d, v) in [(1.5168, 64.17), (1.785, 25.68), (2.42, 55.0), (1.33, 4.0)] {
            let m = khr_model(n_d, Some(v));
            let (n, a) = nd_abbe(&m);
            assert!((n - n_d).abs() < 1e-12 && (a.unwrap() - v).abs() < 1e-9, "{n_d} {v}: {n} {a:?}");
            for nm in [400.0, 486.1327, 550.0, 656.2725, 700.0] {
                let spec = n_d + (n_d - 1.0) / v * (523655.0 / (nm * nm) - 1.5168);
                assert!((m.n(nm) - spec).abs() < 2e-4 * (n_d - 1.0) / v * 20.0, "{nm} nm: {} vs {spec}", m.n(nm));
            }
            assert!(m.n(450.0) > m.n(650.0));
        }
        assert_eq!(khr_model(1.5, None), IorModel::Constant(1.5));
        assert_eq!(nd_abbe(&IorModel::Constant(1.5)), (1.5, None));
    }

    #[test]
    fn the_nearest_catalogue_glass_is_the_one_a_glass_names() {
        for g in glass::catalogue() {
            assert_eq!(nearest(g.sellmeier(lines::LD), g.abbe()).name, g.name);
        }
        assert_eq!(nearest(1.52, 64.0).name, "N-BK7");
    }
}
