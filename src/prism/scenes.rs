//! The prism scenes of report 000 (and the single-prism anchor), built in
//! code. Units are metres; light travels along +x in the xy plane, where
//! the dispersion happens; prisms are extruded along z.
//!
//! - `amici-screen`: a white slit beam (2 mm x 2 cm) through an Amici prism
//!   onto a matte screen 2 m away: the rainbow strip (report 000, Picture 5;
//!   `--no-prism` gives Picture 4, `--no-dispersion` Picture 6).
//! - `amici-lamp`: the camera looks through the Amici prism at a fluorescent
//!   tube 1 m away: one image of the tube per spectral line (Picture 1).
//! - `single-prism`: a 60 degree prism, a 2 cm round beam, a screen 4 m
//!   behind, perpendicular to the d line (the anchor scene of the issue).

use super::amici::{cross_sections, solve_crown_apex, DESIGN_NM};
use super::probe::probe;
use super::scene::{Camera, Emission, Face, Light, Medium, PrismScene, Surface};
use crate::optics::glass::{self, lines};
use crate::optics::ior::{IorKind, IorModel};
use crate::spectrum::Spectrum;
use anyhow::{bail, Result};
use glam::{DVec2, DVec3};

#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SceneKind {
    /// Report 000: a white slit beam through an Amici prism onto a screen.
    AmiciScreen,
    /// Report 000: a fluorescent tube seen through an Amici prism.
    AmiciLamp,
    /// The anchor: a 60 degree prism, a 2 cm beam, a screen 4 m behind.
    SinglePrism,
    /// Report 001: a glass sphere before a spherical black-body light, off centre.
    SphereArealight,
    /// Report 001: a glass sphere before a polished metal plate reflecting a warm light.
    SphereMetal,
    /// Report 001's final image: glass spheres before a bright bar light.
    SpheresFinal,
    /// Report 003: a point light and a glass prism in a Cornell box (a faint rainbow).
    CornellPointlight,
    /// Report 003: the point light at the end of a mirror tube (a brighter rainbow).
    CornellMirrorTube,
    /// Report 003: a laser into a glass prism in a Cornell box.
    CornellLaser,
    /// Report 003's album-cover remake: a white beam through a prism fanning into a spectrum.
    DarkSide,
}

impl SceneKind {
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::AmiciScreen => "amici-screen",
            SceneKind::AmiciLamp => "amici-lamp",
            SceneKind::SinglePrism => "single-prism",
            SceneKind::SphereArealight => "sphere-arealight",
            SceneKind::SphereMetal => "sphere-metal",
            SceneKind::SpheresFinal => "spheres-final",
            SceneKind::CornellPointlight => "cornell-pointlight",
            SceneKind::CornellMirrorTube => "cornell-mirror-tube",
            SceneKind::CornellLaser => "cornell-laser",
            SceneKind::DarkSide => "dark-side",
        }
    }
}

/// Everything that shapes a scene.
#[derive(Clone, Debug)]
pub struct SceneOptions {
    pub kind: SceneKind,
    /// Crown glass (the single prism's glass).
    pub crown: String,
    pub flint: String,
    pub flint_apex_deg: f64,
    pub ior: IorKind,
    /// Light spectrum name (see `Spectrum::light`); `None` = the scene's own.
    pub light: Option<String>,
    /// Angle of incidence on the first face, degrees; `None` = the design
    /// (Amici: along the axis; single prism: minimum deviation at d).
    pub incidence_deg: Option<f64>,
    pub no_prism: bool,
    pub no_dispersion: bool,
    /// A user's OBJ mesh (metres) of `crown` glass in place of the prism.
    pub obj: Option<std::path::PathBuf>,
    pub width: usize,
    pub height: usize,
}

impl SceneOptions {
    pub fn new(kind: SceneKind) -> Self {
        SceneOptions {
            kind,
            crown: "N-BK7".into(),
            flint: "N-SF11".into(),
            flint_apex_deg: 90.0,
            ior: IorKind::Sellmeier,
            light: None,
            incidence_deg: None,
            no_prism: false,
            no_dispersion: false,
            obj: None,
            width: 640,
            height: 240,
        }
    }
}

