//! The welded polygon mesh (steps 1 to 3 of [`super`]): points welded, polygons checked,
//! half-edges with their twins, and the surface checked to be one closed, manifold,
//! outward shell.

use glam::DVec3;

use super::fmt_point;
use crate::geometry::{Aabb, newell, weld};
use crate::io::MeshSoup;
use crate::load::validation::{DefectKind, ValidationReport};
use crate::tolerance::{AREA_REL, COPLANAR_REL, WELD_REL, scaled};

/// A welded polygon mesh as flat half-edge arrays: half-edge `h` runs from
/// `corners[h]` to `corners[next(h)]` inside polygon `polygon_of[h]`.
pub(super) struct Mesh {
    pub(super) points: Vec<DVec3>,
    /// Corner point ids of all polygons, concatenated.
    pub(super) corners: Vec<u32>,
    /// Polygon `p` owns half-edges `starts[p]..starts[p + 1]`.
    pub(super) starts: Vec<u32>,
    pub(super) polygon_of: Vec<u32>,
    /// The opposite half-edge (same edge, other polygon); set by `check_surface`.
    pub(super) twin: Vec<u32>,
    /// Index of each welded polygon in the soup (for messages).
    pub(super) source: Vec<usize>,
    /// Unit Newell normal and area of each polygon.
    pub(super) normals: Vec<DVec3>,
    pub(super) areas: Vec<f64>,
    /// Length scale L of the part: its bounding-box diagonal.
    pub(super) scale: f64,
}

impl Mesh {
    /// Welds the soup's points and checks each polygon (finite, planar, not
    /// degenerate); `None` when nothing can be built on it.
    pub(super) fn weld_and_check(soup: &MeshSoup, report: &mut ValidationReport) -> Option<Mesh> {
        if !check_soup(soup, report) {
            return None;
        }
        let used = soup.polygons.iter().flatten().map(|&v| soup.positions[v as usize]);
        let scale = Aabb::around(used).diagonal();
        if scale <= f64::MIN_POSITIVE {
            report.push(
                DefectKind::ZeroArea,
                "all points coincide",
                "export the part with its real geometry",
            );
            return None;
        }
        let (points, map) = weld(&soup.positions, scaled(WELD_REL, scale));
        let total: usize = soup.polygons.iter().map(Vec::len).sum();
        let mut mesh = Mesh {
            points,
            corners: Vec::with_capacity(total),
            starts: vec![0],
            polygon_of: Vec::with_capacity(total),
            twin: Vec::new(),
            source: Vec::new(),
            normals: Vec::new(),
            areas: Vec::new(),
            scale,
        };
        let mut welded: Vec<u32> = Vec::new();
        for (i, poly) in soup.polygons.iter().enumerate() {
            welded.clear();
            welded.extend(poly.iter().map(|&v| map[v as usize]));
            welded.dedup();
            while welded.len() > 1 && welded.first() == welded.last() {
                welded.pop();
            }
            if let Some((normal, area)) = mesh.polygon_plane(&welded, soup, i, report) {
                let p = mesh.source.len() as u32;
                mesh.corners.extend_from_slice(&welded);
                mesh.polygon_of.extend(std::iter::repeat_n(p, welded.len()));
                mesh.starts.push(mesh.corners.len() as u32);
                mesh.source.push(i);
                mesh.normals.push(normal);
                mesh.areas.push(area);
            }
        }
        Some(mesh)
    }

