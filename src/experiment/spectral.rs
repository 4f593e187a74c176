//! The accuracy table behind reports 001 and 003's choices: every IOR
//! model's n(lambda) against Sellmeier for a glass, and every
//! wavelength-to-colour map against CIE, as CSVs and plots.

use super::error::Result;
use super::plot::{colour_strips, render, LineChart, Series, PALETTE};
use crate::image_io::write_text;
use crate::optics::glass::Glass;
use crate::optics::ior::{IorKind, IorModel};
use crate::spectrum::cie::srgb_encode;
use crate::spectrum::colormap::{error_vs_cie, ColorMap};
use crate::timing::cell;
use std::fmt::Write;
use std::path::Path;

/// Largest and RMS error of one IOR model against Sellmeier.
pub struct IorError {
    pub model: IorKind,
    pub max_abs_380_780: f64,
    pub max_abs_400_700: f64,
    pub rms_380_780: f64,
}

pub fn ior_errors(glass: &Glass) -> Vec<IorError> {
    IorKind::ALL
        .iter()
        .map(|&kind| {
            let m = IorModel::for_glass(glass, kind);
            let err = |l: f64| (m.n(l) - glass.sellmeier(l)).abs();
            let all: Vec<f64> = (380..=780).map(|l| err(l as f64)).collect();
            IorError {
                model: kind,
                max_abs_380_780: all.iter().copied().fold(0.0, f64::max),
                max_abs_400_700: (400..=700).map(|l| err(l as f64)).fold(0.0, f64::max),
                rms_380_780: (all.iter().map(|e| e * e).sum::<f64>() / all.len() as f64).sqrt(),
            }
        })
        .collect()
}

/// Mean and largest colour error of one map against CIE over 400-700 nm.
pub struct MapSummary {
    pub map: ColorMap,
    pub mean_delta_e: f64,
    pub max_delta_e: f64,
    pub mean_hue_deg: f64,
}

pub fn map_summaries() -> Vec<MapSummary> {
    ColorMap::ALL
        .iter()
        .map(|&map| {
            let e: Vec<_> = (400..=700).map(|l| error_vs_cie(map, l as f64)).collect();
            let n = e.len() as f64;
            MapSummary {
                map,
                mean_delta_e: e.iter().map(|x| x.delta_e).sum::<f64>() / n,
                max_delta_e: e.iter().map(|x| x.delta_e).fold(0.0, f64::max),
                mean_hue_deg: e.iter().map(|x| x.hue_deg).sum::<f64>() / n,
            }
        })
        .collect()
}

/// Writes the CSVs and plots into `dir`; returns a short text summary.
pub fn write_report(dir: &Path, glass: &Glass) -> Result<String> {
    crate::image_io::create_folder(dir)?;
    let errors = write_ior_report(dir, glass)?;
    let maps = write_colour_map_report(dir)?;
    let mut out = format!("IOR models for {} against Sellmeier, 380-780 nm:\n", glass.name);
    for e in &errors {
        writeln!(out, "  {:<11} max |dn| {:.2e} (400-700: {:.2e})", e.model.name(), e.max_abs_380_780, e.max_abs_400_700)?;
    }
    writeln!(out, "Colour maps against CIE, 400-700 nm:")?;
    for m in &maps {
        writeln!(out, "  {:<11} mean Delta E {:6.2}, max {:6.2}, mean hue error {:5.1} deg", m.map.name(), m.mean_delta_e, m.max_delta_e, m.mean_hue_deg)?;
    }
    writeln!(out, "wrote {}/{{ior_models,ior_models_summary,colour_maps,colour_maps_summary}}.csv and plots", dir.display())?;
    Ok(out)
}

