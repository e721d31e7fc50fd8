//! A face hinged on a face: a rotation-invariant test of two contacts whose points lie
//! on one face's plane of one part and in one convex face of the other.
//!
//! Let a vertex `V` of the moving part touch a face `f` of the fixed part (f-v), and
//! let another contact's point `p` lie in the closure of a convex face `F` of the moving
//! part that has `V` on its outer loop, and on `f`'s plane (its fixed element lies in
//! `f`'s closure). Then `p − V` runs inside `F`'s corner at `V`: `p − V = α d_a + β d_b`
//! with `α, β ≥ 0` along `F`'s two edges leaving `V`. A robust witness keeps both
//! edges rising off `f` by more than the margin `μ` (a sine,
//! [`super::normals::NORMAL_MARGIN`]), so `p` stands at least `μ |p − V|` above `f`'s
//! plane, while both contacts hold it within the contact tolerance of that plane: when
//! `μ |p − V|` exceeds twice the tolerance, no pose shows both. `F` would lie on `f`
//! (f-f) or cross its plane at `V` (and penetrate there). The same holds with the parts'
//! roles swapped (v-f and a convex face of the fixed part at its vertex). The box's
//! corner on the L-block's wall while the box's top edge crosses the wall's top edge,
//! both in the box's side face, is such a pair.

use super::normals::NORMAL_MARGIN;
use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use crate::tolerance::{CONTACT_REL, scaled};

/// Whether some two contacts of `target` hinge a face on a face (see the module's
/// documentation): `true` proves that no pose shows the target robustly.
/// `distance_within(fixed, a, b)` is the distance between two elements' closures of
/// one part; `scale` is L.
pub(crate) fn hinged(
    fixed: &Part,
    moving: &Part,
    target: &[PrincipalContact],
    scale: f64,
    distance_within: impl Fn(bool, ElementId, ElementId) -> f64,
) -> bool {
    // Both points within the contact tolerance of the plane, twice over for safety.
    let least = 4.0 * scaled(CONTACT_REL, scale) / NORMAL_MARGIN;
    target.iter().any(|corner| {
        target.iter().filter(|other| *other != corner).any(|other| {
            let (on_fixed, face, vertex, plane, point) = match (corner.kind, corner.fixed, corner.moving) {
                // The moving part's corner on a fixed face: the moving part's face at it.
                (ContactKind::FaceVertex, ElementId::Face(f), ElementId::Vertex(v)) => {
                    (false, f, v, other.fixed, other.moving)
                }
                (ContactKind::VertexFace, ElementId::Vertex(v), ElementId::Face(g)) => {
                    (true, g, v, other.moving, other.fixed)
                }
                _ => return false,
            };
            // `corner_part` holds the vertex and the convex face at it; the other part
            // holds `face`, whose plane the other contact's point lies on.
            let (corner_part, plane_part) = if on_fixed { (fixed, moving) } else { (moving, fixed) };
            if !plane_part.in_closure(ElementId::Face(face), plane) || !corner_part.vertex(vertex).convex {
                return false;
            }
            corner_part.vertex(vertex).faces.iter().any(|&g| {
                convex_corner(corner_part, g, vertex)
                    && corner_part.in_closure(ElementId::Face(g), point)
                    && distance_within(on_fixed, ElementId::Vertex(vertex), point) > least
            })
        })
    })
}

/// Whether a crossing of two edges and another contact hinge a face of each part on
/// the crossing's plane: with `u` the crossing's normal, a robust witness keeps each
/// face at the fixed edge at least the margin `μ` (a sine) below the plane through
/// both edges, and each face at the moving edge that much above it (the wedges'
/// separation, by the margin of [`super::normals`]). A point of a convex face at the
/// fixed edge `d_A` from that edge's line then lies at least `μ d_A` below the plane,
/// and a point of a convex face at the moving edge `d_B` from its line `μ d_B` above
/// it. Another contact holding a point of the one face within the contact tolerance
/// of a point of the other needs `μ (d_A + d_B)` within twice that tolerance (the
/// crossing holds its edges that close too).
pub(crate) fn crossing_hinged(fixed: &Part, moving: &Part, target: &[PrincipalContact], scale: f64) -> bool {
    let least = 4.0 * scaled(CONTACT_REL, scale) / NORMAL_MARGIN;
    target.iter().any(|crossing| {
        let (ContactKind::EdgeEdge, ElementId::Edge(a), ElementId::Edge(b)) =
            (crossing.kind, crossing.fixed, crossing.moving)
        else {
            return false;
        };
        if !fixed.edge(a).convex || !moving.edge(b).convex {
            return false;
        }
        target.iter().filter(|other| *other != crossing).any(|other| {
            let reach = |part: &Part, edge: EdgeId, element: ElementId| {
                part.edge(edge)
                    .faces
                    .iter()
                    .filter(|&&f| convex_side(part, f, edge) && part.in_closure(ElementId::Face(f), element))
                    .map(|_| distance_from_line(part, edge, element))
                    .fold(None, |best: Option<f64>, d| Some(best.map_or(d, |b| b.max(d))))
            };
            match (reach(fixed, a, other.fixed), reach(moving, b, other.moving)) {
                (Some(d_a), Some(d_b)) => d_a + d_b > least,
                _ => false,
            }
        })
    })
}

