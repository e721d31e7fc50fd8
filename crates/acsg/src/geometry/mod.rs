//! Geometry shared by the whole crate, knowing nothing of parts or contacts: boxes,
//! convex polytopes, distances between points, segments and planar regions, planar
//! polygons, welding of nearby points, winding numbers. Every other module may use it; it uses only
//! [`crate::tolerance`].

mod aabb;
mod distance;
mod plane;
mod polytope;
mod weld;
mod winding;

pub use aabb::Aabb;
pub use polytope::{ConvexFace, ConvexPolytope};

pub(crate) use distance::{
    PlanarRegion, Segment, point_region, point_segment, region_region, segment_region, segment_segment,
};
pub(crate) use plane::{hull_in_plane, newell, plane_basis, shoelace};
pub(crate) use polytope::{clip_convex, clip_polygon};
pub(crate) use weld::weld;
pub(crate) use winding::winding_number;
