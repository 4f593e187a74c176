//! Chart text drawn glyph by glyph at each glyph's own side bearing, on
//! one baseline. plotters 0.3.7's bitmap text places each glyph's ink at
//! the pen position without its left side bearing, so letters crowd and a
//! space after a glyph with little bearing all but vanishes ("NOT HOLD"
//! read "NOTHOLD", "x = 0" read "x= 0"), and it rounds each glyph's top
//! on its own (a decimal point sat a pixel high: "1·02"). `Glyphs` wraps a
//! bitmap backend, passes every other drawing through, and draws text
//! itself with the same font, size, anchor and layout box, so a chart's
//! layout is unchanged.

use ab_glyph::{point, Font, FontRef, ScaleFont};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind};

/// The embedded font (DejaVu Sans), as registered with plotters.
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// A backend whose text is drawn by `draw_text` below.
pub struct Glyphs<DB>(pub DB);

/// The font could not be read (never, for the embedded one).
#[derive(Debug, thiserror::Error)]
#[error("the embedded font cannot be read: {0}")]
pub struct FontUnreadable(String);

impl<DB: DrawingBackend> DrawingBackend for Glyphs<DB> {
    type ErrorType = DB::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(&mut self, p: BackendCoord, c: BackendColor) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(p, c)
    }

    fn draw_line<S: BackendStyle>(&mut self, a: BackendCoord, b: BackendCoord, s: &S) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(a, b, s)
    }

    fn draw_rect<S: BackendStyle>(&mut self, a: BackendCoord, b: BackendCoord, s: &S, fill: bool) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(a, b, s, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(&mut self, path: I, s: &S) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_path(path, s)
    }

    fn draw_circle<S: BackendStyle>(&mut self, c: BackendCoord, r: u32, s: &S, fill: bool) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(c, r, s, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(&mut self, vert: I, s: &S) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, s)
    }

    fn blit_bitmap(&mut self, pos: BackendCoord, (w, h): (u32, u32), src: &[u8]) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, (w, h), src)
    }

    /// The text in the box plotters lays it out in (its width the sum of
    /// the advances, its baseline half the font's size below the top), each
    /// glyph at the pen position plus its own bearing, rounded once.
    fn draw_text<S: BackendTextStyle>(&mut self, text: &str, style: &S, pos: BackendCoord) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let font = FontRef::try_from_slice(FONT).map_err(|e| DrawingErrorKind::FontError(Box::new(FontUnreadable(e.to_string()))))?;
        let ((min_x, min_y), (max_x, max_y)) = style.layout_box(text).map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let size = style.size() as f32;
        let scaled = font.as_scaled(size);
        let baseline = (size / 2.0).round();
        let trans = style.transform();
        let (w, h) = self.get_size();
        let mut pen = 0f32;
        let mut prev = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                pen += scaled.kern(p, id);
            }
            prev = Some(id);
            if let Some(q) = scaled.outline_glyph(id.with_scale_and_position(size, point(pen, baseline))) {
                let b = q.px_bounds();
                let mut ink = Vec::new();
                q.draw(|x, y, cover| ink.push((b.min.x as i32 + x as i32, b.min.y as i32 + y as i32, cover)));
                for (x, y, cover) in ink {
                    let (x, y) = trans.transform(x + dx - min_x, y + dy - min_y);
                    let (x, y) = (pos.0 + x, pos.1 + y);
                    if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h && cover > 0.0 {
                        self.0.draw_pixel((x, y), BackendColor { alpha: color.alpha * cover.min(1.0) as f64, rgb: color.rgb })?;
                    }
                }
            }
            pen += scaled.h_advance(id);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    /// The columns with ink of `text` drawn alone at 14 px.
    fn inked_columns(text: &str) -> Vec<bool> {
        crate::experiment::plot::register();
        let (w, h) = (200u32, 40u32);
        let mut buf = vec![255u8; (w * h * 3) as usize];
        {
            let root = Glyphs(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
            root.draw(&Text::new(text.to_string(), (10, 10), crate::experiment::plot::font(14.0))).unwrap();
            root.present().unwrap();
        }
        (0..w).map(|x| (0..h).any(|y| buf[((y * w + x) * 3) as usize] < 200)).collect()
    }

    /// The widest run of blank columns between the first and last ink.
    fn widest_gap(cols: &[bool]) -> usize {
        let (first, last) = (cols.iter().position(|c| *c).unwrap(), cols.iter().rposition(|c| *c).unwrap());
        cols[first..=last].split(|c| *c).map(|run| run.len()).max().unwrap_or(0)
    }

    /// A space shows as a space after any glyph: "T H" and "x = 0" keep a
    /// gap of at least three pixels (a space is 4.5 px at 14 px), and two
    /// letters set close ("TH") keep none that wide.
    #[test]
    fn a_space_shows_after_every_glyph() {
        for text in ["T H", "x = 0", "NOT HOLD", "l a"] {
            let gap = widest_gap(&inked_columns(text));
            assert!(gap >= 3, "{text:?}: widest gap {gap} px");
        }
        assert!(widest_gap(&inked_columns("TH")) < 3);
    }
}
