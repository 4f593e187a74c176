//! `refract prism trace`: one ray per wavelength through the scene's prism
//! with the renderer's own optics, always taking the transmitted branch,
//! until it is back in air: exit direction, signed deviation and the
//! Fresnel transmittance (prod Ts + prod Tp) / 2 along the way.

use super::interface::cross;
use super::{Surface, World};
use crate::optics::fresnel::train_transmittance;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct ProbeRay {
    pub nm: f64,
    /// Where the ray leaves the last glass face (or its start, with no prism).
    pub exit_point: DVec3,
    pub exit_dir: DVec3,
    /// Angle from the entry direction to the exit direction in the xy plane,
    /// degrees, counter-clockwise positive (toward +y, the crown apices).
    pub deviation_deg: f64,
    pub transmittance: f64,
    /// Total internal reflection stopped the ray inside the glass.
    pub tir: bool,
    /// Faces crossed.
    pub faces: usize,
    /// The points the ray went through: its start, each crossing.
    pub path: Vec<DVec3>,
}

/// The scene's probe ray (`World::probe`) at wavelength `nm`.
pub fn probe(scene: &World, nm: f64) -> ProbeRay {
    probe_ray(scene, scene.probe.0, scene.probe.1, nm)
}

/// Any ray from `o` along `d0` at wavelength `nm`, until it is back in air.
pub fn probe_ray(scene: &World, o: DVec3, d0: DVec3, nm: f64) -> ProbeRay {
    let mut o = o;
    let mut d = d0;
    let mut crossed = Vec::new();
    let mut medium = 0;
    let mut skip = None;
    let mut faces = 0;
    let mut tir = false;
    let mut path = vec![o];
    for _ in 0..64 {
        let Some(hit) = scene.intersect(o, d, skip) else { break };
        if !matches!(scene.surface(hit.face), Surface::Interface { .. }) {
            break;
        }
        o += hit.t * d;
        path.push(o);
        let c = cross(scene, hit.face, o, d, Some(nm)).expect("a wavelength is given");
        debug_assert_eq!(c.from, medium, "media must be consistent along the ray");
        skip = Some(hit.face);
        faces += 1;
        match c.refracted {
            Some(t) => {
                crossed.push(c.fresnel);
                d = t;
                medium = c.to;
            }
            None => {
                tir = true;
                break;
            }
        }
        if medium == 0 {
            break;
        }
    }
    let angle = |v: DVec3| v.y.atan2(v.x);
    let mut dev = (angle(d) - angle(d0)).to_degrees();
    if dev > 180.0 {
        dev -= 360.0;
    } else if dev <= -180.0 {
        dev += 360.0;
    }
    ProbeRay { nm, exit_point: o, exit_dir: d, deviation_deg: dev, transmittance: if tir { 0.0 } else { train_transmittance(&crossed) }, tir, faces, path }
}
