use refract::geometry::AccelKind;
use refract::interior::config::{InteriorConfig, SceneKind, SpecularOpacity};
use refract::interior::render_mesh;
use refract::mesh::generate;

fn render(mesh: refract::mesh::Mesh, accel: AccelKind, tweak: impl Fn(&mut InteriorConfig)) -> refract::image_io::Image {
    let mut cfg = refract::params::interior::defaults();
    (cfg.width, cfg.height) = (96, 72);
    cfg.accel = accel;
    tweak(&mut cfg);
    render_mesh(mesh, &cfg).unwrap().image
}

/// A named change to the configuration.
type Setting = (&'static str, fn(&mut InteriorConfig));

#[test]
fn identical_pixels_on_several_meshes_and_settings() {
    let meshes = [
        ("cube", generate::cube().to_mesh()),
        ("dodecahedron", generate::dodecahedron().to_mesh()),
        ("torus", generate::torus(32, 16).to_mesh()),
        ("icosphere", generate::icosphere(4)),
    ];
    let settings: [Setting; 4] = [
        ("default", |_| {}),
        ("trace 6, rotated", |c| {
            c.max_trace = 6;
            c.rot = glam::Vec3::new(25.0, 40.0, 5.0);
        }),
        ("cornell, trace 10, fixed, low ior", |c| {
            c.scene = SceneKind::Cornell;
            c.max_trace = 10;
            c.specular_opacity = SpecularOpacity::Fixed;
            c.ior = 0.5;
        }),
        ("ior 3, light off centre", |c| {
            c.ior = 3.0;
            c.max_trace = 3;
            c.light = Some(glam::Vec3::new(0.3, 0.2, -1.8));
        }),
    ];
    for (name, mesh) in &meshes {
        for (what, tweak) in &settings {
            let a = render(mesh.clone(), AccelKind::Bvh, tweak);
            let b = render(mesh.clone(), AccelKind::Linear, tweak);
            let differing = a.pixels.iter().zip(&b.pixels).filter(|(x, y)| x != y).count();
            assert_eq!(differing, 0, "{name}, {what}: {differing} pixels differ");
            let lit = a.pixels.iter().filter(|p| p.0.max_element() > 0.05).count();
            assert!(lit > 200, "{name}, {what}: the mesh is not in view ({lit} lit pixels)");
        }
    }
}
