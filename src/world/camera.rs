//! The pinhole camera of the eye pass, and its inverse (projection) for
//! tests and metrics that ask where a world point appears.

use glam::{DVec2, DVec3};

/// Pinhole camera.
#[derive(Clone, Debug)]
pub struct Camera {
    pub pos: DVec3,
    pub forward: DVec3,
    pub up: DVec3,
    /// Vertical field of view, radians.
    pub vfov: f64,
    pub width: usize,
    pub height: usize,
}

impl Camera {
    pub fn look_at(pos: DVec3, target: DVec3, up: DVec3, vfov_deg: f64, width: usize, height: usize) -> Camera {
        let forward = (target - pos).normalize();
        let right = forward.cross(up).normalize();
        Camera { pos, forward, up: right.cross(forward), vfov: vfov_deg.to_radians(), width, height }
    }

    fn right(&self) -> DVec3 {
        self.forward.cross(self.up)
    }

    /// Ray direction through image position (x, y) in pixels from the top left.
    pub fn ray(&self, x: f64, y: f64) -> DVec3 {
        let t = (self.vfov / 2.0).tan();
        let aspect = self.width as f64 / self.height as f64;
        let sx = (2.0 * x / self.width as f64 - 1.0) * t * aspect;
        let sy = (1.0 - 2.0 * y / self.height as f64) * t;
        (self.forward + sx * self.right() + sy * self.up).normalize()
    }

    /// Pixel position of a world point in front of the camera.
    pub fn project(&self, p: DVec3) -> Option<DVec2> {
        let r = p - self.pos;
        let z = r.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let t = (self.vfov / 2.0).tan();
        let aspect = self.width as f64 / self.height as f64;
        let sx = r.dot(self.right()) / z / (t * aspect);
        let sy = r.dot(self.up) / z / t;
        Some(DVec2::new((sx + 1.0) * self.width as f64 / 2.0, (1.0 - sy) * self.height as f64 / 2.0))
    }
}
