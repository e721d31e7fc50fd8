//! The boundary representation of one part.

use glam::DVec3;

use super::ids::{EdgeId, ElementId, FaceId, VertexId};
use crate::geometry::{Aabb, ConvexPolytope, winding_number};

/// A vertex: a point where three or more faces meet.
#[derive(Clone, Debug, PartialEq)]
pub struct Vertex {
    /// Position in the part's frame.
    pub position: DVec3,
    /// Whether the solid is locally convex here (docs/concepts.md#elements).
    pub convex: bool,
    /// Incident edges, sorted.
    pub edges: Vec<EdgeId>,
    /// Incident faces, sorted.
    pub faces: Vec<FaceId>,
}

/// An edge: a maximal straight segment between two faces.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// End points, `vertices[0] < vertices[1]`.
    pub vertices: [VertexId; 2],
    /// `faces[0]` has this edge in one of its loops running from `vertices[0]` to
    /// `vertices[1]`; `faces[1]` runs it the other way.
    pub faces: [FaceId; 2],
    /// Whether the solid's interior dihedral angle here is below 180 degrees.
    pub convex: bool,
}

/// A closed boundary loop of a face.
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// Corners in order, the face's interior on the left seen from outside (outer loop
    /// counter-clockwise, holes clockwise).
    pub vertices: Vec<VertexId>,
    /// `edges[i]` joins `vertices[i]` and `vertices[(i + 1) % n]`.
    pub edges: Vec<EdgeId>,
}

/// A face: a maximal planar connected region of the boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// Outward unit normal.
    pub normal: DVec3,
    /// Plane offset: points `p` of the face satisfy `normal · p = offset`.
    pub offset: f64,
    /// The outer loop first, then one loop per hole.
    pub loops: Vec<Loop>,
    /// Area (outer loop minus holes).
    pub area: f64,
    /// A triangulation of the face over its own vertices.
    pub triangles: Vec<[VertexId; 3]>,
}

impl Face {
    /// The outer boundary loop.
    #[must_use]
    pub fn outer(&self) -> &Loop {
        &self.loops[0]
    }

    /// The hole loops.
    #[must_use]
    pub fn holes(&self) -> &[Loop] {
        &self.loops[1..]
    }

