//! Inside or outside a closed surface: the generalised winding number.

use glam::DVec3;

/// The generalised winding number of `q` with respect to the closed surface made of
/// `triangles` (outward winding): 1 inside, 0 outside (Van Oosterom–Strackee solid
/// angles).
pub(crate) fn winding_number(triangles: impl Iterator<Item = [DVec3; 3]>, q: DVec3) -> f64 {
    let total: f64 = triangles
        .map(|corners| {
            let [a, b, c] = corners.map(|p| p - q);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}
