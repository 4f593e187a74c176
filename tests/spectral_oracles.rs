//! The spectral core against the reference tables in tests/data (copied
//! from the project's shared data; sources in each file's `#` lines).

use crate::common::*;
use refract::data::Table;
use refract::spectrum::Spectrum;

fn oracle(name: &str) -> Table {
    Table::parse(&std::fs::read_to_string(repo(&format!("tests/data/{name}"))).unwrap())
}

#[test]
fn locus_from_the_cli_matches_the_reference_locus() {
    let o = run(&["spectrum", "locus"], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let ours = Table::parse(&text);
    assert_eq!(ours.header, ["wavelength_nm", "X", "Y", "Z", "r_lin", "g_lin", "b_lin"]);
    let reference = oracle("reference_locus_srgb.csv");
    let rl = reference.numbers("wavelength_nm").unwrap();
    let mut compared = 0;
    for (i, l) in ours.numbers("wavelength_nm").unwrap().iter().enumerate() {
        let j = rl.iter().position(|x| x == l).expect("wavelength in the oracle");
        for (a, b) in [("X", "X"), ("Y", "Y"), ("Z", "Z"), ("r_lin", "R_lin"), ("g_lin", "G_lin"), ("b_lin", "B_lin")] {
            let (x, y) = (ours.numbers(a).unwrap()[i], reference.numbers(b).unwrap()[j]);
            assert!((x - y).abs() < 1e-4, "{l} nm {a}: {x} vs {y}");
        }
        compared += 1;
    }
    assert_eq!(compared, 81);
}

#[test]
fn illuminants_match_the_5nm_oracle_rows() {
    let t = oracle("spd_srgb_oracle.csv");
    let method = t.column("method").unwrap();
    let mut compared = 0;
    for (i, row) in t.rows.iter().enumerate() {
        if row[method] != "sum_5nm_380_780" {
            continue;
        }
        let xyz = Spectrum::light(&row[0]).unwrap().to_xyz().normalised();
        let rgb = xyz.to_linear_srgb().0;
        for (name, ours) in [("X", xyz.0.x), ("Y", xyz.0.y), ("Z", xyz.0.z), ("R_lin", rgb.x), ("G_lin", rgb.y), ("B_lin", rgb.z)] {
            let want = t.numbers(name).unwrap()[i];
            assert!((ours - want).abs() < 1e-4, "{} {name}: {ours} vs {want}", row[0]);
        }
        compared += 1;
    }
    assert_eq!(compared, 5, "D65, FL11, FL12, FL3.7, FL2");
    // The CLI prints the same numbers.
    let o = run(&["spectrum", "illuminant", "FL11"], "", &repo(""));
    let t2 = Table::parse(&String::from_utf8(o.stdout).unwrap());
    assert!((t2.numbers("r_lin").unwrap()[0] - 1.4136903).abs() < 1e-4);
    let o = run(&["spectrum", "illuminant", "FL99"], "", &repo(""));
    assert_clean_failure(&o, "unknown light spectrum `FL99`; valid: E, D65");
}

#[test]
fn the_renderers_1nm_integration_differs_little_from_the_oracle_method() {
    // The renderer samples 360-830 nm finely; the oracle sums 5 nm samples
    // over 380-780 nm. For smooth D65 the two chromaticities agree closely.
    let d65 = Spectrum::light("D65").unwrap();
    let a = d65.to_xyz().normalised().xy();
    let b = refract::spectrum::cie::xyz_sum_1nm(|l| d65.eval(l)).normalised().xy();
    assert!((a.0 - b.0).abs() < 5e-4 && (a.1 - b.1).abs() < 5e-4, "{a:?} vs {b:?}");
}

#[test]
fn glass_cli_prints_catalogue_indices() {
    let o = run(&["glass", "N-SF11", "--wavelengths", "656.2725,587.5618,486.1327"], "", &repo(""));
    assert!(o.status.success(), "{}", stderr(&o));
    let t = Table::parse(&String::from_utf8(o.stdout).unwrap());
    let n = t.numbers("n").unwrap();
    for (got, want) in n.iter().zip([1.7759551, 1.7847199, 1.8065127]) {
        assert!((got - want).abs() < 1e-6, "{got} vs {want}");
    }
    let o = run(&["glass", "--list"], "", &repo(""));
    let list = String::from_utf8(o.stdout).unwrap();
    assert_eq!(list.lines().count(), 10, "{list}");
    let o = run(&["glass", "BK9"], "", &repo(""));
    assert_clean_failure(&o, "unknown glass `BK9` (did you mean `N-BK7`?); valid: N-BK7");
    // The list takes no model or wavelengths, which it would ignore.
    let o = run(&["glass", "--list", "--model", "cauchy"], "", &repo(""));
    assert_clean_failure(&o, "the argument '--list' cannot be used with '--model <MODEL>'");
}

#[test]
fn accuracy_report_writes_csvs_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("spectral");
    let o = run(&["spectrum", "accuracy", "--out", out.to_str().unwrap()], "", dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = Table::parse(&std::fs::read_to_string(out.join("ior_models_summary.csv")).unwrap());
    let max = summary.numbers("max_abs_err_380_780").unwrap();
    assert_eq!(summary.rows[0][0], "sellmeier");
    assert_eq!(max[0], 0.0);
    assert!(max.iter().all(|v| v.is_finite()));
    // The Cauchy row reproduces the published fit's error (cauchy_fits.csv:
    // N-BK7 two-point C-F, max |error| 400-700 nm = 7.31e-05).
    let cauchy = summary.rows.iter().position(|r| r[0] == "cauchy").unwrap();
    assert!((summary.numbers("max_abs_err_400_700").unwrap()[cauchy] - 7.31e-5).abs() < 1e-6);
    // The hue error chart is colour_maps.csv's rows: every nanometre of
    // 400-700 for every map, whose mean is the summary's.
    let maps = Table::parse(&std::fs::read_to_string(out.join("colour_maps.csv")).unwrap());
    let sums = Table::parse(&std::fs::read_to_string(out.join("colour_maps_summary.csv")).unwrap());
    let (nm, hue) = (maps.numbers("wavelength_nm").unwrap(), maps.numbers("hue_err_deg").unwrap());
    let means = sums.numbers("mean_hue_err_deg_400_700").unwrap();
    for (k, row) in sums.rows.iter().enumerate() {
        let of: Vec<usize> = (0..maps.rows.len()).filter(|&i| maps.rows[i][1] == row[0] && (400.0..=700.0).contains(&nm[i])).collect();
        assert_eq!(of.len(), 301, "{}: a row per nm over 400-700", row[0]);
        let mean = of.iter().map(|&i| hue[i]).sum::<f64>() / of.len() as f64;
        assert!((mean - means[k]).abs() < 2e-3, "{}: CSV mean {mean} against the summary's {}", row[0], means[k]);
    }
    for png in ["ior_models.png", "ior_models_error.png", "colour_maps.png", "colour_maps_error.png"] {
        let img = image::open(out.join(png)).unwrap().to_rgb8();
        let first = img.get_pixel(0, 0);
        assert!(img.pixels().filter(|p| *p != first).count() > 1000, "{png} looks blank");
    }
}
