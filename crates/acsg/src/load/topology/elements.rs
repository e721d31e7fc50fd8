//! The elements with their geometry (step 6 of [`super`]): vertices, edges and faces
//! in canonical order, each face's loops ordered and triangulated, and every edge and
//! vertex classified as convex or not.

use glam::{DVec2, DVec3};

use super::fmt_point;
use super::loops::TracedLoops;
use super::mesh::Mesh;
use super::numbering::Numbering;
use crate::geometry::{plane_basis, shoelace};
use crate::load::validation::{DefectKind, ValidationReport};
use crate::model::{Edge, EdgeId, Face, Loop, Vertex, VertexId};
use crate::tolerance::{AREA_REL, PARALLEL_SIN, ROUNDOFF_REL, TRIANGULATION_REL};

impl Mesh {
    /// The vertices in canonical order, with their faces and edges.
    pub(super) fn vertices(&self, numbering: &Numbering, point_regions: &[Vec<u32>]) -> Vec<Vertex> {
        let mut vertices: Vec<Vertex> = numbering
            .corner_points
            .iter()
            .map(|&v| Vertex {
                position: self.points[v as usize],
                convex: false,
                edges: Vec::new(),
                faces: point_regions[v as usize]
                    .iter()
                    .map(|&r| numbering.face_of[r as usize])
                    .collect(),
            })
            .collect();
        for v in &mut vertices {
            v.faces.sort_unstable();
        }
        for (i, e) in numbering.edges.iter().enumerate() {
            for v in e.vertices {
                vertices[v.index()].edges.push(EdgeId(i as u32));
            }
        }
        vertices
    }

    /// The faces in canonical order: each region's loops (outer loop first, holes after,
    /// each starting at its lowest vertex), area and triangulation. `None` (and a
    /// defect) when a face has other than one outer loop; a face whose triangulation
    /// misses its area is reported too.
    pub(super) fn faces(
        &self,
        numbering: &Numbering,
        traced: &TracedLoops,
        planes: &[(DVec3, f64)],
        vertices: &[Vertex],
        report: &mut ValidationReport,
    ) -> Option<Vec<Face>> {
        let mut faces = Vec::with_capacity(numbering.face_order.len());
        for (_, r) in &numbering.face_order {
            let (normal, offset) = planes[*r as usize];
            let (u, w) = plane_basis(normal);
            let flat = |v: &VertexId| {
                let p = vertices[v.index()].position;
                DVec2::new(p.dot(u), p.dot(w))
            };
            let mut face_loops: Vec<(f64, Loop)> = traced.loops[*r as usize]
                .iter()
                .map(|raw| {
                    let mut vs: Vec<VertexId> = raw.corners.iter().map(|c| numbering.vertex_of[c]).collect();
                    let mut es: Vec<EdgeId> = raw.edges.iter().map(|&e| numbering.edge_of[e]).collect();
                    let start = (0..vs.len()).min_by_key(|&i| vs[i]).unwrap_or(0);
                    vs.rotate_left(start);
                    es.rotate_left(start);
                    let points: Vec<DVec2> = vs.iter().map(flat).collect();
                    (
                        0.5 * shoelace(&points),
                        Loop {
                            vertices: vs,
                            edges: es,
                        },
                    )
                })
                .collect();
            let outer_count = face_loops.iter().filter(|(a, _)| *a > 0.0).count();
            if outer_count != 1 {
                report.push(
                    DefectKind::Degenerate,
                    format!(
                        "a face with normal {} has {outer_count} outer boundaries",
                        fmt_point(normal)
                    ),
                    "faces must be connected regions; check for faces touching at a single point",
                );
                return None;
            }
            // Outer loop first, holes after, in order of their first vertex.
            face_loops
                .sort_by(|(a1, l1), (a2, l2)| (*a2 > 0.0).cmp(&(*a1 > 0.0)).then(l1.vertices[0].cmp(&l2.vertices[0])));
            let area: f64 = face_loops.iter().map(|(a, _)| a).sum();
            let loops: Vec<Loop> = face_loops.into_iter().map(|(_, l)| l).collect();
            let triangles = triangulate(&loops, vertices, u, w);
            self.check_triangulation(&triangles, vertices, normal, area, report);
            faces.push(Face {
                normal,
                offset,
                loops,
                area,
                triangles,
            });
        }
        Some(faces)
    }

