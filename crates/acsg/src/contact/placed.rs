//! A part's elements as points in one frame: the fixed part in its own frame once, the
//! moving part transformed per pose. Vertices and face planes are mapped eagerly (cheap);
//! a face's loops and triangles only when a query needs that face.

use std::sync::OnceLock;

use glam::{DAffine3, DVec3};

use crate::geometry::{Aabb, PlanarRegion, Segment};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};

/// A face's loops and triangles as points.
#[derive(Clone, Debug)]
struct FacePoints {
    loops: Vec<Vec<DVec3>>,
    triangles: Vec<[DVec3; 3]>,
}

/// A placed element's geometry: a vertex's point, an edge's segment, a face's region.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shape<'a> {
    /// A vertex.
    Point(DVec3),
    /// An edge.
    Segment(Segment),
    /// A face.
    Region(PlanarRegion<'a>),
}

/// The geometry of a part's faces, edges and vertices in some frame.
#[derive(Clone, Debug)]
pub(crate) struct PlacedPart<'a> {
    pub part: &'a Part,
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    offsets: Vec<f64>,
    faces: Vec<OnceLock<FacePoints>>,
}

impl<'a> PlacedPart<'a> {
    /// The part mapped by `transform`.
    pub fn new(part: &'a Part, transform: &DAffine3) -> PlacedPart<'a> {
        let positions: Vec<DVec3> = part
            .vertices()
            .iter()
            .map(|v| transform.transform_point3(v.position))
            .collect();
        let normals: Vec<DVec3> = part
            .faces()
            .iter()
            .map(|f| transform.transform_vector3(f.normal).normalize())
            .collect();
        let offsets = part
            .faces()
            .iter()
            .zip(&normals)
            .map(|(f, n)| n.dot(positions[f.outer().vertices[0].index()]))
            .collect();
        let faces = vec![OnceLock::new(); part.faces().len()];
        PlacedPart {
            part,
            positions,
            normals,
            offsets,
            faces,
        }
    }

    pub fn vertex(&self, v: VertexId) -> DVec3 {
        self.positions[v.index()]
    }

    pub fn segment(&self, e: EdgeId) -> Segment {
        let [a, b] = self.part.edge(e).vertices;
        Segment::new(self.vertex(a), self.vertex(b))
    }

    fn face_points(&self, f: FaceId) -> &FacePoints {
        self.faces[f.index()].get_or_init(|| {
            let face = self.part.face(f);
            let at = |v: VertexId| self.positions[v.index()];
            FacePoints {
                loops: face
                    .loops
                    .iter()
                    .map(|l| l.vertices.iter().map(|&v| at(v)).collect())
                    .collect(),
                triangles: face.triangles.iter().map(|t| t.map(at)).collect(),
            }
        })
    }

    pub fn region(&self, f: FaceId) -> PlanarRegion<'_> {
        let points = self.face_points(f);
        PlanarRegion {
            normal: self.normals[f.index()],
            offset: self.offsets[f.index()],
            loops: &points.loops,
            triangles: &points.triangles,
        }
    }

    /// An element's geometry: the one place where an element is told apart by kind to
    /// reach its geometry (the contact and distance tests then match on shapes, a
    /// pair in either order).
    pub fn shape(&self, element: ElementId) -> Shape<'_> {
        match element {
            ElementId::Vertex(v) => Shape::Point(self.vertex(v)),
            ElementId::Edge(e) => Shape::Segment(self.segment(e)),
            ElementId::Face(f) => Shape::Region(self.region(f)),
        }
    }

    pub fn bounds(&self, element: ElementId) -> Aabb {
        match element {
            ElementId::Vertex(v) => Aabb::around([self.vertex(v)]),
            ElementId::Edge(e) => {
                let s = self.segment(e);
                Aabb::around([s.a, s.b])
            }
            ElementId::Face(f) => Aabb::around(
                self.part
                    .face(f)
                    .outer()
                    .vertices
                    .iter()
                    .map(|&v| self.positions[v.index()]),
            ),
        }
    }
}
