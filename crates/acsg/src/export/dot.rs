//! Graphviz DOT: `dot -Tsvg graph.dot -o graph.svg`.

use std::fmt::Write as _;

use super::{GraphFile, contact_text, witness_text};

/// The graph in Graphviz DOT: an undirected graph with one node per state (id
/// `s<id>`), laid out in ranks by [`layer`](super::layer), 6 − DOF (free space on top), and one edge
/// per neighbour pair. Each node carries `label` (the id and its contacts, one per
/// line), `contacts` (`; `-separated), `n_contacts`, `dof`, `degenerate` and `witness`
/// (`x,y,z,rx,ry,rz` in radians, absent without one) as attributes; the graph carries
/// the parts' paths and the format.
///
/// ```
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// let bounds = acsg::pose::Bounds::try_new([-1.0, -1.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 5.0, 0.0, 0.0, 0.0])?;
/// let options = acsg::graph::Options::default();
/// let graph = acsg::graph::generate(&slab, &cube, &bounds, &options);
/// let document = acsg::graph::Document::new(&graph, &slab, &cube, &bounds, &options, ["slab.off", "cube.off"]);
/// let dot = acsg::export::dot::to_dot(&acsg::export::GraphFile::from_document(&document));
/// assert!(dot.starts_with("graph acsg {"));
/// assert_eq!(dot.matches(" -- ").count(), graph.edges.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn to_dot(graph: &GraphFile) -> String {
    let mut out = String::new();
    let q = quote;
    let _ = writeln!(out, "graph acsg {{");
    let _ = writeln!(
        out,
        "  graph [format={}, fixed={}, moving={}, states={}, edges={}, rankdir=TB];",
        q(&graph.format),
        q(&graph.fixed.path),
        q(&graph.moving.path),
        graph.states.len(),
        graph.edges.len()
    );
    let _ = writeln!(out, "  node [shape=box, style=rounded, fontname=Helvetica];");
    for state in &graph.states {
        let mut label = format!("S{}", state.id);
        if state.contacts.is_empty() {
            label.push_str("\nfree space");
        }
        for contact in &state.contacts {
            label.push('\n');
            label.push_str(&contact_text(contact));
        }
        let _ = write!(
            out,
            "  s{} [label={}, contacts={}, n_contacts={}, dof={}, degenerate={}",
            state.id,
            q(&label),
            q(&super::contacts_text(state)),
            state.contacts.len(),
            state.dof,
            state.degenerate
        );
        if let Some(witness) = witness_text(state) {
            let _ = write!(out, ", witness={}", q(&witness));
        }
        let _ = writeln!(out, "];");
    }
    // Same rank for the same DOF: the picture reads from free space down to the most
    // constrained states.
    let mut ranks: std::collections::BTreeMap<usize, Vec<usize>> = std::collections::BTreeMap::new();
    for state in &graph.states {
        ranks.entry(super::layer(state)).or_default().push(state.id);
    }
    for (layer, ids) in &ranks {
        let nodes: Vec<String> = ids.iter().map(|id| format!("s{id}")).collect();
        let _ = writeln!(out, "  {{ rank=same; /* DOF {} */ {}; }}", 6 - layer, nodes.join("; "));
    }
    for [a, b] in &graph.edges {
        let _ = writeln!(out, "  s{a} -- s{b};");
    }
    out.push_str("}\n");
    out
}

/// A DOT double-quoted string: `"` and `\` escaped, newlines as `\n` (a centred line
/// break in labels).
fn quote(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => {}
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::quote;

    #[test]
    fn quoting_escapes_quotes_backslashes_and_newlines() {
        assert_eq!(quote("a \"b\"\\c\nd"), "\"a \\\"b\\\"\\\\c\\nd\"");
    }
}
