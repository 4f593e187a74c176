//! The prism bench's peer, Mitsuba 3, run in the same minutes as refract
//! on the same scene and scored against the same exact image: its
//! particle tracer (`ptracer`; `llvm_ad_spectral` where an LLVM it can
//! use is installed, else `scalar_spectral`), driven by
//! `scripts/mitsuba_prism.py` in the Python environment that
//! `scripts/mitsuba-venv` makes. Mitsuba has no dispersive dielectric, so
//! the glass is a two-term Cauchy fit through the catalogue's n_C and n_F
//! (`IorKind::Cauchy`), rendered one wavelength band at a time, each band
//! a dielectric of the fit's index at the band's centre.

use crate::optics::glass::Glass;
use crate::optics::ior::{IorKind, IorModel};
use crate::spectral::film::XyzImage;
use crate::world::{Emission, Medium, Surface, World};
use std::fmt::Write;
use std::num::{ParseFloatError, ParseIntError};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The script, carried in the binary so that the bench needs no checkout.
const SCRIPT: &str = include_str!("../../scripts/mitsuba_prism.py");

/// Where `scripts/mitsuba-venv` puts the environment by default.
pub const DEFAULT_VENV: &str = ".venv-mitsuba";

/// Wavelength bands a sample per pixel: at s samples per pixel the script
/// renders `BANDS * s` bands of one sample each, the bands finer as s
/// grows (so the image tends to the dispersive one), each an equal share
/// of half the light as the eye weighs it plus half an even spread over
/// 360-830 nm (`bands` in the script).
pub const BANDS: usize = 16;

/// One of Mitsuba's renders: samples per pixel, seconds of its render
/// calls, relative error against the reference.
pub struct PeerRun {
    pub spp: u32,
    pub seconds: f64,
    pub error: f64,
}

