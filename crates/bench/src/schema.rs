//! `tumble-bench schema [--out FILE]`: the JSON Schema of scene files, for editors.
//!
//! The schema comes from the scene types themselves (tumble-physics's `schema` feature, with
//! `schemars`), so it says what the loader accepts. docs/scene.schema.json is this command's
//! output; a test keeps the two equal.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

/// Arguments of `tumble-bench schema`.
#[derive(Debug, Args)]
pub struct SchemaArgs {
    /// Write the schema to FILE instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The schema as pretty JSON, ending in a newline.
pub fn render() -> Result<String> {
    let mut text = serde_json::to_string_pretty(&tumble_physics::scene_schema())
        .context("could not render the scene schema as JSON")?;
    text.push('\n');
    Ok(text)
}

/// Prints the schema, or writes it to `--out`.
pub fn run(args: &SchemaArgs) -> Result<()> {
    let text = render()?;
    match &args.out {
        Some(path) => std::fs::write(path, text)
            .with_context(|| format!("{}: could not write the schema", path.display())),
        None => {
            use std::io::Write;
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(text.as_bytes())
                .and_then(|()| stdout.flush())
                .context("could not write the schema to stdout")
        }
    }
}
