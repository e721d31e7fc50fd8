//! A self-contained HTML report: the run summary, the graph (cytoscape.js), the
//! selected state's witness pose in 3D (three.js) and a searchable table of states.
//!
//! The page needs no network: the vendored libraries (`assets/vendor/`, see
//! `VENDORED.md` there), the page's own script and style (`assets/report/`) and the
//! graph's data are all inlined.

use serde::Serialize;

use super::{GraphFile, layered_layout};

const TEMPLATE: &str = include_str!("../../assets/report/report.html");
const STYLE: &str = include_str!("../../assets/report/report.css");
const SCRIPT: &str = include_str!("../../assets/report/report.js");

/// The vendored libraries, in load order: (file name, source).
pub const VENDORED: [(&str, &str); 3] = [
    ("three.min.js", include_str!("../../assets/vendor/three.min.js")),
    ("OrbitControls.js", include_str!("../../assets/vendor/OrbitControls.js")),
    ("cytoscape.min.js", include_str!("../../assets/vendor/cytoscape.min.js")),
];

/// What the page's script reads.
#[derive(Serialize)]
struct PageData<'a> {
    generator: &'static str,
    graph: &'a GraphFile,
    /// Preset node positions (see [`layered_layout`]).
    layout: Vec<[f64; 2]>,
}

/// The report of a graph: one HTML file that opens offline in any recent browser.
///
/// The page embeds the graph's JSON (with `<` written `\u003c`, so nothing in it can
/// close the `<script>` holding it). After drawing, it writes the results of a self
/// check into a hidden `<pre id="acsg-selftest">` (JSON: number of graph nodes and
/// states, whether the 3D view drew, errors seen); the browser test reads it.
///
/// ```
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// let bounds = acsg::pose::Bounds::try_new([-1.0, -1.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 5.0, 0.0, 0.0, 0.0])?;
/// let options = acsg::graph::Options::default();
/// let graph = acsg::graph::generate(&slab, &cube, &bounds, &options);
/// let document = acsg::graph::Document::new(&graph, &slab, &cube, &bounds, &options, ["slab.off", "cube.off"]);
/// let page = acsg::export::html::to_html(&acsg::export::GraphFile::from_document(&document));
/// assert!(page.starts_with("<!DOCTYPE html>"));
/// assert!(!page.contains("src=\"http") && !page.contains("href=\"http"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn to_html(graph: &GraphFile) -> String {
    let data = PageData {
        generator: concat!("acsg ", env!("CARGO_PKG_VERSION")),
        graph,
        layout: layered_layout(graph),
    };
    // Numbers, strings and arrays only: serialising cannot fail.
    let json = serde_json::to_string(&data).expect("the page data serialises");
    let title = format!("acsg: {} / {}", graph.fixed.path, graph.moving.path);
    let vendor: String = VENDORED
        .iter()
        .map(|(name, source)| {
            format!(
                "<script>/* {name} (see VENDORED.md) */\n{}\n</script>\n",
                script_safe(source)
            )
        })
        .collect();
    fill(
        TEMPLATE,
        &[
            ("{{TITLE}}", &super::xml_escape(&title)),
            ("{{STYLE}}", STYLE),
            ("{{VENDOR}}", &vendor),
            ("{{DATA}}", &json_in_script(&json)),
            ("{{SCRIPT}}", &script_safe(SCRIPT)),
        ],
    )
}

/// JSON text made safe inside `<script type="application/json">`: every `<` becomes
/// `\u003c` (still the same JSON value), so no `</script>` or `<!--` can appear.
fn json_in_script(json: &str) -> String {
    json.replace('<', "\\u003c")
}

/// JavaScript source made safe inside `<script>`: a `</script` in it (there is none
/// in the vendored files today) would end the element early; `<\/script` means the
/// same in JavaScript strings and regular expressions.
fn script_safe(source: &str) -> std::borrow::Cow<'_, str> {
    if source.to_ascii_lowercase().contains("</script") {
        let mut out = String::with_capacity(source.len());
        let lower = source.to_ascii_lowercase();
        let mut last = 0;
        for (at, _) in lower.match_indices("</script") {
            out.push_str(&source[last..at]);
            out.push_str("<\\/");
            last = at + 2;
        }
        out.push_str(&source[last..]);
        std::borrow::Cow::Owned(out)
    } else {
        std::borrow::Cow::Borrowed(source)
    }
}

/// The template with each marker replaced once, scanning only the template (so text
/// that is inserted is never searched for markers).
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len() + values.iter().map(|(_, v)| v.len()).sum::<usize>());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        let Some((marker, value)) = values.iter().find(|(m, _)| rest[start..].starts_with(m)) else {
            out.push_str(&rest[..start + 2]);
            rest = &rest[start + 2..];
            continue;
        };
        out.push_str(&rest[..start]);
        out.push_str(value);
        rest = &rest[start + marker.len()..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_json_cannot_close_its_script() {
        let text = json_in_script(r#"{"path":"</script><!-- x"}"#);
        assert!(!text.contains('<'));
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back["path"], "</script><!-- x");
    }

    #[test]
    fn scripts_with_a_closing_tag_are_escaped() {
        assert_eq!(
            script_safe("a='</SCRIPT>';b='</script'"),
            "a='<\\/SCRIPT>';b='<\\/script'"
        );
        assert!(matches!(script_safe("plain"), std::borrow::Cow::Borrowed(_)));
    }

    #[test]
    fn fill_replaces_markers_in_the_template_only() {
        let out = fill("a {{X}} b {{Y}} {{unknown}}", &[("{{X}}", "{{Y}}"), ("{{Y}}", "y")]);
        assert_eq!(out, "a {{Y}} b y {{unknown}}");
    }

    #[test]
    fn vendored_libraries_and_page_script_are_inlined_whole() {
        for (name, source) in VENDORED {
            assert!(source.len() > 10_000, "{name} looks truncated");
            assert!(!source.to_ascii_lowercase().contains("</script"), "{name}");
        }
        for marker in ["{{TITLE}}", "{{STYLE}}", "{{VENDOR}}", "{{DATA}}", "{{SCRIPT}}"] {
            assert_eq!(TEMPLATE.matches(marker).count(), 1, "{marker}");
        }
    }
}
