//! The combinatorial side of stage 2: which primitive contacts a state already implies
//! (its KLC), and what a state plus one more primitive contact can become (the derived
//! mapping rules of docs/concepts.md#generation, with topological existence).
//!
//! The rules only prune and propose: a proposed state is accepted only when a verified
//! witness shows it (P(X) at the witness is the canonical description).

use std::collections::BTreeSet;

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};

/// The largest elements in the intersection of two closures: where one point touching
/// both can lie. Empty when the closures are disjoint.
#[must_use]
pub fn meet(part: &Part, x: ElementId, y: ElementId) -> Vec<ElementId> {
    if part.in_closure(x, y) {
        return vec![y];
    }
    if part.in_closure(y, x) {
        return vec![x];
    }
    let edges_y: BTreeSet<EdgeId> = part.closure_edges(y).into_iter().collect();
    let shared_edges: Vec<EdgeId> = part
        .closure_edges(x)
        .into_iter()
        .filter(|e| edges_y.contains(e))
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let vertices_y: BTreeSet<VertexId> = part.closure_vertices(y).into_iter().collect();
    let shared_vertices = part
        .closure_vertices(x)
        .into_iter()
        .filter(|v| vertices_y.contains(v))
        .filter(|&v| !shared_edges.iter().any(|&e| part.edge(e).vertices.contains(&v)))
        .collect::<BTreeSet<_>>();
    shared_edges
        .into_iter()
        .map(ElementId::Edge)
        .chain(shared_vertices.into_iter().map(ElementId::Vertex))
        .collect()
}

/// The smallest element whose closure holds both: where two contacts can be parts of
/// one. `None` when there is none or it is not unique.
#[must_use]
pub fn join(part: &Part, x: ElementId, y: ElementId) -> Option<ElementId> {
    if part.in_closure(x, y) {
        return Some(x);
    }
    if part.in_closure(y, x) {
        return Some(y);
    }
    if let (ElementId::Vertex(a), ElementId::Vertex(b)) = (x, y) {
        if let Some(&e) = part
            .vertex(a)
            .edges
            .iter()
            .find(|e| part.edge(**e).vertices.contains(&b))
        {
            return Some(ElementId::Edge(e));
        }
    }
    let around_y = part.faces_around(y);
    let common: Vec<FaceId> = part
        .faces_around(x)
        .into_iter()
        .filter(|f| around_y.contains(f))
        .collect();
    match common.as_slice() {
        [f] => Some(ElementId::Face(*f)),
        _ => None,
    }
}

fn contact(a: ElementId, b: ElementId) -> PrincipalContact {
    PrincipalContact {
        fixed: a,
        moving: b,
        // Two edges merged from two contacts lie along each other (e-e-t).
        kind: ContactKind::of(a, b, true),
    }
}

/// One thing two contacts of one state can make together (a pair may have several; the
/// pose decides which).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outcome {
    /// They stay separate contacts.
    Keep,
    /// They are one contact.
    Merge(PrincipalContact),
}

/// Whether a contact touches at a single point (f-v, v-f, e-e, e-v, v-e, v-v).
fn is_point_contact(pc: &PrincipalContact) -> bool {
    use ContactKind as K;
    matches!(
        pc.kind,
        K::FaceVertex | K::VertexFace | K::EdgeEdge | K::EdgeVertex | K::VertexEdge | K::VertexVertex
    )
}

