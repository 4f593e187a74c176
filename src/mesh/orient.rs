//! Consistent outward winding: neighbouring triangles are made to traverse
//! their shared edge in opposite directions, then each connected part is
//! flipped if its signed volume is negative. Refraction decides "entering"
//! or "leaving" from the normal, so a flipped face would swap n1 and n2.

use super::Mesh;
use std::collections::HashMap;

/// Reorients the mesh in place; returns how many triangles were flipped.
/// Edges shared by more than two triangles (non-manifold) are not used to
/// propagate orientation.
pub fn orient_outward(mesh: &mut Mesh) -> usize {
    let n = mesh.triangles.len();
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::with_capacity(n * 3 / 2);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(t as u32);
        }
    }
    let directed = |tri: &[u32; 3], a: u32, b: u32| (0..3).any(|e| tri[e] == a && tri[(e + 1) % 3] == b);
    let mut flip = vec![false; n];
    let mut seen = vec![false; n];
    let mut flipped = 0;
    let mut stack = Vec::new();
    for start in 0..n {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start as u32);
        let mut component = Vec::new();
        while let Some(t) = stack.pop() {
            component.push(t);
            let tri = oriented(mesh.triangles[t as usize], flip[t as usize]);
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                let users = &edges[&(a.min(b), a.max(b))];
                if users.len() != 2 {
                    continue;
                }
                let o = if users[0] == t { users[1] } else { users[0] };
                if seen[o as usize] {
                    continue;
                }
                seen[o as usize] = true;
                // A consistent neighbour runs the shared edge b -> a.
                flip[o as usize] = directed(&mesh.triangles[o as usize], a, b);
                stack.push(o);
            }
        }
        // Signed volume of the part (divergence theorem); negative = inward.
        let volume: f64 = component
            .iter()
            .map(|&t| {
                let [a, b, c] = oriented(mesh.triangles[t as usize], flip[t as usize]).map(|i| mesh.positions[i as usize].as_dvec3());
                a.dot(b.cross(c))
            })
            .sum();
        if volume < 0.0 {
            for &t in &component {
                flip[t as usize] = !flip[t as usize];
            }
        }
    }
    for (t, f) in flip.iter().enumerate() {
        if *f {
            mesh.triangles[t].swap(1, 2);
            flipped += 1;
        }
    }
    flipped
}

fn oriented(t: [u32; 3], flip: bool) -> [u32; 3] {
    if flip {
        [t[0], t[2], t[1]]
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;

    #[test]
    fn fixes_random_flips_and_inside_out_meshes() {
        let good = generate::icosphere(2);
        let mut m = good.clone();
        for (i, t) in m.triangles.iter_mut().enumerate() {
            if i % 3 == 0 {
                t.swap(1, 2);
            }
        }
        orient_outward(&mut m);
        assert_eq!(m.triangles, good.triangles);
        // Entirely inside-out: flipped back.
        let mut m = good.clone();
        m.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        assert_eq!(orient_outward(&mut m), good.triangles.len());
        assert_eq!(m.triangles, good.triangles);
    }
}
