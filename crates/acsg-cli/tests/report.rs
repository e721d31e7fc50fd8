//! `acsg report`, `acsg export` and `--html` on the built-in example: the report is
//! loaded in a real headless Chromium (the graph and the 3D view must render, without
//! console errors) and screenshotted; the GraphML is parsed independently.
//!
//! Outside CI the browser test is skipped, with a message, when no Chromium is
//! installed; with `CI` set it fails instead (`.ci/run` installs Debian's chromium).

use std::path::{Path, PathBuf};
use std::process::{Command as Process, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use assert_cmd::Command;
use predicates::str::contains;
use serde_json::Value;

fn acsg() -> Command {
    Command::cargo_bin("acsg").expect("binary built")
}

/// The built-in parts' bounds for these tests: 19 states, 58 edges and an undecided
/// candidate in seconds (the built-in bounds take a minute and a half in the test
/// build; the generation tests run those in full).
const DEMO_BOUNDS: &str = "--bounds=x=-2:2,y=-2:2,z=0:60,rx=-2:2,rz=-2:2";

/// The built-in example within [`DEMO_BOUNDS`], generated once for all tests: (folder,
/// graph JSON). The graph is written under its default name, copied to `demo.json` for
/// the commands that read it.
fn demo() -> &'static (tempfile::TempDir, Value) {
    static DEMO: OnceLock<(tempfile::TempDir, Value)> = OnceLock::new();
    DEMO.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        acsg()
            .current_dir(dir.path())
            .args(["demo", DEMO_BOUNDS, "--html", "demo.html", "--no-timings"])
            .assert()
            .success()
            .stdout(
                contains("card(PPC) 328")
                    .and(contains("wrote acsg-demo.graph.json"))
                    .and(contains("wrote demo.html")),
            );
        std::fs::copy(dir.path().join("acsg-demo.graph.json"), dir.path().join("demo.json")).unwrap();
        let text = std::fs::read_to_string(dir.path().join("demo.json")).unwrap();
        let json: Value = serde_json::from_str(&text).unwrap();
        (dir, json)
    })
}

use predicates::prelude::PredicateBooleanExt;

fn counts(json: &Value) -> (usize, usize) {
    (
        json["states"].as_array().unwrap().len(),
        json["edges"].as_array().unwrap().len(),
    )
}

#[test]
fn report_command_matches_the_html_flag_and_is_self_contained() {
    let (dir, json) = demo();
    acsg()
        .current_dir(dir.path())
        .args(["report", "demo.json"])
        .assert()
        .success()
        .stdout(contains("wrote demo.html"));
    acsg()
        .current_dir(dir.path())
        .args(["report", "demo.json", "-o", "again.html"])
        .assert()
        .success();
    let page = std::fs::read_to_string(dir.path().join("demo.html")).unwrap();
    assert_eq!(page, std::fs::read_to_string(dir.path().join("again.html")).unwrap());
    assert!(page.contains(&format!("\"states\":{}", counts(json).0)));
    for remote in ["src=\"http", "href=\"http", "src=\"//", "<link "] {
        assert!(!page.contains(remote), "the report loads {remote}...");
    }
    eprintln!("report of the built-in example: {} bytes", page.len());
}

/// A minimal XML reader, enough to check GraphML independently of the writer: the
/// document is well formed (every element closed in order), and gives the elements'
/// names with their attributes in document order.
fn xml_elements(text: &str) -> Vec<(String, Vec<(String, String)>)> {
    let mut out = Vec::new();
    let mut open: Vec<String> = Vec::new();
    let mut rest = text;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unclosed tag") + start;
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') || tag.starts_with('!') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(open.pop().as_deref(), Some(name.trim()), "mismatched </{name}>");
            continue;
        }
        let self_closing = tag.ends_with('/');
        let tag = tag.trim_end_matches('/');
        let (name, mut attrs_text) = tag.split_once(char::is_whitespace).unwrap_or((tag, ""));
        let mut attrs = Vec::new();
        loop {
            attrs_text = attrs_text.trim_start();
            if attrs_text.is_empty() {
                break;
            }
            let (key, after) = attrs_text.split_once("=\"").expect("attribute without a quoted value");
            let (value, after) = after.split_once('"').expect("unterminated attribute");
            assert!(!value.contains('<'), "raw < in an attribute");
            attrs.push((key.trim().to_string(), value.to_string()));
            attrs_text = after;
        }
        out.push((name.to_string(), attrs));
        if !self_closing {
            open.push(name.to_string());
        }
    }
    assert!(open.is_empty(), "unclosed elements {open:?}");
    out
}

