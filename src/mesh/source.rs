//! Where a mesh comes from: an OFF file (or an OBJ, by its extension), or a shape generated in code for
//! sweeps over mesh size (`icosphere:S`, `torus:N`). Parsed once, where
//! the user names it.

use super::{generate, obj::read_obj, off::read_off, Mesh, MeshError};
use std::fmt;
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum MeshSource {
    /// An OFF or COFF file, or a Wavefront OBJ if its name ends in `.obj`.
    File(PathBuf),
    /// A unit icosphere of S subdivisions (20 * 4^S triangles), 0-8.
    Icosphere(u32),
    /// A torus of N x N/2 quads, N from 3 to 4096.
    Torus(u32),
}

/// Why a mesh's name is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SourceError {
    #[error("the file name is empty")]
    Empty,
    #[error("`{0}`: icosphere subdivisions must be 0-8")]
    Icosphere(String),
    #[error("`{0}`: torus segments must be 3-4096")]
    Torus(String),
}

impl MeshSource {
    /// `icosphere:S`, `torus:N`, or a file name.
    pub fn parse(s: &str) -> Result<MeshSource, SourceError> {
        let s = s.trim();
        if s.is_empty() {
            return Err(SourceError::Empty);
        }
        if let Some(n) = s.strip_prefix("icosphere:") {
            return n.parse().ok().filter(|n| *n <= 8).map(MeshSource::Icosphere).ok_or_else(|| SourceError::Icosphere(s.into()));
        }
        if let Some(n) = s.strip_prefix("torus:") {
            return n.parse().ok().filter(|n| (3..=4096).contains(n)).map(MeshSource::Torus).ok_or_else(|| SourceError::Torus(s.into()));
        }
        Ok(MeshSource::File(PathBuf::from(s)))
    }

    /// The mesh, refused if it has no triangle to render (the OBJ reader
    /// and the prism's `--obj` refuse the same).
    pub fn load(&self) -> Result<Mesh, MeshError> {
        Ok(match self {
            MeshSource::File(p) => {
                let obj = p.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj"));
                let m = if obj { read_obj(p)? } else { read_off(p)? };
                if m.triangles.is_empty() {
                    let s = &m.stats;
                    let kind = super::MeshErrorKind::NoFaces { faces: s.faces, small: s.skipped_small, degenerate: s.skipped_degenerate };
                    return Err(MeshError { path: p.display().to_string(), line: 0, kind });
                }
                m
            }
            MeshSource::Icosphere(n) => generate::icosphere(*n),
            MeshSource::Torus(n) => generate::torus(*n, n / 2).to_mesh(),
        })
    }
}

impl fmt::Display for MeshSource {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            MeshSource::File(p) => write!(f, "{}", p.display()),
            MeshSource::Icosphere(n) => write!(f, "icosphere:{n}"),
            MeshSource::Torus(n) => write!(f, "torus:{n}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_files_and_generated_shapes() {
        assert_eq!(MeshSource::parse("icosphere:3"), Ok(MeshSource::Icosphere(3)));
        assert_eq!(MeshSource::parse("torus:48"), Ok(MeshSource::Torus(48)));
        assert_eq!(MeshSource::parse("off/cube.off"), Ok(MeshSource::File("off/cube.off".into())));
        assert!(MeshSource::parse("icosphere:9").unwrap_err().to_string().contains("0-8"));
        assert!(MeshSource::parse("torus:2").is_err() && MeshSource::parse(" ").is_err());
        assert_eq!(MeshSource::Icosphere(2).load().unwrap().triangles.len(), 320);
        assert_eq!(MeshSource::parse("icosphere:4").unwrap().to_string(), "icosphere:4");
    }

    #[test]
    fn a_mesh_with_no_faces_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("flat.off");
        // Three vertices, a line and a face of zero area.
        std::fs::write(&p, "OFF\n3 2 0\n0 0 0\n1 0 0\n2 0 0\n2 0 1\n3 0 1 2\n").unwrap();
        let err = MeshSource::File(p.clone()).load().unwrap_err().to_string();
        assert_eq!(err, format!("{}: no faces to render (2 in the file: 1 with fewer than 3 vertices, 1 triangles of zero area)", p.display()));
    }
}
