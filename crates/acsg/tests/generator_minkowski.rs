//! The generator against an independent truth (docs/concepts.md#ground-truth): with translation
//! only and two convex parts, B placed at translation t (p_A = p_B + t) touches A
//! exactly when t lies on the boundary of the Minkowski difference
//! M = A ⊕ (−B) = hull{a − b}, and the contact states in a translation box are exactly
//! the faces of M whose relative interior meets the open box: facets are the single
//! f-v, v-f and e-e states, edges the degenerate e-v and v-e states, vertices the
//! degenerate v-v states.
//!
//! M is built by the brute-force hull of `common::hull`, which shares nothing with the
//! library. A face of M is mapped to its principal contact through the supporting
//! features of A and B in a direction inside the face's normal cone. Configurations
//! that are not in general position, or whose box boundary passes too close to a face,
//! are rejected and re-sampled, so that the expected set does not hang on round-off.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use acsg::contact::{ContactKind, ContactScene, PrincipalContact};
use acsg::graph::{Options, generate};
use acsg::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use acsg::pose::{Bounds, Pose};
use acsg::tolerance::{CONTACT_REL, SEPARATION_REL};
use common::hull::{Rng, convex_part, hull_facets, random_points};
use glam::{DAffine3, DVec3};

/// General position, relative to L: every point of M not on a facet lies at least this
/// far below the facet's plane, and every vertex of a part not in a supporting feature
/// at least this far behind it.
const GAP_REL: f64 = 1e-3;
/// [`GAP_REL`] for parts of 16 to 20 points.
const LARGE_GAP_REL: f64 = 2e-4;
/// The box is shrunk and grown by this (relative to L); a configuration where some face
/// of M meets the one and not the other is rejected.
const MARGIN_REL: f64 = 1e-4;
/// How far (relative to L) a witness's translation may lie off its face of M.
const WITNESS_REL: f64 = 1e-7;

/// How many pairs of parts, and boxes per pair.
const PART_SEEDS: usize = 8;
const BOXES_PER_PARTS: usize = 3;

/// One face of M.
#[derive(Clone, Debug)]
struct MFace {
    /// 2 for a facet, 1 for an edge, 0 for a vertex.
    dim: usize,
    /// Its vertices, a facet's in order around it.
    points: Vec<DVec3>,
    /// The facets of M that contain it (a facet: itself).
    facets: Vec<usize>,
    /// A unit direction inside its normal cone.
    dir: DVec3,
    /// The single principal contact of every translation in its relative interior.
    contact: PrincipalContact,
}

#[derive(Clone, Debug)]
struct Minkowski {
    /// L, the larger bounding-box diagonal of the two parts.
    scale: f64,
    /// The facets' planes (outward unit normal, offset).
    planes: Vec<(DVec3, f64)>,
    faces: Vec<MFace>,
}

struct Config {
    label: String,
    a: Part,
    b: Part,
    m: Minkowski,
    lo: DVec3,
    hi: DVec3,
    /// Indices into `m.faces` of the faces whose relative interior meets the open box.
    in_box: Vec<usize>,
}

fn mean(points: &[DVec3]) -> DVec3 {
    points.iter().copied().sum::<DVec3>() / points.len() as f64
}

/// The supporting feature of `part` in direction `sign · dir` (its vertices maximising
/// `sign · dir · p`) as an element and its dimension; `None` when a vertex outside the
/// feature comes within `gap` of it or the feature is not an element of the part.
fn feature(part: &Part, dir: DVec3, sign: f64, tiny: f64, gap: f64) -> Option<(ElementId, usize)> {
    let h: Vec<f64> = part.vertices().iter().map(|v| sign * dir.dot(v.position)).collect();
    let best = h.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut set: Vec<u32> = Vec::new();
    for (i, &x) in h.iter().enumerate() {
        if x >= best - tiny {
            set.push(i as u32);
        } else if x > best - gap {
            return None;
        }
    }
    match set.len() {
        1 => Some((ElementId::Vertex(VertexId(set[0])), 0)),
        2 => part
            .edges()
            .iter()
            .position(|e| {
                let mut ids = e.vertices.map(|v| v.0);
                ids.sort_unstable();
                ids[..] == set[..]
            })
            .map(|i| (ElementId::Edge(EdgeId(i as u32)), 1)),
        _ => part
            .faces()
            .iter()
            .position(|f| {
                let mut ids: Vec<u32> = f.loops[0].vertices.iter().map(|v| v.0).collect();
                ids.sort_unstable();
                f.loops.len() == 1 && ids == set
            })
            .map(|i| (ElementId::Face(FaceId(i as u32)), 2)),
    }
}

