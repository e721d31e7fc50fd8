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
//!
//! The chord between two contacts obeys the same kind of law
//! ([`chord_off_the_boundary`]). Every contact but face on face has a point in the
//! interiors of both its elements (a point contact's point, a point of a lying edge
//! over the face's interior, of two edges running together), and the chord between two
//! such points must not reach into either part's interior: next to every point of one
//! part's boundary lies that part's interior, and next to every point of a part lies
//! some of its interior, so a chord point on one part's boundary (or inside it) and
//! inside the other (or on its boundary) makes the parts penetrate. Three cases follow,
//! each decided on the contacts' elements alone:
//! - the chord lies on one part's boundary (along an edge, or through the interior of a
//!   face `F`: convex without holes, or the two elements spanning a polygon in it that
//!   no other edge of it enters) and one convex piece of the other part holds both
//!   ends' elements, so the chord: the chord lies on that part's boundary too, in one
//!   of its edges or faces, and such a face lies flush on `F` (f-f);
//! - the chord runs through the interiors of a face of each part: the faces lie flush;
//! - each part holds the chord (both ends' elements in one convex piece of each): it
//!   lies on a face or an edge of each.
//!
//! A state that breaks one has no exact pose: the parts penetrate. Within the tolerance
//! a face may turn off the other by the tolerance over the chord's reach (the built-in
//! example's box with the corner of its end face past the corner of the L-block's wall,
//! a bottom and a side edge crossing the wall's top and side edges): an artefact again.

use glam::DVec3;

use crate::contact::{ContactKind, PrincipalContact};
use crate::geometry::{PlanarRegion, hull_in_plane};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use crate::tolerance::{WELD_REL, scaled};

/// The smallest turn (a sine) at every corner of a face that [`chord_off_the_boundary`]
/// takes as convex: a corner that turns less is as good as straight, and a chord
/// between points on its two edges runs along the face's rim.
const LEAST_CORNER_TURN: f64 = 1e-3;

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

/// Whether two contacts' points lie on one part's boundary (the chord between them
/// through the interior of one of its faces, or along one of its edges) where the other
/// part cannot hold that chord (see the module's documentation): `true` means that no
/// pose shows `contacts` robustly.
pub(crate) fn chord_off_the_boundary(fixed: &Part, moving: &Part, contacts: &[PrincipalContact]) -> bool {
    use ContactKind as K;
    // Each contact but face on face has a point in the interiors of both its elements:
    // a point contact's point, a point where a lying edge overlaps the face's interior
    // or where two edges run together. (Face on face holds no point that another pair
    // of faces could share.)
    let points: Vec<&PrincipalContact> = contacts.iter().filter(|pc| pc.kind != K::FaceFace).collect();
    let flush = |f: FaceId, g: FaceId| {
        contacts.iter().any(|pc| {
            pc.kind == ContactKind::FaceFace && pc.fixed == ElementId::Face(f) && pc.moving == ElementId::Face(g)
        })
    };
    points.iter().enumerate().any(|(i, a)| {
        points[i + 1..].iter().any(|b| {
            let through_fixed = common_faces(fixed, a.fixed, b.fixed);
            let through_moving = common_faces(moving, a.moving, b.moving);
            let chord_on_fixed = !through_fixed.is_empty() || along_an_edge(fixed, a.fixed, b.fixed);
            let chord_on_moving = !through_moving.is_empty() || along_an_edge(moving, a.moving, b.moving);
            (chord_on_fixed && !holds_chord(moving, a.moving, b.moving, &through_fixed, |g, f| flush(f, g)))
                || (chord_on_moving && !holds_chord(fixed, a.fixed, b.fixed, &through_moving, flush))
                || (in_one_piece(fixed, a.fixed, b.fixed)
                    && in_one_piece(moving, a.moving, b.moving)
                    && !(on_one_element(fixed, a.fixed, b.fixed) && on_one_element(moving, a.moving, b.moving)))
        })
    })
}

