//! Reading a graph's JSON back ([`GraphFile`]) and writing it for people and other
//! tools: a self-contained HTML report ([`html`]), Graphviz DOT ([`dot`]), GraphML
//! ([`graphml`], for Gephi, yEd, networkx) and node-link JSON ([`node_link`], for
//! `networkx.node_link_graph` and d3).
//!
//! Every writer is a pure function of a [`GraphFile`] and gives the same bytes for the
//! same graph.

use std::path::Path;

use crate::graph::document::{Document, FORMAT, StateRecord};
use crate::model::{ElementId, PartElements};

pub mod dot;
pub mod graphml;
pub mod html;
pub mod node_link;

/// Errors of reading a graph's JSON.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The file could not be read.
    #[error("{path}: cannot read the graph: {source}")]
    Read {
        /// The file, as given.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file is empty.
    #[error("{path}: empty file (expected a graph written by `acsg generate`, `run` or `demo`, format {FORMAT})")]
    Empty {
        /// The file, as given.
        path: String,
    },
    /// The file is not JSON.
    #[error("{path}: not JSON ({source}); expected a graph written by `acsg generate`, `run` or `demo`")]
    NotJson {
        /// The file, as given.
        path: String,
        /// The parser's message, with line and column.
        source: serde_json::Error,
    },
    /// JSON, but not a graph of the format this version reads.
    #[error("{path}: not an acsg graph: {problem}")]
    NotGraph {
        /// The file, as given.
        path: String,
        /// What is wrong, and what was expected.
        problem: String,
    },
    /// A graph whose parts refer to one another inconsistently (an edge to a missing
    /// state, a contact with a missing face, ...).
    #[error("{path}: inconsistent graph: {problem}")]
    Inconsistent {
        /// The file, as given.
        path: String,
        /// The first inconsistency found.
        problem: String,
    },
}

/// A graph as read from its JSON (format [`FORMAT`], `schema/graph.schema.json`),
/// checked for consistency: state ids are their indices, edges join existing states,
/// and every element named by a contact, edge or face exists.
pub type GraphFile = Document;

impl GraphFile {
    /// Reads and checks a graph file; errors name the file.
    ///
    /// # Errors
    /// [`ExportError`]: unreadable, empty, not JSON, another format, inconsistent.
    pub fn from_path(path: &Path) -> Result<GraphFile, ExportError> {
        let name = path.display().to_string();
        let read = |source| ExportError::Read {
            path: name.clone(),
            source,
        };
        let bytes = crate::io::read_capped(path, crate::io::max_input_bytes()).map_err(|e| match e {
            crate::io::CappedReadError::Io(source) => read(source),
            crate::io::CappedReadError::TooLarge(_) => read(std::io::Error::other(format!(
                "larger than the {}-byte input limit",
                crate::io::max_input_bytes()
            ))),
        })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            read(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "not UTF-8 text (byte {}); expected a graph written by `acsg generate`, `run` or `demo`",
                    e.utf8_error().valid_up_to()
                ),
            ))
        })?;
        GraphFile::from_json(&text, &name)
    }

    /// Parses and checks a graph's JSON text; `name` (the file's path) is used in
    /// messages.
    ///
    /// # Errors
    /// [`ExportError`]: empty, not JSON, another format, inconsistent.
    pub fn from_json(text: &str, name: &str) -> Result<GraphFile, ExportError> {
        let path = || name.to_string();
        // A byte-order mark, as some editors write, is not part of the JSON.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        if text.trim().is_empty() {
            return Err(ExportError::Empty { path: path() });
        }
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|source| ExportError::NotJson { path: path(), source })?;
        let Some(object) = value.as_object() else {
            return Err(ExportError::NotGraph {
                path: path(),
                problem: format!("expected a JSON object with \"format\": \"{FORMAT}\""),
            });
        };
        match object.get("format") {
            Some(serde_json::Value::String(found)) if found == FORMAT => {}
            Some(found) => {
                return Err(ExportError::NotGraph {
                    path: path(),
                    problem: format!(
                        "format {found}, but this version of acsg reads \"{FORMAT}\" (regenerate the graph with it)"
                    ),
                });
            }
            None => {
                return Err(ExportError::NotGraph {
                    path: path(),
                    problem: format!("no \"format\" key (expected \"format\": \"{FORMAT}\")"),
                });
            }
        }
        let graph: GraphFile = serde_json::from_value(value).map_err(|e| ExportError::NotGraph {
            path: path(),
            problem: format!("{e} (see schema/graph.schema.json)"),
        })?;
        graph
            .check()
            .map_err(|problem| ExportError::Inconsistent { path: path(), problem })?;
        Ok(graph)
    }

    /// The graph of a document just generated (no file involved).
    #[must_use]
    pub fn from_document(document: &Document) -> GraphFile {
        document.clone()
    }

    /// The first inconsistency, if any.
    fn check(&self) -> Result<(), String> {
        for (role, part) in [("fixed", &self.fixed), ("moving", &self.moving)] {
            check_part(part).map_err(|e| format!("{role} part: {e}"))?;
        }
        let lengths = ["mm", "cm", "m", "in", crate::units::UNSPECIFIED];
        if !lengths.contains(&self.units.length.as_str()) || self.units.angle != "radians" {
            return Err(format!(
                "units {{\"length\": {:?}, \"angle\": {:?}}}: lengths must be one of {lengths:?} and angles \"radians\"",
                self.units.length, self.units.angle
            ));
        }
        let finite = |m: &[[f64; 4]; 4]| m.iter().flatten().all(|x| x.is_finite());
        if !finite(&self.assembled) {
            return Err("the assembled pose has a non-finite entry".into());
        }
        for (index, state) in self.states.iter().enumerate() {
            if state.id != index {
                return Err(format!("states[{index}] has id {}", state.id));
            }
            let bad_witness = state
                .witness
                .as_ref()
                .is_some_and(|w| !finite(&w.matrix) || w.pose.iter().any(|x| !x.is_finite()));
            if bad_witness {
                return Err(format!("state {index}: the witness has a non-finite entry"));
            }
            if state.dof > 6 {
                return Err(format!(
                    "state {index} has dof {}, but a rigid part has at most 6",
                    state.dof
                ));
            }
            for contact in &state.contacts {
                check_contact(contact).map_err(|e| format!("state {index}: {e}"))?;
                for (role, part, element) in [
                    ("fixed", &self.fixed, contact.fixed),
                    ("moving", &self.moving, contact.moving),
                ] {
                    if !element_exists(part, element) {
                        return Err(format!(
                            "state {index}: contact {} names {element}, which the {role} part does not have",
                            contact_text(contact)
                        ));
                    }
                }
            }
        }
        let mut seen = std::collections::HashSet::new();
        for &[a, b] in &self.edges {
            if a >= self.states.len() || b >= self.states.len() || a == b {
                return Err(format!(
                    "edge [{a}, {b}] does not join two of the {} states",
                    self.states.len()
                ));
            }
            if !seen.insert((a.min(b), a.max(b))) {
                return Err(format!("edge [{a}, {b}] is listed twice"));
            }
        }
        for (index, undecided) in self.undecided.iter().enumerate() {
            for contact in &undecided.contacts {
                check_contact(contact).map_err(|e| format!("undecided candidate {index}: {e}"))?;
            }
        }
        Ok(())
    }
}