fn kind(dims: (usize, usize)) -> Option<ContactKind> {
    Some(match dims {
        (2, 0) => ContactKind::FaceVertex,
        (0, 2) => ContactKind::VertexFace,
        (1, 1) => ContactKind::EdgeEdge,
        (1, 0) => ContactKind::EdgeVertex,
        (0, 1) => ContactKind::VertexEdge,
        (0, 0) => ContactKind::VertexVertex,
        _ => return None,
    })
}

/// Sorts the points of a planar convex polygon around its centroid.
fn order_around(mut points: Vec<DVec3>, normal: DVec3) -> Vec<DVec3> {
    let c = mean(&points);
    let u = (points[0] - c).normalize();
    let w = normal.cross(u);
    let angle = |p: &DVec3| (*p - c).dot(w).atan2((*p - c).dot(u));
    points.sort_by(|p, q| angle(p).total_cmp(&angle(q)));
    points
}

/// The face lattice of M = hull{a − b} with each face's principal contact, or `None`
/// when the parts are not in general position.
/// The facets of the hull of `diff` = {a - b}: every facet normal of A ⊕ (−B) is a
/// facet normal of A or of B (up to sign) or the cross product of an edge of each, so
/// only those directions are tried (the brute-force hull of all differences is too slow
/// for parts of 20 points). A direction gives a facet when at least three
/// non-collinear differences reach its support value.
fn difference_facets(va: &[DVec3], vb: &[DVec3], diff: &[DVec3], tiny: f64) -> Vec<(DVec3, f64, Vec<usize>)> {
    let normals_and_edges = |points: &[DVec3]| {
        let facets = hull_facets(points, tiny);
        let normals: Vec<DVec3> = facets.iter().map(|(n, _, _)| *n).collect();
        let mut edges = Vec::new();
        for (i, (_, _, on)) in facets.iter().enumerate() {
            for (_, _, other) in &facets[i + 1..] {
                let shared: Vec<usize> = on.iter().copied().filter(|k| other.contains(k)).collect();
                if let [p, q] = shared[..] {
                    edges.push((points[q] - points[p]).normalize());
                }
            }
        }
        (normals, edges)
    };
    let (na, ea) = normals_and_edges(va);
    let (nb, eb) = normals_and_edges(vb);
    let mut directions: Vec<DVec3> = na.iter().chain(&nb).copied().collect();
    for &x in &ea {
        for &y in &eb {
            if let Some(c) = x.cross(y).try_normalize() {
                directions.push(c);
            }
        }
    }
    let mut facets: Vec<(DVec3, f64, Vec<usize>)> = Vec::new();
    for n in directions.into_iter().flat_map(|d| [d, -d]) {
        let offset = diff.iter().map(|p| n.dot(*p)).fold(f64::NEG_INFINITY, f64::max);
        let on: Vec<usize> = (0..diff.len()).filter(|&i| n.dot(diff[i]) >= offset - tiny).collect();
        let spans_plane = on.iter().any(|&i| {
            on.iter().any(|&j| {
                on.iter()
                    .any(|&k| (diff[j] - diff[i]).cross(diff[k] - diff[i]).length() > tiny)
            })
        });
        if spans_plane && !facets.iter().any(|(m, _, _)| m.distance(n) < 1e-9) {
            facets.push((n, offset, on));
        }
    }
    facets
}

