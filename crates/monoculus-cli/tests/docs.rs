//! The front door: the README stays short, every page of `docs/` is reachable from it,
//! and no link in the README or the docs points to a file (or a heading) that is not
//! there, or outside the repository.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The relative links of a Markdown text: (target, anchor).
fn links(text: &str) -> Vec<(String, Option<String>)> {
    let mut out = Vec::new();
    for (k, _) in text.match_indices("](") {
        let rest = &text[k + 2..];
        let Some(end) = rest.find(')') else { continue };
        let target = &rest[..end];
        if target.starts_with("http") || target.contains(' ') {
            continue;
        }
        let (file, anchor) = match target.split_once('#') {
            Some((f, a)) => (f.to_string(), Some(a.to_string())),
            None => (target.to_string(), None),
        };
        out.push((file, anchor));
    }
    out
}

/// GitHub's anchors of a page's headings.
fn anchors(text: &str) -> HashSet<String> {
    text.lines()
        .filter(|l| l.starts_with('#'))
        .map(|l| {
            l.trim_start_matches('#')
                .trim()
                .to_lowercase()
                .chars()
                .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
                .map(|c| if c == ' ' { '-' } else { c })
                .collect()
        })
        .collect()
}

fn pages() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    v.sort();
    v
}

#[test]
fn the_readme_is_short_and_reaches_every_page() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(
        readme.lines().count() <= 150,
        "README.md has {} lines",
        readme.lines().count()
    );
    assert!(
        !readme.contains("SPEC.md"),
        "the README sends no one outside the repository"
    );
    let linked: HashSet<String> = links(&readme).into_iter().map(|(f, _)| f).collect();
    for page in pages() {
        let rel = format!("docs/{}", page.file_name().unwrap().to_string_lossy());
        assert!(linked.contains(&rel), "{rel} is not linked from README.md");
    }
}

#[test]
fn every_link_resolves() {
    let mut files = vec![root().join("README.md")];
    files.extend(pages());
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let dir = file.parent().unwrap();
        for (target, anchor) in links(&text) {
            let path = if target.is_empty() {
                file.clone()
            } else {
                dir.join(&target)
            };
            let canonical = path
                .canonicalize()
                .unwrap_or_else(|_| panic!("{}: link to {target}: no such file", file.display()));
            assert!(
                canonical.starts_with(root().canonicalize().unwrap()),
                "{}: {target} is outside the repository",
                file.display()
            );
            if let Some(a) = anchor
                && target.ends_with(".md") | target.is_empty()
            {
                let page = std::fs::read_to_string(&canonical).unwrap();
                assert!(
                    anchors(&page).contains(&a),
                    "{}: link to {target}#{a}: no such heading",
                    file.display()
                );
            }
        }
    }
}

/// The files a user reads below `dir` with one of `endings`, recursively.
fn user_files(dir: &Path, endings: &[&str], out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            user_files(&p, endings, out);
        } else if endings.iter().any(|x| p.to_string_lossy().ends_with(x)) {
            out.push(p);
        }
    }
}

/// What a user reads (the README, the docs, the configs' comments, the examples' pages
/// and Python) sends them to no document outside the repository: the model is
/// docs/model.md's, not a specification they do not have.
#[test]
fn no_page_or_config_cites_a_document_outside_the_repository() {
    let root = root();
    let mut files = vec![root.join("README.md"), root.join("CHANGELOG.md")];
    files.extend(pages());
    user_files(&root.join("configs"), &[".toml"], &mut files);
    user_files(&root.join("examples"), &[".md", ".py", ".toml"], &mut files);
    user_files(&root.join("python/python"), &[".py", ".pyi"], &mut files);
    assert!(files.len() > 60, "{}", files.len());
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for needle in ["SPEC ", "SPEC.md", "../shared"] {
            assert!(
                !text.contains(needle),
                "{} cites {needle:?}: say it with a page of docs/",
                f.display()
            );
        }
    }
}

/// One word, one meaning: every page of prose sends its reader to the glossary, which
/// defines the words the pages use before their own definitions.
#[test]
fn every_page_links_the_glossary_and_the_glossary_defines_the_words() {
    let model = std::fs::read_to_string(root().join("docs/model.md")).unwrap();
    let glossary = &model[model.find("## Glossary").expect("a glossary")..];
    let glossary = &glossary[..glossary[3..].find("\n## ").unwrap()];
    for word in [
        "| CL, CQ |",
        "| d_opt, d_max |",
        "| tick, epoch |",
        "| cell |",
        "| bin |",
        "| rho, tau |",
        "| goal, converged, stuck |",
    ] {
        assert!(glossary.contains(word), "the glossary defines {word}");
    }
    for page in pages() {
        let name = page.file_name().unwrap().to_string_lossy().into_owned();
        if name == "model.md" || name.ends_with("-table.md") {
            continue;
        }
        let text = std::fs::read_to_string(&page).unwrap();
        assert!(
            text.contains("(model.md#glossary)"),
            "docs/{name} links the glossary"
        );
    }
}

/// The house stays within its sizes: a page of docs/ holds at most 400 lines (tables
/// made by scripts, `*-table.md`, excepted), a source file at most 600; past that, a page
/// or a module is split along a seam a reader would look for.
#[test]
fn pages_and_source_files_stay_within_their_sizes() {
    let root = root();
    let mut too_long = Vec::new();
    for page in pages() {
        let name = page.file_name().unwrap().to_string_lossy().to_string();
        let lines = std::fs::read_to_string(&page).unwrap().lines().count();
        if !name.ends_with("-table.md") && lines > 400 {
            too_long.push(format!("docs/{name}: {lines} lines (at most 400)"));
        }
    }
    let mut sources = Vec::new();
    for dir in ["crates", "python/src", "examples", "benches"] {
        user_files(&root.join(dir), &[".rs"], &mut sources);
    }
    let sources: Vec<PathBuf> = sources
        .into_iter()
        .filter(|p| {
            let s = p.to_string_lossy();
            s.contains("/src/") && !s.contains("/target/")
        })
        .collect();
    assert!(sources.len() > 50, "{}", sources.len());
    for file in sources {
        let lines = std::fs::read_to_string(&file).unwrap().lines().count();
        if lines > 600 {
            too_long.push(format!(
                "{}: {lines} lines (at most 600)",
                file.strip_prefix(&root).unwrap_or(&file).display()
            ));
        }
    }
    assert!(too_long.is_empty(), "{}", too_long.join("\n"));
}
