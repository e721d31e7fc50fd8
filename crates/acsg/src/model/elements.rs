//! A part's elements with geometry, as written in JSON outputs: ids index these arrays.

use serde::{Deserialize, Serialize};

use super::{ElementId, Part};

/// A part's vertices, edges and faces, in the part's own frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartElements {
    /// The part's name (its path, as given).
    pub path: String,
    /// Vertex coordinates; `v7` is `vertices[7]`.
    pub vertices: Vec<[f64; 3]>,
    /// Whether each vertex is convex.
    pub convex_vertices: Vec<bool>,
    /// Edges as pairs of vertex indices; `e5` is `edges[5]`.
    pub edges: Vec<[u32; 2]>,
    /// Whether each edge is convex.
    pub convex_edges: Vec<bool>,
    /// Faces as loops of vertex indices, the outer loop first (counter-clockwise seen
    /// from outside), then holes; `f3` is `faces[3]`.
    pub faces: Vec<Vec<Vec<u32>>>,
    /// Each face's outward unit normal.
    pub face_normals: Vec<[f64; 3]>,
}

impl PartElements {
    /// The elements of a part.
    #[must_use]
    pub fn of(part: &Part) -> PartElements {
        PartElements {
            path: part.name().to_string(),
            vertices: part.vertices().iter().map(|v| v.position.to_array()).collect(),
            convex_vertices: part.vertices().iter().map(|v| v.convex).collect(),
            edges: part.edges().iter().map(|e| e.vertices.map(|v| v.0)).collect(),
            convex_edges: part.edges().iter().map(|e| e.convex).collect(),
            faces: part
                .faces()
                .iter()
                .map(|f| {
                    f.loops
                        .iter()
                        .map(|l| l.vertices.iter().map(|v| v.0).collect())
                        .collect()
                })
                .collect(),
            face_normals: part.faces().iter().map(|f| f.normal.to_array()).collect(),
        }
    }
}

impl Serialize for ElementId {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for ElementId {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = std::borrow::Cow::<'de, str>::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}