/// A contact's elements are of the kinds its type names (`f-v`: a face of the fixed
/// part, a vertex of the moving part), and its DOF is the one of its type.
fn check_contact(contact: &crate::contact::ContactRecord) -> Result<(), String> {
    let label = contact.kind.label();
    let mut letters = label.split('-').filter_map(|p| p.chars().next());
    let (Some(want_fixed), Some(want_moving)) = (letters.next(), letters.next()) else {
        return Ok(());
    };
    let letter = |e: ElementId| match e {
        ElementId::Face(_) => 'f',
        ElementId::Edge(_) => 'e',
        ElementId::Vertex(_) => 'v',
    };
    let noun = |c: char| match c {
        'f' => "face",
        'e' => "edge",
        _ => "vertex",
    };
    for (role, want, element) in [
        ("fixed", want_fixed, contact.fixed),
        ("moving", want_moving, contact.moving),
    ] {
        if letter(element) != want {
            return Err(format!(
                "contact {} names {element} as the {role} element, but a {label} contact needs a {}",
                contact_text(contact),
                noun(want)
            ));
        }
    }
    let dof = crate::contact::PrincipalContact {
        fixed: contact.fixed,
        moving: contact.moving,
        kind: contact.kind,
    }
    .dof();
    if contact.dof != dof {
        return Err(format!(
            "contact {} has dof {}, but a {label} contact leaves {dof}",
            contact_text(contact),
            contact.dof
        ));
    }
    Ok(())
}

fn check_part(part: &PartElements) -> Result<(), String> {
    let n = part.vertices.len();
    if part.vertices.iter().flatten().any(|x| !x.is_finite()) {
        return Err("a vertex has a non-finite coordinate".into());
    }
    if part.convex_vertices.len() != n
        || part.convex_edges.len() != part.edges.len()
        || part.face_normals.len() != part.faces.len()
    {
        return Err("the convexity or normal arrays do not match the element arrays".into());
    }
    for (e, edge) in part.edges.iter().enumerate() {
        if edge.iter().any(|&v| v as usize >= n) {
            return Err(format!("edge e{e} names a missing vertex"));
        }
    }
    for (f, face) in part.faces.iter().enumerate() {
        if face.is_empty() || face.iter().any(|l| l.len() < 3) {
            return Err(format!("face f{f} has a loop of fewer than three vertices"));
        }
        if face.iter().flatten().any(|&v| v as usize >= n) {
            return Err(format!("face f{f} names a missing vertex"));
        }
    }
    Ok(())
}

