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

/// The element pairs to push apart from a witness of `state` to reach `target`, when
/// `target` lies below `state` (see the module docs) and differs from it: every other
/// contact of the state whole, and for a contact of which the target keeps a part, the
/// vertices of each element reduced to a part from the other element (unless another
/// contact of the target holds them together).
/// `None` when `target` does not lie below `state`.
pub(crate) fn parted_pairs(
    fixed: &Part,
    moving: &Part,
    target: &[PrincipalContact],
    state: &[PrincipalContact],
) -> Option<Vec<(ElementId, ElementId)>> {
    if target.len() > state.len() || target == state {
        return None;
    }
    let matched = match_below(fixed, moving, target, state)?;
    let held = |x: ElementId, y: ElementId| {
        target
            .iter()
            .any(|c| fixed.in_closure(x, c.fixed) && moving.in_closure(y, c.moving))
    };
    let mut pairs = Vec::new();
    for (s, whole) in state.iter().enumerate() {
        match matched.iter().position(|&m| m == s) {
            None => pairs.push((whole.fixed, whole.moving)),
            Some(i) if target[i] == *whole => {}
            Some(i) => {
                // The vertices of an element the target keeps only a part of part from
                // the other element: an edge tilts off a face about its kept vertex.
                let kept = &target[i];
                let mut part = |pair: (ElementId, ElementId)| {
                    if !held(pair.0, pair.1) && !pairs.contains(&pair) {
                        pairs.push(pair);
                    }
                };
                if kept.moving != whole.moving {
                    for y in moving.closure_vertices(whole.moving) {
                        if !moving.in_closure(kept.moving, ElementId::Vertex(y)) {
                            part((whole.fixed, ElementId::Vertex(y)));
                        }
                    }
                }
                if kept.fixed != whole.fixed {
                    for x in fixed.closure_vertices(whole.fixed) {
                        if !fixed.in_closure(kept.fixed, ElementId::Vertex(x)) {
                            part((ElementId::Vertex(x), whole.moving));
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
    !target.iter().all(|c| state.contains(c)) && parted_pairs(fixed, moving, target, state).is_some()
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

    #[test]
    fn a_vertex_of_an_edge_on_a_face_lies_below_the_edge_and_parts_the_other_vertex() {
        let (slab, cube) = cube_and_slab();
        // An edge of the cube and one of its ends.
        let edge = EdgeId(0);
        let [v0, v1] = cube.edge(edge).vertices;
        let top = FaceId(0);
        let on_edge = pc(ContactKind::FaceEdge, ElementId::Face(top), ElementId::Edge(edge));
        let on_vertex = pc(ContactKind::FaceVertex, ElementId::Face(top), ElementId::Vertex(v0));
        let pairs = parted_pairs(&slab, &cube, &[on_vertex], &[on_edge]).expect("below");
        assert!(pairs.contains(&(ElementId::Face(top), ElementId::Vertex(v1))));
        assert!(!pairs.contains(&(ElementId::Face(top), ElementId::Vertex(v0))));
        assert_eq!(pairs.len(), 1);
        assert!(lies_strictly_below(&slab, &cube, &[on_vertex], &[on_edge]));
        // Not the other way up, and a vertex off the edge is not below it.
        assert!(parted_pairs(&slab, &cube, &[on_edge], &[on_vertex]).is_none());
        let off = (0..8)
            .map(VertexId)
            .find(|v| !cube.edge(edge).vertices.contains(v))
            .unwrap();
        let elsewhere = pc(ContactKind::FaceVertex, ElementId::Face(top), ElementId::Vertex(off));
        assert!(parted_pairs(&slab, &cube, &[elsewhere], &[on_edge]).is_none());
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
        assert_eq!(
            parted_pairs(&slab, &cube, &[a], &state),
            Some(vec![(b.fixed, b.moving)])
        );
        assert!(!lies_strictly_below(&slab, &cube, &[a], &state));
        assert_eq!(parted_pairs(&slab, &cube, &state, &state), None);
    }
}