    /// Reports a face whose triangles do not add up to its area (self-intersecting or
    /// touching loops).
    fn check_triangulation(
        &self,
        triangles: &[[VertexId; 3]],
        vertices: &[Vertex],
        normal: DVec3,
        area: f64,
        report: &mut ValidationReport,
    ) {
        let tri_area: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| vertices[v.index()].position);
                0.5 * (b - a).cross(c - a).dot(normal)
            })
            .sum();
        if (tri_area - area).abs() > TRIANGULATION_REL * area.abs().max(self.scale * self.scale * AREA_REL) {
            report.push(
                DefectKind::Degenerate,
                format!(
                    "a face with normal {} and area {area} could not be triangulated (got {tri_area})",
                    fmt_point(normal)
                ),
                "check the face for self-intersecting or touching boundary loops",
            );
        }
    }
}

/// Edge convexity: with n_l, n_r the normals of the faces left and right of the edge
/// run a -> b in the left face, the dihedral is convex iff (n_l × n_r) · (b - a) > 0.
/// Faces meeting at 0 or 360 degrees are reported.
pub(super) fn classify_edges(edges: &mut [Edge], vertices: &[Vertex], faces: &[Face], report: &mut ValidationReport) {
    for e in edges {
        let [a, b] = e.vertices.map(|v| vertices[v.index()].position);
        let cross = faces[e.faces[0].index()].normal.cross(faces[e.faces[1].index()].normal);
        if cross.length() < PARALLEL_SIN {
            report.push(
                DefectKind::Degenerate,
                format!(
                    "faces {} and {} meet at 0 or 360 degrees along {} - {}",
                    e.faces[0],
                    e.faces[1],
                    fmt_point(a),
                    fmt_point(b)
                ),
                "remove the zero-thickness fin or slit",
            );
        }
        e.convex = cross.dot(b - a) > 0.0;
    }
}

/// A vertex is convex when every incident edge is convex, every incident face's corner
/// there is below 180 degrees, and every incident edge runs on the inner side of every
/// incident face's plane (the local cone is convex).
pub(super) fn classify_vertices(vertices: &mut [Vertex], edges: &[Edge], faces: &[Face]) {
    let mut corner_convex = vec![true; vertices.len()];
    for face in faces {
        for l in &face.loops {
            let n = l.vertices.len();
            for i in 0..n {
                let p = |k: usize| vertices[l.vertices[k % n].index()].position;
                let turn = (p(i) - p(i + n - 1)).cross(p(i + 1) - p(i)).dot(face.normal);
                if turn <= 0.0 {
                    corner_convex[l.vertices[i].index()] = false;
                }
            }
        }
    }
    let positions: Vec<DVec3> = vertices.iter().map(|v| v.position).collect();
    for (i, v) in vertices.iter_mut().enumerate() {
        let here = positions[i];
        let cone_convex = v.edges.iter().all(|e| {
            let [a, b] = edges[e.index()].vertices;
            let other = if a.index() == i { b } else { a };
            let d = (positions[other.index()] - here).normalize();
            v.faces.iter().all(|f| faces[f.index()].normal.dot(d) <= ROUNDOFF_REL)
        });
        v.convex = corner_convex[i] && cone_convex && v.edges.iter().all(|e| edges[e.index()].convex);
    }
}

/// Triangulates a face's loops (outer first) over its own vertices.
fn triangulate(loops: &[Loop], vertices: &[Vertex], u: DVec3, w: DVec3) -> Vec<[VertexId; 3]> {
    let mut coords = Vec::new();
    let mut holes = Vec::new();
    let mut ids = Vec::new();
    for (k, l) in loops.iter().enumerate() {
        if k > 0 {
            holes.push(ids.len());
        }
        for &v in &l.vertices {
            let p = vertices[v.index()].position;
            coords.extend([p.dot(u), p.dot(w)]);
            ids.push(v);
        }
    }
    let Ok(indices) = earcutr::earcut(&coords, &holes, 2) else {
        return Vec::new();
    };
    indices
        .chunks_exact(3)
        .map(|t| {
            let tri = [ids[t[0]], ids[t[1]], ids[t[2]]];
            // earcut's winding follows the input's projected orientation; make every
            // triangle counter-clockwise around the face normal.
            let [a, b, c] = tri.map(|v| {
                let p = vertices[v.index()].position;
                DVec2::new(p.dot(u), p.dot(w))
            });
            if (b - a).perp_dot(c - a) < 0.0 {
                [tri[0], tri[2], tri[1]]
            } else {
                tri
            }
        })
        .collect()
}
