//! Whole renders of the prism scenes against analytic optics.

use glam::{DVec2, DVec3};
use refract::photon::emit::{light_pass, Batch, Keep};
use refract::photon::gather::{Filter, Lookup};
use refract::photon::map::MapKind;
use refract::scenes::{build, SceneKind, SceneOptions};
use refract::spectral::options::EyeMode;
use refract::spectral::options::RenderOptions;
use refract::spectral::render::{render, SpectralRender};
use refract::spectrum::sampler::WavelengthSampler;
use refract::world::probe::probe;
use refract::world::{Albedo, Face, Surface, World};

fn hidden() -> refract::progress::Silent {
    refract::progress::Silent
}

fn scene(kind: SceneKind, light: Option<&str>, size: [usize; 2]) -> World {
    let mut o = SceneOptions::new(kind);
    o.light = light.map(|l| refract::spectrum::spectra::NamedSpectrum::parse(l).unwrap());
    [o.width, o.height] = size;
    build(&o).unwrap()
}

fn opts(photons: u64, spp: u32) -> RenderOptions {
    RenderOptions {
        photons,
        map: MapKind::Kdtree,
        filter: Filter::Cone,
        lookup: Lookup::Radius(1e-3),
        spp,
        seed: 1,
        eye: EyeMode::Hero,
        split: 8,
        colours: refract::spectrum::colormap::ColorMap::Cie,
        film_kernel: None,
    }
}

/// Luminance-weighted centroid of an image, in pixels.
fn centroid(r: &SpectralRender) -> DVec2 {
    let (mut sum, mut w) = (DVec2::ZERO, 0.0);
    for y in 0..r.image.height {
        for x in 0..r.image.width {
            let v = r.image.xyz[y * r.image.width + x].y;
            sum += v * DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            w += v;
        }
    }
    assert!(w > 0.0, "black image");
    sum / w
}

#[test]
fn energy_on_the_screen_is_the_emitted_power_times_fresnel_transmittance() {
    for kind in [SceneKind::AmiciScreen, SceneKind::SinglePrism] {
        let mut s = scene(kind, None, [64, 32]);
        // A screen large enough to catch every wavelength of D65.
        let f = s.maps[0];
        let (c, eu, ev) = s.faces[f].frame.unwrap();
        let mid = c + eu / 2.0 + ev / 2.0;
        s.faces[f] = Face::rect("big screen", mid - eu * 5.0 - ev * 5.0, eu * 10.0, ev * 10.0, Surface::Diffuse { albedo: Albedo::new([0.8; 3]), map: 0 });
        let pass = light_pass(&s, Batch::new(400_000, 3, refract::spectrum::colormap::ColorMap::Cie), Keep, &refract::progress::Silent);
        let measured = pass.stats.stored_power / pass.stats.emitted_power;
        // Analytic: the light's spectrum-weighted (prod Ts + prod Tp) / 2.
        let sampler = WavelengthSampler::new(&s.lights[0].spectrum);
        let n = 2000;
        let analytic: f64 = (0..n).map(|i| probe(&s, sampler.sample((i as f64 + 0.5) / n as f64).0).transmittance).sum::<f64>() / n as f64;
        assert!((measured / analytic - 1.0).abs() < 0.02, "{kind:?}: {measured} vs {analytic}");
        assert!(pass.stats.dispersed > 0);
    }
}

#[test]
fn each_narrow_band_lands_where_the_analytic_ray_lands() {
    for kind in [SceneKind::AmiciScreen, SceneKind::SinglePrism] {
        for nm in [450.0, 500.0, 550.0, 600.0, 650.0] {
            let light = format!("laser:{nm}");
            let s = scene(kind, Some(&light), [320, 120]);
            let r = render(&s, &opts(60_000, 1), &hidden());
            // The beam's axis through the prism, then straight to the screen.
            let p = probe(&s, nm);
            let f = &s.faces[s.maps[0]];
            let t = (f.verts[0] - p.exit_point).dot(f.normal) / p.exit_dir.dot(f.normal);
            let want = s.camera.project(p.exit_point + t * p.exit_dir).unwrap();
            let got = centroid(&r);
            assert!((got - want).length() < 1.0, "{kind:?} {nm} nm: lands at {got:?}, analytic {want:?}");
        }
    }
}

