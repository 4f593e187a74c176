//! The film's kernel, chosen from the film itself (docs/physics.md §20).
//! Light tracing onto the film (`splat`) has no bias and no floor, but
//! with few photons a pixel is noisy where a kernel a few pixels wide
//! would average its neighbours. Which width is best depends on the
//! photon count and on the image, so it is measured: the photons fall
//! into two halves, two independent estimates A and B of the same image.
//! For a kernel K, E|KA - B|^2 = E|KA - I|^2 + E|B - I|^2, and the second
//! term does not depend on K, so the K whose smoothed A best predicts B
//! (and B, A) is the one closest to the true image I: hold-out
//! cross-validation. As photons grow the noise falls, the chosen width
//! shrinks to none, and the film keeps converging.

use glam::DVec3;
use rayon::prelude::*;

/// The kernels tried: tents of these radii in pixels along each axis
/// (their product, separable); 0 is no kernel.
pub const RADII: [f64; 10] = [0.0, 1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0];

/// An image of `width` columns, row by row.
#[derive(Clone, Copy)]
pub struct Grid {
    pub width: usize,
    pub height: usize,
}

/// The 1-D tent of radius `r` pixels: weights at offsets -k..=k.
fn tent(r: f64) -> Vec<f64> {
    let k = (r.ceil() as usize).saturating_sub(1);
    (0..=2 * k).map(|i| (1.0 - (i as f64 - k as f64).abs() / r).max(0.0)).collect()
}

/// `img` smoothed by the product of two tents of radius `r` pixels, each
/// pass renormalised over the taps inside the image (so the edges keep
/// their level). Radius 0 or under 1 returns the image as it is.
pub fn smooth(img: &[DVec3], g: Grid, r: f64) -> Vec<DVec3> {
    if r <= 1.0 {
        return img.to_vec();
    }
    let w = tent(r);
    let k = w.len() / 2;
    // One pass along rows (step 1) or columns (step `width`): the taps
    // that fall inside the image, and their weights' sum.
    let pass = |src: &[DVec3], along_rows: bool| -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; src.len()];
        let (n, step) = if along_rows { (g.width, 1) } else { (g.height, g.width) };
        let row = |(y, row): (usize, &mut [DVec3])| {
            for (x, px) in row.iter_mut().enumerate() {
                let (at, i) = if along_rows { (y * g.width, x) } else { (x, y) };
                let (lo, hi) = (k.saturating_sub(i), (n + k - i).min(w.len()));
                let mut sum = DVec3::ZERO;
                let mut norm = 0.0;
                for (j, &wj) in w.iter().enumerate().take(hi).skip(lo) {
                    sum += src[at + (i + j - k) * step] * wj;
                    norm += wj;
                }
                *px = sum / norm;
            }
        };
        // Rows in parallel where there are enough to pay for it: each
        // output pixel is its own sum, the same either way.
        if src.len() * w.len() >= 1 << 18 {
            out.par_chunks_mut(g.width).enumerate().for_each(row);
        } else {
            out.chunks_mut(g.width).enumerate().for_each(row);
        }
        out
    };
    pass(&pass(img, true), false)
}

/// The part of the image where either half has light, widened by the
/// largest kernel: outside it both halves and every smoothing are zero.
fn lit_window(halves: &[Vec<DVec3>; 2], g: Grid) -> (usize, usize, usize, usize) {
    let (mut x0, mut y0, mut x1, mut y1) = (g.width, g.height, 0, 0);
    for y in 0..g.height {
        for x in 0..g.width {
            let i = y * g.width + x;
            if halves[0][i] != DVec3::ZERO || halves[1][i] != DVec3::ZERO {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1));
            }
        }
    }
    if x0 >= x1 {
        return (0, 0, 0, 0);
    }
    let m = RADII[RADII.len() - 1].ceil() as usize;
    (x0.saturating_sub(m), y0.saturating_sub(m), (x1 + m).min(g.width), (y1 + m).min(g.height))
}

/// The radius (one of `RADII`) whose kernel makes the whole film closest
/// to the true image, as the two halves estimate it over `window` (the
/// lit part, `lit_window`; docs/physics.md
/// §20). With V the noise of one half (E|2A - I|^2, measured as |2A -
/// 2B|^2 / 2) and s the kernel's sum of squared weights (how much of the
/// noise it keeps), |K(2A) - 2B|^2 = bias + s V + V; the whole film, with
/// half the noise of a half, has error bias + s V / 2.
fn choose(halves: &[Vec<DVec3>; 2], g: Grid, (x0, y0, x1, y1): (usize, usize, usize, usize)) -> f64 {
    if x1 == 0 {
        return 0.0;
    }
    let w = Grid { width: x1 - x0, height: y1 - y0 };
    let (a, b) = (crop(&halves[0], g, x0..x1, y0..y1, 2.0), crop(&halves[1], g, x0..x1, y0..y1, 2.0));
    let miss = |s: &[DVec3], t: &[DVec3]| s.iter().zip(t).map(|(p, q)| (*p - *q).length_squared()).sum::<f64>();
    let noise = miss(&a, &b) / 2.0;
    let mut best = (0.0, f64::INFINITY);
    let mut worse = 0;
    for r in RADII {
        let held_out = (miss(&smooth(&a, w, r), &b) + miss(&smooth(&b, w, r), &a)) / 2.0;
        let s = kept_noise(r);
        let error = held_out - noise - s * noise / 2.0;
        if error < best.1 {
            (best, worse) = ((r, error), 0);
        } else {
            // Wider kernels only blur more once two in a row are worse.
            worse += 1;
            if worse == 2 {
                break;
            }
        }
    }
    best.0
}

