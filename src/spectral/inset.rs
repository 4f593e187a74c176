//! A magnified inset: a small region of the finished (display) image,
//! enlarged and drawn in a corner with a white border, the region itself
//! outlined, as a paper shows a detail too small to read at 1:1 (report
//! 001's colour fringes are a few pixels wide at any size the whole sphere
//! fits the frame: docs/physics.md §22). Only the displayed PNG changes;
//! the rendered light is untouched.

/// Where the inset sits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Corner {
    TopLeft,
    TopRight,
    BottomLeft,
    BottomRight,
}

/// A region (fractions of the frame: left, top, width, height), its
/// magnification and the corner it is drawn in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inset {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
    pub zoom: f64,
    pub corner: Corner,
}

/// Why an inset's text is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InsetError {
    #[error("`{0}`: expected x,y,w,h,zoom,corner (fractions of the frame, a magnification, tl/tr/bl/br)")]
    Fields(String),
    #[error("`{0}` is not a number")]
    NotNumber(String),
    #[error("`{0}`: the region must lie inside the frame (0 <= x, y and x + w, y + h <= 1)")]
    Outside(String),
    #[error("`{0}`: the magnification must be 1 to 16 and the enlarged region fit in the frame")]
    Zoom(String),
    #[error("`{0}`: the corner must be tl, tr, bl or br")]
    Corner(String),
}

impl Inset {
    /// Parses `x,y,w,h,zoom,corner` (fractions of the frame; corner one of
    /// tl, tr, bl, br). The enlarged region must fit in the frame.
    pub fn parse(s: &str) -> Result<Inset, InsetError> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        if parts.len() != 6 {
            return Err(InsetError::Fields(s.into()));
        }
        let mut v = [0.0; 5];
        for (k, p) in parts[..5].iter().enumerate() {
            v[k] = p.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| InsetError::NotNumber(p.to_string()))?;
        }
        let [x, y, w, h, zoom] = v;
        if !(0.0..1.0).contains(&x) || !(0.0..1.0).contains(&y) || w <= 0.0 || h <= 0.0 || x + w > 1.0 || y + h > 1.0 {
            return Err(InsetError::Outside(s.into()));
        }
        if !(1.0..=16.0).contains(&zoom) || w * zoom > 0.95 || h * zoom > 0.95 {
            return Err(InsetError::Zoom(s.into()));
        }
        let corner = match parts[5] {
            "tl" => Corner::TopLeft,
            "tr" => Corner::TopRight,
            "bl" => Corner::BottomLeft,
            "br" => Corner::BottomRight,
            c => return Err(InsetError::Corner(c.into())),
        };
        Ok(Inset { x, y, w, h, zoom, corner })
    }

    /// The source region and the inset's box in pixels, each as
    /// (left, top, width, height), for a `width` x `height` frame.
    pub fn boxes(&self, width: usize, height: usize) -> ([usize; 4], [usize; 4]) {
        let (fw, fh) = (width as f64, height as f64);
        let src = [(self.x * fw) as usize, (self.y * fh) as usize, ((self.w * fw).round() as usize).max(1), ((self.h * fh).round() as usize).max(1)];
        let (dw, dh) = (((src[2] as f64) * self.zoom).round() as usize, ((src[3] as f64) * self.zoom).round() as usize);
        let margin = (width / 60).max(2);
        let left = matches!(self.corner, Corner::TopLeft | Corner::BottomLeft);
        let top = matches!(self.corner, Corner::TopLeft | Corner::TopRight);
        let dx = if left { margin } else { width.saturating_sub(margin + dw) };
        let dy = if top { margin } else { height.saturating_sub(margin + dh) };
        (src, [dx, dy, dw.min(width), dh.min(height)])
    }

    /// Draws the inset into `px` (8-bit RGB, `width` x `height`): the
    /// region enlarged by bilinear interpolation, a white border round it
    /// and a white outline round the region.
    pub fn apply(&self, px: &mut [u8], width: usize, height: usize) {
        let (src, dst) = self.boxes(width, height);
        let orig = px.to_vec();
        let at = |x: usize, y: usize, c: usize| orig[(y.min(height - 1) * width + x.min(width - 1)) * 3 + c] as f64;
        for j in 0..dst[3] {
            for i in 0..dst[2] {
                // Pixel centres map to pixel centres.
                let sx = (src[0] as f64 + (i as f64 + 0.5) / self.zoom - 0.5).max(0.0);
                let sy = (src[1] as f64 + (j as f64 + 0.5) / self.zoom - 0.5).max(0.0);
                let (x0, y0) = (sx.floor() as usize, sy.floor() as usize);
                let (fx, fy) = (sx - x0 as f64, sy - y0 as f64);
                let (x, y) = (dst[0] + i, dst[1] + j);
                if x >= width || y >= height {
                    continue;
                }
                for c in 0..3 {
                    let top = at(x0, y0, c) * (1.0 - fx) + at(x0 + 1, y0, c) * fx;
                    let bottom = at(x0, y0 + 1, c) * (1.0 - fx) + at(x0 + 1, y0 + 1, c) * fx;
                    px[(y * width + x) * 3 + c] = (top * (1.0 - fy) + bottom * fy).round().clamp(0.0, 255.0) as u8;
                }
            }
        }
        let line = (width / 320).max(1);
        let mut frame = |b: [usize; 4], t: usize| {
            let (x0, y0) = (b[0].saturating_sub(t), b[1].saturating_sub(t));
            let (x1, y1) = ((b[0] + b[2] + t).min(width), (b[1] + b[3] + t).min(height));
            for y in y0..y1 {
                for x in x0..x1 {
                    let inside = x >= b[0] && x < b[0] + b[2] && y >= b[1] && y < b[1] + b[3];
                    if !inside {
                        px[(y * width + x) * 3..(y * width + x) * 3 + 3].copy_from_slice(&[255, 255, 255]);
                    }
                }
            }
        };
        frame(src, line);
        frame(dst, line + 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_inset_enlarges_its_region_into_its_corner() {
        let i = Inset::parse("0.5,0.5,0.1,0.1,4,tl").unwrap();
        let (w, h) = (100, 100);
        let mut px = vec![0u8; w * h * 3];
        // One red pixel in the region's centre becomes a red blob of about
        // 4x4 in the inset's centre.
        px[(55 * w + 55) * 3] = 255;
        i.apply(&mut px, w, h);
        let (src, dst) = i.boxes(w, h);
        assert_eq!((src, dst), ([50, 50, 10, 10], [2, 2, 40, 40]));
        let red =
            (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).filter(|&(x, y)| px[(y * w + x) * 3] > 100 && px[(y * w + x) * 3 + 1] < 50).collect::<Vec<_>>();
        assert!(red.iter().any(|&(x, y)| (x, y) == (2 + 22, 2 + 22)), "{red:?}");
        assert!(red.len() >= 9, "{} red pixels", red.len());
        assert!(Inset::parse("0.9,0.5,0.2,0.1,2,tl").unwrap_err().to_string().contains("inside the frame"));
        assert!(Inset::parse("0.5,0.5,0.1,0.1,4,up").unwrap_err().to_string().contains("corner"));
    }
}
