//! CIE 1931 colour: spectrum to XYZ with the 2-degree colour-matching
//! functions (embedded from `data/cie1931_2deg_cmf.csv`, CIE 015:2018 via
//! colour-science 0.4.7), XYZ to linear sRGB (IEC 61966-2-1), gamut mapping,
//! exposure and the sRGB transfer function (docs/physics.md §5).

use crate::data::{Table, CMF_1931};
use glam::{DMat3, DVec3};
use std::sync::OnceLock;

#[derive(Copy, Clone, Debug, PartialEq, Default)]
pub struct Xyz(pub DVec3);

/// Linear sRGB (D65 white), unclipped: negative where out of gamut.
#[derive(Copy, Clone, Debug, PartialEq, Default)]
pub struct LinearRgb(pub DVec3);

/// IEC 61966-2-1 XYZ to linear sRGB, the 4-decimal form the oracles use.
pub const XYZ_TO_SRGB: DMat3 = DMat3::from_cols_array(&[3.2406, -0.9689, 0.0557, -1.5372, 1.8758, -0.2040, -0.4986, 0.0415, 1.0570]);

/// Relative luminance weights of linear sRGB (the Y row of the inverse).
pub const SRGB_LUMA: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);

/// Rows of the colour-matching table: 360 to 830 nm at 1 nm.
const CMF_ROWS: usize = 471;

fn cmf_table() -> &'static [[f64; 3]; CMF_ROWS] {
    static T: OnceLock<Box<[[f64; 3]; CMF_ROWS]>> = OnceLock::new();
    T.get_or_init(|| {
        let t = Table::parse(CMF_1931);
        let (l, x, y, z) = (t.numbers("wavelength_nm").unwrap(), t.numbers("xbar").unwrap(), t.numbers("ybar").unwrap(), t.numbers("zbar").unwrap());
        assert!(l.len() == CMF_ROWS && l.iter().enumerate().all(|(i, v)| *v == 360.0 + i as f64), "the CMF table is 360-830 nm at 1 nm");
        let rows: Vec<[f64; 3]> = (0..l.len()).map(|i| [x[i], y[i], z[i]]).collect();
        rows.into_boxed_slice().try_into().expect("471 rows")
    })
}

/// Colour-matching functions at `nm` (linear between the 1 nm samples, zero
/// outside 360-830 nm). The row is found in 32-bit integers: on baseline
/// x86-64 a 64-bit unsigned conversion takes several instructions, and
/// this runs once a photon.
#[inline]
pub fn cmf(nm: f64) -> DVec3 {
    let t = cmf_table();
    let f = nm - 360.0;
    if !(f >= 0.0 && f <= (CMF_ROWS - 1) as f64) {
        return DVec3::ZERO;
    }
    let i = (f as i32).min(CMF_ROWS as i32 - 2);
    let w = f - f64::from(i);
    let i = i as usize;
    DVec3::from(t[i]) * (1.0 - w) + DVec3::from(t[i + 1]) * w
}

/// Integral of ybar over 360-830 nm (1 nm sum): the Y of a unit equal-energy
/// spectrum, used to normalise sampled estimates.
pub fn cie_y_integral() -> f64 {
    static Y: OnceLock<f64> = OnceLock::new();
    *Y.get_or_init(|| cmf_table().iter().map(|c| c[1]).sum())
}

/// XYZ by the oracles' method: S(l) cmf(l) 5 nm summed at l = 380, 385, ..., 780.
pub fn xyz_sum_5nm(s: impl Fn(f64) -> f64) -> Xyz {
    Xyz((0..=80).map(|i| 380.0 + 5.0 * i as f64).map(|l| s(l) * cmf(l) * 5.0).sum())
}

/// XYZ integrated at 1 nm over the tables' whole range (360-830 nm).
pub fn xyz_sum_1nm(s: impl Fn(f64) -> f64) -> Xyz {
    Xyz((360..=830).map(|l| l as f64).map(|l| s(l) * cmf(l)).sum())
}

