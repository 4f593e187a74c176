//! Intel Embree 3 as a third back-end, for `refract bench interior` only:
//! the same triangles and the same rays as the BVH, through Embree's
//! single-ray API (`rtcIntersect1`), so the two rates and hit counts can be
//! compared on one machine in one run. Built with `--features embree`
//! (Debian: `apt-get install libembree-dev`); nothing else depends on it.
//!
//! The C declarations follow `/usr/include/embree3/rtcore_*.h` (3.13).

use super::{Hit, Ray, Triangle};
use std::ffi::{c_char, c_void, CStr};

#[repr(C)]
struct RtcDevice(c_void);
#[repr(C)]
struct RtcScene(c_void);
#[repr(C)]
struct RtcGeometry(c_void);

const RTC_GEOMETRY_TYPE_TRIANGLE: u32 = 0;
const RTC_BUFFER_TYPE_INDEX: u32 = 0;
const RTC_BUFFER_TYPE_VERTEX: u32 = 1;
const RTC_FORMAT_UINT3: u32 = 0x5003;
const RTC_FORMAT_FLOAT3: u32 = 0x9003;
const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;
const RTC_DEVICE_PROPERTY_VERSION: u32 = 0;
const RTC_SCENE_FLAG_ROBUST: u32 = 1 << 2;

/// Embree's scene mode (`rtcSetSceneFlags`).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum EmbreeMode {
    /// No flags: Embree's fastest traversal (its slab test, for one, is a
    /// fused multiply-subtract on a precomputed `origin / direction`,
    /// which is not conservative).
    Default,
    /// `RTC_SCENE_FLAG_ROBUST`: "avoids optimizations that reduce
    /// arithmetic accuracy ... for avoiding artifacts caused by rays
    /// shooting through edges of neighboring primitives" (rtcSetSceneFlags(3)):
    /// the BVH's kind of test (its boxes never lose a hit its triangle
    /// test would find).
    Robust,
}

/// `struct RTCIntersectContext` with RTC_MAX_INSTANCE_LEVEL_COUNT 1 and
/// RTC_MIN_WIDTH 0 (Debian's build).
#[repr(C)]
struct IntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [u32; 1],
}

/// `struct RTCRayHit` (RTCRay then RTCHit, each 16-byte aligned).
#[repr(C, align(16))]
struct RayHit {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[link(name = "embree3")]
extern "C" {
    fn rtcNewDevice(config: *const c_char) -> *mut RtcDevice;
    fn rtcReleaseDevice(device: *mut RtcDevice);
    fn rtcGetDeviceProperty(device: *mut RtcDevice, prop: u32) -> isize;
    fn rtcGetDeviceError(device: *mut RtcDevice) -> u32;
    fn rtcNewScene(device: *mut RtcDevice) -> *mut RtcScene;
    fn rtcReleaseScene(scene: *mut RtcScene);
    fn rtcCommitScene(scene: *mut RtcScene);
    fn rtcSetSceneFlags(scene: *mut RtcScene, flags: u32);
    fn rtcNewGeometry(device: *mut RtcDevice, kind: u32) -> *mut RtcGeometry;
    fn rtcSetNewGeometryBuffer(geometry: *mut RtcGeometry, kind: u32, slot: u32, format: u32, stride: usize, count: usize) -> *mut c_void;
    fn rtcCommitGeometry(geometry: *mut RtcGeometry);
    fn rtcAttachGeometry(scene: *mut RtcScene, geometry: *mut RtcGeometry) -> u32;
    fn rtcReleaseGeometry(geometry: *mut RtcGeometry);
    fn rtcIntersect1(scene: *mut RtcScene, context: *mut IntersectContext, rayhit: *mut RayHit);
}

/// Why Embree could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum EmbreeError {
    #[error("Embree: rtcNewDevice failed (error code {0})")]
    Device(u32),
    #[error("Embree: building the scene failed (error code {0})")]
    Build(u32),
}

/// One Embree device and a scene of one triangle mesh.
pub struct Embree {
    device: *mut RtcDevice,
    scene: *mut RtcScene,
}

// Embree's committed scenes are safe to trace from any thread.
unsafe impl Send for Embree {}
unsafe impl Sync for Embree {}