/// Why the peer cannot run, or ran and gave no numbers (one line each).
#[derive(Debug, thiserror::Error)]
pub enum PeerError {
    #[error("no Python environment at {} (make it with `bash scripts/mitsuba-venv`)", .0.display())]
    NoEnvironment(PathBuf),
    #[error("cannot run {}: {io}", .python.display())]
    CannotRun { python: PathBuf, io: std::io::Error },
    #[error("{} cannot load Mitsuba's scalar_spectral variant: {why} (make the environment with `bash scripts/mitsuba-venv`)", .python.display())]
    NoVariant { python: PathBuf, why: String },
    #[error("cannot make the temporary folder {}: {io}", .path.display())]
    TempDir { path: PathBuf, io: std::io::Error },
    #[error("running Mitsuba: {0}")]
    Running(std::io::Error),
    /// Mitsuba's last line on its error output.
    #[error("Mitsuba failed: {0}")]
    Failed(String),
    #[error("Mitsuba's script printed `{0}`")]
    Printed(String),
    #[error(transparent)]
    Count(#[from] ParseIntError),
    #[error(transparent)]
    Seconds(#[from] ParseFloatError),
    #[error("Mitsuba's image at {spp} spp has {bytes} bytes, not {expected}")]
    ImageSize { spp: u32, bytes: usize, expected: usize },
    #[error("Mitsuba rendered {got} of {asked} sample counts")]
    Counts { got: usize, asked: usize },
    #[error("the peer's screen must be grey")]
    NotGrey,
    #[error("the peer renders glass and a matte screen only; face {0} is neither")]
    Face(String),
    #[error("the peer needs a matte screen")]
    NoScreen,
    #[error("the peer renders one beam; the scene has {0} lights")]
    Lights(usize),
    #[error("the peer renders a round collimated beam")]
    NotBeam,
    /// The scene's files in the temporary folder.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Fmt(#[from] std::fmt::Error),
}

type Result<T> = std::result::Result<T, PeerError>;

/// Mitsuba, found: the environment's Python and the version it reports.
pub struct Mitsuba {
    python: PathBuf,
    pub version: String,
}

impl Mitsuba {
    /// The Python of the environment `venv` with Mitsuba importable, or
    /// why not (one line): checked before any work.
    pub fn find(venv: &Path) -> Result<Mitsuba> {
        let python = venv.join("bin").join("python");
        if !python.is_file() {
            return Err(PeerError::NoEnvironment(venv.into()));
        }
        let out = Command::new(&python)
            .args(["-c", "import mitsuba as mi; mi.set_variant('scalar_spectral'); print(mi.__version__)"])
            .output()
            .map_err(|io| PeerError::CannotRun { python: python.clone(), io })?;
        if !out.status.success() {
            let why = String::from_utf8_lossy(&out.stderr).lines().next_back().unwrap_or("").to_string();
            return Err(PeerError::NoVariant { python, why });
        }
        Ok(Mitsuba { python, version: String::from_utf8_lossy(&out.stdout).trim().to_string() })
    }

    /// Renders `scene` at each of `spps` samples per pixel (of every band)
    /// and returns (seconds, relative error against `reference`) per
    /// count: the seconds of Mitsuba's render calls alone, as the script
    /// times them; and the variant it ran.
    pub fn error_vs_time(&self, scene: &World, glass: &Glass, spps: &[u32], reference: &XyzImage) -> Result<(String, Vec<PeerRun>)> {
        let dir = TempDir::new()?;
        let script = dir.path().join("mitsuba_prism.py");
        std::fs::write(&script, SCRIPT)?;
        let json = scene_json(scene, glass, dir.path())?;
        let json_path = dir.path().join("scene.json");
        std::fs::write(&json_path, json)?;
        let list = spps.iter().map(u32::to_string).collect::<Vec<_>>().join(",");
        let out = Command::new(&self.python).arg(&script).arg(&json_path).arg(dir.path()).arg(&list).output().map_err(PeerError::Running)?;
        if !out.status.success() {
            let err = String::from_utf8_lossy(&out.stderr);
            return Err(PeerError::Failed(err.lines().rfind(|l| !l.trim().is_empty()).unwrap_or("no message").to_string()));
        }
        let (w, h) = (reference.width, reference.height);
        let mut runs = Vec::new();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let variant = stdout.lines().find_map(|l| l.strip_prefix("mitsuba ")).and_then(|l| l.split_whitespace().nth(1)).unwrap_or("?").to_string();
        for line in stdout.lines().filter(|l| !l.starts_with("mitsuba")) {
            let (spp, secs) = line.split_once(' ').ok_or_else(|| PeerError::Printed(line.to_string()))?;
            let (spp, secs): (u32, f64) = (spp.parse()?, secs.parse()?);
            let bytes = std::fs::read(dir.path().join(format!("xyz-{spp}.f32")))?;
            if bytes.len() != w * h * 12 {
                return Err(PeerError::ImageSize { spp, bytes: bytes.len(), expected: w * h * 12 });
            }
            let v: Vec<f64> = bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64).collect();
            let img = XyzImage { width: w, height: h, xyz: v.chunks_exact(3).map(|p| glam::DVec3::new(p[0], p[1], p[2])).collect() };
            runs.push(PeerRun { spp, seconds: secs, error: crate::spectral::exact::relative_error(&img, reference) });
        }
        if runs.len() != spps.len() {
            return Err(PeerError::Counts { got: runs.len(), asked: spps.len() });
        }
        Ok((variant, runs))
    }
}

/// A folder of this process's own under the system's temporary folder,
/// removed with everything in it when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Result<TempDir> {
        let p = std::env::temp_dir().join(format!("refract-mitsuba-{}", std::process::id()));
        std::fs::create_dir_all(&p).map_err(|io| PeerError::TempDir { path: p.clone(), io })?;
        Ok(TempDir(p))
    }

    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `[x, y, z]` in JSON.
