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
use crate::model::{ElementId, FaceId, Part, VertexId};
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
}
