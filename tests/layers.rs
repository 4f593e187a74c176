//! The module layering of docs/architecture.md, checked on the source: a
//! module may use only the modules listed before it (and itself), so no
//! module imports one above it and no two modules import each other; and
//! inside a module, no two files import each other, directly or through
//! others (a circle of files).

use crate::common::repo;

/// From the bottom up, as docs/architecture.md lists them.
const LAYERS: [&str; 24] = [
    "data",
    "names",
    "progress",
    "sampling",
    "color",
    "timing",
    "owner",
    "image_io",
    "spectrum",
    "optics",
    "geometry",
    "mesh",
    "world",
    "gltf",
    "photon",
    "scenes",
    "spectral",
    "interior",
    "params",
    "modes",
    "terminal",
    "experiment",
    "bench",
    "cli",
];

fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_module_imports_one_above_it() {
    let src = repo("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut seen = 0;
    let mut wrong = Vec::new();
    for f in files {
        let rel = f.strip_prefix(&src).unwrap().to_string_lossy().replace('\\', "/");
        let top = rel.split(['/', '.']).next().unwrap().to_string();
        if top == "lib" || top == "main" {
            continue;
        }
        let Some(level) = LAYERS.iter().position(|l| *l == top) else {
            wrong.push(format!("src/{rel}: module `{top}` is not in the layer list"));
            continue;
        };
        let text = std::fs::read_to_string(&f).unwrap();
        // Unit tests may reach anywhere.
        let code = text.split("#[cfg(test)]").next().unwrap();
        for (i, line) in code.lines().enumerate() {
            for part in line.split("crate::").skip(1) {
                let name: String = part.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                let name = if name == "named_enum" { "names".to_string() } else { name };
                seen += 1;
                match LAYERS.iter().position(|l| *l == name) {
                    Some(l) if l <= level => {}
                    Some(_) => wrong.push(format!("src/{rel}:{}: `{top}` uses `{name}`, a layer above it", i + 1)),
                    None => {}
                }
            }
        }
    }
    assert!(seen > 100, "the scan found only {seen} uses of crate::");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// A file's module path: `experiment/spec.rs` is `experiment::spec`,
/// `world/mod.rs` is `world`.
fn module_of(rel: &str) -> Vec<String> {
    let stem = rel.strip_suffix(".rs").unwrap();
    let mut m: Vec<String> = stem.split('/').map(str::to_string).collect();
    if m.last().is_some_and(|l| l == "mod") {
        m.pop();
    }
    m
}

/// The source with comments and the unit tests left out.
fn code_of(text: &str) -> String {
    let code = text.split("#[cfg(test)]").next().unwrap();
    code.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
}

/// `a::{b, c::{d, e}}` as `a::b`, `a::c::d`, `a::c::e`.
fn expand_use(tree: &str) -> Vec<String> {
    let tree: String = tree.chars().filter(|c| !c.is_whitespace()).collect();
    let Some(open) = tree.find('{') else { return vec![tree] };
    let (prefix, inner) = (&tree[..open], &tree[open + 1..tree.len() - 1]);
    let (mut parts, mut depth, mut start) = (Vec::new(), 0, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts.into_iter().filter(|p| !p.is_empty()).flat_map(|p| expand_use(p).into_iter().map(move |e| format!("{prefix}{e}"))).collect()
}

/// The trees of the code's `keyword` items (`use ` or `pub use `), at the
/// top of the file or inside a function: `a::{b, c}` of `use a::{b, c};`.
fn use_trees<'a>(code: &'a str, keyword: &str) -> Vec<&'a str> {
    code.match_indices(keyword)
        .filter(|(at, _)| !code[..*at].chars().next_back().is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':'))
        .filter_map(|(at, _)| code[at + keyword.len()..].split(';').next())
        .collect()
}

/// Every path the code names: the paths of its `use` items, expanded, and
/// any `crate::`, `super::` or `self::` path in the code.
fn paths_in(code: &str) -> Vec<Vec<String>> {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    out.extend(use_trees(code, "use ").iter().flat_map(|t| expand_use(t)).map(|p| p.split("::").map(str::to_string).collect()));
    for root in ["crate::", "super::", "self::"] {
        for (at, _) in code.match_indices(root) {
            if code[..at].chars().next_back().is_some_and(|c| ident(c) || c == ':') {
                continue;
            }
            let rest = &code[at..];
            let end = rest.find(|c: char| !(ident(c) || c == ':')).unwrap_or(rest.len());
            // `a::{b, c}` is a use tree, read whole above.
            if rest[end..].starts_with('{') {
                continue;
            }
            out.push(rest[..end].split("::").filter(|s| !s.is_empty()).map(str::to_string).collect());
        }
    }
    out
}

/// Which file a path names from the file of module `from`: the deepest
/// file module it reaches, following `pub use` re-exports of that module.
fn resolve(
    path: &[String],
    from: &[String],
    modules: &std::collections::BTreeMap<Vec<String>, String>,
    reexports: &std::collections::BTreeMap<(Vec<String>, String), Vec<String>>,
    depth: usize,
) -> Option<String> {
    let mut abs: Vec<String> = match path.first()?.as_str() {
        "crate" => path[1..].to_vec(),
        "self" => from.iter().chain(&path[1..]).cloned().collect(),
        "super" => {
            let ups = path.iter().take_while(|s| *s == "super").count();
            from[..from.len().checked_sub(ups)?].iter().chain(&path[ups..]).cloned().collect()
        }
        // A bare path: a child module of `from` (or another crate).
        first => {
            let mut child = from.to_vec();
            child.push(first.to_string());
            if !modules.contains_key(&child) {
                return None;
            }
            from.iter().chain(path).cloned().collect()
        }
    };
    abs.retain(|s| s != "self");
    let n = (1..=abs.len()).rev().find(|&n| modules.contains_key(&abs[..n]))?;
    if n < abs.len() && depth < 8 {
        if let Some(target) = reexports.get(&(abs[..n].to_vec(), abs[n].clone())) {
            return resolve(target, &abs[..n], modules, reexports, depth + 1);
        }
    }
    modules.get(&abs[..n]).cloned()
}