#[test]
fn graphml_of_the_example_has_every_state_and_edge() {
    let (dir, json) = demo();
    let (states, edges) = counts(json);
    acsg()
        .current_dir(dir.path())
        .args(["export", "demo.json", "--format", "graphml", "-o", "demo.graphml"])
        .assert()
        .success()
        .stdout("");
    let path = dir.path().join("demo.graphml");
    let text = std::fs::read_to_string(&path).unwrap();
    let elements = xml_elements(&text);
    let attr = |attrs: &[(String, String)], key: &str| {
        attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    let nodes: Vec<String> = elements
        .iter()
        .filter(|(n, _)| n == "node")
        .map(|(_, a)| attr(a, "id"))
        .collect();
    let links: Vec<(String, String)> = elements
        .iter()
        .filter(|(n, _)| n == "edge")
        .map(|(_, a)| (attr(a, "source"), attr(a, "target")))
        .collect();
    assert_eq!((nodes.len(), links.len()), (states, edges));
    let mut unique = nodes.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), states, "node ids are unique");
    assert!(links.iter().all(|(a, b)| nodes.contains(a) && nodes.contains(b)));
    for (k, pair) in json["edges"].as_array().unwrap().iter().enumerate() {
        assert_eq!(links[k], (format!("s{}", pair[0]), format!("s{}", pair[1])));
    }

    // networkx, when this Python has it.
    let has_networkx = Process::new("python3")
        .args(["-c", "import networkx"])
        .output()
        .is_ok_and(|o| o.status.success());
    if has_networkx {
        let out = Process::new("python3")
            .args([
                "-c",
                "import sys, networkx as nx; g = nx.read_graphml(sys.argv[1]); \
                 print(g.number_of_nodes(), g.number_of_edges(), nx.is_connected(g))",
            ])
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).trim(),
            format!("{states} {edges} True")
        );
    } else {
        skipped(
            "the networkx check of the GraphML export",
            "python3 with networkx not available (pip install networkx)",
        );
    }
}

#[test]
fn dot_of_the_example_goes_to_stdout_with_every_state_and_edge() {
    let (dir, json) = demo();
    let (states, edges) = counts(json);
    let out = acsg()
        .current_dir(dir.path())
        .args(["export", "demo.json", "--format", "dot"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("graph acsg {") && text.ends_with("}\n"));
    let node_lines = text
        .lines()
        .filter(|l| l.trim_start().starts_with('s') && l.contains(" [label="))
        .count();
    assert_eq!(node_lines, states);
    assert_eq!(text.matches(" -- ").count(), edges);
}

#[test]
fn bad_graph_files_fail_with_exit_1_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let cases = [
        (write("empty.json", ""), "empty file"),
        (write("text.json", "hello"), "not JSON"),
        (
            write("other.json", "{\"format\": \"acsg-graph/0\"}"),
            "this version of acsg reads \"acsg-graph/1\"",
        ),
        (dir.path().join("missing.json"), "cannot read the graph"),
    ];
    for (path, reason) in &cases {
        for args in [
            vec!["report"],
            vec!["export", "--format", "dot"],
            vec!["export", "--format", "graphml"],
        ] {
            acsg()
                .args(&args)
                .arg(path)
                .args(["-o"])
                .arg(dir.path().join("out"))
                .assert()
                .code(1)
                .stderr(contains(path.display().to_string()).and(contains(*reason)));
        }
    }
    assert!(!dir.path().join("out").exists(), "nothing written on failure");
    acsg().args(["export", "x.json", "--format", "svg"]).assert().code(2);
    acsg().args(["report"]).assert().code(2);
}

// ---------------------------------------------------------------- the browser test

fn chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("ACSG_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome", "google-chrome-stable"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|candidate| candidate.is_file())
}

/// Runs Chromium headless on `page` with `extra` flags, stdout to `stdout_file`,
/// killing it after two minutes.
fn run_chromium(browser: &Path, page: &Path, extra: &[String], stdout_file: &Path) -> std::process::ExitStatus {
    let profile = tempfile::tempdir().unwrap();
    let mut child = Process::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--hide-scrollbars",
            // WebGL in software (SwiftShader), as on a machine without a GPU.
            "--use-gl=angle",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--virtual-time-budget=10000",
            "--window-size=1400,900",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(extra)
        .arg(format!("file://{}", page.display()))
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(stdout_file).unwrap())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", browser.display()));
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{} did not finish within two minutes", browser.display());
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn html_unescape(text: &str) -> String {
    text.replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&nbsp;", "\u{a0}")
        .replace("&amp;", "&")
}

