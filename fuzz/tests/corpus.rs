//! Every input of the committed corpus (`corpus/<target>/`) and every
//! crash the fuzzer ever found (`artifacts/<target>/`) through its target's
//! check: the fuzz campaign's findings kept as ordinary tests.

use std::path::{Path, PathBuf};

use parasils_fuzz::TARGETS;

/// The files in `dir`, sorted; none when it does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut out: Vec<PathBuf> = entries
        .map(|e| e.expect("a readable folder entry").path())
        .filter(|p| p.is_file())
        .collect();
    out.sort();
    out
}

fn replay(name: &str, check: fn(&[u8])) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    for folder in ["corpus", "artifacts"] {
        for path in files(&root.join(folder).join(name)) {
            let data = std::fs::read(&path).expect("a readable input");
            let outcome = std::panic::catch_unwind(|| check(&data));
            assert!(outcome.is_ok(), "{} fails its check", path.display());
            n += 1;
        }
    }
    n
}

#[test]
fn every_corpus_input_passes_its_target_s_check() {
    let mut counts = Vec::new();
    for (name, check) in TARGETS {
        counts.push((name, replay(name, check)));
    }
    eprintln!("inputs replayed: {counts:?}");
    for (name, n) in counts {
        assert!(n > 0, "the corpus of `{name}` is empty");
    }
}
