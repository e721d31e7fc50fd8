//! The `acsg` binary, end to end: outputs checked against hand-derived counts, every
//! bad-input class checked for its message and exit code.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use predicates::prelude::*;
use predicates::str::contains;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

fn acsg() -> Command {
    Command::cargo_bin("acsg").expect("binary built")
}

#[test]
fn inspect_json_reports_the_papers_counts() {
    let out = acsg()
        .args(["inspect", "--json"])
        .arg(fixture("l_block.stl"))
        .arg(fixture("box.obj"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    let l = &v["parts"][0];
    let b = &v["parts"][1];
    assert!(l["path"].as_str().unwrap().ends_with("l_block.stl"));
    for (key, want) in [
        ("faces", 8),
        ("faces_with_holes", 0),
        ("nonconvex_faces", 2),
        ("vertices", 12),
        ("convex_vertices", 10),
        ("edges", 18),
        ("convex_edges", 17),
        ("concave_edges", 1),
        ("convex_pieces", 2),
    ] {
        assert_eq!(l[key], want, "l_block {key}");
    }
    assert_eq!(l["volume"], 1_500_000.0);
    for (key, want) in [
        ("faces", 6),
        ("vertices", 8),
        ("convex_vertices", 8),
        ("edges", 12),
        ("convex_edges", 12),
    ] {
        assert_eq!(b[key], want, "box {key}");
    }
    assert_eq!(
        v["ppc"],
        serde_json::json!({"f_v": 64, "e_e": 204, "v_f": 60, "total": 328})
    );
}

#[test]
fn inspect_text_names_both_roles_and_card_ppc() {
    acsg()
        .arg("inspect")
        .arg(fixture("block_with_hole.off"))
        .arg(fixture("peg.stl"))
        .assert()
        .success()
        .stdout(
            contains("(fixed)")
                .and(contains("(moving)"))
                .and(contains("2 with holes"))
                .and(contains("4 concave")),
        )
        // 10 faces x 8 + 20 x 12 + 8 x 6
        .stdout(contains("card(PPC) = 368"));
}

/// A task file next to its parts: paths relative to the task, as given in the output;
/// a cube tilting 10 degrees on a slab has 9 states besides free space.
#[test]
fn run_reads_a_task_file_and_writes_the_graph_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixture("cube.off"), dir.path().join("cube.off")).unwrap();
    std::fs::copy(fixture("slab.off"), dir.path().join("slab.off")).unwrap();
    let task = dir.path().join("cube.toml");
    std::fs::write(
        &task,
        "fixed = \"slab.off\"\nmoving = \"cube.off\"\n[bounds]\nx = [-1, 1]\ny = [-1, 1]\nz = [0, 30]\n\
         rx = [-10, 10]\nry = [-10, 10]\nrz = [-180, 180]\n",
    )
    .unwrap();
    acsg().arg("run").arg(&task).assert().success();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cube.graph.json")).unwrap()).unwrap();
    assert_eq!(v["fixed"]["path"], "slab.off");
    assert_eq!(v["states"].as_array().unwrap().len(), 10);
    assert!((v["bounds"]["max"][3].as_f64().unwrap() - 10f64.to_radians()).abs() < 1e-15);
}

#[test]
fn generate_with_flags_prints_json_and_is_deterministic() {
    let run = |threads: &str| {
        acsg()
            .arg("generate")
            .arg(fixture("slab.off"))
            .arg(fixture("cube.off"))
            .args(["--bounds", "x=-1:1,y=-1:1,z=0:30,rx=-10:10,ry=-10:10,rz=-180:180"])
            .args(["--threads", threads, "--no-timings", "-q"])
            .output()
            .unwrap()
    };
    let (one, two) = (run("1"), run("2"));
    assert!(one.status.success(), "{}", String::from_utf8_lossy(&one.stderr));
    assert_eq!(one.stdout, two.stdout);
    let v: serde_json::Value = serde_json::from_slice(&one.stdout).unwrap();
    assert_eq!(v["states"].as_array().unwrap().len(), 10);
}

#[test]
fn bad_bounds_and_task_files_are_refused_clearly() {
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "x=1:-1"])
        .assert()
        .code(2)
        .stderr(contains("x").and(contains("min")));
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "w=0:1"])
        .assert()
        .code(2)
        .stderr(contains("unknown component 'w'"));
    // The demo's own bounds, when given, are checked the same way, and nothing is
    // written.
    let dir = tempfile::tempdir().unwrap();
    acsg()
        .current_dir(dir.path())
        .args(["demo", "--bounds=z=5:0"])
        .assert()
        .code(2)
        .stderr(contains("z").and(contains("min")));
    assert!(!dir.path().join("acsg-demo.graph.json").exists());
    let cases = [
        (
            "fixed = \"a.off\"\nmoving = \"b.off\"\n[bounds]\nx = [1, -1]\ny = [0, 0]\nz = [0, 0]\nrx = [0, 0]\nry = [0, 0]\nrz = [0, 0]\n",
            "[bounds]",
        ),
        (
            "fixed = \"a.off\"\nmoving = \"b.off\"\n[bounds]\nx = [0, 1]\n",
            "missing field",
        ),
        ("fixed = \"a.off\"\nmoving = \"b.off\"\ncolour = 3\n", "unknown field"),
        ("fixed = \"a.off\"\nmoving = \n", ":2:"),
    ];
    for (i, (text, fragment)) in cases.iter().enumerate() {
        let task = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&task, text).unwrap();
        acsg()
            .arg("run")
            .arg(&task)
            .assert()
            .code(1)
            .stderr(contains(format!("bad{i}.toml")).and(contains(*fragment)));
    }
}