fn minkowski(a: &Part, b: &Part, gap_rel: f64) -> Option<Minkowski> {
    let scale = acsg::model::length_scale(a, b);
    let (tiny, gap) = (1e-9 * scale, gap_rel * scale);
    let va: Vec<DVec3> = a.vertices().iter().map(|v| v.position).collect();
    let vb: Vec<DVec3> = b.vertices().iter().map(|v| v.position).collect();
    let diff: Vec<DVec3> = va.iter().flat_map(|&p| vb.iter().map(move |&q| p - q)).collect();
    let hull = difference_facets(&va, &vb, &diff, tiny);
    for (n, d, on) in &hull {
        if !matches!(on.len(), 3 | 4) {
            return None;
        }
        let clear = diff
            .iter()
            .enumerate()
            .all(|(i, p)| on.contains(&i) || n.dot(*p) < d - gap);
        if !clear {
            return None;
        }
    }
    let planes: Vec<(DVec3, f64)> = hull.iter().map(|(n, d, _)| (*n, *d)).collect();
    let make = |dim: usize, points: Vec<DVec3>, facets: Vec<usize>| -> Option<MFace> {
        let dir = facets.iter().map(|&k| planes[k].0).sum::<DVec3>().normalize();
        let (fixed, da) = feature(a, dir, 1.0, tiny, gap)?;
        let (moving, db) = feature(b, dir, -1.0, tiny, gap)?;
        if da + db != dim {
            return None;
        }
        Some(MFace {
            dim,
            points,
            facets,
            dir,
            contact: PrincipalContact {
                fixed,
                moving,
                kind: kind((da, db))?,
            },
        })
    };
    let mut faces = Vec::new();
    for (k, (n, _, on)) in hull.iter().enumerate() {
        let points = order_around(on.iter().map(|&i| diff[i]).collect(), *n);
        let m = points.len();
        let perimeter: f64 = (0..m).map(|i| points[i].distance(points[(i + 1) % m])).sum();
        let area: f64 = (1..m - 1)
            .map(|i| 0.5 * (points[i] - points[0]).cross(points[i + 1] - points[0]).length())
            .sum();
        if 2.0 * area / perimeter < gap {
            return None; // a sliver
        }
        faces.push(make(2, points, vec![k])?);
    }
    let mut edge_count = 0;
    for k in 0..hull.len() {
        for l in k + 1..hull.len() {
            let shared: Vec<usize> = hull[k].2.iter().filter(|i| hull[l].2.contains(i)).copied().collect();
            match shared.len() {
                0 | 1 => {}
                2 => {
                    let (p, q) = (diff[shared[0]], diff[shared[1]]);
                    if p.distance(q) < 10.0 * gap || planes[k].0.distance(planes[l].0) < gap_rel {
                        return None;
                    }
                    faces.push(make(1, vec![p, q], vec![k, l])?);
                    edge_count += 1;
                }
                _ => return None,
            }
        }
    }
    let vertices: BTreeSet<usize> = hull.iter().flat_map(|f| f.2.iter().copied()).collect();
    for &v in &vertices {
        let incident: Vec<usize> = (0..hull.len()).filter(|&k| hull[k].2.contains(&v)).collect();
        if incident.len() < 3 {
            return None;
        }
        faces.push(make(0, vec![diff[v]], incident)?);
    }
    // Euler's formula and one face per contact: the lattice is a polytope's.
    if vertices.len() + hull.len() != edge_count + 2 {
        return None;
    }
    let contacts: BTreeSet<PrincipalContact> = faces.iter().map(|f| f.contact).collect();
    if contacts.len() != faces.len() {
        return None;
    }
    Some(Minkowski { scale, planes, faces })
}

/// Sutherland–Hodgman clipping of a convex polygon (or segment, or point) by the closed
/// box [lo, hi].
fn clip(points: &[DVec3], lo: DVec3, hi: DVec3) -> Vec<DVec3> {
    let mut poly = points.to_vec();
    for axis in 0..3 {
        for (bound, sign) in [(lo[axis], 1.0), (hi[axis], -1.0)] {
            let inside = |p: DVec3| sign * (p[axis] - bound) >= 0.0;
            let mut out = Vec::new();
            for i in 0..poly.len() {
                let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
                if inside(p) {
                    out.push(p);
                }
                if inside(p) != inside(q) {
                    let s = (bound - p[axis]) / (q[axis] - p[axis]);
                    out.push(p + (q - p) * s);
                }
            }
            poly = out;
            if poly.is_empty() {
                return poly;
            }
        }
    }
    poly
}