/// The share of independent pixel noise the kernel of radius `r` keeps
/// (its normalised weights' sum of squares, away from the edges).
fn kept_noise(r: f64) -> f64 {
    if r <= 1.0 {
        return 1.0;
    }
    let t = tent(r);
    let sum: f64 = t.iter().sum();
    (t.iter().map(|w| w * w).sum::<f64>() / (sum * sum)).powi(2)
}

/// The pixels of columns `xs` and rows `ys` of `img`, times `k`.
fn crop(img: &[DVec3], g: Grid, xs: std::ops::Range<usize>, ys: std::ops::Range<usize>, k: f64) -> Vec<DVec3> {
    ys.flat_map(|y| xs.clone().map(move |x| y * g.width + x)).map(|i| img[i] * k).collect()
}

/// The film's image: the two halves summed, smoothed where there is light
/// by the kernel of radius `fixed`, or else the chosen one; and the
/// kernel's radius.
pub fn film_image(halves: &[Vec<DVec3>; 2], g: Grid, fixed: Option<f64>) -> (Vec<DVec3>, f64) {
    let window = lit_window(halves, g);
    let r = fixed.unwrap_or_else(|| choose(halves, g, window));
    let mut sum: Vec<DVec3> = halves[0].iter().zip(&halves[1]).map(|(a, b)| *a + *b).collect();
    let (x0, y0, x1, y1) = window;
    if r > 1.0 && x1 > 0 {
        let w = Grid { width: x1 - x0, height: y1 - y0 };
        let smoothed = smooth(&crop(&sum, g, x0..x1, y0..y1, 1.0), w, r);
        for (y, row) in smoothed.chunks(w.width).enumerate() {
            sum[(y0 + y) * g.width + x0..][..w.width].copy_from_slice(row);
        }
    }
    (sum, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tent_is_symmetric_and_smoothing_keeps_a_flat_image() {
        assert_eq!(tent(2.0), vec![0.5, 1.0, 0.5]);
        assert_eq!(tent(1.5).len(), 3);
        let g = Grid { width: 7, height: 5 };
        let flat = vec![DVec3::new(1.0, 2.0, 3.0); 35];
        for r in RADII {
            for p in smooth(&flat, g, r) {
                assert!((p - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12, "radius {r}");
            }
        }
    }

    /// A film with a known true image: photons drawn from a bright strip
    /// with sharp ends (a rainbow strip's shape: a ramp across, a step at
    /// each end, black around), each half from its own photons. The
    /// radius the halves choose is checked against the truth itself.
    fn film_of(photons: usize, seed: u64) -> ([Vec<DVec3>; 2], Vec<DVec3>, Grid) {
        let g = Grid { width: 64, height: 32 };
        let truth: Vec<DVec3> = (0..g.width * g.height)
            .map(|i| {
                let (x, y) = (i % g.width, i / g.width);
                let lit = (8..56).contains(&x) && (10..22).contains(&y);
                if lit {
                    DVec3::new(1.0 + x as f64 / 32.0, 1.0, 2.0 - x as f64 / 48.0)
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        let total: DVec3 = truth.iter().sum();
        let lum: Vec<f64> = truth.iter().map(|v| v.y).collect();
        let cdf: Vec<f64> = lum
            .iter()
            .scan(0.0, |a, v| {
                *a += v;
                Some(*a)
            })
            .collect();
        let mut rng = crate::sampling::Rng::new(seed, photons as u64, 7);
        let mut half = |_| {
            let mut img = vec![DVec3::ZERO; truth.len()];
            for _ in 0..photons / 2 {
                let u = rng.f64() * cdf[cdf.len() - 1];
                let i = cdf.partition_point(|&c| c <= u).min(truth.len() - 1);
                // Each photon carries the pixel's colour at the mean
                // brightness: the halves sum to the truth on average.
                img[i] += truth[i] / truth[i].y * (total.y / photons as f64);
            }
            img
        };
        ([half(0), half(1)], truth, g)
    }

    fn error(img: &[DVec3], truth: &[DVec3]) -> f64 {
        img.iter().zip(truth).map(|(a, b)| (*a - *b).length_squared()).sum::<f64>().sqrt()
    }

    #[test]
    fn the_halves_choose_a_kernel_near_the_best_one_for_the_truth() {
        let mut chosen = Vec::new();
        for photons in [2_000, 20_000, 200_000, 2_000_000, 20_000_000] {
            let (halves, truth, g) = film_of(photons, 3);
            let (img, r) = film_image(&halves, g, None);
            let sum: Vec<DVec3> = halves[0].iter().zip(&halves[1]).map(|(a, b)| *a + *b).collect();
            let best = RADII.iter().map(|&r| error(&smooth(&sum, g, r), &truth)).fold(f64::INFINITY, f64::min);
            let got = error(&img, &truth);
            assert!(got <= 1.1 * best, "{photons} photons: radius {r} gives {got}, the best radius {best}");
            assert!(got <= error(&sum, &truth) * 1.0001, "{photons} photons: a kernel no better than none");
            chosen.push(r);
        }
        // Few photons: a wide kernel; many: none (measured 2.5, 1.25, 0,
        // 0, 0; at 2000 photons the kernel halves the error).
        assert!(chosen[0] >= 2.0 && chosen[4] == 0.0, "radii chosen {chosen:?}");
        assert!(chosen.windows(2).all(|w| w[1] <= w[0]), "radii chosen {chosen:?}");
    }
}