/// Whether one convex piece of `part` holds `a` and `b` (every corner of both), and so
/// every chord between their points.
///
/// A chord inside both parts lies on both boundaries: a point of it inside one part
/// has the other part's interior next to it. A segment on a part's boundary lies in
/// one of its faces or edges (across an edge it would leave the boundary), whose
/// closure then holds the elements of both ends ([`on_one_element`]).
fn in_one_piece(part: &Part, a: ElementId, b: ElementId) -> bool {
    let eps = scaled(WELD_REL, part.bounds().diagonal());
    let corners: Vec<DVec3> = part
        .closure_vertices(a)
        .into_iter()
        .chain(part.closure_vertices(b))
        .map(|v| part.vertex(v).position)
        .collect();
    part.convex_pieces()
        .iter()
        .any(|piece| corners.iter().all(|&p| piece.outside_distance(p) <= eps))
}

/// Whether an edge or a face of `part` holds both `a` and `b` in its closure.
fn on_one_element(part: &Part, a: ElementId, b: ElementId) -> bool {
    along_an_edge(part, a, b) || faces_holding(part, a, b).next().is_some()
}

/// The faces of `part` whose closures hold both `a` and `b`.
fn faces_holding(part: &Part, a: ElementId, b: ElementId) -> impl Iterator<Item = FaceId> + '_ {
    part.faces_around(a)
        .into_iter()
        .filter(move |&f| part.in_closure(ElementId::Face(f), b))
}

/// Whether `part` may hold a chord that lies on the other part's boundary (through the
/// interiors of the other part's faces `through`, or along its edges) between a point
/// in the interior of its element `a` and one in the interior of `b`; `flush(g, f)`
/// says whether its face `g` lies flush on the other part's face `f`.
///
/// Every point of the other part's boundary has that part's interior next to it, which
/// `part` must not reach. When one convex piece of `part` holds `a` and `b`, it holds
/// the chord, so the chord lies on the part's boundary: in one of its edges, or in one
/// of its faces, whose closure then holds `a` and `b`; that face lies flush on a face
/// of `through`. Otherwise: a face whose interior the chord runs through lies flush on
/// a face of `through`.
fn holds_chord(
    part: &Part,
    a: ElementId,
    b: ElementId,
    through: &[FaceId],
    flush: impl Fn(FaceId, FaceId) -> bool,
) -> bool {
    let flush_on_through = |g: FaceId| through.iter().all(|&f| flush(g, f));
    if in_one_piece(part, a, b) {
        along_an_edge(part, a, b) || faces_holding(part, a, b).any(flush_on_through)
    } else {
        common_faces(part, a, b).into_iter().all(flush_on_through)
    }
}

/// Whether an edge of `part` holds both `a` and `b` in its closure.
fn along_an_edge(part: &Part, a: ElementId, b: ElementId) -> bool {
    edges_holding(part, a)
        .into_iter()
        .any(|x| part.in_closure(ElementId::Edge(x), b))
}

/// The faces of `part` whose closures hold both `a` and `b`, on no common edge of the
/// face, such that the chord between any point of `a` and any point of `b` runs
/// through the face's interior: every face that is convex without holes, and a face
/// that is not when `a` and `b` are vertices or edges whose corners span a polygon in
/// the face that no other edge of the face enters ([`spans_within`]).
fn common_faces(part: &Part, a: ElementId, b: ElementId) -> Vec<FaceId> {
    let rim = |f: FaceId, e: ElementId| -> Vec<EdgeId> {
        edges_holding(part, e)
            .into_iter()
            .filter(|&x| part.in_closure(ElementId::Face(f), ElementId::Edge(x)))
            .collect()
    };
    faces_holding(part, a, b)
        .filter(|&f| {
            let on_a = rim(f, a);
            rim(f, b).iter().all(|x| !on_a.contains(x))
        })
        .filter(|&f| strictly_convex(part, f) || spans_within(part, f, a, b))
        .collect()
}