#[test]
fn no_dispersion_gives_a_patch_with_no_chroma() {
    let mut o = SceneOptions::new(SceneKind::AmiciScreen);
    o.no_dispersion = true;
    [o.width, o.height] = [320, 120];
    let s = build(&o).unwrap();
    let r = render(&s, &opts(100_000, 2), &hidden());
    let white = refract::spectrum::Xyz(WavelengthSampler::new(&s.lights[0].spectrum).mean_cmf()).xy();
    let max_y = r.image.xyz.iter().map(|v| v.y).fold(0.0, f64::max);
    let mut lit = 0;
    for v in &r.image.xyz {
        if v.y > 0.01 * max_y {
            let xy = refract::spectrum::Xyz(*v).xy();
            // Photons store their flux to 2^-15 of its largest component
            // (16-byte photons): equal to that precision.
            assert!((xy.0 - white.0).abs() < 5e-5 && (xy.1 - white.1).abs() < 5e-5, "{xy:?} vs {white:?}");
            lit += 1;
        }
    }
    assert!(lit > 20, "the patch must be visible ({lit} pixels)");
    // With dispersion, the same scene is coloured.
    let s = scene(SceneKind::AmiciScreen, None, [160, 60]);
    let r = render(&s, &opts(100_000, 2), &hidden());
    let spread = r.image.xyz.iter().filter(|v| v.y > 0.01).map(|v| refract::spectrum::Xyz(*v).xy().0).fold((1.0f64, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    assert!(spread.1 - spread.0 > 0.3, "dispersion must spread chromaticity: {spread:?}");
}

/// The figure's own scene (scenes/css552-p1.toml) at `size`, lit by `light`.
fn figure_p1(light: Option<&str>, size: [usize; 2]) -> (refract::spectral::SpectralConfig, World) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = refract::experiment::scene_file::SceneFile::load(&root.join("scenes/css552-p1.toml"), true).unwrap();
    let mut cfg = refract::experiment::params::prism_config(&file.params).unwrap();
    cfg.scene.light = light.map(|l| refract::spectrum::spectra::NamedSpectrum::parse(l).unwrap());
    [cfg.scene.width, cfg.scene.height] = size;
    let s = build(&cfg.scene).unwrap();
    (cfg, s)
}

#[test]
fn cfl_lines_give_separate_tube_images_where_the_probe_says() {
    let size = [640, 240];
    let (_, s) = figure_p1(None, size);
    let lamp_x = s.faces.iter().find(|f| f.name.starts_with("cfl tube")).unwrap().verts[0].x;
    // Each line alone, as a 1 nm laser-like emitter: its image of the tube
    // is centred where the probe's optics (`refract prism trace`), traced
    // back from the camera, meet the lamp's axis.
    let lines = [435.834, 546.075, 587.0, 611.0];
    let mut x = Vec::new();
    for nm in lines {
        let (_, s) = figure_p1(Some(&format!("laser:{nm}")), size);
        let r = render(&s, &opts(1, 4), &hidden());
        let got = centroid(&r).x;
        let a = refract::scenes::amici::lamp_image_angle(&s, s.camera.pos, lamp_x, nm).expect("the line is seen through the prism");
        let dir = DVec3::new(a.cos(), a.sin(), 0.0);
        let want = s.camera.project(s.camera.pos + dir).unwrap().x;
        assert!((got - want).abs() < 1.0, "{nm} nm: image centred at column {got:.2}, the probe says {want:.2}");
        x.push(got);
    }
    assert!(x.windows(2).all(|w| w[0] > w[1]), "violet to red from right to left: {x:?}");
    // The lamp's half width in pixels.
    let half = {
        let a = refract::scenes::amici::LAMP_WIDTH / 2.0 / refract::scenes::amici::LAMP_DISTANCE;
        let p = |t: f64| s.camera.project(s.camera.pos + DVec3::new(1.0, t, 0.0)).unwrap().x;
        (p(a) - p(-a)).abs() / 2.0
    };
    // The whole lamp, as the figure renders it (quick size): a bright image
    // of the right hue at each line's place, and between neighbouring
    // images that stand farther apart than the tube is wide, only the
    // faint phosphor continuum: under 5 % of the dimmer image's peak.
    // (The weak Tb 488 nm image is not one of them: it stands on that
    // continuum, 11-15 % of its peak, as the F12 lamp's spectrum says.)
    let (cfg, s) = figure_p1(None, [320, 120]);
    // Four samples a pixel: enough for the gaps measured here.
    let mut o = opts(1, 4);
    o.eye = cfg.eye;
    o.split = cfg.split;
    let r = render(&s, &o, &hidden());
    // Brightness per column: the largest linear sRGB channel, summed over
    // the middle rows of the lamp's legs.
    let column = |c: usize| -> DVec3 { (45..75).map(|y| r.image.linear_srgb(y * r.image.width + c).max(DVec3::ZERO)).sum() };
    let profile: Vec<f64> = (0..r.image.width).map(|c| column(c).max_element()).collect();
    let at = |full_px: f64| (full_px / 2.0) as usize;
    let (blue, green, red) = (column(at(x[0])), column(at(x[1])), column(at(x[3])));
    assert!(blue.z > blue.x && blue.z > blue.y, "435.8 nm image is blue: {blue:?}");
    assert!(green.y > green.x && green.y > green.z, "546.1 nm image is green: {green:?}");
    assert!(red.x > red.y && red.x > red.z, "611 nm image is red: {red:?}");
    // The pairs with only continuum between them: not 587 | 611 nm, between
    // whose images stand the europium 593 and 599 nm lines' own.
    for w in x.windows(2).take(2) {
        // In full-size pixels: the images' near edges.
        let (right, left) = (w[0] - half, w[1] + half);
        assert!(right - left >= 2.0, "the images at columns {:.1} and {:.1} stand apart", w[1], w[0]);
        let peak = |c: f64| (at(c - half)..=at(c + half)).map(|k| profile[k]).fold(0.0, f64::max);
        let dimmer = peak(w[0]).min(peak(w[1]));
        let gap = (at(left) + 1..at(right)).map(|k| profile[k]).fold(f64::INFINITY, f64::min);
        // Measured with the figure's eye rays (eye = "lines") and its 30 mm
        // twin-tube lamp at 30 m: 0.0 % between the 435.8 and 546.1 nm
        // images (the dim Tb 488 image between them), 2.4 % between 546.1
        // and 587 (5.6 % with the lamp at 14 m): there the Hg 577/579 nm
        // doublet's own image stands beside the 587 nm one, on the
        // continuum, so that pair is allowed 10 %.
        let limit = if w[0] == x[1] { 0.10 } else { 0.05 };
        assert!(gap < limit * dimmer, "between the images at columns {:.1} and {:.1}: {gap:.3} against a peak of {dimmer:.3}", w[1], w[0]);
    }
}

/// Picture 1 as printed at the quick set's size and samples (the
/// figure's own exposure and display): the copies fill two thirds of the
/// frame's height, on black between them; the 546 nm copy is green at full
/// scale and the brightest, 611 nm red, 587 nm orange and 435.8 nm blue;
/// the 611 nm copy shows its legs (a darker gap between them), not one
/// clipped block; a black column stands between the red copies and the
/// orange ones; the smeared edges are smooth, not speckled; the quick
/// frame is tall enough to read; and the wavelength labels stand where
/// their wavelengths fall.
#[test]
fn picture_1_prints_sharp_copies_on_black() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let quick = refract::experiment::scene_file::SceneFile::load(&root.join("scenes/css552-p1.toml"), true).unwrap();
    let quick = refract::experiment::params::prism_config(&quick.params).unwrap();
    let (cfg, s) = figure_p1(None, [quick.scene.width, quick.scene.height]);
    let exposure = cfg.exposure.expect("the figure fixes its exposure");
    let mut o = opts(1, cfg.spp);
    o.eye = cfg.eye;
    o.split = cfg.split;
    let r = render(&s, &o, &hidden());
    let (w, h) = (r.image.width, r.image.height);
    let px = r.image.to_srgb8(exposure, cfg.gamut);
    let at = |x: usize, y: usize| -> DVec3 { DVec3::new(px[(y * w + x) * 3] as f64, px[(y * w + x) * 3 + 1] as f64, px[(y * w + x) * 3 + 2] as f64) / 255.0 };
    // Where each line's copy stands (its centre column), by the probe.
    let lamp_x = s.faces.iter().find(|f| f.name.starts_with("cfl tube")).unwrap().verts[0].x;
    let column = |nm: f64| -> usize {
        let a = refract::scenes::amici::lamp_image_angle(&s, s.camera.pos, lamp_x, nm).expect("the line is seen");
        s.camera.project(s.camera.pos + DVec3::new(a.cos(), a.sin(), 0.0)).unwrap().x as usize
    };
    // The lamp's half width, in pixels.
    let p = |t: f64| s.camera.project(s.camera.pos + DVec3::new(1.0, t, 0.0)).unwrap().x;
    let half = (p(refract::scenes::amici::LAMP_WIDTH / 2.0 / refract::scenes::amici::LAMP_DISTANCE) - p(0.0)).abs();
    // Rows with any printed light: the lamp's height, two thirds of the frame.
    let lit_rows: Vec<usize> = (0..h).filter(|&y| (0..w).any(|x| at(x, y).max_element() > 0.0)).collect();
    let span = lit_rows.last().unwrap() - lit_rows.first().unwrap() + 1;
    assert!(span as f64 > 0.6 * h as f64, "the copies span {span} of {h} rows");
    let legs = lit_rows[0] + span / 4..lit_rows[0] + 3 * span / 4;
    // Black between the green copies (Tb 541 nm, 3 fwhm short of it, is the
    // nearest to the blue) and the 435.8 nm copy: the weak Tb 488 nm copy and
    // the phosphor continuum print black, every row.
    let (green, blue) = (column(546.075), column(435.834));
    let lit: Vec<(usize, usize, DVec3)> = (column(536.0) + half as usize + 2..blue - half as usize - 2)
        .flat_map(|x| (0..h).map(move |y| (x, y)))
        .map(|(x, y)| (x, y, at(x, y)))
        .filter(|p| p.2.max_element() > 0.0)
        .collect();
    assert!(lit.is_empty(), "light between the 546 and 436 nm copies (columns {green} and {blue}, half width {half:.1}): {lit:?}");
    // Colours, at each copy's brightest pixel in its legs' rows.
    let brightest = |c: usize| {
        (c - half as usize..=c + half as usize).flat_map(|x| legs.clone().map(move |y| (x, y))).map(|(x, y)| at(x, y)).fold(DVec3::ZERO, |a, b| {
            if b.max_element() + b.min_element() > a.max_element() + a.min_element() {
                b
            } else {
                a
            }
        })
    };
    let (g, rd, b) = (brightest(green), brightest(column(611.0)), brightest(blue));
    assert!(g.y > 0.95 && g.x < g.y && g.z < 0.3, "the 546 nm copy's core is green at full scale: {g:?}");
    assert!(rd.x > 0.9 && rd.y < 0.3 && rd.z < 0.3, "the 611 nm copy is red: {rd:?}");
    assert!(b.z > 0.4 && b.z > 2.0 * b.y, "the 435.8 nm copy is blue: {b:?}");
    // The 546 nm copy is the brightest: its peak luminance (Rec. 709
    // weights on the printed sRGB, decoded) over the red copy's.
    let luminance = |c: DVec3| {
        let lin = c.to_array().map(|v| if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) });
        0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]
    };
    assert!(luminance(g) > 2.0 * luminance(rd), "the 546 nm copy ({g:?}) is not the brightest beside the 611 nm one ({rd:?})");
    // The orange 587 nm copy prints (not black under the print's black
    // point): orange, red over green over blue.
    let o = brightest(column(587.0));
    assert!(o.x > 0.3 && o.x > o.y && o.y > o.z, "the 587 nm copy is orange: {o:?}");
    // Each column's red, averaged over the legs' rows.
    let red_at = |x: usize| legs.clone().map(|y| at(x, y).x).sum::<f64>() / legs.len() as f64;
    // The 611 nm copy's legs: across its width, a column well darker than
    // the brightest (its legs' gap).
    let red = column(611.0);
    let row: Vec<f64> = (red - half as usize..=red + half as usize).map(red_at).collect();
    let (lo, hi) = (row.iter().cloned().fold(1.0, f64::min), row.iter().cloned().fold(0.0, f64::max));
    assert!(lo < LEG_GAP * hi, "the 611 nm copy is one block: {row:?}");
    // A black column between the 611 nm copy's near edge and the weak
    // 599 nm copy's (the orange group's red end): the red and orange
    // copies stand apart in every leg row.
    let gap: Vec<f64> = (red + half as usize + 1..column(599.0) - half as usize).map(red_at).collect();
    assert!(gap.contains(&0.0), "no black column between the 611 and 599 nm copies: {gap:?}");
    // Speckle: printed pixels more than a quarter of white off their 3 x 3
    // neighbourhood's median, as a share of the lit pixels.
    let v = |x: usize, y: usize| at(x, y).max_element();
    let (mut off, mut lit) = (0, 0);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let mut n: Vec<f64> = (0..9).map(|k| v(x + k % 3 - 1, y + k / 3 - 1)).collect();
            n.sort_by(f64::total_cmp);
            if v(x, y) > 0.0 || n[4] > 0.0 {
                lit += 1;
                off += usize::from((v(x, y) - n[4]).abs() > 0.25);
            }
        }
    }
    let share = off as f64 / lit as f64;
    assert!(share < SPECKLE, "{off} of {lit} lit pixels ({:.1} %) stand out of their neighbourhood", 100.0 * share);
    // The quick frame is tall enough to read each copy as a lamp: at least
    // 100 rows, the full frame's aspect.
    let full = refract::experiment::scene_file::SceneFile::load(&root.join("scenes/css552-p1.toml"), false).unwrap();
    let full = refract::experiment::params::prism_config(&full.params).unwrap();
    let aspect = |c: &refract::spectral::SpectralConfig| c.scene.width as f64 / c.scene.height as f64;
    assert!(h >= 100, "the quick frame is {w} x {h}");
    assert!((aspect(&quick) / aspect(&full) - 1.0).abs() < 0.01, "the quick frame's aspect {} is not the full frame's {}", aspect(&quick), aspect(&full));
    // Every wavelength label (the copies' and the scale's, "500", "450 nm")
    // stands within 1 % of the width of where the probe puts that
    // wavelength.
    let labels = refract::experiment::scene_file::SceneFile::load(&root.join("scenes/css552-p1.toml"), true).unwrap().labels;
    let mut scale = 0;
    for l in &labels {
        let nm: f64 = l.text.trim_end_matches(" nm").parse().unwrap_or_else(|_| panic!("label {:?} is a wavelength", l.text));
        let a = refract::scenes::amici::lamp_image_angle(&s, s.camera.pos, lamp_x, nm).expect("the label's wavelength is seen");
        let x = s.camera.project(s.camera.pos + DVec3::new(a.cos(), a.sin(), 0.0)).unwrap().x / w as f64;
        assert!((x - l.at[0]).abs() < 0.01, "label {:?} at {:.3} of the width, {nm} nm at {x:.3}", l.text, l.at[0]);
        scale += usize::from(nm == 500.0 || nm == 450.0);
    }
    assert_eq!(scale, 2, "the scale marks 500 and 450 nm between the green and blue copies");
}