impl Xyz {
    pub fn to_linear_srgb(self) -> LinearRgb {
        LinearRgb(XYZ_TO_SRGB * self.0)
    }

    /// Scaled so Y = 1 (Y = 0 stays black).
    pub fn normalised(self) -> Xyz {
        if self.0.y > 0.0 {
            Xyz(self.0 / self.0.y)
        } else {
            Xyz(DVec3::ZERO)
        }
    }

    /// Chromaticity (x, y).
    pub fn xy(self) -> (f64, f64) {
        let s = self.0.x + self.0.y + self.0.z;
        if s > 0.0 {
            (self.0.x / s, self.0.y / s)
        } else {
            (0.0, 0.0)
        }
    }

    /// CIELAB against the D65 white of Y = 1.
    pub fn to_lab(self) -> DVec3 {
        let white = DVec3::new(0.95047, 1.0, 1.08883);
        let f = |t: f64| {
            let d: f64 = 6.0 / 29.0;
            if t > d * d * d {
                t.cbrt()
            } else {
                t / (3.0 * d * d) + 4.0 / 29.0
            }
        };
        let v = self.0 / white;
        let (fx, fy, fz) = (f(v.x), f(v.y), f(v.z));
        DVec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz))
    }
}

impl LinearRgb {
    pub fn to_xyz(self) -> Xyz {
        Xyz(XYZ_TO_SRGB.inverse() * self.0)
    }

    pub fn luminance(self) -> f64 {
        SRGB_LUMA.dot(self.0)
    }
}