/// Whether the corners of `a` and `b` (vertices or edges of face `f`) span a convex
/// polygon inside the face that no edge of the face other than `a` and `b` enters
/// (an edge from one of their corners may touch it there, leaving at an angle of more
/// than a thousandth): every chord between a point
/// of `a` and one of `b` then runs through the face's interior. A bay of an L-shaped
/// face between its two edges at the inner corner fails: the polygon covers the notch.
fn spans_within(part: &Part, f: FaceId, a: ElementId, b: ElementId) -> bool {
    if matches!(a, ElementId::Face(_)) || matches!(b, ElementId::Face(_)) {
        return false;
    }
    let face = part.face(f);
    let eps = scaled(WELD_REL, part.bounds().diagonal());
    let at = |v: VertexId| part.vertex(v).position;
    let mut corners: Vec<VertexId> = part.closure_vertices(a);
    corners.extend(part.closure_vertices(b));
    let hull = hull_in_plane(&corners.iter().map(|&v| at(v)).collect::<Vec<_>>(), face.normal, eps);
    if hull.len() < 3 {
        return false;
    }
    let own = |x: EdgeId| ElementId::Edge(x) == a || ElementId::Edge(x) == b;
    let entered = face.loops.iter().flat_map(|l| l.edges.iter()).any(|&x| {
        if own(x) {
            return false;
        }
        // An edge from a corner may touch the polygon there: its rest, from a thousand
        // times the tolerance off that corner, must stay out.
        let [mut p, mut q] = part.edge(x).vertices;
        if corners.contains(&q) {
            std::mem::swap(&mut p, &mut q);
        }
        let from_corner = corners.contains(&p);
        let (p, q) = (at(p), at(q));
        let p = if from_corner {
            p + (q - p) * (1e3 * eps / p.distance(q)).min(1.0)
        } else {
            p
        };
        clip_to_convex(p, q, &hull, face.normal, eps).is_some()
    });
    // No edge enters the polygon, so it is inside the face or outside: its centre says.
    let loops: Vec<Vec<DVec3>> = face
        .loops
        .iter()
        .map(|l| l.vertices.iter().map(|&v| at(v)).collect())
        .collect();
    let region = PlanarRegion {
        normal: face.normal,
        offset: face.offset,
        loops: &loops,
        triangles: &[],
    };
    !entered && region.contains_projection(hull.iter().copied().sum::<DVec3>() / hull.len() as f64)
}

