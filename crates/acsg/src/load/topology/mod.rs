//! From a polygon soup to a boundary representation (the B-rep of a part before its
//! convex decomposition).
//!
//! The steps, each of which may add defects to the [`ValidationReport`]:
//! 1. weld points closer than [`WELD_REL`]` · L` (STL stores each corner separately);
//! 2. check every polygon: finite, planar, non-zero area;
//! 3. check the surface: every edge used by exactly two polygons in opposite
//!    directions, every vertex a single fan, one connected shell, outward normals;
//! 4. merge adjacent coplanar polygons into faces (maximal planar connected regions),
//!    trace each face's boundary loops (outer loop, holes);
//! 5. keep as vertices only the points where three or more faces meet (points that
//!    only split a straight boundary are dropped), split loops into edges there;
//! 6. classify edges and vertices as convex or not, triangulate faces, and number
//!    everything in a canonical, format-independent order.

mod elements;
mod loops;
mod mesh;
mod numbering;
mod regions;

use glam::DVec3;

use crate::geometry::Aabb;
use crate::io::MeshSoup;
use crate::load::validation::ValidationReport;
use crate::model::{Edge, Face, Vertex};
#[cfg(doc)]
use crate::tolerance::WELD_REL;

use mesh::Mesh;
use regions::Regions;

/// The boundary representation as built from a soup, before convex decomposition.
#[derive(Clone, Debug)]
pub(crate) struct Brep {
    /// Vertices in canonical order.
    pub(crate) vertices: Vec<Vertex>,
    /// Edges in canonical order.
    pub(crate) edges: Vec<Edge>,
    /// Faces in canonical order.
    pub(crate) faces: Vec<Face>,
    /// Bounding box.
    pub(crate) bounds: Aabb,
    /// Enclosed volume.
    pub(crate) volume: f64,
}

/// Builds the B-rep of a soup, or reports everything wrong with it.
///
/// # Errors
/// A [`ValidationReport`] listing each defect with its place and fix.
pub(crate) fn build(soup: &MeshSoup) -> Result<Brep, ValidationReport> {
    let mut report = ValidationReport::default();
    let Some(mesh) = Mesh::weld_and_check(soup, &mut report) else {
        return Err(report);
    };
    if !report.is_ok() {
        return Err(report);
    }
    let mut mesh = mesh;
    mesh.check_surface(soup, &mut report);
    if !report.is_ok() {
        return Err(report);
    }
    let regions = mesh.planar_regions();
    let brep = to_brep(&mesh, soup, &regions, &mut report);
    match brep {
        Some(b) if report.is_ok() => Ok(b),
        _ => Err(report),
    }
}

/// Steps 4 to 6 on a checked mesh whose polygons are grouped into faces.
fn to_brep(mesh: &Mesh, soup: &MeshSoup, regions: &Regions, report: &mut ValidationReport) -> Option<Brep> {
    let planes = mesh.region_planes(regions, soup, report);
    let point_regions = mesh.point_regions(regions);
    let traced = mesh.trace_loops(regions, &point_regions, report)?;
    let numbering = mesh.number(&point_regions, &traced, regions.count);
    let mut vertices = mesh.vertices(&numbering, &point_regions);
    let faces = mesh.faces(&numbering, &traced, &planes, &vertices, report)?;
    let mut edges = numbering.edges;
    elements::classify_edges(&mut edges, &vertices, &faces, report);
    elements::classify_vertices(&mut vertices, &edges, &faces);
    let bounds = Aabb::around(vertices.iter().map(|v| v.position));
    let volume = faces
        .iter()
        .flat_map(|f| f.triangles.iter())
        .map(|t| {
            let [a, b, c] = t.map(|v| vertices[v.index()].position);
            a.dot(b.cross(c))
        })
        .sum::<f64>()
        / 6.0;
    Some(Brep {
        vertices,
        edges,
        faces,
        bounds,
        volume,
    })
}

/// A point as `(x, y, z)` for messages.
fn fmt_point(p: DVec3) -> String {
    format!("({}, {}, {})", p.x, p.y, p.z)
}
