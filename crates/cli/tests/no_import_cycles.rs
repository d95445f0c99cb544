//! No import cycles between sibling files, in every crate of the workspace.
//!
//! A folder reads top-down when its files import one another in one direction only: the shared
//! item lives in the file it belongs to, or in a small file both import, or in the folder's
//! `mod.rs`. This test checks that with a text scan of the sources, by these rules:
//!
//! - Every `.rs` file under `crates/*/src` is a module: `a/b.rs` is `a::b`; `a/mod.rs`,
//!   `lib.rs` and `main.rs` are the module of their folder.
//! - A file's imports are the paths it names that start with `crate::`, `super::` or `self::`,
//!   resolved against the file's module: in its `use` declarations (any visibility, over
//!   several lines, with `{…}` groups expanded) and written inline in its code
//!   (`crate::a::f()`). Paths into other crates, and paths in comments and doc links, are not
//!   imports.
//! - Lines that start with `//` are skipped, and so is everything from a `#[cfg(test)]`
//!   followed by a `mod` line on: unit tests may import what they test from anywhere.
//! - The siblings of a folder are its files and its sub-folders, each sub-folder standing for
//!   its `mod.rs`. File `f` depends on sibling `g` when one of `f`'s own imports goes through
//!   `g` (`use super::g::X`, `use crate::a::g::Y`). Imports of a folder's parent (`super::X`
//!   from `a/b.rs`, an item of `a/mod.rs`) and of modules outside the folder are not edges
//!   there; every folder is checked on its own, so a file inside `g/` is checked against its
//!   own siblings.
//! - A cycle in that graph, in any folder, fails the test, naming the folder and the files in
//!   order.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A source file: its module path within its crate, and its text.
struct Module {
    path: Vec<String>,
    text: String,
}

/// The module path of `file` (relative to its crate's `src`).
fn module_path(file: &Path) -> Vec<String> {
    let mut path: Vec<String> = file
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        path.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        path.pop();
    }
    path
}

/// The text that counts: no comment lines, nothing from the unit tests on.
fn scanned_text(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .windows(2)
        .position(|w| {
            w[0].trim() == "#[cfg(test)]"
                && w[1].split_whitespace().any(|word| word == "mod")
                && !w[1].trim_start().starts_with("use")
        })
        .unwrap_or(lines.len());
    lines[..end]
        .iter()
        .filter(|l| !l.trim_start().starts_with("//"))
        .copied()
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths of the `use` declarations of `text`, with `{…}` groups expanded.
fn use_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = find_use(rest) {
        let after = &rest[at..];
        let Some(end) = after.find(';') else { break };
        let declared: String = after[..end]
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect();
        out.extend(expand(&declared));
        rest = &after[end + 1..];
    }
    out
}

/// Where the path of the next `use` declaration starts: after `use` at the start of a line
/// (behind an optional visibility).
fn find_use(text: &str) -> Option<usize> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let mut words = trimmed;
        if let Some(vis) = words.strip_prefix("pub") {
            words = vis.trim_start();
            if words.starts_with('(') {
                words = words.split_once(')').map_or("", |(_, w)| w).trim_start();
            }
        }
        if let Some(path) = words.strip_prefix("use ") {
            return Some(offset + line.len() - path.len());
        }
        offset += line.len();
    }
    None
}

/// The paths written inline in `text`: `crate::…`, `super::…` or `self::…` after a character
/// that cannot belong to a path.
fn inline_paths(text: &str) -> Vec<String> {
    let is_path = |c: char| c.is_alphanumeric() || c == '_' || c == ':';
    let mut out = Vec::new();
    for root in ["crate::", "super::", "self::"] {
        for (at, _) in text.match_indices(root) {
            if text[..at].chars().next_back().is_some_and(is_path) {
                continue;
            }
            let path = text[at..].split(|c: char| !is_path(c)).next().unwrap_or("");
            out.push(path.trim_end_matches(':').to_owned());
        }
    }
    out
}