/// The part `[t0, t1]` of the segment from `p` to `q` (as parameters in `[0, 1]`)
/// within `eps` of the convex polygon `hull` (counter-clockwise about `n`, on the
/// segment's plane), `None` when none is.
fn clip_to_convex(p: DVec3, q: DVec3, hull: &[DVec3], n: DVec3, eps: f64) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for i in 0..hull.len() {
        let (h, k) = (hull[i], hull[(i + 1) % hull.len()]);
        let inward = n.cross(k - h).normalize();
        // Distance to the inner side of the side, at p and at q.
        let (dp, dq) = (inward.dot(p - h) + eps, inward.dot(q - h) + eps);
        if dp < 0.0 && dq < 0.0 {
            return None;
        }
        if dp < 0.0 {
            t0 = t0.max(dp / (dp - dq));
        } else if dq < 0.0 {
            t1 = t1.min(dp / (dp - dq));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Whether a face has no holes and turns by at least [`LEAST_CORNER_TURN`] at every
/// corner, always the same way.
fn strictly_convex(part: &Part, f: FaceId) -> bool {
    let face = part.face(f);
    if !face.holes().is_empty() {
        return false;
    }
    let corners: Vec<_> = face.outer().vertices.iter().map(|&v| part.vertex(v).position).collect();
    let n = corners.len();
    (0..n).all(|i| {
        let (prev, here, next) = (corners[(i + n - 1) % n], corners[i], corners[(i + 1) % n]);
        (here - prev)
            .normalize()
            .cross((next - here).normalize())
            .dot(face.normal)
            >= LEAST_CORNER_TURN
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

    /// The name of the edge of `part` between two corners.
    fn edge(part: &Part, p: [f64; 3], q: [f64; 3]) -> String {
        let ElementId::Edge(x) = crate::testing::edge_between(part, p.into(), q.into()) else {
            panic!("an edge between the corners");
        };
        format!("e{}", x.0)
    }

    /// The name of the vertex of `part` at a corner.
    fn vertex(part: &Part, at: [f64; 3]) -> String {
        let v = part
            .vertices()
            .iter()
            .position(|v| v.position == glam::DVec3::from(at))
            .expect("a vertex there");
        format!("v{v}")
    }

    /// The name of the face of `part` whose outward normal is `normal` and whose plane
    /// passes through `at`.
    fn face(part: &Part, normal: [f64; 3], at: [f64; 3]) -> String {
        let (n, p) = (glam::DVec3::from(normal), glam::DVec3::from(at));
        let f = part
            .faces()
            .iter()
            .position(|f| f.normal.dot(n) > 0.999 && (f.normal.dot(p) - f.offset).abs() < 1e-9)
            .expect("a face there");
        format!("f{f}")
    }

    #[test]
    fn the_corner_of_a_face_past_the_corner_of_another_lies_flush_on_it() {
        // The box's end face (x = 150) against the L-block's wall (x = 150): the box's
        // side edge crossing the wall's top edge and its bottom edge crossing the
        // wall's side edge. The chord between the crossings cuts the corner of both
        // faces, so in exact geometry the end face lies on the wall.
        let (block, bx) = l_block_and_box();
        let wall_top = edge(&block, [150.0, 0.0, 150.0], [150.0, 100.0, 150.0]);
        let wall_side = edge(&block, [150.0, 100.0, 50.0], [150.0, 100.0, 150.0]);
        let box_side = edge(&bx, [150.0, 90.0, 50.0], [150.0, 90.0, 150.0]);
        let box_bottom = edge(&bx, [150.0, 10.0, 50.0], [150.0, 90.0, 50.0]);
        let state = [pc(&wall_top, &box_side, false), pc(&wall_side, &box_bottom, false)];
        assert!(chord_off_the_boundary(&block, &bx, &state));
        // Listed flush, the state says so itself.
        let wall = face(&block, [-1.0, 0.0, 0.0], [150.0, 0.0, 0.0]);
        let end = face(&bx, [1.0, 0.0, 0.0], [150.0, 0.0, 0.0]);
        let mut flush = state.to_vec();
        flush.push(pc(&wall, &end, false));
        assert!(!chord_off_the_boundary(&block, &bx, &flush));
        // Two box edges crossing the one wall edge: the chord runs along the wall's
        // rim, not through it (the edge rule speaks there).
        let box_front = edge(&bx, [150.0, 10.0, 50.0], [150.0, 10.0, 150.0]);
        let along_rim = [pc(&wall_top, &box_side, false), pc(&wall_top, &box_front, false)];
        assert!(!chord_off_the_boundary(&block, &bx, &along_rim));
        assert!(edge_on_two_points(&block, &bx, &along_rim));
        // The wall's side edge lying on the box's end face, and the wall's top edge
        // crossing a bottom edge that leaves the end face: the chord between them runs
        // through the wall, inside the (convex) box, and on no face or edge of it, so
        // the box reaches past the wall.
        let leaving = edge(&bx, [50.0, 90.0, 50.0], [150.0, 90.0, 50.0]);
        let off_the_box = [pc(&wall_top, &leaving, false), pc(&wall_side, &end, false)];
        assert!(chord_off_the_boundary(&block, &bx, &off_the_box));
        // The top edge crossing an edge of the end face instead: flush, or nothing.
        let on_the_end = [pc(&wall_top, &box_side, false), pc(&wall_side, &end, false)];
        assert!(chord_off_the_boundary(&block, &bx, &on_the_end));
        // The wall's top edge crossing the box's side edge, and its end on the box's
        // bottom face: the chord runs along the wall's edge, inside the box, and on no
        // face or edge of it.
        let corner = vertex(&block, [150.0, 100.0, 150.0]);
        let bottom = face(&bx, [0.0, 0.0, -1.0], [0.0, 0.0, 50.0]);
        let along_wall_edge = [pc(&wall_top, &box_side, false), pc(&corner, &bottom, false)];
        assert!(chord_off_the_boundary(&block, &bx, &along_wall_edge));
        assert!(!edge_on_two_points(&block, &bx, &along_wall_edge));
        let mut on_the_end_flush = on_the_end.to_vec();
        on_the_end_flush.push(pc(&wall, &end, false));
        assert!(!chord_off_the_boundary(&block, &bx, &on_the_end_flush));
    }

    #[test]
    fn diagonal_corners_on_a_face_put_their_face_on_it() {
        let (block, bx) = l_block_and_box();
        let step = face(&block, [0.0, 0.0, 1.0], [0.0, 0.0, 50.0]);
        let corner = |at: [f64; 3]| pc(&step, &vertex(&bx, at), false);
        let diagonal = [corner([50.0, 10.0, 50.0]), corner([150.0, 90.0, 50.0])];
        assert!(chord_off_the_boundary(&block, &bx, &diagonal));
        // Two corners of one edge: the edge lies on the step, the face need not.
        let along = [corner([50.0, 10.0, 50.0]), corner([50.0, 90.0, 50.0])];
        assert!(!chord_off_the_boundary(&block, &bx, &along));
        assert!(edge_on_two_points(&block, &bx, &along));
        // A bottom edge lying on the step and the far corner on it: the bottom face
        // lies on the step as well. With that edge's own end instead, nothing follows.
        let bottom_edge = edge(&bx, [50.0, 10.0, 50.0], [150.0, 10.0, 50.0]);
        let lying = [pc(&step, &bottom_edge, false), corner([150.0, 90.0, 50.0])];
        assert!(chord_off_the_boundary(&block, &bx, &lying));
        let own_end = [pc(&step, &bottom_edge, false), corner([150.0, 10.0, 50.0])];
        assert!(!chord_off_the_boundary(&block, &bx, &own_end));
    }

    #[test]
    fn a_face_with_a_reflex_corner_says_nothing() {
        // The L-block's front face is an L: a chord between its bottom edge and the
        // wall's front edge may leave it. The box's front face is the one with both
        // crossing edges.
        let (block, bx) = l_block_and_box();
        let bottom = edge(&block, [0.0, 0.0, 0.0], [200.0, 0.0, 0.0]);
        let wall_front = edge(&block, [150.0, 0.0, 50.0], [150.0, 0.0, 150.0]);
        let box_bottom = edge(&bx, [50.0, 10.0, 50.0], [150.0, 10.0, 50.0]);
        let box_top = edge(&bx, [50.0, 10.0, 150.0], [150.0, 10.0, 150.0]);
        let state = [pc(&bottom, &box_bottom, false), pc(&wall_front, &box_top, false)];
        assert!(!chord_off_the_boundary(&block, &bx, &state));
    }

    #[test]
    fn a_chord_counts_on_an_l_shaped_face_where_no_other_edge_enters_its_span() {
        // The L-block's back face is an L. The wall's side edge and the wall's top back
        // edge (the upright's corner of it) span a triangle inside the face; the step's
        // back edge and the wall's side edge span the notch, outside it.
        let (block, bx) = l_block_and_box();
        let wall_side = edge(&block, [150.0, 100.0, 50.0], [150.0, 100.0, 150.0]);
        let wall_top_back = edge(&block, [150.0, 100.0, 150.0], [200.0, 100.0, 150.0]);
        let step_back = edge(&block, [0.0, 100.0, 50.0], [150.0, 100.0, 50.0]);
        // Two edges of the box's back face (y = 90) crossing them.
        let box_side = edge(&bx, [150.0, 90.0, 50.0], [150.0, 90.0, 150.0]);
        let box_bottom = edge(&bx, [50.0, 90.0, 50.0], [150.0, 90.0, 50.0]);
        let upright = [pc(&wall_side, &box_side, false), pc(&wall_top_back, &box_bottom, false)];
        assert!(chord_off_the_boundary(&block, &bx, &upright));
        let notch = [pc(&step_back, &box_bottom, false), pc(&wall_side, &box_side, false)];
        assert!(!chord_off_the_boundary(&block, &bx, &notch));
    }

    #[test]
    fn a_segment_is_clipped_to_the_part_of_it_over_a_convex_polygon() {
        // The triangle (0,0), (2,0), (1,1) on the plane z = 0, its hull dropping the
        // point on a side and the one inside.
        let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        let hull = hull_in_plane(
            &[p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0), p(1.0, 1.0), p(1.0, 0.2)],
            DVec3::Z,
            1e-12,
        );
        assert_eq!(hull.len(), 3);
        // Through it from x = 0.5 to 1.5 of a segment from -1 to 3: parameters 3/8, 5/8.
        let (t0, t1) = clip_to_convex(p(-1.0, 0.5), p(3.0, 0.5), &hull, DVec3::Z, 1e-12).unwrap();
        assert!((t0 - 0.375).abs() < 1e-9 && (t1 - 0.625).abs() < 1e-9);
        // Touching its corner only, and outside.
        assert!(
            clip_to_convex(p(2.0, 0.0), p(3.0, 1.0), &hull, DVec3::Z, 1e-12).is_some_and(|(t0, t1)| t1 - t0 < 1e-9)
        );
        assert_eq!(clip_to_convex(p(-1.0, 2.0), p(3.0, 2.0), &hull, DVec3::Z, 1e-12), None);
    }

    #[test]
    fn a_chord_inside_both_parts_lies_on_a_face_or_an_edge_of_each() {
        // The box's end-face bottom edge lying on the L-block's wall, and the upright's
        // front top edge crossing the box's front bottom edge: the chord from the wall
        // to that top edge runs through the upright (one convex piece), and the box
        // holds it, so the parts would penetrate.
        let (block, bx) = l_block_and_box();
        let wall = face(&block, [-1.0, 0.0, 0.0], [150.0, 0.0, 0.0]);
        let upright_top_front = edge(&block, [150.0, 0.0, 150.0], [200.0, 0.0, 150.0]);
        let end_bottom = edge(&bx, [150.0, 10.0, 50.0], [150.0, 90.0, 50.0]);
        let front_bottom = edge(&bx, [50.0, 10.0, 50.0], [150.0, 10.0, 50.0]);
        assert!(in_one_piece(
            &block,
            wall.parse().unwrap(),
            upright_top_front.parse().unwrap()
        ));
        let state = [
            pc(&wall, &end_bottom, false),
            pc(&upright_top_front, &front_bottom, false),
        ];
        assert!(chord_off_the_boundary(&block, &bx, &state));
        // The wall's top edge instead: the chord runs on the wall, nothing follows
        // from this rule alone.
        let wall_top = edge(&block, [150.0, 0.0, 150.0], [150.0, 100.0, 150.0]);
        let on_the_wall = [pc(&wall, &end_bottom, false), pc(&wall_top, &front_bottom, false)];
        assert!(on_one_element(&block, on_the_wall[0].fixed, on_the_wall[1].fixed));
    }
}
