//! The units of a lot, found in the folders given: each log file is a unit of one run, each
//! folder of logs one unit of several runs (a campaign of that gyro), and a recipe lying beside
//! a unit is that unit's own.
//!
//! - In a folder given, every regular file whose name does not start with `.` and does not end
//!   in `.json` is a log, and a unit (a file that is no log is then a unit that cannot be read:
//!   an `error` row, never a silent skip); every folder is a unit whose runs are its own logs,
//!   by the same rule (its folders are left out, and said so).
//! - A file given in place of a folder is a unit of its own.
//! - A unit's own recipe is `<unit>.recipe.json` beside it (`u7.recipe.json` for `u7.csv` or the
//!   folder `u7`), or `recipe.json` inside its folder; both at once is refused for that unit.
//!
//! Units are named as a campaign's runs are ([`run_names`]): by their file or folder name, or
//! where two share one, by the fewest parts of their paths that tell them apart, with any
//! character a terminal would obey escaped. Each unit's outputs go into a folder of `OUT` named
//! from that name by [`folder_of`], which no name can lead out of `OUT`.

use super::LotError;
use crate::log::campaign::run_names;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// How the names of the lot's own files in `OUT` begin (`lot.csv`, `lot.json`, `lot.html`,
/// `lot-shard-3-of-100.json`): no unit's folder begins so.
pub const LOT_FILE_PREFIXES: [&str; 2] = ["lot.", "lot-"];

/// One unit to calibrate.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitJob {
    /// The unit's name, as the table shows it.
    pub name: String,
    /// Its folder in `OUT` ([`folder_of`] its name).
    pub folder: String,
    /// Its file, or its folder of runs.
    pub path: PathBuf,
    /// Its runs: one log, or a folder's logs in the order of their names.
    pub runs: Vec<PathBuf>,
    /// Its own recipe, when one lies beside it.
    pub recipe: Option<PathBuf>,
    /// Why it cannot be calibrated before anything is read (a folder with no log, two
    /// recipes): the unit is then an `error` with this message.
    pub problem: Option<String>,
    /// What was left out of its folder (folders inside it).
    pub notes: Vec<String>,
}

/// The units in `paths` (folders of units, or unit files), in the order given and, within a
/// folder, of their names.
///
/// # Errors
/// A path that cannot be listed, and a lot of no unit at all (a mistyped folder is not an
/// empty lot that passes).
pub fn find_units(paths: &[PathBuf]) -> Result<Vec<UnitJob>, LotError> {
    let mut found: Vec<(PathBuf, bool)> = Vec::new();
    for path in paths {
        let meta = std::fs::metadata(path).map_err(|e| LotError::Io {
            path: path.clone(),
            source: e,
        })?;
        if meta.is_file() {
            found.push((path.clone(), false));
            continue;
        }
        for entry in sorted_entries(path)? {
            let meta = match std::fs::metadata(&entry) {
                Ok(m) => m,
                // A link to nothing is a unit that cannot be read, said in its row.
                Err(_) => {
                    found.push((entry, false));
                    continue;
                }
            };
            if meta.is_dir() {
                found.push((entry, true));
            } else if meta.is_file() && is_log_name(&entry) {
                found.push((entry, false));
            }
        }
    }
    if found.is_empty() {
        return Err(LotError::NoUnits {
            paths: paths.to_vec(),
        });
    }
    let units: Vec<&Path> = found.iter().map(|(p, _)| p.as_path()).collect();
    let names = distinct(run_names(&units));
    // One unit found twice (a folder given twice, a file given beside its folder, by any
    // path, a hard link) would be calibrated twice, into one folder or two. Each unit is
    // looked up once (a lot of ten thousand units is listed in a moment, not in pairs).
    let mut seen: HashMap<Identity, usize> = HashMap::with_capacity(found.len());
    let mut jobs: Vec<UnitJob> = Vec::with_capacity(found.len());
    for ((path, is_folder), name) in found.iter().zip(names) {
        if let Some(id) = identity(path)
            && let Some(&first) = seen.get(&id)
        {
            return Err(LotError::UnitTwice {
                first: jobs[first].path.clone(),
                second: path.clone(),
            });
        } else if let Some(id) = identity(path) {
            seen.insert(id, jobs.len());
        }
        jobs.push(unit_job(path, *is_folder, name)?);
    }
    Ok(jobs)
}

