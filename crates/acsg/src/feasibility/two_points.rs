//! An edge with two points held on a face's plane lies in that plane (DOMAIN §7): a
//! combinatorial test of a state's contacts that the witness check and the decisions
//! share, so that what one rejects the other proves infeasible.
//!
//! A point of one part is *held* on a face `F` of the other when a contact puts it
//! there: the contact point of a point contact (f-v, v-f, e-e, and the contacts in
//! concave edges and corners) with its element of the other part in `F`'s closure,
//! and every corner of an edge or face listed as lying on `F` (f-e, e-f, f-f: read from
//! end to end, each corner lies within the tolerance of `F`'s plane). When two held
//! points of two different contacts lie on one edge `X` (the edge itself, or its two
//! ends, or an end and a crossing), `X` has two points on `F`'s plane, so `X` lies in
//! that plane and, wherever it overlaps `F`, the contact is `X` in `F` (e-f or f-e),
//! which the state does not list. In exact geometry such a state never occurs: an
//! edge leaving a vertex that lies on a floor, and crossing the floor's rim elsewhere,
//! lies on the floor and enters it past the rim. It shows up only within the
//! tolerance, with the edge turned off the rim's line by less than the tolerance over
//! the separation (the built-in example's bottom edge on the floor with the next
//! bottom edge crossing the floor's front edge, 1e-7 mm over the floor's plane): an
//! artefact of the tolerance, not a state.
//!
//! The state is left alone when one of its contacts already lists `X` on `F` (f-e,
//! e-f, or f-f with `X` in the closure of the lying face).

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{EdgeId, ElementId, FaceId, Part};

/// A point held on a face of the other part: which contact holds it (its index in the
/// state), its element on the part that owns the point, the element of the other part
/// it lies on.
#[derive(Clone, Copy)]
struct Held {
    contact: usize,
    own: ElementId,
    on: ElementId,
}

/// Whether two held points of different contacts put an edge of one part on a face of
/// the other that no contact lists it on (see the module's documentation): `true`
/// means that no pose shows `contacts` robustly.
pub(crate) fn edge_on_two_points(fixed: &Part, moving: &Part, contacts: &[PrincipalContact]) -> bool {
    // The moving part's points on the fixed part's faces, then the other way round.
    let moving_points = held_points(fixed, moving, contacts, Side::Moving);
    let fixed_points = held_points(fixed, moving, contacts, Side::Fixed);
    lies_unlisted(moving, fixed, &moving_points, contacts, Side::Moving)
        || lies_unlisted(fixed, moving, &fixed_points, contacts, Side::Fixed)
}

/// The part whose points are held.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Fixed,
    Moving,
}

impl Side {
    /// A contact's elements as (the side's own, the other part's).
    fn split(self, pc: &PrincipalContact) -> (ElementId, ElementId) {
        match self {
            Side::Fixed => (pc.fixed, pc.moving),
            Side::Moving => (pc.moving, pc.fixed),
        }
    }
}

/// The points of `side`'s part that the contacts hold on the other part's elements.
fn held_points(fixed: &Part, moving: &Part, contacts: &[PrincipalContact], side: Side) -> Vec<Held> {
    use ContactKind as K;
    let own_part = if side == Side::Fixed { fixed } else { moving };
    let mut out = Vec::new();
    for (contact, pc) in contacts.iter().enumerate() {
        let (own, on) = side.split(pc);
        match pc.kind {
            K::FaceVertex | K::VertexFace | K::EdgeEdge | K::EdgeVertex | K::VertexEdge | K::VertexVertex => {
                out.push(Held { contact, own, on });
            }
            // A lying edge or face: its corners on the other's face.
            K::FaceEdge | K::EdgeFace | K::FaceFace if matches!(on, ElementId::Face(_)) => {
                for v in own_part.closure_vertices(own) {
                    out.push(Held {
                        contact,
                        own: ElementId::Vertex(v),
                        on,
                    });
                }
            }
            _ => {}
        }
    }
    out
}

/// Whether two held points of different contacts lie on one edge of `part` and on one
/// face of `other` that no contact lists the edge on.
fn lies_unlisted(part: &Part, other: &Part, held: &[Held], contacts: &[PrincipalContact], side: Side) -> bool {
    held.iter().enumerate().any(|(i, p)| {
        held[i + 1..].iter().any(|q| {
            // Two distinct points: two different vertices, or a crossing of the edge.
            let distinct = p.own != q.own || matches!(p.own, ElementId::Edge(_));
            if p.contact == q.contact || !distinct {
                return false;
            }
            let q_edges = edges_holding(part, q.own);
            edges_holding(part, p.own)
                .into_iter()
                .filter(|x| q_edges.contains(x))
                .any(|x| {
                    other
                        .faces_around(p.on)
                        .into_iter()
                        .filter(|&f| other.in_closure(ElementId::Face(f), q.on))
                        .any(|f| !listed_on(part, contacts, side, x, f))
                })
        })
    })
}

