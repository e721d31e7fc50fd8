//! From a polygon soup to a boundary representation.
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

pub mod refine;

use rustc_hash::FxHashMap as HashMap;

use glam::{DVec2, DVec3};

use crate::io::MeshSoup;
use crate::model::validation::{DefectKind, ValidationReport};
use crate::model::{Aabb, Edge, EdgeId, Face, FaceId, Loop, Vertex, VertexId};
use crate::tolerance::{AREA_REL, COPLANAR_REL, PARALLEL_SIN, WELD_REL, scaled};

/// The boundary representation as built from a soup, before convex decomposition.
#[derive(Clone, Debug)]
pub struct Brep {
    /// Vertices in canonical order.
    pub vertices: Vec<Vertex>,
    /// Edges in canonical order.
    pub edges: Vec<Edge>,
    /// Faces in canonical order.
    pub faces: Vec<Face>,
    /// Bounding box.
    pub bounds: Aabb,
    /// Enclosed volume.
    pub volume: f64,
}

/// Builds the B-rep of a soup, or reports everything wrong with it.
///
/// # Errors
/// A [`ValidationReport`] listing each defect with its place and fix.
pub fn build(soup: &MeshSoup) -> Result<Brep, ValidationReport> {
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
    let brep = mesh.to_brep(soup, &regions, &mut report);
    match brep {
        Some(b) if report.is_ok() => Ok(b),
        _ => Err(report),
    }
}

/// A welded polygon mesh as flat half-edge arrays: half-edge `h` runs from
/// `corners[h]` to `corners[next(h)]` inside polygon `polygon_of[h]`.
struct Mesh {
    points: Vec<DVec3>,
    /// Corner point ids of all polygons, concatenated.
    corners: Vec<u32>,
    /// Polygon `p` owns half-edges `starts[p]..starts[p + 1]`.
    starts: Vec<u32>,
    polygon_of: Vec<u32>,
    /// The opposite half-edge (same edge, other polygon); set by `check_surface`.
    twin: Vec<u32>,
    /// Index of each welded polygon in the soup (for messages).
    source: Vec<usize>,
    /// Unit Newell normal and area of each polygon.
    normals: Vec<DVec3>,
    areas: Vec<f64>,
    /// Length scale L of the part: its bounding-box diagonal.
    scale: f64,
}

fn fmt_point(p: DVec3) -> String {
    format!("({}, {}, {})", p.x, p.y, p.z)
}

/// Newell's normal (length = twice the area) of a closed polygon.
fn newell(points: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let next = points.clone().cycle().skip(1);
    points.zip(next).fold(DVec3::ZERO, |acc, (p, q)| acc + p.cross(q))
}

