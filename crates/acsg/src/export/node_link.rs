//! Node-link JSON: what `networkx.node_link_graph` reads (and d3 and other JavaScript
//! graph tools), with numeric attributes: the witness as 6 numbers and its 4x4 matrix
//! as nested arrays.

use serde_json::{Value, json};

use super::GraphFile;

/// The graph as node-link JSON: `{"directed": false, "multigraph": false, "graph":
/// {...}, "nodes": [...], "links": [...]}`. Each node has the state's `id` and `dof`,
/// `degenerate`, `n_contacts`, `contacts` (`[type, fixed, moving]` triples, e.g.
/// `["f-v", "f3", "v7"]`), `witness` (x, y, z, rx, ry, rz in radians, or null) and
/// `matrix` (the witness placement, row-major 4x4, or null); each link joins two
/// neighbour states by id. The graph carries the format, the pose convention, the
/// units, the parts' paths, the bounds and whether the graph is complete. The numbers
/// are those of the graph's JSON, written so that they read back exactly.
///
/// ```
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// let bounds = acsg::pose::Bounds::try_new([-1.0, -1.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 5.0, 0.0, 0.0, 0.0])?;
/// let options = acsg::graph::Options::default();
/// let graph = acsg::graph::generate(&slab, &cube, &bounds, &options);
/// let document = acsg::graph::Document::new(&graph, &slab, &cube, &bounds, &options, ["slab.off", "cube.off"]);
/// let text = acsg::export::node_link::to_node_link(&acsg::export::GraphFile::from_document(&document));
/// let value: serde_json::Value = serde_json::from_str(&text)?;
/// assert_eq!(value["nodes"].as_array().map(Vec::len), Some(graph.states.len()));
/// assert_eq!(value["links"].as_array().map(Vec::len), Some(graph.edges.len()));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn to_node_link(graph: &GraphFile) -> String {
    let nodes: Vec<Value> = graph
        .states
        .iter()
        .map(|state| {
            let contacts: Vec<Value> = state
                .contacts
                .iter()
                .map(|c| json!([c.kind.label(), c.fixed, c.moving]))
                .collect();
            json!({
                "id": state.id,
                "dof": state.dof,
                "degenerate": state.degenerate,
                "n_contacts": state.contacts.len(),
                "contacts": contacts,
                "witness": state.witness.as_ref().map(|w| w.pose),
                "matrix": state.witness.as_ref().map(|w| w.matrix),
            })
        })
        .collect();
    let links: Vec<Value> = graph
        .edges
        .iter()
        .map(|[a, b]| json!({"source": a, "target": b}))
        .collect();
    let value = json!({
        "directed": false,
        "multigraph": false,
        "graph": {
            "format": graph.format,
            "convention": graph.convention,
            "units": graph.units,
            "fixed": graph.fixed.path,
            "moving": graph.moving.path,
            "bounds": graph.bounds,
            "complete": graph.complete,
        },
        "nodes": nodes,
        "links": links,
    });
    // Plain values (numbers, strings, arrays): serialising cannot fail.
    let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
    text.push('\n');
    text
}