#[test]
fn a_failed_run_leaves_an_existing_output_file_alone() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("graph.json");
    std::fs::write(&out, "previous result").unwrap();
    acsg()
        .arg("generate")
        .arg(fixture("bad/open_box.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "z=0:1"])
        .arg("-o")
        .arg(&out)
        .assert()
        .code(1);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous result");
}

/// Each bad input: the file, its message fragments, and the exit code 1.
#[test]
fn every_bad_input_gets_a_clear_error_and_exit_code_1() {
    let cases: &[(&str, &[&str])] = &[
        ("bad/empty.off", &["empty.off", "empty"]),
        ("bad/whitespace.stl", &["whitespace.stl", "empty"]),
        (
            "bad/open_box.off",
            &[
                "open_box.off",
                "not closed",
                "(0, 0, 10) - (10, 0, 10)",
                "add the missing faces",
            ],
        ),
        (
            "bad/nonmanifold.off",
            &["nonmanifold.off", "not manifold", "(10, 10, 0) - (10, 10, 10)"],
        ),
        (
            "bad/flipped_face.off",
            &[
                "flipped_face.off",
                "inconsistent orientation",
                "line 13",
                "reverse the winding",
            ],
        ),
        (
            "bad/inward.off",
            &["inward.off", "inward orientation", "-1000", "flip normals"],
        ),
        ("bad/zero_area.off", &["zero_area.off", "zero-area face", "line 21"]),
        ("bad/nan.off", &["nan.off", "line 11", "vertex 7", "not finite"]),
        ("bad/inf.obj", &["inf.obj", "not finite"]),
        (
            "bad/nonplanar.off",
            &["nonplanar.off", "not planar", "line 13", "split the polygon"],
        ),
        ("bad/truncated.stl", &["truncated.stl", "12", "6"]),
        ("bad/bad_index.off", &["bad_index.off", "line 13", "42"]),
        ("bad/garbage.obj", &["garbage.obj", "abc"]),
        (
            "bad/two_shells.off",
            &["two_shells.off", "2 separate closed shells", "one solid in each file"],
        ),
    ];
    for (name, fragments) in cases {
        let out = acsg().arg("inspect").arg(fixture(name)).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}: exit code");
        assert!(out.stdout.is_empty(), "{name}: printed a result");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{name} panicked: {err}");
        for f in *fragments {
            assert!(err.contains(f), "{name}: message lacks {f:?}:\n{err}");
        }
    }
}

#[test]
fn missing_file_and_unknown_format_are_errors() {
    acsg()
        .args(["inspect", "no/such/file.off"])
        .assert()
        .code(1)
        .stderr(contains("no/such/file.off").and(contains("cannot read")));
    // The operating system's reason is said once, though the library's message holds
    // it and names it as its source too.
    let out = acsg().args(["inspect", "no/such/file.off"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("os error").count(), 1, "{stderr}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("notes.txt");
    std::fs::write(&path, "these are not the vertices you are looking for\n").unwrap();
    acsg()
        .arg("inspect")
        .arg(&path)
        .assert()
        .code(1)
        .stderr(contains("notes.txt").and(contains("unknown model format")));
}

#[test]
fn huge_file_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.stl");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(2 << 30).unwrap(); // sparse: takes no disk space
    acsg()
        .arg("inspect")
        .arg(&path)
        .assert()
        .code(1)
        .stderr(contains("huge.stl").and(contains("limit")));
}

#[test]
fn mislabelled_file_is_read_by_its_content() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.stl");
    std::fs::copy(fixture("cube.off"), &path).unwrap();
    acsg()
        .arg("inspect")
        .arg(&path)
        .assert()
        .success()
        .stdout(contains("12 convex"));
}

#[test]
fn bad_usage_exits_2() {
    acsg()
        .args(["inspect", "--frobnicate"])
        .assert()
        .code(2)
        .stderr(contains("--frobnicate"));
    acsg().arg("inspect").assert().code(2);
    acsg().arg("no-such-command").assert().code(2);
}

#[test]
fn contacts_json_lists_the_two_face_contacts_of_the_assembled_pose() {
    let out = acsg()
        .args(["contacts", "--json", "--pose", "0,0,0,0,0,0"])
        .arg(fixture("l_block.off"))
        .arg(fixture("box.stl"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["penetration"], 0.0);
    assert!(v["convention"].as_str().unwrap().contains("Rz(rz)*Ry(ry)*Rx(rx)"));
    let contacts = v["contacts"].as_array().unwrap();
    assert_eq!(contacts.len(), 2);
    // Check each contact's faces through the geometry in the same document: the floor
    // (normal +z) against the box bottom (-z), the wall (-x) against the box side (+x).
    let normal = |part: &str, id: &serde_json::Value| {
        let index: usize = id.as_str().unwrap().strip_prefix('f').unwrap().parse().unwrap();
        v["parts"][part]["face_normals"][index]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect::<Vec<_>>()
    };
    let mut pairs: Vec<(Vec<f64>, Vec<f64>)> = contacts
        .iter()
        .map(|c| {
            assert_eq!(c["type"], "f-f");
            assert_eq!(c["dof"], 3);
            (normal("fixed", &c["fixed"]), normal("moving", &c["moving"]))
        })
        .collect();
    pairs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        pairs,
        vec![
            (vec![-1.0, 0.0, 0.0], vec![1.0, 0.0, 0.0]),
            (vec![0.0, 0.0, 1.0], vec![0.0, 0.0, -1.0])
        ]
    );
    // Elements with geometry: 12 vertices, 18 edges as index pairs, faces as loops.
    assert_eq!(v["parts"]["fixed"]["vertices"].as_array().unwrap().len(), 12);
    assert_eq!(v["parts"]["fixed"]["edges"][0].as_array().unwrap().len(), 2);
    assert_eq!(v["parts"]["moving"]["faces"].as_array().unwrap().len(), 6);
}

#[test]
fn contacts_text_reports_penetration_and_gap() {
    // Pushed 1 into the wall, lifted 5 off the floor.
    box_on_the_l_block(&["--pose", "1,0,5,0,0,0"])
        .success()
        .stdout(contains("penetration  1").and(contains("the parts penetrate")));
    // Degrees are accepted; 5 away from the wall, 2 off the floor: nearest gap 2.
    box_on_the_l_block(&["--degrees", "--pose=-5,0,2,0,0,0"])
        .success()
        .stdout(contains("contacts     0").and(contains("min gap      2 ")));
}

