//! The separating axis test restricted to the facets of the Minkowski difference, for
//! convex pieces with many faces.
//!
//! The penetration depth of two convex polytopes is the smallest support distance of
//! M = A ⊕ (−B) over M's facet normals. Those normals are
//! - A's face normals (the other support found by hill-climbing over B's vertices),
//! - the reverses of B's face normals,
//! - the normals e_A × e_B of edge pairs whose arcs on the Gauss map intersect (each
//!   edge's arc joins the normals of its two faces; B's arcs are negated), found through
//!   a bounding volume hierarchy over the arcs.
//!
//! So the cost grows with the number of faces and edges, not with their product as the
//! plain test over all edge pairs does; on penetrating pairs the depth is the same.

use glam::{DAffine3, DMat3, DVec3};

use super::bvh::Bvh;
use super::separation::Separation;
use crate::geometry::{Aabb, ConvexPolytope, weld};
use crate::tolerance::ROUNDOFF_REL;

/// A convex polytope with its vertex adjacency and edge-face incidence.
#[derive(Clone, Debug)]
pub(crate) struct GaussHull {
    vertices: Vec<DVec3>,
    neighbours: Vec<Vec<u32>>,
    normals: Vec<DVec3>,
    /// A vertex on each face (for offsets after a transform).
    face_vertex: Vec<u32>,
    /// Each edge once: end vertices and the two faces it bounds.
    edges: Vec<([u32; 2], [u32; 2])>,
    /// Faces in Morton order of their normals, so that consecutive faces have close
    /// normals and a support search can start where the last one ended.
    face_order: Vec<u32>,
    /// The hierarchy over the edges' arcs (n_f, n_g), in this hull's own frame: the
    /// arcs of A when this hull is A.
    arcs: Bvh,
    /// The same over the reversed arcs (-n_f, -n_g): the arcs of -B when this hull is B.
    reversed_arcs: Bvh,
}

impl GaussHull {
    /// The polytope's topology, or `None` if its faces do not close up consistently
    /// (then callers fall back to the plain test).
    pub(crate) fn new(polytope: &ConvexPolytope, eps: f64) -> Option<GaussHull> {
        let vertices = polytope.vertices().to_vec();
        // Weld the vertices followed by every face corner: the vertices are pairwise
        // farther apart than eps, so each keeps its own index and a corner maps to the
        // vertex it lies on (or to a new index past the vertices: inconsistent faces).
        let corners: Vec<DVec3> = polytope.faces().iter().flat_map(|f| f.points.iter().copied()).collect();
        let all: Vec<DVec3> = vertices.iter().chain(&corners).copied().collect();
        let (_, ids_of) = weld(&all, eps);
        let mut corner_ids = ids_of[vertices.len()..].iter().copied();
        let mut faces_of_edge: std::collections::BTreeMap<(u32, u32), Vec<u32>> = Default::default();
        let mut neighbours = vec![Vec::new(); vertices.len()];
        let mut face_vertex = Vec::new();
        for (f, face) in polytope.faces().iter().enumerate() {
            let ids: Vec<u32> = corner_ids.by_ref().take(face.points.len()).collect();
            if ids.iter().any(|&i| i as usize >= vertices.len()) {
                return None;
            }
            face_vertex.push(ids[0]);
            for (k, &a) in ids.iter().enumerate() {
                let b = ids[(k + 1) % ids.len()];
                if a == b {
                    continue;
                }
                faces_of_edge.entry((a.min(b), a.max(b))).or_default().push(f as u32);
                if !neighbours[a as usize].contains(&b) {
                    neighbours[a as usize].push(b);
                    neighbours[b as usize].push(a);
                }
            }
        }
        let mut edges = Vec::with_capacity(faces_of_edge.len());
        for ((a, b), faces) in faces_of_edge {
            let [f, g] = <[u32; 2]>::try_from(faces.as_slice()).ok()?;
            edges.push(([a, b], [f, g]));
        }
        let normals: Vec<DVec3> = polytope.faces().iter().map(|f| f.normal).collect();
        let mut face_order: Vec<u32> = (0..normals.len() as u32).collect();
        face_order.sort_by_key(|&f| morton(normals[f as usize]));
        let arc_boxes = |sign: f64| -> Vec<Aabb> {
            edges
                .iter()
                .map(|(_, [f, g])| arc_bounds(normals[*f as usize] * sign, normals[*g as usize] * sign))
                .collect()
        };
        let (arcs, reversed_arcs) = (Bvh::new(&arc_boxes(1.0)), Bvh::new(&arc_boxes(-1.0)));
        Some(GaussHull {
            vertices,
            neighbours,
            normals,
            face_vertex,
            edges,
            face_order,
            arcs,
            reversed_arcs,
        })
    }