fn element_exists(part: &PartElements, element: ElementId) -> bool {
    match element {
        ElementId::Face(f) => f.index() < part.faces.len(),
        ElementId::Edge(e) => e.index() < part.edges.len(),
        ElementId::Vertex(v) => v.index() < part.vertices.len(),
    }
}

/// One contact as text: `f-v f3 v7` (kind, fixed element, moving element).
#[must_use]
pub(crate) fn contact_text(contact: &crate::contact::ContactRecord) -> String {
    format!("{} {} {}", contact.kind.label(), contact.fixed, contact.moving)
}

/// A state's contacts as text, `; `-separated (`f-f f1 f0; f-v f2 v3`); empty for free
/// space.
#[must_use]
pub(crate) fn contacts_text(state: &StateRecord) -> String {
    state.contacts.iter().map(contact_text).collect::<Vec<_>>().join("; ")
}

/// A state's witness pose as `x,y,z,rx,ry,rz` (radians), the form `acsg contacts --radians
/// --pose` reads; `None` without a witness.
#[must_use]
pub(crate) fn witness_text(state: &StateRecord) -> Option<String> {
    state
        .witness
        .as_ref()
        .map(|w| w.pose.iter().map(|x| format!("{x}")).collect::<Vec<_>>().join(","))
}

/// A state's layer in drawings: how constrained it is, 6 − DOF (free space 0, a
/// vertex on a face 1, an edge on a face 2, a face on a face 3, ...). Neighbours
/// differ by one primitive contact, so edges mostly join consecutive layers.
#[must_use]
pub fn layer(state: &StateRecord) -> usize {
    6usize.saturating_sub(usize::from(state.dof))
}

/// Node positions of a layered drawing, from free space (top) to the most constrained
/// states (bottom): a state's layer is [`layer`]. Within a layer, states
/// are ordered by the mean position of their neighbours in the layers above (then by
/// id), and a layer wider than a row wraps onto several rows, so that thousands of
/// states still make a compact picture. Deterministic; units are arbitrary (a node
/// is about 1 wide).
#[must_use]
pub fn layered_layout(graph: &GraphFile) -> Vec<[f64; 2]> {
    let n = graph.states.len();
    let mut positions = vec![[0.0; 2]; n];
    if n == 0 {
        return positions;
    }
    let layer_of: Vec<usize> = graph.states.iter().map(layer).collect();
    let layers = layer_of.iter().copied().max().unwrap_or(0) + 1;
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); layers];
    for (id, &layer) in layer_of.iter().enumerate() {
        members[layer].push(id);
    }
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &[a, b] in &graph.edges {
        neighbours[a].push(b);
        neighbours[b].push(a);
    }
    // Wrap layers wider than this onto several rows (about a square picture overall).
    let row = ((n as f64).sqrt() * 1.5).ceil().max(12.0) as usize;
    let (dx, dy) = (1.6, 1.6);
    let mut x_of = vec![f64::NAN; n];
    let mut rows_above = 0usize;
    for ids in &mut members {
        if ids.is_empty() {
            continue;
        }
        // Barycentre of the already-placed neighbours (those in layers above).
        let key = |id: usize| {
            let placed: Vec<f64> = neighbours[id]
                .iter()
                .map(|&m| x_of[m])
                .filter(|x| x.is_finite())
                .collect();
            if placed.is_empty() {
                f64::INFINITY
            } else {
                placed.iter().sum::<f64>() / placed.len() as f64
            }
        };
        let mut keyed: Vec<(f64, usize)> = ids.iter().map(|&id| (key(id), id)).collect();
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let count = keyed.len();
        let rows = count.div_ceil(row);
        for (k, &(_, id)) in keyed.iter().enumerate() {
            let (r, c) = (k / row, k % row);
            let in_row = if r + 1 == rows { count - r * row } else { row };
            // Rows of a wrapped layer are staggered by half a slot for legibility.
            let stagger = if r % 2 == 1 { 0.5 } else { 0.0 };
            let x = (c as f64 - (in_row as f64 - 1.0) / 2.0 + stagger) * dx;
            x_of[id] = x;
            positions[id] = [x, (rows_above + r) as f64 * dy];
        }
        // One empty row between layers.
        rows_above += rows + 1;
    }
    positions
}

/// Escapes text for a double-quoted XML attribute or element content.
pub(crate) fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Characters XML 1.0 cannot hold at all (controls other than tab/newline/CR).
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xml_escape_covers_markup_and_controls() {
        assert_eq!(xml_escape("a<b>&\"c'\u{1}"), "a&lt;b&gt;&amp;&quot;c&apos;\u{fffd}");
    }
}