#[test]
fn the_report_renders_in_a_real_browser() {
    let Some(browser) = chromium() else {
        if std::env::var_os("CI").is_some() {
            panic!(
                "CI is set but no Chromium was found: .ci/run installs Debian's chromium (apt-get install chromium)"
            );
        }
        skipped(
            "the_report_renders_in_a_real_browser",
            "no chromium on PATH (install it with `apt-get install chromium`, or set ACSG_CHROMIUM)",
        );
        return;
    };
    let (dir, json) = demo();
    let (states, edges) = counts(json);
    let page = dir.path().join("demo.html");

    // 1. The page's own self check, read from the DOM after the page settled.
    let check = self_check(&browser, &page, dir.path());
    eprintln!("browser self check: {check}");
    assert_eq!(check["errors"], serde_json::json!([]), "errors in the page");
    assert_eq!(check["states"], states);
    assert_eq!(check["nodes"], states, "one graph node per state");
    assert_eq!(check["edges"], edges, "one graph edge per neighbour pair");
    assert!(
        check["graph_pixels"].as_u64().unwrap() > 1000,
        "the graph canvas stayed empty"
    );
    assert_eq!(check["webgl"], true, "no WebGL context");
    let [w, h] = [&check["canvas"][0], &check["canvas"][1]].map(|v| v.as_u64().unwrap());
    let drawn = check["drawn_pixels"].as_u64().unwrap();
    assert!(w > 100 && h > 100, "3D canvas {w}x{h}");
    assert!(drawn * 20 > w * h, "the 3D view drew only {drawn} of {w}x{h} pixels");
    assert_eq!(check["table_rows"], states);
    // Readable labels at the first view, axes with the unit, names on hover, and the
    // see-through switch.
    assert!(
        check["label_px"].as_f64().unwrap() >= 9.99,
        "labels of {} px",
        check["label_px"]
    );
    assert_eq!(check["axes"], true);
    assert!(
        check["axes_text"].as_str().unwrap().contains("lengths in mm"),
        "{}",
        check["axes_text"]
    );
    let hover = check["hover_centre"].as_str().unwrap();
    assert!(
        hover.starts_with("fixed part: face f") || hover.starts_with("moving part: face f"),
        "nothing named under the centre of the 3D view: {hover:?}"
    );
    assert_eq!(check["see_through"], true);
    assert_eq!(check["summary_overlaps"], 0);

    // 2. A screenshot, kept under target/ for people to look at.
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("acsg-report-screenshot.png");
    let _ = std::fs::remove_file(&shot);
    let status = run_chromium(
        &browser,
        &page,
        &[format!("--screenshot={}", shot.display())],
        &dir.path().join("screenshot.log"),
    );
    assert!(status.success(), "chromium --screenshot failed: {status}");
    let png = std::fs::read(&shot).expect("a screenshot was written");
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    assert!(png.len() > 20_000, "screenshot of {} bytes: a blank page?", png.len());
    eprintln!("screenshot: {}", shot.display());
}