/// Picture 1's legs: the darkest column across the 611 nm copy, as a
/// share of its brightest (measured 0.78 at the quick size at exposure 0.1,
/// where the red copy printed as one block; 0.55 at 0.05 with the soft
/// print, measured at 989f9f4; the Eu 615 nm
/// copy's leg and each line's width fill part of the gap).
const LEG_GAP: f64 = 0.7;
/// Picture 1's speckle allowed: measured 1.0 % of the lit pixels at the
/// quick size (960 x 112, 18 samples, exposure 0.05, soft print); 3.0 % at
/// 640 x 75, 40 samples, exposure 0.1 and the hard print; 16 % at 1280 x 150 with 10 samples,
/// 11 % in the quick set before (1280 x 240, 4 samples).
const SPECKLE: f64 = 0.06;

#[test]
fn same_seed_same_image_whatever_the_thread_count() {
    let s = scene(SceneKind::AmiciScreen, None, [96, 36]);
    let mut images = Vec::new();
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        for map in [MapKind::Kdtree, MapKind::Buffer] {
            let o = RenderOptions { map, ..opts(50_000, 2) };
            images.push((map, pool.install(|| render(&s, &o, &hidden())).image));
        }
    }
    for i in 2..images.len() {
        assert!(images[i].1 == images[i % 2].1, "{:?} differs with another thread count", images[i].0);
    }
}

