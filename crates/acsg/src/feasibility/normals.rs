//! Contact normals on the Gauss sphere: a rotation-invariant test of whether a
//! target's point contacts can hold under one rotation.
//!
//! At a vertex touching a face (f-v, v-f) the face's normal `u` (outward of the fixed
//! part, in its frame) lies in the fixed element's outward normal set and `Rᵀ u` in the
//! moving element's inward one (its outward normals, negated): a face has one normal,
//! a convex vertex the spherical polygon of its faces' normals. A vertex in a concave
//! edge touches both of the edge's faces, so both their normals go into the vertex's
//! polygon. A robust witness keeps each such normal inside its set by the margin `μ`
//! (DOMAIN §7: every checker whose tolerance lies between `1e-9 L` and `1e-6 L` reads
//! the same state): an edge leaving the vertex that rises by less than `μ` (a sine)
//! lies within `μ L` of the face's plane over its whole stretch on the face, which such
//! a checker reads as lying in it; one that dips below it penetrates the face's part
//! near the vertex, or lies within the contact tolerance of it there, read the same
//! way.
//!
//! The rotation keeps angles, so two such conditions `u_i ∈ P_i, Rᵀ u_i ∈ Q_i` and
//! `u_k ∈ P_k, Rᵀ u_k ∈ Q_k` need the angles between `P_i` and `P_k` to meet those
//! between `Q_i` and `Q_k`. When the two ranges are apart, no rotation at all shows
//! the target: a box corner in the L-block's right-angled groove needs both wall
//! normals, 90° apart, strictly inside the corner's normal triangle, whose points are
//! less than 90° apart (the corner fits only with an edge lying in the groove).
//!
//! Contacts along a segment or over an area (f-f, f-e, e-f, e-e-t) pin their normals
//! only to the contact tolerance over the contact's length, which may be short; they
//! set no condition here, nor do contacts at non-convex vertices. Nor do crossing
//! edges: near an edge's end a witness may have both parts below the plane through
//! two nearly parallel crossing edges (the wall's face separates them there), so the
//! crossing's normal need not lie in the edges' normal arcs.

use glam::DVec3;

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};

/// How far inside its normal set a robust witness keeps each contact normal (a sine):
/// a tenth of the loose tolerance's `0.99e-6`, which bounds it from below for any edge
/// no longer than `L` (an edge turned closer to a face lies within `0.99e-6 L` of its
/// plane over its whole stretch on it).
pub(crate) const NORMAL_MARGIN: f64 = 1e-7;

/// Round-off allowed in the angles compared (radians).
const ANGLE_SLACK: f64 = 1e-12;

/// A closed convex set of unit vectors on the sphere: one point (a face's normal) or a
/// polygon (a convex vertex's face normals, at least three, counter-clockwise seen from
/// outside). Every point of a polygon that a robust witness may use
/// lies at least `inset` (an angle) inside it, in every direction along the sphere: a
/// side's great circle is normal to the vertex's edge between its two faces, and the
/// witness keeps that edge rising by the margin.
#[derive(Clone, Debug)]
struct NormalSet {
    corners: Vec<DVec3>,
    inset: f64,
}

/// One contact's condition: `u` in `fixed` (the fixed part's frame) and `Rᵀ u` in
/// `moving` (the moving part's frame) for some unit `u`.
#[derive(Clone, Debug)]
struct NormalCondition {
    fixed: NormalSet,
    moving: NormalSet,
}

/// Whether the point contacts of `target` may hold together under some rotation, as
/// far as their normals tell: `false` proves that no pose shows the target robustly.
pub(crate) fn normals_compatible(fixed: &Part, moving: &Part, target: &[PrincipalContact]) -> bool {
    let conditions: Vec<NormalCondition> = target.iter().flat_map(|pc| conditions_of(fixed, moving, pc)).collect();
    for (i, a) in conditions.iter().enumerate() {
        for b in &conditions[i + 1..] {
            let (flo, fhi) = angle_range(&a.fixed, &b.fixed);
            let (mlo, mhi) = angle_range(&a.moving, &b.moving);
            if fhi < mlo || mhi < flo {
                return false;
            }
        }
    }
    true
}

