//! Which candidates lie below a known state in C-space, and what must part to reach
//! them from its witness.
//!
//! A candidate lies below a state when each of its contacts is one of the state's
//! contacts or a part of one (its elements in the closures of that contact's elements:
//! a vertex of an edge lying in a face, {f-v} below {f-e}), no two of them parts of the
//! same. Its region of poses then reaches the state's: from the state's witness, the
//! state's other contacts part, and each contact with a part kept holds only that part
//! (the edge tilts off the face about its vertex).

use crate::contact::PrincipalContact;
use crate::model::{ElementId, Part};

/// Whether contact `part_of` is `whole` or a part of it.
fn is_part_of(fixed: &Part, moving: &Part, part_of: &PrincipalContact, whole: &PrincipalContact) -> bool {
    fixed.in_closure(whole.fixed, part_of.fixed) && moving.in_closure(whole.moving, part_of.moving)
}

/// Matches each contact of `target` to a distinct contact of `state` it is equal to or
/// a part of (equal ones first): `matched[i]` is the state contact of `target[i]`.
fn match_below(
    fixed: &Part,
    moving: &Part,
    target: &[PrincipalContact],
    state: &[PrincipalContact],
) -> Option<Vec<usize>> {
    let mut matched: Vec<Option<usize>> = target.iter().map(|c| state.iter().position(|s| s == c)).collect();
    let mut used: Vec<bool> = vec![false; state.len()];
    for &s in matched.iter().flatten() {
        used[s] = true;
    }
    let open: Vec<usize> = (0..target.len()).filter(|&i| matched[i].is_none()).collect();
    fn assign(
        k: usize,
        open: &[usize],
        options: &dyn Fn(usize, usize) -> bool,
        used: &mut [bool],
        matched: &mut [Option<usize>],
    ) -> bool {
        let Some(&i) = open.get(k) else { return true };
        for s in 0..used.len() {
            if !used[s] && options(i, s) {
                used[s] = true;
                matched[i] = Some(s);
                if assign(k + 1, open, options, used, matched) {
                    return true;
                }
                used[s] = false;
                matched[i] = None;
            }
        }
        false
    }
    let options = |i: usize, s: usize| is_part_of(fixed, moving, &target[i], &state[s]);
    assign(0, &open, &options, &mut used, &mut matched).then(|| matched.into_iter().flatten().collect())
}

/// Every element of an element's closure: itself, its edges, its vertices.
fn closure(part: &Part, e: ElementId) -> Vec<ElementId> {
    let mut out = vec![e];
    if let ElementId::Face(_) = e {
        out.extend(part.closure_edges(e).into_iter().map(ElementId::Edge));
    }
    out.extend(
        part.closure_vertices(e)
            .into_iter()
            .map(ElementId::Vertex)
            .filter(|&v| v != e),
    );
    out
}

/// The elements of one side of a contact that touch the other side wherever the contact
/// holds: a face lying on a face touches it with its whole closure, an edge lying in a
/// face with its vertices too; a crossing or a point on a face, only at the element
/// itself.
fn touching(part: &Part, own: ElementId, other: ElementId) -> Vec<ElementId> {
    match (own, other) {
        (ElementId::Face(_) | ElementId::Edge(_), ElementId::Face(_)) => closure(part, own),
        _ => vec![own],
    }
}

/// The element pairs to push apart from a witness of `state` to reach `target`, when
/// `target` lies below `state` (see the module docs) and differs from it: every other
/// contact of the state whole, and for a contact of which the target keeps a part, the
/// pairs of elements in the two closures that touch at the witness (`touches`) unless
/// a contact of the target holds them together (an edge lying in a face tilts off it
/// about its kept vertex; an edge lying across a face lifts off all of it but one of
/// its sides). `None` when `target` does not lie below `state`.
pub(crate) fn parted_pairs(
    fixed: &Part,
    moving: &Part,
    target: &[PrincipalContact],
    state: &[PrincipalContact],
    touches: impl Fn(ElementId, ElementId) -> bool,
) -> Option<Vec<(ElementId, ElementId)>> {
    if target.len() > state.len() || target == state {
        return None;
    }
    let matched = match_below(fixed, moving, target, state)?;
    // Whether a contact of the target makes x and y touch: an element touching on
    // each side lies in their closures.
    let held = |x: ElementId, y: ElementId| {
        target.iter().any(|c| {
            touching(fixed, c.fixed, c.moving)
                .iter()
                .any(|&t| fixed.in_closure(x, t))
                && touching(moving, c.moving, c.fixed)
                    .iter()
                    .any(|&t| moving.in_closure(y, t))
        })
    };
    let mut pairs = Vec::new();
    for (s, whole) in state.iter().enumerate() {
        match matched.iter().position(|&m| m == s) {
            None => pairs.push((whole.fixed, whole.moving)),
            Some(i) if target[i] == *whole => {}
            Some(_) => {
                for x in closure(fixed, whole.fixed) {
                    for y in closure(moving, whole.moving) {
                        if !held(x, y) && !pairs.contains(&(x, y)) && touches(x, y) {
                            pairs.push((x, y));
                        }
                    }
                }
            }
        }
    }
    Some(pairs)
}