/// What tells one unit from another on disk: its file's device and inode (a hard link, a
/// second path, a link to it are one unit), else its path resolved.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Identity {
    Inode(u64, u64),
    Path(PathBuf),
}

fn identity(path: &Path) -> Option<Identity> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(m) = std::fs::metadata(path) {
            return Some(Identity::Inode(m.dev(), m.ino()));
        }
    }
    std::fs::canonicalize(path).ok().map(Identity::Path)
}

/// The units' names made distinct: two units whose names are one once escaped or made valid
/// text (`u\xff.csv` and `u\xfe.csv` both read `u\u{fffd}.csv`), or whose folders differ
/// only in case (one folder where case is ignored), are two units, the later ones named
/// `~2`, `~3`... after it, so that each has its row and its folder.
fn distinct(names: Vec<String>) -> Vec<String> {
    let mut taken: HashSet<String> = HashSet::with_capacity(names.len());
    let mut folders: HashSet<String> = HashSet::with_capacity(names.len());
    names
        .into_iter()
        .map(|name| {
            let mut candidate = name.clone();
            let mut k = 1;
            // Folders compared as a file system that ignores case would (macOS, Windows).
            let folder = |c: &str| folder_of(c).to_ascii_lowercase();
            while taken.contains(&candidate) || folders.contains(&folder(&candidate)) {
                k += 1;
                candidate = format!("{name}~{k}");
            }
            folders.insert(folder(&candidate));
            taken.insert(candidate.clone());
            candidate
        })
        .collect()
}

/// The unit at `path`, named `name`.
fn unit_job(path: &Path, is_folder: bool, name: String) -> Result<UnitJob, LotError> {
    let mut job = UnitJob {
        folder: folder_of(&name),
        path: path.to_path_buf(),
        name,
        runs: Vec::new(),
        recipe: None,
        problem: None,
        notes: Vec::new(),
    };
    let stem = match (is_folder, path.file_stem()) {
        (true, _) => path.file_name(),
        (false, stem) => stem,
    };
    let mut recipes: Vec<PathBuf> = Vec::new();
    if let (Some(stem), Some(dir)) = (stem, path.parent()) {
        let mut beside = stem.to_os_string();
        beside.push(".recipe.json");
        recipes.push(dir.join(beside));
    }
    if is_folder {
        recipes.push(path.join("recipe.json"));
        for entry in sorted_entries(path)? {
            match std::fs::metadata(&entry) {
                Ok(m) if m.is_dir() => job.notes.push(format!(
                    "{}: a folder inside the unit's folder is left out (a unit's runs are its \
                     folder's logs)",
                    crate::text::escaped(&entry.display().to_string(), false)
                )),
                Ok(m) if m.is_file() && is_log_name(&entry) => job.runs.push(entry),
                Ok(_) => {}
                Err(_) => job.runs.push(entry),
            }
        }
        if job.runs.is_empty() {
            job.problem = Some(format!(
                "{}: the unit's folder holds no log (its logs are the files not ending in .json)",
                crate::text::escaped(&path.display().to_string(), false)
            ));
        }
    } else {
        job.runs.push(path.to_path_buf());
    }
    let present: Vec<PathBuf> = recipes.into_iter().filter(|r| r.is_file()).collect();
    match present.as_slice() {
        [] => {}
        [one] => job.recipe = Some(one.clone()),
        [a, b, ..] => {
            job.problem.get_or_insert(format!(
                "two recipes for the unit, {} and {}: keep one",
                a.display(),
                b.display()
            ));
        }
    }
    Ok(job)
}

/// The entries of the folder `dir`, hidden ones left out, in the order of their names.
fn sorted_entries(dir: &Path) -> Result<Vec<PathBuf>, LotError> {
    let io = |e| LotError::Io {
        path: dir.to_path_buf(),
        source: e,
    };
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let entry = entry.map_err(io)?;
        if !entry.file_name().to_string_lossy().starts_with('.') {
            out.push(entry.path());
        }
    }
    out.sort();
    Ok(out)
}

