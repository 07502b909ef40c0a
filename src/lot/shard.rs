//! A lot past one machine: `--shard i/n` calibrates the units of one shard of the lot (one
//! task of a batch scheduler's job array), and `lot merge` joins the shards' tables into the
//! lot's, which equals the table of the whole lot run at once.
//!
//! A unit's shard is told by its name alone (the SHA-256 of the name, modulo n), so every
//! task, listing the same folders, agrees on it without talking to the others, and a unit keeps
//! its shard when others are added. Each shard writes its units' folders into `OUT` as a whole
//! lot would (shards sharing one `OUT` never write the same folder) and its table as
//! `OUT/lot-shard-I-of-N.json`, with each unit's place in the whole lot and a fingerprint of
//! the lot's list of units, so that a merge can tell shards of another lot, or of another
//! listing of it, and a shard missing. Outliers are found by the merge, over the whole lot.

use super::{LotError, LotOutcome, Spec, UnitOutcome};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The most shards a lot may be split into.
pub const MAX_SHARDS: usize = 1_000_000;

/// One shard of a lot: the `index`-th (from 1) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shard {
    /// Which shard, from 1.
    pub index: usize,
    /// How many.
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;

    /// `I/N`: shard I of N, 1 ≤ I ≤ N ≤ [`MAX_SHARDS`].
    fn from_str(s: &str) -> Result<Shard, String> {
        let parsed = s
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((index, count))
                if (1..=MAX_SHARDS).contains(&count) && (1..=count).contains(&index) =>
            {
                Ok(Shard { index, count })
            }
            _ => Err(format!(
                "\"{}\": give I/N, shard I of N, 1 ≤ I ≤ N ≤ {MAX_SHARDS} (a job array's task \
                 number and size: 3/100)",
                s.escape_debug()
            )),
        }
    }
}

impl Shard {
    /// Whether the unit named `name` is of this shard.
    pub fn holds(&self, name: &str) -> bool {
        let digest = Sha256::digest(name.as_bytes());
        let mut first = [0u8; 8];
        first.copy_from_slice(&digest[..8]);
        (u64::from_be_bytes(first) % self.count as u64) as usize == self.index - 1
    }

    /// The file of its table in `OUT`.
    pub fn file_name(&self) -> String {
        format!("lot-shard-{}-of-{}.json", self.index, self.count)
    }
}

/// A unit of a shard, with its place in the whole lot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placed {
    /// Its place in the whole lot's order, from 0.
    pub position: usize,
    /// Its outcome.
    pub outcome: UnitOutcome,
}

/// A shard's table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardTable {
    /// Which shard.
    pub shard: Shard,
    /// The spec its units were held to.
    pub spec: Spec,
    /// Units in the whole lot.
    pub lot_units: usize,
    /// SHA-256 of the whole lot's unit names, in order: the same for every shard of one
    /// listing of one lot.
    pub lot_fingerprint: String,
    /// SHA-256 of the shared recipe (`--recipe`), as a unit's key holds it; none for the
    /// defaults. Shards of one lot share it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub recipe_sha256: Option<String>,
    /// The shard's units.
    pub units: Vec<Placed>,
}

/// The fingerprint of a lot's list of unit names.
pub fn fingerprint<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let mut hasher = Sha256::new();
    for name in names {
        hasher.update(name.as_bytes());
        hasher.update([0u8]);
    }
    hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Writes a shard's table into `out`.
///
/// # Errors
/// The write's.
pub fn write(out: &Path, table: &ShardTable) -> crate::Result<()> {
    let path = out.join(table.shard.file_name());
    let text = serde_json::to_string_pretty(table)
        .map_err(|e| crate::Error::io(&path, std::io::Error::other(e)))?
        + "\n";
    crate::files::atomic::write_bytes(&path, text.as_bytes())
        .map_err(|e| crate::Error::io(&path, e))
}

