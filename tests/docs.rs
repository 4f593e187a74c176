//! Every `docs/physics.md §N` that the code and the tests cite names a
//! section that exists, and the documents the README names exist.

use crate::common::repo;

fn cited_sections(dir: &std::path::Path, out: &mut Vec<(String, u32)>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            cited_sections(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            let text = std::fs::read_to_string(&p).unwrap();
            for part in text.split("docs/physics.md §").skip(1) {
                let n: String = part.chars().take_while(char::is_ascii_digit).collect();
                // (Text about citations, like this file's, names no number.)
                if let Ok(n) = n.parse() {
                    out.push((p.display().to_string(), n));
                }
            }
        }
    }
}

#[test]
fn physics_citations_point_at_sections_that_exist() {
    let doc = std::fs::read_to_string(repo("docs/physics.md")).unwrap();
    let sections: Vec<u32> = doc.lines().filter_map(|l| l.strip_prefix("## §")).filter_map(|l| l.split_whitespace().next()?.parse().ok()).collect();
    assert!(sections.len() >= 10, "docs/physics.md has sections {sections:?}");
    let mut cited = Vec::new();
    cited_sections(&repo("src"), &mut cited);
    cited_sections(&repo("tests"), &mut cited);
    assert!(cited.len() >= 10, "only {} citations found", cited.len());
    for (file, n) in cited {
        assert!(sections.contains(&n), "{file} cites docs/physics.md §{n}, which does not exist");
    }
    assert!(repo("docs/architecture.md").is_file());
}