/// The sRGB transfer function (IEC 61966-2-1) for c >= 0.
pub fn srgb_encode(c: f64) -> f64 {
    if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Its inverse, for colours given as display (encoded) sRGB values.
pub fn srgb_decode(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Encoding extended to negative values by odd symmetry (the oracles'
/// convention for out-of-gamut colours).
pub fn srgb_encode_odd(c: f64) -> f64 {
    c.signum() * srgb_encode(c.abs())
}

crate::named_enum! {
    /// How colours outside the sRGB gamut are brought into the image.
    pub enum GamutMap {
        /// Clamp each channel to [0, 1]: hue shifts toward the primaries, so a
        /// spectrum collapses into a few saturated bands.
        Clip = "clip",
        /// Keep luminance and hue: mix with the grey of the same luminance until
        /// no channel is negative, then, if a channel exceeds 1, scale the whole
        /// colour down (never clip one channel alone).
        Desaturate = "desaturate",
        /// Filmic, of the AgX kind (docs/physics.md §23): hue kept as for
        /// desaturate, then log encoding in an inset gamut, a sigmoid and an
        /// outset, so the brightest saturated light rolls smoothly toward
        /// white as on film and nothing posterises.
        Agx = "agx",
        /// AgX with a print look (§23): the display values raised to a
        /// power and their saturation raised, as AgX's "Punchy" look does,
        /// so faint light between bright features sinks toward black as on
        /// contrasty film.
        AgxPunchy = "agx-punchy",
        /// A camera's sensor and print (§25): each channel clipped where a
        /// real camera's sensor saturates (in its own colour space, so an
        /// over-exposed green line turns yellow and then white, as in a
        /// photograph), back to sRGB, and a print's black point, so faint
        /// light a few per cent of white is black.
        Camera = "camera",
        /// The camera's sensor with a hard print (§25): as `camera`, but
        /// the print's black point at 30 % of white (`CAMERA_HARD_BLACK`),
        /// as on a contrasty paper grade, so the smear of faint light
        /// beside bright line copies prints black and their edges read sharp.
        CameraHard = "camera-hard",
    }
}

impl GamutMap {
    /// Maps linear sRGB into [0, 1]^3. NaN and infinity become black.
    pub fn apply(self, c: LinearRgb) -> DVec3 {
        let v = c.0;
        if !v.is_finite() {
            return DVec3::ZERO;
        }
        match self {
            GamutMap::Clip => v.clamp(DVec3::ZERO, DVec3::ONE),
            GamutMap::Desaturate => {
                let v = desaturate(v);
                let max = v.max_element();
                if max > 1.0 {
                    v / max
                } else {
                    v
                }
            }
            GamutMap::Agx => agx(v),
            GamutMap::AgxPunchy => punchy(agx(v)),
            GamutMap::Camera => camera(v),
            GamutMap::CameraHard => camera_print(v, CAMERA_HARD_BLACK),
        }
    }
}

/// XYZ (D65) to a Canon EOS 5D Mark II's raw colour space, x 10^4: Adobe's
/// matrix as dcraw's `adobe_coeff` table lists it (docs/physics.md §25).
const CAMERA_XYZ: [f64; 9] = [4716.0, 603.0, -830.0, -7798.0, 15474.0, 2480.0, -1496.0, 1937.0, 6651.0];
/// The print's black point: display-linear light below this fraction of
/// white is black (§25).
pub const CAMERA_BLACK: f64 = 0.1;
/// The hard print's black point (`camera-hard`, §25).
pub const CAMERA_HARD_BLACK: f64 = 0.3;

/// Linear sRGB to the camera's white-balanced raw space (§25): the
/// camera's matrix after sRGB-to-XYZ, each row scaled to sum to 1 so
/// that white (1, 1, 1) stays white, as dcraw's `cam_rgb` is.
pub fn camera_from_srgb() -> DMat3 {
    let [a, b, c, d, e, f, g, h, i] = CAMERA_XYZ.map(|x| x / 1e4);
    // Rows of the camera matrix; glam's constructor takes columns.
    let cam_xyz = DMat3::from_cols_array(&[a, d, g, b, e, h, c, f, i]);
    let m = cam_xyz * XYZ_TO_SRGB.inverse();
    let rows = m.transpose();
    let norm = |r: DVec3| r / (r.x + r.y + r.z);
    DMat3::from_cols(norm(rows.x_axis), norm(rows.y_axis), norm(rows.z_axis)).transpose()
}

/// The camera transform (§25) on exposed linear sRGB: into the camera's
/// space, each channel clipped at the sensor's full scale 1 (the negative
/// values a 3x3 fit gives spectral colours are kept), back to sRGB,
/// clamped to [0, 1], then the print's black point, which scales the
/// colour (hue kept) so that its largest channel m becomes
/// (m - b) / (1 - b).
pub fn camera(v: DVec3) -> DVec3 {
    camera_print(v, CAMERA_BLACK)
}

/// The camera transform (§25) with the print's black point `black`.
pub fn camera_print(v: DVec3, black: f64) -> DVec3 {
    static M: OnceLock<(DMat3, DMat3)> = OnceLock::new();
    let (to_cam, from_cam) = *M.get_or_init(|| {
        let m = camera_from_srgb();
        (m, m.inverse())
    });
    let c = (to_cam * v).min(DVec3::ONE);
    let rgb = (from_cam * c).clamp(DVec3::ZERO, DVec3::ONE);
    let m = rgb.max_element();
    if !(m > black) {
        return DVec3::ZERO;
    }
    rgb * ((m - black) / (1.0 - black) / m)
}

/// Linear sRGB to linear Rec. 2020 (ITU-R BT.2087-0, eq. 1), rows
/// summing to 1 so white stays white; AgX works on these primaries
/// (docs/physics.md §23), which hold every spectral colour from about 460
/// to 680 nm, so a prism's red end is not first pushed toward magenta.
const SRGB_TO_REC2020: DMat3 =
    DMat3::from_cols_array(&[0.627403896, 0.069097289, 0.016391439, 0.329283039, 0.919540395, 0.088013307, 0.043313065, 0.011362316, 0.895595254]);
/// Rec. 2020's luma weights (ITU-R BT.2020, table 4).
const REC2020_LUMA: DVec3 = DVec3::new(0.2627, 0.6780, 0.0593);
/// AgX's inset and outset on Rec. 2020 (Blender 4.0's AgX, from E. Chow's
/// AgX_LUT_Gen; §23): each primary drawn toward the others and slightly
/// rotated (red toward yellow, so bright red bleaches through orange,
/// not pink), and, after the curve, pushed back out unrotated. Rows sum to
/// 1: greys stay grey.
const AGX_INSET: DMat3 = DMat3::from_cols_array(&[
    0.856627153315983,
    0.137318972929847,
    0.11189821299995,
    0.0951212405381588,
    0.761241990602591,
    0.0767994186031903,
    0.0482516061458583,
    0.101439036467562,
    0.811302368396859,
]);
const AGX_OUTSET: DMat3 = DMat3::from_cols_array(&[
    1.1271005818144368,
    -0.1413297634984383,
    -0.14132976349843826,
    -0.11060664309660323,
    1.157823702216272,
    -0.11060664309660294,
    -0.016493938717834573,
    -0.016493938717834257,
    1.2519364065950405,
]);
/// The log encoding's range in stops about 1.0: 0.18 (mid grey) lands at
/// 10 / 16.5 of it, as in Blender's AgX (log2 range -10 to +6.5 about 0.18).
const AGX_MIN_EV: f64 = -12.473931188332412;
const AGX_MAX_EV: f64 = 4.026068811667588;
/// Linear input that the figures' exposure brings to 1 (the 99.5th
/// percentile under automatic exposure) is shown 2 stops under AgX's
/// white, at about 92 % of full scale: what is brighter still rolls on.
const AGX_HEADROOM: f64 = 4.0;

/// The filmic curve on linear sRGB (§23): to Rec. 2020, hue and luminance
/// kept while a negative channel is lifted, inset, log2 encoding, sigmoid
/// per channel, outset, back to sRGB (any colour outside it desaturated
/// at its luminance). Returns display-linear values in [0, 1].
pub fn agx(v: DVec3) -> DVec3 {
    let c = desaturate_about(SRGB_TO_REC2020 * v, REC2020_LUMA);
    let c = AGX_INSET * (c * AGX_HEADROOM);
    let encode = |x: f64| ((x.max(1e-10).log2() - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV)).clamp(0.0, 1.0);
    let y = DVec3::new(agx_sigmoid(encode(c.x)), agx_sigmoid(encode(c.y)), agx_sigmoid(encode(c.z)));
    let out = SRGB_TO_REC2020.inverse() * (AGX_OUTSET * y.powf(2.4)).max(DVec3::ZERO);
    desaturate(out).clamp(DVec3::ZERO, DVec3::ONE)
}

/// The print look's power and saturation (§23): an ASC CDL with slope 1
/// and offset 0 on AgX's display-linear output.
const PUNCHY_POWER: f64 = 1.6;
const PUNCHY_SATURATION: f64 = 1.3;
/// How far toward the gamut's edge the print look's saturation may go.
const PUNCHY_EDGE: f64 = 0.85;

/// The print look (§23): ASC CDL power, then saturation about Rec. 709
/// luma, raised by `PUNCHY_SATURATION` but never past 85 % of the way to
/// the gamut's edge, so no channel is clipped and a colour already at the
/// edge (a spectrum's cyan-green, which AgX leaves with R = 0) is drawn in
/// a little and keeps some of its weakest channel, as film's dyes do.
pub fn punchy(v: DVec3) -> DVec3 {
    let c = v.max(DVec3::ZERO).powf(PUNCHY_POWER);
    let y = SRGB_LUMA.dot(c);
    // The largest factor s with y + (c - y) s inside [0, 1]^3.
    let edge = (0..3).fold(f64::INFINITY, |m, i| {
        let d = c[i] - y;
        if d < 0.0 {
            m.min(y / -d)
        } else if d > 0.0 {
            m.min((1.0 - y) / d)
        } else {
            m
        }
    });
    let s = PUNCHY_SATURATION.min(PUNCHY_EDGE * edge);
    (DVec3::splat(y) + (c - DVec3::splat(y)) * s).clamp(DVec3::ZERO, DVec3::ONE)
}

/// AgX's sigmoid (§23) on the log-encoded x in [0, 1], giving a display
/// value (encoded with power 2.4): slope 2.4 through mid grey at
/// (x_p, 0.18^(1/2.4)), each side bent by (1 + (k |x - x_p|)^1.5)^(-1/1.5)
/// with k chosen so that the curve meets (0, 0) and (1, 1).
pub fn agx_sigmoid(x: f64) -> f64 {
    const P: f64 = 1.5;
    const SLOPE: f64 = 2.4;
    let x_p = -AGX_MIN_EV / (AGX_MAX_EV - AGX_MIN_EV) + 0.18f64.log2() / (AGX_MAX_EV - AGX_MIN_EV);
    let y_p = 0.18f64.powf(1.0 / 2.4);
    let d = x - x_p;
    // The end the curve bends toward, and k that makes it arrive there.
    let (end_d, end_y) = if d < 0.0 { (x_p, y_p) } else { (1.0 - x_p, 1.0 - y_p) };
    let k = ((SLOPE * end_d / end_y).powf(P) - 1.0).powf(1.0 / P) / end_d;
    y_p + SLOPE * d / (1.0 + (k * d.abs()).powf(P)).powf(1.0 / P)
}

/// Moves a colour toward the grey of its own luminance just far enough
/// that no channel is negative (black if its luminance is not positive).
/// Scale-invariant: exposure can be chosen after it.
pub fn desaturate(v: DVec3) -> DVec3 {
    desaturate_about(v, SRGB_LUMA)
}

/// `desaturate` with the luma weights of the colour's own primaries.
fn desaturate_about(v: DVec3, luma: DVec3) -> DVec3 {
    let y = luma.dot(v);
    if !(y > 0.0) || !v.is_finite() {
        return DVec3::ZERO;
    }
    let min = v.min_element();
    if min < 0.0 {
        let t = y / (y - min);
        DVec3::splat(y) + t * (v - DVec3::splat(y))
    } else {
        v
    }
}

/// XYZ times a linear-sRGB albedo: what a coloured matte surface sends on
/// (an RGB product, not spectral; exact for grey).
pub fn tint(xyz: DVec3, albedo: [f64; 3]) -> DVec3 {
    if albedo[0] == albedo[1] && albedo[1] == albedo[2] {
        return xyz * albedo[0];
    }
    let rgb = XYZ_TO_SRGB * xyz * DVec3::from(albedo);
    XYZ_TO_SRGB.inverse() * rgb
}

/// Linear sRGB to 8-bit display values: exposure, gamut map, encode.
pub fn to_srgb8(c: LinearRgb, exposure: f64, map: GamutMap) -> [u8; 3] {
    let v = map.apply(LinearRgb(c.0 * exposure));
    let q = |x: f64| (srgb_encode(x.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8;
    [q(v.x), q(v.y), q(v.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn desaturate_keeps_luminance_and_lands_in_gamut() {
        for nm in (400..=700).step_by(10) {
            let c = Xyz(cmf(nm as f64)).to_linear_srgb();
            let m = GamutMap::Desaturate.apply(LinearRgb(c.0 / c.0.max_element().max(1e-9) * 0.5));
            assert!(m.min_element() >= -1e-12 && m.max_element() <= 1.0 + 1e-12, "{nm}: {m:?}");
        }
        let c = LinearRgb(DVec3::new(0.6, -0.1, 0.2));
        let m = GamutMap::Desaturate.apply(c);
        assert!((SRGB_LUMA.dot(m) - c.luminance()).abs() < 1e-12);
        assert!(m.min_element().abs() < 1e-12);
        assert_eq!(GamutMap::Clip.apply(LinearRgb(DVec3::new(f64::NAN, 0.0, 0.0))), DVec3::ZERO);
    }

    #[test]
    fn camera_matrix_is_dcraws_and_keeps_white() {
        let m = camera_from_srgb();
        // White stays white; dcraw's cam_rgb for this camera, computed
        // independently (numpy, its sRGB matrix), first row.
        assert!((m * DVec3::ONE - DVec3::ONE).abs().max_element() < 1e-12);
        let r = m.row(0);
        assert!((r.x - 0.4920).abs() < 2e-3 && (r.y - 0.4827).abs() < 2e-3 && (r.z - 0.0253).abs() < 2e-3, "{r:?}");
    }

    #[test]
    fn camera_turns_an_over_exposed_green_line_yellow_then_white_and_keeps_red_red() {
        let line = |nm: f64, k: f64| {
            let c = Xyz(cmf(nm)).to_linear_srgb().0;
            camera(c / desaturate(c).max_element() * k)
        };
        // Exposed at full scale the 546 nm line is green with no red; three
        // times over, the sensor's green clips and red rises: yellow-green.
        let (a, b) = (line(546.075, 0.5), line(546.075, 3.0));
        assert!(a.x < 0.05 && a.y > 0.3, "{a:?}");
        assert!(b.x > 0.7 && b.y > 0.95 && b.z < b.x, "{b:?}");
        assert!(line(546.075, 100.0).min_element() > 0.95);
        // Clipping each sRGB channel never adds red to it.
        assert!(GamutMap::Clip.apply(LinearRgb(Xyz(cmf(546.075)).to_linear_srgb().0 * 10.0)).x == 0.0);
        let red = line(611.0, 10.0);
        assert!(red.x > 0.99 && red.y < 0.05 && red.z < 0.05, "{red:?}");
        // The print's black point: faint light is black, greys stay grey.
        assert_eq!(camera(DVec3::splat(0.5 * CAMERA_BLACK)), DVec3::ZERO);
        let g = camera(DVec3::splat(0.55));
        assert!((g.x - 0.5).abs() < 1e-9 && (g.x - g.z).abs() < 1e-12, "{g:?}");
    }

    #[test]
    fn the_hard_print_blacks_out_what_the_soft_one_shows_and_keeps_the_rest() {
        let hard = |v: DVec3| GamutMap::CameraHard.apply(LinearRgb(v));
        // A fifth of white: grey on the soft print, black on the hard one.
        let fifth = DVec3::splat(0.2);
        assert!(camera(fifth).x > 0.1 && hard(fifth) == DVec3::ZERO);
        // Grey stays grey, white white; 65 % of white prints at half.
        let g = hard(DVec3::splat(0.65));
        assert!((g.x - 0.5).abs() < 1e-9 && (g.x - g.z).abs() < 1e-12, "{g:?}");
        assert!((hard(DVec3::ONE) - DVec3::ONE).abs().max_element() < 1e-9);
        // The sensor is the same: an over-exposed 546 nm line still turns
        // yellow-green, a red line stays red.
        let line = |nm: f64, k: f64| {
            let c = Xyz(cmf(nm)).to_linear_srgb().0;
            hard(c / desaturate(c).max_element() * k)
        };
        let b = line(546.075, 3.0);
        assert!(b.x > 0.6 && b.y > 0.95 && b.z < b.x, "{b:?}");
        let red = line(611.0, 10.0);
        assert!(red.x > 0.99 && red.y < 0.05 && red.z < 0.05, "{red:?}");
    }

    #[test]
    fn agx_sigmoid_meets_its_three_points_and_rises() {
        let x_p = 10.0 / 16.5;
        assert!(agx_sigmoid(0.0).abs() < 1e-12);
        assert!((agx_sigmoid(1.0) - 1.0).abs() < 1e-12);
        assert!((agx_sigmoid(x_p) - 0.18f64.powf(1.0 / 2.4)).abs() < 1e-12);
        // Blender's curve (EaryChow's AgX_LUT_Gen, its published constants
        // evaluated independently) at two points.
        assert!((agx_sigmoid(0.3) - 0.0884922242427314).abs() < 1e-9, "{}", agx_sigmoid(0.3));
        assert!((agx_sigmoid(0.8) - 0.8407495052554047).abs() < 1e-9, "{}", agx_sigmoid(0.8));
        let ys: Vec<f64> = (0..=1000).map(|i| agx_sigmoid(i as f64 / 1000.0)).collect();
        assert!(ys.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn agx_keeps_greys_grey_and_rolls_bright_colours_toward_white() {
        for e in [0.01, 0.1, 1.0, 10.0] {
            let g = agx(DVec3::splat(e));
            assert!((g.x - g.y).abs() < 1e-9 && (g.y - g.z).abs() < 1e-9, "{e}: {g:?}");
        }
        // The exposure's white (a quarter of AgX's headroom) to about 92 %
        // of full scale once encoded.
        let w = srgb_encode(agx(DVec3::ONE).x);
        assert!((0.85..0.97).contains(&w), "{w}");
        // A saturated green brightens and whitens as it is exposed more:
        // its weakest channel rises toward its strongest.
        let green = Xyz(cmf(520.0)).to_linear_srgb().0;
        let (dim, bright) = (GamutMap::Agx.apply(LinearRgb(green * 0.3)), GamutMap::Agx.apply(LinearRgb(green * 30.0)));
        let sat = |v: DVec3| 1.0 - v.min_element() / v.max_element();
        assert!(sat(bright) < 0.5 * sat(dim), "{dim:?} {bright:?}");
        assert!(bright.max_element() > dim.max_element());
        // Never out of [0, 1], NaN to black.
        for nm in (380..=780).step_by(5) {
            for e in [1e-6, 1e-2, 1.0, 1e2, 1e6] {
                let v = GamutMap::Agx.apply(LinearRgb(Xyz(cmf(nm as f64)).to_linear_srgb().0 * e));
                assert!(v.min_element() >= 0.0 && v.max_element() <= 1.0, "{nm} {e}: {v:?}");
            }
        }
        assert_eq!(GamutMap::Agx.apply(LinearRgb(DVec3::new(f64::NAN, 1.0, 1.0))), DVec3::ZERO);
    }

    #[test]
    fn punchy_sinks_faint_light_and_keeps_black_white_and_grey() {
        // Display-linear 3 % of white falls to 0.03^1.6 (§23), white and
        // black stay, a grey stays grey.
        assert!((punchy(DVec3::splat(0.03)).x - 0.03f64.powf(1.6)).abs() < 1e-12);
        assert_eq!(punchy(DVec3::ONE), DVec3::ONE);
        assert_eq!(punchy(DVec3::ZERO), DVec3::ZERO);
        let g = punchy(DVec3::splat(0.4));
        assert!((g.x - g.y).abs() < 1e-12 && (g.y - g.z).abs() < 1e-12);
        // Saturation rises: a muted red moves away from its luma.
        let (c, p) = (DVec3::new(0.6, 0.3, 0.3), punchy(DVec3::new(0.6, 0.3, 0.3)));
        assert!(p.x / p.y > (c.x / c.y).powf(1.6), "{p}");
        // A colour at the gamut's edge is drawn in: its weakest channel
        // rises above 0.
        let edge = punchy(DVec3::new(0.0, 0.6, 0.4));
        assert!(edge.x > 0.0 && edge.min_element() > 0.0, "{edge}");
        // Through the whole map, faint light is darker than under plain AgX.
        let faint = LinearRgb(DVec3::splat(0.01));
        assert!(GamutMap::AgxPunchy.apply(faint).x < 0.5 * GamutMap::Agx.apply(faint).x);
    }

    #[test]
    fn agx_shows_an_overexposed_spectrum_without_flat_blocks() {
        // The spectrum 400-700 nm at 1 nm, exposed so its peak is 8 times
        // full scale: clipping turns long runs of it into identical 8-bit
        // colours (flat blocks); AgX changes colour from step to step.
        let peak = (400..=700).map(|nm| desaturate(Xyz(cmf(nm as f64)).to_linear_srgb().0).max_element()).fold(0.0, f64::max);
        let runs = |map: GamutMap| {
            let px: Vec<[u8; 3]> = (400..=700).map(|nm| to_srgb8(Xyz(cmf(nm as f64)).to_linear_srgb(), 8.0 / peak, map)).collect();
            let mut longest = 1;
            let mut run = 1;
            for w in px.windows(2) {
                run = if w[0] == w[1] { run + 1 } else { 1 };
                longest = longest.max(run);
            }
            longest
        };
        let (clip, agx) = (runs(GamutMap::Clip), runs(GamutMap::Agx));
        assert!(clip >= 10, "clip's longest flat run: {clip} nm");
        assert!(agx <= 4 && agx * 3 <= clip, "AgX's longest flat run: {agx} nm, clip's {clip} nm");
    }

    #[test]
    fn the_print_look_keeps_red_in_a_bright_spectrums_cyan_green() {
        // 480-520 nm exposed from dim to eight times over: under the print
        // look the red channel never falls to 0 where green leads (a clip
        // of the boosted saturation made R = 0 over the whole cyan-green,
        // a flat band), as on film, where cyan keeps some red.
        for nm in 480..=520 {
            let c = Xyz(cmf(nm as f64)).to_linear_srgb();
            for e in [0.3, 1.0, 3.0, 8.0] {
                let [r, g, b] = to_srgb8(LinearRgb(c.0 / c.0.max_element()), e, GamutMap::AgxPunchy);
                if g.max(b) > 60 {
                    assert!(r > 0, "{nm} nm at {e}: {r} {g} {b}");
                }
            }
        }
    }

    #[test]
    fn agx_keeps_the_spectrum_red_end_red_not_magenta() {
        // 610-700 nm at 1 nm, each dim to eight times over-exposed: in 8-bit
        // display values red leads and the hue stays within 18 degrees of
        // red on the magenta side (on sRGB primaries, hue-keeping
        // desaturation then the curve per channel made 620-660 nm pink:
        // 255, 0, 109 at 650 nm, 26 degrees).
        for nm in 610..=700 {
            let c = Xyz(cmf(nm as f64)).to_linear_srgb();
            for e in [0.3, 1.0, 3.0, 8.0] {
                for map in [GamutMap::Agx, GamutMap::AgxPunchy] {
                    let [r, g, b] = to_srgb8(LinearRgb(c.0 / c.0.max_element()), e, map).map(f64::from);
                    let hue = 60.0 * (g - b) / (r - g.min(b)).max(1.0);
                    assert!(r >= g && r >= b && hue > -18.0, "{nm} nm at {e}: {r} {g} {b}, hue {hue:.1}");
                }
            }
        }
    }

    #[test]
    fn transfer_function_round_trips() {
        for i in 0..=100 {
            let c = i as f64 / 100.0;
            assert!((srgb_decode(srgb_encode(c)) - c).abs() < 1e-12);
        }
        assert_eq!(srgb_encode_odd(-0.5), -srgb_encode(0.5));
    }

    #[test]
    fn matrix_inverse_maps_white_to_d65() {
        let w = LinearRgb(DVec3::ONE).to_xyz();
        assert!((w.0 - DVec3::new(0.9505, 1.0, 1.089)).abs().max_element() < 2e-3);
    }
}