/// `acsg contacts` of the box against the L-block with `args`.
fn box_on_the_l_block(args: &[&str]) -> assert_cmd::assert::Assert {
    acsg()
        .arg("contacts")
        .args(args)
        .arg(fixture("l_block.off"))
        .arg(fixture("box.off"))
        .assert()
}

#[test]
fn contacts_says_whether_the_pose_is_a_robust_witness_and_why_not() {
    // The box in the L-block's corner, face on face twice: robust.
    box_on_the_l_block(&["--pose", "0,0,0,0,0,0"])
        .success()
        .stdout(contains("witness      robust"));
    // Pushed 1 into the wall: not robust, and the reason says so.
    box_on_the_l_block(&["--pose", "1,0,5,0,0,0"])
        .success()
        .stdout(contains("witness      not robust: the parts penetrate by 1"));
    // The box's corner 5e-8 mm from the L-block's concave corner, its edge from there
    // crossing the floor's back edge 3.4e-4 mm away at 1.8e-4 rad: read from end to
    // end, an edge in a face and the corners together; read over the overlap, the two
    // edges run together (DOMAIN §7's reading of an edge with two points on a line).
    let band = "--pose=-0.0017440112563633647,-0.7649061686836358,28.883407230713246,\
                -0.30053863035103057,-5.736010645374471e-06,-1.8509079748124447e-05";
    let out = acsg()
        .args(["contacts", "--json", "--radians", band])
        .arg(fixture("l_block.off"))
        .arg(fixture("box.off"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let kinds: Vec<&str> = v["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["type"].as_str().unwrap())
        .collect();
    assert_eq!(kinds, ["e-f", "v-v"]);
    assert_eq!(v["robust"], false);
    let why = v["not_robust_because"].as_str().unwrap();
    assert!(
        why.starts_with("read over the overlap") && why.contains("e-e-t e7 e6"),
        "{why}"
    );
}

#[test]
fn bad_poses_and_tolerances_are_usage_errors() {
    let run = |args: &[&str]| {
        acsg()
            .arg("contacts")
            .arg(fixture("cube.off"))
            .arg(fixture("cube.off"))
            .args(args)
            .assert()
    };
    run(&["--pose", "0,0,nan,0,0,0"])
        .code(2)
        .stderr(contains("value 3 (z) is NaN"));
    run(&["--pose", "0,0,0"])
        .code(2)
        .stderr(contains("expected 6 comma-separated values"));
    run(&["--pose", "0,0,abc,0,0,0"]).code(2).stderr(contains("'abc'"));
    run(&["--pose", "0,0,0,0,0,0", "--tol", "-1"])
        .code(2)
        .stderr(contains("--tol"));
    run(&[]).code(2).stderr(contains("--pose"));
}

/// Runs `acsg` with its stdout closed before it writes (`acsg ... | head -0`).
fn run_with_closed_stdout(args: &[std::ffi::OsString]) -> std::process::Output {
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("acsg"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    child.wait_with_output().unwrap()
}

#[test]
fn a_closed_pipe_is_not_an_error() {
    let out = run_with_closed_stdout(&[
        "contacts".into(),
        "--json".into(),
        "--pose".into(),
        "0,0,0,0,0,0".into(),
        fixture("l_block.off").into(),
        fixture("box.off").into(),
    ]);
    assert!(out.status.success());
    assert!(!String::from_utf8_lossy(&out.stderr).contains("Broken pipe"));
}

/// The summary goes to stdout after the graph file is written: a reader that has gone
/// (`acsg generate ... -o g.json | head -1`) costs neither the file nor the exit code.
#[test]
fn a_closed_pipe_after_generate_keeps_the_graph_file() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("g.json");
    let out = run_with_closed_stdout(&[
        "generate".into(),
        fixture("slab.off").into(),
        fixture("cube.off").into(),
        "--bounds".into(),
        "x=-1:1,y=-1:1,z=0:30,rx=-10:10,ry=-10:10,rz=-180:180".into(),
        "-o".into(),
        output.clone().into(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&output).unwrap()).unwrap();
    assert_eq!(v["states"].as_array().unwrap().len(), 10);
}

#[test]
fn inspect_takes_step_and_iges_paths() {
    acsg()
        .arg("inspect")
        .arg(fixture("cad/block_with_hole.step"))
        .arg(fixture("cad/peg.igs"))
        .assert()
        .success()
        .stdout(contains("2 with holes").and(contains("4 concave")))
        .stdout(contains("card(PPC) = 368"));
    let out = acsg()
        .args(["inspect", "--json"])
        .arg(fixture("cad/l_block_faces.igs"))
        .arg(fixture("cad/peg_inch.step"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    assert_eq!(v["parts"][0]["faces"], 8);
    assert_eq!(v["parts"][0]["volume"], 1_500_000.0);
    assert_eq!(v["parts"][1]["vertices"], 8);
}

#[test]
fn a_curved_step_file_is_refused_naming_the_entity() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixture("cad/peg.step")).unwrap();
    let path = dir.path().join("round.step");
    std::fs::write(
        &path,
        text.replace("#32 = PLANE('',#33);", "#32 = CYLINDRICAL_SURFACE('',#33,5.);"),
    )
    .unwrap();
    acsg().arg("inspect").arg(&path).assert().code(1).stderr(
        contains("round.step")
            .and(contains("#32 CYLINDRICAL_SURFACE"))
            .and(contains("planar")),
    );
}

#[test]
fn generate_takes_cad_parts_and_matches_the_mesh_run() {
    let run = |fixed: &str, moving: &str| {
        let out = acsg()
            .arg("generate")
            .arg(fixture(fixed))
            .arg(fixture(moving))
            .args(["--bounds", "x=-2:2,z=0:5"])
            .args(["--threads", "1", "--no-timings", "-q"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v["states"].clone()
    };
    let mesh = run("block_with_hole.off", "peg.off");
    assert!(!mesh.as_array().unwrap().is_empty());
    assert_eq!(run("cad/block_with_hole.step", "cad/peg.igs"), mesh);
}

/// `contacts --pose` reads degrees, like every other flag; `--radians` reads radians.
/// A quarter turn about z puts the rotation's first row at (0, -1, 0), whichever way
/// it is written, and the JSON keeps radians.
#[test]
fn contacts_pose_angles_are_degrees_unless_radians() {
    let run = |args: &[&str]| {
        let out = acsg()
            .args(["contacts", "--json"])
            .args(args)
            .arg(fixture("cube.off"))
            .arg(fixture("cube.off"))
            .args(["--assembled", "0,0,100,0,0,0"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let degrees = run(&["--pose", "0,0,0,0,0,90"]);
    let radians = run(&[
        "--radians",
        "--pose",
        &format!("0,0,0,0,0,{}", std::f64::consts::FRAC_PI_2),
    ]);
    for v in [&degrees, &radians] {
        assert!((v["pose"][5].as_f64().unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let row: Vec<f64> = (0..3).map(|j| v["matrix"][0][j].as_f64().unwrap()).collect();
        assert!(
            row[0].abs() < 1e-12 && (row[1] + 1.0).abs() < 1e-12 && row[2].abs() < 1e-12,
            "{row:?}"
        );
        assert_eq!(v["units"]["angle"], "radians");
        assert!(v["convention"].as_str().unwrap().contains("radians"));
    }
    // The text output says degrees.
    acsg()
        .args(["contacts", "--pose", "0,0,50,0,0,90"])
        .arg(fixture("cube.off"))
        .arg(fixture("cube.off"))
        .assert()
        .success()
        .stdout(contains("rz=90°"));
}

#[test]
fn angles_outside_a_half_turn_are_refused_everywhere() {
    let contacts = |args: &[&str]| {
        acsg()
            .arg("contacts")
            .arg(fixture("cube.off"))
            .arg(fixture("cube.off"))
            .args(args)
            .assert()
    };
    contacts(&["--pose", "0,0,0,0,0,200"]).code(2).stderr(
        contains("--pose")
            .and(contains("200°, outside ±180°"))
            .and(contains("-160°")),
    );
    // 18 was read as 18 rad before the switch to degrees: refused, not wrapped.
    contacts(&["--radians", "--pose", "0,0,0,18,0,0"])
        .code(2)
        .stderr(contains("18 rad").and(contains("outside ±π")));
    contacts(&["--pose", "0,0,0,0,0,0", "--assembled", "0,0,0,-181,0,0"])
        .code(2)
        .stderr(contains("--assembled").and(contains("outside ±180°")));
    contacts(&["--pose", "0,0,0,0,0,180"]).success();
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "z=0:1,rz=-190:10"])
        .assert()
        .code(2)
        .stderr(contains("min bound on rz is -190°, outside ±180°"));
    let dir = tempfile::tempdir().unwrap();
    for (name, text, fragment) in [
        ("bounds.toml", "rz = [0, 360]", "max bound on rz is 360°"),
        (
            "assembled.toml",
            "rz = [0, 0]\n[options]\nassembled = [0, 0, 0, 0, 270, 0]",
            "270°",
        ),
    ] {
        let task = dir.path().join(name);
        std::fs::write(
            &task,
            format!("fixed = \"a.off\"\nmoving = \"b.off\"\n[bounds]\nx = [0, 0]\ny = [0, 0]\nz = [0, 0]\nrx = [0, 0]\nry = [0, 0]\n{text}\n"),
        )
        .unwrap();
        acsg()
            .arg("run")
            .arg(&task)
            .assert()
            .code(1)
            .stderr(contains(name).and(contains(fragment)).and(contains("outside ±180°")));
    }
}

/// `--units` labels a mesh (its numbers unchanged) and converts a CAD part (which
/// states its unit): the STEP peg in inches is the millimetre peg divided by 25.4.
#[test]
fn units_label_meshes_and_convert_cad_parts() {
    let inspect = |path: &str, units: Option<&str>| {
        let mut cmd = acsg();
        cmd.args(["inspect", "--json"]).arg(fixture(path));
        if let Some(u) = units {
            cmd.args(["--units", u]);
        }
        let out = cmd.output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let num = |v: &serde_json::Value| v.as_f64().unwrap();
    let step_mm = inspect("cad/peg.step", None);
    assert_eq!(step_mm["units"], "mm");
    let step_in = inspect("cad/peg.step", Some("in"));
    assert_eq!(step_in["units"], "in");
    for (k, corner) in [0, 1].iter().flat_map(|c| (0..3).map(move |k| (k, *c))) {
        let (mm, inch) = (
            num(&step_mm["parts"][0]["bounds"][corner][k]),
            num(&step_in["parts"][0]["bounds"][corner][k]),
        );
        assert!(
            (mm / 25.4 - inch).abs() <= 1e-12 * mm.abs().max(1.0),
            "{mm} mm vs {inch} in"
        );
    }
    let volume_ratio = num(&step_mm["parts"][0]["volume"]) / num(&step_in["parts"][0]["volume"]);
    assert!((volume_ratio - 25.4f64.powi(3)).abs() < 1e-6 * volume_ratio);
    // A mesh: the same numbers, labelled.
    let mesh = inspect("peg.off", None);
    assert_eq!(mesh["units"], "model units");
    let mesh_cm = inspect("peg.off", Some("cm"));
    assert_eq!(mesh_cm["units"], "cm");
    assert_eq!(mesh["parts"], mesh_cm["parts"]);
    acsg()
        .arg("inspect")
        .arg(fixture("peg.off"))
        .args(["--units", "cm"])
        .assert()
        .success()
        .stdout(contains("units  cm"));
    acsg()
        .arg("inspect")
        .arg(fixture("peg.off"))
        .args(["--units", "ft"])
        .assert()
        .code(2)
        .stderr(contains("unknown length unit 'ft' (give mm, cm, m or in)"));
    // A task file's units reach the summary, the JSON and the report.
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixture("cube.off"), dir.path().join("cube.off")).unwrap();
    std::fs::copy(fixture("slab.off"), dir.path().join("slab.off")).unwrap();
    let task = dir.path().join("cube.toml");
    std::fs::write(
        &task,
        "fixed = \"slab.off\"\nmoving = \"cube.off\"\nunits = \"cm\"\n[bounds]\nx = [0, 0]\ny = [0, 0]\nz = [0, 1]\n\
         rx = [0, 0]\nry = [0, 0]\nrz = [0, 0]\n",
    )
    .unwrap();
    let html = dir.path().join("cube.html");
    acsg()
        .arg("run")
        .arg(&task)
        .arg("--html")
        .arg(&html)
        .assert()
        .success()
        .stdout(contains("lengths in cm, angles in degrees"));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cube.graph.json")).unwrap()).unwrap();
    assert_eq!(v["units"]["length"], "cm");
    assert_eq!(v["units"]["angle"], "radians");
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains(r#""units":{"length":"cm","angle":"radians"}"#));
    // The flag overrides the task file.
    acsg()
        .arg("run")
        .arg(&task)
        .args(["--units", "in", "-o"])
        .arg(dir.path().join("in.json"))
        .assert()
        .success()
        .stdout(contains("lengths in in,"));
}

/// A small graph written by the binary (slab and cube, translation only).
fn small_graph(dir: &Path) -> PathBuf {
    let path = dir.join("small.json");
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "x=-1:1,z=0:5", "-q", "--no-timings", "-o"])
        .arg(&path)
        .assert()
        .success();
    path
}

#[cfg(unix)]
#[test]
fn atomic_output_follows_links_writes_devices_and_keeps_the_mode() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let graph = small_graph(dir.path());
    let export = |output: &Path| {
        acsg()
            .args(["export", "--format", "dot"])
            .arg(&graph)
            .arg("-o")
            .arg(output)
            .assert()
            .success();
    };
    // Through a symlink: the target gets the bytes, the link stays a link.
    let target = dir.path().join("real.dot");
    std::fs::write(&target, "old").unwrap();
    let link = dir.path().join("link.dot");
    std::os::unix::fs::symlink("real.dot", &link).unwrap();
    export(&link);
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert!(std::fs::read_to_string(&target).unwrap().starts_with("graph"));
    // A file's mode survives its replacement.
    let private = dir.path().join("private.dot");
    std::fs::write(&private, "old").unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
    export(&private);
    assert_eq!(std::fs::metadata(&private).unwrap().permissions().mode() & 0o777, 0o600);
    assert!(std::fs::read_to_string(&private).unwrap().starts_with("graph"));
    // A device is written, not replaced (the test cannot replace /dev/null as a user,
    // so write to it and check it is still a character device).
    export(Path::new("/dev/null"));
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
    // A named pipe stays a pipe and receives the bytes.
    let fifo = dir.path().join("fifo.dot");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        export(&fifo);
        assert!(reader.join().unwrap().starts_with("graph"));
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    } else {
        use std::io::Write as _;
        let _ = writeln!(
            std::io::stderr().lock(),
            "SKIPPED the named-pipe part of atomic_output_...: mkfifo is not available"
        );
    }
    // Nothing of ours is left in the folder.
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// A temporary file left by a run killed between write and rename (its process is
/// gone) is removed by the next write of the same file; one of a live process stays.
#[cfg(target_os = "linux")]
#[test]
fn stale_temporary_files_are_cleaned_and_named_recognisably() {
    let dir = tempfile::tempdir().unwrap();
    let graph = small_graph(dir.path());
    // A process id that cannot be running: above the kernel's pid_max.
    let pid_max: u64 = std::fs::read_to_string("/proc/sys/kernel/pid_max")
        .map_or(4_194_304, |t| t.trim().parse().unwrap_or(4_194_304));
    let stale = dir.path().join(format!(".out.dot.acsg-partial.{}.tmp", pid_max + 1));
    std::fs::write(&stale, "half a graph").unwrap();
    let live = dir
        .path()
        .join(format!(".out.dot.acsg-partial.{}.tmp", std::process::id()));
    std::fs::write(&live, "being written").unwrap();
    acsg()
        .args(["export", "--format", "dot"])
        .arg(&graph)
        .arg("-o")
        .arg(dir.path().join("out.dot"))
        .assert()
        .success();
    assert!(!stale.exists(), "the stale temporary file was left");
    assert!(live.exists(), "a live process's temporary file was removed");
}

#[test]
fn threads_beyond_the_cap_are_refused() {
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "z=0:1", "--threads", "100000"])
        .assert()
        .code(2)
        .stderr(contains("--threads").and(contains("100000 threads is more than the limit")));
    let dir = tempfile::tempdir().unwrap();
    let task = dir.path().join("t.toml");
    std::fs::write(
        &task,
        "fixed = \"a.off\"\nmoving = \"b.off\"\n[bounds]\nx = [0, 0]\ny = [0, 0]\nz = [0, 1]\nrx = [0, 0]\n\
         ry = [0, 0]\nrz = [0, 0]\n[options]\nthreads = 100000\n",
    )
    .unwrap();
    acsg()
        .arg("run")
        .arg(&task)
        .assert()
        .code(1)
        .stderr(contains("t.toml:11:11:").and(contains("more than the limit")));
}

#[test]
fn task_arrays_of_the_wrong_length_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let head = "fixed = \"a.off\"\nmoving = \"b.off\"\n[bounds]\n";
    let ok_bounds = "y = [0, 0]\nz = [0, 1]\nrx = [0, 0]\nry = [0, 0]\nrz = [0, 0]\n";
    for (name, text, fragment) in [
        (
            "three.toml",
            format!("{head}x = [-1, 0, 1]\n{ok_bounds}"),
            "three.toml:4:5: [bounds] x has 3 values; give two",
        ),
        ("one.toml", format!("{head}x = [1]\n{ok_bounds}"), "x has 1 values"),
        (
            "seven.toml",
            format!("{head}x = [0, 0]\n{ok_bounds}[options]\nassembled = [0, 0, 0, 0, 0, 0, 0]\n"),
            "seven.toml:11:13: [options] assembled has 7 values; give six",
        ),
    ] {
        let task = dir.path().join(name);
        std::fs::write(&task, text).unwrap();
        acsg().arg("run").arg(&task).assert().code(1).stderr(contains(fragment));
    }
}

/// The input cap holds on the bytes read, not the size the file system reports (0 for
/// a device or a pipe). `ACSG_MAX_INPUT_BYTES` lowers the cap so that the test reads
/// little.
#[cfg(unix)]
#[test]
fn the_input_cap_holds_for_devices_and_pipes() {
    for args in [
        vec!["inspect", "/dev/zero"],
        vec!["report", "/dev/zero", "-o", "/dev/null"],
    ] {
        acsg()
            .args(&args)
            .env("ACSG_MAX_INPUT_BYTES", "100000")
            .timeout(std::time::Duration::from_secs(60))
            .assert()
            .code(1)
            .stderr(contains("/dev/zero").and(contains("limit")));
    }
    // A pipe (process substitution gives /dev/fd/N): the same cap.
    let script = format!(
        "head -c 200000 /dev/zero | {} inspect /dev/stdin",
        assert_cmd::cargo::cargo_bin("acsg").display()
    );
    let out = std::process::Command::new("sh")
        .args(["-c", &script])
        .env("ACSG_MAX_INPUT_BYTES", "100000")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("the input is more than the 100000-byte limit"),
        "{stderr}"
    );
}

#[test]
fn ply_and_iges_errors_are_in_plain_words() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("bad.ply");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty flot x\nend_header\n",
    )
    .unwrap();
    let out = acsg().arg("inspect").arg(&ply).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("line 4: the header line `property flot x` cannot be read"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("ParseError") && !stderr.contains("ExpectedSet"),
        "{stderr}"
    );
    // An IGES whose parameter data names another type than its directory entry.
    let text = std::fs::read_to_string(fixture("cad/peg.igs")).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("186,") && l.ends_with("P0000001"))
        .unwrap();
    let bad = text.replace(line, &line.replacen("186,", "120,", 1));
    let iges = dir.path().join("bad.igs");
    std::fs::write(&iges, bad).unwrap();
    let out = acsg().arg("inspect").arg(&iges).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("starts with `120`, not its type 186"), "{stderr}");
    assert!(!stderr.contains("Some(") && !stderr.contains("Text("), "{stderr}");
}

