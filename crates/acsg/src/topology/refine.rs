//! Conforming refinement of triangle soups, for tests and benchmarks that need large
//! meshes of known geometry.

use std::collections::HashMap;

use crate::io::MeshSoup;
use crate::model::Part;

/// The part's faces as a triangle soup over its vertices (outward winding).
#[must_use]
pub fn triangle_soup(part: &Part) -> MeshSoup {
    MeshSoup {
        positions: part.vertices().iter().map(|v| v.position).collect(),
        polygons: part
            .faces()
            .iter()
            .flat_map(|f| f.triangles.iter().map(|t| t.map(|v| v.0).to_vec()))
            .collect(),
        polygon_lines: Vec::new(),
        polygon_noun: "triangle",
    }
}

/// Splits every triangle into four at its edge midpoints. Midpoints are shared between
/// neighbouring triangles, so a closed mesh stays closed (no T-junctions).
///
/// ```
/// let (l_block, _) = acsg::examples::l_block_and_box();
/// let soup = acsg::topology::refine::triangle_soup(&l_block);
/// let fine = acsg::topology::refine::refine_midpoints(&soup);
/// assert_eq!(fine.polygons.len(), 4 * soup.polygons.len());
/// ```
///
/// # Panics
/// If a polygon is not a triangle.
#[must_use]
pub fn refine_midpoints(soup: &MeshSoup) -> MeshSoup {
    let mut positions = soup.positions.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut polygons = Vec::with_capacity(soup.polygons.len() * 4);
    for poly in &soup.polygons {
        let [a, b, c] = <[u32; 3]>::try_from(poly.as_slice()).expect("a triangle soup");
        let mut mid = |p: u32, q: u32| {
            *midpoints.entry((p.min(q), p.max(q))).or_insert_with(|| {
                positions.push((positions[p as usize] + positions[q as usize]) * 0.5);
                (positions.len() - 1) as u32
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        polygons.extend([vec![a, ab, ca], vec![ab, b, bc], vec![ca, bc, c], vec![ab, bc, ca]]);
    }
    MeshSoup {
        positions,
        polygon_lines: Vec::new(),
        polygons,
        polygon_noun: "triangle",
    }
}