impl Mesh {
    fn weld_and_check(soup: &MeshSoup, report: &mut ValidationReport) -> Option<Mesh> {
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
            return None;
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
        if !report.is_ok() {
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
        let area_tol = AREA_REL * scale * scale;
        let plane_tol = scaled(COPLANAR_REL, scale);
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
            let pts = welded.iter().map(|&v| mesh.points[v as usize]);
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
                continue;
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
                    continue;
                }
            }
            let p = mesh.source.len() as u32;
            mesh.corners.extend_from_slice(&welded);
            mesh.polygon_of.extend(std::iter::repeat_n(p, welded.len()));
            mesh.starts.push(mesh.corners.len() as u32);
            mesh.source.push(i);
            mesh.normals.push(normal);
            mesh.areas.push(area);
        }
        Some(mesh)
    }

    fn polygon_count(&self) -> usize {
        self.source.len()
    }

    fn half_edges(&self, p: usize) -> std::ops::Range<usize> {
        self.starts[p] as usize..self.starts[p + 1] as usize
    }

    fn next(&self, h: usize) -> usize {
        let p = self.polygon_of[h] as usize;
        if h + 1 == self.starts[p + 1] as usize {
            self.starts[p] as usize
        } else {
            h + 1
        }
    }

    fn prev(&self, h: usize) -> usize {
        let p = self.polygon_of[h] as usize;
        if h == self.starts[p] as usize {
            self.starts[p + 1] as usize - 1
        } else {
            h - 1
        }
    }

    /// End points of half-edge `h`.
    fn ends(&self, h: usize) -> (u32, u32) {
        (self.corners[h], self.corners[self.next(h)])
    }

    fn polygon_points(&self, p: usize) -> impl Iterator<Item = DVec3> + Clone + '_ {
        self.half_edges(p).map(|h| self.points[self.corners[h] as usize])
    }

    fn describe(&self, soup: &MeshSoup, poly: u32) -> String {
        soup.describe_polygon(self.source[poly as usize])
    }

    /// Edge use (and twins), vertex fans, shells and orientation.
    fn check_surface(&mut self, soup: &MeshSoup, report: &mut ValidationReport) {
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
    fn around(&self, h: usize) -> usize {
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

/// Merges points closer than `tol`; returns the merged points and, for each input
/// point, its merged index. The first point of a cluster represents it.
pub(crate) fn weld(points: &[DVec3], tol: f64) -> (Vec<DVec3>, Vec<u32>) {
    // Cells much larger than tol: a point needs a look into a neighbouring cell only
    // along axes where it lies within tol of its cell's side.
    let tol = tol.max(0.0);
    // A cell no smaller than a tiny fraction of the coordinates, so that keys stay far
    // from overflow even for tol = 0.
    let magnitude = points.iter().map(|p| p.abs().max_element()).fold(1.0, f64::max);
    let cell = (tol * 1024.0).max(magnitude * 1e-12);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::default();
    let mut merged: Vec<DVec3> = Vec::new();
    let mut map = Vec::with_capacity(points.len());
    for &p in points {
        let scaled = p / cell;
        let home = scaled.floor();
        let frac = (scaled - home) * cell;
        let key = [home.x as i64, home.y as i64, home.z as i64];
        let span = |axis: usize| {
            let lo = if frac[axis] <= tol { -1 } else { 0 };
            let hi = if cell - frac[axis] <= tol { 1 } else { 0 };
            lo..=hi
        };
        let mut found = None;
        'search: for dx in span(0) {
            for dy in span(1) {
                for dz in span(2) {
                    let near = grid.get(&[
                        key[0].saturating_add(dx),
                        key[1].saturating_add(dy),
                        key[2].saturating_add(dz),
                    ]);
                    if let Some(&m) =
                        near.and_then(|list| list.iter().find(|&&m| merged[m as usize].distance(p) <= tol))
                    {
                        found = Some(m);
                        break 'search;
                    }
                }
            }
        }
        let id = found.unwrap_or_else(|| {
            let id = merged.len() as u32;
            merged.push(p);
            grid.entry(key).or_default().push(id);
            id
        });
        map.push(id);
    }
    (merged, map)
}

/// Disjoint sets over `0..n`.
pub(crate) struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }
    pub(crate) fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }
    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// A B-rep edge found while tracing loops, in mesh point ids.
struct RawEdge {
    /// Region whose loop runs `from -> to`.
    left: u32,
    right: u32,
    from: u32,
    to: u32,
    sides_seen: u8,
}

/// A region's boundary loop, split at its corners.
struct RawLoop {
    /// Mesh point ids of the corners only (points where three or more faces meet).
    corners: Vec<u32>,
    /// Raw edge index of the segment starting at each corner.
    edges: Vec<usize>,
}

/// Orthonormal basis (u, v) of the plane with normal `n`.
fn plane_basis(n: DVec3) -> (DVec3, DVec3) {
    let u = n.any_orthonormal_vector();
    (u, n.cross(u))
}

