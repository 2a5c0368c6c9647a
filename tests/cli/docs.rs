//! The documentation a reader follows: every relative link of README.md and docs/*.md
//! (and of the scenario format's README) resolves to a file or directory inside this
//! repository, and the README stays short enough to read in five minutes with its two
//! commands at the top.

use super::repo;
use std::path::{Component, Path, PathBuf};

/// The targets of every Markdown link and image of `text` (`[text](target)`,
/// `![alt](target)`), their `#anchor` dropped; web links left out.
fn relative_links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].trim();
        let target = target.split('#').next().unwrap_or("");
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            out.push(target.to_string());
        }
    }
    out
}

/// `target` resolved against `from`'s directory, within the repository (None: it leaves
/// the repository).
fn resolve(root: &Path, from: &Path, target: &str) -> Option<PathBuf> {
    let mut path = from.parent()?.strip_prefix(root).ok()?.to_path_buf();
    for c in Path::new(target).components() {
        match c {
            Component::ParentDir => {
                if !path.pop() {
                    return None;
                }
            }
            Component::Normal(p) => path.push(p),
            Component::CurDir => {}
            _ => return None,
        }
    }
    Some(root.join(path))
}

#[test]
fn every_relative_link_of_the_docs_resolves_inside_the_repository() {
    let root = repo("");
    let mut files = vec![root.join("README.md"), root.join("scenarios/README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "md") {
            files.push(p);
        }
    }
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for target in relative_links(&text) {
            checked += 1;
            match resolve(&root, file, &target) {
                Some(p) if p.exists() => {}
                Some(p) => broken.push(format!(
                    "{}: {target} ({} missing)",
                    file.display(),
                    p.display()
                )),
                None => broken.push(format!(
                    "{}: {target} leaves the repository",
                    file.display()
                )),
            }
        }
    }
    assert!(
        checked > 10,
        "only {checked} links found: is the reader right?"
    );
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_link_reader_finds_links_and_refuses_escapes() {
    let links = relative_links("a [x](docs/a.md#b) ![i](img.png) [w](https://x.org) [m](mailto:a)");
    assert_eq!(links, ["docs/a.md", "img.png"]);
    let root = Path::new("/r");
    assert_eq!(
        resolve(
            root,
            Path::new("/r/docs/usage.md"),
            "../scenarios/README.md"
        ),
        Some(PathBuf::from("/r/scenarios/README.md"))
    );
    assert_eq!(
        resolve(root, Path::new("/r/README.md"), "../shared/notes/a.md"),
        None
    );
}

#[test]
fn the_readme_is_short_and_starts_with_its_commands() {
    let text = std::fs::read_to_string(repo("README.md")).unwrap();
    assert!(
        text.len() <= 12_000,
        "README.md is {} characters",
        text.len()
    );
    let top: Vec<&str> = text.lines().take(40).collect();
    for command in [
        "cargo run --release -- run scenarios/quickstart.toml",
        "cargo test --release --workspace",
    ] {
        assert!(
            top.contains(&command),
            "`{command}` is not in the first 40 lines"
        );
    }
}
