//! Shortcuts for finding the next surface among prisms, which are built of
//! convex parts (`World::add_extruded`). Inside a convex glass cell a ray
//! leaves through the nearest of the cell's planes it heads out of: no
//! polygon tests, and no other surface to try, since nothing lies inside a
//! prism. Outside, a convex solid (a prism whose whole outline is convex)
//! is met where the ray enters the last of the half-spaces that bound it,
//! if that comes before it leaves the first (Cyrus and Beck's clipping),
//! one test for the whole solid instead of one per face; and a ray that
//! has just left a convex solid cannot meet it again.
//!
//! Every shortcut finds the surface the plain scan finds, at a distance
//! computed the same way to the bit (`World::intersect_in`; a test checks
//! it on random rays).

use super::shape::{Face, FaceHit, Sphere};
use glam::DVec3;

/// Where a ray is, as far as the tracer knows. It only makes the search
/// for the next surface cheaper; every region finds the same surface.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Region {
    /// Not known (scan everything).
    Unknown,
    /// Outside every cell.
    Outside,
    /// Outside every cell, having just left convex solid `s` through one
    /// of its outer faces (refracted or reflected): a convex solid lies
    /// wholly behind each of its faces, so the ray cannot meet it again.
    Left(u32),
    /// Inside cell `c`.
    Cell(u32),
}

/// The cells and convex solids of a world, indexed from its faces'
/// `cells` and `solid` (`Cells::index`).
#[derive(Clone, Debug, Default)]
pub struct Cells {
    /// How many faces the world had when indexed: a world whose faces
    /// changed since is scanned whole (`valid`).
    faces: usize,
    /// Faces of no convex solid, scanned one by one from outside.
    pub loose: Vec<usize>,
    cells: Vec<Vec<Plane>>,
    /// Per convex solid: its outer planes, and the faces lying in each
    /// (coplanar faces of neighbouring parts share one).
    solids: Vec<Vec<(Plane, Vec<usize>)>>,
    /// Per convex solid, a sphere around it (centre, radius squared): a
    /// line that passes outside misses it.
    bounds: Vec<(DVec3, f64)>,
}

/// The faces other than `id` that lie in its plane.
fn coplanar(faces: &[Face], id: usize) -> Vec<usize> {
    let f = &faces[id];
    let scale = f.verts.iter().map(|v| v.abs().max_element()).fold(1e-3, f64::max);
    (0..faces.len())
        .filter(|&k| {
            k != id && faces[k].normal.cross(f.normal).length() < 1e-12 && faces[k].verts.iter().all(|v| (*v - f.verts[0]).dot(f.normal).abs() < 1e-12 * scale)
        })
        .collect()
}

/// Where a ray meets a convex solid from outside.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Entry {
    Miss,
    Hit(FaceHit),
    /// Rounding leaves the face in doubt (the ray passes an edge, or
    /// starts on the solid): test its faces one by one.
    InDoubt,
}

/// Whether hit `a` comes before `b` as the scan decides: nearer, or as
/// near and the lower index.
pub fn before(a: FaceHit, b: Option<FaceHit>) -> bool {
    b.is_none_or(|b| a.t < b.t || (a.t == b.t && a.face < b.face))
}

/// A bounding plane of a cell or solid: its face's first vertex (the
/// point the plane is measured from) and its normal turned to point out
/// of the cell or solid. Turning a normal negates every dot product with
/// it exactly (the rounded sum of negated products is the negated sum), so
/// signs and the distance `(at - o) . outward / d . outward` are the
/// face's own, to the bit.
#[derive(Clone, Debug)]
struct Plane {
    at: DVec3,
    outward: DVec3,
    face: usize,
    /// Other faces in the same plane (a floor a prism stands on, the caps
    /// of its neighbouring parts): the scan may meet one of them at the
    /// same distance, and then keeps the lower index.
    ties: Vec<usize>,
}

