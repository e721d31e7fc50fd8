//! The canonical numbering (step 6 of [`super`]): vertices by position, faces by their
//! vertex sets, edges by their end points, so that the same solid gets the same ids
//! whatever the file's format or polygon order.

use rustc_hash::FxHashMap as HashMap;

use super::loops::TracedLoops;
use super::mesh::Mesh;
use crate::model::{Edge, EdgeId, FaceId, VertexId};
use crate::tolerance::{COPLANAR_REL, scaled};

/// The ids given to the mesh's corners, regions and traced edges.
pub(super) struct Numbering {
    /// The mesh points that are vertices, in vertex order.
    pub(super) corner_points: Vec<u32>,
    /// The vertex of each of those points.
    pub(super) vertex_of: HashMap<u32, VertexId>,
    /// The regions in face order (each with its sorted vertices).
    pub(super) face_order: Vec<(Vec<VertexId>, u32)>,
    /// The face of each region.
    pub(super) face_of: Vec<FaceId>,
    /// The edges in order, not yet classified as convex or concave.
    pub(super) edges: Vec<Edge>,
    /// The edge of each traced edge.
    pub(super) edge_of: Vec<EdgeId>,
}

impl Mesh {
    /// Numbers the corners (points where three or more regions meet), the regions and
    /// the traced edges.
    pub(super) fn number(&self, point_regions: &[Vec<u32>], traced: &TracedLoops, region_count: usize) -> Numbering {
        let is_corner = |v: u32| point_regions[v as usize].len() >= 3;
        let quantum = scaled(COPLANAR_REL, self.scale);
        let mut corner_points: Vec<u32> = (0..self.points.len() as u32).filter(|&v| is_corner(v)).collect();
        let sort_key = |v: &u32| {
            let p = self.points[*v as usize];
            let q = (p / quantum).round();
            (
                (q.x as i64, q.y as i64, q.z as i64),
                p.x.to_bits(),
                p.y.to_bits(),
                p.z.to_bits(),
            )
        };
        corner_points.sort_by_key(sort_key);
        let mut vertex_of = HashMap::default();
        for (i, &v) in corner_points.iter().enumerate() {
            vertex_of.insert(v, VertexId(i as u32));
        }
        let mut face_order: Vec<(Vec<VertexId>, u32)> = (0..region_count as u32)
            .map(|r| {
                let mut vs: Vec<VertexId> = traced.loops[r as usize]
                    .iter()
                    .flat_map(|l| l.corners.iter().map(|c| vertex_of[c]))
                    .collect();
                vs.sort_unstable();
                (vs, r)
            })
            .collect();
        face_order.sort();
        let mut face_of = vec![FaceId(0); region_count];
        for (i, (_, r)) in face_order.iter().enumerate() {
            face_of[*r as usize] = FaceId(i as u32);
        }
        let (edges, edge_of) = number_edges(traced, &vertex_of, &face_of);
        Numbering {
            corner_points,
            vertex_of,
            face_order,
            face_of,
            edges,
            edge_of,
        }
    }
}

/// The traced edges as B-rep edges (lower vertex first) in order of their vertices,
/// and the id of each traced edge.
fn number_edges(
    traced: &TracedLoops,
    vertex_of: &HashMap<u32, VertexId>,
    face_of: &[FaceId],
) -> (Vec<Edge>, Vec<EdgeId>) {
    let mut edge_order: Vec<(Edge, usize)> = traced
        .edges
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let (a, b) = (vertex_of[&e.from], vertex_of[&e.to]);
            let (l, r) = (face_of[e.left as usize], face_of[e.right as usize]);
            let edge = if a < b {
                Edge {
                    vertices: [a, b],
                    faces: [l, r],
                    convex: false,
                }
            } else {
                Edge {
                    vertices: [b, a],
                    faces: [r, l],
                    convex: false,
                }
            };
            (edge, i)
        })
        .collect();
    edge_order.sort_by_key(|(e, _)| (e.vertices, e.faces));
    let mut edge_of = vec![EdgeId(0); traced.edges.len()];
    for (i, (_, raw)) in edge_order.iter().enumerate() {
        edge_of[*raw] = EdgeId(i as u32);
    }
    (edge_order.into_iter().map(|(e, _)| e).collect(), edge_of)
}
