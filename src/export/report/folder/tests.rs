//! The folder replaced whole, with a file written into it while the report runs.

use super::*;

/// What a test's report returns: nothing with paths in it.
#[derive(Debug)]
struct Nothing;

impl Relocate for Nothing {
    fn relocate(&mut self, _: &Path, _: &Path) {}
}

/// A report of one page into `dest`, during which `meanwhile` runs (another job writing
/// into the destination after it was checked, before the swap).
fn report(dest: &Path, page: &str, meanwhile: impl FnOnce()) -> Result<Nothing> {
    replace(dest, |staged| {
        std::fs::write(staged.join("report.html"), page).unwrap();
        meanwhile();
        Ok(Nothing)
    })
}

#[test]
fn a_file_written_into_the_folder_while_the_report_runs_is_kept_with_the_old_report() {
    let dir = tempfile::tempdir().unwrap();
    let dest = dir.path().join("rep");
    report(&dest, "first", || {}).unwrap();
    let notes = dest.join("notes.txt");
    let err = report(&dest, "second", || std::fs::write(&notes, "mine").unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("notes.txt was written into it while the report ran"),
        "{err}"
    );
    // The user's file and the old report, untouched; no staging folder left behind.
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "mine");
    assert_eq!(
        std::fs::read_to_string(dest.join("report.html")).unwrap(),
        "first"
    );
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["rep"]);
    // Without a writer meanwhile, the next report (the file moved out) replaces it.
    std::fs::remove_file(&notes).unwrap();
    report(&dest, "third", || {}).unwrap();
    assert_eq!(
        std::fs::read_to_string(dest.join("report.html")).unwrap(),
        "third"
    );
}

#[test]
fn an_empty_folder_given_a_file_while_the_report_runs_is_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let dest = dir.path().join("rep");
    std::fs::create_dir(&dest).unwrap();
    let log = dest.join("run.csv");
    let err = report(&dest, "first", || std::fs::write(&log, "t,w").unwrap())
        .unwrap_err()
        .to_string();
    assert!(err.contains("run.csv was written into it"), "{err}");
    assert_eq!(std::fs::read_to_string(&log).unwrap(), "t,w");
    assert!(!dest.join("report.html").exists());
}
