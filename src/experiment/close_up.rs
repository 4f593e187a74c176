//! A close-up on a figure: a second render of the same scene file with a
//! few parameters changed (another camera on what the figure is about,
//! e.g. the screen's strip seen square on), pasted into a corner with a
//! thin frame, as a paper's figure enlarges a detail. (The `inset`
//! parameter, by contrast, magnifies a region of the same render.) Placed by fractions of the figure's size, so
//! one table serves the full and the quick size.
//!
//! ```toml
//! [close_up]
//! at = [0.02, 0.03]    # top-left corner: x from the left, y from the top
//! width = 0.45         # fraction of the figure's width
//! aspect = 2.5         # the close-up's width over its height
//! label = "the screen, enlarged"
//! [close_up.params]       # what differs from the figure's parameters
//! view = "screen"
//! ```

use super::labels::number;
use toml::Value;

#[derive(Clone, Debug, PartialEq)]
pub struct CloseUp {
    /// Parameters that differ from the figure's (the scene file checks
    /// those `parse` gives back as written and puts them here).
    pub params: Vec<crate::params::given::Given>,
    /// Top-left corner, fractions of the figure's width and height.
    pub at: [f64; 2],
    /// Width, a fraction of the figure's width.
    pub width: f64,
    /// Width over height.
    pub aspect: f64,
    pub label: Option<String>,
}

/// Why a `[close_up]` table is refused, naming the key (the caller adds
/// the file and line).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CloseUpError {
    #[error("must be a table ([close_up])")]
    NotTable,
    #[error("unknown key `{0}`; expected at, width, aspect, label and params")]
    UnknownKey(String),
    #[error("`at` must be two fractions of the figure, each from 0 to under 1")]
    AtRange,
    #[error("`at` must be [x, y], the top-left corner as fractions of the figure")]
    At,
    #[error("`width` must be a fraction of the figure's width above 0.05 that keeps the close-up inside it")]
    Width,
    #[error("`aspect` (width over height) must be from 0.2 to 10")]
    Aspect,
    #[error("`label` must be a string of 1 to 40 characters")]
    Label,
    #[error("`params` must be a table of what differs from the figure ([close_up.params]), not empty")]
    Params,
}

/// Reads a scene file's `[close_up]` table, and its parameters as written
/// (for the scene file to check by the mode's table); the error names the key.
pub fn parse(v: &Value) -> Result<(CloseUp, Vec<(String, Value)>), CloseUpError> {
    let Value::Table(t) = v else { return Err(CloseUpError::NotTable) };
    if let Some(k) = t.keys().find(|k| !["at", "width", "aspect", "label", "params"].contains(&k.as_str())) {
        return Err(CloseUpError::UnknownKey(k.clone()));
    }
    let at = match t.get("at") {
        Some(Value::Array(a)) if a.len() == 2 => match (number(a.first()), number(a.get(1))) {
            (Some(x), Some(y)) if (0.0..1.0).contains(&x) && (0.0..1.0).contains(&y) => [x, y],
            _ => return Err(CloseUpError::AtRange),
        },
        _ => return Err(CloseUpError::At),
    };
    let width = match number(t.get("width")) {
        Some(w) if w > 0.05 && at[0] + w <= 1.0 => w,
        _ => return Err(CloseUpError::Width),
    };
    let aspect = match number(t.get("aspect")) {
        Some(a) if (0.2..=10.0).contains(&a) => a,
        None => 16.0 / 9.0,
        _ => return Err(CloseUpError::Aspect),
    };
    let label = match t.get("label") {
        None => None,
        Some(Value::String(s)) if !s.trim().is_empty() && s.len() <= 40 => Some(s.clone()),
        _ => return Err(CloseUpError::Label),
    };
    let params = match t.get("params") {
        Some(Value::Table(p)) if !p.is_empty() => p.iter().map(|(k, v)| (k.clone(), v.clone())).collect(),
        _ => return Err(CloseUpError::Params),
    };
    Ok((CloseUp { params: Vec::new(), at, width, aspect, label }, params))
}

impl CloseUp {
    /// The close-up's size in pixels on a `w` x `h` figure, and its top-left
    /// corner; `None` if it would not fit below the corner.
    pub fn place(&self, w: usize, h: usize) -> Option<([usize; 2], [usize; 2])> {
        let iw = (self.width * w as f64).round().max(8.0) as usize;
        let ih = (iw as f64 / self.aspect).round().max(4.0) as usize;
        let (x, y) = ((self.at[0] * w as f64).round() as usize, (self.at[1] * h as f64).round() as usize);
        (x + iw <= w && y + ih <= h).then_some(([iw, ih], [x, y]))
    }
}

/// Pastes the `iw` x `ih` RGB image `close` into `buf` (`w` wide) at
/// `at`, inside a light frame 2 pixels wide (drawn over the figure).
pub fn paste(buf: &mut [u8], w: usize, close: &[u8], [iw, ih]: [usize; 2], [x, y]: [usize; 2]) {
    for r in 0..ih {
        let dst = ((y + r) * w + x) * 3;
        buf[dst..dst + iw * 3].copy_from_slice(&close[r * iw * 3..(r + 1) * iw * 3]);
    }
    let h = buf.len() / 3 / w;
    let mut set = |px: isize, py: isize| {
        if px >= 0 && py >= 0 && (px as usize) < w && (py as usize) < h {
            let i = (py as usize * w + px as usize) * 3;
            buf[i..i + 3].copy_from_slice(&[225, 225, 225]);
        }
    };
    let (x, y, iw, ih) = (x as isize, y as isize, iw as isize, ih as isize);
    for d in 1..=2 {
        for px in x - d..x + iw + d {
            set(px, y - d);
            set(px, y + ih - 1 + d);
        }
        for py in y - d..y + ih + d {
            set(x - d, py);
            set(x + iw - 1 + d, py);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_a_close_up_and_names_the_bad_key() {
        let v: Value = toml::from_str("[close_up]\nat = [0.1, 0.2]\nwidth = 0.4\naspect = 2\n[close_up.params]\nview = \"screen\"").unwrap();
        let (i, written) = parse(&v["close_up"]).unwrap();
        assert_eq!((i.at, i.width, i.aspect, written.len()), ([0.1, 0.2], 0.4, 2.0, 1));
        assert_eq!(i.place(1000, 500), Some(([400, 200], [100, 100])));
        assert_eq!(CloseUp { at: [0.1, 0.8], ..i }.place(1000, 500), None, "runs off the bottom");
        for (bad, says) in [
            ("[close_up]\nat = [0.7, 0]\nwidth = 0.4\n[close_up.params]\nview = \"screen\"", "`width`"),
            ("[close_up]\nat = [0, 0]\nwidth = 0.4", "`params`"),
            ("[close_up]\nat = [0, 0]\nwidth = 0.4\nzoom = 2\n[close_up.params]\nview = \"screen\"", "unknown key `zoom`"),
        ] {
            let v: Value = toml::from_str(bad).unwrap();
            let e = parse(&v["close_up"]).unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn pastes_inside_a_frame() {
        let (w, h) = (20, 10);
        let mut buf = vec![0u8; w * h * 3];
        paste(&mut buf, w, &[100u8; 4 * 3 * 3], [4, 3], [5, 4]);
        let px = |x: usize, y: usize| buf[(y * w + x) * 3];
        assert_eq!((px(5, 4), px(8, 6)), (100, 100), "the close-up's corners");
        assert_eq!((px(4, 4), px(3, 3), px(9, 7)), (225, 225, 225), "the frame");
        assert_eq!((px(2, 2), px(12, 4)), (0, 0), "outside the frame");
    }
}
