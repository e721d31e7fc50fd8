//! GraphML, for Gephi, yEd, Cytoscape desktop and `networkx.read_graphml`.

use std::fmt::Write as _;

use super::{GraphFile, contacts_text, witness_text, xml_escape};

/// The attributes declared for nodes: (id and name, GraphML type).
const NODE_KEYS: [(&str, &str); 6] = [
    ("label", "string"),
    ("contacts", "string"),
    ("n_contacts", "int"),
    ("dof", "int"),
    ("degenerate", "boolean"),
    ("witness", "string"),
];

/// The witness pose as numbers, one attribute per component (radians for angles).
const POSE_KEYS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// The witness placement as numbers: the top three rows of its 4x4 matrix, `m<row><col>`
/// (the last row is always 0 0 0 1).
const MATRIX_KEYS: [&str; 12] = [
    "m00", "m01", "m02", "m03", "m10", "m11", "m12", "m13", "m20", "m21", "m22", "m23",
];

/// The attributes declared for the graph.
const GRAPH_KEYS: [&str; 4] = ["format", "convention", "fixed", "moving"];

/// The graph in GraphML: an undirected graph with one node per state (id `s<id>`)
/// and one edge per neighbour pair. Nodes carry `label` (`S<id>`), `contacts`
/// (`; `-separated, e.g. `f-f f1 f0; f-v f2 v3`), `n_contacts`, `dof`, `degenerate`
/// and `witness` (`x,y,z,rx,ry,rz` in radians, absent without one), and the witness as
/// numbers (`double`): `x`, `y`, `z`, `rx`, `ry`, `rz` and its placement's matrix
/// entries `m00` .. `m23` (row, column; the last row is 0 0 0 1); the graph carries the
/// format, the pose convention and the parts' paths. Numbers are written so that they
/// read back exactly.
///
/// ```
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// let bounds = acsg::pose::Bounds::try_new([-1.0, -1.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 5.0, 0.0, 0.0, 0.0])?;
/// let options = acsg::graph::Options::default();
/// let graph = acsg::graph::generate(&slab, &cube, &bounds, &options);
/// let document = acsg::graph::Document::new(&graph, &slab, &cube, &bounds, &options, ["slab.off", "cube.off"]);
/// let xml = acsg::export::graphml::to_graphml(&acsg::export::GraphFile::from_document(&document));
/// assert_eq!(xml.matches("<node ").count(), graph.states.len());
/// assert_eq!(xml.matches("<edge ").count(), graph.edges.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn to_graphml(graph: &GraphFile) -> String {
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(
        "<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\" \
         xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
         xsi:schemaLocation=\"http://graphml.graphdrawing.org/xmlns \
         http://graphml.graphdrawing.org/xmlns/1.0/graphml.xsd\">\n",
    );
    for name in GRAPH_KEYS {
        let _ = writeln!(
            out,
            "  <key id=\"{name}\" for=\"graph\" attr.name=\"{name}\" attr.type=\"string\"/>"
        );
    }
    for (name, kind) in NODE_KEYS {
        let _ = writeln!(
            out,
            "  <key id=\"{name}\" for=\"node\" attr.name=\"{name}\" attr.type=\"{kind}\"/>"
        );
    }
    for name in POSE_KEYS.iter().chain(&MATRIX_KEYS) {
        let _ = writeln!(
            out,
            "  <key id=\"{name}\" for=\"node\" attr.name=\"{name}\" attr.type=\"double\"/>"
        );
    }
    out.push_str("  <graph id=\"acsg\" edgedefault=\"undirected\">\n");
    for (name, value) in
        GRAPH_KEYS
            .iter()
            .zip([&graph.format, &graph.convention, &graph.fixed.path, &graph.moving.path])
    {
        let _ = writeln!(out, "    <data key=\"{name}\">{}</data>", xml_escape(value));
    }
    for state in &graph.states {
        let _ = writeln!(out, "    <node id=\"s{}\">", state.id);
        let mut data = |key: &str, value: &str| {
            let _ = writeln!(out, "      <data key=\"{key}\">{}</data>", xml_escape(value));
        };
        data("label", &format!("S{}", state.id));
        data("contacts", &contacts_text(state));
        data("n_contacts", &state.contacts.len().to_string());
        data("dof", &state.dof.to_string());
        data("degenerate", if state.degenerate { "true" } else { "false" });
        if let Some(witness) = witness_text(state) {
            data("witness", &witness);
        }
        if let Some(w) = &state.witness {
            for (key, value) in POSE_KEYS.iter().zip(w.pose) {
                data(key, &format!("{value:?}"));
            }
            let entries = w.matrix.iter().take(3).flatten();
            for (key, value) in MATRIX_KEYS.iter().zip(entries) {
                data(key, &format!("{value:?}"));
            }
        }
        out.push_str("    </node>\n");
    }
    for (k, [a, b]) in graph.edges.iter().enumerate() {
        let _ = writeln!(out, "    <edge id=\"edge{k}\" source=\"s{a}\" target=\"s{b}\"/>");
    }
    out.push_str("  </graph>\n</graphml>\n");
    out
}
