//! Wavefront OBJ meshes through tobj, into the same `Mesh` type as OFF.
//!
//! tobj's errors carry no line number, so the file is first checked line by
//! line here (vertex and face syntax, finite numbers, indices in range,
//! text only); tobj then does the loading and triangulation, on the text
//! with its `#` comments cut (tobj reads `v 1 2 3 # note` as a bad colour).
//! Should tobj still refuse it, the line is found by loading ever shorter
//! beginnings of the text (a bisection), so the message names it. Winding is
//! made consistent and outward afterwards (`orient`), because refraction
//! reads "entering" or "leaving" from the normal (report 003's trouble).

use super::{Mesh, MeshColors, MeshError, MeshErrorKind, MeshStats};
use glam::Vec3;
use std::path::Path;

pub fn read_obj(path: &Path) -> Result<Mesh, MeshError> {
    let name = path.display().to_string();
    let err = |line: usize, kind: MeshErrorKind| MeshError { path: name.clone(), line, kind };
    let bytes = crate::data::read_input(path).map_err(|e| err(0, e.into()))?;
    let text = check(&bytes).map_err(|(line, kind)| err(line, kind))?;
    let (models, _) = load(&text).map_err(|e| err(failing_line(&text), MeshErrorKind::Tobj(e.to_string())))?;
    let mut mesh = Mesh { positions: Vec::new(), triangles: Vec::new(), colors: MeshColors::None, stats: MeshStats::default() };
    for m in models {
        let base = mesh.positions.len() as u32;
        let p = &m.mesh.positions;
        mesh.positions.extend(p.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        for t in m.mesh.indices.chunks_exact(3) {
            mesh.stats.faces += 1;
            let tri = [t[0] + base, t[1] + base, t[2] + base];
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            if super::triangulate::is_degenerate(a, b, c) {
                mesh.stats.skipped_degenerate += 1;
            } else {
                mesh.triangles.push(tri);
            }
        }
    }
    super::orient::orient_outward(&mut mesh);
    Ok(mesh)
}

fn load(text: &str) -> tobj::LoadResult {
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| Ok(Default::default()))
}

/// The 1-based line whose addition makes tobj refuse `text`: the first `k`
/// lines load and the first `k + 1` do not (bisection over the line count,
/// so about log2(lines) loads).
fn failing_line(text: &str) -> usize {
    let ends: Vec<usize> = text.match_indices('\n').map(|(i, _)| i + 1).chain((!text.ends_with('\n')).then_some(text.len())).collect();
    let fails = |k: usize| k > 0 && load(&text[..ends[k - 1]]).is_err();
    let (mut ok, mut bad) = (0, ends.len());
    if !fails(bad) {
        return 0;
    }
    while bad - ok > 1 {
        let mid = (ok + bad) / 2;
        if fails(mid) {
            bad = mid;
        } else {
            ok = mid;
        }
    }
    bad
}