    /// The unit normal and area of soup polygon `i` with welded corners `welded`, or
    /// `None` (and a defect) when it has no area or is not planar.
    fn polygon_plane(
        &self,
        welded: &[u32],
        soup: &MeshSoup,
        i: usize,
        report: &mut ValidationReport,
    ) -> Option<(DVec3, f64)> {
        let area_tol = AREA_REL * self.scale * self.scale;
        let plane_tol = scaled(COPLANAR_REL, self.scale);
        let pts = welded.iter().map(|&v| self.points[v as usize]);
        let n = newell(pts.clone());
        let area = 0.5 * n.length();
        if welded.len() < 3 || area <= area_tol {
            report.push(
                DefectKind::ZeroArea,
                format!(
                    "{} has area {area:.3e} (its corners are collinear or coincide)",
                    soup.describe_polygon(i)
                ),
                "remove the degenerate polygon and close the surface without it",
            );
            return None;
        }
        let normal = n / n.length();
        if welded.len() > 3 {
            let offset = pts.clone().map(|p| normal.dot(p)).sum::<f64>() / welded.len() as f64;
            let worst = pts.map(|p| (normal.dot(p) - offset).abs()).fold(0.0, f64::max);
            if worst > plane_tol {
                report.push(
                    DefectKind::NotPlanar,
                    format!(
                        "{}: a corner is {worst:.3e} off the polygon's plane",
                        soup.describe_polygon(i)
                    ),
                    "split the polygon into triangles or planar polygons",
                );
                return None;
            }
        }
        Some((normal, area))
    }

    pub(super) fn polygon_count(&self) -> usize {
        self.source.len()
    }

    pub(super) fn half_edges(&self, p: usize) -> std::ops::Range<usize> {
        self.starts[p] as usize..self.starts[p + 1] as usize
    }

    pub(super) fn next(&self, h: usize) -> usize {
        let p = self.polygon_of[h] as usize;
        if h + 1 == self.starts[p + 1] as usize {
            self.starts[p] as usize
        } else {
            h + 1
        }
    }

    pub(super) fn prev(&self, h: usize) -> usize {
        let p = self.polygon_of[h] as usize;
        if h == self.starts[p] as usize {
            self.starts[p + 1] as usize - 1
        } else {
            h - 1
        }
    }

    /// End points of half-edge `h`.
    pub(super) fn ends(&self, h: usize) -> (u32, u32) {
        (self.corners[h], self.corners[self.next(h)])
    }