/// Twice the signed area of a 2D polygon (positive counter-clockwise).
fn shoelace(points: &[DVec2]) -> f64 {
    points
        .iter()
        .zip(points.iter().cycle().skip(1))
        .map(|(p, q)| p.perp_dot(*q))
        .sum()
}

impl Mesh {
    /// Groups polygons into maximal planar connected regions; returns the region of
    /// each polygon and the number of regions.
    fn planar_regions(&self) -> (Vec<u32>, usize) {
        let tol = scaled(COPLANAR_REL, self.scale);
        let n = self.polygon_count();
        let mut region = vec![u32::MAX; n];
        let mut count = 0u32;
        let centroid = |p: usize| self.polygon_points(p).sum::<DVec3>() / self.half_edges(p).len() as f64;
        let mut stack = Vec::new();
        for seed in 0..n {
            if region[seed] != u32::MAX {
                continue;
            }
            region[seed] = count;
            let mut normal_sum = self.normals[seed] * self.areas[seed];
            let mut point_sum = centroid(seed) * self.areas[seed];
            let mut area_sum = self.areas[seed];
            stack.push(seed);
            while let Some(p) = stack.pop() {
                for h in self.half_edges(p) {
                    let q = self.polygon_of[self.twin[h] as usize] as usize;
                    if region[q] != u32::MAX {
                        continue;
                    }
                    let normal = normal_sum.normalize();
                    let offset = normal.dot(point_sum / area_sum);
                    let flat = self.normals[q].dot(normal) > 0.0
                        && self.polygon_points(q).all(|x| (normal.dot(x) - offset).abs() <= tol);
                    if flat {
                        region[q] = count;
                        normal_sum += self.normals[q] * self.areas[q];
                        point_sum += centroid(q) * self.areas[q];
                        area_sum += self.areas[q];
                        stack.push(q);
                    }
                }
            }
            count += 1;
        }
        (region, count as usize)
    }