impl Cells {
    /// Reads the cells and solids off the faces.
    pub fn index(faces: &[Face], spheres: &[Sphere]) -> Cells {
        let count = |f: &dyn Fn(&Face) -> Option<u32>| faces.iter().filter_map(f).map(|c| c as usize + 1).max().unwrap_or(0);
        let mut cells = vec![Vec::new(); count(&|f| f.cells.iter().flatten().max().copied())];
        let mut solids: Vec<Vec<(Plane, Vec<usize>)>> = vec![Vec::new(); count(&|f| f.solid)];
        for (id, f) in faces.iter().enumerate() {
            for (side, c) in f.cells.iter().enumerate() {
                if let Some(c) = c {
                    // The back side's cell has the normal pointing out of it.
                    let out = if side == 1 { 1.0 } else { -1.0 };
                    cells[*c as usize].push(Plane { outward: f.normal * out, at: f.verts[0], face: id, ties: coplanar(faces, id) });
                }
            }
            if let (Some(s), true) = (f.solid, f.cells.contains(&None)) {
                let out = if f.cells[1].is_some() { 1.0 } else { -1.0 };
                let scale = f.verts.iter().map(|v| v.abs().max_element()).fold(1e-3, f64::max);
                let planes = &mut solids[s as usize];
                match planes.iter_mut().find(|(p, _)| (p.outward - f.normal * out).length() < 1e-12 && (f.verts[0] - p.at).dot(p.outward).abs() < 1e-12 * scale)
                {
                    Some((_, faces)) => faces.push(id),
                    None => planes.push((Plane { outward: f.normal * out, at: f.verts[0], face: id, ties: Vec::new() }, vec![id])),
                }
            }
        }
        // A cell something else reaches into (a face with a corner inside,
        // or whose plane cuts it, or a sphere near it) is not walked.
        for (c, planes) in cells.iter_mut().enumerate() {
            let own = |f: &Face| f.cells.contains(&Some(c as u32));
            let verts: Vec<DVec3> = faces.iter().filter(|f| own(f)).flat_map(|f| f.verts.iter().copied()).collect();
            let (lo, hi) = verts.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
            let eps = 1e-9 * (hi - lo).max_element().max(1e-9);
            let inside = |p: DVec3| planes.iter().all(|q| (p - q.at).dot(q.outward) < -eps);
            let crowded = faces.iter().filter(|f| !own(f)).any(|f| {
                let (flo, fhi) = f.verts.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
                let overlap = flo.cmplt(hi - eps).all() && fhi.cmpgt(lo + eps).all();
                let side = |v: &DVec3| (*v - f.verts[0]).dot(f.normal);
                let cuts = verts.iter().any(|v| side(v) > eps) && verts.iter().any(|v| side(v) < -eps);
                f.verts.iter().any(|&v| inside(v)) || (overlap && cuts)
            }) || spheres.iter().any(|s| (s.centre.cmpgt(lo - s.radius) & s.centre.cmplt(hi + s.radius)).all());
            if crowded {
                planes.clear();
            }
        }
        let loose = (0..faces.len()).filter(|&i| faces[i].solid.is_none()).collect();
        let bounds = (0..solids.len() as u32)
            .map(|s| {
                let verts: Vec<DVec3> = faces.iter().filter(|f| f.solid == Some(s)).flat_map(|f| f.verts.iter().copied()).collect();
                let centre = verts.iter().sum::<DVec3>() / verts.len() as f64;
                let r2 = verts.iter().map(|v| v.distance_squared(centre)).fold(0.0, f64::max);
                (centre, r2 * (1.0 + 1e-6) + 1e-18)
            })
            .collect();
        Cells { faces: faces.len(), loose, cells, solids, bounds }
    }

    /// Whether the index still describes these faces and has a cell to
    /// offer (without one, the plain scan is the quicker).
    pub fn valid(&self, faces: &[Face]) -> bool {
        self.faces == faces.len() && !self.cells.is_empty()
    }

    /// Whether every cell is walked (none had something reach into it).
    pub fn all_walked(&self) -> bool {
        self.cells.iter().all(|planes| !planes.is_empty())
    }