/// The least distance from an element's closure (its vertices: it lies in a convex
/// face through the line, where that distance is linear) to the line of an edge.
fn distance_from_line(part: &Part, edge: EdgeId, element: ElementId) -> f64 {
    let [p, q] = part.edge_points(edge);
    let d = (q - p).normalize();
    part.closure_vertices(element)
        .into_iter()
        .map(|v| {
            let w = part.vertex(v).position - p;
            (w - w.dot(d) * d).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Whether face `f` is convex with `edge` on its outer loop: the face then lies on one
/// side of the edge's line.
fn convex_side(part: &Part, f: FaceId, edge: EdgeId) -> bool {
    part.face(f).outer().edges.contains(&edge) && !part.face_outline_is_nonconvex(f)
}

/// Whether face `g` is convex with `v` on its outer loop: the face then lies inside
/// its corner at `v`.
fn convex_corner(part: &Part, g: FaceId, v: VertexId) -> bool {
    part.face(g).outer().vertices.contains(&v) && !part.face_outline_is_nonconvex(g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{ContactKind as K, ContactScene};
    use crate::testing::contact;

    fn hinged_in_the_example(target: &[PrincipalContact]) -> bool {
        let (block, cuboid) = crate::examples::l_block_and_box();
        let scene = ContactScene::new(&block, &cuboid);
        hinged(&block, &cuboid, target, scene.scale(), |fixed, a, b| {
            scene.distance_within(fixed, a, b)
        })
    }

    #[test]
    fn a_corner_on_the_wall_and_an_edge_of_its_face_across_the_walls_top_edge_hinge_the_face() {
        // The box's corner v4 (150, 10, 50) on the wall f5 (x = 150), and the box's
        // top edge e10 (x = 150, z = 150), 100 mm above it in the box's side face,
        // crossing the wall's top edge e10 (in the wall's closure): both points on the
        // wall's plane, so the side face lies on the wall or crosses its plane at v4.
        assert!(hinged_in_the_example(&[
            contact("f5", "v4", K::FaceVertex),
            contact("e10", "e10", K::EdgeEdge)
        ]));
        // The box's far top edge e3 (x = 50) lies in no face at v4.
        assert!(!hinged_in_the_example(&[
            contact("f5", "v4", K::FaceVertex),
            contact("e10", "e3", K::EdgeEdge)
        ]));
        // Nor does the floor's edge e7 lie in the wall's closure.
        assert!(!hinged_in_the_example(&[
            contact("f5", "v4", K::FaceVertex),
            contact("e7", "e10", K::EdgeEdge)
        ]));
    }

    #[test]
    fn a_crossing_on_the_walls_top_edge_and_the_walls_foot_on_the_crossing_boxs_face_hinge_the_faces() {
        // The box's top edge e10 crosses the wall's top edge e10; the wall's corner v4
        // (150, 0, 50), 100 mm below the wall's top edge in the wall f5, lies on the
        // box's side face f5, which holds the box's top edge. The plane through both
        // edges has the wall below it, the box's face above it; a point on both is
        // only possible with the faces flush.
        let (block, cuboid) = crate::examples::l_block_and_box();
        let scale = ContactScene::new(&block, &cuboid).scale();
        let crossing = contact("e10", "e10", K::EdgeEdge);
        assert!(crossing_hinged(&block, &cuboid, &[crossing, contact("v4", "f5", K::VertexFace)], scale));
        // The L-block's far corner v0 (0, 0, 0) lies in no face at the wall's top edge.
        assert!(!crossing_hinged(&block, &cuboid, &[crossing, contact("v0", "f5", K::VertexFace)], scale));
    }
}
