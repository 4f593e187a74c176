//! Report 000's Picture 2 (css552-p2): a white ray split by the Amici
//! prism, each wavelength refracted by Snell's law in vector form
//! (docs/physics.md §1) at every face. Past the prism the angles are drawn
//! five times larger so the fan shows at the page's scale; inside the
//! prism, where the wavelengths part by about a millimetre, an inset
//! magnifies its exit face at true angles.

use super::error::Result;
use super::plot::PlotError;
use crate::image_io::write_rgb8;
use crate::world::probe::{probe, ProbeRay};
use plotters::prelude::*;
use std::path::Path;

/// How much larger than true the angles past the prism are drawn.
pub const FAN_EXAGGERATION: f64 = 5.0;
/// The image's size in pixels.
pub const SIZE: (u32, u32) = (900, 520);
/// The main chart's ranges, metres.
const X_RANGE: (f64, f64) = (-0.12, 0.26);
const Y_RANGE: (f64, f64) = (-0.10, 0.12);
/// The inset's place on the main chart (data coordinates, metres): the
/// empty lower right, under the fan.
const INSET_AT: ((f64, f64), (f64, f64)) = ((0.055, 0.255), (-0.095, -0.03));
/// Wavelengths whose CIE colours are told apart: violet, blue, azure,
/// cyan-green, green, yellow, orange, red.
pub const LAMBDAS: [f64; 8] = [404.7, 465.0, 485.0, 505.0, 546.1, 575.0, 600.0, 656.3];

/// How much the inset magnifies (the same along x and y).
pub const INSET_MAGNIFICATION: f64 = 12.0;

/// The region of the prism the inset magnifies, as x and y ranges `span`
/// metres wide with the aspect `aspect` (width / height): the exit face,
/// where the rays leave the glass, a little left of the middle, so the
/// last stretch inside the glass and the start of the fan both show.
pub fn inset_region(rays: &[ProbeRay], span: f64, aspect: f64) -> ((f64, f64), (f64, f64)) {
    let n = rays.len().max(1) as f64;
    let centre = rays.iter().map(|p| p.exit_point.truncate()).sum::<glam::DVec2>() / n;
    let half = span / aspect / 2.0;
    ((centre.x - 0.6 * span, centre.x + 0.4 * span), (centre.y - half, centre.y + half))
}

/// The segment a-b clipped to the rectangle (Liang-Barsky), if any of it
/// is inside.
fn clip(a: (f64, f64), b: (f64, f64), xr: (f64, f64), yr: (f64, f64)) -> Option<[(f64, f64); 2]> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.0 - xr.0), (dx, xr.1 - a.0), (-dy, a.1 - yr.0), (dy, yr.1 - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 < t1).then_some([(a.0 + t0 * dx, a.1 + t0 * dy), (a.0 + t1 * dx, a.1 + t1 * dy)])
}

/// The length of one wavelength's dash inside the prism on the main
/// chart, m (about 6 px).
const DASH: f64 = 0.003;

/// An axis tick in metres: two decimals at most, and zero never "-0".
fn axis_tick(v: &f64) -> String {
    let r = (v * 100.0).round() / 100.0;
    if r == 0.0 {
        "0".to_string()
    } else {
        super::plot::tick(&r)
    }
}

/// The dashes of `path` that the `i`th of `n` wavelengths draws: the path
/// cut into pieces `dash` long along its length, piece k drawn by
/// wavelength k mod n, so n paths that coincide show every colour in turn.
fn dashes(path: &[(f64, f64)], dash: f64, i: usize, n: usize) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut walked = 0.0;
    for ab in path.windows(2) {
        let (a, b) = (ab[0], ab[1]);
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let at = |s: f64| {
            let t = ((s - walked) / len).clamp(0.0, 1.0);
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        };
        // Pieces that overlap this segment, cut at its ends.
        let mut k = (walked / dash).floor() as usize;
        while (k as f64) * dash < walked + len {
            if k % n == i {
                let (s0, s1) = ((k as f64 * dash).max(walked), ((k + 1) as f64 * dash).min(walked + len));
                if s1 > s0 {
                    out.push(vec![at(s0), at(s1)]);
                }
            }
            k += 1;
        }
        walked += len;
    }
    out
}