fn v3(v: glam::DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

/// The scene for the script (see its header): the glass's faces and the
/// screen as OBJ files in `dir` (the glass's faces wound so that their
/// normals point into the air, as Mitsuba's dielectric reads them), and
/// the rest as JSON. Refuses a scene that is not one beam, glass and one
/// grey matte screen.
fn scene_json(scene: &World, glass: &Glass, dir: &Path) -> Result<String> {
    let (mut prism, mut screen, mut albedo) = (String::new(), String::new(), None);
    let (mut np, mut ns) = (0, 0);
    for f in &scene.faces {
        let (obj, n, verts) = match f.surface {
            Surface::Interface { front, .. } => {
                let outward = matches!(scene.media[front], Medium::Air);
                (&mut prism, &mut np, if outward { f.verts.clone() } else { f.verts.iter().rev().copied().collect() })
            }
            Surface::Diffuse { albedo: a, .. } => {
                albedo = Some(a.rgb[1]);
                if !a.rgb.iter().all(|&c| c == a.rgb[0]) {
                    return Err(PeerError::NotGrey);
                }
                (&mut screen, &mut ns, f.verts.clone())
            }
            _ => return Err(PeerError::Face(f.name.clone())),
        };
        for v in &verts {
            writeln!(obj, "v {:?} {:?} {:?}", v.x, v.y, v.z)?;
        }
        // A convex polygon as a fan of triangles.
        for k in 1..verts.len() - 1 {
            writeln!(obj, "f {} {} {}", *n + 1, *n + k + 1, *n + k + 2)?;
        }
        *n += verts.len();
    }
    let albedo = albedo.ok_or(PeerError::NoScreen)?;
    let [light] = &scene.lights[..] else { return Err(PeerError::Lights(scene.lights.len())) };
    let Emission::Beam { centre, dir: beam_dir, v, half, disc: true, .. } = light.emission else { return Err(PeerError::NotBeam) };
    let IorModel::Cauchy { a, b_um2 } = IorModel::for_glass(glass, IorKind::Cauchy) else { unreachable!("IorKind::Cauchy makes a Cauchy model") };
    let nm: Vec<f64> = (360..=830).map(f64::from).collect();
    let values: Vec<f64> = nm.iter().map(|&l| light.spectrum.eval(l)).collect();
    // The light as the eye weighs it, which the script's bands share out.
    let weight: Vec<f64> = nm.iter().zip(&values).map(|(&l, s)| s * crate::spectrum::cie::cmf(l).element_sum()).collect();
    let (prism_obj, screen_obj) = (dir.join("prism.obj"), dir.join("screen.obj"));
    std::fs::write(&prism_obj, prism)?;
    std::fs::write(&screen_obj, screen)?;
    let cam = &scene.camera;
    let list = |v: &[f64]| v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ");
    Ok(format!(
        "{{\"width\": {}, \"height\": {}, \"max_depth\": 16, \"albedo\": {albedo:?},\n\"prism_obj\": {:?}, \"screen_obj\": {:?},\n\"camera\": {{\"pos\": {}, \"target\": {}, \"up\": {}, \"vfov_deg\": {:?}}},\n\"beam\": {{\"centre\": {}, \"dir\": {}, \"up\": {}, \"radius\": {:?}}},\n\"cauchy\": {{\"a\": {a:?}, \"b_um2\": {b_um2:?}}},\n\"spectrum\": {{\"nm\": [{}], \"values\": [{}], \"weight\": [{}]}},\n\"bands\": {BANDS}}}\n",
        cam.width,
        cam.height,
        prism_obj.display().to_string(),
        screen_obj.display().to_string(),
        v3(cam.pos),
        v3(cam.pos + cam.forward),
        v3(cam.up),
        cam.vfov.to_degrees(),
        v3(centre),
        v3(beam_dir),
        v3(v),
        half.x,
        list(&nm),
        list(&values),
        list(&weight)
    ))
}