/// Whether the relative interior of `face` meets the open box (lo, hi): `None` when the
/// answer changes as the box shrinks or grows by `margin`.
fn meets(face: &MFace, lo: DVec3, hi: DVec3, margin: f64) -> Option<bool> {
    let shrunk = !clip(&face.points, lo + margin, hi - margin).is_empty();
    let grown = !clip(&face.points, lo - margin, hi + margin).is_empty();
    (shrunk == grown).then_some(shrunk)
}

/// How far `t`, a point of `face`, lies from the face's relative boundary (0 for a
/// vertex).
fn depth(face: &MFace, t: DVec3) -> f64 {
    let n = face.points.len();
    match face.dim {
        0 => 0.0,
        1 => t.distance(face.points[0]).min(t.distance(face.points[1])),
        _ => (0..n)
            .map(|i| {
                let (p, q) = (face.points[i], face.points[(i + 1) % n]);
                let (e, d) = ((q - p).normalize(), t - p);
                (d - e * d.dot(e)).length()
            })
            .fold(f64::INFINITY, f64::min),
    }
}

/// A translation in the relative interior of `face`, at least `margin / 2` inside the
/// box and as deep in the face as a few candidates allow, for a face that meets the box
/// shrunk by `margin`.
fn point_inside(face: &MFace, lo: DVec3, hi: DVec3, margin: f64) -> DVec3 {
    let clipped = clip(&face.points, lo + margin, hi - margin);
    let centre = mean(&clipped);
    let mut candidates = vec![centre];
    for &p in &clipped {
        candidates.extend(clipped.iter().map(|&q| (p + q + centre) / 3.0));
    }
    // Towards the face's centroid: off the face's boundary even when the clipped piece
    // lies on it.
    let towards = mean(&face.points) - centre;
    let len = towards.length();
    if len > 0.0 {
        candidates.push(centre + towards * (0.5 * margin / len).min(1.0));
    }
    candidates
        .into_iter()
        .max_by(|p, q| depth(face, *p).total_cmp(&depth(face, *q)))
        .expect("a candidate")
}

/// How many random points span each part, and how many faces each hull must have.
struct Sizes {
    points: (usize, usize),
    /// The general-position gap (relative to L): many points make near-degenerate
    /// differences likely, so large parts are accepted with a smaller gap.
    gap_rel: f64,
    faces: (std::ops::RangeInclusive<usize>, std::ops::RangeInclusive<usize>),
}

/// Small parts: 8 and 7 points (at most 12 and 10 faces).
fn small() -> Sizes {
    Sizes {
        points: (8, 7),
        gap_rel: GAP_REL,
        faces: (4..=usize::MAX, 4..=usize::MAX),
    }
}

/// The contact module compares convex pieces of more than 24 faces through their
/// Gauss maps, and a large piece against a small one by plain SAT: both paths.
const LARGE_PIECE: usize = 25;

