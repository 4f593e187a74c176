//! The prism scenes' optics against closed forms and the Amici oracle
//! (tests/data/amici_deviation.csv, traced from SCHOTT Sellmeier data).

use crate::common::*;
use refract::data::Table;
use refract::optics::glass::{by_name, lines};
use refract::scenes::{build, SceneKind, SceneOptions};
use refract::world::probe::probe;

#[test]
fn amici_matches_the_deviation_oracle_at_every_wavelength() {
    let scene = build(&SceneOptions::new(SceneKind::AmiciScreen)).unwrap();
    let d = probe(&scene, lines::LD);
    assert!(d.deviation_deg.abs() < 1e-3, "the d line must leave undeviated: {}", d.deviation_deg);
    assert_eq!(d.faces, 4, "air|crown|flint|crown|air");
    let t = Table::parse(&std::fs::read_to_string(repo("tests/data/amici_deviation.csv")).unwrap());
    let (nm, dev, tr) = (t.numbers("wavelength_nm").unwrap(), t.numbers("deviation_deg").unwrap(), t.numbers("T_unpol").unwrap());
    for i in 0..nm.len() {
        let p = probe(&scene, nm[i]);
        assert!((p.deviation_deg - dev[i]).abs() < 1e-3, "{} nm: {} vs {}", nm[i], p.deviation_deg, dev[i]);
        assert!((p.transmittance - tr[i]).abs() < 1e-5, "{} nm: T {} vs {}", nm[i], p.transmittance, tr[i]);
    }
    assert_eq!(nm.len(), 81);
}

#[test]
fn single_prism_matches_the_closed_form_deviation() {
    let scene = build(&SceneOptions::new(SceneKind::SinglePrism)).unwrap();
    let g = by_name("N-BK7").unwrap();
    let a = 60f64.to_radians();
    // Incidence: minimum deviation at d (docs/physics.md §3: 49.3233 deg).
    let th1 = (g.sellmeier(lines::LD) * (a / 2.0).sin()).asin();
    assert!((th1.to_degrees() - 49.3233).abs() < 1e-4);
    for nm in [lines::C, lines::LD, lines::F, 435.8343, 700.0] {
        let n = g.sellmeier(nm);
        let th2 = (a.sin() * (n * n - th1.sin().powi(2)).sqrt() - a.cos() * th1.sin()).asin();
        let closed = th1 + th2 - a;
        let traced = -probe(&scene, nm).deviation_deg.to_radians(); // bent clockwise, toward the base
        assert!((traced - closed).abs() < 1e-5, "{nm} nm: {traced} vs {closed}");
    }
    assert!((-probe(&scene, lines::LD).deviation_deg - 38.6467).abs() < 1e-4);
    assert!((probe(&scene, lines::F).deviation_deg - probe(&scene, lines::C).deviation_deg + 0.710).abs() < 1e-3);
}

#[test]
fn an_obj_prism_with_mixed_winding_refracts_like_the_built_in_one() {
    // off/prism60.obj is the built-in prism with three faces wound inward.
    let mut o = SceneOptions::new(SceneKind::SinglePrism);
    let built_in = build(&o).unwrap();
    o.obj = Some(repo("off/prism60.obj"));
    let from_obj = build(&o).unwrap();
    for nm in [400.0, lines::F, lines::LD, lines::C, 700.0] {
        let (a, b) = (probe(&built_in, nm), probe(&from_obj, nm));
        // The OBJ's vertices pass through f32: agree to 1e-5 degrees.
        assert!((a.deviation_deg - b.deviation_deg).abs() < 1e-5, "{nm}: {} vs {}", a.deviation_deg, b.deviation_deg);
        assert!((a.transmittance - b.transmittance).abs() < 1e-6);
        assert_eq!(b.faces, 2, "in through one face, out through another");
    }
}