/// `a::{b, c::{d, e}}` → `a::b`, `a::c::d`, `a::c::e` (whitespace already removed).
fn expand(path: &str) -> Vec<String> {
    let Some(open) = path.find('{') else {
        return vec![path.to_owned()];
    };
    let (prefix, group) = (&path[..open], &path[open + 1..path.len() - 1]);
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&group[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&group[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(|p| expand(p).into_iter().map(move |e| format!("{prefix}{e}")))
        .collect()
}

/// The module path `path` names, written in module `me`; `None` outside the crate.
fn resolve(me: &[String], path: &str) -> Option<Vec<String>> {
    let mut segments = path.split("::").peekable();
    let mut target: Vec<String> = match *segments.peek()? {
        "crate" => {
            segments.next();
            Vec::new()
        }
        "self" => {
            segments.next();
            me.to_vec()
        }
        "super" => me.to_vec(),
        _ => return None,
    };
    while segments.peek() == Some(&"super") {
        segments.next();
        target.pop();
    }
    target.extend(
        segments
            .filter(|s| !s.is_empty() && *s != "*" && *s != "self")
            .map(str::to_owned),
    );
    Some(target)
}

/// Per folder (its module path), the sibling dependencies: file → the siblings it imports.
type Graphs = BTreeMap<Vec<String>, BTreeMap<String, BTreeSet<String>>>;

/// The sibling graphs of one crate's modules.
fn graphs(modules: &[Module]) -> Graphs {
    let known: BTreeSet<&[String]> = modules.iter().map(|m| m.path.as_slice()).collect();
    let mut out = Graphs::new();
    for module in modules {
        let Some((name, folder)) = module.path.split_last() else {
            continue;
        };
        let text = scanned_text(&module.text);
        for path in use_paths(&text).into_iter().chain(inline_paths(&text)) {
            let Some(target) = resolve(&module.path, &path) else {
                continue;
            };
            if target.len() > folder.len() && target.starts_with(folder) {
                let sibling = &target[folder.len()];
                if sibling != name && known.contains(&target[..=folder.len()]) {
                    out.entry(folder.to_vec())
                        .or_default()
                        .entry(name.clone())
                        .or_default()
                        .insert(sibling.clone());
                }
            }
        }
    }
    out
}

/// One cycle of `graph`, as the files in order with the first repeated at the end.
fn cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    // Depth-first search; a sibling on the current path closes a cycle.
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut found = path[at..].to_vec();
            found.push(node.to_owned());
            return Some(found);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_owned());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(found) = visit(next, graph, path, done) {
                return Some(found);
            }
        }
        path.pop();
        done.insert(node.to_owned());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(node, graph, &mut Vec::new(), &mut done))
}

/// Every cycle found, one line per folder: `crate folder: a -> b -> a`.
fn cycles(krate: &str, modules: &[Module]) -> Vec<String> {
    graphs(modules)
        .iter()
        .filter_map(|(folder, graph)| {
            cycle(graph).map(|c| {
                let folder = if folder.is_empty() {
                    "src".to_owned()
                } else {
                    format!("src/{}", folder.join("/"))
                };
                format!("{krate} {folder}: {}", c.join(" -> "))
            })
        })
        .collect()
}

/// The `.rs` files under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn no_crate_has_an_import_cycle_between_sibling_files() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut found = Vec::new();
    let mut scanned = 0;
    for entry in std::fs::read_dir(&crates).expect("crates/") {
        let src = entry.expect("crate").path().join("src");
        if !src.is_dir() {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let modules: Vec<Module> = files
            .iter()
            .map(|f| Module {
                path: module_path(f.strip_prefix(&src).expect("under src")),
                text: std::fs::read_to_string(f).expect("readable source"),
            })
            .collect();
        scanned += modules.len();
        let krate = src.parent().and_then(Path::file_name).expect("crate name");
        found.extend(cycles(&krate.to_string_lossy(), &modules));
    }
    assert!(scanned > 100, "only {scanned} source files found");
    assert!(
        found.is_empty(),
        "import cycles between sibling files:\n  {}",
        found.join("\n  ")
    );
}

#[test]
fn the_scan_finds_a_planted_cycle_and_ignores_tests_comments_and_parents() {
    let module = |path: &str, text: &str| Module {
        path: module_path(Path::new(path)),
        text: text.to_owned(),
    };
    let clean = [
        module("lib.rs", "pub mod a;\nuse crate::a::Shared;\n"),
        module("a/mod.rs", "mod b;\nmod c;\npub struct Shared;\nuse self::b::B;\n"),
        module(
            "a/b.rs",
            "use super::Shared;\n// use super::c::C;\npub(crate) use super::{\n    c::{C, D},\n};\n",
        ),
        module(
            "a/c.rs",
            "use crate::a::Shared;\n#[cfg(test)]\nmod tests {\n    use super::super::b::B;\n}\n",
        ),
    ];
    assert!(cycles("k", &clean).is_empty(), "{:?}", cycles("k", &clean));
    let mut planted = clean;
    planted[3] = module("a/c.rs", "use crate::a::{b::B, Shared};\n");
    assert_eq!(cycles("k", &planted), ["k src/a: b -> c -> b"]);
    planted[3] = module("a/c.rs", "fn f() -> u8 {\n    super::b::g()\n}\n");
    assert_eq!(cycles("k", &planted), ["k src/a: b -> c -> b"]);
}
