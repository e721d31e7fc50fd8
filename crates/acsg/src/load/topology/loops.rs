//! Each face's boundary loops (steps 4 and 5 of [`super`]): traced along the region
//! boundaries, split into edges at the corners (the points where three or more faces
//! meet).

use rustc_hash::FxHashMap as HashMap;

use super::fmt_point;
use super::mesh::Mesh;
use super::regions::Regions;
use crate::load::validation::{DefectKind, ValidationReport};

/// A B-rep edge found while tracing loops, in mesh point ids.
pub(super) struct RawEdge {
    /// Region whose loop runs `from -> to`.
    pub(super) left: u32,
    pub(super) right: u32,
    pub(super) from: u32,
    pub(super) to: u32,
    sides_seen: u8,
}

/// A region's boundary loop, split at its corners.
pub(super) struct RawLoop {
    /// Mesh point ids of the corners only (points where three or more faces meet).
    pub(super) corners: Vec<u32>,
    /// Raw edge index of the segment starting at each corner.
    pub(super) edges: Vec<usize>,
}

/// Every region's loops, over edges shared by the two regions they separate.
pub(super) struct TracedLoops {
    pub(super) edges: Vec<RawEdge>,
    /// The loops of each region.
    pub(super) loops: Vec<Vec<RawLoop>>,
}

impl Mesh {
    /// Traces each region's boundary loops: after boundary half-edge h, the next one
    /// leaves h's end point inside the same region. `None` (and a defect) when a loop
    /// does not close, crosses itself, has no corner, or an edge is not traced once from
    /// each side.
    pub(super) fn trace_loops(
        &self,
        regions: &Regions,
        point_regions: &[Vec<u32>],
        report: &mut ValidationReport,
    ) -> Option<TracedLoops> {
        let is_corner = |v: u32| point_regions[v as usize].len() >= 3;
        let mut traced = TracedLoops {
            edges: Vec::new(),
            loops: (0..regions.count).map(|_| Vec::new()).collect(),
        };
        let mut edge_index: HashMap<(u32, u32, u32, u32), usize> = HashMap::default();
        let mut seen = vec![false; self.corners.len()];
        for start in 0..self.corners.len() {
            if seen[start] || !self.is_region_boundary(regions, start) {
                continue;
            }
            let mut chain = self.boundary_chain(regions, start, &mut seen, report)?;
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
            let r = self.region_of(regions, start);
            let raw = self.split_at_corners(regions, r, &chain, &is_corner, &mut traced.edges, &mut edge_index);
            traced.loops[r as usize].push(raw);
        }
        if traced.edges.iter().any(|e| e.sides_seen != 2) {
            report.push(
                DefectKind::Degenerate,
                "an edge between two faces is traced inconsistently",
                "check the model for slivers or overlapping faces",
            );
            return None;
        }
        Some(traced)
    }

    /// Whether half-edge `h` separates two regions.
    fn is_region_boundary(&self, regions: &Regions, h: usize) -> bool {
        self.region_of(regions, self.twin[h] as usize) != self.region_of(regions, h)
    }

    /// The boundary half-edges of one loop, from `start` round to it, marked in
    /// `seen`. `None` (and a defect) when the walk does not close or crosses itself.
    fn boundary_chain(
        &self,
        regions: &Regions,
        start: usize,
        seen: &mut [bool],
        report: &mut ValidationReport,
    ) -> Option<Vec<usize>> {
        let mut chain = Vec::new();
        let mut h = start;
        loop {
            seen[h] = true;
            chain.push(h);
            let mut g = self.next(h);
            let mut guard = 0;
            while !self.is_region_boundary(regions, g) {
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
                return Some(chain);
            }
            if seen[g] {
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
    }

    /// A loop of region `r` from its chain of half-edges (starting at a corner): one
    /// edge from each corner to the next, shared with the loop on its other side
    /// through `edge_index`.
    fn split_at_corners(
        &self,
        regions: &Regions,
        r: u32,
        chain: &[usize],
        is_corner: &impl Fn(u32) -> bool,
        raw_edges: &mut Vec<RawEdge>,
        edge_index: &mut HashMap<(u32, u32, u32, u32), usize>,
    ) -> RawLoop {
        let mut raw = RawLoop {
            corners: Vec::new(),
            edges: Vec::new(),
        };
        let m = chain.len();
        let mut i = 0;
        while i < m {
            let from = self.corners[chain[i]];
            let right = self.region_of(regions, self.twin[chain[i]] as usize);
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
        raw
    }
}
