//! Reader for Geomview's OFF format (text OFF and COFF).
//!
//! Follows the OOGL description of OFF: `[C]OFF` keyword (optionally glued
//! to the first count, `OFF3514 3546 0`, as ModelNet writes it), then
//! `NVertices NFaces NEdges`, the vertices `x y z [r g b [a]]`, then the faces
//! `k i1 .. ik [colour]`, where a face colour is whatever follows the indices
//! on the same line. `#` starts a comment anywhere; tokens may be split over
//! lines in any way (every number on its own line is fine).
//!
//! Choices where files in the wild differ:
//! - colours are integers 0-255 when every component is an integer and one
//!   exceeds 1, values 0-1 otherwise; alpha is read and ignored (opacity is
//!   a render setting);
//! - a COFF vertex colour has 3 or 4 components when the vertex sits on one
//!   line (the rest of the line), else 4 (Geomview's RGBA) for streamed files;
//! - a one-token face colour is a Geomview colormap index, which we do not
//!   have: the face keeps the object colour;
//! - faces of 1 or 2 vertices are skipped (not surfaces), zero-area triangles
//!   are dropped, counted in [`MeshStats`];
//! - NOFF, STOFF, 4OFF, nOFF and binary OFF are refused as unsupported.
//!
//! No allocation is sized by a count from the file: storage grows only as
//! data is actually read, so a header declaring billions of elements in a
//! tiny file fails fast with "file ends early".

use super::triangulate::triangulate;
use super::{Mesh, MeshColors, MeshError, MeshErrorKind, MeshStats};
use crate::color::Rgb;
use glam::Vec3;
use std::path::Path;

/// Reads and parses an OFF file; errors name the file and line.
pub fn read_off(path: &Path) -> Result<Mesh, MeshError> {
    let name = path.display().to_string();
    let bytes = crate::data::read_input(path).map_err(|e| MeshError { path: name.clone(), line: 0, kind: e.into() })?;
    parse_off(&bytes, &name)
}

/// Parses OFF text; `name` is used in error messages.
pub fn parse_off(bytes: &[u8], name: &str) -> Result<Mesh, MeshError> {
    let err = |line: usize, kind: MeshErrorKind| MeshError { path: name.to_string(), line, kind };
    let text = check_text(bytes).map_err(|(line, what)| err(line, MeshErrorKind::NotText { format: "OFF", what }))?;
    Parser { lex: Lexer::new(text) }.parse().map_err(|(line, kind)| err(line, kind))
}

/// Rejects binary data: invalid UTF-8, NUL and other control characters.
fn check_text(bytes: &[u8]) -> Result<&str, (usize, String)> {
    let line_of = |at: usize| 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
    let text = std::str::from_utf8(bytes).map_err(|e| (line_of(e.valid_up_to()), "invalid UTF-8".to_string()))?;
    if let Some(at) = text.bytes().position(|b| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0b | 0x0c) || b == 0x7f) {
        return Err((line_of(at), format!("control byte 0x{:02x}", bytes[at])));
    }
    Ok(text)
}

type PResult<T> = Result<T, (usize, MeshErrorKind)>;

/// Splits text into whitespace-separated tokens, skipping `#` comments and
/// keeping track of line numbers.
struct Lexer<'a> {
    s: &'a str,
    pos: usize,
    line: usize,
}

impl<'a> Lexer<'a> {
    fn new(s: &'a str) -> Self {
        Lexer { s, pos: 0, line: 1 }
    }

    /// Skips blanks and comments; with `same_line`, stops at a newline.
    /// Returns false if it stopped at a newline (or the end).
    fn skip(&mut self, same_line: bool) -> bool {
        let b = self.s.as_bytes();
        while self.pos < b.len() {
            match b[self.pos] {
                b'\n' => {
                    if same_line {
                        return false;
                    }
                    self.line += 1;
                    self.pos += 1;
                }
                b'#' => {
                    while self.pos < b.len() && b[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                c if c.is_ascii_whitespace() || c == 0x0b => self.pos += 1,
                _ => return true,
            }
        }
        false
    }

    fn take(&mut self) -> &'a str {
        let b = self.s.as_bytes();
        let start = self.pos;
        while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() && b[self.pos] != 0x0b && b[self.pos] != b'#' {
            self.pos += 1;
        }
        &self.s[start..self.pos]
    }

    /// Next token anywhere, with its line.
    fn next(&mut self) -> Option<(&'a str, usize)> {
        if self.skip(false) {
            let line = self.line;
            Some((self.take(), line))
        } else {
            None
        }
    }

    /// Next token only if it is on the current line.
    fn next_on_line(&mut self) -> Option<&'a str> {
        if self.skip(true) {
            Some(self.take())
        } else {
            None
        }
    }
}

