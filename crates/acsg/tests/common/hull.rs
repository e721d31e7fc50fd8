//! A brute-force convex hull that shares nothing with the library, convex parts built
//! from it, and a deterministic random stream for point sets.

use acsg::io::MeshSoup;
use acsg::model::Part;
use glam::DVec3;

/// Hull facets of a point set in general position, as (outward unit normal, offset,
/// indices of the points on the facet plane).
pub fn hull_facets(points: &[DVec3], eps: f64) -> Vec<(DVec3, f64, Vec<usize>)> {
    let mut facets: Vec<(DVec3, f64, Vec<usize>)> = Vec::new();
    let n = points.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let normal = (points[j] - points[i]).cross(points[k] - points[i]);
                if normal.length() < 1e-9 {
                    continue;
                }
                let normal = normal.normalize();
                let side: Vec<f64> = points.iter().map(|p| normal.dot(*p - points[i])).collect();
                let outward = if side.iter().all(|&s| s <= eps) {
                    normal
                } else if side.iter().all(|&s| s >= -eps) {
                    -normal
                } else {
                    continue;
                };
                let offset = outward.dot(points[i]);
                if facets
                    .iter()
                    .any(|(m, d, _)| m.distance(outward) < 1e-9 && (d - offset).abs() < eps)
                {
                    continue;
                }
                let on: Vec<usize> = (0..n)
                    .filter(|&q| (outward.dot(points[q]) - offset).abs() <= eps)
                    .collect();
                facets.push((outward, offset, on));
            }
        }
    }
    facets
}

/// A convex part from the hull of points in general position (triangular facets).
pub fn convex_part(points: &[DVec3], name: &str) -> Option<Part> {
    let facets = hull_facets(points, 1e-9);
    let mut polygons = Vec::new();
    for (normal, _, on) in &facets {
        if on.len() != 3 {
            return None; // not in general position
        }
        let (a, b, c) = (on[0], on[1], on[2]);
        let ccw = (points[b] - points[a]).cross(points[c] - points[a]).dot(*normal) > 0.0;
        polygons.push(if ccw {
            vec![a as u32, b as u32, c as u32]
        } else {
            vec![a as u32, c as u32, b as u32]
        });
    }
    let soup = MeshSoup {
        positions: points.to_vec(),
        polygons,
        polygon_lines: vec![],
        polygon_noun: "face",
    };
    Part::try_new(&soup, name).ok()
}

/// A deterministic xorshift stream of numbers in [0, 1).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed | 1)
    }

    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

/// `count` points around the origin, at distances between 0.6 and 1 times `radius`.
pub fn random_points(seed: u64, count: usize, radius: f64) -> Vec<DVec3> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let (u, v, r) = (
                rng.next_f64() * std::f64::consts::TAU,
                rng.next_f64() * 2.0 - 1.0,
                radius * (0.6 + 0.4 * rng.next_f64()),
            );
            let s = (1.0 - v * v).sqrt();
            DVec3::new(r * s * u.cos(), r * s * u.sin(), r * v)
        })
        .collect()
}