    fn to_brep(&self, soup: &MeshSoup, regions: &(Vec<u32>, usize), report: &mut ValidationReport) -> Option<Brep> {
        let (region, region_count) = (&regions.0, regions.1);
        let tol = scaled(COPLANAR_REL, self.scale);
        let region_of = |h: usize| region[self.polygon_of[h] as usize];

        // Each region's plane: area-weighted normal, mean offset over its corners.
        let mut normal_sums = vec![DVec3::ZERO; region_count];
        for p in 0..self.polygon_count() {
            normal_sums[region[p] as usize] += self.normals[p] * self.areas[p];
        }
        let normals: Vec<DVec3> = normal_sums.iter().map(|n| n.normalize()).collect();
        let mut offset_sums = vec![(0.0, 0usize); region_count];
        for h in 0..self.corners.len() {
            let r = region_of(h) as usize;
            offset_sums[r].0 += normals[r].dot(self.points[self.corners[h] as usize]);
            offset_sums[r].1 += 1;
        }
        let planes: Vec<(DVec3, f64)> = normals
            .iter()
            .zip(&offset_sums)
            .map(|(&n, &(sum, count))| (n, sum / count as f64))
            .collect();
        let mut worst = vec![0.0f64; region_count];
        for h in 0..self.corners.len() {
            let r = region_of(h) as usize;
            let (n, d) = planes[r];
            worst[r] = worst[r].max((n.dot(self.points[self.corners[h] as usize]) - d).abs());
        }
        for (r, &w) in worst.iter().enumerate().filter(|&(_, &w)| w > tol) {
            let first = region.iter().position(|&x| x as usize == r).unwrap_or(0) as u32;
            report.push(
                DefectKind::NotPlanar,
                format!(
                    "the face containing {} bends: a point is {w:.3e} off its plane",
                    self.describe(soup, first)
                ),
                "the surface curves gradually; model it with distinct planar faces",
            );
        }

        // The distinct regions around each point, from one walk around its fan.
        let mut point_regions: Vec<Vec<u32>> = vec![Vec::new(); self.points.len()];
        let mut walked = vec![false; self.points.len()];
        for start in 0..self.corners.len() {
            let v = self.corners[start] as usize;
            if std::mem::replace(&mut walked[v], true) {
                continue;
            }
            let mut h = start;
            loop {
                let r = region_of(h);
                if !point_regions[v].contains(&r) {
                    point_regions[v].push(r);
                }
                h = self.around(h);
                if h == start {
                    break;
                }
            }
            point_regions[v].sort_unstable();
        }
        let is_corner = |v: u32| point_regions[v as usize].len() >= 3;
        let is_boundary = |h: usize| region_of(self.twin[h] as usize) != region_of(h);

        // Trace each region's boundary loops: after boundary half-edge h, the next one
        // leaves h's end point inside the same region.
        let mut raw_edges: Vec<RawEdge> = Vec::new();
        let mut edge_index: HashMap<(u32, u32, u32, u32), usize> = HashMap::default();
        let mut loops: Vec<Vec<RawLoop>> = (0..region_count).map(|_| Vec::new()).collect();
        let mut traced = vec![false; self.corners.len()];
        for start in 0..self.corners.len() {
            if traced[start] || !is_boundary(start) {
                continue;
            }
            let r = region_of(start);
            let mut chain = Vec::new();
            let mut h = start;
            loop {
                traced[h] = true;
                chain.push(h);
                let mut g = self.next(h);
                let mut guard = 0;
                while !is_boundary(g) {
                    g = self.next(self.twin[g] as usize);
                    guard += 1;
                    if guard > self.corners.len() {
                        report.push(
                            DefectKind::Degenerate,
                            format!(
                                "the boundary of a face through point {} does not close",
                                fmt_point(self.points[self.corners[h] as usize])
                            ),
                            "check the model for slivers or overlapping faces",
                        );
                        return None;
                    }
                }
                if g == start {
                    break;
                }
                if traced[g] {
                    report.push(
                        DefectKind::Degenerate,
                        format!(
                            "the boundary of a face through point {} crosses itself",
                            fmt_point(self.points[self.corners[g] as usize])
                        ),
                        "check the model for faces touching at a single point",
                    );
                    return None;
                }
                h = g;
            }
            let Some(first_corner) = chain.iter().position(|&h| is_corner(self.corners[h])) else {
                report.push(
                    DefectKind::Degenerate,
                    format!(
                        "a boundary loop through point {} has no corner",
                        fmt_point(self.points[self.corners[start] as usize])
                    ),
                    "check the model for faces meeting at 0 or 360 degrees",
                );
                return None;
            };
            chain.rotate_left(first_corner);
            let mut raw = RawLoop {
                corners: Vec::new(),
                edges: Vec::new(),
            };
            let m = chain.len();
            let mut i = 0;
            while i < m {
                let from = self.corners[chain[i]];
                let right = region_of(self.twin[chain[i]] as usize);
                let mut j = i + 1;
                while j < m && !is_corner(self.corners[chain[j]]) {
                    j += 1;
                }
                let to = self.corners[chain[j % m]];
                let key = (from.min(to), from.max(to), r.min(right), r.max(right));
                let e = *edge_index.entry(key).or_insert_with(|| {
                    raw_edges.push(RawEdge {
                        left: r,
                        right,
                        from,
                        to,
                        sides_seen: 0,
                    });
                    raw_edges.len() - 1
                });
                raw_edges[e].sides_seen += 1;
                raw.corners.push(from);
                raw.edges.push(e);
                i = j;
            }
            loops[r as usize].push(raw);
        }
        if raw_edges.iter().any(|e| e.sides_seen != 2) {
            report.push(
                DefectKind::Degenerate,
                "an edge between two faces is traced inconsistently",
                "check the model for slivers or overlapping faces",
            );
            return None;
        }

        // Canonical numbering: vertices by position, faces by their vertex sets, edges
        // by their end points.
        let quantum = scaled(COPLANAR_REL, self.scale);
        let mut corner_ids: Vec<u32> = (0..self.points.len() as u32).filter(|&v| is_corner(v)).collect();
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
        corner_ids.sort_by_key(sort_key);
        let mut vertex_of = HashMap::default();
        for (i, &v) in corner_ids.iter().enumerate() {
            vertex_of.insert(v, VertexId(i as u32));
        }
        let mut face_order: Vec<(Vec<VertexId>, u32)> = (0..region_count as u32)
            .map(|r| {
                let mut vs: Vec<VertexId> = loops[r as usize]
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
        let mut edge_order: Vec<(Edge, usize)> = raw_edges
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
        let mut edge_of = vec![EdgeId(0); raw_edges.len()];
        for (i, (_, raw)) in edge_order.iter().enumerate() {
            edge_of[*raw] = EdgeId(i as u32);
        }

        let mut vertices: Vec<Vertex> = corner_ids
            .iter()
            .map(|&v| Vertex {
                position: self.points[v as usize],
                convex: false,
                edges: Vec::new(),
                faces: point_regions[v as usize].iter().map(|&r| face_of[r as usize]).collect(),
            })
            .collect();
        for v in &mut vertices {
            v.faces.sort_unstable();
        }
        let mut edges: Vec<Edge> = edge_order.into_iter().map(|(e, _)| e).collect();
        for (i, e) in edges.iter().enumerate() {
            for v in e.vertices {
                vertices[v.index()].edges.push(EdgeId(i as u32));
            }
        }

        let mut faces = Vec::with_capacity(region_count);
        for (_, r) in &face_order {
            let (normal, offset) = planes[*r as usize];
            let (u, w) = plane_basis(normal);
            let mut face_loops: Vec<(f64, Loop)> = loops[*r as usize]
                .iter()
                .map(|raw| {
                    let mut vs: Vec<VertexId> = raw.corners.iter().map(|c| vertex_of[c]).collect();
                    let mut es: Vec<EdgeId> = raw.edges.iter().map(|&e| edge_of[e]).collect();
                    let start = (0..vs.len()).min_by_key(|&i| vs[i]).unwrap_or(0);
                    vs.rotate_left(start);
                    es.rotate_left(start);
                    let flat: Vec<DVec2> = vs
                        .iter()
                        .map(|v| {
                            let p = vertices[v.index()].position;
                            DVec2::new(p.dot(u), p.dot(w))
                        })
                        .collect();
                    (
                        0.5 * shoelace(&flat),
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
            let triangles = triangulate(&loops, &vertices, u, w);
            let tri_area: f64 = triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|v| vertices[v.index()].position);
                    0.5 * (b - a).cross(c - a).dot(normal)
                })
                .sum();
            if (tri_area - area).abs() > 1e-6 * area.abs().max(self.scale * self.scale * AREA_REL) {
                report.push(
                    DefectKind::Degenerate,
                    format!(
                        "a face with normal {} and area {area} could not be triangulated (got {tri_area})",
                        fmt_point(normal)
                    ),
                    "check the face for self-intersecting or touching boundary loops",
                );
            }
            faces.push(Face {
                normal,
                offset,
                loops,
                area,
                triangles,
            });
        }

        // Edge convexity: with n_l, n_r the normals of the faces left and right of the
        // edge run a -> b in the left face, the dihedral is convex iff
        // (n_l × n_r) · (b - a) > 0.
        for e in &mut edges {
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
        classify_vertices(&mut vertices, &edges, &faces);

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
}

/// A vertex is convex when every incident edge is convex, every incident face's corner
/// there is below 180 degrees, and every incident edge runs on the inner side of every
/// incident face's plane (the local cone is convex).
fn classify_vertices(vertices: &mut [Vertex], edges: &[Edge], faces: &[Face]) {
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
            v.faces.iter().all(|f| faces[f.index()].normal.dot(d) <= 1e-12)
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