/// The derived mapping rules for a pair of contacts: everything the pair can become;
/// empty when the two cannot hold together (topological existence fails).
fn combine(fixed: &Part, moving: &Part, c1: PrincipalContact, c2: PrincipalContact, hinged: bool) -> Vec<Outcome> {
    if c1 == c2 {
        return vec![Outcome::Merge(c1)];
    }
    let (a1, b1, a2, b2) = (c1.fixed, c1.moving, c2.fixed, c2.moving);
    // One point of B (a vertex, or an edge lying in two faces) touching two elements of
    // A: it lies where their closures meet.
    if b1 == b2 && (b1.is_vertex() || (b1.is_edge() && a1.is_face() && a2.is_face())) {
        return meet(fixed, a1, a2)
            .into_iter()
            .map(|a| Outcome::Merge(contact(a, b1)))
            .collect();
    }
    if a1 == a2 && (a1.is_vertex() || (a1.is_edge() && b1.is_face() && b2.is_face())) {
        return meet(moving, b1, b2)
            .into_iter()
            .map(|b| Outcome::Merge(contact(a1, b)))
            .collect();
    }
    let mut outcomes = Vec::new();
    // Two contacts between parts of one element on each side: one higher contact. When
    // an edge (a line) is one of the two, its two points in the other element force it
    // there; two points of a face in another face's plane do not (the faces may hinge
    // about the line through them), so with `hinged` the contacts may also stay apart.
    match (join(fixed, a1, a2), join(moving, b1, b2)) {
        (Some(a), Some(b)) => {
            let merged = contact(a, b);
            // Two crossings that join into the same crossing pair stay a crossing.
            let merged = if merged.fixed == a1 && merged.moving == b1 {
                c1
            } else if merged.fixed == a2 && merged.moving == b2 {
                c2
            } else {
                merged
            };
            if hinged && a.is_face() && b.is_face() && merged != c1 && merged != c2 {
                outcomes.push(Outcome::Keep);
            }
            outcomes.push(Outcome::Merge(merged));
        }
        _ => outcomes.push(Outcome::Keep),
    }
    // The two contact points may also coincide, where the elements' closures meet on
    // both sides: f-v plus e-e through that vertex on the face's edge is e-v; two edges
    // of A at one vertex crossing one edge of B is v-e there. For nested elements (a
    // contact and one through its boundary) this is the lower contact.
    let nested = |part: &Part, x: ElementId, y: ElementId| part.in_closure(x, y) || part.in_closure(y, x);
    let nested_both = nested(fixed, a1, a2) && nested(moving, b1, b2);
    if nested_both || (is_point_contact(&c1) && is_point_contact(&c2)) {
        for a in meet(fixed, a1, a2) {
            for b in meet(moving, b1, b2) {
                let low = PrincipalContact {
                    fixed: a,
                    moving: b,
                    kind: ContactKind::of(a, b, false),
                };
                if low != c1 && low != c2 && !outcomes.contains(&Outcome::Merge(low)) {
                    outcomes.push(Outcome::Merge(low));
                }
            }
        }
    }
    outcomes
}

/// Closes a list of contacts under the mapping rules: every description it can map to,
/// each sorted; nothing when the combination cannot exist. `kept` holds the pairs
/// already taken to stay separate.
fn close(
    fixed: &Part,
    moving: &Part,
    hinged: bool,
    list: Vec<PrincipalContact>,
    kept: &mut Vec<[PrincipalContact; 2]>,
    out: &mut BTreeSet<Vec<PrincipalContact>>,
) {
    for i in 0..list.len() {
        for j in i + 1..list.len() {
            let pair = if list[i] <= list[j] {
                [list[i], list[j]]
            } else {
                [list[j], list[i]]
            };
            if kept.contains(&pair) {
                continue;
            }
            let outcomes = combine(fixed, moving, list[i], list[j], hinged);
            if outcomes == [Outcome::Keep] {
                continue;
            }
            for outcome in outcomes {
                match outcome {
                    Outcome::Keep => {
                        kept.push(pair);
                        close(fixed, moving, hinged, list.clone(), kept, out);
                        kept.pop();
                    }
                    Outcome::Merge(merged) => {
                        let mut next: Vec<PrincipalContact> = list
                            .iter()
                            .enumerate()
                            .filter(|&(k, _)| k != i && k != j)
                            .map(|(_, c)| *c)
                            .collect();
                        next.push(merged);
                        close(fixed, moving, hinged, next, kept, out);
                    }
                }
            }
            return;
        }
    }
    let mut list = list;
    list.sort();
    list.dedup();
    out.insert(list);
}

/// The states a state plus one primitive contact can map to (TopUniqDesc); empty when
/// topological existence rules the combination out. Two point contacts within one face
/// on each side map to the two faces in contact (the likely outcome, which keeps the
/// search small); [`grow_every`] also keeps them apart.
// The paper's one-outcome mapping: used by the tests here (and by a search that follows
// the paper step by step).
#[cfg_attr(not(test), allow(dead_code))]
#[must_use]
pub fn grow(
    fixed: &Part,
    moving: &Part,
    state: &[PrincipalContact],
    added: PrincipalContact,
) -> Vec<Vec<PrincipalContact>> {
    grow_with(fixed, moving, state, added, false)
}

/// Every state a state plus one primitive contact can map to, including two point
/// contacts of one face on each side that stay apart (the faces hinged about the line
/// through the two points): what decides whether two known states are neighbours.
#[must_use]
pub fn grow_every(
    fixed: &Part,
    moving: &Part,
    state: &[PrincipalContact],
    added: PrincipalContact,
) -> Vec<Vec<PrincipalContact>> {
    grow_with(fixed, moving, state, added, true)
}

fn grow_with(
    fixed: &Part,
    moving: &Part,
    state: &[PrincipalContact],
    added: PrincipalContact,
    hinged: bool,
) -> Vec<Vec<PrincipalContact>> {
    let mut list = state.to_vec();
    list.push(added);
    let mut out = BTreeSet::new();
    close(fixed, moving, hinged, list, &mut Vec::new(), &mut out);
    out.into_iter().collect()
}