/// The normal conditions of one contact (none for the kinds this test leaves alone).
fn conditions_of(fixed: &Part, moving: &Part, pc: &PrincipalContact) -> Vec<NormalCondition> {
    let pair = |f: Option<NormalSet>, m: Option<NormalSet>| match (f, m) {
        (Some(fixed), Some(moving)) => vec![NormalCondition { fixed, moving }],
        _ => Vec::new(),
    };
    match (pc.kind, pc.fixed, pc.moving) {
        (ContactKind::FaceVertex, ElementId::Face(f), ElementId::Vertex(v)) => {
            pair(Some(point(fixed.face(f).normal)), vertex_cone(moving, v, -1.0))
        }
        (ContactKind::VertexFace, ElementId::Vertex(v), ElementId::Face(g)) => {
            pair(vertex_cone(fixed, v, 1.0), Some(point(-moving.face(g).normal)))
        }
        (ContactKind::EdgeVertex, ElementId::Edge(e), ElementId::Vertex(v)) if !fixed.edge(e).convex => {
            let Some(cone) = vertex_cone(moving, v, -1.0) else {
                return Vec::new();
            };
            groove_normals(fixed, e, 1.0)
                .into_iter()
                .map(|n| NormalCondition {
                    fixed: point(n),
                    moving: cone.clone(),
                })
                .collect()
        }
        (ContactKind::VertexEdge, ElementId::Vertex(v), ElementId::Edge(x)) if !moving.edge(x).convex => {
            let Some(cone) = vertex_cone(fixed, v, 1.0) else {
                return Vec::new();
            };
            groove_normals(moving, x, -1.0)
                .into_iter()
                .map(|n| NormalCondition {
                    fixed: cone.clone(),
                    moving: point(n),
                })
                .collect()
        }
        _ => Vec::new(),
    }
}

fn point(n: DVec3) -> NormalSet {
    NormalSet {
        corners: vec![n],
        inset: 0.0,
    }
}

/// The normals of a concave edge's two faces, times `sign`.
fn groove_normals(part: &Part, e: EdgeId, sign: f64) -> [DVec3; 2] {
    let [f, g] = part.edge(e).faces;
    [sign * part.face(f).normal, sign * part.face(g).normal]
}

/// The outward normal cone of a convex vertex (its faces' normals times `sign`), as a
/// polygon whose usable points lie the margin inside it.
fn vertex_cone(part: &Part, v: VertexId, sign: f64) -> Option<NormalSet> {
    let vertex = part.vertex(v);
    if !vertex.convex || vertex.faces.len() < 3 {
        return None;
    }
    let normals: Vec<DVec3> = vertex
        .faces
        .iter()
        .map(|&f: &FaceId| sign * part.face(f).normal)
        .collect();
    let centre = normals.iter().copied().sum::<DVec3>().try_normalize()?;
    // Every normal must be within a right angle of the centre for the polygon to be
    // the spherical hull taken below.
    if normals.iter().any(|n| n.dot(centre) <= 0.0) {
        return None;
    }
    let e1 = centre.any_orthonormal_vector();
    let e2 = centre.cross(e1);
    let mut by_angle: Vec<(f64, DVec3)> = normals.iter().map(|&n| (n.dot(e2).atan2(n.dot(e1)), n)).collect();
    by_angle.sort_by(|x, y| x.0.total_cmp(&y.0));
    let corners: Vec<DVec3> = by_angle.into_iter().map(|(_, n)| n).collect();
    // Every corner an extreme point (a convex vertex's face normals are).
    let convex = (0..corners.len()).all(|j| {
        let (a, b) = (corners[j], corners[(j + 1) % corners.len()]);
        corners.iter().all(|&c| c == a || c == b || a.cross(b).dot(c) > 0.0)
    });
    convex.then(|| NormalSet {
        corners,
        inset: NORMAL_MARGIN.asin(),
    })
}

/// Bounds `(lo, hi)` on the angle between a usable point of `p` and one of `q`.
fn angle_range(p: &NormalSet, q: &NormalSet) -> (f64, f64) {
    if let ([a], [b]) = (p.corners.as_slice(), q.corners.as_slice()) {
        let theta = angle(*a, *b);
        return (theta - ANGLE_SLACK, theta + ANGLE_SLACK);
    }
    let inset = p.inset + q.inset;
    // A usable point lies `inset` inside its set: it can move that far towards the
    // other set's point (or away from it) and stay in the set.
    let least = least_angle(p, q);
    let lo = if least > 0.0 { least + inset } else { 0.0 };
    let pairs = || p.corners.iter().flat_map(|&a| q.corners.iter().map(move |&b| (a, b)));
    // The largest angle is at two corners when no two corners are more than a right
    // angle apart (a linear function over a cone of such vectors is least at a
    // corner); else it is a straight angle less the least angle to the antipodes.
    let farthest = if pairs().all(|(a, b)| a.dot(b) >= 0.0) {
        pairs().map(|(a, b)| angle(a, b)).fold(0.0, f64::max)
    } else {
        std::f64::consts::PI - least_angle(&p.antipodes(), q)
    };
    (lo - ANGLE_SLACK, farthest - inset + ANGLE_SLACK)
}

