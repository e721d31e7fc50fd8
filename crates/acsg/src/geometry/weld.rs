//! Welding: points closer than a tolerance merged into one.

use glam::DVec3;
use rustc_hash::FxHashMap as HashMap;

use crate::tolerance::ROUNDOFF_REL;

/// Merges points closer than `tol`; returns the merged points and, for each input
/// point, its merged index. The first point of a cluster represents it.
pub(crate) fn weld(points: &[DVec3], tol: f64) -> (Vec<DVec3>, Vec<u32>) {
    // Cells much larger than tol: a point needs a look into a neighbouring cell only
    // along axes where it lies within tol of its cell's side.
    let tol = tol.max(0.0);
    // A cell no smaller than a tiny fraction of the coordinates, so that keys stay far
    // from overflow even for tol = 0.
    let magnitude = points.iter().map(|p| p.abs().max_element()).fold(1.0, f64::max);
    let cell = (tol * 1024.0).max(magnitude * ROUNDOFF_REL);
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
