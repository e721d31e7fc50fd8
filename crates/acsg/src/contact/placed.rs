//! A part's elements as points in one frame: the fixed part in its own frame once, the
//! moving part transformed per pose.

use glam::{DAffine3, DVec3};

use super::bvh::Bounds3;
use super::queries::{PlanarRegion, Segment};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};

/// The geometry of a part's faces, edges and vertices in some frame.
#[derive(Clone, Debug)]
pub(crate) struct PlacedPart<'a> {
    pub part: &'a Part,
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub offsets: Vec<f64>,
    /// Each face's loops as points.
    pub loops: Vec<Vec<Vec<DVec3>>>,
    /// Each face's triangles as points.
    pub triangles: Vec<Vec<[DVec3; 3]>>,
}

impl<'a> PlacedPart<'a> {
    /// The part mapped by `transform`.
    pub fn new(part: &'a Part, transform: &DAffine3) -> PlacedPart<'a> {
        let positions: Vec<DVec3> = part
            .vertices()
            .iter()
            .map(|v| transform.transform_point3(v.position))
            .collect();
        let at = |v: VertexId| positions[v.index()];
        let normals: Vec<DVec3> = part
            .faces()
            .iter()
            .map(|f| transform.transform_vector3(f.normal).normalize())
            .collect();
        let offsets = part
            .faces()
            .iter()
            .zip(&normals)
            .map(|(f, n)| n.dot(at(f.outer().vertices[0])))
            .collect();
        let loops = part
            .faces()
            .iter()
            .map(|f| {
                f.loops
                    .iter()
                    .map(|l| l.vertices.iter().map(|&v| at(v)).collect())
                    .collect()
            })
            .collect();
        let triangles = part
            .faces()
            .iter()
            .map(|f| f.triangles.iter().map(|t| t.map(at)).collect())
            .collect();
        PlacedPart {
            part,
            positions,
            normals,
            offsets,
            loops,
            triangles,
        }
    }

    pub fn vertex(&self, v: VertexId) -> DVec3 {
        self.positions[v.index()]
    }

    pub fn segment(&self, e: EdgeId) -> Segment {
        let [a, b] = self.part.edge(e).vertices;
        Segment::new(self.vertex(a), self.vertex(b))
    }

    pub fn region(&self, f: FaceId) -> PlanarRegion<'_> {
        let i = f.index();
        PlanarRegion {
            normal: self.normals[i],
            offset: self.offsets[i],
            loops: &self.loops[i],
            triangles: &self.triangles[i],
        }
    }

    /// Every element id, faces first, then edges, then vertices.
    pub fn elements(&self) -> Vec<ElementId> {
        let faces = (0..self.part.faces().len() as u32).map(|i| ElementId::Face(FaceId(i)));
        let edges = (0..self.part.edges().len() as u32).map(|i| ElementId::Edge(EdgeId(i)));
        let vertices = (0..self.part.vertices().len() as u32).map(|i| ElementId::Vertex(VertexId(i)));
        faces.chain(edges).chain(vertices).collect()
    }

    pub fn bounds(&self, element: ElementId) -> Bounds3 {
        match element {
            ElementId::Vertex(v) => Bounds3::around([self.vertex(v)]),
            ElementId::Edge(e) => {
                let s = self.segment(e);
                Bounds3::around([s.a, s.b])
            }
            ElementId::Face(f) => Bounds3::around(self.loops[f.index()][0].iter().copied()),
        }
    }
}