/// Whether `target` lies below `state` with at least one contact a strict part of one
/// of the state's (not merely a subset of its contacts).
pub(crate) fn lies_strictly_below(
    fixed: &Part,
    moving: &Part,
    target: &[PrincipalContact],
    state: &[PrincipalContact],
) -> bool {
    !target.iter().all(|c| state.contains(c)) && match_below(fixed, moving, target, state).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactKind;
    use crate::examples::cube_and_slab;
    use crate::model::{EdgeId, FaceId, VertexId};

    fn pc(kind: ContactKind, fixed: ElementId, moving: ElementId) -> PrincipalContact {
        PrincipalContact { fixed, moving, kind }
    }

    /// The pairs that touch at an imagined witness: `fixed` against each of `moving`.
    fn touching_pairs(fixed: ElementId, moving: Vec<ElementId>) -> impl Fn(ElementId, ElementId) -> bool {
        move |x, y| x == fixed && moving.contains(&y)
    }

    #[test]
    fn a_vertex_of_an_edge_on_a_face_lies_below_the_edge_and_parts_the_other_vertex() {
        let (slab, cube) = cube_and_slab();
        let edge = EdgeId(0);
        let [v0, v1] = cube.edge(edge).vertices.map(ElementId::Vertex);
        let top = ElementId::Face(FaceId(0));
        let on_edge = pc(ContactKind::FaceEdge, top, ElementId::Edge(edge));
        let on_vertex = pc(ContactKind::FaceVertex, top, v0);
        // The edge lies inside the face: it and both its ends touch the face.
        let touches = || touching_pairs(top, vec![ElementId::Edge(edge), v0, v1]);
        let pairs = parted_pairs(&slab, &cube, &[on_vertex], &[on_edge], touches()).expect("below");
        assert_eq!(pairs, vec![(top, v1)]);
        assert!(lies_strictly_below(&slab, &cube, &[on_vertex], &[on_edge]));
        // Not the other way up, and a vertex off the edge is not below it.
        assert!(parted_pairs(&slab, &cube, &[on_edge], &[on_vertex], touches()).is_none());
        let off = (0..8)
            .map(|v| ElementId::Vertex(VertexId(v)))
            .find(|v| ![v0, v1].contains(v))
            .unwrap();
        let elsewhere = pc(ContactKind::FaceVertex, top, off);
        assert!(parted_pairs(&slab, &cube, &[elsewhere], &[on_edge], touches()).is_none());
        assert!(!lies_strictly_below(&slab, &cube, &[elsewhere], &[on_edge]));
    }

    #[test]
    fn a_face_on_a_face_down_to_one_edge_lifts_the_rest_of_the_face_but_not_that_edges_neighbours() {
        let (slab, cube) = cube_and_slab();
        let top = ElementId::Face(FaceId(0));
        let face = ElementId::Face(FaceId(0));
        let edges = cube.closure_edges(face);
        let kept = edges[0];
        let kept_ends = cube.edge(kept).vertices;
        let flat = pc(ContactKind::FaceFace, top, face);
        let on_edge = pc(ContactKind::FaceEdge, top, ElementId::Edge(kept));
        // The face lies inside the slab's top: its whole closure touches it.
        let touches = touching_pairs(top, closure(&cube, face));
        let pairs = parted_pairs(&slab, &cube, &[on_edge], &[flat], touches).expect("below");
        for &e in &edges[1..] {
            let neighbour = cube.edge(e).vertices.iter().any(|v| kept_ends.contains(v));
            // An edge sharing an end with the kept edge touches the face there.
            assert_eq!(pairs.contains(&(top, ElementId::Edge(e))), !neighbour, "edge {e:?}");
        }
        for v in cube.closure_vertices(face) {
            assert_eq!(pairs.contains(&(top, ElementId::Vertex(v))), !kept_ends.contains(&v));
        }
        assert_eq!(pairs.len(), 3, "the opposite edge and the two far corners: {pairs:?}");
    }

    #[test]
    fn an_edge_lying_across_a_face_down_to_crossing_one_of_its_edges_lifts_off_the_other_and_its_ends() {
        let (slab, cube) = cube_and_slab();
        let (edge, face) = (ElementId::Edge(EdgeId(0)), ElementId::Face(FaceId(0)));
        let edges = cube.closure_edges(face);
        let (crossed, also_crossed) = (ElementId::Edge(edges[0]), ElementId::Edge(edges[2]));
        let [end0, end1] = slab.edge(EdgeId(0)).vertices.map(ElementId::Vertex);
        let lying = pc(ContactKind::EdgeFace, edge, face);
        let crossing = pc(ContactKind::EdgeEdge, edge, crossed);
        // The edge lies across the face, crossing two of its edges, one end over it.
        let touches = |x: ElementId, y: ElementId| {
            (x == edge && [face, crossed, also_crossed].contains(&y)) || (x == end0 && y == face)
        };
        let pairs = parted_pairs(&slab, &cube, &[crossing], &[lying], touches).expect("below");
        // A crossing touches only inside both edges: the other crossed edge and the end
        // over the face part; the face itself (held at the crossing) does not.
        assert_eq!(pairs, vec![(edge, also_crossed), (end0, face)]);
        assert!(!pairs.iter().any(|&(x, _)| x == end1));
    }

    #[test]
    fn a_subset_parts_the_contacts_left_out_whole_and_is_not_strictly_below() {
        let (slab, cube) = cube_and_slab();
        let a = pc(
            ContactKind::FaceVertex,
            ElementId::Face(FaceId(0)),
            ElementId::Vertex(VertexId(0)),
        );
        let b = pc(
            ContactKind::FaceVertex,
            ElementId::Face(FaceId(1)),
            ElementId::Vertex(VertexId(1)),
        );
        let mut state = vec![a, b];
        state.sort();
        let all = |_: ElementId, _: ElementId| true;
        assert_eq!(
            parted_pairs(&slab, &cube, &[a], &state, all),
            Some(vec![(b.fixed, b.moving)])
        );
        assert!(!lies_strictly_below(&slab, &cube, &[a], &state));
        assert_eq!(parted_pairs(&slab, &cube, &state, &state, all), None);
    }
}
