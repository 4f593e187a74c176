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

    /// Whether any part of the ball of `radius` about `centre` can lie in
    /// the camera's view (a conservative test: false only when the whole
    /// ball is outside one of the frustum's four sides or behind the
    /// camera).
    pub fn may_see(&self, centre: DVec3, radius: f64) -> bool {
        let r = centre - self.pos;
        let z = r.dot(self.forward);
        let t = (self.vfov / 2.0).tan();
        let aspect = self.width as f64 / self.height as f64;
        // A side plane through the pinhole, x = z tan: the ball lies
        // wholly beyond it when its centre is farther than `radius`.
        let inside = |x: f64, tan: f64| (x.abs() - z * tan) <= radius * (1.0 + tan * tan).sqrt();
        z >= -radius && inside(r.dot(self.right()), t * aspect) && inside(r.dot(self.up), t)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A ball that some ray through the image meets is never said to be
    /// out of view: checked against rays through a fine grid of image
    /// points, for balls in front of, beside and behind the camera (and
    /// enough of them out of view that the test is not passed by saying
    /// every ball may be seen).
    #[test]
    fn a_ball_out_of_view_is_never_met_by_a_camera_ray() {
        let cam = Camera::look_at(DVec3::new(0.1, -0.2, 0.3), DVec3::new(3.0, 0.5, 0.0), DVec3::Z, 30.0, 64, 48);
        let mut rng = crate::sampling::Rng::new(4, 4, 4);
        let (mut seen, mut unseen) = (0, 0);
        for _ in 0..400 {
            let c = cam.pos + cam.forward * (rng.f64() * 6.0 - 1.0) + DVec3::new(rng.f64() * 4.0 - 2.0, rng.f64() * 4.0 - 2.0, rng.f64() * 4.0 - 2.0);
            let radius = 0.05 + rng.f64() * 0.8;
            let met = (0..=64).any(|i| {
                (0..=48).any(|j| {
                    let d = cam.ray(i as f64, j as f64);
                    let oc = c - cam.pos;
                    let b = oc.dot(d);
                    b > 0.0 && oc.length_squared() - b * b <= radius * radius || oc.length() <= radius
                })
            });
            let may = cam.may_see(c, radius);
            assert!(may || !met, "ball at {c} of radius {radius} is met but said out of view");
            if may {
                seen += 1;
            } else {
                unseen += 1;
            }
        }
        assert!(seen > 40 && unseen > 40, "the test must see both: {seen} seen, {unseen} not");
    }
}
