//! The repository's scripts that patch the source still fit it.

use std::path::Path;
use std::process::Command;

/// `scripts/ablation/run` applies `ablate.patch` to a worktree of HEAD; a
/// change to the slab loop that the patch no longer fits must update it.
#[test]
fn the_ablation_patch_applies() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if !root.join(".git").exists() {
        eprintln!("skipping: not a git checkout");
        return;
    }
    let check = Command::new("git")
        .current_dir(root)
        .args(["apply", "--check", "scripts/ablation/ablate.patch"])
        .output();
    let out = match check {
        Ok(out) => out,
        Err(e) => {
            eprintln!("skipping: git not runnable: {e}");
            return;
        }
    };
    assert!(
        out.status.success(),
        "scripts/ablation/ablate.patch does not apply: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}
