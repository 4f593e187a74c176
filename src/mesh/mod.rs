//! Triangle meshes: the type the renderers use, the OFF and OBJ readers, polygon
//! triangulation, consistent outward orientation and generated meshes.

pub mod generate;
pub mod obj;
pub mod off;
pub mod orient;
pub mod source;
pub mod triangulate;

use crate::color::Rgb;
use crate::geometry::{Aabb, Triangle};
use glam::Vec3;
use std::fmt;

/// Colours a mesh file may carry.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshColors {
    None,
    /// One colour per vertex (COFF), interpolated across each triangle.
    PerVertex(Vec<Rgb>),
    /// One optional colour per triangle (from its source face).
    PerTriangle(Vec<Option<Rgb>>),
}

/// What loading skipped, so a user learns why a face count differs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshStats {
    /// Faces in the file.
    pub faces: usize,
    /// Faces with fewer than 3 vertices (points and lines): not surfaces.
    pub skipped_small: usize,
    /// Triangles of zero area dropped after triangulation.
    pub skipped_degenerate: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    pub colors: MeshColors,
    pub stats: MeshStats,
}

impl Mesh {
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }

    pub fn triangle(&self, i: usize) -> Triangle {
        let [a, b, c] = self.triangles[i];
        Triangle::new(self.positions[a as usize], self.positions[b as usize], self.positions[c as usize])
    }

    pub fn build_triangles(&self) -> Vec<Triangle> {
        (0..self.triangles.len()).map(|i| self.triangle(i)).collect()
    }

    /// Colour at barycentric `(u, v)` of triangle `tri`, if the mesh has one.
    pub fn color_at(&self, tri: usize, u: f32, v: f32) -> Option<Rgb> {
        match &self.colors {
            MeshColors::None => None,
            MeshColors::PerTriangle(c) => c[tri],
            MeshColors::PerVertex(c) => {
                let [a, b, cc] = self.triangles[tri];
                Some((1.0 - u - v) * c[a as usize] + u * c[b as usize] + v * c[cc as usize])
            }
        }
    }

    /// Applies `f` to every vertex position.
    pub fn transform(&mut self, f: impl Fn(Vec3) -> Vec3) {
        for p in &mut self.positions {
            *p = f(*p);
        }
    }
}

/// An error reading a mesh file: displays as `path:line: message`.
#[derive(Debug)]
pub struct MeshError {
    pub path: String,
    /// 1-based line, 0 when the error concerns the whole file.
    pub line: usize,
    pub kind: MeshErrorKind,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line > 0 {
            write!(f, "{}:{}: {}", self.path, self.line, self.kind)
        } else {
            write!(f, "{}: {}", self.path, self.kind)
        }
    }
}

impl std::error::Error for MeshError {}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeshErrorKind {
    /// The file could not be opened or read.
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
    /// NUL bytes, invalid UTF-8 or control characters: not a text file of
    /// the format read (`OFF` or `OBJ`).
    #[error("non-text data ({what}); only text {format} files are read")]
    NotText { format: &'static str, what: String },
    /// An OBJ statement tobj refused that the line check let through.
    #[error("tobj could not read the OBJ statement here: {0}")]
    Tobj(String),
    /// The first token is not an OFF keyword, e.g. `PLY`.
    #[error("expected the keyword OFF or COFF, found `{0}`")]
    MissingKeyword(String),
    /// NOFF, STOFF, 4OFF, nOFF, binary OFF and the like.
    #[error("unsupported OFF variant `{0}`: only OFF and COFF (text) are read")]
    Unsupported(String),
    /// A token that is not the number expected, e.g. `abc` as a coordinate.
    #[error("expected {what}, found `{token}`")]
    BadToken { what: String, token: String },
    /// NaN, infinity, or a value beyond f32's range.
    #[error("{what} `{token}` is not a finite number in range")]
    NotFinite { what: String, token: String },
    /// The body ends before the counts in the header are reached.
    #[error("file ends early: expected {0} (the counts in the header do not match the body)")]
    UnexpectedEof(String),
    #[error("face {face} refers to vertex {index}, but the file has {count} vertices")]
    IndexOutOfRange { face: usize, index: String, count: usize },
    #[error("{0}")]
    Invalid(String),
    /// A mesh with no triangle to render (no faces, or only points,
    /// lines and zero-area faces): refused, as an image of it would be
    /// black.
    #[error("no faces to render ({faces} in the file: {small} with fewer than 3 vertices, {degenerate} triangles of zero area)")]
    NoFaces { faces: usize, small: usize, degenerate: usize },
    /// Tokens after the last declared face.
    #[error("extra data `{0}` after the last declared face (the counts in the header do not match the body)")]
    TrailingData(String),
}