#[test]
fn report_accepts_a_bom_and_validates_what_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let graph = small_graph(dir.path());
    let text = std::fs::read_to_string(&graph).unwrap();
    let with_bom = dir.path().join("bom.json");
    std::fs::write(&with_bom, format!("\u{feff}{text}")).unwrap();
    acsg()
        .arg("report")
        .arg(&with_bom)
        .args(["-o", "/dev/null"])
        .assert()
        .success();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let state = v["states"]
        .as_array()
        .unwrap()
        .iter()
        .position(|s| {
            s["contacts"]
                .as_array()
                .is_some_and(|c| c.iter().any(|c| c["type"] == "f-f"))
        })
        .expect("the cube sits on the slab in some state");
    let contact = v["states"][state]["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .position(|c| c["type"] == "f-f")
        .unwrap();
    let mut wrong_kind = v.clone();
    wrong_kind["states"][state]["contacts"][contact]["moving"] = "v0".into();
    let mut wrong_dof = v.clone();
    wrong_dof["states"][state]["dof"] = 200.into();
    let mut wrong_contact_dof = v.clone();
    wrong_contact_dof["states"][state]["contacts"][contact]["dof"] = 5.into();
    let mut duplicate = v.clone();
    let first = duplicate["edges"][0].clone();
    let reversed = serde_json::json!([first[1], first[0]]);
    duplicate["edges"].as_array_mut().unwrap().push(reversed);
    let mut wrong_units = v.clone();
    wrong_units["units"]["angle"] = "degrees".into();
    for (name, doc, fragment) in [
        (
            "kind.json",
            wrong_kind,
            "names v0 as the moving element, but a f-f contact needs a face",
        ),
        ("dof.json", wrong_dof, "has dof 200, but a rigid part has at most 6"),
        ("cdof.json", wrong_contact_dof, "has dof 5, but a f-f contact leaves 3"),
        ("dup.json", duplicate, "is listed twice"),
        ("units.json", wrong_units, "angles \"radians\""),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, serde_json::to_string(&doc).unwrap()).unwrap();
        acsg()
            .arg("report")
            .arg(&path)
            .args(["-o", "/dev/null"])
            .assert()
            .code(1)
            .stderr(
                contains(name)
                    .and(contains("inconsistent graph"))
                    .and(contains(fragment)),
            );
    }
}

