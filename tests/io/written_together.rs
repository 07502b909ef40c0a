//! Files one command writes together are put in place together: every file is written
//! first, and only when all are written are they renamed over their destinations. A command
//! that fails on any of them leaves every destination as it was.

use driftlab::files::atomic::Batch;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

const OLD: &[u8] = b"the engineer's previous file\n";

/// Files in `dir` whose names say they are temporaries of driftlab's.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(".driftlab-"))
        })
        .collect()
}

#[test]
fn nothing_is_in_place_until_every_file_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let a = dir.join("a.json");
    let fresh = dir.join("fresh.json");
    fs::write(&a, OLD).unwrap();
    let mut batch = Batch::new();
    batch.stage_bytes(&a, b"new a").unwrap();
    batch.stage_bytes(&fresh, b"new fresh").unwrap();
    // Written, synced, and not yet in place.
    assert_eq!(fs::read(&a).unwrap(), OLD);
    assert!(!fresh.exists());
    batch.commit().unwrap();
    assert_eq!(fs::read(&a).unwrap(), b"new a");
    assert_eq!(fs::read(&fresh).unwrap(), b"new fresh");
    assert!(temporaries(dir).is_empty(), "{:?}", temporaries(dir));
}

#[test]
fn one_file_that_cannot_be_written_leaves_every_destination_as_it_was() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let a = dir.join("a.json");
    fs::write(&a, OLD).unwrap();
    let not_a_folder = dir.join("notes.txt");
    fs::write(&not_a_folder, "a file").unwrap();
    let cases: [(&str, PathBuf); 3] = [
        ("its folder is a file", not_a_folder.join("b.json")),
        ("it is a folder", dir.to_path_buf()),
        ("its writer fails", dir.join("b.json")),
    ];
    for (why, b) in cases {
        let mut batch = Batch::new();
        batch.stage_bytes(&a, b"new a").unwrap();
        let e = batch
            .stage_with(&b, |w| {
                w.write_all(b"half of b")?;
                Err(std::io::Error::other("the writer gave up"))
            })
            .expect_err(why)
            .to_string();
        assert!(e.contains(&b.display().to_string()), "{why}: names it: {e}");
        // The command stops here: the batch goes without a commit.
        drop(batch);
        assert_eq!(fs::read(&a).unwrap(), OLD, "{why}");
        assert!(!dir.join("b.json").exists(), "{why}");
        assert!(temporaries(dir).is_empty(), "{why}: {:?}", temporaries(dir));
    }
    // The same file twice would leave one of the two contents to chance: refused.
    let mut batch = Batch::new();
    batch.stage_bytes(&a, b"one").unwrap();
    let e = batch
        .stage_bytes(&dir.join(".").join("a.json"), b"two")
        .unwrap_err();
    assert!(e.to_string().contains("twice"), "{e}");
}

fn calibrate(out: &Path, save_recipe: &Path) -> std::process::Output {
    let log = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .arg("calibrate")
        .arg(log)
        .arg("-o")
        .arg(out)
        .arg("--save-recipe")
        .arg(save_recipe)
        .output()
        .unwrap()
}

#[test]
fn calibrate_that_cannot_save_its_recipe_keeps_the_old_calibration() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let keep = dir.join("keep.json");
    fs::write(&keep, OLD).unwrap();
    let a_file = dir.join("recipes");
    fs::write(&a_file, "not a folder").unwrap();
    let a_folder = dir.join("folder.json");
    fs::create_dir(&a_folder).unwrap();
    for recipe in [a_file.join("recipe.json"), a_folder] {
        let out = calibrate(&keep, &recipe);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{}: {err}", recipe.display());
        assert!(
            err.contains(&recipe.display().to_string()),
            "the error names the recipe: {err}"
        );
        assert_eq!(fs::read(&keep).unwrap(), OLD, "{}", recipe.display());
        assert!(temporaries(dir).is_empty(), "{:?}", temporaries(dir));
    }
    // Both writable: both written.
    let recipe = dir.join("recipe.json");
    let out = calibrate(&keep, &recipe);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cal: serde_json::Value = serde_json::from_slice(&fs::read(&keep).unwrap()).unwrap();
    let saved: serde_json::Value = serde_json::from_slice(&fs::read(&recipe).unwrap()).unwrap();
    assert!(cal.get("format").is_some(), "{cal}");
    assert!(saved.get("filter_s").is_some(), "{saved}");
}