    /// Signed distance of `p` from the face's plane (positive outside the solid).
    #[must_use]
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

/// A validated polyhedral solid: faces (possibly non-convex, possibly with holes),
/// edges, vertices, their adjacency and convexity, and an exact decomposition into
/// convex pieces.
///
/// Build one with [`Part::try_new`] or [`Part::from_path`] (in [`crate::load`]).
#[derive(Clone, Debug)]
pub struct Part {
    pub(crate) name: String,
    pub(crate) vertices: Vec<Vertex>,
    pub(crate) edges: Vec<Edge>,
    pub(crate) faces: Vec<Face>,
    pub(crate) pieces: Vec<ConvexPolytope>,
    pub(crate) bounds: Aabb,
    pub(crate) volume: f64,
}

impl Part {
    /// The name given at construction (usually the file path).
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The vertices, indexed by [`VertexId`].
    #[must_use]
    pub fn vertices(&self) -> &[Vertex] {
        &self.vertices
    }
    /// The edges, indexed by [`EdgeId`].
    #[must_use]
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }
    /// The faces, indexed by [`FaceId`].
    #[must_use]
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }
    /// One vertex.
    #[must_use]
    pub fn vertex(&self, id: VertexId) -> &Vertex {
        &self.vertices[id.index()]
    }
    /// One edge.
    #[must_use]
    pub fn edge(&self, id: EdgeId) -> &Edge {
        &self.edges[id.index()]
    }
    /// One face.
    #[must_use]
    pub fn face(&self, id: FaceId) -> &Face {
        &self.faces[id.index()]
    }
    /// The exact convex pieces whose union is the solid (interiors disjoint).
    #[must_use]
    pub fn convex_pieces(&self) -> &[ConvexPolytope] {
        &self.pieces
    }
    /// The bounding box.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
    /// The enclosed volume.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.volume
    }
    /// The generalised winding number of `q` with respect to the part's surface: 1
    /// inside, 0 outside.
    #[must_use]
    pub fn winding_number(&self, q: DVec3) -> f64 {
        let triangles = self.faces.iter().flat_map(|f| f.triangles.iter());
        winding_number(triangles.map(|t| t.map(|v| self.vertex(v).position)), q)
    }
    /// Every element id: the faces, then the edges, then the vertices.
    #[must_use]
    pub fn elements(&self) -> Vec<ElementId> {
        let faces = (0..self.faces.len() as u32).map(|i| ElementId::Face(FaceId(i)));
        let edges = (0..self.edges.len() as u32).map(|i| ElementId::Edge(EdgeId(i)));
        let vertices = (0..self.vertices.len() as u32).map(|i| ElementId::Vertex(VertexId(i)));
        faces.chain(edges).chain(vertices).collect()
    }
    /// The two end points of an edge.
    #[must_use]
    pub fn edge_points(&self, id: EdgeId) -> [DVec3; 2] {
        let [a, b] = self.edge(id).vertices;
        [self.vertex(a).position, self.vertex(b).position]
    }
    /// The unit direction of an edge, from `vertices[0]` to `vertices[1]`.
    #[must_use]
    pub fn edge_direction(&self, id: EdgeId) -> DVec3 {
        let [a, b] = self.edge_points(id);
        (b - a).normalize()
    }

    /// The edge's wedge: for each of its two faces, the unit direction in the face,
    /// across the edge, into the face.
    #[must_use]
    pub fn edge_wedge(&self, id: EdgeId) -> [DVec3; 2] {
        let d = self.edge_direction(id);
        let [f0, f1] = self.edge(id).faces;
        // faces[0] runs the edge forwards with its interior on the left seen from outside.
        [self.face(f0).normal.cross(d), self.face(f1).normal.cross(-d)]
    }

    /// Whether `inner` lies in the closure of `outer` (an element is in its own closure).
    #[must_use]
    pub fn in_closure(&self, outer: ElementId, inner: ElementId) -> bool {
        use ElementId::{Edge, Face, Vertex};
        match (outer, inner) {
            _ if outer == inner => true,
            (Face(f), Edge(e)) => self.edge(e).faces.contains(&f),
            (Face(f), Vertex(v)) => self.vertex(v).faces.contains(&f),
            (Edge(e), Vertex(v)) => self.edge(e).vertices.contains(&v),
            _ => false,
        }
    }
    /// The vertices in an element's closure (a face's over all its loops).
    #[must_use]
    pub fn closure_vertices(&self, e: ElementId) -> Vec<VertexId> {
        match e {
            ElementId::Vertex(v) => vec![v],
            ElementId::Edge(x) => self.edge(x).vertices.to_vec(),
            ElementId::Face(f) => self.face(f).loops.iter().flat_map(|l| l.vertices.clone()).collect(),
        }
    }
    /// Whether two elements' closures share a vertex (an element shares its own).
    #[must_use]
    pub fn share_a_vertex(&self, a: ElementId, b: ElementId) -> bool {
        let around = self.closure_vertices(b);
        self.closure_vertices(a).iter().any(|v| around.contains(v))
    }
    /// The edges in an element's closure.
    #[must_use]
    pub fn closure_edges(&self, e: ElementId) -> Vec<EdgeId> {
        match e {
            ElementId::Vertex(_) => Vec::new(),
            ElementId::Edge(x) => vec![x],
            ElementId::Face(f) => self.face(f).loops.iter().flat_map(|l| l.edges.clone()).collect(),
        }
    }
    /// The faces whose closure holds an element.
    #[must_use]
    pub fn faces_around(&self, e: ElementId) -> Vec<FaceId> {
        match e {
            ElementId::Vertex(v) => self.vertex(v).faces.clone(),
            ElementId::Edge(x) => self.edge(x).faces.to_vec(),
            ElementId::Face(f) => vec![f],
        }
    }
    /// An element's corner points: a vertex, an edge's ends, a face's outer loop.
    #[must_use]
    pub fn outline_points(&self, e: ElementId) -> Vec<DVec3> {
        match e {
            ElementId::Vertex(v) => vec![self.vertex(v).position],
            ElementId::Edge(x) => self.edge_points(x).to_vec(),
            ElementId::Face(f) => self
                .face(f)
                .outer()
                .vertices
                .iter()
                .map(|&v| self.vertex(v).position)
                .collect(),
        }
    }
    /// Whether an element is convex: an edge or a vertex as classified
    /// (docs/concepts.md#elements); a face always, since a contact's degeneracy and
    /// stability depend on its edges and vertices only.
    #[must_use]
    pub fn is_convex(&self, e: ElementId) -> bool {
        match e {
            ElementId::Vertex(v) => self.vertex(v).convex,
            ElementId::Edge(x) => self.edge(x).convex,
            ElementId::Face(_) => true,
        }
    }
    /// Ids of the convex vertices.
    pub fn convex_vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        (0..self.vertices.len() as u32)
            .map(VertexId)
            .filter(|&v| self.vertex(v).convex)
    }
    /// Ids of the convex edges.
    pub fn convex_edges(&self) -> impl Iterator<Item = EdgeId> + '_ {
        (0..self.edges.len() as u32)
            .map(EdgeId)
            .filter(|&e| self.edge(e).convex)
    }
    /// Whether a face's outer outline has a reflex corner.
    #[must_use]
    pub fn face_outline_is_nonconvex(&self, id: FaceId) -> bool {
        let face = self.face(id);
        let outer = &face.outer().vertices;
        (0..outer.len()).any(|i| !self.corner_is_convex(id, outer, i))
    }

    /// Whether the corner at `corners[i]` of a loop of face `id` turns left (the face's
    /// interior angle there is below 180 degrees).
    pub(crate) fn corner_is_convex(&self, id: FaceId, corners: &[VertexId], i: usize) -> bool {
        let n = corners.len();
        let p = |k: usize| self.vertex(corners[k % n]).position;
        let (prev, here, next) = (p(i + n - 1), p(i), p(i + 1));
        (here - prev).cross(next - here).dot(self.face(id).normal) > 0.0
    }
}