/// Files (under `src/`) and the files each imports.
fn file_imports() -> std::collections::BTreeMap<String, std::collections::BTreeSet<String>> {
    use std::collections::{BTreeMap, BTreeSet};
    let src = repo("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut modules = BTreeMap::new();
    let mut codes = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap().to_string_lossy().replace('\\', "/");
        if rel == "lib.rs" || rel == "main.rs" {
            continue;
        }
        modules.insert(module_of(&rel), rel.clone());
        codes.push((rel, code_of(&std::fs::read_to_string(f).unwrap())));
    }
    // `pub use a::B;` in module M: M::B is a::B.
    let mut reexports = BTreeMap::new();
    for (rel, code) in &codes {
        for p in use_trees(code, "pub use ").iter().flat_map(|t| expand_use(t)) {
            let p: Vec<String> = p.split("::").map(str::to_string).collect();
            reexports.insert((module_of(rel), p.last().unwrap().clone()), p);
        }
    }
    let mut graph = BTreeMap::new();
    for (rel, code) in &codes {
        let from = module_of(rel);
        let to: BTreeSet<String> = paths_in(code).iter().filter_map(|p| resolve(p, &from, &modules, &reexports, 0)).filter(|t| t != rel).collect();
        graph.insert(rel.clone(), to);
    }
    graph
}

/// The strongly connected groups of two or more files (Tarjan).
fn circles(graph: &std::collections::BTreeMap<String, std::collections::BTreeSet<String>>) -> Vec<Vec<String>> {
    use std::collections::BTreeMap;
    struct T<'a> {
        g: &'a BTreeMap<String, std::collections::BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: std::collections::BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    impl<'a> T<'a> {
        fn visit(&mut self, v: &'a str) {
            let i = self.index.len();
            self.index.insert(v, i);
            self.low.insert(v, i);
            self.stack.push(v);
            self.on.insert(v);
            for w in self.g.get(v).into_iter().flatten() {
                if !self.index.contains_key(w.as_str()) {
                    self.visit(w);
                    let l = self.low[v].min(self.low[w.as_str()]);
                    self.low.insert(v, l);
                } else if self.on.contains(w.as_str()) {
                    let l = self.low[v].min(self.index[w.as_str()]);
                    self.low.insert(v, l);
                }
            }
            if self.low[v] == self.index[v] {
                let mut group = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on.remove(w);
                    group.push(w.to_string());
                    if w == v {
                        break;
                    }
                }
                if group.len() > 1 {
                    group.sort();
                    self.out.push(group);
                }
            }
        }
    }
    let mut t = T { g: graph, index: BTreeMap::new(), low: BTreeMap::new(), stack: Vec::new(), on: Default::default(), out: Vec::new() };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    t.out
}

#[test]
fn no_two_files_import_each_other() {
    let graph = file_imports();
    let edges: usize = graph.values().map(|s| s.len()).sum();
    assert!(graph.len() > 80 && edges > 300, "the scan found only {} files and {edges} imports", graph.len());
    // The scan sees the imports it must: a `super::` path, a `crate::`
    // path, and one through a `pub use` re-export.
    for (from, to) in [("experiment/grid.rs", "experiment/spec.rs"), ("experiment/sweep.rs", "experiment/grid.rs"), ("cli/mod.rs", "experiment/sweep.rs")] {
        assert!(graph[from].contains(to), "{from} imports {to}, but the scan did not see it: {:?}", graph[from]);
    }
    let wrong: Vec<String> = circles(&graph)
        .into_iter()
        .map(|c| {
            let ties: Vec<String> = c.iter().flat_map(|f| graph[f].iter().filter(|t| c.contains(t)).map(move |t| format!("src/{f} -> src/{t}"))).collect();
            format!("a circle of {} files: {}", c.len(), ties.join(", "))
        })
        .collect();
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The check finds a circle planted in the real graph: the light pass's
/// shared types (`photon/landing.rs`) made to import a tracer that imports
/// them, directly and through the driver.
#[test]
fn a_planted_circle_of_files_is_found() {
    let mut graph = file_imports();
    assert!(circles(&graph).is_empty());
    assert!(graph["photon/train.rs"].contains("photon/landing.rs") && graph["photon/emit.rs"].contains("photon/train.rs"));
    graph.get_mut("photon/landing.rs").unwrap().insert("photon/train.rs".into());
    assert_eq!(circles(&graph), vec![vec!["photon/landing.rs".to_string(), "photon/train.rs".to_string()]]);
    graph.get_mut("photon/landing.rs").unwrap().remove("photon/train.rs");
    graph.get_mut("photon/landing.rs").unwrap().insert("photon/emit.rs".into());
    let found = circles(&graph);
    assert!(found.len() == 1 && found[0].contains(&"photon/emit.rs".to_string()) && found[0].contains(&"photon/landing.rs".to_string()), "{found:?}");
}