/// The configurations: `part_seeds` pairs of random convex parts of the given sizes,
/// each with `BOXES_PER_PARTS` random translation boxes across the boundary of M.
fn configurations_of(sizes: Sizes, part_seeds: usize) -> Vec<Config> {
    let mut configs = Vec::new();
    let mut parts_found = 0;
    for s in 1u64.. {
        if parts_found == part_seeds {
            break;
        }
        assert!(s < 400, "too few configurations in general position");
        let seed = s.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let pa = random_points(seed, sizes.points.0, 1.0);
        let pb = random_points(seed.rotate_left(17) ^ 0x5555, sizes.points.1, 0.7);
        let (Some(a), Some(b)) = (convex_part(&pa, "A"), convex_part(&pb, "B")) else {
            continue;
        };
        if !sizes.faces.0.contains(&a.faces().len()) || !sizes.faces.1.contains(&b.faces().len()) {
            continue;
        }
        let Some(m) = minkowski(&a, &b, sizes.gap_rel) else {
            continue;
        };
        let margin = MARGIN_REL * m.scale;
        let mut rng = Rng::new(seed ^ 0xABCD_EF01);
        let mut boxes = Vec::new();
        for _ in 0..200 {
            if boxes.len() == BOXES_PER_PARTS {
                break;
            }
            // Around a random point of a random facet.
            let facets: Vec<&MFace> = m.faces.iter().filter(|f| f.dim == 2).collect();
            let facet = facets[(rng.next_f64() * facets.len() as f64) as usize];
            let weights: Vec<f64> = facet.points.iter().map(|_| rng.range(0.1, 1.0)).collect();
            let total: f64 = weights.iter().sum();
            let on: DVec3 = facet.points.iter().zip(&weights).map(|(p, w)| *p * (w / total)).sum();
            let centre = on + DVec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
            let half = DVec3::new(rng.range(0.15, 0.7), rng.range(0.15, 0.7), rng.range(0.15, 0.7));
            let (lo, hi) = (centre - half, centre + half);
            let Some(hits) = m
                .faces
                .iter()
                .map(|f| meets(f, lo, hi, margin))
                .collect::<Option<Vec<bool>>>()
            else {
                continue;
            };
            let in_box: Vec<usize> = (0..hits.len()).filter(|&i| hits[i]).collect();
            let facets_in = in_box.iter().filter(|&&i| m.faces[i].dim == 2).count();
            if facets_in < 3 || in_box.len() == m.faces.len() {
                continue;
            }
            boxes.push((lo, hi, in_box));
        }
        if boxes.len() < BOXES_PER_PARTS {
            continue;
        }
        parts_found += 1;
        for (j, (lo, hi, in_box)) in boxes.into_iter().enumerate() {
            configs.push(Config {
                label: format!("parts seed {s}, box {j}: [{lo:.4?}, {hi:.4?}]"),
                a: a.clone(),
                b: b.clone(),
                m: m.clone(),
                lo,
                hi,
                in_box,
            });
        }
    }
    configs
}

fn configurations() -> Vec<Config> {
    configurations_of(small(), PART_SEEDS)
}

fn describe(contacts: &[PrincipalContact]) -> String {
    let one = |c: &PrincipalContact| format!("{} A:{:?} B:{:?}", c.kind, c.fixed, c.moving);
    contacts.iter().map(one).collect::<Vec<_>>().join(" + ")
}