/// The line colour of a wavelength: its CIE colour at full brightness.
fn colour(nm: f64) -> RGBColor {
    let rgb = crate::spectrum::colormap::ColorMap::Cie.rgb(nm);
    let scale = 1.0 / rgb.max_element().max(1e-9);
    let enc = |v: f64| (crate::spectrum::cie::srgb_encode((v * scale).clamp(0.0, 1.0)) * 255.0) as u8;
    RGBColor(enc(rgb.x), enc(rgb.y), enc(rgb.z))
}

/// The main chart: data coordinates in metres.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

/// Draws Picture 2 into `png`; returns its parameter text.
pub fn draw(png: &Path) -> Result<String> {
    super::plot::register();
    let s = crate::scenes::build(&crate::scenes::SceneOptions::new(crate::scenes::SceneKind::AmiciScreen))?;
    let outline = prism_outline(&s);
    let rays: Vec<ProbeRay> = LAMBDAS.iter().map(|nm| probe(&s, *nm)).collect();
    let angle = |p: &ProbeRay| p.exit_dir.y.atan2(p.exit_dir.x).to_degrees();
    let spread = angle(&rays[0]) - angle(&rays[LAMBDAS.len() - 1]);
    let (w, h) = SIZE;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let magnification;
    {
        let root = super::glyphs::Glyphs(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::draw)?;
        let mut c = main_chart(&root)?;
        draw_main(&mut c, &s, &outline, &rays)?;
        // The fan's true spread, written beside it.
        let note = format!("fan drawn {FAN_EXAGGERATION}x wider: its true spread is {spread:.1} degrees");
        c.draw_series(std::iter::once(Text::new(note, (-0.005, 0.112), ("sans-serif", 16).into_font().color(&BLACK)))).map_err(PlotError::draw)?;
        magnification = draw_inset(&root, &mut c, &outline, &rays)?;
        root.present().map_err(PlotError::draw)?;
    }
    write_rgb8(png, w as usize, h as usize, &buf)?;
    Ok(format!(
        "N-BK7 | N-SF11 | N-BK7, flint apex 90 deg, Sellmeier; deviation past the prism drawn {FAN_EXAGGERATION}x (true spread {spread:.2} deg); inset magnified {magnification:.1}x at true angles"
    ))
}

/// The main chart on `root`, with its caption and its axes' grid.
fn main_chart<'a, DB>(root: &'a DrawingArea<DB, plotters::coord::Shift>) -> Result<Chart<'a, DB>>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    let mut c = ChartBuilder::on(root)
        .caption(
            format!("A white ray split by the Amici prism (Snell's law per wavelength); past the prism, angles drawn {FAN_EXAGGERATION}x"),
            ("sans-serif", 19),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(X_RANGE.0..X_RANGE.1, Y_RANGE.0..Y_RANGE.1)
        .map_err(PlotError::draw)?;
    // A light grid at the labelled ticks only.
    c.configure_mesh()
        .x_labels(8)
        .y_labels(5)
        .x_label_formatter(&axis_tick)
        .y_label_formatter(&axis_tick)
        .bold_line_style(RGBColor(226, 226, 226))
        .light_line_style(TRANSPARENT)
        .x_desc("x (m)")
        .y_desc("y (m)")
        .label_style(("sans-serif", 16))
        .draw()
        .map_err(PlotError::draw)?;
    Ok(c)
}

/// The prism's outline, each wavelength's path through it and its fan
/// past it (angles exaggerated), the white ray up to it, and the legend.
fn draw_main<'a, DB>(c: &mut Chart<'a, DB>, s: &crate::world::World, outline: &[[(f64, f64); 2]], rays: &[ProbeRay]) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    for seg in outline {
        c.draw_series(LineSeries::new(seg.to_vec(), BLACK.stroke_width(2))).map_err(PlotError::draw)?;
    }
    for (i, p) in rays.iter().enumerate() {
        let col = colour(p.nm);
        // Inside the prism the paths lie within a millimetre of each
        // other: each wavelength draws its own dashes in turn, so all
        // show where one line would hide the rest.
        let inside: Vec<(f64, f64)> = p.path.iter().skip(1).map(|v| (v.x, v.y)).collect();
        for dash in dashes(&inside, DASH, i, rays.len()) {
            c.draw_series(LineSeries::new(dash, col.stroke_width(3))).map_err(PlotError::draw)?;
        }
        // Past the prism, FAN_EXAGGERATION times the angle so the fan shows.
        let (end, d) = (p.exit_point, p.exit_dir);
        let fan = vec![(end.x, end.y), (end.x + 0.2, end.y + 0.2 * (d.y / d.x) * FAN_EXAGGERATION)];
        c.draw_series(LineSeries::new(fan, col.stroke_width(2)))
            .map_err(PlotError::draw)?
            .label(format!("{} nm", p.nm))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], col.stroke_width(3)));
    }
    // The white ray, one path for every wavelength up to the prism,
    // drawn over them in grey.
    let white: Vec<(f64, f64)> = probe(s, 587.6).path.iter().take(2).map(|v| (v.x, v.y)).collect();
    let grey = RGBColor(110, 110, 110);
    c.draw_series(LineSeries::new(white, grey.stroke_width(3)))
        .map_err(PlotError::draw)?
        .label("white light")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], grey.stroke_width(3)));
    c.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()
        .map_err(PlotError::draw)?;
    Ok(())
}