    pub(super) fn polygon_points(&self, p: usize) -> impl Iterator<Item = DVec3> + Clone + '_ {
        self.half_edges(p).map(|h| self.points[self.corners[h] as usize])
    }

    pub(super) fn describe(&self, soup: &MeshSoup, poly: u32) -> String {
        soup.describe_polygon(self.source[poly as usize])
    }

    /// Edge use (and twins), vertex fans, shells and orientation.
    pub(super) fn check_surface(&mut self, soup: &MeshSoup, report: &mut ValidationReport) {
        // Every use of every undirected edge, grouped by sorting: (low, high, half-edge).
        let mut uses: Vec<(u32, u32, u32)> = (0..self.corners.len())
            .map(|h| {
                let (a, b) = self.ends(h);
                (a.min(b), a.max(b), h as u32)
            })
            .collect();
        uses.sort_unstable();
        self.twin = vec![u32::MAX; self.corners.len()];
        for group in uses.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let place = || {
                format!(
                    "edge {} - {} (used by {})",
                    fmt_point(self.points[group[0].0 as usize]),
                    fmt_point(self.points[group[0].1 as usize]),
                    group
                        .iter()
                        .map(|&(.., h)| self.describe(soup, self.polygon_of[h as usize]))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            match *group {
                [_] => report.push(
                    DefectKind::NotClosed,
                    place(),
                    "the surface has a gap there; add the missing faces so it encloses a volume",
                ),
                [(.., h1), (.., h2)] if self.ends(h1 as usize) == self.ends(h2 as usize) => report.push(
                    DefectKind::InconsistentOrientation,
                    place(),
                    "reverse the winding of one of these polygons so neighbours run their common edge in opposite directions",
                ),
                [(.., h1), (.., h2)] => {
                    self.twin[h1 as usize] = h2;
                    self.twin[h2 as usize] = h1;
                }
                _ => report.push(
                    DefectKind::NotManifold,
                    place(),
                    "more than two faces meet at this edge; separate the solids or remove the extra faces",
                ),
            }
        }
        if !report.is_ok() {
            return;
        }
        self.check_vertex_fans(report);
        if !report.is_ok() {
            return;
        }
        let shells = self.shell_count();
        if shells > 1 {
            report.push(
                DefectKind::SeveralShells,
                format!("the file holds {shells} separate closed shells"),
                "put one solid in each file (the fixed part and the moving part are separate files)",
            );
            return;
        }
        let volume = self.signed_volume();
        if volume < 0.0 {
            report.push(
                DefectKind::InwardOrientation,
                format!("the enclosed volume is {volume} (negative: every normal points inwards)"),
                "reverse the winding of every polygon (flip normals) when exporting",
            );
        }
    }

    /// The half-edge leaving the same point as `h`, one polygon further around it.
    pub(super) fn around(&self, h: usize) -> usize {
        self.twin[self.prev(h)] as usize
    }

    /// A manifold point has one fan: walking `around` from any of its half-edges
    /// visits all of them.
    fn check_vertex_fans(&self, report: &mut ValidationReport) {
        let mut fans = vec![0u32; self.points.len()];
        let mut seen = vec![false; self.corners.len()];
        for start in 0..self.corners.len() {
            if seen[start] {
                continue;
            }
            fans[self.corners[start] as usize] += 1;
            let mut h = start;
            while !seen[h] {
                seen[h] = true;
                h = self.around(h);
            }
        }
        for (v, _) in fans.iter().enumerate().filter(|&(_, &n)| n > 1) {
            report.push(
                DefectKind::NotManifold,
                format!(
                    "point {}: separate fans of faces meet only at this point",
                    fmt_point(self.points[v])
                ),
                "separate the solids that touch at this point, or merge them properly",
            );
        }
    }

    fn shell_count(&self) -> usize {
        let mut uf = UnionFind::new(self.polygon_count());
        for h in 0..self.corners.len() {
            uf.union(
                self.polygon_of[h] as usize,
                self.polygon_of[self.twin[h] as usize] as usize,
            );
        }
        (0..self.polygon_count()).filter(|&i| uf.find(i) == i).count()
    }

    fn signed_volume(&self) -> f64 {
        (0..self.polygon_count())
            .map(|p| {
                let hs = self.half_edges(p);
                let p0 = self.points[self.corners[hs.start] as usize];
                (hs.start + 1..hs.end - 1)
                    .map(|h| {
                        p0.dot(self.points[self.corners[h] as usize].cross(self.points[self.corners[h + 1] as usize]))
                    })
                    .sum::<f64>()
            })
            .sum::<f64>()
            / 6.0
    }
}

/// The checks a soup must pass before welding: some points and polygons, finite
/// coordinates, polygon indices within the points. Reports every failure; `false`
/// when any.
fn check_soup(soup: &MeshSoup, report: &mut ValidationReport) -> bool {
    if soup.positions.is_empty() || soup.polygons.is_empty() {
        report.push(
            DefectKind::Empty,
            format!(
                "{} points, {} {}s",
                soup.positions.len(),
                soup.polygons.len(),
                soup.polygon_noun
            ),
            "the file holds no solid; export the part again",
        );
        return false;
    }
    for (i, p) in soup.positions.iter().enumerate() {
        if !p.is_finite() {
            report.push(
                DefectKind::NonFinite,
                format!("point {i} = {}", fmt_point(*p)),
                "give every coordinate a finite value",
            );
        }
    }
    for (i, poly) in soup.polygons.iter().enumerate() {
        if let Some(&bad) = poly.iter().find(|&&v| v as usize >= soup.positions.len()) {
            report.push(
                DefectKind::Degenerate,
                format!(
                    "{} refers to point {bad} of {}",
                    soup.describe_polygon(i),
                    soup.positions.len()
                ),
                "fix the polygon's point indices",
            );
        }
    }
    report.is_ok()
}

/// Disjoint sets over `0..n`.
struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }
    fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }
}