/// Whether a file in a lot's folder is taken as a log: any name but a hidden one and JSON (a
/// recipe, a spec, a calibration).
fn is_log_name(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    !name.starts_with('.') && !name.to_ascii_lowercase().ends_with(".json")
}

/// The folder of `OUT` a unit named `name` writes into: the name with every byte but ASCII
/// letters, digits, `_`, a `-` and a `.` after the first written as `%XX`, so that it stays
/// one folder inside `OUT` (no `/`, no `..`, no hidden name, nothing a shell tool takes for an
/// option or a spreadsheet for a formula) and two names never share one; a name that begins
/// as the lot's own files do ([`LOT_FILE_PREFIXES`]) has its first letter so written too. A
/// folder name longer than [`MAX_FOLDER_BYTES`] (a file system takes 255 bytes) is cut and
/// ends in `~` and a hash of the whole name, which keeps it apart from every other.
pub fn folder_of(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for (i, b) in name.bytes().enumerate() {
        let keep = b.is_ascii_alphanumeric() || b == b'_' || ((b == b'.' || b == b'-') && i > 0);
        if keep {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    let lower = out.to_ascii_lowercase();
    if LOT_FILE_PREFIXES.iter().any(|p| lower.starts_with(p)) {
        out = format!("%{:02X}{}", out.as_bytes()[0], &out[1..]);
    }
    if out.len() > MAX_FOLDER_BYTES {
        use sha2::Digest;
        let hash: String = sha2::Sha256::digest(name.as_bytes())[..8]
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        // Cut before a `%XX` it would split (the text is ASCII: any byte is a boundary).
        let mut cut = MAX_FOLDER_BYTES - hash.len() - 1;
        while let Some(p) = out[..cut].rfind('%').filter(|&p| p + 3 > cut) {
            cut = p;
        }
        out = format!("{}~{hash}", &out[..cut]);
    }
    out
}

/// The longest folder name [`folder_of`] writes, in bytes: under the 255 of common file
/// systems, with room for the `.driftlab-staging-…` names written beside it.
pub const MAX_FOLDER_BYTES: usize = 160;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_name_stays_inside_out_and_apart_from_every_other() {
        assert_eq!(folder_of("u7.csv"), "u7.csv");
        assert_eq!(folder_of("day1/u7.csv"), "day1%2Fu7.csv");
        assert_eq!(folder_of(".."), "%2E.");
        assert_eq!(folder_of("a b"), "a%20b");
        assert_eq!(folder_of("a%20b"), "a%2520b");
        assert_eq!(folder_of("lot.csv"), "%6Cot.csv");
        assert_eq!(
            folder_of("lot-shard-1-of-2.json"),
            "%6Cot-shard-1-of-2.json"
        );
        assert_eq!(folder_of("lots"), "lots");
        assert_ne!(folder_of("%6Cot.csv"), folder_of("lot.csv"));
        assert_eq!(folder_of("-42.csv"), "%2D42.csv");
        assert_eq!(folder_of("a-b"), "a-b");
    }

    #[test]
    fn a_long_name_gets_a_short_folder_of_its_own() {
        let a = "\u{e9}".repeat(100);
        let b = format!("{}x", "\u{e9}".repeat(100));
        let (fa, fb) = (folder_of(&a), folder_of(&b));
        assert!(fa.len() <= MAX_FOLDER_BYTES, "{}", fa.len());
        assert_ne!(fa, fb);
        assert!(!fa.contains('/') && !fa.starts_with('.'));
        // A `%XX` is never cut in two.
        let stem = fa.rsplit_once('~').unwrap().0;
        assert!(stem.len() >= 3 && stem.rfind('%').is_none_or(|p| p + 3 <= stem.len()));
    }

    #[test]
    fn names_one_once_escaped_are_made_two() {
        let names = distinct(vec![
            "u\u{fffd}.csv".into(),
            "u\u{fffd}.csv".into(),
            "v".into(),
        ]);
        assert_eq!(names, ["u\u{fffd}.csv", "u\u{fffd}.csv~2", "v"]);
        let names = distinct(vec!["U1.csv".into(), "u1.csv".into()]);
        assert_eq!(names, ["U1.csv", "u1.csv~2"]);
        assert_eq!(folder_of("LOT.csv"), "%4COT.csv");
    }
}