    /// Cell `c`'s planes as `leave` meets them: the face, the point the
    /// plane is measured from, its outward normal, and whether another
    /// face lies in it.
    pub fn planes(&self, c: usize) -> impl Iterator<Item = (usize, DVec3, DVec3, bool)> + '_ {
        self.cells.get(c).into_iter().flatten().map(|p| (p.face, p.at, p.outward, !p.ties.is_empty()))
    }

    /// How many convex solids there are.
    pub fn solids(&self) -> usize {
        self.solids.len()
    }

    /// The region of a point: the cell it lies in, or outside them all.
    pub fn region_at(&self, p: DVec3) -> Region {
        self.cells
            .iter()
            .position(|planes| !planes.is_empty() && planes.iter().all(|q| (p - q.at).dot(q.outward) < 0.0))
            .map_or(Region::Outside, |c| Region::Cell(c as u32))
    }

    /// Where a ray inside cell `c` leaves it: the nearest plane ahead that
    /// it heads out through (not `skip`). `None` if rounding left no such
    /// plane ahead, or the cell is not walked (then scan).
    pub fn leave(&self, faces: &[Face], c: usize, o: DVec3, d: DVec3, skip: Option<usize>) -> Option<FaceHit> {
        let planes = self.cells.get(c)?;
        // Plain indices, not options, in the loop (a face index is never
        // usize::MAX): the nearest plane ahead, and the one left.
        let skip = skip.unwrap_or(usize::MAX);
        let (mut best, mut best_t, mut from) = (usize::MAX, 0.0, usize::MAX);
        for (k, p) in planes.iter().enumerate() {
            if p.face == skip {
                // Reflected off this plane: rounding may have put the ray
                // just beyond a face lying in it, which the scan would meet.
                from = k;
                continue;
            }
            let denom = d.dot(p.outward);
            if !(denom > 0.0) {
                continue;
            }
            // As `Face::plane_distance` (`at` is the face's first vertex).
            let t = (p.at - o).dot(p.outward) / denom;
            if t > 0.0 && (best == usize::MAX || t < best_t) {
                (best, best_t) = (k, t);
            }
        }
        let plane = planes.get(best)?;
        let mut hit = FaceHit { t: best_t, face: plane.face };
        let from = planes.get(from).map_or(&[][..], |p| &p.ties[..]);
        if plane.ties.is_empty() && from.is_empty() {
            return Some(hit);
        }
        for &k in plane.ties.iter().chain(from) {
            if let Some(t) = faces[k].intersect_before(o, d, hit.t.next_up()) {
                let tie = FaceHit { t, face: k };
                if k != skip && before(tie, Some(hit)) {
                    hit = tie;
                }
            }
        }
        Some(hit)
    }

    /// Where a ray from outside every cell enters convex solid `s`.
    pub fn enter(&self, faces: &[Face], s: usize, o: DVec3, d: DVec3) -> Entry {
        // The bounding sphere first (d need not be unit: compare scaled).
        let (c, r2) = self.bounds[s];
        let oc = c - o;
        let (b, dd) = (oc.dot(d), d.length_squared());
        if oc.length_squared() * dd - b * b > r2 * dd {
            return Entry::Miss;
        }
        let (mut t_in, mut t_out, mut entry) = (f64::NEG_INFINITY, f64::INFINITY, None);
        for (p, faces) in &self.solids[s] {
            let (denom, gap) = (d.dot(p.outward), (p.at - o).dot(p.outward));
            if denom < 0.0 {
                let t = gap / denom;
                if t > t_in {
                    (t_in, entry) = (t, Some((p.face, faces)));
                }
            } else if denom > 0.0 {
                t_out = t_out.min(gap / denom);
            } else if !denom.is_finite() {
                return Entry::InDoubt;
            } else if gap < 0.0 {
                // Parallel to the plane and outside it.
                return Entry::Miss;
            }
        }
        let Some((first, coplanar)) = entry else { return Entry::Miss };
        if t_out < t_in || t_out <= 0.0 {
            return Entry::Miss;
        }
        if t_in <= 0.0 {
            // The ray starts on the solid (from a floor it stands on).
            return Entry::InDoubt;
        }
        // The face of the entry plane the scan would find there: at its own
        // distance, computed as the scan does, and inside its polygon (then
        // inside its bounding sphere too); none where rounding put the
        // entry on an edge.
        let mut hit = None;
        for &k in if coplanar.len() == 1 { std::slice::from_ref(&first) } else { coplanar } {
            let f = &faces[k];
            let t = f.plane_distance(o, d.dot(f.normal));
            if t > 0.0 && f.contains(o + t * d) && before(FaceHit { t, face: k }, hit) {
                hit = Some(FaceHit { t, face: k });
            }
        }
        hit.map_or(Entry::InDoubt, Entry::Hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::emit::uniform_sphere;
    use crate::sampling::Rng;
    use crate::scenes::{build, SceneKind, SceneOptions};

    /// In every scene with prisms, rays from inside a cell, from outside
    /// every cell and from a prism face (refracted or reflected off it)
    /// meet the same surface at the same distance, to the bit, through
    /// the shortcuts as by the plain scan of every face.
    #[test]
    fn every_region_finds_what_the_scan_finds() {
        let mut tried = [0usize; 4];
        for kind in [
            SceneKind::AmiciScreen,
            SceneKind::AmiciLamp,
            SceneKind::AmiciBench,
            SceneKind::SinglePrism,
            SceneKind::CornellPointlight,
            SceneKind::CornellMirrorTube,
            SceneKind::CornellLaser,
            SceneKind::DarkSide,
        ] {
            let mut o = SceneOptions::new(kind);
            (o.width, o.height) = (8, 8);
            let w = build(&o).unwrap();
            assert!(w.cells.valid(&w.faces) && !w.cells.cells.is_empty(), "{kind:?} has cells");
            assert!(w.cells.cells.iter().all(|p| !p.is_empty()), "{kind:?}: every cell is walked");
            let mut rng = Rng::new(11, kind as u64, 0);
            let (lo, hi) = w.faces.iter().flat_map(|f| f.verts.iter()).fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
            for i in 0..30_000 {
                let d = uniform_sphere(rng.f64(), rng.f64());
                let (o, skip, region) = match i % 4 {
                    0 => {
                        // A random point inside a random cell: a blend of its vertices.
                        let c = (rng.next_u64() % w.cells.cells.len() as u64) as u32;
                        let verts: Vec<DVec3> = w.faces.iter().filter(|f| f.cells.contains(&Some(c))).flat_map(|f| f.verts.clone()).collect();
                        let weights: Vec<f64> = verts.iter().map(|_| rng.f64() + 0.05).collect();
                        let p = verts.iter().zip(&weights).map(|(v, k)| *v * *k).sum::<DVec3>() / weights.iter().sum::<f64>();
                        assert_eq!(w.cells.region_at(p), Region::Cell(c));
                        (p, None, Region::Cell(c))
                    }
                    1 => {
                        let p = lo + (hi - lo) * DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 1.2 - (hi - lo) * 0.1;
                        (p, None, w.cells.region_at(p))
                    }
                    3 => {
                        // Where a prism stands on a floor: leaving the floor
                        // under the prism; or reflected inside off the
                        // prism's base from a point rounding put a hair
                        // beyond the floor.
                        let Some((c, k, tie)) = w.cells.cells.iter().enumerate().find_map(|(c, planes)| {
                            planes.iter().find_map(|p| p.ties.iter().find(|&&t| w.faces[t].solid.is_none()).map(|&t| (c as u32, p.face, t)))
                        }) else {
                            continue;
                        };
                        let f = &w.faces[k];
                        let weights: Vec<f64> = f.verts.iter().map(|_| rng.f64() + 0.05).collect();
                        let p = f.verts.iter().zip(&weights).map(|(v, k)| *v * *k).sum::<DVec3>() / weights.iter().sum::<f64>();
                        if rng.f64() < 0.5 {
                            (p, Some(tie), w.region_after(tie, d))
                        } else {
                            let out = if f.cells[1] == Some(c) { f.normal } else { -f.normal };
                            let d = if d.dot(out) > 0.0 { d - 2.0 * d.dot(out) * out } else { d };
                            let q = p + out * (1e-33 * rng.f64());
                            let (a, b) = (w.intersect_in(q, d, Some(k), Region::Cell(c)), w.intersect(q, d, Some(k)));
                            assert_eq!(a.map(|h| (h.t.to_bits(), h.face)), b.map(|h| (h.t.to_bits(), h.face)), "{kind:?} ray {i} from {q} along {d}");
                            (p, Some(tie), w.region_after(tie, d))
                        }
                    }
                    _ => {
                        // Leaving a prism face, to either side.
                        let prism: Vec<usize> = (0..w.faces.len()).filter(|&k| w.faces[k].cells != [None, None]).collect();
                        let k = prism[(rng.next_u64() % prism.len() as u64) as usize];
                        let f = &w.faces[k];
                        let weights: Vec<f64> = f.verts.iter().map(|_| rng.f64() + 0.05).collect();
                        let p = f.verts.iter().zip(&weights).map(|(v, k)| *v * *k).sum::<DVec3>() / weights.iter().sum::<f64>();
                        (p, Some(k), w.region_after(k, d))
                    }
                };
                tried[i % 4] += 1;
                let (a, b) = (w.intersect_in(o, d, skip, region), w.intersect(o, d, skip));
                assert_eq!(a.map(|h| (h.t.to_bits(), h.face)), b.map(|h| (h.t.to_bits(), h.face)), "{kind:?} ray {i} from {o} along {d} in {region:?}");
            }
        }
        assert!(tried[..3].iter().all(|&n| n > 30_000) && tried[3] > 5000, "{tried:?}");
    }

    /// The Amici prism and the single prism are convex solids; a prism
    /// train whose outline has a notch is not, and keeps the scan.
    #[test]
    fn convex_outlines_are_found() {
        for kind in [SceneKind::AmiciScreen, SceneKind::SinglePrism] {
            let w = build(&SceneOptions::new(kind)).unwrap();
            assert_eq!(w.cells.solids(), 1, "{kind:?}");
        }
        let mut w = crate::world::World::new("notch", vec![crate::world::Medium::Air], 8, 8);
        let v = glam::DVec2::new;
        // Two triangles sharing an edge, making a diamond.
        w.add_extruded("diamond", &[([v(0.0, 0.0), v(1.0, 0.2), v(0.0, 1.0)], 0), ([v(0.0, 0.0), v(0.0, 1.0), v(-1.0, 0.2)], 0)], 0.0, 1.0);
        assert_eq!(w.cells.solids(), 1, "a diamond is convex");
        let mut w = crate::world::World::new("notch", vec![crate::world::Medium::Air], 8, 8);
        w.add_extruded(
            "dart",
            &[([v(0.0, 0.0), v(1.0, 0.5), v(0.0, 1.0)], 0), ([v(0.0, 1.0), v(1.0, 0.5), v(1.0, 1.5)], 0), ([v(0.0, 1.0), v(1.0, 1.5), v(0.0, 2.0)], 0)],
            0.0,
            1.0,
        );
        assert_eq!(w.cells.solids(), 1, "a train whose outline is convex");
        let mut w = crate::world::World::new("notch", vec![crate::world::Medium::Air], 8, 8);
        w.add_extruded("dart", &[([v(0.0, 0.0), v(1.0, 0.5), v(0.0, 1.0)], 0), ([v(0.0, 1.0), v(1.0, 0.5), v(2.0, 0.3)], 0)], 0.0, 1.0);
        assert_eq!(w.cells.solids(), 0, "a notched train is not");
        assert_eq!(w.cells.cells.len(), 2);
        // A card through a prism, or a ball in it, and its cell is not
        // walked: rays in it find the card or the ball by the scan.
        for crowd in 0..2 {
            let mut w = build(&SceneOptions::new(SceneKind::SinglePrism)).unwrap();
            let (lo, hi) = w
                .faces
                .iter()
                .filter(|f| f.cells != [None, None])
                .flat_map(|f| f.verts.iter())
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
            let mid = (lo + hi) / 2.0;
            if crowd == 0 {
                w.faces.push(Face::rect(
                    "card",
                    DVec3::new(mid.x + 2e-3, lo.y - 1.0, lo.z - 1.0),
                    DVec3::Y * 10.0,
                    DVec3::Z * 10.0,
                    crate::world::Surface::Mirror { reflectance: 1.0 },
                ));
            } else {
                w.spheres.push(crate::world::Sphere {
                    name: "ball".into(),
                    centre: mid,
                    radius: 1e-3,
                    surface: crate::world::Surface::Mirror { reflectance: 1.0 },
                });
            }
            w.build_accel();
            assert!(w.cells.cells[0].is_empty(), "case {crowd}");
            let inside = mid + DVec3::new(0.0, 0.0, 1e-4);
            let (a, b) = (w.intersect_in(inside, DVec3::X, None, Region::Cell(0)), w.intersect(inside, DVec3::X, None));
            assert_eq!(a, b);
            assert!(a.is_some_and(|h| h.face >= 5), "the card or the ball: {a:?}");
        }
    }
}
