//! The two example scenes shipped as glTF in `scenes/gltf/` (written by
//! `refract export prism-table` and `refract export sphere-box`; a test
//! checks the files are the writer's own output): a glass prism on a table
//! under a directional light, and a glass sphere in a box lit from its
//! ceiling.

use super::{matte, rotate_z};
use crate::optics::glass::{self, lines};
use crate::optics::ior::{IorKind, IorModel};
use crate::spectrum::Spectrum;
use crate::world::probe::probe;
use crate::world::{Camera, Emission, Face, Light, Medium, Sphere, Surface, World};
use glam::{DVec2, DVec3};

/// The examples by name, with what each is.
pub const EXAMPLES: &[(&str, &str)] = &[
    ("prism-table", "a 60 degree N-SF11 prism on a table; a 1 cm sunbeam descending 6 degrees through it fans into a spectrum on the table"),
    ("sphere-box", "an N-BK7 sphere in a white box with a red and a green wall, lit by a square lamp in the ceiling: its caustic on the floor"),
];

/// The example `name` at `width` x `height`, if there is one.
pub fn by_name(name: &str, width: usize, height: usize) -> Option<World> {
    match name {
        "prism-table" => Some(prism_table(width, height)),
        "sphere-box" => Some(sphere_box(width, height)),
        _ => None,
    }
}

fn sf11() -> Medium {
    let g = glass::by_name("N-SF11").expect("N-SF11 is in the catalogue");
    Medium::Glass { name: g.name.clone(), ior: IorModel::for_glass(g, IorKind::Sellmeier) }
}

/// A prism on a table, lit by a narrow sunbeam at minimum deviation
/// (docs/physics.md §3) descending 6 degrees, and a dim lamp above.
pub fn prism_table(width: usize, height: usize) -> World {
    let mut w = World::new("prism-table", vec![Medium::Air, sf11()], width, height);
    let (side, tall_z) = (0.08, 0.06);
    let apex = 60f64.to_radians();
    let tall = side * (apex / 2.0).cos();
    let tri = [DVec2::new(-side / 2.0, -tall / 3.0), DVec2::new(side / 2.0, -tall / 3.0), DVec2::new(0.0, 2.0 * tall / 3.0)];
    // A hair above the table: a face in the table's plane would hide it.
    w.add_extruded("prism", &[(tri, 1)], 0.0005, tall_z);
    let n_d = glass::by_name("N-SF11").expect("in the catalogue").sellmeier(lines::LD);
    let incidence = (n_d * (apex / 2.0).sin()).asin();
    let across = rotate_z(DVec3::X, -apex / 2.0 + incidence);
    let descent = 6f64.to_radians();
    let dir = (across * descent.cos() - DVec3::Z * descent.sin()).normalize();
    let mid = (tri[2] + tri[0]) / 2.0;
    let aim = DVec3::new(mid.x, mid.y, tall_z / 2.0);
    let start = aim - dir * 0.35;
    w.probe = (start, dir);
    // Where the d line lands on the table, to frame the camera.
    let d = probe(&w, lines::LD);
    let land = d.exit_point + d.exit_dir * (d.exit_point.z / -d.exit_dir.z.min(-1e-6));
    let centre = (DVec3::new(0.0, 0.0, 0.0) + land) / 2.0;
    matte(&mut w, "table", DVec3::new(-0.6, -0.6, 0.0), DVec3::new(1.2, 0.0, 0.0), DVec3::new(0.0, 1.2, 0.0), [0.78, 0.74, 0.68]);
    let u = DVec3::Z.cross(dir).normalize();
    let v = dir.cross(u);
    w.lights.push(Light {
        name: "sunbeam".into(),
        emission: Emission::Beam { centre: start, dir, u, v, half: DVec2::splat(0.005), disc: true, polarisation: None },
        spectrum: Spectrum::light("D65").expect("D65 is known"),
        power: 1.0,
    });
    w.lights.push(Light {
        name: "lamp above".into(),
        emission: Emission::Point { pos: centre + DVec3::new(-0.2, -0.3, 1.2) },
        spectrum: Spectrum::light("D65").expect("D65 is known"),
        power: 150.0,
    });
    w.photon_shares = Some(vec![0.7, 0.3]);
    w.direct_lighting = true;
    w.bounces = 0;
    let back = (centre - DVec3::new(0.0, 0.0, 0.0)).normalize_or(DVec3::X);
    let eye = centre - DVec3::new(back.x, back.y, 0.0).normalize_or(DVec3::X) * 0.35 + DVec3::new(0.0, 0.0, 0.42);
    w.camera = Camera::look_at(eye, centre, DVec3::Z, 40.0, width, height);
    w.build_accel();
    w
}

/// A glass sphere on the floor of a 1 m box, a square lamp in its ceiling.
pub fn sphere_box(width: usize, height: usize) -> World {
    let bk7 = glass::by_name("N-BK7").expect("N-BK7 is in the catalogue");
    let glass = Medium::Glass { name: bk7.name.clone(), ior: IorModel::for_glass(bk7, IorKind::Sellmeier) };
    let mut w = World::new("sphere-box", vec![Medium::Air, glass], width, height);
    let v = DVec3::new;
    let (white, red, green) = ([0.75; 3], [0.75, 0.12, 0.1], [0.12, 0.55, 0.12]);
    matte(&mut w, "floor", v(-0.5, -0.5, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), white);
    matte(&mut w, "ceiling", v(-0.5, -0.5, 1.0), v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.0), white);
    matte(&mut w, "back wall", v(-0.5, 0.5, 0.0), v(1.0, 0.0, 0.0), v(0.0, 0.0, 1.0), white);
    matte(&mut w, "left wall", v(-0.5, -0.5, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0), red);
    matte(&mut w, "right wall", v(0.5, -0.5, 0.0), v(0.0, 0.0, 1.0), v(0.0, 1.0, 0.0), green);
    let r = 0.16;
    w.spheres.push(Sphere { name: "glass sphere".into(), centre: v(0.08, 0.05, r + 0.001), radius: r, surface: Surface::Interface { front: 0, back: 1 } });
    // The lamp faces down, a little below the ceiling.
    w.faces.push(Face::rect("lamp", v(-0.1, -0.1, 0.995), v(0.0, 0.2, 0.0), v(0.2, 0.0, 0.0), Surface::Emitter { light: 0 }));
    w.lights.push(Light {
        name: "lamp".into(),
        emission: Emission::Area { face: w.faces.len() - 1 },
        spectrum: Spectrum::light("D65").expect("D65 is known"),
        power: 10.0,
    });
    w.maps = w.faces.iter().enumerate().filter(|(_, f)| matches!(f.surface, Surface::Diffuse { .. })).map(|(i, _)| i).collect();
    w.bounces = 3;
    w.direct_lighting = true;
    w.indirect_gather = 6.0;
    w.probe = (v(0.08, 0.05, 0.9), DVec3::NEG_Z);
    w.camera = Camera::look_at(v(0.0, -2.1, 0.44), v(0.0, 0.0, 0.44), DVec3::Z, 27.0, width, height);
    w.build_accel();
    w
}