/// n(lambda) of every model (CSV and plot) and each model's error against
/// Sellmeier (summary CSV and plot).
fn write_ior_report(dir: &Path, glass: &Glass) -> Result<Vec<IorError>> {
    // n(lambda) of every model.
    let models: Vec<(IorKind, IorModel)> = IorKind::ALL.iter().map(|&k| (k, IorModel::for_glass(glass, k))).collect();
    let mut csv = String::from("wavelength_nm");
    for (k, _) in &models {
        write!(csv, ",{}", k.name())?;
    }
    csv.push('\n');
    for l in 380..=780 {
        write!(csv, "{l}")?;
        for (_, m) in &models {
            write!(csv, ",{:.7}", m.n(l as f64))?;
        }
        csv.push('\n');
    }
    write_text(&dir.join("ior_models.csv"), &csv)?;
    let errors = ior_errors(glass);
    let mut summary = String::from("model,max_abs_err_380_780,max_abs_err_400_700,rms_err_380_780\n");
    for e in &errors {
        writeln!(summary, "{},{:.3e},{:.3e},{:.3e}", e.model.name(), e.max_abs_380_780, e.max_abs_400_700, e.rms_380_780)?;
    }
    write_text(&dir.join("ior_models_summary.csv"), &summary)?;
    let curve = |f: &dyn Fn(f64) -> f64| (380..=780).map(|l| (l as f64, f(l as f64))).collect::<Vec<_>>();
    let series = |diff: bool| -> Vec<Series> {
        models
            .iter()
            .zip(PALETTE)
            .zip(&errors)
            .map(|(((k, m), color), e)| {
                Series::new(
                    if diff { format!("{} (max {:.1e})", k.name(), e.max_abs_380_780) } else { k.name().to_string() },
                    curve(&|l| if diff { m.n(l) - glass.sellmeier(l) } else { m.n(l) }),
                    color,
                )
            })
            .collect()
    };
    render(
        &dir.join("ior_models.png"),
        &LineChart {
            title: format!("{}: index of refraction by model", glass.name),
            x_label: "wavelength (nm)".into(),
            y_label: "n".into(),
            series: series(false),
            ..Default::default()
        },
    )?;
    render(
        &dir.join("ior_models_error.png"),
        &LineChart {
            title: format!("{}: model minus Sellmeier", glass.name),
            x_label: "wavelength (nm)".into(),
            y_label: "n - n_Sellmeier".into(),
            series: series(true),
            ..Default::default()
        },
    )?;
    Ok(errors)
}

/// Wavelengths of the colour-map CSV: every nanometre, the grid the hue
/// error chart is drawn on, so the chart can be redrawn from the CSV.
pub const MAP_NM: std::ops::RangeInclusive<u32> = 380..=780;

/// Every colour map against CIE: per-wavelength CSV, summary, strips and
/// the hue error plot (drawn from the CSV's rows over 400-700 nm).
fn write_colour_map_report(dir: &Path) -> Result<Vec<MapSummary>> {
    let mut csv = String::from("wavelength_nm,map,r_lin,g_lin,b_lin,delta_e,hue_err_deg\n");
    let mut hue: Vec<Vec<(f64, f64)>> = vec![Vec::new(); ColorMap::ALL.len()];
    for (k, map) in ColorMap::ALL.into_iter().enumerate() {
        for l in MAP_NM {
            let c = map.rgb(l as f64);
            let e = error_vs_cie(map, l as f64);
            let row = [cell(c.x), cell(c.y), cell(c.z), cell(e.delta_e), cell(e.hue_deg)];
            writeln!(csv, "{l},{},{}", map.name(), row.join(","))?;
            if (400..=700).contains(&l) {
                // The value as written, so the chart is the CSV's.
                hue[k].push((l as f64, row[4].parse().unwrap_or(f64::NAN)));
            }
        }
    }
    write_text(&dir.join("colour_maps.csv"), &csv)?;
    let maps = map_summaries();
    let mut summary = String::from("map,mean_delta_e_400_700,max_delta_e_400_700,mean_hue_err_deg_400_700\n");
    for m in &maps {
        writeln!(summary, "{},{:.3},{:.3},{:.3}", m.map.name(), m.mean_delta_e, m.max_delta_e, m.mean_hue_deg)?;
    }
    write_text(&dir.join("colour_maps_summary.csv"), &summary)?;
    let enc = |c: glam::DVec3| [c.x, c.y, c.z].map(|v| (srgb_encode(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8);
    let rows: Vec<super::plot::StripRow<'static>> =
        ColorMap::ALL.iter().map(|&m| (m.name().to_string(), Box::new(move |l: f64| enc(m.rgb(l))) as Box<dyn Fn(f64) -> [u8; 3]>)).collect();
    colour_strips(&dir.join("colour_maps.png"), "wavelength to colour: CIE and the reports' maps", (380.0, 780.0), &rows)?;
    render(
        &dir.join("colour_maps_error.png"),
        &LineChart {
            title: "hue error against CIE: how far each map turns a wavelength's hue".into(),
            subtitle: "400-700 nm, where every map has a colour".into(),
            notes: vec![(
                "the angle between the CIELAB hues of the map's colour and CIE's, unsigned (0 where either is grey); every point is a row of colour_maps.csv (1 nm steps); the legend adds each map's mean Delta E 1976, which also counts lightness and chroma".into(),
                plotters::style::RGBColor(60, 60, 60),
            )],
            x_label: "wavelength (nm)".into(),
            y_label: "hue error (degrees)".into(),
            series: ColorMap::ALL[1..]
                .iter()
                .zip(PALETTE)
                .zip(&maps[1..])
                .zip(&hue[1..])
                .map(|(((&m, color), s), pts)| {
                    Series::new(format!("{} (mean hue error {:.1} deg, mean Delta E {:.1})", m.name(), s.mean_hue_deg, s.mean_delta_e), pts.clone(), color)
                })
                .collect(),
            ..Default::default()
        },
    )?;
    Ok(maps)
}
