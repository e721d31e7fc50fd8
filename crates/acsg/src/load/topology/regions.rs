//! Faces as regions of the mesh (step 4 of [`super`]): adjacent coplanar polygons
//! merged, each region's plane, and the regions met around each point.

use glam::DVec3;

use super::mesh::Mesh;
use crate::io::MeshSoup;
use crate::load::validation::{DefectKind, ValidationReport};
use crate::tolerance::{COPLANAR_REL, scaled};

/// The faces to be, as regions of the mesh's polygons.
pub(super) struct Regions {
    /// The region of each polygon.
    pub(super) of_polygon: Vec<u32>,
    /// The number of regions.
    pub(super) count: usize,
}

impl Mesh {
    /// Groups polygons into maximal planar connected regions.
    pub(super) fn planar_regions(&self) -> Regions {
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
        Regions {
            of_polygon: region,
            count: count as usize,
        }
    }

    /// The region of half-edge `h`'s polygon.
    pub(super) fn region_of(&self, regions: &Regions, h: usize) -> u32 {
        regions.of_polygon[self.polygon_of[h] as usize]
    }

    /// Each region's plane: the area-weighted normal and the mean offset over its
    /// corners. A region whose corners stray from that plane (a gradually curving
    /// surface merged polygon by polygon) is reported as not planar.
    pub(super) fn region_planes(
        &self,
        regions: &Regions,
        soup: &MeshSoup,
        report: &mut ValidationReport,
    ) -> Vec<(DVec3, f64)> {
        let region_count = regions.count;
        let tol = scaled(COPLANAR_REL, self.scale);
        let mut normal_sums = vec![DVec3::ZERO; region_count];
        for p in 0..self.polygon_count() {
            normal_sums[regions.of_polygon[p] as usize] += self.normals[p] * self.areas[p];
        }
        let normals: Vec<DVec3> = normal_sums.iter().map(|n| n.normalize()).collect();
        let mut offset_sums = vec![(0.0, 0usize); region_count];
        for h in 0..self.corners.len() {
            let r = self.region_of(regions, h) as usize;
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
            let r = self.region_of(regions, h) as usize;
            let (n, d) = planes[r];
            worst[r] = worst[r].max((n.dot(self.points[self.corners[h] as usize]) - d).abs());
        }
        for (r, &w) in worst.iter().enumerate().filter(|&(_, &w)| w > tol) {
            let first = regions.of_polygon.iter().position(|&x| x as usize == r).unwrap_or(0) as u32;
            report.push(
                DefectKind::NotPlanar,
                format!(
                    "the face containing {} bends: a point is {w:.3e} off its plane",
                    self.describe(soup, first)
                ),
                "the surface curves gradually; model it with distinct planar faces",
            );
        }
        planes
    }

    /// The distinct regions around each point, sorted, from one walk around its fan.
    pub(super) fn point_regions(&self, regions: &Regions) -> Vec<Vec<u32>> {
        let mut point_regions: Vec<Vec<u32>> = vec![Vec::new(); self.points.len()];
        let mut walked = vec![false; self.points.len()];
        for start in 0..self.corners.len() {
            let v = self.corners[start] as usize;
            if std::mem::replace(&mut walked[v], true) {
                continue;
            }
            let mut h = start;
            loop {
                let r = self.region_of(regions, h);
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
        point_regions
    }
}