pub(crate) fn glass_medium(name: &str, kind: IorKind, no_dispersion: bool) -> Result<Medium> {
    let g = glass::by_name(name)?;
    let kind = if no_dispersion { IorKind::Constant } else { kind };
    Ok(Medium::Glass { name: g.name.clone(), ior: IorModel::for_glass(g, kind) })
}

pub(crate) fn rotate_z(v: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// Builds the scene the options describe.
pub fn build(o: &SceneOptions) -> Result<PrismScene> {
    if o.width == 0 || o.height == 0 {
        bail!("--size: width and height must be at least 1");
    }
    let mut scene = match o.kind {
        SceneKind::AmiciScreen | SceneKind::AmiciLamp => amici(o)?,
        SceneKind::SinglePrism => single_prism(o)?,
        SceneKind::SphereArealight | SceneKind::SphereMetal | SceneKind::SpheresFinal => super::scenes_extra::spheres(o)?,
        SceneKind::CornellPointlight | SceneKind::CornellMirrorTube | SceneKind::CornellLaser => super::scenes_extra::cornell(o)?,
        SceneKind::DarkSide => super::scenes_extra::dark_side(o)?,
    };
    if let Some(path) = &o.obj {
        // The user's mesh replaces the prism; beam, screen and camera stay
        // where the built-in prism put them.
        let mesh = crate::mesh::obj::read_obj(path)?;
        let keep: Vec<Face> = scene.faces.drain(..).filter(|f| !matches!(f.surface, Surface::Interface { .. })).collect();
        for (i, t) in mesh.triangles.iter().enumerate() {
            let v: Vec<DVec3> = t.iter().map(|&k| mesh.positions[k as usize].as_dvec3()).collect();
            let n = (v[1] - v[0]).cross(v[2] - v[0]);
            scene.faces.push(Face::polygon(&format!("obj triangle {i}"), v, n, Surface::Interface { front: 0, back: 1 }));
        }
        scene.faces.extend(keep);
        reindex(&mut scene);
    }
    if o.no_prism {
        scene.faces.retain(|f| !matches!(f.surface, Surface::Interface { .. }));
        reindex(&mut scene);
    }
    Ok(scene)
}

/// After faces were removed or added: the matte-surface list and the area
/// lights' face indices follow the faces.
fn reindex(scene: &mut PrismScene) {
    scene.maps = scene.faces.iter().enumerate().filter(|(_, f)| matches!(f.surface, Surface::Diffuse { .. })).map(|(i, _)| i).collect();
    for (li, l) in scene.lights.iter_mut().enumerate() {
        if let Emission::Area { face } = &mut l.emission {
            *face = scene.faces.iter().position(|f| f.surface == Surface::Emitter { light: li }).expect("each area light keeps its face");
        }
    }
}

pub(crate) fn light_spectrum(o: &SceneOptions, default: &str) -> Result<Spectrum> {
    Ok(Spectrum::light(o.light.as_deref().unwrap_or(default))?)
}

fn amici(o: &SceneOptions) -> Result<PrismScene> {
    let crown = glass_medium(&o.crown, o.ior, o.no_dispersion)?;
    let flint = glass_medium(&o.flint, o.ior, o.no_dispersion)?;
    // The prism is designed from the catalogue (Sellmeier), whatever model
    // the renderer then uses for its index.
    let (nc, nf) = (glass::by_name(&o.crown)?.sellmeier(DESIGN_NM), glass::by_name(&o.flint)?.sellmeier(DESIGN_NM));
    if !(0.0 < o.flint_apex_deg && o.flint_apex_deg < 180.0) {
        bail!("--flint-apex: {} degrees is not between 0 and 180", o.flint_apex_deg);
    }
    let a2 = o.flint_apex_deg.to_radians();
    let Some(a1) = solve_crown_apex(nc, nf, a2) else {
        bail!(
            "--flint-apex: no crown apex makes {} / {} direct-vision with a {} degree flint (the cemented face would reflect totally)",
            o.crown,
            o.flint,
            o.flint_apex_deg
        );
    };
    let height = 0.03;
    let [left, mid, right] = cross_sections(a1, a2, height);
    let mut scene = PrismScene::new(o.kind.name(), vec![Medium::Air, crown, flint], o.width, o.height);
    scene.add_extruded("amici", &[(left, 1), (mid, 2), (right, 1)], -0.015, 0.015);
    // Incidence on the entry face, whose inward normal is at h - a1 from +x.
    let h = a2 / 2.0;
    let design_incidence = a1 - h;
    let incidence = o.incidence_deg.map_or(design_incidence, f64::to_radians);
    let dir = rotate_z(DVec3::X, h - a1 + incidence);
    // Aim the beam at the middle of the entry face.
    let entry_mid = (left[0] + left[1]) / 2.0;
    let start = DVec3::new(entry_mid.x, entry_mid.y, 0.0) - dir * 0.3;
    scene.probe = (start, dir);
    // Screen and camera are placed from the glasses' Sellmeier dispersion
    // whatever index model is chosen, so --no-prism, --no-dispersion and
    // every model frame the same view (report 000's Pictures 4, 5 and 6).
    let mut design = scene.clone();
    design.media = vec![Medium::Air, glass_medium(&o.crown, IorKind::Sellmeier, false)?, glass_medium(&o.flint, IorKind::Sellmeier, false)?];
    let exits = |nm: f64| probe(&design, nm);
    let d_line = exits(DESIGN_NM);
    if d_line.tir {
        bail!("--incidence: at {:.3} degrees the d line is totally reflected inside the prism", incidence.to_degrees());
    }
    match o.kind {
        SceneKind::AmiciScreen => {
            // Screen 2 m past the prism, across the strip from 400 to 700 nm.
            let dist = 2.0;
            let land = |nm: f64| {
                let p = exits(nm);
                p.exit_point + p.exit_dir * ((d_line.exit_point.x + dist - p.exit_point.x) / p.exit_dir.x.max(1e-9))
            };
            let (a, b) = (land(400.0), land(700.0));
            let centre = (a + b) / 2.0;
            let width = ((a.y - b.y).abs() * 1.4).max(0.1);
            let tall = width * o.height as f64 / o.width as f64;
            // Normal -x (facing the prism), u along +y, v along +z... wound so u x v = -x.
            let corner = centre + DVec3::new(0.0, width / 2.0, -tall / 2.0);
            scene.faces.push(Face::rect(
                "screen",
                corner,
                DVec3::new(0.0, -width, 0.0),
                DVec3::new(0.0, 0.0, tall),
                Surface::Diffuse { albedo: [0.8; 3], map: 0 },
            ));
            scene.maps.push(scene.faces.len() - 1);
            let cam = centre - DVec3::X * 1.0;
            let vfov = 2.0 * ((tall / 2.0) / 1.0).atan().to_degrees();
            scene.camera = Camera::look_at(cam, centre, DVec3::Z, vfov, o.width, o.height);
            let u = rotate_z(DVec3::Y, h - a1 + incidence);
            scene.lights.push(Light {
                name: "beam".into(),
                emission: Emission::Beam { centre: start, dir, u, v: DVec3::Z, half: DVec2::new(0.001, 0.01), disc: false },
                spectrum: light_spectrum(o, "D65")?,
                power: 1.0,
            });
        }
        _ => {
            // A fluorescent tube 1 m past the prism, seen through it.
            let lamp_x = d_line.exit_point.x + 1.0;
            let (w, tall) = (0.008, 0.12);
            let corner = DVec3::new(lamp_x, -w / 2.0, -tall / 2.0);
            scene.faces.push(Face::rect("lamp", corner, DVec3::new(0.0, 0.0, tall), DVec3::new(0.0, w, 0.0), Surface::Emitter { light: 0 }));
            scene.lights.push(Light {
                name: "cfl tube".into(),
                emission: Emission::Area { face: scene.faces.len() - 1 },
                spectrum: light_spectrum(o, "cfl-lines")?,
                power: 1.0,
            });
            // The camera sits just before the entry face, looking back the
            // way light from the lines between 404 and 700 nm arrives.
            let mid_dev = (exits(404.0).deviation_deg + exits(700.0).deviation_deg) / 2.0;
            let cam = DVec3::new(left[1].x - 0.03, 0.0, 0.0);
            let look = rotate_z(DVec3::X, (-mid_dev).to_radians());
            let hfov = 11.0f64.to_radians();
            let vfov = 2.0 * ((hfov / 2.0).tan() * o.height as f64 / o.width as f64).atan();
            scene.camera = Camera::look_at(cam, cam + look, DVec3::Z, vfov.to_degrees(), o.width, o.height);
            scene.probe = (cam, DVec3::X);
        }
    }
    Ok(scene)
}

fn single_prism(o: &SceneOptions) -> Result<PrismScene> {
    let g = glass_medium(&o.crown, o.ior, o.no_dispersion)?;
    let apex = 60f64.to_radians();
    let side = 0.05;
    let tall = side * (apex / 2.0).cos();
    let c = tall / 3.0;
    let tri = [DVec2::new(-side / 2.0, -c), DVec2::new(side / 2.0, -c), DVec2::new(0.0, tall - c)];
    let mut scene = PrismScene::new(o.kind.name(), vec![Medium::Air, g], o.width, o.height);
    scene.add_extruded("prism", &[(tri, 1)], -0.025, 0.025);
    // Placed from the catalogue (Sellmeier) whatever index model renders it.
    let n_d = glass::by_name(&o.crown)?.sellmeier(lines::LD);
    let min_dev_incidence = (n_d * (apex / 2.0).sin()).asin();
    let incidence = o.incidence_deg.map_or(min_dev_incidence, f64::to_radians);
    // The left face's inward normal points at -apex/2 from +x.
    let dir = rotate_z(DVec3::X, -apex / 2.0 + incidence);
    let face_mid = (tri[2] + tri[0]) / 2.0;
    let start = DVec3::new(face_mid.x, face_mid.y, 0.0) - dir * 0.3;
    scene.probe = (start, dir);
    let mut design = scene.clone();
    design.media[1] = glass_medium(&o.crown, IorKind::Sellmeier, false)?;
    let d_line = probe(&design, lines::LD);
    if d_line.tir {
        bail!("--incidence: at {:.3} degrees the d line is totally reflected inside the prism", incidence.to_degrees());
    }
    let out = d_line.exit_dir;
    let centre = d_line.exit_point + out * 4.0;
    let (width, high) = (0.24, 0.24 * o.height as f64 / o.width as f64);
    let u = out.cross(DVec3::Z).normalize(); // in the xy plane, across the strip
    let corner = centre - u * (width / 2.0) - DVec3::Z * (high / 2.0);
    // Normal u x z = -out: facing the prism.
    scene.faces.push(Face::rect("screen", corner, u * width, DVec3::Z * high, Surface::Diffuse { albedo: [0.8; 3], map: 0 }));
    scene.maps.push(scene.faces.len() - 1);
    let cam = centre - out * 1.0;
    let vfov = 2.0 * ((high / 2.0) / 1.0).atan().to_degrees();
    scene.camera = Camera::look_at(cam, centre, DVec3::Z, vfov, o.width, o.height);
    let bu = DVec3::Z.cross(dir).normalize();
    scene.lights.push(Light {
        name: "beam".into(),
        emission: Emission::Beam { centre: start, dir, u: bu, v: DVec3::Z, half: DVec2::new(0.01, 0.01), disc: true },
        spectrum: light_spectrum(o, "D65")?,
        power: 1.0,
    });
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_build_with_consistent_faces() {
        for kind in [SceneKind::AmiciScreen, SceneKind::AmiciLamp, SceneKind::SinglePrism] {
            let s = build(&SceneOptions::new(kind)).unwrap();
            // Amici: 3 parts x 3 sides - 2 cemented + 6 caps = 13; single: 5.
            let interfaces = s.faces.iter().filter(|f| matches!(f.surface, Surface::Interface { .. })).count();
            assert_eq!(interfaces, if kind == SceneKind::SinglePrism { 5 } else { 13 }, "{kind:?}");
            let mut o = SceneOptions::new(kind);
            o.no_prism = true;
            let s = build(&o).unwrap();
            assert!(s.faces.iter().all(|f| !matches!(f.surface, Surface::Interface { .. })));
        }
        let mut o = SceneOptions::new(SceneKind::AmiciScreen);
        o.flint_apex_deg = 150.0;
        assert!(build(&o).unwrap_err().to_string().contains("--flint-apex"));
        o.flint_apex_deg = 90.0;
        o.flint = "unobtainium".into();
        assert!(build(&o).unwrap_err().to_string().contains("unknown glass"));
    }
}