    /// This hull's geometry moved by a rigid transform (the topology is shared).
    pub(crate) fn placed(&self, t: &DAffine3) -> Placed<'_> {
        let vertices: Vec<DVec3> = self.vertices.iter().map(|&p| t.transform_point3(p)).collect();
        let normals: Vec<DVec3> = self
            .normals
            .iter()
            .map(|&n| t.transform_vector3(n).normalize())
            .collect();
        let offsets = normals
            .iter()
            .zip(&self.face_vertex)
            .map(|(n, &v)| n.dot(vertices[v as usize]))
            .collect();
        Placed {
            hull: self,
            vertices,
            normals,
            offsets,
            rotation: t.matrix3,
        }
    }
}

/// A [`GaussHull`]'s geometry in the frame of a comparison.
#[derive(Clone, Debug)]
pub(crate) struct Placed<'a> {
    hull: &'a GaussHull,
    vertices: Vec<DVec3>,
    normals: Vec<DVec3>,
    offsets: Vec<f64>,
    /// The linear part of the placement (rotation).
    rotation: DMat3,
}

impl Placed<'_> {
    /// The smallest projection of the vertices on `direction`, by hill-climbing from
    /// vertex `start` (on a convex polytope a local minimum is global); returns the
    /// value and the vertex reaching it.
    fn min_along(&self, direction: DVec3, start: u32) -> (f64, u32) {
        let mut at = start;
        let mut best = direction.dot(self.vertices[at as usize]);
        loop {
            let next = self.hull.neighbours[at as usize]
                .iter()
                .map(|&n| (direction.dot(self.vertices[n as usize]), n))
                .min_by(|x, y| x.0.total_cmp(&y.0));
            match next {
                Some((value, n)) if value < best => {
                    best = value;
                    at = n;
                }
                _ => return (best, at),
            }
        }
    }

    /// The arc on the Gauss map between two faces' normals, in the comparison frame.
    fn arc_of(&self, f: u32, g: u32) -> (DVec3, DVec3) {
        (self.normals[f as usize], self.normals[g as usize])
    }
}

/// Interleaves the bits of a unit vector's quantised coordinates.
fn morton(n: DVec3) -> u64 {
    let q = |c: f64| (((c + 1.0) * 0.5 * 1023.0).round().clamp(0.0, 1023.0)) as u64;
    let spread = |mut x: u64| {
        let mut out = 0;
        for bit in 0..10 {
            out |= (x & 1) << (3 * bit);
            x >>= 1;
        }
        out
    };
    spread(q(n.x)) | spread(q(n.y)) << 1 | spread(q(n.z)) << 2
}

/// The box around a short great-circle arc from `u` to `v` (unit vectors).
fn arc_bounds(u: DVec3, v: DVec3) -> Aabb {
    let half_angle = 0.5 * u.dot(v).clamp(-1.0, 1.0).acos();
    Aabb::around([u, v]).inflated(1.0 - half_angle.cos() + ROUNDOFF_REL)
}