/// The inset at `INSET_AT`: the exit face magnified at true angles, the
/// box on the main chart it magnifies and guides to it; returns the
/// magnification along x.
fn draw_inset<'a, DB>(root: &DrawingArea<DB, plotters::coord::Shift>, c: &mut Chart<'a, DB>, outline: &[[(f64, f64); 2]], rays: &[ProbeRay]) -> Result<f64>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    // The inset: where on the page, and which part of the prism.
    let (ix, iy) = INSET_AT;
    let (p0, p1) = (c.backend_coord(&(ix.0, iy.1)), c.backend_coord(&(ix.1, iy.0)));
    let (pw, ph) = ((p1.0 - p0.0) as u32, (p1.1 - p0.1) as u32);
    let (xr, yr) = inset_region(rays, (ix.1 - ix.0) / INSET_MAGNIFICATION, pw as f64 / ph as f64);
    // Inset pixels per metre over the main chart's, along x.
    let magnification = (ix.1 - ix.0) / (xr.1 - xr.0);
    let region = [(xr.0, yr.0), (xr.1, yr.0), (xr.1, yr.1), (xr.0, yr.1), (xr.0, yr.0)];
    c.draw_series(LineSeries::new(region, BLACK.stroke_width(1))).map_err(PlotError::draw)?;
    // Thin grey lines from the box to the inset's top corners.
    let guide = RGBColor(150, 150, 150);
    for (from, to) in [((xr.0, yr.0), (ix.0, iy.1)), ((xr.1, yr.0), (ix.1, iy.1))] {
        c.draw_series(LineSeries::new([from, to], guide.stroke_width(1))).map_err(PlotError::draw)?;
    }
    let title = format!("inset: the exit face (box) magnified {magnification:.0}x, at true angles");
    c.draw_series(std::iter::once(Text::new(title, (ix.0, iy.1 + 0.009), ("sans-serif", 16).into_font().color(&BLACK)))).map_err(PlotError::draw)?;
    let area = root.clone().shrink(p0, (pw, ph));
    area.fill(&WHITE).map_err(PlotError::draw)?;
    let mut inset = ChartBuilder::on(&area).build_cartesian_2d(xr.0..xr.1, yr.0..yr.1).map_err(PlotError::draw)?;
    for seg in outline {
        if let Some(seg) = clip(seg[0], seg[1], xr, yr) {
            inset.draw_series(LineSeries::new(seg, BLACK.stroke_width(2))).map_err(PlotError::draw)?;
        }
    }
    for p in rays {
        let col = colour(p.nm);
        // True angles here, the ray carried on past the exit face.
        let mut pts: Vec<(f64, f64)> = p.path.iter().map(|v| (v.x, v.y)).collect();
        let (end, d) = (p.exit_point, p.exit_dir);
        let t = (xr.1 - end.x) / d.x.max(1e-9);
        pts.push((end.x + t * d.x, end.y + t * d.y));
        for ab in pts.windows(2) {
            if let Some(seg) = clip(ab[0], ab[1], xr, yr) {
                inset.draw_series(LineSeries::new(seg, col.stroke_width(2))).map_err(PlotError::draw)?;
            }
        }
    }
    area.draw(&Rectangle::new([(0, 0), (pw as i32 - 1, ph as i32 - 1)], BLACK.stroke_width(1))).map_err(PlotError::draw)?;
    Ok(magnification)
}

