//! Every relative link of the repository's Markdown (README, guide, reference, notes, the
//! crates' READMEs) leads to a file or folder that exists: a page moved or renamed leaves
//! no dead link behind.

use std::path::{Path, PathBuf};

/// The Markdown files under `dir`, skipping build outputs, virtual environments and
/// hidden folders.
fn markdown(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("a readable folder") {
        let path = entry.expect("a folder entry").path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if path.is_dir() {
            if !(name.starts_with('.') || name == "target" || name.contains("venv")) {
                markdown(&path, out);
            }
        } else if name.ends_with(".md") {
            out.push(path);
        }
    }
}

/// The targets of the inline links `[text](target)` of `text`, outside code blocks.
fn links(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            found.push(after[..end].trim().to_string());
            rest = &after[end..];
        }
    }
    found
}

#[test]
fn every_relative_link_of_the_docs_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    markdown(&root, &mut files);
    assert!(files.len() > 10, "found only {} pages", files.len());
    let mut dead = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).expect("a UTF-8 page");
        for link in links(&text) {
            let external = link.contains("://") || link.starts_with("mailto:");
            let target = link.split('#').next().unwrap_or("");
            if external || target.is_empty() || target.starts_with('<') {
                continue;
            }
            checked += 1;
            let path = file.parent().expect("a folder").join(target);
            if !path.exists() {
                dead.push(format!("{}: {link}", file.display()));
            }
        }
    }
    assert!(checked > 20, "checked only {checked} links");
    assert!(dead.is_empty(), "dead links:\n{}", dead.join("\n"));
}