/// Whether arcs (a, b) and (c, d) on the unit sphere cross (Gregorius's test).
fn arcs_cross(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> bool {
    let bxa = b.cross(a);
    let dxc = d.cross(c);
    let (cba, dba) = (c.dot(bxa), d.dot(bxa));
    let (adc, bdc) = (a.dot(dxc), b.dot(dxc));
    cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0
}

/// SAT over the facets of A ⊕ (−B); both hulls in the same frame.
/// Stops at the first axis whose overlap is at most `stop_at` (0: one that separates
/// or touches; `f64::NEG_INFINITY`: never): the depth returned is then only an upper
/// bound, enough to know that the pair does not penetrate by more.
pub(crate) fn separate(a: &Placed<'_>, b: &Placed<'_>, stop_at: f64) -> Separation {
    let mut best = Separation {
        depth: f64::INFINITY,
        axis: DVec3::X,
        offset: 0.0,
    };
    let mut consider = |depth: f64, axis: DVec3, offset: f64| {
        if depth < best.depth {
            best = Separation { depth, axis, offset };
        }
    };
    // A's faces: h_M(n) = offset_A - min_B(n).
    let mut start = 0;
    for &f in &a.hull.face_order {
        let (n, offset) = (a.normals[f as usize], a.offsets[f as usize]);
        let (min_b, at) = b.min_along(n, start);
        start = at;
        let depth = offset - min_b;
        if depth <= stop_at {
            return Separation::bound(depth, n);
        }
        consider(depth, n, 0.5 * (offset + min_b));
    }
    // B's faces, reversed: h_M(-m) = offset_B - min_A(m).
    let mut start = 0;
    for &g in &b.hull.face_order {
        let (m, offset) = (b.normals[g as usize], b.offsets[g as usize]);
        let (min_a, at) = a.min_along(m, start);
        start = at;
        let depth = offset - min_a;
        if depth <= stop_at {
            return Separation::bound(depth, -m);
        }
        consider(depth, -m, -0.5 * (offset + min_a));
    }
    // Edge pairs whose arcs (A's, and -B's) cross: one traversal of both hierarchies,
    // B's boxes mapped into A's own frame; the exact test in A's own frame too.
    let b_to_a = DAffine3::from_mat3(a.rotation.inverse() * b.rotation);
    a.hull
        .arcs
        .query_pairs_dense(&b.hull.reversed_arcs, &b_to_a, 0.0, |ea, eb| {
            let ([p, q], [f, g]) = a.hull.edges[ea as usize];
            let ([r, s], [fb, gb]) = b.hull.edges[eb as usize];
            let (n1, n2) = (a.hull.normals[f as usize], a.hull.normals[g as usize]);
            let (c, d) = (
                b_to_a.matrix3 * -b.hull.normals[fb as usize],
                b_to_a.matrix3 * -b.hull.normals[gb as usize],
            );
            if !arcs_cross(n1, n2, c, d) {
                return;
            }
            let (pa, qa) = (a.vertices[p as usize], a.vertices[q as usize]);
            let (pb, qb) = (b.vertices[r as usize], b.vertices[s as usize]);
            let axis = (qa - pa).cross(qb - pb);
            if axis.length_squared() == 0.0 {
                return;
            }
            // The facet normal lies between the arc's end normals (in the comparison frame).
            let axis = axis.normalize();
            let (m1, m2) = a.arc_of(f, g);
            let axis = if axis.dot(m1 + m2) < 0.0 { -axis } else { axis };
            let (ha, hb) = (axis.dot(pa), axis.dot(pb));
            consider(ha - hb, axis, 0.5 * (ha + hb));
        });
    best
}

#[cfg(test)]
mod tests {
    use super::super::separation::convex_separation;
    use super::*;
    use glam::DQuat;

    /// A cube trimmed by `cuts` random planes tangent to its inscribed sphere: a convex
    /// polytope with many faces.
    fn faceted(seed: u64, cuts: usize, radius: f64) -> ConvexPolytope {
        let mut state = seed | 1;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut p = ConvexPolytope::cuboid(DVec3::splat(-radius), DVec3::splat(radius));
        for _ in 0..cuts {
            let (u, v) = (next() * std::f64::consts::TAU, next() * 2.0 - 1.0);
            let s = (1.0 - v * v).sqrt();
            let n = DVec3::new(s * u.cos(), s * u.sin(), v);
            p = p
                .clip(n, radius * (0.9 + 0.1 * next()), 1e-12)
                .expect("a trimmed cube remains");
        }
        p
    }

    #[test]
    fn facet_restricted_sat_agrees_with_the_plain_test() {
        let mut penetrating = 0;
        for seed in 1..24u64 {
            let a = faceted(seed, 60, 10.0);
            let b = faceted(seed * 7919, 50, 6.0);
            assert!(a.faces().len() > 24 && b.faces().len() > 24);
            let (ga, gb) = (GaussHull::new(&a, 1e-9).unwrap(), GaussHull::new(&b, 1e-9).unwrap());
            let rotation = DQuat::from_euler(glam::EulerRot::XYZ, seed as f64 * 0.7, seed as f64 * 0.3, 0.2);
            let direction = (rotation * DVec3::X).normalize();
            for distance in [10.0, 14.0, 15.5, 16.5, 20.0] {
                let t = DAffine3::from_rotation_translation(rotation, direction * distance);
                let plain = convex_separation(&a, &b, &t);
                let fast = separate(&ga.placed(&DAffine3::IDENTITY), &gb.placed(&t), f64::NEG_INFINITY);
                if plain.depth > 1e-9 {
                    penetrating += 1;
                    crate::assert_near!(fast.depth, plain.depth, 1e-9);
                } else if plain.depth < -1e-9 {
                    assert!(fast.depth < 0.0, "seed {seed} at {distance}: {fast:?} vs {plain:?}");
                    // The plane separates every vertex of A from every vertex of B.
                    assert!(a.vertices().iter().all(|&p| fast.axis.dot(p) <= fast.offset + 1e-9));
                    assert!(
                        b.vertices()
                            .iter()
                            .all(|&p| fast.axis.dot(t.transform_point3(p)) >= fast.offset - 1e-9)
                    );
                }
            }
        }
        assert!(penetrating > 30, "only {penetrating} penetrating cases");
    }
}