/// Joins the shards' tables in `out` into the lot's: every shard of one lot present once, its
/// units in the whole lot's order, the outliers found over them all, and `lot.csv` and
/// `lot.json` written as the whole lot run at once writes them.
///
/// # Errors
/// No shard's table in `out`, tables of different lots (shard counts, specs, listings), a
/// shard missing or given twice, a unit's outcome holding what the lot does not compute
/// ([`super::read_back`]), and the write.
pub fn merge(out: &Path) -> Result<LotOutcome, LotError> {
    let refused = |message: String| LotError::Merge {
        out: out.to_path_buf(),
        message,
    };
    if !out.is_dir() {
        return Err(LotError::Io {
            path: out.to_path_buf(),
            source: std::io::Error::from(std::io::ErrorKind::NotFound),
        });
    }
    // No shard writes while the lot is joined.
    let _lock = super::lock::lock(out, None)?;
    let tables = read_tables(out)?;
    let Some((first_path, first)) = tables.first() else {
        return Err(refused(
            "holds no shard's table (lot-shard-I-of-N.json, which each shard of a lot writes \
             into its output folder)"
                .into(),
        ));
    };
    let name = |p: &PathBuf| {
        p.file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into())
    };
    for (path, t) in &tables[1..] {
        let differs = if t.shard.count != first.shard.count {
            Some("a count of shards")
        } else if t.spec != first.spec {
            Some("a spec")
        } else if t.recipe_sha256 != first.recipe_sha256 {
            Some("shared recipe")
        } else if t.lot_units != first.lot_units || t.lot_fingerprint != first.lot_fingerprint {
            Some("a list of units")
        } else {
            None
        };
        if let Some(what) = differs {
            return Err(refused(format!(
                "{} and {} have another {what}: they are shards of two lots (or of two \
                 listings of one); remove the other lot's tables, or merge each lot in its own \
                 folder",
                name(first_path),
                name(path)
            )));
        }
    }
    let count = first.shard.count;
    let missing: Vec<String> = (1..=count)
        .filter(|i| !tables.iter().any(|(_, t)| t.shard.index == *i))
        .map(|i| Shard { index: i, count }.file_name())
        .collect();
    if !missing.is_empty() {
        let shown: Vec<&str> = missing.iter().take(8).map(String::as_str).collect();
        return Err(refused(format!(
            "{} of the {count} shards missing ({}{}): run them, then merge",
            missing.len(),
            shown.join(", "),
            if missing.len() > shown.len() {
                ", …"
            } else {
                ""
            }
        )));
    }
    // The lot's size is what its tables hold, never a number a table states: a table cut,
    // edited or made by hand is refused before anything is made for it.
    let held: usize = tables.iter().map(|(_, t)| t.units.len()).sum();
    if held != first.lot_units {
        return Err(refused(format!(
            "the shards' tables hold {held} units, and say their lot has {}: a shard's table \
             was cut or edited; run that shard again",
            first.lot_units
        )));
    }
    let mut slots: Vec<Option<UnitOutcome>> = vec![None; held];
    for (path, t) in &tables {
        for p in &t.units {
            match slots.get_mut(p.position) {
                Some(slot @ None) => {
                    *slot = Some(p.outcome.clone().settled(&first.spec, out, path)?);
                }
                _ => {
                    return Err(refused(format!(
                        "{}: unit {} at place {} of a lot of {}, which another shard holds or \
                         the lot has not",
                        name(path),
                        p.outcome.unit,
                        p.position,
                        first.lot_units
                    )));
                }
            }
        }
    }
    let units: Option<Vec<UnitOutcome>> = slots.into_iter().collect();
    let Some(units) = units else {
        return Err(refused(
            "the shards' tables hold fewer units than their lot: a shard's table was cut or \
             edited; run that shard again"
                .into(),
        ));
    };
    let spec = first.spec.clone();
    let outliers = LotOutcome::find_outliers(&spec, &units);
    let lot = LotOutcome {
        spec,
        units,
        outliers,
    };
    super::table::write(out, &lot)?;
    Ok(lot)
}

/// Every shard's table in `out`, in the order of their shard numbers.
fn read_tables(out: &Path) -> Result<Vec<(PathBuf, ShardTable)>, LotError> {
    let io = |e| LotError::Io {
        path: out.to_path_buf(),
        source: e,
    };
    let mut tables = Vec::new();
    for entry in std::fs::read_dir(out).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if !(name.starts_with("lot-shard-") && name.ends_with(".json")) {
            continue;
        }
        let text = std::fs::read_to_string(&path).map_err(|e| LotError::Io {
            path: path.clone(),
            source: e,
        })?;
        let table: ShardTable = serde_json::from_str(&text).map_err(|e| LotError::Merge {
            out: out.to_path_buf(),
            message: format!("{name}: not a shard's table: {e}"),
        })?;
        if table.shard.file_name() != name {
            return Err(LotError::Merge {
                out: out.to_path_buf(),
                message: format!(
                    "{name} holds the table of shard {} of {}: a shard's table keeps the name \
                     its shard gave it",
                    table.shard.index, table.shard.count
                ),
            });
        }
        tables.push((path, table));
    }
    tables.sort_by_key(|(_, t)| t.shard.index);
    Ok(tables)
}