/// A lower bound on the angle between a point of `p` and one of `q` (their closed
/// hulls): 0 when they may meet. Exact from a point (the nearest point of a closed
/// set to a point outside it is on its boundary: a corner or a side's foot), and
/// between two disjoint sets in an open hemisphere (closest at a corner of one);
/// otherwise 0.
fn least_angle(p: &NormalSet, q: &NormalSet) -> f64 {
    if may_meet(p, q) {
        return 0.0;
    }
    match (p.corners.as_slice(), q.corners.as_slice()) {
        ([x], _) => distance_to(q, *x),
        (_, [y]) => distance_to(p, *y),
        _ if in_open_hemisphere(p, q) => p
            .corners
            .iter()
            .map(|&a| distance_to(q, a))
            .chain(q.corners.iter().map(|&b| distance_to(p, b)))
            .fold(f64::INFINITY, f64::min),
        _ => 0.0,
    }
}

/// Whether every corner of both sets lies strictly ahead of one direction (tried: the
/// corners' means, and each corner).
fn in_open_hemisphere(p: &NormalSet, q: &NormalSet) -> bool {
    let all = || p.corners.iter().chain(&q.corners).copied();
    let mean = |s: &NormalSet| s.corners.iter().copied().sum::<DVec3>();
    [mean(p) + mean(q), mean(p), mean(q)]
        .into_iter()
        .chain(all())
        .filter_map(DVec3::try_normalize)
        .any(|c| all().all(|a| a.dot(c) > 0.0))
}

impl NormalSet {
    /// The antipodal set (a polygon's corners kept counter-clockwise).
    fn antipodes(&self) -> NormalSet {
        NormalSet {
            corners: self.corners.iter().rev().map(|&c| -c).collect(),
            inset: self.inset,
        }
    }
}

/// The sides of a set: a polygon's in turn, none for a point.
fn sides(s: &NormalSet) -> Vec<(DVec3, DVec3)> {
    match s.corners.as_slice() {
        [_] => Vec::new(),
        c => (0..c.len()).map(|j| (c[j], c[(j + 1) % c.len()])).collect(),
    }
}

/// Whether `x` may lie in the set (inclusive, with round-off counted in).
fn may_contain(s: &NormalSet, x: DVec3) -> bool {
    match s.corners.as_slice() {
        [c] => angle(*c, x) <= ANGLE_SLACK,
        _ => sides(s).iter().all(|&(a, b)| a.cross(b).dot(x) >= -ANGLE_SLACK),
    }
}

/// Whether two sets (in an open hemisphere) may share a point: a corner of one in the
/// other, or two sides crossing (in the gnomonic view, segments in a plane).
fn may_meet(p: &NormalSet, q: &NormalSet) -> bool {
    p.corners.iter().any(|&a| may_contain(q, a))
        || q.corners.iter().any(|&b| may_contain(p, b))
        || sides(p).iter().any(|&(a0, a1)| {
            sides(q).iter().any(|&(b0, b1)| {
                let (na, nb) = (a0.cross(a1), b0.cross(b1));
                na.dot(b0) * na.dot(b1) <= 0.0 && nb.dot(a0) * nb.dot(a1) <= 0.0
            })
        })
}

/// The angle from `x` to the nearest point of the set, for `x` outside it: the nearest
/// corner, or the foot of `x` on a side when it falls inside that side.
fn distance_to(s: &NormalSet, x: DVec3) -> f64 {
    let corner = s.corners.iter().map(|&c| angle(x, c)).fold(f64::INFINITY, f64::min);
    sides(s)
        .into_iter()
        .filter_map(|(a, b)| {
            let n = a.cross(b).try_normalize()?;
            let foot = (x - x.dot(n) * n).try_normalize()?;
            (a.cross(foot).dot(n) >= 0.0 && foot.cross(b).dot(n) >= 0.0).then(|| angle(x, foot))
        })
        .fold(corner, f64::min)
}

