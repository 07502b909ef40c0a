//! What the workbench remembers between runs (not part of any session): the theme, the
//! recent files, the window's place and size, the last folder. A small JSON file in the
//! user's config folder (`$XDG_CONFIG_HOME/driftlab/workbench.json`, else
//! `~/.config/driftlab/workbench.json`), written atomically; a missing or unreadable file
//! gives the defaults.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The colour theme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ThemeChoice {
    /// Follow the desktop.
    #[default]
    System,
    /// Light.
    Light,
    /// Dark.
    Dark,
}

/// The window's last place and size, points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowGeometry {
    /// Left edge.
    pub x: f32,
    /// Top edge.
    pub y: f32,
    /// Inner width.
    pub width: f32,
    /// Inner height.
    pub height: f32,
    /// Whether it was maximised.
    #[serde(default)]
    pub maximized: bool,
}

/// Remembered between runs.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Colour theme.
    pub theme: ThemeChoice,
    /// Recently opened logs and sessions, newest first.
    pub recent: Vec<PathBuf>,
    /// The window.
    pub window: Option<WindowGeometry>,
    /// Folder of the last file opened or saved.
    pub last_dir: Option<PathBuf>,
    /// Folders files were opened from or saved to, newest first (the workbench's own file
    /// dialog offers them).
    pub recent_dirs: Vec<PathBuf>,
}

const RECENT_MAX: usize = 10;

impl Settings {
    /// Where the settings live, when a config folder can be found.
    pub fn default_path() -> Option<PathBuf> {
        let base = std::env::var_os("XDG_CONFIG_HOME")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
        Some(base.join("driftlab").join("workbench.json"))
    }

    /// Reads the settings; defaults when the file is missing or unreadable.
    pub fn load(path: &Path) -> Settings {
        std::fs::read_to_string(path)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or_default()
    }

    /// Writes the settings atomically (creating the folder).
    pub fn save(&self, path: &Path) -> Result<(), String> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())? + "\n";
        crate::files::atomic::write_bytes(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Puts `path` first in the recent files.
    pub fn add_recent(&mut self, path: &Path) {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| p != &path);
        self.recent.insert(0, path.clone());
        self.recent.truncate(RECENT_MAX);
        if let Some(dir) = path.parent() {
            self.add_recent_dir(dir);
        }
    }

    /// Puts `dir` first in the recent folders (and makes it the last folder).
    pub fn add_recent_dir(&mut self, dir: &Path) {
        let dir = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
        self.recent_dirs.retain(|d| d != &dir);
        self.recent_dirs.insert(0, dir.clone());
        self.recent_dirs.truncate(RECENT_MAX);
        self.last_dir = Some(dir);
    }
}
