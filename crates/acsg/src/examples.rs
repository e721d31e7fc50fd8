//! Built-in example parts, so that the tool runs with no files to find, and meshes of
//! known geometry for tests and benchmarks.
//!
//! The models are copies of the repository's fixtures (`fixtures/`, made by
//! `scripts/make_fixtures.py`) kept in the crate (`assets/examples/`, so that the
//! crate builds on its own when packaged), compiled into the library; a test checks
//! that the copies equal the fixtures.

use std::path::Path;

use crate::geometry::ConvexPolytope;
use crate::io::MeshSoup;
use crate::model::Part;
use crate::tolerance::{WELD_REL, scaled};

/// The paper's example (its Fig. 4, as modelled in `fixtures/`): an L-shaped block
/// (fixed, 200 × 100 × 150 mm) and a box (moving, 100 × 80 × 100 mm) that sits in the
/// L's inside corner at the assembled pose.
pub const L_BLOCK_OFF: &str = include_str!("../assets/examples/l_block.off");
/// The box of [`L_BLOCK_OFF`]'s example.
pub const BOX_OFF: &str = include_str!("../assets/examples/box.off");

/// A cube of side 10 with a corner at the origin (the moving part of
/// [`cube_and_slab`]).
pub const CUBE_OFF: &str = include_str!("../assets/examples/cube.off");
/// A large slab whose top face is the plane z = 0.
pub const SLAB_OFF: &str = include_str!("../assets/examples/slab.off");

/// Builds a part from an embedded OFF text.
///
/// # Panics
/// Only if the embedded model is broken, which the test suite rules out.
#[must_use]
pub fn builtin(name: &str, off: &str) -> Part {
    let soup = crate::io::read_bytes(off.as_bytes(), Path::new(name)).expect("embedded model reads");
    Part::try_new(&soup, name).expect("embedded model is a valid solid")
}

/// The L-block (fixed) and the box (moving) of the paper's example.
#[must_use]
pub fn l_block_and_box() -> (Part, Part) {
    (
        builtin("builtin:l_block.off", L_BLOCK_OFF),
        builtin("builtin:box.off", BOX_OFF),
    )
}

/// A large slab (fixed) and a cube (moving) resting on it at the identity pose.
#[must_use]
pub fn cube_and_slab() -> (Part, Part) {
    (
        builtin("builtin:slab.off", SLAB_OFF),
        builtin("builtin:cube.off", CUBE_OFF),
    )
}

/// The bounds of the built-in example, as in the paper's run: each rotation within
/// ±π/10, x and y within ±5 mm, z from 0 to 240 mm (the models are the paper's size).
#[must_use]
pub fn paper_bounds() -> crate::pose::Bounds {
    let r = std::f64::consts::PI / 10.0;
    crate::pose::Bounds::try_new([-5.0, -5.0, 0.0, -r, -r, -r], [5.0, 5.0, 240.0, r, r, r])
        .expect("the built-in bounds are valid")
}

/// A convex part with `faces` faces around a sphere of radius `radius` at the origin:
/// the cube trimmed by the sphere's tangent planes, their normals on a Fibonacci
/// lattice (so every plane leaves a face). For benchmarks on many-faced parts.
///
/// ```
/// let part = acsg::examples::faceted_sphere(200, 10.0);
/// assert_eq!(part.faces().len(), 200);
/// assert_eq!(part.convex_pieces().len(), 1);
/// ```
///
/// # Panics
/// If `faces` is too small to close the solid (fewer than 4).
#[must_use]
pub fn faceted_sphere(faces: usize, radius: f64) -> Part {
    use glam::DVec3;
    let mut polytope = ConvexPolytope::cuboid(DVec3::splat(-2.0 * radius), DVec3::splat(2.0 * radius));
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..faces {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / faces as f64;
        let r = (1.0 - z * z).sqrt();
        let normal = DVec3::new(r * (golden * i as f64).cos(), r * (golden * i as f64).sin(), z);
        polytope = polytope
            .clip(normal, radius, scaled(WELD_REL, radius))
            .expect("a tangent plane keeps the sphere");
    }
    let mut soup = MeshSoup {
        polygon_noun: "face",
        ..Default::default()
    };
    for face in polytope.faces() {
        let start = soup.positions.len() as u32;
        soup.positions.extend(&face.points);
        soup.polygons.push((start..start + face.points.len() as u32).collect());
    }
    Part::try_new(&soup, "faceted sphere").expect("a closed convex solid")
}

/// The part's faces as a triangle soup over its vertices (outward winding): with
/// [`refine_midpoints`], large meshes of known geometry for tests and benchmarks.
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
/// let soup = acsg::examples::triangle_soup(&l_block);
/// let fine = acsg::examples::refine_midpoints(&soup);
/// assert_eq!(fine.polygons.len(), 4 * soup.polygons.len());
/// ```
///
/// # Panics
/// If a polygon is not a triangle.
#[must_use]
pub fn refine_midpoints(soup: &MeshSoup) -> MeshSoup {
    let mut positions = soup.positions.clone();
    let mut midpoints: std::collections::HashMap<(u32, u32), u32> = std::collections::HashMap::new();
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

#[cfg(test)]
mod tests {
    /// The copies in `assets/examples/` are the repository's fixtures, byte for byte
    /// (skipped, with a line on stderr, outside the repository: a packaged crate).
    #[test]
    fn embedded_models_are_the_fixtures() {
        let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        if !fixtures.is_dir() {
            use std::io::Write as _;
            let _ = writeln!(
                std::io::stderr().lock(),
                "SKIPPED embedded_models_are_the_fixtures: no fixtures/ folder (not in the repository)"
            );
            return;
        }
        for (name, text) in [
            ("l_block.off", super::L_BLOCK_OFF),
            ("box.off", super::BOX_OFF),
            ("cube.off", super::CUBE_OFF),
            ("slab.off", super::SLAB_OFF),
        ] {
            let fixture = std::fs::read_to_string(fixtures.join(name)).expect("the fixture reads");
            assert_eq!(
                fixture, text,
                "assets/examples/{name} differs from fixtures/{name}: copy it again"
            );
        }
    }
}
