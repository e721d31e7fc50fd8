//! The library's modules import one another without cycles.
//!
//! The test reads the library's source files (text, not the compiler's view) and
//! builds a graph of modules: an arrow from the module of a file to the module that
//! defines each item it names through `use` or a path starting with `crate::`,
//! `super::` or `self::` (re-exports are followed to the defining module; comments,
//! string literals and `#[cfg(test)]` items are skipped, since tests may reach
//! anywhere). Two graphs must be acyclic:
//! - the crate's top-level modules (`model`, `contact`, ...), each with everything
//!   below it;
//! - inside each module, its child modules (`contact::gauss`, `contact::penetration`,
//!   ...), each with everything below it.
//!
//! A module's own file (`mod.rs`) and its children are one module at the level above;
//! children may use what it defines (Rust lets them see its private items for that
//! reason) and it may re-export theirs, so arrows between a parent and its own child
//! are not checked.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module path from the crate root: `["contact", "gauss"]`.
type ModPath = Vec<String>;

/// One source file as the test sees it.
struct Module {
    /// The code with comments, strings and test items blanked out.
    code: String,
    /// Names brought in by `use` (and `pub use`): name -> absolute path.
    imports: BTreeMap<String, ModPath>,
    /// Names of the child modules declared here.
    children: BTreeSet<String>,
}

/// Every `.rs` file under `src`, by module path.
fn read_modules(src: &Path) -> BTreeMap<ModPath, Module> {
    let mut files = Vec::new();
    collect_files(src, &mut files);
    let mut modules = BTreeMap::new();
    for file in files {
        let relative = file.strip_prefix(src).expect("a file under src");
        let mut path: ModPath = relative
            .with_extension("")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        if matches!(path.last().map(String::as_str), Some("mod" | "lib")) {
            path.pop();
        }
        let text = std::fs::read_to_string(&file).expect("a readable source file");
        let code = without_test_items(&blank_comments_and_strings(&text));
        let children = child_modules(&code);
        modules.insert(
            path,
            Module {
                code,
                imports: BTreeMap::new(),
                children,
            },
        );
    }
    let paths: Vec<ModPath> = modules.keys().cloned().collect();
    for path in paths {
        let imports = {
            let module = &modules[&path];
            let mut imports = BTreeMap::new();
            for tree in use_trees(&module.code) {
                for (name, target) in expand_use_tree(&tree) {
                    if let Some(absolute) = absolute_path(&path, &target, &module.children) {
                        imports.insert(name, absolute);
                    }
                }
            }
            imports
        };
        modules.get_mut(&path).expect("listed").imports = imports;
    }
    modules
}

fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("a readable folder")
        .map(|e| e.expect("a folder entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            collect_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text with comments, string and char literals replaced by spaces (lines kept).
fn blank_comments_and_strings(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = bytes.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for b in &mut out[from..to.min(bytes.len())] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
    };
    let mut i = 0;
    while i < bytes.len() {
        let rest = &bytes[i..];
        if rest.starts_with(b"//") {
            let end = rest.iter().position(|&b| b == b'\n').map_or(bytes.len(), |k| i + k);
            blank(&mut out, i, end);
            i = end;
        } else if rest.starts_with(b"/*") {
            let (mut depth, mut j) = (0usize, i);
            while j < bytes.len() {
                if bytes[j..].starts_with(b"/*") {
                    depth += 1;
                    j += 2;
                } else if bytes[j..].starts_with(b"*/") {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            blank(&mut out, i, j);
            i = j;
        } else if let Some((body, hashes)) = raw_string_start(rest).filter(|_| i == 0 || !is_ident_byte(bytes[i - 1])) {
            let close: Vec<u8> = std::iter::once(b'"').chain(std::iter::repeat_n(b'#', hashes)).collect();
            let body = i + body;
            let end = bytes[body..]
                .windows(close.len())
                .position(|w| w == close.as_slice())
                .map_or(bytes.len(), |k| body + k + close.len());
            blank(&mut out, i, end);
            i = end;
        } else if rest[0] == b'"' {
            let mut j = i + 1;
            while j < bytes.len() && bytes[j] != b'"' {
                j += if bytes[j] == b'\\' { 2 } else { 1 };
            }
            blank(&mut out, i, j + 1);
            i = j + 1;
        } else if rest[0] == b'\'' && (rest.get(1) == Some(&b'\\') || rest.get(2) == Some(&b'\'')) {
            // A char literal ('x', '\n', '\''), not a lifetime ('a).
            let mut j = i + 2;
            while j < bytes.len() && bytes[j] != b'\'' {
                j += if bytes[j] == b'\\' { 2 } else { 1 };
            }
            blank(&mut out, i, j + 1);
            i = j + 1;
        } else {
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Where the body of a raw string starting here (`r"`, `r#"`, `br"`) begins, and its
/// number of `#`.
fn raw_string_start(rest: &[u8]) -> Option<(usize, usize)> {
    let prefix = usize::from(rest.starts_with(b"b"));
    let after_r = rest[prefix..].strip_prefix(b"r")?;
    let hashes = after_r.iter().take_while(|&&b| b == b'#').count();
    (after_r.get(hashes) == Some(&b'"')).then_some((prefix + 1 + hashes + 1, hashes))
}

/// The code without the items marked `#[cfg(test)]` (a `mod tests { ... }`, a test
/// helper function, a `use` for tests).
fn without_test_items(code: &str) -> String {
    let mut out = code.to_string();
    let mut from = 0;
    while let Some(k) = out[from..].find("#[cfg(test)]") {
        let start = from + k;
        let bytes = out.as_bytes();
        let mut j = start + "#[cfg(test)]".len();
        // The item ends at its first `;` outside braces, or at the brace closing its
        // first `{`.
        let mut depth = 0usize;
        while j < bytes.len() {
            match bytes[j] {
                b'{' => depth += 1,
                b'}' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                b';' if depth == 0 => break,
                _ => {}
            }
            j += 1;
        }
        let end = (j + 1).min(out.len());
        let blanked: String = out[start..end]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' })
            .collect();
        out.replace_range(start..end, &blanked);
        from = end;
    }
    out
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// Where `word` occurs in `code` at the start of a word (not inside a longer one).
fn word_positions<'a>(code: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    code.match_indices(word)
        .map(|(i, _)| i)
        .filter(move |&i| i == 0 || !is_ident_byte(code.as_bytes()[i - 1]))
}

/// The names of `mod name;` and `mod name { ... }` declarations at any depth.
fn child_modules(code: &str) -> BTreeSet<String> {
    word_positions(code, "mod ")
        .map(|i| {
            code[i + 4..]
                .trim_start()
                .chars()
                .take_while(|&c| c.is_ascii_alphanumeric() || c == '_')
                .collect::<String>()
        })
        .filter(|name| !name.is_empty())
        .collect()
}

/// The trees of every `use` declaration: the text between `use` and `;`.
fn use_trees(code: &str) -> Vec<String> {
    word_positions(code, "use ")
        .filter_map(|i| {
            let end = code[i..].find(';')?;
            Some(code[i + 4..i + end].split_whitespace().collect::<Vec<_>>().join(" "))
        })
        .collect()
}

/// A use tree (`a::{b, c::{d as e, self}}`) as (name brought in, path) pairs; globs
/// give no name.
fn expand_use_tree(tree: &str) -> Vec<(String, Vec<String>)> {
    fn expand(prefix: &[String], tree: &str, out: &mut Vec<(String, Vec<String>)>) {
        let tree = tree.trim().trim_start_matches("::");
        if tree.is_empty() {
            return;
        }
        if let Some(open) = tree.find('{') {
            let mut path = prefix.to_vec();
            path.extend(segments(&tree[..open]));
            let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
            let mut depth = 0;
            let mut start = 0;
            for (k, c) in inner.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        expand(&path, &inner[start..k], out);
                        start = k + 1;
                    }
                    _ => {}
                }
            }
            expand(&path, &inner[start..], out);
            return;
        }
        let (body, alias) = match tree.split_once(" as ") {
            Some((body, alias)) => (body, Some(alias.trim())),
            None => (tree, None),
        };
        let mut path = prefix.to_vec();
        path.extend(segments(body));
        let Some(last) = path.last().cloned() else { return };
        if last == "*" || alias == Some("_") {
            out.push(("*".to_string(), path[..path.len() - 1].to_vec()));
            return;
        }
        if last == "self" {
            path.pop();
            let name = alias.map_or_else(|| path.last().cloned().unwrap_or_default(), str::to_string);
            out.push((name, path));
            return;
        }
        out.push((alias.map_or(last, str::to_string), path));
    }
    let mut out = Vec::new();
    expand(&[], tree, &mut out);
    out
}

/// The segments of a path written `a::b::c`.
fn segments(text: &str) -> Vec<String> {
    text.split("::")
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

/// `path` (as written in module `here`) from the crate root, or `None` for an
/// external crate or a primitive.
fn absolute_path(here: &ModPath, path: &[String], children: &BTreeSet<String>) -> Option<ModPath> {
    let (first, rest) = path.split_first()?;
    let mut base: ModPath = match first.as_str() {
        "crate" => Vec::new(),
        "self" => here.clone(),
        "super" => here[..here.len().checked_sub(1)?].to_vec(),
        name if children.contains(name) => {
            let mut base = here.clone();
            base.push(name.to_string());
            base
        }
        _ => return None,
    };
    let mut rest = rest;
    while let Some(("super", tail)) = rest.split_first().map(|(s, t)| (s.as_str(), t)) {
        base.pop();
        rest = tail;
    }
    base.extend(rest.iter().cloned());
    Some(base)
}

/// The module that defines what `path` names: the longest prefix that is a module,
/// then, when the next name was imported there, where that import leads.
fn defining_module(modules: &BTreeMap<ModPath, Module>, path: &[String], depth: usize) -> ModPath {
    let mut module: ModPath = Vec::new();
    for (k, segment) in path.iter().enumerate() {
        let mut child = module.clone();
        child.push(segment.clone());
        if modules.contains_key(&child) {
            module = child;
            continue;
        }
        if depth < 16
            && let Some(target) = modules.get(&module).and_then(|m| m.imports.get(segment))
        {
            let mut full = target.clone();
            full.extend(path[k + 1..].iter().cloned());
            return defining_module(modules, &full, depth + 1);
        }
        break;
    }
    module
}

/// Every path the code names from the crate root (`crate::a::b`, `super::c`,
/// `self::d`) or through `use`, resolved to absolute paths.
fn named_paths(here: &ModPath, module: &Module) -> Vec<ModPath> {
    let mut out: Vec<ModPath> = module.imports.values().cloned().collect();
    let code = &module.code;
    for start in ["crate::", "super::", "self::"] {
        // `$crate::` belongs to a macro's expansion, not to this module.
        for i in word_positions(code, start).filter(|&i| !code[..i].ends_with('$')) {
            let text: String = code[i..]
                .chars()
                .take_while(|&c| c.is_ascii_alphanumeric() || c == '_' || c == ':')
                .collect();
            out.extend(absolute_path(here, &segments(&text), &module.children));
        }
    }
    out
}

/// Arrows between modules: (from, to) for every name used in `from` and defined in `to`.
fn module_arrows(modules: &BTreeMap<ModPath, Module>) -> BTreeSet<(ModPath, ModPath)> {
    let mut arrows = BTreeSet::new();
    for (here, module) in modules {
        for path in named_paths(here, module) {
            let target = defining_module(modules, &path, 0);
            if &target != here {
                arrows.insert((here.clone(), target));
            }
        }
    }
    arrows
}

/// The arrows between the children of `parent`: each module below a child stands for
/// that child; arrows from or to `parent` itself, and within one child, are dropped.
fn arrows_between_children(
    arrows: &BTreeSet<(ModPath, ModPath)>,
    parent: &[String],
) -> BTreeMap<String, BTreeSet<String>> {
    let child_of = |m: &ModPath| (m.len() > parent.len() && m.starts_with(parent)).then(|| m[parent.len()].clone());
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, to) in arrows {
        if let (Some(a), Some(b)) = (child_of(from), child_of(to))
            && a != b
        {
            graph.entry(a).or_default().insert(b);
        }
    }
    graph
}

/// The nodes reachable from `start` (itself included).
fn reachable(graph: &BTreeMap<String, BTreeSet<String>>, start: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::from([start.to_string()]);
    let mut stack = vec![start.to_string()];
    while let Some(node) = stack.pop() {
        for next in graph.get(&node).into_iter().flatten() {
            if seen.insert(next.clone()) {
                stack.push(next.clone());
            }
        }
    }
    seen
}

/// Each group of mutually reachable nodes, with one cycle through its first node as
/// the list of the cycle's nodes (the first repeated at the end).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<(BTreeSet<String>, Vec<String>)> {
    let reach: BTreeMap<&String, BTreeSet<String>> = graph.keys().map(|n| (n, reachable(graph, n))).collect();
    let mut covered = BTreeSet::new();
    let mut out = Vec::new();
    for (&node, from_node) in &reach {
        if covered.contains(node) {
            continue;
        }
        // The group: nodes reachable from `node` that reach it back.
        let group: BTreeSet<&String> = from_node
            .iter()
            .filter(|m| *m != node && reach.get(m).is_some_and(|r| r.contains(node)))
            .collect();
        if group.is_empty() {
            continue;
        }
        covered.extend(group.iter().map(|m| (*m).clone()));
        // A shortest way back to `node`, by breadth-first search inside the group.
        let mut before: BTreeMap<String, String> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([node.clone()]);
        'search: while let Some(here) = queue.pop_front() {
            for next in graph.get(&here).into_iter().flatten() {
                if next == node {
                    let mut cycle = vec![node.clone(), here.clone()];
                    while let Some(prev) = before.get(cycle.last().expect("not empty")) {
                        cycle.push(prev.clone());
                    }
                    if here == *node {
                        cycle.pop();
                    }
                    cycle.reverse();
                    cycle.insert(0, node.clone());
                    cycle.dedup();
                    let mut members: BTreeSet<String> = group.iter().map(|m| (*m).clone()).collect();
                    members.insert(node.clone());
                    out.push((members, cycle));
                    break 'search;
                }
                if group.contains(next) && !before.contains_key(next) {
                    before.insert(next.clone(), here.clone());
                    queue.push_back(next.clone());
                }
            }
        }
    }
    out
}

/// Where a cycle's arrows come from: for each step, the files and the names.
fn explain(cycle: &[String], parent: &[String], arrows: &BTreeSet<(ModPath, ModPath)>) -> String {
    let within = |m: &ModPath, child: &str| m.len() > parent.len() && m.starts_with(parent) && m[parent.len()] == child;
    let mut text = String::new();
    for step in cycle.windows(2) {
        let found: Vec<String> = arrows
            .iter()
            .filter(|(from, to)| within(from, &step[0]) && within(to, &step[1]))
            .map(|(from, to)| format!("{} -> {}", from.join("::"), to.join("::")))
            .collect();
        text.push_str(&format!("  {} -> {}: {}\n", step[0], step[1], found.join(", ")));
    }
    text
}

#[test]
fn modules_import_one_another_without_cycles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let modules = read_modules(&src);
    let arrows = module_arrows(&modules);
    let mut problems = String::new();
    for parent in modules.keys() {
        let graph = arrows_between_children(&arrows, parent);
        for (members, cycle) in cycles(&graph) {
            let scope = if parent.is_empty() {
                "the crate".to_string()
            } else {
                parent.join("::")
            };
            problems.push_str(&format!(
                "modules of {scope} that import one another ({}); one cycle: {}\n{}",
                members.into_iter().collect::<Vec<_>>().join(", "),
                cycle.join(" -> "),
                explain(&cycle, parent, &arrows)
            ));
        }
    }
    assert!(problems.is_empty(), "{problems}");
}