/// The edges whose closure holds a point element: the edge itself, or a vertex's edges.
fn edges_holding(part: &Part, e: ElementId) -> Vec<EdgeId> {
    match e {
        ElementId::Edge(x) => vec![x],
        ElementId::Vertex(v) => part.vertex(v).edges.clone(),
        ElementId::Face(_) => Vec::new(),
    }
}

/// Whether a contact lists edge `x` (of `side`'s part) lying on face `f` of the other:
/// f-e or e-f of the two, or a face holding `x` lying on `f`.
fn listed_on(part: &Part, contacts: &[PrincipalContact], side: Side, x: EdgeId, f: FaceId) -> bool {
    use ContactKind as K;
    contacts.iter().any(|pc| {
        let (own, on) = side.split(pc);
        matches!(pc.kind, K::FaceEdge | K::EdgeFace | K::FaceFace)
            && on == ElementId::Face(f)
            && part.in_closure(own, ElementId::Edge(x))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::l_block_and_box;

    fn pc(fixed: &str, moving: &str, along: bool) -> PrincipalContact {
        let (fixed, moving): (ElementId, ElementId) = (fixed.parse().unwrap(), moving.parse().unwrap());
        PrincipalContact {
            fixed,
            moving,
            kind: ContactKind::of(fixed, moving, along),
        }
    }

    /// The box's edges at a vertex, and the L-block's floor with one of its rim edges.
    fn floor_and_rim(block: &Part) -> (FaceId, EdgeId) {
        // The floor: the face whose outward normal points up, lowest of those.
        let floor = (0..block.faces().len() as u32)
            .map(FaceId)
            .filter(|&f| block.face(f).normal.z > 0.99)
            .min_by(|&f, &g| block.face(f).offset.total_cmp(&block.face(g).offset))
            .expect("an upward face");
        let rim = block.face(floor).outer().edges[0];
        (floor, rim)
    }

    #[test]
    fn an_edge_from_a_lying_edges_end_crossing_the_faces_rim_is_caught() {
        let (block, bx) = l_block_and_box();
        let (floor, rim) = floor_and_rim(&block);
        // A bottom edge of the box lying on the floor, and another edge at one of its
        // ends crossing the floor's rim.
        let lying = bx.edges().len() as u32;
        let (e, x) = (0..lying)
            .map(EdgeId)
            .flat_map(|e| {
                let bx = &bx;
                bx.edge(e).vertices.iter().flat_map(move |&v| {
                    bx.vertex(v)
                        .edges
                        .iter()
                        .filter(move |&&x| x != e)
                        .map(move |&x| (e, x))
                })
            })
            .next()
            .expect("two edges at a vertex");
        let f = format!("f{}", floor.0);
        let state = [
            pc(&f, &format!("e{}", e.0), true),
            pc(&format!("e{}", rim.0), &format!("e{}", x.0), false),
        ];
        assert!(edge_on_two_points(&block, &bx, &state));
        // With the crossing edge listed on the floor too, nothing is left unlisted.
        let mut listed = state.to_vec();
        listed.push(pc(&f, &format!("e{}", x.0), true));
        assert!(!edge_on_two_points(&block, &bx, &listed));
        // The crossing edge not meeting the lying edge: nothing to say.
        let apart = (0..lying)
            .map(EdgeId)
            .find(|&y| {
                let shared = bx.edge(y).vertices.iter().any(|v| bx.edge(e).vertices.contains(v));
                y != e && !shared
            })
            .expect("an edge apart");
        let other = [
            pc(&f, &format!("e{}", e.0), true),
            pc(&format!("e{}", rim.0), &format!("e{}", apart.0), false),
        ];
        assert!(!edge_on_two_points(&block, &bx, &other));
    }

    #[test]
    fn one_lying_edge_alone_is_not_two_contacts() {
        let (block, bx) = l_block_and_box();
        let (floor, _) = floor_and_rim(&block);
        let state = [pc(&format!("f{}", floor.0), "e0", true)];
        assert!(!edge_on_two_points(&block, &bx, &state));
    }
}
