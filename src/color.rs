//! Linear RGB colour with components nominally in [0, 1].

use glam::Vec3;
use std::ops::{Add, AddAssign, Mul};

/// A linear RGB triple. Arithmetic is component-wise.
#[derive(Copy, Clone, Debug, PartialEq, Default)]
pub struct Rgb(pub Vec3);

impl Rgb {
    pub const BLACK: Rgb = Rgb(Vec3::ZERO);
    pub const WHITE: Rgb = Rgb(Vec3::ONE);

    pub fn new(r: f32, g: f32, b: f32) -> Self {
        Rgb(Vec3::new(r, g, b))
    }

    /// From 0-255 integer components, as the report's prompts take them.
    pub fn from_u8(c: [u8; 3]) -> Self {
        Rgb::new(c[0] as f32 / 255.0, c[1] as f32 / 255.0, c[2] as f32 / 255.0)
    }

    /// To 8 bits: clamped to [0, 1] and rounded. NaN becomes 0, so a NaN can
    /// never reach an image.
    pub fn to_u8(self) -> [u8; 3] {
        let q = |c: f32| if c.is_nan() { 0 } else { (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8 };
        [q(self.0.x), q(self.0.y), q(self.0.z)]
    }

    pub fn is_finite(self) -> bool {
        self.0.is_finite()
    }
}

impl Add for Rgb {
    type Output = Rgb;
    fn add(self, o: Rgb) -> Rgb {
        Rgb(self.0 + o.0)
    }
}

impl AddAssign for Rgb {
    fn add_assign(&mut self, o: Rgb) {
        self.0 += o.0;
    }
}

impl Mul for Rgb {
    type Output = Rgb;
    fn mul(self, o: Rgb) -> Rgb {
        Rgb(self.0 * o.0)
    }
}

impl Mul<f32> for Rgb {
    type Output = Rgb;
    fn mul(self, k: f32) -> Rgb {
        Rgb(self.0 * k)
    }
}

impl Mul<Rgb> for f32 {
    type Output = Rgb;
    fn mul(self, c: Rgb) -> Rgb {
        Rgb(self * c.0)
    }
}