struct Parser<'a> {
    lex: Lexer<'a>,
}

impl<'a> Parser<'a> {
    fn expect(&mut self, what: &str) -> PResult<(&'a str, usize)> {
        let line = self.lex.line;
        self.lex.next().ok_or((line, MeshErrorKind::UnexpectedEof(what.to_string())))
    }

    fn count(&mut self, what: &str, first: Option<(&'a str, usize)>) -> PResult<usize> {
        let (tok, line) = match first {
            Some(t) => t,
            None => self.expect(what)?,
        };
        match tok.parse::<u64>() {
            Ok(n) if n <= u32::MAX as u64 => Ok(n as usize),
            Ok(n) => Err((line, MeshErrorKind::Invalid(format!("{what} {n} exceeds the limit of {}", u32::MAX)))),
            Err(_) => Err((line, MeshErrorKind::BadToken { what: format!("{what} (a non-negative integer)"), token: tok.into() })),
        }
    }

    fn parse(mut self) -> PResult<Mesh> {
        let (colour_vertices, nv, nf) = self.header()?;
        // Capacity bounded by what the text could hold, never by the header.
        let cap = |n: usize, min_bytes: usize| n.min(self.lex.s.len() / min_bytes + 1);
        let (positions, vcolors) = self.vertices(nv, colour_vertices, cap(nv, 6))?;
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(cap(nf, 8));
        let mut tri_colors: Vec<Option<Rgb>> = Vec::with_capacity(cap(nf, 8));
        let mut stats = MeshStats { faces: nf, ..Default::default() };
        let mut poly: Vec<u32> = Vec::new();
        for f in 0..nf {
            let face_colour = self.face(f, nf, nv, &mut poly)?;
            if poly.len() < 3 {
                stats.skipped_small += 1;
                continue;
            }
            let before = triangles.len();
            stats.skipped_degenerate += triangulate(&positions, &poly, &mut triangles);
            tri_colors.resize(tri_colors.len() + (triangles.len() - before), face_colour);
        }
        if let Some((tok, line)) = self.lex.next() {
            return Err((line, MeshErrorKind::TrailingData(tok.chars().take(40).collect())));
        }
        let colors = if colour_vertices {
            MeshColors::PerVertex(vcolors)
        } else if tri_colors.iter().any(Option::is_some) {
            MeshColors::PerTriangle(tri_colors)
        } else {
            MeshColors::None
        };
        Ok(Mesh { positions, triangles, colors, stats })
    }

    /// The keyword (OFF or COFF, counts may be glued to it) and the vertex
    /// and face counts: (colour per vertex, vertices, faces).
    fn header(&mut self) -> PResult<(bool, usize, usize)> {
        let Some((kw, kw_line)) = self.lex.next() else {
            return Err((1, MeshErrorKind::MissingKeyword("end of file".into())));
        };
        let (colour_vertices, glued) = keyword(kw).map_err(|k| (kw_line, k))?;
        let first = match glued {
            Some(g) => Some((g, kw_line)),
            None => {
                // `OFF BINARY` declares the binary form.
                let save = (self.lex.pos, self.lex.line);
                match self.lex.next() {
                    Some((t, _)) if t.eq_ignore_ascii_case("BINARY") => {
                        return Err((kw_line, MeshErrorKind::Unsupported(format!("{kw} BINARY"))));
                    }
                    _ => (self.lex.pos, self.lex.line) = save,
                }
                None
            }
        };
        let nv = self.count("vertex count", first)?;
        let nf = self.count("face count", None)?;
        let _ne = self.count("edge count", None)?;
        Ok((colour_vertices, nv, nf))
    }

    /// `nv` vertices, each x y z and, for COFF, 3 or 4 colour components
    /// (on the vertex's line, or streamed over lines as some writers do).
    fn vertices(&mut self, nv: usize, colour_vertices: bool, capacity: usize) -> PResult<(Vec<Vec3>, Vec<Rgb>)> {
        let mut positions = Vec::with_capacity(capacity);
        let mut vcolors: Vec<Rgb> = Vec::new();
        let mut stream_colors = false;
        for i in 0..nv {
            let what = format!("vertex {} of {nv}", i + 1);
            let (p, line) = self.vec3(&what)?;
            positions.push(p);
            if colour_vertices {
                if i == 0 {
                    stream_colors = line != self.lex.line;
                }
                let toks: Vec<(&str, usize)> = if stream_colors {
                    (0..4).map(|_| self.expect(&format!("colour of {what}"))).collect::<PResult<_>>()?
                } else {
                    let l = self.lex.line;
                    std::iter::from_fn(|| self.lex.next_on_line()).take(5).map(|t| (t, l)).collect()
                };
                if toks.len() != 3 && toks.len() != 4 {
                    return Err((
                        self.lex.line,
                        MeshErrorKind::Invalid(format!("COFF {what} needs 3 or 4 colour components after x y z, found {}", toks.len())),
                    ));
                }
                vcolors.push(colour(&toks)?);
            }
        }
        Ok((positions, vcolors))
    }

    /// Face `f` of `nf`: its vertex indices into `poly`, and its colour if
    /// the line gives one.
    fn face(&mut self, f: usize, nf: usize, nv: usize, poly: &mut Vec<u32>) -> PResult<Option<Rgb>> {
        let what = format!("face {} of {nf}", f + 1);
        let (tok, line) = self.expect(&what)?;
        let k: u64 = tok.parse().map_err(|_| (line, MeshErrorKind::BadToken { what: format!("the vertex count of {what}"), token: tok.into() }))?;
        poly.clear();
        for _ in 0..k {
            let (tok, line) = self.expect(&format!("a vertex index of {what}"))?;
            let idx: i64 = tok.parse().map_err(|_| (line, MeshErrorKind::BadToken { what: format!("a vertex index of {what}"), token: tok.into() }))?;
            if idx < 0 || idx as u64 >= nv as u64 {
                return Err((line, MeshErrorKind::IndexOutOfRange { face: f + 1, index: tok.into(), count: nv }));
            }
            poly.push(idx as u32);
        }
        let line = self.lex.line;
        let ctoks: Vec<(&str, usize)> = std::iter::from_fn(|| self.lex.next_on_line()).take(5).map(|t| (t, line)).collect();
        match ctoks.len() {
            0 => Ok(None),
            1 => {
                // A colormap index (Geomview): checked, but we keep the object colour.
                ctoks[0]
                    .0
                    .parse::<u32>()
                    .map_err(|_| (line, MeshErrorKind::BadToken { what: format!("a colour or colormap index for {what}"), token: ctoks[0].0.into() }))?;
                Ok(None)
            }
            3 | 4 => Ok(Some(colour(&ctoks)?)),
            n => Err((line, MeshErrorKind::Invalid(format!("{what} has {n} colour components after its indices; expected 0, 1, 3 or 4")))),
        }
    }

    fn vec3(&mut self, what: &str) -> PResult<(Vec3, usize)> {
        let mut c = [0.0f32; 3];
        let mut first_line = 0;
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            let (tok, line) = self.expect(&format!("{axis} of {what}"))?;
            if i == 0 {
                first_line = line;
            }
            c[i] = number(tok, line, &format!("{axis} of {what}"))?;
        }
        Ok((Vec3::from(c), first_line))
    }
}