/// Checks the truth builder on its own, against the contact module: at a translation
/// inside each face of M (inside the box when the face meets it) the contact state is
/// the face's single contact with no penetration, and (inside the box) every other
/// pair of elements is clear as a witness requires (docs/concepts.md#tolerances); stepping out
/// of M along the face's normal cone leaves no contact, stepping in penetrates.
#[test]
fn minkowski_faces_predict_the_contact_state() {
    let configs = configurations();
    assert_eq!(configs.len(), PART_SEEDS * BOXES_PER_PARTS);
    for config in &configs {
        let m = &config.m;
        let scene = ContactScene::new(&config.a, &config.b);
        assert_eq!(scene.scale(), m.scale);
        let margin = MARGIN_REL * m.scale;
        let counts = [0, 1, 2].map(|d| m.faces.iter().filter(|f| f.dim == d).count());
        assert!(counts[2] >= 12 && counts[1] >= 18 && counts[0] >= 8, "{counts:?}");
        let in_box = [0, 1, 2].map(|d| config.in_box.iter().filter(|&&i| m.faces[i].dim == d).count());
        eprintln!(
            "{}: M has {counts:?} vertices/edges/facets, {in_box:?} meet the box",
            config.label
        );
        for (i, face) in m.faces.iter().enumerate() {
            let t = if config.in_box.contains(&i) {
                let t = point_inside(face, config.lo, config.hi, margin);
                let clear = (t - config.lo).min_element().min((config.hi - t).min_element());
                assert!(clear > 0.25 * margin, "{}: {t} not inside the box", config.label);
                t
            } else {
                mean(&face.points)
            };
            let at = |t: DVec3| scene.state(&DAffine3::from_translation(t), CONTACT_REL);
            let report = scene.evaluate(&DAffine3::from_translation(t), CONTACT_REL);
            if config.in_box.contains(&i) {
                // A witness by section 7's standard: every other pair is clear.
                assert!(
                    report.min_gap.is_none_or(|g| g >= SEPARATION_REL * m.scale),
                    "{}: face {i} at {t}: min gap {:?}",
                    config.label,
                    report.min_gap
                );
            }
            assert_eq!(
                report.contacts,
                vec![face.contact],
                "{}: face {i} ({face:?}) at {t}: got {}",
                config.label,
                describe(&report.contacts)
            );
            assert_eq!(report.penetration, 0.0, "{}: face {i} at {t}", config.label);
            let step = 1e-3 * m.scale;
            let outside = at(t + face.dir * step);
            assert!(
                outside.contacts.is_empty() && outside.penetration == 0.0,
                "{}: outside face {i}: {outside:?}",
                config.label
            );
            // Towards M's centre: into M whatever the face (-dir can leave M at a sharp
            // vertex).
            let centre = mean(
                &m.faces
                    .iter()
                    .filter(|f| f.dim == 0)
                    .flat_map(|f| f.points.clone())
                    .collect::<Vec<_>>(),
            );
            let inside = at(t + (centre - t).normalize() * step);
            assert!(
                inside.penetration > 0.0,
                "{}: inside face {i}: {inside:?}",
                config.label
            );
        }
    }
}

/// Whether a witness's translation lies on `face` of M: on the planes of the facets
/// that contain the face and inside (or on) every other facet's plane.
fn witness_problem(m: &Minkowski, face: &MFace, bounds: &Bounds, pose: &Pose) -> Option<String> {
    let tol = WITNESS_REL * m.scale;
    if !bounds.contains(pose, CONTACT_REL * m.scale, 0.0) {
        return Some(format!("witness {pose:?} outside the bounds"));
    }
    let t = pose.translation();
    for (k, (n, d)) in m.planes.iter().enumerate() {
        let h = n.dot(t) - d;
        if h > tol || (face.facets.contains(&k) && h < -tol) {
            return Some(format!(
                "witness translation {t} is {h:.3e} from the plane of M's facet {k} ({})",
                if face.facets.contains(&k) {
                    "one of its face's"
                } else {
                    "another"
                }
            ));
        }
    }
    None
}

#[test]
fn generator_states_are_the_faces_of_the_minkowski_difference() {
    check_generator(&configurations(), &[false]);
}

/// Parts of more than 24 faces: a large part against a small one (plain SAT with the
/// large piece's axes) and two large parts (Gauss maps), in both roles.
#[test]
fn large_parts_give_the_faces_of_the_minkowski_difference() {
    let (large, small) = (LARGE_PIECE..=usize::MAX, 4..=LARGE_PIECE - 1);
    let mut configs = Vec::new();
    for sizes in [
        Sizes {
            points: (16, 7),
            gap_rel: LARGE_GAP_REL,
            faces: (large.clone(), small.clone()),
        },
        Sizes {
            points: (7, 16),
            gap_rel: LARGE_GAP_REL,
            faces: (small, large.clone()),
        },
        Sizes {
            points: (16, 16),
            gap_rel: LARGE_GAP_REL,
            faces: (large.clone(), large),
        },
    ] {
        configs.extend(configurations_of(sizes, 2));
    }
    check_generator(&configs, &[false]);
}

/// With degenerate states kept, the edges and vertices of M must appear too.
#[test]
fn with_degenerate_states_the_edges_and_vertices_of_the_minkowski_difference_appear_too() {
    check_generator(&configurations(), &[true]);
}

