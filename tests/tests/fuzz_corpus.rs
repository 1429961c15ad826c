//! Replays the scene fuzzer's corpus (`fuzz/corpus/scene`, kept by `cargo xtask fuzz`) through
//! the loader in the normal test suite, so that every input the fuzzer ever found interesting
//! stays handled: refused with a message, or accepted and simulated finitely.

use std::path::Path;

use tumble_physics::{Limits, World};
use tumble_scene::{Format, LoadLimits, parse};
use tumble_tests::all_finite;

#[test]
fn every_corpus_input_is_refused_or_simulates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/scene");
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    // The same small limits as the fuzz target, so accepted inputs stay quick.
    let limits = LoadLimits {
        max_file_bytes: 1 << 20,
        scene: Limits {
            max_bodies: 64,
            max_substeps: 8,
        },
    };
    let (mut accepted, mut refused) = (0, 0);
    for path in &entries {
        let data = std::fs::read(path).unwrap();
        let Some((&first, text)) = data.split_first() else {
            continue;
        };
        let format = if first & 1 == 0 {
            Format::Ron
        } else {
            Format::Json
        };
        match parse(text, format, "corpus", &limits) {
            Ok(scene) => {
                let mut w = World::from_scene(&scene, &limits.scene).unwrap_or_else(|e| {
                    panic!("{}: accepted but refused by World: {e}", path.display())
                });
                for _ in 0..30 {
                    w.step(scene.dt, scene.substeps);
                }
                assert!(all_finite(&w), "{}: non-finite state", path.display());
                accepted += 1;
            }
            Err(e) => {
                // A refusal is a message that names the origin, never an empty string.
                assert!(e.to_string().contains("corpus"), "{}: {e}", path.display());
                refused += 1;
            }
        }
    }
    // The corpus was seeded with the asset scenes and grew to hundreds of inputs; both kinds
    // must be present or the replay proves little.
    assert!(entries.len() >= 100, "only {} corpus files", entries.len());
    assert!(
        accepted >= 5 && refused >= 5,
        "accepted {accepted}, refused {refused}"
    );
}