/// Interprets the keyword token. Returns whether vertices carry colours and
/// the count glued to the keyword, if any.
fn keyword(kw: &str) -> Result<(bool, Option<&str>), MeshErrorKind> {
    let Some(at) = kw.find("OFF") else {
        return Err(MeshErrorKind::MissingKeyword(kw.chars().take(40).collect()));
    };
    let (prefix, rest) = (&kw[..at], &kw[at + 3..]);
    let glued = if rest.is_empty() {
        None
    } else if rest.bytes().all(|b| b.is_ascii_digit()) {
        Some(rest)
    } else {
        return Err(MeshErrorKind::MissingKeyword(kw.chars().take(40).collect()));
    };
    // Geomview's prefixes: [ST][C][N][4][n]OFF.
    let valid = {
        let mut p = prefix;
        for opt in ["ST", "C", "N", "4", "n"] {
            p = p.strip_prefix(opt).unwrap_or(p);
        }
        p.is_empty()
    };
    match prefix {
        "" => Ok((false, glued)),
        "C" => Ok((true, glued)),
        _ if valid => Err(MeshErrorKind::Unsupported(format!("{prefix}OFF"))),
        _ => Err(MeshErrorKind::MissingKeyword(kw.chars().take(40).collect())),
    }
}

/// A finite float that fits in f32.
fn number(tok: &str, line: usize, what: &str) -> PResult<f32> {
    let v: f64 = tok.parse().map_err(|_| (line, MeshErrorKind::BadToken { what: format!("{what} (a number)"), token: tok.into() }))?;
    if !v.is_finite() || v.abs() > f32::MAX as f64 {
        return Err((line, MeshErrorKind::NotFinite { what: what.to_string(), token: tok.into() }));
    }
    Ok(v as f32)
}

