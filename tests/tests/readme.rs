//! The README's promises that can rot: its program is `crates/physics/examples/hello.rs`
//! (which `cargo xtask test` runs, and which asserts what it shows), and its links, and those
//! of the manuals in `docs/`, lead to files that exist.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace root")
        .to_path_buf()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The README shows `hello.rs` as it is: the whole file but its leading `//!` lines, as the
/// whole of one ```rust block.
#[test]
fn the_readme_program_is_the_hello_example() {
    let root = root();
    let example = read(&root.join("crates/physics/examples/hello.rs"));
    let program = example
        .lines()
        .skip_while(|line| line.starts_with("//!") || line.trim().is_empty())
        .collect::<Vec<_>>()
        .join("\n");
    assert!(
        program.contains("fn main()"),
        "hello.rs has no main:\n{example}"
    );
    let readme = read(&root.join("README.md"));
    let block = format!("```rust\n{}\n```\n", program.trim_end());
    assert!(
        readme.contains(&block),
        "README.md must show crates/physics/examples/hello.rs (without its `//!` header) as \
         one ```rust block, exactly; copy the file's program into the README:\n\n{block}"
    );
}

/// Every relative link `](target)` in README.md and in the Markdown files directly in docs/
/// names a file or folder that exists (an `#anchor` or an absolute URL is not checked).
#[test]
fn relative_links_in_the_readme_and_docs_resolve() {
    let root = root();
    let mut files = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).expect("docs/") {
        let path = entry.expect("an entry of docs/").path();
        if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    let mut broken = Vec::new();
    for file in &files {
        let text = read(file);
        let dir = file.parent().unwrap();
        let mut rest = text.as_str();
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            let Some(end) = rest.find(')') else { break };
            let target = rest[..end].split('#').next().unwrap().trim();
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            if !dir.join(target).exists() {
                broken.push(format!("{}: {target}", file.display()));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "links to nothing:\n{}",
        broken.join("\n")
    );
}