/// The primitive contacts a contact implies (its KLC, docs/concepts.md#ppc-and-klc): those that
/// hold wherever it holds, in the closure of its contact region. f-e: the edge's ends
/// on the face and the edge crossing the face's boundary; f-f: the vertices of either
/// face on the other and the crossings of their boundaries; e-v: the vertex on the
/// edge's faces and the vertex's edges crossing the edge; e-e-t: the ends of each edge
/// on the other's faces; v-v: everything around both vertices.
#[must_use]
pub fn implied_primitives(fixed: &Part, moving: &Part, pc: &PrincipalContact) -> Vec<PrincipalContact> {
    use ContactKind as K;
    let (a, b) = (pc.fixed, pc.moving);
    // (faces of A, vertices of B), (vertices of A, faces of B), (edges of A, edges of B)
    let (face_vertex, vertex_face, edge_edge) = match pc.kind {
        K::FaceVertex | K::VertexFace | K::EdgeEdge => ((vec![], vec![]), (vec![], vec![]), (vec![], vec![])),
        K::FaceEdge => (
            (fixed.faces_around(a), moving.closure_vertices(b)),
            (vec![], vec![]),
            (fixed.closure_edges(a), moving.closure_edges(b)),
        ),
        K::EdgeFace => (
            (vec![], vec![]),
            (fixed.closure_vertices(a), moving.faces_around(b)),
            (fixed.closure_edges(a), moving.closure_edges(b)),
        ),
        K::FaceFace => (
            (fixed.faces_around(a), moving.closure_vertices(b)),
            (fixed.closure_vertices(a), moving.faces_around(b)),
            (fixed.closure_edges(a), moving.closure_edges(b)),
        ),
        K::EdgeVertex => (
            (fixed.faces_around(a), moving.closure_vertices(b)),
            (vec![], vec![]),
            (fixed.closure_edges(a), edges_at(moving, b)),
        ),
        K::VertexEdge => (
            (vec![], vec![]),
            (fixed.closure_vertices(a), moving.faces_around(b)),
            (edges_at(fixed, a), moving.closure_edges(b)),
        ),
        K::EdgeEdgeTouch => (
            (fixed.faces_around(a), moving.closure_vertices(b)),
            (fixed.closure_vertices(a), moving.faces_around(b)),
            (fixed.closure_edges(a), moving.closure_edges(b)),
        ),
        K::VertexVertex => (
            (fixed.faces_around(a), moving.closure_vertices(b)),
            (fixed.closure_vertices(a), moving.faces_around(b)),
            (edges_at(fixed, a), edges_at(moving, b)),
        ),
    };
    let mut out = Vec::new();
    if crate::feasibility::is_primitive(pc) {
        out.push(*pc);
    }
    for &f in &face_vertex.0 {
        for &v in face_vertex.1.iter().filter(|&&v| moving.vertex(v).convex) {
            out.push(PrincipalContact {
                fixed: ElementId::Face(f),
                moving: ElementId::Vertex(v),
                kind: ContactKind::FaceVertex,
            });
        }
    }
    for &v in vertex_face.0.iter().filter(|&&v| fixed.vertex(v).convex) {
        for &f in &vertex_face.1 {
            out.push(PrincipalContact {
                fixed: ElementId::Vertex(v),
                moving: ElementId::Face(f),
                kind: ContactKind::VertexFace,
            });
        }
    }
    for &e in edge_edge.0.iter().filter(|&&e| fixed.edge(e).convex) {
        for &x in edge_edge.1.iter().filter(|&&x| moving.edge(x).convex) {
            out.push(PrincipalContact {
                fixed: ElementId::Edge(e),
                moving: ElementId::Edge(x),
                kind: ContactKind::EdgeEdge,
            });
        }
    }
    out.sort();
    out.dedup();
    out
}

/// The edges at a vertex (a vertex touch lies on each of them).
fn edges_at(part: &Part, e: ElementId) -> Vec<EdgeId> {
    match e {
        ElementId::Vertex(v) => part.vertex(v).edges.clone(),
        _ => Vec::new(),
    }
}