/// The angle between two unit vectors, accurate near 0 and π.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::VertexId;
    use crate::testing::fixture;
    use crate::tolerance::assert_near;

    fn concave_edges(part: &Part) -> Vec<EdgeId> {
        (0..part.edges().len() as u32)
            .map(EdgeId)
            .filter(|&e| !part.edge(e).convex)
            .collect()
    }

    fn in_groove(e: EdgeId, v: VertexId) -> PrincipalContact {
        PrincipalContact {
            fixed: ElementId::Edge(e),
            moving: ElementId::Vertex(v),
            kind: ContactKind::EdgeVertex,
        }
    }

    #[test]
    fn a_box_corner_fits_a_right_angled_groove_only_with_an_edge_along_it() {
        // The groove's free wedge is a right angle, so both wall normals (90° apart)
        // must lie strictly inside the corner's normal triangle, whose points are
        // less than 90° apart except its corners: no rotation does it.
        let (block, cuboid) = (fixture("l_block.off"), fixture("box.off"));
        let grooves = concave_edges(&block);
        assert_eq!(grooves.len(), 1);
        for v in 0..cuboid.vertices().len() as u32 {
            assert!(!normals_compatible(
                &block,
                &cuboid,
                &[in_groove(grooves[0], VertexId(v))]
            ));
        }
    }

    #[test]
    fn the_last_proofs_rule_out_a_box_corner_alone_in_the_groove_and_the_decisions_do_not() {
        use crate::feasibility::{Problem, Rule};
        let (block, cuboid) = crate::examples::l_block_and_box();
        let bounds = crate::examples::paper_bounds();
        let problem = Problem::new(&block, &cuboid, bounds, glam::DAffine3::IDENTITY);
        let groove = concave_edges(&block)[0];
        let corner = (0..cuboid.vertices().len() as u32)
            .map(VertexId)
            .next()
            .expect("a corner");
        let target = [in_groove(groove, corner)];
        assert_eq!(problem.last_exclusion(&target, &bounds), Some(Rule::NormalAngles));
        assert_ne!(problem.exclusion(&target, &bounds), Some(Rule::NormalAngles));
    }

    #[test]
    fn a_box_corner_fits_a_groove_whose_walls_meet_at_less_than_a_right_angle_of_normals() {
        // Two 45° chamfers meet at a concave diagonal whose faces' normals are 60°
        // apart (fixtures/README.md). Turning the peg's corner so that its normal
        // cone's centre lies on the normals' bisector puts each normal 30° from the
        // centre, inside the cone's inscribed circle (35.3°, the angle from
        // (1,1,1)/√3 to a coordinate plane).
        let (block, peg) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let narrow: Vec<EdgeId> = concave_edges(&block)
            .into_iter()
            .filter(|&e| {
                let [a, b] = groove_normals(&block, e, 1.0);
                (angle(a, b) - std::f64::consts::FRAC_PI_3).abs() < 1e-9
            })
            .collect();
        assert!(!narrow.is_empty());
        let corner = (0..peg.vertices().len() as u32)
            .map(VertexId)
            .find(|&v| peg.vertex(v).convex);
        let corner = corner.expect("a convex corner");
        for e in narrow {
            assert!(normals_compatible(&block, &peg, &[in_groove(e, corner)]));
        }
    }

    #[test]
    fn the_angles_from_a_point_to_an_octant_triangle_run_from_its_nearest_side_to_its_farthest_corner() {
        let octant = NormalSet {
            corners: vec![DVec3::X, DVec3::Y, DVec3::Z],
            inset: 0.0,
        };
        let below = DVec3::new(1.0, 1.0, -0.2).normalize();
        let (lo, hi) = angle_range(&point(below), &octant);
        assert_near!(lo, (0.2f64 / 2f64.sqrt()).atan(), 1e-9);
        assert_near!(hi, below.dot(DVec3::Z).acos(), 1e-9);
        // Inside the triangle the least angle is zero; the inset takes from the
        // largest.
        let inset = NormalSet { inset: 0.01, ..octant };
        let (lo, hi) = angle_range(&point(DVec3::new(1.0, 1.0, 1.0).normalize()), &inset);
        assert!(lo <= 0.0);
        assert_near!(hi, (1.0f64 / 3f64.sqrt()).acos() - 0.01, 1e-9);
    }
}
