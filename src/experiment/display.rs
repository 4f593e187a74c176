//! The display transforms side by side: four photograph-like figures, each
//! rendered once (from its own scene file, at its quick size and its own
//! exposure) and shown five ways, clipped, desaturated, through the
//! filmic AgX curve, through AgX with its print look (docs/physics.md §23)
//! and as a camera's sensor and print would show it (§25), so a reader can see what each
//! does to a spectrum: `results/display/transforms.png` in the gallery.

use super::error::Result;
use super::labels::{draw, Label};
use super::scene_file::SceneFile;
use crate::image_io::write_rgb8;
use crate::spectrum::cie::GamutMap;
use std::path::Path;

/// The figures compared: the lamp's lines, the bench's strip, the album
/// cover's fan and the laser's spectrum on a wall.
pub const FIGURES: [&str; 4] = ["css552-p1", "css552-p5", "pm-dark-side", "pm-laser-prism"];
const MAPS: [GamutMap; 5] = [GamutMap::Clip, GamutMap::Desaturate, GamutMap::Agx, GamutMap::AgxPunchy, GamutMap::Camera];
/// Each tile's width in pixels (heights follow the figures' aspects).
const TILE: usize = 272;

/// Renders the comparison into `png`; the figures' scene files are in
/// `scenes`.
pub fn write(png: &Path, scenes: &Path) -> Result<()> {
    let mut rows: Vec<(usize, Vec<Vec<u8>>)> = Vec::new();
    for id in FIGURES {
        let file = SceneFile::load(&scenes.join(format!("{id}.toml")), true)?;
        let mut cfg = super::params::prism_config(&file.params)?;
        let (w, h) = (cfg.scene.width, cfg.scene.height);
        let th = (TILE * h / w).max(1);
        (cfg.scene.width, cfg.scene.height) = (TILE, th);
        let r = crate::spectral::render_config(&cfg, &crate::progress::Silent)?;
        let tiles = MAPS.iter().map(|map| r.render.image.to_srgb8(r.exposure, *map)).collect();
        rows.push((th, tiles));
    }
    let head = 24;
    let (w, h) = (TILE * MAPS.len(), head + rows.iter().map(|(th, _)| th).sum::<usize>());
    let mut buf = vec![0u8; w * h * 3];
    let mut y0 = head;
    for (th, tiles) in &rows {
        for (k, tile) in tiles.iter().enumerate() {
            for y in 0..*th {
                let dst = ((y0 + y) * w + k * TILE) * 3;
                buf[dst..dst + TILE * 3].copy_from_slice(&tile[y * TILE * 3..(y + 1) * TILE * 3]);
            }
        }
        y0 += th;
    }
    let labels: Vec<Label> = MAPS
        .iter()
        .enumerate()
        .map(|(k, map)| Label { text: format!("--gamut {}", map.name()), at: [(k as f64 + 0.5) / MAPS.len() as f64, 12.0 / h as f64] })
        .collect();
    draw(&mut buf, w, h, &labels)?;
    Ok(write_rgb8(png, w, h, &buf)?)
}
