//! Helpers shared by the unit tests.

/// A small deterministic generator of numbers in [0, 1) (xorshift), so that sampled
/// tests see the same cases on every run.
pub(crate) struct Numbers(pub(crate) u64);

impl Numbers {
    /// The next number in [0, 1).
    pub(crate) fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The root of `f` in `[lo, hi]` by bisection (`f` changes sign there).
pub(crate) fn bisect(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (f(mid) > 0.0) == (f(lo) > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The edge of `part` between the points `p` and `q`.
pub(crate) fn edge_between(part: &crate::model::Part, p: glam::DVec3, q: glam::DVec3) -> crate::model::ElementId {
    use crate::model::{EdgeId, ElementId, VertexId};
    let at = |v: VertexId, x: glam::DVec3| part.vertex(v).position.distance(x) < 1e-9;
    let found = part.edges().iter().position(|e| {
        let [u, v] = e.vertices;
        (at(u, p) && at(v, q)) || (at(u, q) && at(v, p))
    });
    ElementId::Edge(EdgeId(found.expect("no such edge") as u32))
}

/// The tilted square peg's bounds: x and y ±1 mm, z 0–45 mm, rx and ry ±1°, no turn
/// about z.
pub(crate) fn tilted_peg_bounds() -> crate::pose::Bounds {
    let d = 1f64.to_radians();
    crate::pose::Bounds::try_new([-1.0, -1.0, 0.0, -d, -d, 0.0], [1.0, 1.0, 45.0, d, d, 0.0]).expect("valid bounds")
}

/// The turned square peg's bounds: x and y ±2 mm, z 0–45 mm, ry ±2°, rz ±1°, no
/// turn about x.
pub(crate) fn turned_peg_bounds() -> crate::pose::Bounds {
    let (ry, rz) = (2f64.to_radians(), 1f64.to_radians());
    crate::pose::Bounds::try_new([-2.0, -2.0, 0.0, 0.0, -ry, -rz], [2.0, 2.0, 45.0, 0.0, ry, rz]).expect("valid bounds")
}

/// A fixture model by file name (`fixtures/` at the repository's root).
pub(crate) fn fixture(name: &str) -> crate::model::Part {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    crate::model::Part::from_path(&root.join(name)).expect("fixture loads")
}

/// A principal contact by its elements' names (`"f3"`, `"e10"`, `"v2"`).
pub(crate) fn contact(
    fixed: &str,
    moving: &str,
    kind: crate::contact::ContactKind,
) -> crate::contact::PrincipalContact {
    crate::contact::PrincipalContact {
        fixed: fixed.parse().expect("an element name"),
        moving: moving.parse().expect("an element name"),
        kind,
    }
}

/// A contact state of the built-in example (sorted) and a pose the contact module reads
/// it at, from end to end: the box on the L-block's step against its wall, its top edge
/// turned 7.7e-5 rad and crossing the wall's top edge 2.8e-3 mm from that edge's end,
/// the wall edge lying along the box's face there. No witness: the box's top edge has
/// its end (on the wall, with the edge e11) and the crossing on the wall's plane, so in
/// exact geometry it lies on the wall (`feasibility::two_points`).
pub(crate) fn grazing_crossing() -> (Vec<crate::contact::PrincipalContact>, [f64; 6]) {
    use crate::contact::ContactKind as K;
    let mut state = vec![
        contact("f3", "f2", K::FaceFace),
        contact("f5", "e11", K::FaceEdge),
        contact("e10", "e10", K::EdgeEdge),
    ];
    state.sort();
    let witness = [
        -0.006902579441998569,
        0.0,
        3.213270360902243e-7,
        0.0,
        2.142180201833669e-9,
        -7.669903939428206e-5,
    ];
    (state, witness)
}

/// A contact state of the square peg tilted in the plain hole
/// ([`tilted_peg_bounds`]; sorted) and its robust witness, the generator's (x at its
/// bound): the peg's bottom corner v0 on the block's top f3 just past the hole's rim
/// corner v5, which touches the peg's bottom f2, the faces 1.1e-4 rad apart in turn.
pub(crate) fn corner_beside_the_rim() -> (Vec<crate::contact::PrincipalContact>, crate::pose::Pose) {
    use crate::contact::ContactKind as K;
    let mut state = vec![contact("f3", "v0", K::FaceVertex), contact("v5", "f2", K::VertexFace)];
    state.sort();
    let witness = crate::pose::Pose::from_array([
        -0.999768541671432,
        -0.9994899367500578,
        39.99466247871642,
        0.00010199394019068386,
        -4.627083730533374e-05,
        0.0,
    ]);
    (state, witness)
}

/// Whether `report`, read at `placement`, is a robust witness of exactly `target`:
/// the contact module reads that state there and the witness check finds no flaw.
pub(crate) fn witnesses(
    scene: &crate::contact::ContactScene<'_>,
    placement: &glam::DAffine3,
    report: &crate::contact::ContactReport,
    target: &[crate::contact::PrincipalContact],
) -> bool {
    report.contacts == target && crate::feasibility::witness_flaw(scene, placement, report).is_none()
}