/// Coordinates far from the origin, for the part's size, are refused with advice to
/// move the part; the same cube near the origin reads.
#[test]
fn parts_far_from_the_origin_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cube = std::fs::read_to_string(fixture("cube.off")).unwrap();
    let shifted = |offset: f64| {
        let mut lines: Vec<String> = cube.lines().map(str::to_string).collect();
        for line in lines.iter_mut().skip(2).take(8) {
            let v: Vec<f64> = line.split_whitespace().map(|t| t.parse().unwrap()).collect();
            *line = format!("{} {} {}", v[0] + offset, v[1], v[2]);
        }
        lines.join("\n") + "\n"
    };
    for offset in [1e12, 1e15] {
        let path = dir.path().join(format!("far{offset:e}.off"));
        std::fs::write(&path, shifted(offset)).unwrap();
        acsg()
            .arg("inspect")
            .arg(&path)
            .assert()
            .code(1)
            .stderr(contains("from the origin").and(contains("move the part near the origin")));
    }
    // 1000 times its size away (17 mm diagonal, 10 m off): still fine, same volume.
    let near = dir.path().join("near.off");
    std::fs::write(&near, shifted(1e4)).unwrap();
    let out = acsg().args(["inspect", "--json"]).arg(&near).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!((v["parts"][0]["volume"].as_f64().unwrap() - 1000.0).abs() < 1e-6);
}