/// The KLC of a state: every primitive contact it implies.
#[must_use]
pub fn state_primitives(fixed: &Part, moving: &Part, state: &[PrincipalContact]) -> BTreeSet<PrincipalContact> {
    state
        .iter()
        .flat_map(|pc| implied_primitives(fixed, moving, pc))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::cube_and_slab;

    fn pc(fixed: ElementId, moving: ElementId) -> PrincipalContact {
        PrincipalContact {
            fixed,
            moving,
            kind: ContactKind::of(fixed, moving, false),
        }
    }

    /// Two edges of the cube at one corner, and one edge of the slab's top face.
    fn corner_edges(cube: &Part) -> (VertexId, EdgeId, EdgeId) {
        let v = VertexId(0);
        let edges = &cube.vertex(v).edges;
        (v, edges[0], edges[1])
    }

    #[test]
    fn two_crossings_of_one_edge_may_coincide_at_the_vertex_between_them() {
        // Fixed: the cube (A); moving: the slab (B). Two edges of A at vertex v both
        // crossing edge x of B: apart (two e-e), or at v (v-e), never anything else.
        let (slab, cube) = cube_and_slab();
        let (v, e1, e2) = corner_edges(&cube);
        let x = slab.convex_edges().next().expect("a convex edge");
        let c1 = pc(ElementId::Edge(e1), ElementId::Edge(x));
        let c2 = pc(ElementId::Edge(e2), ElementId::Edge(x));
        let grown = grow(&cube, &slab, &[c1], c2);
        let at_vertex = vec![pc(ElementId::Vertex(v), ElementId::Edge(x))];
        assert!(grown.contains(&at_vertex), "{grown:?}");
        // e1 and e2 share a face of the cube: the edge may also lie in it (f-e); two
        // separate crossings of a convex face's boundary by a straight edge put the edge
        // in the face, so they are not proposed apart.
        let face = join(&cube, ElementId::Edge(e1), ElementId::Edge(e2)).expect("a common face");
        assert!(grown.contains(&vec![contact(face, ElementId::Edge(x))]), "{grown:?}");
        assert_eq!(grown.len(), 2, "{grown:?}");
    }

    #[test]
    fn a_vertex_on_a_face_and_a_crossing_through_it_may_be_one_edge_vertex_contact() {
        let (slab, cube) = cube_and_slab();
        // The slab's top face f and one of its edges e; a cube vertex w and an edge y
        // ending at w.
        let f = FaceId(0);
        let e = slab.closure_edges(ElementId::Face(f))[0];
        let w = VertexId(0);
        let y = cube.vertex(w).edges[0];
        let on_face = pc(ElementId::Face(f), ElementId::Vertex(w));
        let crossing = pc(ElementId::Edge(e), ElementId::Edge(y));
        let grown = grow(&slab, &cube, &[on_face], crossing);
        assert!(
            grown.contains(&vec![pc(ElementId::Edge(e), ElementId::Vertex(w))]),
            "{grown:?}"
        );
        assert!(
            grown.contains(&vec![contact(ElementId::Face(f), ElementId::Edge(y))]),
            "{grown:?}"
        );
    }

    #[test]
    fn contacts_with_disjoint_elements_stay_apart() {
        let (slab, cube) = cube_and_slab();
        // Two opposite cube vertices on one slab face: no common element on the cube,
        // so no merge; the two f-v contacts stay.
        let f = ElementId::Face(FaceId(0));
        let far = (0..cube.vertices().len() as u32)
            .map(VertexId)
            .max_by(|a, b| {
                let p0 = cube.vertex(VertexId(0)).position;
                p0.distance(cube.vertex(*a).position)
                    .total_cmp(&p0.distance(cube.vertex(*b).position))
            })
            .expect("vertices");
        let c1 = pc(f, ElementId::Vertex(VertexId(0)));
        let c2 = pc(f, ElementId::Vertex(far));
        let mut both = vec![c1, c2];
        both.sort();
        assert_eq!(grow(&slab, &cube, &[c1], c2), vec![both]);
    }

    #[test]
    fn two_corners_of_one_face_on_a_face_may_hinge_apart() {
        // Two diagonal corners of a cube face on the slab's face: the cube face on the
        // slab (f-f) is the likely outcome; the cube may also rest on the two corners,
        // turned about the diagonal, which only `grow_every` keeps.
        let (slab, cube) = cube_and_slab();
        let f = ElementId::Face(FaceId(0));
        let g = cube.vertex(VertexId(0)).faces[0];
        let corners = cube.closure_vertices(ElementId::Face(g));
        let v = corners[0];
        let diagonal = *corners
            .iter()
            .find(|&&w| w != v && !cube.vertex(v).edges.iter().any(|&e| cube.edge(e).vertices.contains(&w)))
            .expect("the opposite corner");
        let (c1, c2) = (pc(f, ElementId::Vertex(v)), pc(f, ElementId::Vertex(diagonal)));
        let on_face = vec![contact(f, ElementId::Face(g))];
        let mut apart = vec![c1, c2];
        apart.sort();
        assert_eq!(grow(&slab, &cube, &[c1], c2), vec![on_face.clone()]);
        let every = grow_every(&slab, &cube, &[c1], c2);
        assert!(every.contains(&on_face) && every.contains(&apart), "{every:?}");
    }
}
