//! Reading graphs back, and the DOT, GraphML and HTML writers, on a small hand-built
//! graph whose every value is known.

use acsg::export::{ExportError, GraphFile, dot, graphml, html, layered_layout, node_link};
use acsg::graph::Stats;
use serde_json::{Value, json};

/// A tetrahedron's elements (4 vertices, 6 edges, 4 faces).
fn tetrahedron(path: &str) -> Value {
    json!({
        "path": path,
        "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        "convex_vertices": [true, true, true, true],
        "edges": [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]],
        "convex_edges": [true, true, true, true, true, true],
        "faces": [[[0, 2, 1]], [[0, 1, 3]], [[0, 3, 2]], [[1, 2, 3]]],
        "face_normals": [[0, 0, -1], [0, -1, 0], [-1, 0, 0], [0.5773502691896258, 0.5773502691896258, 0.5773502691896258]]
    })
}

fn witness(pose: [f64; 6]) -> Value {
    let [x, y, z, ..] = pose;
    json!({"pose": pose, "matrix": [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]})
}

/// Four states: free space without a witness, a vertex on a face, an edge on a face,
/// and a degenerate two-contact state; a path with characters every format must escape.
fn small_json() -> Value {
    let mut stats = serde_json::to_value(Stats::default()).unwrap();
    stats["states"] = json!(4);
    stats["edges"] = json!(4);
    stats["ppc"] = json!(48);
    json!({
        "format": "acsg-graph/1",
        "convention": acsg::pose::CONVENTION,
        "units": {"length": "model units", "angle": "radians"},
        "fixed": tetrahedron("parts/\"odd\" <name> & 'quotes'\\.off"),
        "moving": tetrahedron("tet.off"),
        "assembled": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
        "bounds": {"min": [-1, -1, 0, -0.1, -0.1, -0.1], "max": [1, 1, 2, 0.1, 0.1, 0.1]},
        "options": {"degenerate": true},
        "states": [
            {"id": 0, "contacts": [], "dof": 6, "degenerate": false, "witness": null},
            {"id": 1, "contacts": [{"type": "f-v", "fixed": "f3", "moving": "v0", "dof": 5, "degenerate": false}],
             "dof": 5, "degenerate": false, "witness": witness([0.25, 0.25, 0.5, 0.0, 0.0, 0.0])},
            {"id": 2, "contacts": [{"type": "f-e", "fixed": "f3", "moving": "e1", "dof": 4, "degenerate": false}],
             "dof": 4, "degenerate": false, "witness": witness([0.5, 0.0, 0.5, 0.0, 0.0, 0.1])},
            {"id": 3, "contacts": [
                {"type": "e-e", "fixed": "e5", "moving": "e0", "dof": 5, "degenerate": false},
                {"type": "v-v", "fixed": "v3", "moving": "v2", "dof": 3, "degenerate": true}],
             "dof": 3, "degenerate": true, "witness": witness([-1.0, 0.125, 1.0, 0.0, -0.05, 0.0])}
        ],
        "edges": [[0, 1], [1, 2], [1, 3], [2, 3]],
        "stats": stats
    })
}

fn small() -> GraphFile {
    GraphFile::from_json(&small_json().to_string(), "small.json").expect("the hand-built graph reads")
}

#[test]
fn dot_snapshot() {
    insta::assert_snapshot!(dot::to_dot(&small()));
}

#[test]
fn graphml_snapshot() {
    insta::assert_snapshot!(graphml::to_graphml(&small()));
}

#[test]
fn writers_are_deterministic() {
    let (a, b) = (small(), small());
    assert_eq!(dot::to_dot(&a), dot::to_dot(&b));
    assert_eq!(graphml::to_graphml(&a), graphml::to_graphml(&b));
    assert_eq!(html::to_html(&a), html::to_html(&b));
}