/// The stage-2 counters are explained: each line says what it counts, and the summary
/// says that they add up to more than the pairs.
#[test]
fn the_stage_two_summary_says_what_each_counter_counts() {
    let dir = tempfile::tempdir().unwrap();
    let out = acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "x=-1:1,y=-1:1,z=0:30,rx=-10:10,ry=-10:10,rz=-180:180", "-o"])
        .arg(dir.path().join("g.json"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("g.json")).unwrap()).unwrap();
    let stat = |k: &str| v["stats"][k].as_u64().unwrap();
    for (key, words) in [
        ("stage2_pairs", "pairs (a known state and a single contact to add)"),
        ("pruned_implied", "implied (the state already holds the contact"),
        ("pruned_topology", "pairs with no outcome"),
        ("pruned_duplicate", "outcomes already known or already proposed"),
        ("stage2_candidates", "new candidates, each decided"),
    ] {
        let line = text
            .lines()
            .find(|l| l.contains(words))
            .unwrap_or_else(|| panic!("no line with {words:?} in\n{text}"));
        assert!(line.contains(&stat(key).to_string()), "{key}: {line}");
    }
    assert!(text.contains("add up to more than the pairs"));
}

/// The sample task runs as written from the repository root (its part paths are
/// relative to it), and gives the same graph as the command line it stands for.
#[test]
fn the_sample_task_runs_from_the_repository_root() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = tempfile::tempdir().unwrap();
    let from_task = dir.path().join("task.json");
    acsg()
        .current_dir(&root)
        .args(["run", "examples/peg_in_hole.toml", "--no-timings", "-o"])
        .arg(&from_task)
        .assert()
        .success()
        .stdout(contains("lengths in mm").and(contains("complete yes")));
    let from_flags = acsg()
        .current_dir(&root)
        .args(["generate", "fixtures/block_with_hole.off", "fixtures/peg.off"])
        .args([
            "--bounds",
            "x=-2:2,y=-2:2,z=0:45",
            "--units",
            "mm",
            "--no-timings",
            "-q",
        ])
        .output()
        .unwrap();
    assert!(from_flags.status.success());
    let task: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&from_task).unwrap()).unwrap();
    let flags: serde_json::Value = serde_json::from_slice(&from_flags.stdout).unwrap();
    assert_eq!(task["states"], flags["states"]);
    assert_eq!(task["edges"], flags["edges"]);
    assert_eq!(task["complete"], true);
}