/// The reader itself: a known cycle is found, and what hides in comments, strings and
/// test items is not read.
#[test]
fn the_reader_sees_code_only() {
    let code = blank_comments_and_strings(
        "// use crate::a;\nlet s = \"crate::b\"; let c = '\"'; /* crate::c */ use crate::d::{e, f::{self, g as h}};",
    );
    assert!(!code.contains("crate::a") && !code.contains("crate::b") && !code.contains("crate::c"));
    let trees = use_trees(&code);
    assert_eq!(trees, ["crate::d::{e, f::{self, g as h}}"]);
    let names: Vec<(String, Vec<String>)> = expand_use_tree(&trees[0]);
    let expected = [("e", "crate::d::e"), ("f", "crate::d::f"), ("h", "crate::d::f::g")]
        .map(|(name, path)| (name.to_string(), segments(path)));
    assert_eq!(names, expected);
    let tested = without_test_items("use crate::x;\n#[cfg(test)]\nmod tests { use crate::y; }\n");
    assert!(tested.contains("crate::x") && !tested.contains("crate::y"));
    let graph: BTreeMap<String, BTreeSet<String>> = [("a", "b"), ("b", "c"), ("c", "a")]
        .iter()
        .map(|&(a, b)| (a.to_string(), BTreeSet::from([b.to_string()])))
        .collect();
    let found = cycles(&graph);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].1, ["a", "b", "c", "a"]);
}