#[test]
fn graphml_loads_in_networkx_when_python_has_it() {
    let has_networkx = std::process::Command::new("python3")
        .args(["-c", "import networkx"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_networkx {
        skipped(
            "graphml_loads_in_networkx_when_python_has_it",
            "python3 with networkx not available (pip install networkx)",
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("small.graphml");
    std::fs::write(&path, graphml::to_graphml(&small())).unwrap();
    let script = "import sys, networkx as nx\n\
                  g = nx.read_graphml(sys.argv[1])\n\
                  s3 = g.nodes['s3']\n\
                  print(g.number_of_nodes(), g.number_of_edges(), s3['n_contacts'], s3['dof'], s3['degenerate'], repr(s3['contacts']), 'witness' in g.nodes['s0'], g.graph['fixed'])\n\
                  print(repr([s3[k] for k in ('x', 'y', 'z', 'rx', 'ry', 'rz')]), repr(s3['m03']), repr(s3['m11']), 'm00' in g.nodes['s0'])";
    let out = std::process::Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout).trim(),
        "4 4 2 3 True 'e-e e5 e0; v-v v3 v2' False parts/\"odd\" <name> & 'quotes'\\.off\n\
         [-1.0, 0.125, 1.0, 0.0, -0.05, 0.0] -1.0 1.0 False"
    );
}

#[test]
fn the_report_embeds_the_graph_safely_and_completely() {
    let mut value = small_json();
    value["moving"]["path"] = json!("</script><script>alert(1)</script><!--");
    let graph = GraphFile::from_json(&value.to_string(), "evil.json").unwrap();
    let page = html::to_html(&graph);
    // Every <script> is closed exactly once: the hostile name closed none of them.
    let opened = page.matches("<script").count();
    assert_eq!(page.matches("</script>").count(), opened);
    assert_eq!(opened, 3 + html::VENDORED.len());
    // The data reads back as the graph itself.
    let start = page
        .find("<script type=\"application/json\" id=\"acsg-data\">")
        .unwrap();
    let body = &page[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</script>").unwrap()];
    let data: Value = serde_json::from_str(body).unwrap();
    let back: GraphFile = serde_json::from_value(data["graph"].clone()).unwrap();
    assert_eq!(back, graph);
    assert_eq!(data["layout"].as_array().unwrap().len(), 4);
    // The title is escaped too, and nothing is fetched from elsewhere.
    assert!(
        page.contains(
            "<title>acsg: parts/&quot;odd&quot; &lt;name&gt; &amp; &apos;quotes&apos;\\.off / &lt;/script&gt;"
        )
    );
    for remote in ["src=\"http", "href=\"http", "src=\"//", "@import", "<link "] {
        assert!(!page.contains(remote), "{remote}");
    }
}

#[test]
fn layered_layout_puts_more_constrained_states_lower_and_wraps_wide_layers() {
    let graph = small();
    let p = layered_layout(&graph);
    assert_eq!(p, layered_layout(&graph));
    // Free space on top, then DOF 5, 4, 3 below one another.
    assert!(p[0][1] < p[1][1] && p[1][1] < p[2][1] && p[2][1] < p[3][1], "{p:?}");

    // 400 single-contact states: the layer wraps onto rows instead of one long line.
    let mut value = small_json();
    let state = value["states"][1].clone();
    let mut states = vec![value["states"][0].clone()];
    for id in 1..=400 {
        let mut s = state.clone();
        s["id"] = json!(id);
        states.push(s);
    }
    value["states"] = json!(states);
    value["edges"] = json!((1..=400).map(|i| [0, i]).collect::<Vec<_>>());
    let wide = GraphFile::from_json(&value.to_string(), "wide.json").unwrap();
    let p = layered_layout(&wide);
    let xs: Vec<f64> = p.iter().map(|q| q[0]).collect();
    let ys: Vec<f64> = p.iter().map(|q| q[1]).collect();
    let width = xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
    let height = ys.iter().cloned().fold(f64::MIN, f64::max) - ys.iter().cloned().fold(f64::MAX, f64::min);
    assert!(p.iter().flatten().all(|x| x.is_finite()));
    assert!(width < 3.0 * height, "width {width}, height {height}");
    // No two states share a position.
    let mut seen: Vec<(i64, i64)> = p
        .iter()
        .map(|q| ((q[0] * 100.0) as i64, (q[1] * 100.0) as i64))
        .collect();
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), 401);
}

fn error_of(text: &str) -> String {
    let err: ExportError = GraphFile::from_json(text, "in/put.json").expect_err(text);
    let message = err.to_string();
    assert!(message.starts_with("in/put.json: "), "{message}");
    message
}

#[test]
fn bad_files_are_refused_with_the_reason_and_the_file_name() {
    assert!(error_of("").contains("empty file"));
    assert!(error_of("  \n").contains("empty file"));
    assert!(error_of("{\"format\": ").contains("not JSON"));
    assert!(error_of("ply\nformat ascii 1.0").contains("not JSON"));
    assert!(error_of("[1, 2]").contains("expected a JSON object with \"format\": \"acsg-graph/1\""));
    assert!(error_of("{\"states\": []}").contains("no \"format\" key"));
    assert!(
        error_of("{\"format\": \"acsg-graph/2\"}")
            .contains("format \"acsg-graph/2\", but this version of acsg reads \"acsg-graph/1\"")
    );
    assert!(error_of("{\"format\": \"acsg-graph/1\"}").contains("missing field"));

    let broken = |edit: &dyn Fn(&mut Value)| {
        let mut value = small_json();
        edit(&mut value);
        error_of(&value.to_string())
    };
    assert!(broken(&|v| v["edges"][0] = json!([0, 9])).contains("inconsistent graph: edge [0, 9]"));
    assert!(broken(&|v| v["states"][2]["id"] = json!(7)).contains("states[2] has id 7"));
    assert!(
        broken(&|v| v["states"][1]["contacts"][0]["moving"] = json!("v9"))
            .contains("contact f-v f3 v9 names v9, which the moving part does not have")
    );
    assert!(broken(&|v| v["states"][1]["contacts"][0]["fixed"] = json!("x3")).contains("bad element id \"x3\""));
    assert!(broken(&|v| v["states"][1]["contacts"][0]["type"] = json!("f-q")).contains("unknown variant"));
    assert!(
        broken(&|v| v["fixed"]["faces"][0] = json!([[0, 2, 7]])).contains("fixed part: face f0 names a missing vertex")
    );
    assert!(
        broken(&|v| v["moving"]["edges"][5] = json!([2, 4])).contains("moving part: edge e5 names a missing vertex")
    );

    let missing = GraphFile::from_path(std::path::Path::new("no/such/graph.json")).unwrap_err();
    assert!(
        missing
            .to_string()
            .starts_with("no/such/graph.json: cannot read the graph"),
        "{missing}"
    );
}

/// Says, past the test harness's capture of `eprintln!` (a direct write to stderr is
/// not captured), that a check was skipped: `cargo test` then shows the line even
/// though the test is reported "ok".
fn skipped(what: &str, why: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED {what}: {why}");
}

#[test]
fn node_link_has_numeric_attributes() {
    let text = node_link::to_node_link(&small());
    let v: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["directed"], false);
    assert_eq!(v["multigraph"], false);
    let nodes = v["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 4);
    assert_eq!(nodes[0]["id"], 0);
    assert_eq!(nodes[0]["witness"], Value::Null);
    assert_eq!(nodes[0]["n_contacts"], 0);
    assert_eq!(nodes[3]["contacts"], json!([["e-e", "e5", "e0"], ["v-v", "v3", "v2"]]));
    assert_eq!(nodes[3]["dof"], 3);
    assert_eq!(nodes[3]["degenerate"], true);
    assert_eq!(nodes[3]["witness"], json!([-1.0, 0.125, 1.0, 0.0, -0.05, 0.0]));
    assert_eq!(nodes[3]["matrix"][0], json!([1.0, 0.0, 0.0, -1.0]));
    let links: Vec<[u64; 2]> = v["links"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| [l["source"].as_u64().unwrap(), l["target"].as_u64().unwrap()])
        .collect();
    assert_eq!(links, [[0, 1], [1, 2], [1, 3], [2, 3]]);
    assert_eq!(v["graph"]["moving"], "tet.off");
    assert_eq!(v["graph"]["units"]["angle"], "radians");
}

/// Numbers read back from a graph's JSON are exactly the numbers written (the last
/// digit too), so exports agree with the JSON: 500 pseudo-random doubles of every
/// magnitude as witness poses, through text and back, bit for bit.
#[test]
fn witnesses_read_back_exactly() {
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let mantissa = (seed >> 11) as f64 / (1u64 << 53) as f64;
        let exponent = ((seed % 13) as i32) - 8;
        (mantissa - 0.5) * 10f64.powi(exponent)
    };
    let mut doc = small_json();
    let mut written = Vec::new();
    for _ in 0..125 {
        for state in 1..4 {
            let pose: [f64; 6] = std::array::from_fn(|_| next());
            doc["states"][state]["witness"]["pose"] = json!(pose);
            written.push((state, pose));
        }
        let text = serde_json::to_string(&doc).unwrap();
        let file = GraphFile::from_json(&text, "random.json").unwrap();
        let node_link: Value = serde_json::from_str(&node_link::to_node_link(&file)).unwrap();
        for &(state, pose) in &written[written.len() - 3..] {
            let read = file.states[state].witness.as_ref().unwrap().pose;
            assert_eq!(
                read.map(f64::to_bits),
                pose.map(f64::to_bits),
                "{pose:?} read as {read:?}"
            );
            let exported: Vec<f64> = node_link["nodes"][state]["witness"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(exported, pose);
        }
    }
}
