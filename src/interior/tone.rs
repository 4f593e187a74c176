//! How the model's colours become the image's 8-bit values (docs/physics.md
//! §26). Report 004 computes colours on a 0-1 display scale and clamps each
//! channel at 1, so a hot spot brighter than white prints as a flat white
//! disc with a hard edge, and a blue one stays pure blue however bright.
//! `shoulder` keeps every value below a knee as the report's, and above it
//! rolls the colour's largest channel smoothly toward 1 (the shoulder of a
//! film's characteristic curve) while light beyond white bleaches toward
//! white, as an over-exposed colour does on film.

use crate::color::Rgb;
use glam::Vec3;

crate::named_enum! {
    /// How colours brighter than white are shown.
    pub enum Tone {
        /// Each channel clamped to [0, 1], as the report does.
        Clip = "clip",
        /// The report's values up to a knee, then a film's shoulder (§26).
        Shoulder = "shoulder",
    }
}

/// Where the shoulder starts: values at or below it are the report's.
pub const KNEE: f32 = 0.75;

/// The shoulder on one value (§26): identity to the knee, then
/// k + (1 - k) t / (1 + t) with t = (x - k) / (1 - k): continuous in value
/// and slope at the knee, rising toward 1 and never reaching it.
pub fn shoulder(x: f32) -> f32 {
    if x <= KNEE {
        x
    } else {
        let t = (x - KNEE) / (1.0 - KNEE);
        KNEE + (1.0 - KNEE) * t / (1.0 + t)
    }
}

impl Tone {
    /// The colour shown for the model's colour `c`, for the 8-bit image to
    /// clamp to [0, 1] (with the shoulder: already inside; NaN and infinity
    /// show black).
    pub fn apply(self, c: Rgb) -> Rgb {
        match self {
            Tone::Clip => c,
            Tone::Shoulder => {
                if !c.0.is_finite() {
                    return Rgb::BLACK;
                }
                let v = c.0.max(Vec3::ZERO);
                let m = v.max_element();
                if m <= KNEE {
                    return Rgb(v);
                }
                // Hue kept: the largest channel follows the shoulder, the
                // others in proportion (§26, step 1).
                let s = shoulder(m);
                let kept = v * (s / m);
                // Light beyond white bleaches toward the grey of the same
                // largest value: the fraction 1 - 1/(1 + (m - 1)) = (m-1)/m of
                // what lies past 1 (§26, step 2).
                let bleach = ((m - 1.0) / m).max(0.0);
                Rgb(kept + (Vec3::splat(s) - kept) * bleach)
            }
        }
    }
}

/// The image as shown: each pixel through `tone`, then to 8 bits.
pub fn display(image: &crate::image_io::Image, tone: Tone) -> Vec<u8> {
    image.pixels.iter().flat_map(|&p| tone.apply(p).to_u8()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shoulder_meets_the_report_at_the_knee_and_rises_toward_white() {
        assert_eq!(shoulder(0.5), 0.5);
        assert_eq!(shoulder(KNEE), KNEE);
        // Slope 1 at the knee: no kink.
        let h = 1e-3;
        let slope = (shoulder(KNEE + h) - shoulder(KNEE)) / h;
        assert!((slope - 1.0).abs() < 1e-2, "{slope}");
        // Monotonic, below 1, and close to 1 far past white.
        let mut last = 0.0;
        for i in 0..400 {
            let y = shoulder(i as f32 * 0.025);
            assert!(y >= last && y < 1.0, "{i}: {y}");
            last = y;
        }
        assert!(shoulder(50.0) > 0.99);
        // Past white, twice and four times as bright still show brighter
        // (by over 5 and 2 of 255 grey levels): no flat disc.
        assert!(shoulder(2.0) - shoulder(1.0) > 0.02 && shoulder(4.0) - shoulder(2.0) > 0.008);
    }

    #[test]
    fn clip_is_the_report_and_the_shoulder_keeps_colours_below_the_knee() {
        let c = Rgb(Vec3::new(0.2, 0.5, 0.7));
        assert_eq!(Tone::Clip.apply(c), c);
        assert_eq!(Tone::Shoulder.apply(c), c);
    }

    #[test]
    fn bright_blue_keeps_its_hue_until_white_then_bleaches() {
        // Below white: still pure blue.
        let b = Tone::Shoulder.apply(Rgb(Vec3::new(0.0, 0.0, 0.95))).0;
        assert_eq!((b.x, b.y), (0.0, 0.0));
        assert!(b.z > KNEE && b.z < 0.95);
        // Three times white: mostly white, bluish.
        let w = Tone::Shoulder.apply(Rgb(Vec3::new(0.0, 0.0, 3.0))).0;
        assert!(w.x > 0.6 && w.x < w.z && w.z < 1.0, "{w:?}");
        assert!((w.x - w.y).abs() < 1e-6);
    }

    #[test]
    fn nan_and_negative_show_black() {
        assert_eq!(Tone::Shoulder.apply(Rgb(Vec3::new(f32::NAN, 2.0, 2.0))).0, Vec3::ZERO);
        assert_eq!(Tone::Shoulder.apply(Rgb(Vec3::new(-1.0, 0.3, 0.0))).0, Vec3::new(0.0, 0.3, 0.0));
    }
}
