//! CAD inputs: the same part from STEP, IGES (both forms) and OFF gives the same B-rep
//! and the same card(PPC); curved or unsupported entities, truncated files and wrong
//! units are refused with a message naming the entity and the fix.

use std::path::{Path, PathBuf};

use acsg::io::{ReadError, read_bytes};
use acsg::model::{Part, ppc_count};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

fn text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn load(name: &str) -> Part {
    Part::from_path(&fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Reads `content` as if it were the file `name`.
fn part_of(content: &str, name: &str) -> Result<Part, String> {
    let soup = read_bytes(content.as_bytes(), Path::new(name)).map_err(|e| e.to_string())?;
    Part::try_new(&soup, name).map_err(|e| e.to_string())
}

fn error_of(content: &str, name: &str) -> String {
    match read_bytes(content.as_bytes(), Path::new(name)) {
        Ok(soup) => panic!("{name}: expected an error, read {} polygons", soup.polygons.len()),
        Err(e) => e.to_string(),
    }
}

/// (faces, faces with holes, vertices, convex vertices, edges, convex edges)
fn counts(p: &Part) -> (usize, usize, usize, usize, usize, usize) {
    (
        p.faces().len(),
        p.faces().iter().filter(|f| f.loops.len() > 1).count(),
        p.vertices().len(),
        p.convex_vertices().count(),
        p.edges().len(),
        p.convex_edges().count(),
    )
}

/// Vertex positions in canonical order (micrometre grid) and sorted face planes.
fn geometry(p: &Part) -> (Vec<[i64; 3]>, Vec<[i64; 4]>) {
    let q = |x: f64| (x * 1e3).round() as i64;
    let vs: Vec<_> = p.vertices().iter().map(|v| v.position.to_array().map(q)).collect();
    let mut fs: Vec<_> = p
        .faces()
        .iter()
        .map(|f| [q(f.normal.x), q(f.normal.y), q(f.normal.z), q(f.offset)])
        .collect();
    fs.sort_unstable();
    (vs, fs)
}

const FORMS: [&str; 3] = [".step", ".igs", "_faces.igs"];

#[test]
fn step_iges_and_off_give_the_same_part() {
    for (name, expected, volume) in [
        ("l_block", (8, 0, 12, 10, 18, 17), 1_500_000.0),
        ("block_with_hole", (10, 2, 16, 8, 24, 20), 455_000.0),
        ("peg", (6, 0, 8, 8, 12, 12), 62_720.0),
    ] {
        let reference = load(&format!("{name}.off"));
        assert_eq!(counts(&reference), expected, "{name}.off");
        for form in FORMS {
            let file = format!("cad/{name}{form}");
            let part = load(&file);
            assert_eq!(counts(&part), expected, "{file}");
            assert!(
                (part.volume() - volume).abs() < 1e-6 * volume,
                "{file}: {}",
                part.volume()
            );
            assert_eq!(geometry(&part), geometry(&reference), "{file} differs in geometry");
            // Canonical numbering: the same vertices and edges in the same order.
            assert_eq!(part.edges(), reference.edges(), "{file} numbering");
            for (a, b) in part.vertices().iter().zip(reference.vertices()) {
                assert!(a.position.distance(b.position) < 1e-9, "{file}: {a:?} vs {b:?}");
            }
        }
    }
}

#[test]
fn the_same_card_ppc_against_a_second_part() {
    let pairs = [("l_block", "box.off"), ("block_with_hole", "peg.off")];
    for (a, b) in pairs {
        let moving = load(b);
        let reference = ppc_count(&load(&format!("{a}.off")), &moving);
        for form in FORMS {
            let fixed = load(&format!("cad/{a}{form}"));
            assert_eq!(ppc_count(&fixed, &moving), reference, "{a}{form} x {b}");
        }
    }
    let hole = load("block_with_hole.off");
    let reference = ppc_count(&hole, &load("peg.off"));
    for form in FORMS {
        let peg = load(&format!("cad/peg{form}"));
        assert_eq!(ppc_count(&hole, &peg), reference, "block_with_hole.off x peg{form}");
        let cad_hole = load(&format!("cad/block_with_hole{form}"));
        assert_eq!(ppc_count(&cad_hole, &peg), reference, "both from {form}");
    }
}

#[test]
fn inch_files_come_out_in_millimetres() {
    let reference = geometry(&load("peg.off"));
    for name in ["cad/peg_inch.step", "cad/peg_inch.igs"] {
        assert_eq!(geometry(&load(name)), reference, "{name}");
    }
}

#[test]
fn a_mislabelled_file_reads_as_what_it_is() {
    let reference = geometry(&load("peg.off"));
    for (content, label) in [
        ("cad/peg.step", "peg.igs"),
        ("cad/peg.igs", "peg.step"),
        ("cad/peg_faces.igs", "peg.off"),
        ("peg.off", "peg.step"),
    ] {
        let part = part_of(&text(content), label).unwrap_or_else(|e| panic!("{content} as {label}: {e}"));
        assert_eq!(geometry(&part), reference, "{content} as {label}");
    }
    // Content that is neither: the extension decides and the message says what it wanted.
    let e = error_of("hello, world\n", "part.step");
    assert!(e.contains("STEP") && e.contains("ISO-10303-21"), "{e}");
    let e = error_of("hello, world\n", "part.igs");
    assert!(e.contains("IGES") && e.contains("column"), "{e}");
    let e = error_of("hello, world\n", "part.xyz");
    assert!(e.contains(".step") && e.contains(".igs"), "{e}");
}

// ---------------------------------------------------------------- STEP refusals

#[test]
fn step_refuses_curved_surfaces_and_edges_by_instance() {
    let peg = text("cad/peg.step");
    assert!(peg.contains("#32 = PLANE('',#33);") && peg.contains("#27 = LINE('',#28,#29);"));
    let curved = peg.replace("#32 = PLANE('',#33);", "#32 = CYLINDRICAL_SURFACE('',#33,5.);");
    let e = error_of(&curved, "peg.step");
    assert!(
        e.contains("#32 CYLINDRICAL_SURFACE is curved") && e.contains("planar"),
        "{e}"
    );

    let circle = peg.replace("#27 = LINE('',#28,#29);", "#27 = CIRCLE('',#33,5.);");
    let e = error_of(&circle, "peg.step");
    assert!(e.contains("#27 CIRCLE is curved") && e.contains("faceted"), "{e}");

    // A B-spline edge is read as a line when its control points are collinear, and
    // refused by name when they are not (the edge #21 runs from (36,36,10) to (36,36,90)).
    let spline = |middle: &str| {
        peg.replace(
            "#27 = LINE('',#28,#29);",
            "#27 = B_SPLINE_CURVE_WITH_KNOTS('',2,(#28,#900,#25),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),\
             .UNSPECIFIED.);",
        )
        .replace(
            "ENDSEC;\nEND-ISO",
            &format!("#900 = CARTESIAN_POINT('',({middle}));\nENDSEC;\nEND-ISO"),
        )
    };
    let straight = part_of(&spline("36.,36.,50."), "peg.step").expect("a collinear B-spline edge reads");
    assert_eq!(geometry(&straight), geometry(&load("cad/peg.step")));
    let e = error_of(&spline("40.,36.,50."), "peg.step");
    assert!(
        e.contains("#27 B_SPLINE_CURVE_WITH_KNOTS is curved: its points lie up to") && e.contains("straight"),
        "{e}"
    );

    let unknown = peg.replace("#19 = EDGE_LOOP('',", "#19 = VERTEX_LOOP('',");
    let e = error_of(&unknown, "peg.step");
    assert!(
        e.contains("#19 VERTEX_LOOP is not supported") && e.contains("EDGE_LOOP"),
        "{e}"
    );

    let voids = peg.replacen("MANIFOLD_SOLID_BREP('',#16)", "BREP_WITH_VOIDS('',#16,())", 1);
    let e = error_of(&voids, "peg.step");
    assert!(e.contains("BREP_WITH_VOIDS") && e.contains("voids"), "{e}");
}

#[test]
fn step_refuses_truncated_and_damaged_files() {
    let peg = text("cad/peg.step");
    let e = error_of(&peg[..peg.len() / 2], "peg.step");
    assert!(e.contains("truncated"), "{e}");
    let e = error_of(&peg[..peg.find("DATA;").unwrap_or(0)], "peg.step");
    assert!(e.contains("no DATA section"), "{e}");
    let broken = peg.replace("#23 = CARTESIAN_POINT", "#23 = CARTESIAN_POINT_X");
    let e = error_of(&broken, "peg.step");
    assert!(e.contains("#23 CARTESIAN_POINT_X"), "{e}");
    let dangling = peg.replace("#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#99999);");
    let e = error_of(&dangling, "peg.step");
    assert!(e.contains("#99999 does not exist"), "{e}");
}

#[test]
fn step_units_convert_or_are_refused() {
    let peg = text("cad/peg.step");
    let mm = "SI_UNIT(.MILLI.,.METRE.)";
    assert_eq!(peg.matches(mm).count(), 1);
    let metres = part_of(&peg.replace(mm, "SI_UNIT($,.METRE.)"), "peg.step").expect("metres read");
    let b = metres.bounds();
    assert!(
        (b.min.x - 36_000.0).abs() < 1e-6 && (b.max.z - 90_000.0).abs() < 1e-6,
        "{b:?}"
    );

    let e = error_of(&peg.replace(mm, "SI_UNIT(.MILLI.,.GRAM.)"), "peg.step");
    assert!(e.contains("GRAM") && e.contains("not a length"), "{e}");
    let e = error_of(&peg.replace(mm, "SI_UNIT(.EXA.,.METRE.)"), "peg.step");
    assert!(e.contains("EXA"), "{e}");
    let e = error_of(&peg.replace("LENGTH_UNIT()", ""), "peg.step");
    assert!(e.contains("no length unit"), "{e}");
}

// ---------------------------------------------------------------- IGES refusals

/// Changes the type of the entity at directory entry `de` in both sections.
fn retype(iges: &str, de: usize, from: u32, to: u32) -> String {
    let number =
        |line: &str, range: std::ops::Range<usize>| line.get(range).and_then(|s| s.trim().parse::<usize>().ok());
    iges.lines()
        .map(|line| {
            let section = line.get(72..73);
            let seq = number(line, 73..80);
            if section == Some("D") && (seq == Some(de) || seq == Some(de + 1)) {
                format!("{to:8}{}", &line[8..])
            } else if section == Some("P") && number(line, 64..72) == Some(de) && line.starts_with(&format!("{from},"))
            {
                let body = format!("{to},{}", &line[format!("{from},").len()..64]);
                format!("{body:<64.64}{}", &line[64..])
            } else {
                line.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// The DE number of the first entity of type `kind`.
fn first_de(iges: &str, kind: u32) -> usize {
    iges.lines()
        .find(|l| l.get(72..73) == Some("D") && l.get(0..8).and_then(|s| s.trim().parse().ok()) == Some(kind))
        .and_then(|l| l.get(73..80)?.trim().parse().ok())
        .unwrap_or_else(|| panic!("no entity {kind}"))
}

#[test]
fn iges_refuses_curved_and_unsupported_entities_by_type_and_de() {
    for file in ["cad/peg.igs", "cad/peg_faces.igs"] {
        let peg = text(file);
        let plane = if file.contains("faces") { 108 } else { 190 };
        let de = first_de(&peg, plane);
        // A plane's parameters read as a B-spline surface's: a damaged 128, named.
        let e = error_of(&retype(&peg, de, plane, 128), file);
        assert!(
            e.contains(&format!("entity 128 (rational B-spline surface) at DE {de}")),
            "{file}: {e}"
        );
        let de = first_de(&peg, 110);
        let e = error_of(&retype(&peg, de, 110, 100), file);
        assert!(
            e.contains(&format!("entity 100 (circular arc) at DE {de} is curved")) && e.contains("faceted"),
            "{file}: {e}"
        );
        let e = error_of(&retype(&peg, de, 110, 106), file);
        assert!(
            e.contains(&format!("entity 106 (copious data (polyline)) at DE {de} is outside")),
            "{file}: {e}"
        );
    }
    // A surface of revolution anywhere in the file is refused even if no face uses it.
    let peg = text("cad/peg.igs");
    let de = first_de(&peg, 110);
    let e = error_of(&retype(&peg, de, 110, 120), "peg.igs");
    assert!(
        e.contains(&format!("entity 120 (surface of revolution) at DE {de}")),
        "{e}"
    );
}

#[test]
fn iges_refuses_voids_and_transformed_entities() {
    let peg = text("cad/peg.igs");
    let solid = "186,3,1,0;      ";
    assert_eq!(peg.matches(solid).count(), 1);
    let e = error_of(&peg.replace(solid, "186,3,1,1,3,1;  "), "peg.igs");
    assert!(e.contains("DE 1") && e.contains("1 void shell"), "{e}");
    let de = "     186       1       0       0       0       0       0       000000000D0000001";
    assert_eq!(peg.matches(de).count(), 1);
    let moved = de.replacen("       0       000000000D", "      99       000000000D", 1);
    let e = error_of(&peg.replace(de, &moved), "peg.igs");
    assert!(e.contains("transformation matrix (entity 124, DE 99)"), "{e}");
}

#[test]
fn iges_refuses_truncated_and_damaged_files() {
    let peg = text("cad/peg.igs");
    let e = error_of(&peg[..peg.len() / 2], "peg.igs");
    assert!(e.contains("truncated"), "{e}");
    let whole_lines: String = peg.lines().take(40).map(|l| format!("{l}\n")).collect();
    let e = error_of(&whole_lines, "peg.igs");
    assert!(e.contains("truncated"), "{e}");
    // Without the last P lines (keeping the T record): a pointer past the end.
    let mut lines: Vec<&str> = peg.lines().collect();
    let t = lines.pop().unwrap_or_default();
    lines.truncate(lines.len() - 5);
    lines.push(t);
    let e = error_of(&(lines.join("\n") + "\n"), "peg.igs");
    assert!(e.contains("truncated") || e.contains("does not exist"), "{e}");
    let garbage: String = (0..50).map(|k| format!("{:<72}S{k:7}\n", "#$%^&*")).collect();
    assert!(error_of(&garbage, "junk.igs").contains("IGES"));
}

#[test]
fn iges_units_convert_or_are_refused() {
    let peg = text("cad/peg.igs");
    let mm = ",1.,2,2HMM,";
    assert_eq!(peg.matches(mm).count(), 1, "the unit fields of the fixture");
    let metres = part_of(&peg.replace(mm, ",1.,6,1HM, "), "peg.igs").expect("metres read");
    let b = metres.bounds();
    assert!(
        (b.min.x - 36_000.0).abs() < 1e-6 && (b.max.z - 90_000.0).abs() < 1e-6,
        "{b:?}"
    );
    let scaled = part_of(&peg.replace(mm, ",2.,2,2HMM,"), "peg.igs").expect("scale 2 reads");
    assert!((scaled.bounds().max.z - 45.0).abs() < 1e-9);

    let e = error_of(&peg.replace(mm, ",1.,1,2HMM,"), "peg.igs");
    assert!(e.contains("says inch") && e.contains("`MM`"), "{e}");
    let e = error_of(&peg.replace(mm, ",1.,3,2HXX,"), "peg.igs");
    assert!(e.contains("`XX` is not a unit"), "{e}");
    let e = error_of(&peg.replace(mm, ",1.,42,1HM,"), "peg.igs");
    assert!(e.contains("unit flag") && e.contains("42"), "{e}");
    let e = error_of(&peg.replace(mm, ",0.,2,2HMM,"), "peg.igs");
    assert!(e.contains("model space scale"), "{e}");
}

#[test]
fn read_errors_name_the_file() {
    let e = match acsg::io::read_path(&fixture("cad/missing.step")) {
        Err(e @ ReadError::Io { .. }) => e.to_string(),
        other => panic!("{other:?}"),
    };
    assert!(e.contains("missing.step"), "{e}");
}

/// The chamfered peg of `scripts/make_cad_fixtures.py`: its chamfers are degree (1,1)
/// B-spline surfaces with four coplanar control points (one rational, as a complex
/// STEP instance; IGES 128), the edges around them degree-1 B-spline curves (IGES 126)
/// and one trimmed line. Both files give the solid the script describes, checked
/// against numbers worked out by hand: the peg 28 x 28 x 80 less the bottom 2 mm's
/// frame, a 28 x 28 to 24 x 24 frustum replacing a 28 x 28 x 2 slab.
#[test]
fn planar_b_spline_faces_and_straight_spline_edges_read_as_planes_and_lines() {
    let step = load("cad/chamfered_peg.step");
    let iges = load("cad/chamfered_peg.igs");
    let frustum = 2.0 / 3.0 * (24.0 * 24.0 + 28.0 * 28.0 + 24.0 * 28.0);
    let volume = 28.0 * 28.0 * 80.0 - 28.0 * 28.0 * 2.0 + frustum;
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut expected: Vec<[i64; 3]> = [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [s, 0.0, -s],
        [-s, 0.0, -s],
        [0.0, s, -s],
        [0.0, -s, -s],
    ]
    .iter()
    .map(|n| n.map(|x| (x * 1e3).round() as i64))
    .collect();
    expected.sort_unstable();
    for part in [&step, &iges] {
        assert_eq!(counts(part), (10, 0, 12, 12, 20, 20));
        assert!((part.volume() - volume).abs() < 1e-6, "{} vs {volume}", part.volume());
        let mut normals: Vec<[i64; 3]> = geometry(part).1.iter().map(|f| [f[0], f[1], f[2]]).collect();
        normals.sort_unstable();
        assert_eq!(normals, expected);
    }
    assert_eq!(geometry(&step), geometry(&iges));
}

#[test]
fn curved_b_spline_surfaces_are_refused_by_name() {
    // STEP: move one control point of the chamfer #225 by 1 mm off its plane.
    let step = text("cad/chamfered_peg.step");
    let point = step
        .lines()
        .find(|l| l.starts_with("#225 = B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#221,#224),(#222,#223))"))
        .map(|_| "#223 = CARTESIAN_POINT('',(64.,64.,12.));")
        .expect("the fixture's chamfer #225");
    assert!(step.contains(point), "the fixture changed: update this test");
    let bent = step.replace(point, "#223 = CARTESIAN_POINT('',(64.,64.,13.));");
    let e = error_of(&bent, "chamfered_peg.step");
    assert!(
        e.contains("#225 B_SPLINE_SURFACE_WITH_KNOTS is curved: its control points lie up to") && e.contains("planar"),
        "{e}"
    );
    // IGES: the same for the first 128 (its third control point, (36, 36, 12)).
    let iges = text("cad/chamfered_peg.igs");
    let de = first_de(&iges, 128);
    let line = "\n12.,64.,36.,12.,0.,24.,0.,";
    assert!(iges.contains(line), "the fixture changed: update this test");
    let e = error_of(
        &iges.replacen(line, "\n13.,64.,36.,12.,0.,24.,0.,", 1),
        "chamfered_peg.igs",
    );
    assert!(
        e.contains(&format!(
            "entity 128 (rational B-spline surface) at DE {de} is curved: its control points"
        )) && e.contains("planar"),
        "{e}"
    );
}

fn faceted(name: &str, facet_mm: f64) -> Result<Part, String> {
    Part::from_path_with(&fixture(name), None, Some(facet_mm))
        .map(|(part, _)| part)
        .map_err(|e| e.to_string())
}

/// With a chord tolerance, the STEP round peg (a true cylinder) and the block with a
/// round hole (a cylinder, then a cone) become the 32-sided prisms that
/// scripts/make_fixtures.py wrote independently as OFF (60-digit arithmetic): same
/// counts, same vertices, same face planes.
#[test]
fn faceted_cylinders_and_cones_match_the_polygonal_fixtures() {
    for (step, off) in [
        ("cad/round_peg.step", "round_peg.off"),
        ("cad/block_with_round_hole.step", "block_with_round_hole.off"),
    ] {
        // 0.1 mm: 32 sides for both files (16 would stray 0.27 and 0.35 mm).
        let part = faceted(step, 0.1).unwrap_or_else(|e| panic!("{e}"));
        let mesh = load(off);
        assert_eq!(counts(&part), counts(&mesh), "{step}");
        assert_eq!(geometry(&part), geometry(&mesh), "{step}");
        assert!((part.volume() - mesh.volume()).abs() < 1e-6 * mesh.volume(), "{step}");
    }
    // A coarser tolerance: the fewest sides (a power of two) whose chord strays at most
    // that far, r (1 - cos(pi / n)) <= 0.3 for r = 14: n = 16; the prism's volume is
    // (n / 2) r^2 sin(2 pi / n) times the height.
    let peg = faceted("cad/round_peg.step", 0.3).unwrap();
    let n = 16.0_f64;
    assert!(14.0 * (1.0 - (std::f64::consts::PI / n).cos()) <= 0.3);
    assert!(14.0 * (1.0 - (std::f64::consts::PI / (n / 2.0)).cos()) > 0.3);
    assert_eq!(peg.faces().len(), 2 + 16);
    let volume = n / 2.0 * 14.0 * 14.0 * (std::f64::consts::TAU / n).sin() * 80.0;
    assert!(
        (peg.volume() - volume).abs() < 1e-9 * volume,
        "{} vs {volume}",
        peg.volume()
    );
}

#[test]
fn curved_surfaces_are_refused_with_or_without_facets() {
    // Without --facet: the circle is named and --facet suggested.
    let e = Part::from_path(&fixture("cad/round_peg.step")).unwrap_err().to_string();
    assert!(e.contains("CIRCLE is curved") && e.contains("--facet"), "{e}");
    // A sphere is not faceted: refused by name.
    let peg = text("cad/round_peg.step");
    let sphere = peg.replace("CYLINDRICAL_SURFACE('',", "SPHERICAL_SURFACE('',");
    assert_ne!(sphere, peg);
    let path = std::env::temp_dir().join(format!("acsg-sphere-{}.step", std::process::id()));
    std::fs::write(&path, &sphere).unwrap();
    let e = Part::from_path_with(&path, None, Some(0.1)).unwrap_err().to_string();
    let _ = std::fs::remove_file(&path);
    assert!(
        e.contains("SPHERICAL_SURFACE is curved") && e.contains("faceted"),
        "{e}"
    );
    // A cylinder face bounded otherwise than by two whole circles (here the bottom
    // circle of its loop replaced by the seam) is refused, naming face and surface.
    let line = "#64 = ORIENTED_EDGE('',*,*,#27,.T.);";
    assert!(peg.contains(line), "the fixture changed: update this test");
    let one_circle = peg.replace(line, "#64 = ORIENTED_EDGE('',*,*,#40,.T.);");
    let path = std::env::temp_dir().join(format!("acsg-one-circle-{}.step", std::process::id()));
    std::fs::write(&path, &one_circle).unwrap();
    let e = Part::from_path_with(&path, None, Some(0.1)).unwrap_err().to_string();
    let _ = std::fs::remove_file(&path);
    assert!(
        e.contains("CYLINDRICAL_SURFACE: it is bounded by 1 whole circles, not two") && e.contains("--facet"),
        "{e}"
    );
}
