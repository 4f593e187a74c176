//! The module layering of docs/architecture.md, checked on the source: a
//! module may use only the modules listed before it (and itself), so no
//! module imports one above it and no two modules import each other.

use crate::common::repo;

/// From the bottom up, as docs/architecture.md lists them.
const LAYERS: [&str; 21] = [
    "data",
    "names",
    "progress",
    "sampling",
    "color",
    "timing",
    "image_io",
    "spectrum",
    "optics",
    "geometry",
    "mesh",
    "world",
    "photon",
    "scenes",
    "spectral",
    "interior",
    "params",
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
