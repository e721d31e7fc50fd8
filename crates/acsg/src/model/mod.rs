//! Part models: the validated boundary representation of one polyhedral solid.

mod elements;
mod ids;
mod part;
mod summary;

pub use elements::PartElements;
pub use ids::{EdgeId, ElementId, FaceId, VertexId};
pub use part::{Edge, Face, Loop, Part, Vertex};
pub use summary::{Inspection, PartSummary, PpcTotals};

/// L, the length scale of a pair of parts: the larger of their bounding-box
/// diagonals. Every tolerance of a run is a multiple of it ([`crate::tolerance`]).
#[must_use]
pub fn length_scale(fixed: &Part, moving: &Part) -> f64 {
    fixed.bounds().diagonal().max(moving.bounds().diagonal())
}

/// card(PPC) of a fixed part A and a moving part B, split by type
/// (docs/concepts.md#ppc-and-klc).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct PpcCount {
    /// |faces A| · |convex vertices B|.
    pub f_v: usize,
    /// |convex edges A| · |convex edges B|.
    pub e_e: usize,
    /// |convex vertices A| · |faces B|.
    pub v_f: usize,
}

impl PpcCount {
    /// The total.
    #[must_use]
    pub fn total(&self) -> usize {
        self.f_v + self.e_e + self.v_f
    }
}

/// Counts the primitive principal contacts between a fixed and a moving part.
#[must_use]
pub fn ppc_count(fixed: &Part, moving: &Part) -> PpcCount {
    PpcCount {
        f_v: fixed.faces().len() * moving.convex_vertices().count(),
        e_e: fixed.convex_edges().count() * moving.convex_edges().count(),
        v_f: fixed.convex_vertices().count() * moving.faces().len(),
    }
}