/// Prism faces in the z < 0 cap plane as segments (top view).
fn prism_outline(s: &crate::world::World) -> Vec<[(f64, f64); 2]> {
    s.faces
        .iter()
        .filter(|f| matches!(f.surface, crate::world::Surface::Interface { .. }) && f.normal.z.abs() < 1e-9)
        .map(|f| {
            let low: Vec<_> = f.verts.iter().filter(|v| v.z < 0.0).collect();
            [(low[0].x, low[0].y), (low[1].x, low[1].y)]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inset shows the wavelengths apart: at the exit face neighbouring
    /// rays, drawn at the inset's scale on the 900 px page, stand several
    /// pixels apart, where the main chart's 2 px lines overlap.
    #[test]
    fn the_inset_parts_the_wavelengths_inside_the_prism() {
        let s = crate::scenes::build(&crate::scenes::SceneOptions::new(crate::scenes::SceneKind::AmiciScreen)).unwrap();
        let rays: Vec<ProbeRay> = LAMBDAS.iter().map(|nm| probe(&s, *nm)).collect();
        // The inset's width on the page, about as drawn.
        let (ix, _) = INSET_AT;
        let main_px_per_m = (SIZE.0 as f64 - 84.0) / (X_RANGE.1 - X_RANGE.0);
        let inset_px = main_px_per_m * (ix.1 - ix.0);
        let (xr, yr) = inset_region(&rays, (ix.1 - ix.0) / INSET_MAGNIFICATION, 3.0);
        let per_m = inset_px / (xr.1 - xr.0);
        let (v, r) = (rays[0].exit_point, rays[LAMBDAS.len() - 1].exit_point);
        let apart = (v - r).truncate().length();
        // Neighbouring wavelengths' mean spacing: under the lines' 2 px
        // width on the main chart (they overlap there), several px in the inset.
        let gaps = (LAMBDAS.len() - 1) as f64;
        assert!(apart * per_m / gaps > 4.0, "in the inset neighbours leave {:.1} px apart", apart * per_m / gaps);
        assert!(apart * main_px_per_m / gaps < 2.0, "on the main chart neighbours are {:.1} px apart", apart * main_px_per_m / gaps);
        // Every exit point is inside the inset, and the magnification is real.
        for p in &rays {
            let e = p.exit_point;
            assert!(e.x > xr.0 && e.x < xr.1 && e.y > yr.0 && e.y < yr.1, "{} nm exits outside the inset", p.nm);
        }
        assert!((ix.1 - ix.0) / (xr.1 - xr.0) > 3.0);
    }

    #[test]
    fn every_wavelength_shows_inside_the_prism_and_no_tick_reads_minus_zero() {
        let path: [(f64, f64); 3] = [(0.0, 0.0), (0.05, 0.01), (0.08, -0.01)];
        let total: f64 = path.windows(2).map(|w| ((w[1].0 - w[0].0).powi(2) + (w[1].1 - w[0].1).powi(2)).sqrt()).sum();
        let n = LAMBDAS.len();
        let mut covered = 0.0;
        for i in 0..n {
            let d = dashes(&path, DASH, i, n);
            // Each wavelength draws its share of the path, in several dashes.
            let own: f64 = d.iter().map(|s| ((s[1].0 - s[0].0).powi(2) + (s[1].1 - s[0].1).powi(2)).sqrt()).sum();
            assert!(d.len() >= 3 && (own - total / n as f64).abs() < 1.5 * DASH, "wavelength {i}: {} dashes, {own:.4} m of {total:.4}", d.len());
            covered += own;
        }
        assert!((covered - total).abs() < 1e-9, "the dashes cover the path once: {covered} vs {total}");
        for v in [-1e-17, -0.0, 0.0, 1e-17] {
            assert_eq!(axis_tick(&v), "0");
        }
        assert_eq!(axis_tick(&-0.05), "-0.05");
        assert_eq!(axis_tick(&0.1), "0.1");
    }

    #[test]
    fn clipping_keeps_what_is_inside() {
        let r = (0.0, 1.0);
        assert_eq!(clip((-1.0, 0.5), (2.0, 0.5), r, r), Some([(0.0, 0.5), (1.0, 0.5)]));
        assert_eq!(clip((0.2, 0.2), (0.4, 0.4), r, r), Some([(0.2, 0.2), (0.4, 0.4)]));
        assert_eq!(clip((-1.0, 2.0), (2.0, 2.0), r, r), None);
    }
}