/// Chamfers written as planar B-spline surfaces (STEP and IGES) read as planes: 10
/// faces, 20 edges, 12 vertices, and the same card(PPC) as against each other.
#[test]
fn inspect_reads_planar_b_spline_chamfers() {
    let out = acsg()
        .args(["inspect", "--json"])
        .arg(fixture("cad/chamfered_peg.step"))
        .arg(fixture("cad/chamfered_peg.igs"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for k in 0..2 {
        assert_eq!(v["parts"][k]["faces"], 10);
        assert_eq!(v["parts"][k]["edges"], 20);
        assert_eq!(v["parts"][k]["vertices"], 12);
    }
    // Every face and convex vertex of a convex part: f-v 10 x 12 twice, e-e 20 x 20.
    assert_eq!(v["ppc"]["total"], 10 * 12 * 2 + 20 * 20);
}

/// `--facet` reads STEP cylinders, cones and circles as planar facets: the round peg
/// and the block with a round hole come out as the 32-sided OFF fixtures (same counts
/// and card(PPC)); the run says that its graph is of the faceted parts.
#[test]
fn facet_reads_round_step_parts_as_prisms() {
    let inspect = |args: &[&str], files: [&str; 2]| {
        let out = acsg()
            .args(["inspect", "--json"])
            .args(args)
            .arg(fixture(files[0]))
            .arg(fixture(files[1]))
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let step = inspect(
        &["--facet", "0.1"],
        ["cad/block_with_round_hole.step", "cad/round_peg.step"],
    );
    let off = inspect(&[], ["block_with_round_hole.off", "round_peg.off"]);
    assert_eq!(step["facet"], 0.1);
    assert_eq!(step["ppc"], off["ppc"]);
    for k in 0..2 {
        for key in ["faces", "edges", "vertices", "convex_pieces"] {
            assert_eq!(step["parts"][k][key], off["parts"][k][key], "{key}");
        }
    }
    // Without --facet the circle is refused, and the flag suggested.
    acsg()
        .arg("inspect")
        .arg(fixture("cad/round_peg.step"))
        .assert()
        .code(1)
        .stderr(contains("CIRCLE is curved").and(contains("--facet MM")));
    for bad in ["0", "-1", "nan"] {
        acsg()
            .arg("inspect")
            .arg(fixture("cad/round_peg.step"))
            .args(["--facet", bad])
            .assert()
            .code(2)
            .stderr(contains("invalid --facet"));
    }
    // A run: the summary and the JSON say the graph is of the faceted parts.
    let dir = tempfile::tempdir().unwrap();
    let graph = dir.path().join("g.json");
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cad/round_peg.step"))
        .args(["--facet", "0.3", "--units", "mm", "--bounds", "z=0:5", "-o"])
        .arg(&graph)
        .assert()
        .success()
        .stdout(contains("chord tolerance 0.3 mm): the graph is of the faceted parts"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&graph).unwrap()).unwrap();
    assert_eq!(v["facet"], 0.3);
    assert_eq!(v["moving"]["faces"].as_array().unwrap().len(), 2 + 16);
}

#[test]
fn a_task_file_can_ask_for_facets() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let body = |facet: &str| {
        format!(
            "fixed = \"{}\"\nmoving = \"{}\"\nunits = \"mm\"\nfacet = {facet}\n[bounds]\nx = [0, 0]\ny = [0, 0]\n\
             z = [0, 5]\nrx = [0, 0]\nry = [0, 0]\nrz = [0, 0]\n",
            root.join("slab.off").display(),
            root.join("cad/round_peg.step").display()
        )
    };
    let task = dir.path().join("round.toml");
    std::fs::write(&task, body("0.3")).unwrap();
    acsg()
        .arg("run")
        .arg(&task)
        .assert()
        .success()
        .stdout(contains("chord tolerance 0.3 mm"));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("round.graph.json")).unwrap()).unwrap();
    assert_eq!(v["facet"], 0.3);
    std::fs::write(&task, body("-2")).unwrap();
    acsg()
        .arg("run")
        .arg(&task)
        .assert()
        .code(1)
        .stderr(contains("round.toml:4:9: facet = -2"));
}

