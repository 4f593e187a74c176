//! Labels on a figure: short texts a scene file places on its image, as an
//! author labels a photograph for a paper ("prism", "screen", "546 nm").
//! Each stands at a fraction of the image's width and height, so one list
//! serves the full and the quick size; the text is white with a dark
//! outline, sized to the image's height, so it reads on light and dark.
//!
//! ```toml
//! [[label]]
//! text = "546 nm"
//! at = [0.42, 0.9]     # centre of the text: x from the left, y from the top
//! ```

use super::plot::register;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use toml::Value;

#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub text: String,
    /// Centre of the text, as fractions of the width and height (0..=1).
    pub at: [f64; 2],
}

/// A TOML number, integer or float, as f64 (`at = [1, 0.5]`).
pub(super) fn number(v: Option<&Value>) -> Option<f64> {
    v.and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
}

/// Why a scene file's labels are refused (the entry, counted from 1, and
/// its key), or could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum LabelError {
    #[error("must be an array of tables ([[label]])")]
    NotArray,
    #[error("entry {0} must be a table with `text` and `at`")]
    NotTable(usize),
    #[error("entry {0}: unknown key `{1}`; expected text and at")]
    UnknownKey(usize, String),
    #[error("entry {0}: `text` must be a string of 1 to 40 characters")]
    Text(usize),
    #[error("entry {0}: `at` must be two fractions of the image, each from 0 to 1")]
    AtRange(usize),
    #[error("entry {0}: `at` must be [x, y], fractions of the width and height")]
    At(usize),
    #[error(transparent)]
    Draw(#[from] DrawingAreaErrorKind<<BitMapBackend<'static> as plotters::backend::DrawingBackend>::ErrorType>),
}

/// Reads the `label` array of a scene file; the error names the entry and
/// its key.
pub fn parse(v: &Value) -> Result<Vec<Label>, LabelError> {
    let Value::Array(items) = v else { return Err(LabelError::NotArray) };
    items
        .iter()
        .enumerate()
        .map(|(i, item)| {
            let n = i + 1;
            let Value::Table(t) = item else { return Err(LabelError::NotTable(n)) };
            if let Some(k) = t.keys().find(|k| !["text", "at"].contains(&k.as_str())) {
                return Err(LabelError::UnknownKey(n, k.clone()));
            }
            let text = match t.get("text") {
                Some(Value::String(s)) if !s.trim().is_empty() && s.len() <= 40 => s.clone(),
                _ => return Err(LabelError::Text(n)),
            };
            let at = match t.get("at") {
                Some(Value::Array(a)) if a.len() == 2 => match (number(a.first()), number(a.get(1))) {
                    (Some(x), Some(y)) if (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y) => [x, y],
                    _ => return Err(LabelError::AtRange(n)),
                },
                _ => return Err(LabelError::At(n)),
            };
            Ok(Label { text, at })
        })
        .collect()
}

/// Draws `labels` on the 8-bit RGB image `buf` (`w` x `h`).
pub fn draw(buf: &mut [u8], w: usize, h: usize, labels: &[Label]) -> Result<(), LabelError> {
    register();
    let size = (h as f64 / 14.0).clamp(11.0, 22.0);
    let root = super::glyphs::Glyphs(BitMapBackend::with_buffer(buf, (w as u32, h as u32))).into_drawing_area();
    let centre = Pos::new(HPos::Center, VPos::Center);
    for l in labels {
        let (x, y) = ((l.at[0] * w as f64).round() as i32, (l.at[1] * h as f64).round() as i32);
        let style = |c: &RGBColor| super::plot::font(size).color(c).pos(centre);
        // A dark outline one pixel wide, then the text.
        for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)] {
            root.draw(&Text::new(l.text.as_str(), (x + dx, y + dy), style(&RGBColor(10, 10, 10))))?;
        }
        root.draw(&Text::new(l.text.as_str(), (x, y), style(&RGBColor(235, 235, 235))))?;
    }
    Ok(root.present()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_labels_and_names_the_bad_entry() {
        let v: Value = toml::from_str("label = [{ text = \"prism\", at = [0.5, 1] }]").unwrap();
        assert_eq!(parse(&v["label"]).unwrap(), vec![Label { text: "prism".into(), at: [0.5, 1.0] }]);
        for (bad, says) in [
            ("label = [{ text = \"a\", at = [1.5, 0] }]", "entry 1: `at`"),
            ("label = [{ text = \"a\", at = [0.5, 0.5] }, { at = [0, 0] }]", "entry 2: `text`"),
            ("label = [{ text = \"a\", at = [0.5, 0.5], size = 3 }]", "unknown key `size`"),
            ("label = 3", "array of tables"),
        ] {
            let v: Value = toml::from_str(bad).unwrap();
            let e = parse(&v["label"]).unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn draws_light_text_with_a_dark_outline_where_it_is_placed() {
        let (w, h) = (400, 280);
        let mut buf = vec![128u8; w * h * 3];
        draw(&mut buf, w, h, &[Label { text: "prism".into(), at: [0.25, 0.5] }]).unwrap();
        let px = |x: usize, y: usize| buf[(y * w + x) * 3];
        let changed = |x0: usize, x1: usize| (x0..x1).flat_map(|x| (0..h).map(move |y| (x, y))).filter(|&(x, y)| px(x, y) != 128).count();
        let (left, right) = (changed(0, w / 2), changed(w / 2, w));
        assert!(left > 50 && right == 0, "text on the left half only: {left} and {right} pixels changed");
        let (bright, dark) = (buf.chunks(3).filter(|p| p[0] > 200).count(), buf.chunks(3).filter(|p| p[0] < 40).count());
        assert!(bright > 20 && dark > 20, "{bright} light and {dark} dark pixels");
    }
}