/// The page's own self check (`#acsg-selftest`), read from the DOM after it settled.
fn self_check(browser: &Path, page: &Path, dir: &Path) -> Value {
    let dom_file = dir.join("dom.html");
    let status = run_chromium(browser, page, &["--dump-dom".to_string()], &dom_file);
    assert!(status.success(), "chromium --dump-dom failed: {status}");
    let dom = std::fs::read_to_string(&dom_file).unwrap();
    let start = dom
        .find("<pre id=\"acsg-selftest\"")
        .unwrap_or_else(|| panic!("no self-check element in the DOM ({} bytes)", dom.len()));
    let body = &dom[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</pre>").unwrap()];
    assert!(!body.is_empty(), "the page's script did not finish (empty self check)");
    serde_json::from_str(&html_unescape(body)).unwrap()
}

/// A part path of 200 characters wraps in the summary instead of running over the
/// Bounds table.
#[test]
fn long_part_paths_do_not_overlap_the_summary_tables() {
    let Some(browser) = chromium() else {
        skipped(
            "long_part_paths_do_not_overlap_the_summary_tables",
            "no chromium on PATH (install it with `apt-get install chromium`, or set ACSG_CHROMIUM)",
        );
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join("a_very_long_folder_name_".repeat(8));
    std::fs::create_dir_all(&long).unwrap();
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    for name in ["slab.off", "cube.off"] {
        std::fs::copy(fixtures.join(name), long.join(name)).unwrap();
    }
    let page = dir.path().join("long.html");
    acsg()
        .arg("generate")
        .arg(long.join("slab.off"))
        .arg(long.join("cube.off"))
        .args(["--bounds", "z=0:5", "--units", "mm", "-q", "-o"])
        .arg(dir.path().join("long.json"))
        .arg("--html")
        .arg(&page)
        .assert()
        .success();
    let check = self_check(&browser, &page, dir.path());
    eprintln!("browser self check: {check}");
    assert_eq!(check["errors"], serde_json::json!([]), "errors in the page");
    assert_eq!(check["summary_overlaps"], 0, "summary blocks overlap");
    assert_eq!(check["summary_overflowing"], 0, "a summary block runs over its width");
}

/// Says, past the test harness's capture of `eprintln!` (a direct write to stderr is
/// not captured), that a check was skipped: `cargo test` then shows the line even
/// though the test is reported "ok".
fn skipped(what: &str, why: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED {what}: {why}");
}

/// `acsg demo` with no files: the graph it writes (by default `acsg-demo.graph.json`)
/// holds together (the run is the one every test here shares).
#[test]
fn demo_runs_with_no_files_and_writes_a_consistent_graph() {
    let v: &Value = &demo().1;
    assert_eq!(v["format"], "acsg-graph/1");
    assert!(v["convention"].as_str().unwrap().contains("Rz(rz)*Ry(ry)*Rx(rx)"));
    let states = v["states"].as_array().unwrap();
    assert_eq!(states.len() as u64, v["stats"]["states"].as_u64().unwrap());
    assert_eq!(v["stats"]["ppc"], 328);
    let (faces, edges, vertices) = (
        v["fixed"]["faces"].as_array().unwrap().len(),
        v["fixed"]["edges"].as_array().unwrap().len(),
        v["fixed"]["vertices"].as_array().unwrap().len(),
    );
    assert_eq!((faces, edges, vertices), (8, 18, 12));
    // The bounds given (angles in degrees on the command line, in radians in the
    // JSON); the components not given fixed at 0.
    let bounds = |end: &str| -> Vec<f64> {
        v["bounds"][end]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let degree = std::f64::consts::PI / 180.0;
    let (lo, hi) = (bounds("min"), bounds("max"));
    let expected_lo = [-2.0, -2.0, 0.0, -2.0 * degree, 0.0, -2.0 * degree];
    let expected_hi = [2.0, 2.0, 60.0, 2.0 * degree, 0.0, 2.0 * degree];
    for i in 0..6 {
        assert!((lo[i] - expected_lo[i]).abs() < 1e-12, "{lo:?}");
        assert!((hi[i] - expected_hi[i]).abs() < 1e-12, "{hi:?}");
    }
    // Ids index the parts' arrays; each witness has six values and a rigid 4x4 matrix.
    for state in &states[1..] {
        for c in state["contacts"].as_array().unwrap() {
            for (role, id) in [("fixed", &c["fixed"]), ("moving", &c["moving"])] {
                let id = id.as_str().unwrap();
                let (kind, index) = id.split_at(1);
                let array = match kind {
                    "f" => "faces",
                    "e" => "edges",
                    _ => "vertices",
                };
                assert!(index.parse::<usize>().unwrap() < v[role][array].as_array().unwrap().len());
            }
        }
        let witness = &state["witness"];
        assert_eq!(witness["pose"].as_array().unwrap().len(), 6);
        assert_eq!(witness["matrix"][3], serde_json::json!([0.0, 0.0, 0.0, 1.0]));
    }
    for edge in v["edges"].as_array().unwrap() {
        assert!(edge[0].as_u64().unwrap() < edge[1].as_u64().unwrap());
        assert!(edge[1].as_u64().unwrap() < states.len() as u64);
    }
    // Every key the schema requires is there, at the top and in the counts.
    let schema: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../schema/graph.schema.json")).unwrap(),
    )
    .unwrap();
    for (required, object) in [
        (&schema["required"], v),
        (&schema["properties"]["stats"]["required"], &v["stats"]),
    ] {
        for key in required.as_array().unwrap() {
            assert!(object.get(key.as_str().unwrap()).is_some(), "missing {key}");
        }
    }
    // Completeness: every candidate ended one way, and the flag says whether any is
    // undecided (each then listed with the box its proof left open).
    let s = &v["stats"];
    let count = |k: &str| s[k].as_u64().unwrap();
    assert_eq!(
        count("candidates"),
        count("witnessed") + count("infeasible") + count("undecided")
    );
    let undecided = v["undecided"].as_array().unwrap();
    assert_eq!(undecided.len() as u64, count("undecided"));
    assert_eq!(v["complete"].as_bool().unwrap(), undecided.is_empty());
    for u in undecided {
        assert!(!u["contacts"].as_array().unwrap().is_empty());
        let (lo, hi) = (
            u["open"]["min"].as_array().unwrap(),
            u["open"]["max"].as_array().unwrap(),
        );
        assert!(
            lo.iter()
                .zip(hi)
                .all(|(a, b)| a.as_f64().unwrap() <= b.as_f64().unwrap())
        );
    }
}
