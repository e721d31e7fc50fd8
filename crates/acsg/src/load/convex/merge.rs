//! Merging neighbouring convex pieces whose union is convex.
//!
//! Two convex pieces `P` and `Q` with disjoint interiors, on either side of a plane `H`
//! they both have a facet in, have a convex union exactly when each lies inside the
//! other's bounding half-spaces other than `H`: then `K`, the intersection of all those
//! half-spaces, meets `H`'s side of `P` in `P` and the other side in `Q`, so `K = P ∪ Q`.
//! (Conversely every facet plane of a convex union, other than `H`, bounds it.) The
//! merged piece is `K`, bounded by the pieces' own planes, so merging stays exact.

use std::collections::HashMap;

use glam::DVec3;

use crate::geometry::ConvexPolytope;

/// A plane `normal · p = offset` as bits, to find a facet's exact opposite: both sides
/// of a cut carry the same plane, negated on one side.
type PlaneKey = [u64; 4];

fn key(normal: DVec3, offset: f64) -> PlaneKey {
    [normal.x, normal.y, normal.z, offset].map(|c| (c + 0.0).to_bits())
}

/// Merges pairs of pieces sharing a cut plane while their union is convex, until no
/// pair merges. A vertex within `tol` outside a plane counts as inside; `eps` is the
/// clipping tolerance of [`ConvexPolytope::clip`]. Pieces never merged keep their
/// order; merged ones follow, in the order they were made.
pub(super) fn merge_convex_unions(pieces: Vec<ConvexPolytope>, tol: f64, eps: f64) -> Vec<ConvexPolytope> {
    let mut pieces: Vec<Option<ConvexPolytope>> = pieces.into_iter().map(Some).collect();
    // Which pieces (alive or not) have a facet in each plane.
    let mut in_plane: HashMap<PlaneKey, Vec<usize>> = HashMap::new();
    let mut queue = std::collections::VecDeque::new();
    for i in 0..pieces.len() {
        enqueue_neighbours(&pieces, &mut in_plane, &mut queue, i);
    }
    while let Some((i, j)) = queue.pop_front() {
        let (Some(p), Some(q)) = (&pieces[i], &pieces[j]) else {
            continue;
        };
        if let Some(union) = convex_union(p, q, tol, eps) {
            pieces[i] = None;
            pieces[j] = None;
            pieces.push(Some(union));
            enqueue_neighbours(&pieces, &mut in_plane, &mut queue, pieces.len() - 1);
        }
    }
    pieces.into_iter().flatten().collect()
}

/// Registers piece `i`'s facet planes and queues it with every live piece that has a
/// facet in the opposite plane.
fn enqueue_neighbours(
    pieces: &[Option<ConvexPolytope>],
    in_plane: &mut HashMap<PlaneKey, Vec<usize>>,
    queue: &mut std::collections::VecDeque<(usize, usize)>,
    i: usize,
) {
    let Some(piece) = &pieces[i] else { return };
    for f in piece.faces() {
        if let Some(others) = in_plane.get(&key(-f.normal, -f.offset)) {
            queue.extend(others.iter().filter(|&&j| pieces[j].is_some()).map(|&j| (j, i)));
        }
        in_plane.entry(key(f.normal, f.offset)).or_default().push(i);
    }
}

/// The union of two pieces when it is convex, as a polytope.
fn convex_union(p: &ConvexPolytope, q: &ConvexPolytope, tol: f64, eps: f64) -> Option<ConvexPolytope> {
    let shared = p.faces().iter().find(|f| {
        q.faces()
            .iter()
            .any(|g| key(g.normal, g.offset) == key(-f.normal, -f.offset))
    })?;
    let (h, hd) = (shared.normal, shared.offset);
    let is_shared = |n: DVec3, d: f64| key(n, d) == key(h, hd) || key(n, d) == key(-h, -hd);
    let inside = |piece: &ConvexPolytope, other: &ConvexPolytope| {
        other
            .faces()
            .iter()
            .filter(|f| !is_shared(f.normal, f.offset))
            .all(|f| piece.vertices().iter().all(|&v| f.normal.dot(v) - f.offset <= tol))
    };
    if !inside(p, q) || !inside(q, p) {
        return None;
    }
    let corners = p.vertices().iter().chain(q.vertices());
    let (lo, hi) = corners.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
        (lo.min(v), hi.max(v))
    });
    let mut planes = p
        .faces()
        .iter()
        .chain(q.faces())
        .filter(|f| !is_shared(f.normal, f.offset));
    let union = planes.try_fold(ConvexPolytope::cuboid(lo, hi), |k, f| k.clip(f.normal, f.offset, eps))?;
    // The argument above, checked on the result: nothing of either piece lost.
    let lost = p.volume() + q.volume() - union.volume();
    (lost.abs() <= tol * (area(p) + area(q))).then_some(union)
}

/// A polytope's surface area.
fn area(piece: &ConvexPolytope) -> f64 {
    piece
        .faces()
        .iter()
        .map(|f| {
            let p0 = f.points[0];
            0.5 * f
                .points
                .windows(2)
                .skip(1)
                .map(|w| (w[0] - p0).cross(w[1] - p0))
                .sum::<DVec3>()
                .length()
        })
        .sum()
}