/// Runs the generator on every configuration, with each `degenerate` setting given.
fn check_generator(configs: &[Config], settings: &[bool]) {
    let mut failures = Vec::new();
    for config in configs {
        let m = &config.m;
        let (lo, hi) = (config.lo, config.hi);
        let bounds = Bounds::try_new([lo.x, lo.y, lo.z, 0.0, 0.0, 0.0], [hi.x, hi.y, hi.z, 0.0, 0.0, 0.0])
            .expect("valid bounds");
        for &degenerate in settings {
            let label = format!("{} degenerate={degenerate}", config.label);
            let options = Options {
                degenerate,
                ..Options::default()
            };
            let start = Instant::now();
            let graph = generate(&config.a, &config.b, &bounds, &options);
            eprintln!(
                "{label}: {} states, {} edges in {:.2?}",
                graph.states.len(),
                graph.edges.len(),
                start.elapsed()
            );
            let expected: BTreeMap<Vec<PrincipalContact>, &MFace> = config
                .in_box
                .iter()
                .map(|&i| &m.faces[i])
                .filter(|f| degenerate || f.dim == 2)
                .map(|f| (vec![f.contact], f))
                .collect();
            let mut problems = Vec::new();
            match graph.states.first() {
                None => problems.push("no root state".to_string()),
                Some(root) if !root.contacts.is_empty() => {
                    problems.push(format!("state 0 is not the root: {}", describe(&root.contacts)));
                }
                Some(root) => {
                    if let Some(pose) = &root.witness {
                        let t = pose.translation();
                        let out = m
                            .planes
                            .iter()
                            .map(|(n, d)| n.dot(t) - d)
                            .fold(f64::NEG_INFINITY, f64::max);
                        if out <= 0.0 || !bounds.contains(pose, CONTACT_REL * m.scale, 0.0) {
                            problems.push(format!("root witness {pose:?} not free or not in the bounds"));
                        }
                    }
                }
            }
            let mut got: BTreeMap<Vec<PrincipalContact>, usize> = BTreeMap::new();
            for state in graph.states.iter().skip(1) {
                let mut contacts = state.contacts.clone();
                contacts.sort();
                if got.insert(contacts.clone(), state.id).is_some() {
                    problems.push(format!("duplicate state {}: {}", state.id, describe(&contacts)));
                }
                let Some(face) = expected.get(&contacts) else {
                    problems.push(format!(
                        "extra state {}: {} (witness {:?})",
                        state.id,
                        describe(&contacts),
                        state.witness
                    ));
                    continue;
                };
                if state.degenerate != (face.dim < 2) {
                    problems.push(format!(
                        "state {} ({}): degenerate flag {}",
                        state.id,
                        describe(&contacts),
                        state.degenerate
                    ));
                }
                match &state.witness {
                    None => problems.push(format!("state {} ({}): no witness", state.id, describe(&contacts))),
                    Some(pose) => {
                        if let Some(problem) = witness_problem(m, face, &bounds, pose) {
                            problems.push(format!("state {} ({}): {problem}", state.id, describe(&contacts)));
                        }
                    }
                }
            }
            for (contacts, face) in &expected {
                if !got.contains_key(contacts) {
                    let t = point_inside(face, lo, hi, MARGIN_REL * m.scale);
                    let clear = (t - lo).min_element().min((hi - t).min_element());
                    problems.push(format!(
                        "missing state: {} ({} of M, centroid {:.4}; holds at translation {:.6}, \
                         {:.1e} L from the face's boundary and {:.1e} L inside the box)",
                        describe(contacts),
                        ["a vertex", "an edge", "a facet"][face.dim],
                        mean(&face.points),
                        t,
                        depth(face, t) / m.scale,
                        clear / m.scale
                    ));
                }
            }
            let ids: BTreeSet<usize> = graph.states.iter().map(|s| s.id).collect();
            for edge in &graph.edges {
                if !edge.iter().all(|i| ids.contains(i)) || edge[0] == edge[1] {
                    problems.push(format!("bad graph edge {edge:?}"));
                }
            }
            if !problems.is_empty() {
                failures.push(format!(
                    "{label}: expected {} states, got {}:\n  {}",
                    expected.len(),
                    graph.states.len().saturating_sub(1),
                    problems.join("\n  ")
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
