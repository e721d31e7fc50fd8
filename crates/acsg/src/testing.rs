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