impl Embree {
    /// Embree's version, e.g. "3.13.5".
    pub fn version() -> String {
        // SAFETY: a device made and released here; a null config is allowed.
        unsafe {
            let d = rtcNewDevice(std::ptr::null());
            if d.is_null() {
                return "unknown".into();
            }
            let v = rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION);
            rtcReleaseDevice(d);
            format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
        }
    }

    /// Builds Embree's BVH over `tris` (ids in the same order) on `threads`
    /// threads with its default (medium) build quality, in `mode`.
    pub fn build(tris: &[Triangle], threads: usize, mode: EmbreeMode) -> Result<Embree, EmbreeError> {
        let config = format!("threads={threads}\0");
        let config = CStr::from_bytes_with_nul(config.as_bytes()).expect("one nul at the end");
        // SAFETY: every pointer comes from Embree and is checked for null;
        // the buffers Embree hands out are written within their stated sizes
        // (3 floats per vertex, 3 indices per triangle).
        unsafe {
            let device = rtcNewDevice(config.as_ptr());
            if device.is_null() {
                return Err(EmbreeError::Device(rtcGetDeviceError(std::ptr::null_mut())));
            }
            let scene = rtcNewScene(device);
            if !scene.is_null() && mode == EmbreeMode::Robust {
                rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
            }
            let geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
            let n = tris.len();
            let verts = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 3 * n) as *mut f32;
            let index = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, n) as *mut u32;
            if scene.is_null() || geom.is_null() || verts.is_null() || index.is_null() {
                let e = rtcGetDeviceError(device);
                if !geom.is_null() {
                    rtcReleaseGeometry(geom);
                }
                if !scene.is_null() {
                    rtcReleaseScene(scene);
                }
                rtcReleaseDevice(device);
                return Err(EmbreeError::Build(e));
            }
            let verts = std::slice::from_raw_parts_mut(verts, 9 * n);
            let index = std::slice::from_raw_parts_mut(index, 3 * n);
            for (i, t) in tris.iter().enumerate() {
                for (k, v) in t.vertices().iter().enumerate() {
                    verts[9 * i + 3 * k..9 * i + 3 * k + 3].copy_from_slice(&v.to_array());
                    index[3 * i + k] = (3 * i + k) as u32;
                }
            }
            rtcCommitGeometry(geom);
            rtcAttachGeometry(scene, geom);
            rtcReleaseGeometry(geom);
            rtcCommitScene(scene);
            let e = rtcGetDeviceError(device);
            if e != 0 {
                rtcReleaseScene(scene);
                rtcReleaseDevice(device);
                return Err(EmbreeError::Build(e));
            }
            Ok(Embree { device, scene })
        }
    }

    /// The nearest hit of `ray` (one ray through `rtcIntersect1`).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut context = IntersectContext { flags: 0, filter: std::ptr::null(), inst_id: [RTC_INVALID_GEOMETRY_ID] };
        let mut rh = RayHit {
            org: ray.origin.to_array(),
            tnear: ray.t_min,
            dir: ray.dir.to_array(),
            time: 0.0,
            tfar: ray.t_max,
            mask: u32::MAX,
            id: 0,
            flags: 0,
            ng: [0.0; 3],
            u: 0.0,
            v: 0.0,
            prim_id: RTC_INVALID_GEOMETRY_ID,
            geom_id: RTC_INVALID_GEOMETRY_ID,
            inst_id: [RTC_INVALID_GEOMETRY_ID],
        };
        // SAFETY: a committed scene, a context and a ray laid out as Embree's.
        unsafe { rtcIntersect1(self.scene, &mut context, &mut rh) };
        (rh.geom_id != RTC_INVALID_GEOMETRY_ID).then_some(Hit { t: rh.tfar, tri: rh.prim_id, u: rh.u, v: rh.v })
    }
}

impl Drop for Embree {
    fn drop(&mut self) {
        // SAFETY: made in `build`, released once.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Accel, AccelKind};
    use glam::Vec3;

    /// Embree and the BVH find the same triangle at the same distance for
    /// rays at a closed mesh from outside and from inside.
    #[test]
    fn embree_finds_the_bvhs_hits() {
        let mesh = crate::mesh::generate::icosphere(3);
        let tris: Vec<Triangle> =
            mesh.triangles.iter().map(|f| Triangle::new(mesh.positions[f[0] as usize], mesh.positions[f[1] as usize], mesh.positions[f[2] as usize])).collect();
        let bvh = Accel::build(AccelKind::Bvh, &tris);
        for mode in [EmbreeMode::Default, EmbreeMode::Robust] {
            let e = Embree::build(&tris, 1, mode).unwrap();
            let mut rng = crate::sampling::Rng::new(3, 0, 0);
            let (mut same, mut hits) = (0, 0);
            for k in 0..2000 {
                let o = if k % 2 == 0 { 3.0 * crate::photon::emit::uniform_sphere(rng.f64(), rng.f64()).as_vec3() } else { Vec3::ZERO };
                // From outside, aimed at points within the sphere's radius of its centre.
                let d = (crate::photon::emit::uniform_sphere(rng.f64(), rng.f64()).as_vec3() * 0.9 - o).normalize();
                let r = Ray::new(o, d);
                let (a, b) = (bvh.intersect(&r), e.intersect(&r));
                assert_eq!(a.is_some(), b.is_some(), "{mode:?}: ray {k}");
                if let (Some(a), Some(b)) = (a, b) {
                    hits += 1;
                    same += (a.tri == b.tri) as u32;
                    assert!((a.t - b.t).abs() < 1e-4 * a.t.max(1.0), "ray {k}: {} vs {}", a.t, b.t);
                }
            }
            assert!(hits > 1500, "{mode:?}: {hits}");
            assert!(same as f64 >= 0.99 * hits as f64, "{mode:?}: {same} of {hits}");
        }
    }
}
