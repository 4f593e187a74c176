//! Accuracy and stability metrics recorded for every run.

pub use crate::modes::Frame;

/// Pixels whose luminance is NaN or infinite.
pub fn non_finite(f: &Frame) -> usize {
    f.luminance.iter().filter(|v| !v.is_finite()).count()
}

/// RMSE of the displayed values in [0, 1] (all channels) and PSNR in dB
/// (infinite PSNR is written as 99 dB). `None` if the sizes differ.
pub fn rmse_psnr(a: &Frame, reference: &Frame) -> Option<(f64, f64)> {
    if (a.width, a.height) != (reference.width, reference.height) {
        return None;
    }
    let n = a.display.len().max(1) as f64;
    let se: f64 = a.display.iter().zip(&reference.display).map(|(x, y)| ((*x as f64 - *y as f64) / 255.0).powi(2)).sum();
    let rmse = (se / n).sqrt();
    let psnr = if rmse > 0.0 { (20.0 * (1.0 / rmse).log10()).min(99.0) } else { 99.0 };
    Some((rmse, psnr))
}

/// Relative RMSE of luminance, ||Y - Y_ref|| / ||Y_ref||: against an
/// all-black reference 0 for a black frame and infinite for any other
/// (written to a CSV as an empty cell, not as a perfect 0).
pub fn relative_rmse(a: &Frame, reference: &Frame) -> Option<f64> {
    if (a.width, a.height) != (reference.width, reference.height) {
        return None;
    }
    let fin = |v: f64| if v.is_finite() { v } else { 0.0 };
    let (num, den) = a.luminance.iter().zip(&reference.luminance).fold((0.0, 0.0), |(n, d), (x, y)| (n + (fin(*x) - fin(*y)).powi(2), d + fin(*y).powi(2)));
    Some(relative(num, den))
}

/// The error the prism bench reports (`bench prism`,
/// `spectral::exact::relative_error`): the frame scaled by least squares
/// onto the reference, RMS difference of XYZ over the reference's RMS.
/// `None` where either frame has no XYZ (not a spectral render) or the
/// sizes differ.
pub fn relative_error(a: &Frame, reference: &Frame) -> Option<f64> {
    if (a.width, a.height) != (reference.width, reference.height) || a.xyz.is_empty() || a.xyz.len() != reference.xyz.len() {
        return None;
    }
    let finite = |v: &[glam::DVec3]| -> Vec<glam::DVec3> { v.iter().map(|p| if p.is_finite() { *p } else { glam::DVec3::ZERO }).collect() };
    Some(crate::spectral::exact::relative_error_xyz(&finite(&a.xyz), &finite(&reference.xyz)))
}

/// sqrt(num / den) for sums of squares, with x / 0 read as infinite for
/// x > 0 and as 0 for x = 0 (two black images are equal).
pub fn relative(num: f64, den: f64) -> f64 {
    if den > 0.0 {
        (num / den).sqrt()
    } else if num > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

/// Pixels whose display value differs from the other frame's.
pub fn changed_pixels(a: &Frame, b: &Frame) -> Option<usize> {
    if (a.width, a.height) != (b.width, b.height) {
        return None;
    }
    Some(a.display.chunks(3).zip(b.display.chunks(3)).filter(|(x, y)| x != y).count())
}

/// Fireflies: pixels more than 10 times as bright as the mean of their
/// eight neighbours, and above 1 % of the frame's brightest.
pub fn fireflies(f: &Frame) -> usize {
    let (w, h) = (f.width, f.height);
    let lum = |x: usize, y: usize| {
        let v = f.luminance[y * w + x];
        if v.is_finite() {
            v
        } else {
            0.0
        }
    };
    let max = (0..w * h).map(|i| lum(i % w, i / w)).fold(0.0, f64::max);
    let mut n = 0;
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let v = lum(x, y);
            if v <= 0.01 * max {
                continue;
            }
            let around: f64 =
                [(0, 0), (1, 0), (2, 0), (0, 1), (2, 1), (0, 2), (1, 2), (2, 2)].iter().map(|(dx, dy)| lum(x + dx - 1, y + dy - 1)).sum::<f64>() / 8.0;
            if v > 10.0 * around {
                n += 1;
            }
        }
    }
    n
}

/// Highlight area: pixels of linear luminance at least 0.75.
pub fn highlight_pixels(f: &Frame) -> usize {
    f.luminance.iter().filter(|v| **v >= 0.75).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(lum: Vec<f64>) -> Frame {
        let n = lum.len();
        Frame { width: n, height: 1, display: lum.iter().flat_map(|v| [(v.clamp(0.0, 1.0) * 255.0) as u8; 3]).collect(), luminance: lum, xyz: Vec::new() }
    }

    #[test]
    fn counts_an_injected_nan_and_infinity() {
        let mut f = frame(vec![0.5; 10]);
        assert_eq!(non_finite(&f), 0);
        f.luminance[3] = f64::NAN;
        f.luminance[7] = f64::INFINITY;
        assert_eq!(non_finite(&f), 2);
        // Metrics stay finite with them.
        assert!(relative_rmse(&f, &frame(vec![0.5; 10])).unwrap().is_finite());
    }

    #[test]
    fn a_black_reference_makes_any_other_frame_infinitely_wrong_not_perfect() {
        let black = frame(vec![0.0; 10]);
        assert_eq!(relative_rmse(&black, &black), Some(0.0));
        assert_eq!(relative_rmse(&frame(vec![0.5; 10]), &black), Some(f64::INFINITY));
        assert_eq!(relative_rmse(&frame(vec![0.5; 10]), &frame(vec![0.25; 10])), Some(1.0));
        // And the CSV gets a missing value for it, not 0.
        assert_eq!(crate::timing::cell(f64::INFINITY), "");
    }

    #[test]
    fn rmse_psnr_and_changes() {
        let a = frame(vec![0.0, 1.0]);
        let b = frame(vec![0.0, 0.0]);
        let (rmse, psnr) = rmse_psnr(&a, &b).unwrap();
        assert!((rmse - (0.5f64).sqrt()).abs() < 1e-12 && (psnr - 3.0103).abs() < 1e-3);
        assert_eq!(rmse_psnr(&a, &a).unwrap(), (0.0, 99.0));
        assert_eq!(changed_pixels(&a, &b), Some(1));
        assert_eq!(rmse_psnr(&a, &frame(vec![0.0])), None);
    }

    #[test]
    fn relative_error_is_the_bench_s_scale_free_one() {
        let with = |v: Vec<f64>| Frame { xyz: v.iter().map(|&y| glam::DVec3::new(y, y, y)).collect(), ..frame(v) };
        let r = with(vec![1.0, 2.0, 3.0]);
        assert!(relative_error(&with(vec![2.0, 4.0, 6.0]), &r).unwrap() < 1e-12, "a brighter copy is no error");
        assert!(relative_error(&with(vec![1.0, 2.0, 4.0]), &r).unwrap() > 0.01);
        assert_eq!(relative_error(&frame(vec![1.0, 2.0, 3.0]), &r), None, "no XYZ, no error");
    }

    #[test]
    fn fireflies_stand_out() {
        let mut lum = vec![0.1; 25];
        lum[12] = 5.0;
        let f = Frame { width: 5, height: 5, display: vec![0; 75], luminance: lum, xyz: Vec::new() };
        assert_eq!(fireflies(&f), 1);
    }
}