/// 3 or 4 colour components: integers 0-255 or floats 0-1. Alpha is
/// checked and dropped. Integers that are all 0 or 1 (`1 0 0`) are read as
/// 0-1 values, as Geomview's float colours: as 0-255 they would be black.
fn colour(toks: &[(&str, usize)]) -> PResult<Rgb> {
    let ints = toks.iter().all(|(t, _)| t.parse::<i64>().is_ok()) && toks.iter().any(|(t, _)| t.parse::<i64>().is_ok_and(|v| v > 1));
    let mut c = [0.0f32; 4];
    for (i, (t, line)) in toks.iter().enumerate() {
        let v = number(t, *line, "colour component")?;
        let v = if ints { v / 255.0 } else { v };
        if !(0.0..=1.0).contains(&v) {
            let range = if ints { "0-255" } else { "0-1" };
            return Err((*line, MeshErrorKind::Invalid(format!("colour component `{t}` is outside {range}"))));
        }
        c[i] = v;
    }
    Ok(Rgb::new(c[0], c[1], c[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(s: &str) -> Mesh {
        parse_off(s.as_bytes(), "t.off").unwrap_or_else(|e| panic!("{e}"))
    }

    fn err(s: &[u8]) -> String {
        parse_off(s, "t.off").unwrap_err().to_string()
    }

    const TETRA: &str = "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

    #[test]
    fn plain_tetrahedron() {
        let m = ok(TETRA);
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
        assert_eq!(m.colors, MeshColors::None);
    }

    #[test]
    fn quirks_of_files_in_the_wild() {
        // Counts glued to the keyword (ModelNet), CRLF, tabs, comments before
        // the keyword and inside lines, every number on its own line.
        let glued = "# made by a tool\r\n\r\nOFF4 1 0\r\n0 0 0\t# origin\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n";
        let m = ok(glued);
        assert_eq!(m.triangles.len(), 2);
        let own_lines = TETRA.split_whitespace().collect::<Vec<_>>().join("\n");
        assert_eq!(ok(&own_lines).triangles, ok(TETRA).triangles);
        // Counts on the keyword's line.
        assert_eq!(ok("OFF 3 1 0\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n").triangles.len(), 1);
    }

    #[test]
    fn colours_int_and_float_with_and_without_alpha() {
        let m = ok("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n");
        assert_eq!(m.color_at(0, 0.0, 0.0), Some(Rgb::new(1.0, 0.0, 0.0)));
        assert_eq!(m.color_at(0, 1.0, 0.0), Some(Rgb::new(0.0, 1.0, 0.0)));
        let m = ok("COFF\n3 1 0\n0 0 0 1.0 0.5 0\n1 0 0 0 0.5 0\n0 1 0 0 0.5 0\n3 0 1 2\n");
        assert_eq!(m.color_at(0, 0.0, 0.0), Some(Rgb::new(1.0, 0.5, 0.0)));
        // Streamed COFF: every number on its own line, RGBA as Geomview writes.
        let s = "COFF 3 1 0 0 0 0 1 0 0 1 1 0 0 0 1 0 1 0 1 0 0 0 1 1 3 0 1 2".split(' ').collect::<Vec<_>>().join("\n");
        assert_eq!(ok(&s).color_at(0, 0.0, 1.0), Some(Rgb::new(0.0, 0.0, 1.0)));
        // Face colours on plain OFF, integers with alpha.
        let m = ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 128 0 255\n");
        assert_eq!(m.color_at(0, 0.2, 0.2), Some(Rgb::new(1.0, 128.0 / 255.0, 0.0)));
    }

    #[test]
    fn concave_polygon_and_degenerates() {
        // An L-shaped hexagon: a fan from vertex 0 would cover the notch.
        let s = "OFF\n6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 0 1 2 3 4 5\n";
        let m = ok(s);
        assert_eq!(m.triangles.len(), 4);
        let area: f32 = (0..4).map(|i| 0.5 * m.triangle(i).normal().length()).sum();
        assert!((area - 3.0).abs() < 1e-5, "area {area}");
        // Zero-area face, a line and a point: skipped, no NaN.
        let m = ok("OFF\n3 3 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n2 0 1\n1 0\n");
        assert!(m.triangles.is_empty());
        assert_eq!((m.stats.skipped_degenerate, m.stats.skipped_small), (1, 2));
        // Empty mesh and a single point are fine.
        assert!(ok("OFF\n0 0 0\n").positions.is_empty());
        assert_eq!(ok("OFF\n1 0 0\n5 5 5\n").positions.len(), 1);
    }

    #[test]
    fn malformed_input_names_the_line() {
        assert_eq!(err(b"PLY\n3 1 0\n"), "t.off:1: expected the keyword OFF or COFF, found `PLY`");
        assert_eq!(err(b""), "t.off:1: expected the keyword OFF or COFF, found `end of file`");
        assert!(err(b"NOFF\n").contains("unsupported OFF variant `NOFF`"));
        assert!(err(b"4OFF\n").contains("unsupported"));
        assert!(err(b"OFF BINARY\n").contains("unsupported"));
        assert!(err(b"OFF\n3 1 0\n0 0 0\n1 0 0\n").starts_with("t.off:4: file ends early: expected x of vertex 3 of 3"));
        assert!(err(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n").starts_with("t.off:6: face 1 refers to vertex 3, but the file has 3 vertices"));
        assert!(err(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n").contains("refers to vertex -1"));
        assert!(err(b"OFF\n1 0 0\nnan 0 0\n").starts_with("t.off:3: x of vertex 1 of 1 `nan` is not a finite number"));
        assert!(err(b"OFF\n1 0 0\n0 inf 0\n").contains("not a finite"));
        assert!(err(b"OFF\n1 0 0\n0 0 1e39\n").contains("not a finite"));
        assert!(err(b"OFF\n1 0 0\n0 0 zz\n").contains("expected z of vertex 1 of 1 (a number), found `zz`"));
        assert!(err(b"OFF\n1 0 0\n0 0 0\n7\n").starts_with("t.off:4: extra data `7`"));
        assert!(err(b"OFF\n3 1 0\n0\x000 0\n").starts_with("t.off:3: non-text data (control byte 0x00)"));
        assert!(err(b"OFF\n\xff\xfe\n").starts_with("t.off:2: non-text data (invalid UTF-8)"));
        assert!(err(b"OFF\n-3 1 0\n").contains("vertex count (a non-negative integer)"));
        assert!(err(b"COFF\n1 0 0\n0 0 0 300 0 0\n").contains("outside 0-255"));
    }

    #[test]
    fn huge_declared_counts_fail_without_allocating() {
        let e = err(b"OFF\n4000000000 4000000000 0\n0 0 0\n");
        assert!(e.contains("file ends early"), "{e}");
        assert!(err(b"OFF\n99999999999 1 0\n").contains("exceeds the limit"));
    }
}