/// `generate` of the cube tilting on the slab (x, y ±1, z 0 to 30, rx, ry ±10°, rz free)
/// with `flag` added: the JSON it prints and its summary.
fn cube_tilting_on_the_slab(flag: Option<[&str; 2]>) -> (serde_json::Value, String) {
    let mut command = acsg();
    command
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args([
            "--bounds",
            "x=-1:1,y=-1:1,z=0:30,rx=-10:10,ry=-10:10,rz=-180:180",
            "--no-timings",
        ]);
    command.args(flag.iter().flatten());
    let out = command.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (v, String::from_utf8_lossy(&out.stderr).to_string())
}

/// `--strategy paper` runs the paper's algorithm: named in the JSON and the summary,
/// never complete, and its states are among the default's; an unknown name is a usage
/// error; a task file may ask for it.
#[test]
fn the_papers_algorithm_is_a_strategy_of_generate_and_task_files() {
    let generate = |strategy: Option<&str>| cube_tilting_on_the_slab(strategy.map(|name| ["--strategy", name]));
    let (paper, summary) = generate(Some("paper"));
    let (full, full_summary) = generate(None);
    assert_eq!(paper["options"]["strategy"], "paper");
    assert!(full["options"].get("strategy").is_none(), "the default is not written");
    assert_eq!(paper["complete"], false);
    assert_eq!(full["complete"], true);
    assert!(summary.contains("search paper") && summary.contains("proves nothing infeasible"));
    assert!(!full_summary.contains("search paper"));
    let states = |v: &serde_json::Value| -> std::collections::BTreeSet<String> {
        v["states"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["contacts"].to_string())
            .collect()
    };
    assert!(states(&paper).len() > 1);
    assert!(states(&paper).is_subset(&states(&full)));
    // The same with `--strategy full` as without.
    assert_eq!(generate(Some("full")).0, full);
    acsg()
        .arg("generate")
        .arg(fixture("slab.off"))
        .arg(fixture("cube.off"))
        .args(["--bounds", "z=0:3", "--strategy", "fastest"])
        .assert()
        .code(2)
        .stderr(contains("unknown strategy 'fastest'").and(contains("paper")));

    let dir = tempfile::tempdir().unwrap();
    let task = |name: &str, strategy: &str| {
        let path = dir.path().join(name);
        std::fs::write(
            &path,
            format!(
                "fixed = {:?}\nmoving = {:?}\n[bounds]\nx = [-1, 1]\ny = [0, 0]\nz = [0, 3]\nrx = [-5, 5]\n\
                 ry = [0, 0]\nrz = [0, 0]\n[options]\nstrategy = \"{strategy}\"\n",
                fixture("slab.off").display().to_string(),
                fixture("cube.off").display().to_string()
            ),
        )
        .unwrap();
        path
    };
    acsg()
        .arg("run")
        .arg(task("p.toml", "paper"))
        .arg("-q")
        .assert()
        .success();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("p.graph.json")).unwrap()).unwrap();
    assert_eq!(v["options"]["strategy"], "paper");
    acsg()
        .arg("run")
        .arg(task("bad.toml", "fastest"))
        .assert()
        .code(1)
        .stderr(contains("bad.toml").and(contains("fastest")));
}

/// `--work-limit` cuts a run short and says so: in the summary, in the JSON (the limit
/// under `options`, `work_limit_reached` in the stats, `complete` false, the candidates
/// left undecided listed); a task file may set it; 0 or a non-number is a usage error.
#[test]
fn a_work_limit_cuts_the_run_short_and_the_outputs_say_so() {
    let generate = |limit: Option<&str>| cube_tilting_on_the_slab(limit.map(|limit| ["--work-limit", limit]));
    let (cut, summary) = generate(Some("100"));
    assert_eq!(cut["options"]["work_limit"], 100);
    assert_eq!(cut["stats"]["work_limit_reached"], true);
    assert_eq!(cut["complete"], false);
    assert!(summary.contains("the work limit was reached"), "{summary}");
    let (full, full_summary) = generate(None);
    assert!(full["options"].get("work_limit").is_none(), "no limit is not written");
    assert!(
        full["stats"].get("work_limit_reached").is_none(),
        "written only when reached"
    );
    assert_eq!(full["complete"], true);
    assert!(!full_summary.contains("work limit"));
    // A limit far above what the run needs: the same graph.
    let (roomy, _) = generate(Some("100000000"));
    assert_eq!(roomy["states"], full["states"]);
    assert_eq!(roomy["complete"], true);
    for bad in ["0", "-5", "lots"] {
        acsg()
            .arg("generate")
            .arg(fixture("slab.off"))
            .arg(fixture("cube.off"))
            .args(["--bounds", "z=0:3", &format!("--work-limit={bad}")])
            .assert()
            .code(2)
            .stderr(contains("--work-limit"));
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.toml");
    std::fs::write(
        &path,
        format!(
            "fixed = {:?}\nmoving = {:?}\n[bounds]\nx = [-1, 1]\ny = [-1, 1]\nz = [0, 30]\nrx = [-10, 10]\n\
             ry = [-10, 10]\nrz = [-180, 180]\n[options]\nwork_limit = 100\n",
            fixture("slab.off").display().to_string(),
            fixture("cube.off").display().to_string()
        ),
    )
    .unwrap();
    acsg().arg("run").arg(&path).arg("-q").assert().success();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cut.graph.json")).unwrap()).unwrap();
    assert_eq!(v["options"]["work_limit"], 100);
    assert_eq!(v["stats"]["work_limit_reached"], true);
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("work_limit = 100", "work_limit = 0");
    std::fs::write(&path, text).unwrap();
    acsg()
        .arg("run")
        .arg(&path)
        .assert()
        .code(1)
        .stderr(contains("cut.toml:11:14: [options] work_limit = 0"));
}