mod cli {
    use crate::common::*;
    use refract::data::Table;

    #[test]
    fn trace_prints_the_physics_md_exit_angles() {
        let o = run(&["prism", "trace", "--wavelengths", "404.656,435.834,546.075,587.5618,611"], "", &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
        let t = Table::parse(&String::from_utf8(o.stdout).unwrap());
        assert_eq!(t.header, ["wavelength_nm", "exit_x", "exit_y", "exit_z", "deviation_deg", "transmittance"]);
        let dev = t.numbers("deviation_deg").unwrap();
        for (got, want) in dev.iter().zip([6.277, 4.280, 0.707, 0.0, -0.321]) {
            assert!((got - want).abs() < 1e-3, "{got} vs {want}");
        }
        let o = run(&["prism", "trace", "--scene", "single-prism", "--incidence", "49.4", "--wavelengths", "587.5618"], "", &repo(""));
        let t = Table::parse(&String::from_utf8(o.stdout).unwrap());
        // Just off minimum deviation: slightly more than 38.6467 degrees.
        let d = -t.numbers("deviation_deg").unwrap()[0];
        assert!(d > 38.6467 && d < 38.66, "{d}");
        // Past the critical angle (blue in the Cornell box's N-SF11 prism
        // met at 52 degrees): no number, no NaN, zero transmittance.
        let o = run(&["prism", "trace", "--scene", "cornell-laser", "--glass", "N-SF11", "--incidence", "52", "--wavelengths", "450"], "", &repo(""));
        assert!(o.status.success(), "{}", stderr(&o));
        let text = String::from_utf8(o.stdout).unwrap();
        assert_eq!(text.lines().nth(1), Some("450,,,,,0"), "{text}");
    }

    #[test]
    fn the_light_is_named_for_what_it_is_and_the_old_flag_still_works() {
        let dir = tempfile::tempdir().unwrap();
        let cube = repo("off/cube.off").display().to_string();
        let runs: [(&[&str], &str); 4] = [
            (&["prism", "--photons", "2000", "--size", "32,12", "--light-spectrum", "e", "--out", "a.png"], "a.png"),
            (&["prism", "--photons", "2000", "--size", "32,12", "--light", "e", "--out", "b.png"], "b.png"),
            (&["interior", "--off", &cube, "--size", "32,32", "--light-pos", "0,0,0.3", "--out", "c.png"], "c.png"),
            (&["interior", "--off", &cube, "--size", "32,32", "--light", "0,0,0.3", "--out", "d.png"], "d.png"),
        ];
        for (args, _) in runs {
            let o = run(args, "", dir.path());
            assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        }
        let read = |f: &str| std::fs::read(dir.path().join(f)).unwrap();
        assert_eq!(read("a.png"), read("b.png"), "--light is --light-spectrum in the prism mode");
        assert_eq!(read("c.png"), read("d.png"), "--light is --light-pos in the interior mode");
        // The interior default (the mesh's centre) differs from 0,0,0.3: the flag does something.
        let o = run(&["interior", "--off", &cube, "--size", "32,32", "--out", "e.png"], "", dir.path());
        assert!(o.status.success());
        assert_ne!(read("c.png"), read("e.png"));
    }

    #[test]
    fn quick_prism_runs_are_smaller_unless_told() {
        let dir = tempfile::tempdir().unwrap();
        let o = run(&["prism", "--quick", "--out", "q.png"], "", dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        // The default 640x240 and 1 000 000 photons, quick: half the size, a tenth of the photons.
        assert!(stderr(&o).contains("(320x120, 100000 photons"), "{}", stderr(&o));
        let o = run(&["prism", "--quick", "--size", "64,24", "--photons", "3000", "--out", "q.png"], "", dir.path());
        assert!(stderr(&o).contains("(64x24, 3000 photons"), "{}", stderr(&o));
    }

    #[test]
    fn a_black_render_says_why_and_what_to_do() {
        let dir = tempfile::tempdir().unwrap();
        let o = run(&["prism", "--map", "kdtree", "--photons", "5000", "--size", "160,60", "--radius", "0.000001", "--out", "r.png"], "", dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains("warning: --radius 1.000e-6 m is below the photons' spacing"), "{err}");
        assert!(err.contains("warning: the image is black: photons landed, but none within the gather radius"), "{err}");
        // With the default radius: no warning.
        let o = run(&["prism", "--photons", "5000", "--size", "160,60", "--out", "r.png"], "", dir.path());
        assert!(o.status.success() && !stderr(&o).contains("warning"), "{}", stderr(&o));
    }

    #[test]
    fn renders_write_images_and_timing_rows() {
        let dir = tempfile::tempdir().unwrap();
        for (args, out) in [
            (vec!["--map", "buffer", "--filter", "gaussian"], "a.png"),
            (vec!["--scene", "spheres-final", "--spp", "2"], "b.ppm"),
            (vec!["--no-prism", "--map", "kdtree", "--k", "50"], "c.pfm"),
        ] {
            let mut full = vec!["prism", "--photons", "20000", "--size", "64,24", "--out", out, "--timing-csv", "t.csv"];
            full.extend(args);
            let o = run(&full, "", dir.path());
            assert!(o.status.success(), "{}", stderr(&o));
            assert!(std::fs::metadata(dir.path().join(out)).unwrap().len() > 50);
        }
        let t = Table::parse(&std::fs::read_to_string(dir.path().join("t.csv")).unwrap());
        assert_eq!(t.rows.len(), 3);
        let bytes = t.numbers("bytes_per_photon").unwrap();
        assert!(bytes[2] > 0.0 && bytes[2] <= 24.0, "kd-tree bytes per photon {}", bytes[2]);
        assert!(t.numbers("photons_per_s").unwrap().iter().all(|v| v.is_finite()));
    }

    #[test]
    fn bad_parameters_fail_cleanly() {
        let dir = tempfile::tempdir().unwrap();
        for (args, needle) in [
            (vec!["--glass", "BK9"], "invalid value 'BK9' for '--glass <NAME>'"),
            (vec!["--flint-apex", "170"], "--flint-apex"),
            (vec!["--photons", "0"], "for '--photons <N>': 0 is not between 1 and 2000000000"),
            (vec!["--map", "buffer", "--k", "10"], "--k, --map: k needs map kdtree"),
            (vec!["--map", "kdtree", "--k", "2"], "--k: k = 2 is below 4: the k-nearest estimate"),
            (vec!["--map", "kdtree", "--k", "3"], "--k: k = 3 is below 4"),
            (vec!["--light", "sunshine"], "unknown light spectrum `sunshine`"),
            (vec!["--radius", "-1"], "--radius"),
            (vec!["--out", "nowhere/x.png"], "--out: folder nowhere does not exist"),
            (vec!["--incidence", "20", "--scene", "single-prism"], "--incidence: at 20.000 degrees the d line is totally reflected"),
            // Flags the run would ignore are refused, naming the flag.
            (vec!["--scene", "single-prism", "--flint-apex", "80"], "--flint-apex: the single-prism scene has no Amici prism"),
            (vec!["--scene", "sphere-metal", "--incidence", "40"], "--incidence: the sphere-metal scene's glass is a sphere"),
            (vec!["--scene", "cornell-pointlight", "--haze", "0.3"], "--haze: the cornell-pointlight scene has no collimated beam"),
            (vec!["--scene", "amici-lamp", "--photons", "1000"], "--photons: the amici-lamp scene has no matte surface to store photons on"),
            (vec!["--exact", "--photons", "1000"], "--photons: --exact computes the image without photons"),
            (vec!["--exact-subsamples", "4"], "--exact-subsamples: only --exact uses it"),
            (vec!["--split", "4"], "--split: --eye hero takes one wavelength"),
            (vec!["--exposure", "1", "--exposure-gain", "2"], "--exposure-gain: --exposure sets the exposure"),
        ] {
            let mut full = vec!["prism", "--size", "8,8"];
            if !args.contains(&"--photons") {
                full.extend(["--photons", "1000"]);
            }
            full.extend(args.iter().copied());
            let o = run(&full, "", dir.path());
            assert_clean_failure(&o, needle);
        }
    }
}

#[test]
fn pictures_4_5_and_6_share_one_view() {
    // Report 000's three sample outputs must be framed identically so the
    // strip, the white patch and the undispersed beam can be compared.
    for kind in [SceneKind::AmiciScreen, SceneKind::AmiciLamp, SceneKind::SinglePrism] {
        let views: Vec<_> = [
            (false, false, IorKindFor::Sellmeier),
            (true, false, IorKindFor::Sellmeier),
            (false, true, IorKindFor::Sellmeier),
            (false, false, IorKindFor::Cauchy),
        ]
        .into_iter()
        .map(|(no_prism, no_dispersion, ior)| {
            let mut o = SceneOptions::new(kind);
            (o.no_prism, o.no_dispersion) = (no_prism, no_dispersion);
            o.ior = match ior {
                IorKindFor::Sellmeier => refract::optics::ior::IorKind::Sellmeier,
                IorKindFor::Cauchy => refract::optics::ior::IorKind::Cauchy,
            };
            let s = build(&o).unwrap();
            let screen = s.maps.first().map(|&f| s.faces[f].verts.clone());
            (s.camera.pos, s.camera.forward, screen)
        })
        .collect();
        for v in &views[1..] {
            assert_eq!(v, &views[0], "{kind:?}: the view changed");
        }
    }
}

enum IorKindFor {
    Sellmeier,
    Cauchy,
}