/// Line-by-line check of the statements the renderer relies on; returns
/// the text with comments cut, line for line.
fn check(bytes: &[u8]) -> Result<String, (usize, MeshErrorKind)> {
    let not_text = |what: String| MeshErrorKind::NotText { format: "OBJ", what };
    let text =
        std::str::from_utf8(bytes).map_err(|e| (1 + bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count(), not_text("invalid UTF-8".into())))?;
    let mut cut = String::with_capacity(text.len());
    let (mut nv, mut nvt, mut nvn) = (0i64, 0i64, 0i64);
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        if let Some(b) = raw.bytes().find(|&b| b < 0x20 && b != b'\t' && b != b'\r') {
            return Err((line, not_text(format!("control byte 0x{b:02x}"))));
        }
        let content = raw.split('#').next().unwrap_or("");
        cut.push_str(content);
        cut.push('\n');
        let mut toks = content.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        let args: Vec<&str> = toks.collect();
        let numbers = |what: &str, counts: &[usize], said: &str| -> Result<(), (usize, MeshErrorKind)> {
            if !counts.contains(&args.len()) {
                return Err((line, MeshErrorKind::Invalid(format!("`{kw}` needs {said} numbers, found {}", args.len()))));
            }
            for a in &args {
                let v: f64 = a.parse().map_err(|_| (line, MeshErrorKind::BadToken { what: format!("a number in {what}"), token: a.to_string() }))?;
                if !v.is_finite() || v.abs() > f32::MAX as f64 {
                    return Err((line, MeshErrorKind::NotFinite { what: what.into(), token: a.to_string() }));
                }
            }
            Ok(())
        };
        match kw {
            "v" => {
                numbers("a vertex", &[3, 4, 6], "3, 4 (x y z w) or 6 (x y z r g b)")?;
                if args.len() == 4 && args[3].parse::<f64>() == Ok(0.0) {
                    return Err((line, MeshErrorKind::Invalid("a vertex's w is 0 (x y z are divided by it)".into())));
                }
                nv += 1;
            }
            "vt" => {
                numbers("a texture coordinate", &[2, 3], "2 or 3")?;
                nvt += 1;
            }
            "vn" => {
                numbers("a normal", &[3], "3")?;
                nvn += 1;
            }
            "f" => {
                if args.len() < 3 {
                    return Err((line, MeshErrorKind::Invalid(format!("a face needs at least 3 vertices, found {}", args.len()))));
                }
                for a in &args {
                    for (k, part) in a.split('/').enumerate() {
                        if part.is_empty() && k > 0 {
                            continue;
                        }
                        let count = [nv, nvt, nvn][k.min(2)];
                        let idx: i64 = part.parse().map_err(|_| (line, MeshErrorKind::BadToken { what: "a face index".into(), token: a.to_string() }))?;
                        let ok = if idx > 0 { idx <= count } else { idx < 0 && -idx <= count };
                        if !ok || k > 2 {
                            return Err((line, MeshErrorKind::Invalid(format!("face index `{a}` is out of range ({count} defined so far)"))));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(cut)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn loads_and_orients_a_mixed_winding_tetrahedron() {
        let dir = tempfile::tempdir().unwrap();
        // Two faces wound inward, two outward.
        let p = write(dir.path(), "t.obj", "# tetra\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
        let m = read_obj(&p).unwrap();
        assert_eq!(m.triangles.len(), 4);
        let vol: f32 = (0..4).map(|i| m.triangle(i).v0.dot(m.triangle(i).normal()) / 6.0).sum();
        assert!((vol - 1.0 / 6.0).abs() < 1e-6, "outward volume {vol}");
    }

    #[test]
    fn errors_name_the_line() {
        let dir = tempfile::tempdir().unwrap();
        for (text, needle) in [
            ("v 0 0 0\nv 1 0\n", "b.obj:2: `v` needs 3, 4 (x y z w) or 6 (x y z r g b) numbers, found 2"),
            ("v 0 0 0\nv 1 0 0 1 1\n", "b.obj:2: `v` needs 3, 4"),
            ("v 0 0 0\nv 1 0 0 0\n", "b.obj:2: a vertex's w is 0"),
            ("v 0 0 0\nvt 0.5\n", "b.obj:2: `vt` needs 2 or 3 numbers, found 1"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl\nf 1 2 3\n", "b.obj:5: tobj could not read the OBJ statement here: material parse error"),
            ("v 0 0 0\n\u{0}\n", "b.obj:2: non-text data (control byte 0x00); only text OBJ files are read"),
            ("v 0 0 0\nv 1 nan 0\n", "b.obj:2: a vertex `nan` is not a finite"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "b.obj:4: face index `4` is out of range (3 defined so far)"),
            ("v 0 0 0\nf 1 x 1\n", "b.obj:2: expected a face index, found `x`"),
            ("v 0 0 0\nf 1 1\n", "b.obj:2: a face needs at least 3 vertices"),
            ("v 0 0 0\n\u{1}\n", "b.obj:2: non-text data"),
        ] {
            let p = write(dir.path(), "b.obj", text);
            let e = read_obj(&p).unwrap_err().to_string();
            assert!(e.contains(needle), "{e} / {needle}");
        }
    }

    #[test]
    fn comments_after_statements_load() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(dir.path(), "c.obj", "v 0 0 0 # origin\nv 1 0 0\nv 0 1 0\r\nf 1 2 3 # the one face\n");
        assert_eq!(read_obj(&p).unwrap().triangles.len(), 1);
    }

    #[test]
    fn the_failing_line_is_found_by_bisection() {
        let body = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".repeat(40);
        for at in [1, 77, 160] {
            let mut lines: Vec<&str> = body.lines().collect();
            lines.insert(at - 1, "usemtl");
            assert_eq!(failing_line(&lines.join("\n")), at);
        }
        assert_eq!(failing_line(&body), 0);
    }
}
