//! driftlab's own file dialog, drawn inside the window, for desktops where no system dialog can
//! appear: a path field with completion (Tab takes the suggestion the arrows pick), the
//! folder's listing filtered by kind, the recent folders, and a file name prefilled in a
//! sensible folder. Enter accepts, Escape cancels; writing over an existing file asks first.
//!
//! Why not a crate: egui-file-dialog's newest release (0.15) is built on egui 0.36, and
//! egui_file 0.29 (egui 0.37) has no completion, no recent folders, needs the name field
//! clicked before Enter accepts, and prints its errors to standard output.

use super::dialogs::FileKind;
use eframe::egui::{self, Key, RichText, Ui};
use std::path::{Path, PathBuf};

/// Open an existing file, or choose where to write one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// An existing file.
    Open,
    /// A file (or, for the report, a folder) to write.
    Save,
}

/// What the engineer decided.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// This path.
    Accept(PathBuf),
    /// Nothing.
    Cancel,
}

/// One entry of the folder's listing.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Entry {
    name: String,
    is_dir: bool,
}

/// The dialog's state while it is open.
#[derive(Debug)]
pub struct FileDialog {
    mode: Mode,
    kind: FileKind,
    /// The path field: a folder followed by a file name.
    text: String,
    /// The folder listed (the path field's folder, as last read).
    listed: Option<PathBuf>,
    entries: Vec<Entry>,
    list_error: Option<String>,
    recent: Vec<PathBuf>,
    all_files: bool,
    /// A message under the path field (no such file, no such folder).
    error: Option<String>,
    /// An existing file to be written over, waiting for a second Enter.
    overwrite: Option<PathBuf>,
    focus_pending: bool,
}

impl FileDialog {
    /// A dialog for `kind`, its path field holding `name` in `dir`; `recent` folders are
    /// offered as shortcuts.
    pub fn new(mode: Mode, kind: FileKind, dir: &Path, name: &str, recent: Vec<PathBuf>) -> Self {
        let mut text = dir.display().to_string();
        if !text.ends_with(std::path::MAIN_SEPARATOR) {
            text.push(std::path::MAIN_SEPARATOR);
        }
        text.push_str(name);
        let mut d = FileDialog {
            mode,
            kind,
            text,
            listed: None,
            entries: Vec::new(),
            list_error: None,
            recent,
            all_files: false,
            error: None,
            overwrite: None,
            focus_pending: true,
        };
        d.refresh();
        d
    }

    /// What kind of file it asks for.
    pub fn kind(&self) -> FileKind {
        self.kind
    }

    /// The path field as it stands.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Sets the path field (as typing would).
    pub fn set_text(&mut self, text: &str) {
        self.text = text.to_string();
        self.error = None;
        self.overwrite = None;
        self.refresh();
    }

    /// The folder the path field names (its text up to the last separator).
    fn folder(&self) -> PathBuf {
        let t = &self.text;
        match t.rfind(std::path::MAIN_SEPARATOR) {
            Some(0) => PathBuf::from(std::path::MAIN_SEPARATOR.to_string()),
            Some(k) => PathBuf::from(&t[..k]),
            None => PathBuf::from("."),
        }
    }

    /// The file name part of the path field.
    fn file_part(&self) -> &str {
        let t = &self.text;
        t.rfind(std::path::MAIN_SEPARATOR)
            .map_or(t.as_str(), |k| &t[k + 1..])
    }

    /// Reads the folder again when the path field names another one.
    fn refresh(&mut self) {
        let dir = self.folder();
        if self.listed.as_ref() == Some(&dir) {
            return;
        }
        self.entries.clear();
        self.list_error = None;
        match std::fs::read_dir(&dir) {
            Ok(rd) => {
                for e in rd.flatten() {
                    let name = e.file_name().to_string_lossy().into_owned();
                    if name.starts_with('.') {
                        continue;
                    }
                    let is_dir = e.path().is_dir();
                    self.entries.push(Entry { name, is_dir });
                }
                self.entries.sort_by(|a, b| {
                    b.is_dir
                        .cmp(&a.is_dir)
                        .then_with(|| a.name.to_lowercase().cmp(&b.name.to_lowercase()))
                });
            }
            Err(e) => self.list_error = Some(format!("{}: {e}", dir.display())),
        }
        self.listed = Some(dir);
    }

    /// The entries shown: folders, and the files of this kind (or every file).
    fn shown(&self) -> impl Iterator<Item = &Entry> {
        self.entries.iter().filter(|e| {
            e.is_dir
                || self.all_files
                || self.kind.is_folder()
                || self.kind.matches(Path::new(&e.name))
        })
    }

    /// Names in the folder that continue the typed file name (for completion).
    fn completions(&self, word: &str) -> Vec<String> {
        self.shown()
            .filter(|e| e.name.starts_with(word) && e.name != word)
            .map(|e| {
                if e.is_dir {
                    format!("{}{}", e.name, std::path::MAIN_SEPARATOR)
                } else {
                    e.name.clone()
                }
            })
            .take(50)
            .collect()
    }

    /// The dialog as a modal window; the outcome once decided.
    pub fn show(&mut self, ctx: &egui::Context) -> Option<Outcome> {
        let mut outcome = None;
        let modal = egui::Modal::new(egui::Id::unique("driftlab_file_dialog")).show(ctx, |ui| {
            ui.set_width((ctx.content_rect().width() * 0.6).clamp(420.0, 760.0));
            outcome = self.contents(ui);
        });
        // Escape (or a click beside the dialog) goes back from "replace?" first, then cancels.
        if outcome.is_none() && modal.should_close() && self.overwrite.take().is_none() {
            outcome = Some(Outcome::Cancel);
        }
        outcome
    }

    fn contents(&mut self, ui: &mut Ui) -> Option<Outcome> {
        ui.heading(self.kind.title());
        let (what, exts) = self.kind.filter();
        ui.weak(if self.kind.is_folder() {
            "Type the folder to write into (it is created); Tab completes, Enter writes, Esc cancels."
                .to_string()
        } else {
            format!(
                "{what} ({}). Tab completes the name; Enter {}; Esc cancels.",
                exts.iter()
                    .map(|e| format!(".{e}"))
                    .collect::<Vec<_>>()
                    .join(" "),
                match self.mode {
                    Mode::Open => "opens",
                    Mode::Save => "saves",
                }
            )
        });
        ui.add_space(4.0);

        let mut accept = false;
        let id = egui::Id::unique("driftlab_file_dialog_path");
        let before = self.text.clone();
        let out = {
            // Completion of the last path component from the folder's listing.
            let entries = self.completions(self.file_part());
            egui::CompletionPopup::new(id)
                .word_boundary(|c| c == std::path::MAIN_SEPARATOR)
                .accept_keys([Key::Tab])
                // Below the field: above it the list would hide the dialog's title.
                .align(egui::RectAlign::BOTTOM_START)
                .show(
                    ui,
                    egui::TextEdit::singleline(&mut self.text)
                        .desired_width(f32::INFINITY)
                        .font(egui::TextStyle::Monospace),
                    |q| {
                        if q.word.is_empty() {
                            return Vec::new();
                        }
                        entries
                            .iter()
                            .filter(|n| n.starts_with(q.word))
                            .map(|n| egui::Suggestion::new(n.clone()))
                            .collect()
                    },
                )
        };
        let resp = out.text_edit.response.response.clone();
        let resp = resp.on_hover_text("The whole path: folder and file name");
        if self.focus_pending {
            resp.request_focus();
            self.focus_pending = false;
        }
        if self.text != before || out.accepted.is_some() {
            self.error = None;
            self.overwrite = None;
            self.refresh();
            if out.accepted.is_some() {
                resp.request_focus();
            }
        }
        let enter = ui.input(|i| i.key_pressed(Key::Enter));
        if enter && (resp.lost_focus() || !ui.ctx().egui_wants_keyboard_input()) {
            // This Enter is the dialog's: the view that opens next (the import view) must not
            // take it too.
            ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, Key::Enter));
            accept = true;
        }
        if let Some(e) = &self.error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        if let Some(p) = &self.overwrite {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                format!(
                    "{} exists. Enter (or Replace) writes over it; Esc goes back.",
                    p.display()
                ),
            );
        }

        ui.add_space(4.0);
        ui.horizontal_wrapped(|ui| {
            ui.weak("Folders:");
            let mut go: Option<PathBuf> = None;
            if let Some(parent) = self.folder().parent()
                && ui
                    .small_button("Up")
                    .on_hover_text(parent.display().to_string())
                    .clicked()
            {
                go = Some(parent.to_path_buf());
            }
            for d in &self.recent {
                let label = d
                    .file_name()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| d.display().to_string());
                if ui
                    .small_button(label)
                    .on_hover_text(d.display().to_string())
                    .clicked()
                {
                    go = Some(d.clone());
                }
            }
            if let Some(d) = go {
                self.go_to(&d);
                resp.request_focus();
            }
        });

        ui.add_space(2.0);
        let row_h = ui.text_style_height(&egui::TextStyle::Body) + 4.0;
        let mut clicked: Option<(Entry, bool)> = None;
        egui::Frame::group(ui.style()).show(ui, |ui| {
            ui.set_min_height(10.0 * row_h);
            if let Some(e) = &self.list_error {
                ui.colored_label(ui.visuals().error_fg_color, e);
            }
            let shown: Vec<Entry> = self.shown().cloned().collect();
            if shown.is_empty() && self.list_error.is_none() {
                ui.weak(if self.entries.is_empty() {
                    "This folder is empty.".to_string()
                } else {
                    format!(
                        "No folder and no {what} file here; Show all files lists the {} other files.",
                        self.entries.len()
                    )
                });
            }
            let typed = self.file_part().to_string();
            egui::ScrollArea::vertical()
                .id_salt("file_dialog_list")
                .max_height(10.0 * row_h)
                .auto_shrink([false, true])
                .show_rows(ui, row_h, shown.len(), |ui, rows| {
                    for e in &shown[rows] {
                        let label = if e.is_dir {
                            RichText::new(format!("{}{}", e.name, std::path::MAIN_SEPARATOR))
                                .strong()
                        } else {
                            RichText::new(&e.name)
                        };
                        let r = ui.add(
                            egui::Button::selectable(!e.is_dir && e.name == typed, label)
                                .min_size(egui::vec2(ui.available_width(), row_h - 2.0)),
                        );
                        if r.double_clicked() {
                            clicked = Some((e.clone(), true));
                        } else if r.clicked() {
                            clicked = Some((e.clone(), false));
                        }
                    }
                });
        });
        if let Some((e, twice)) = clicked {
            let path = self.folder().join(&e.name);
            if e.is_dir {
                self.go_to(&path);
            } else {
                self.set_text(&path.display().to_string());
                if twice {
                    accept = true;
                }
            }
            resp.request_focus();
        }

        let mut outcome = None;
        ui.add_space(4.0);
        ui.horizontal(|ui| {
            if !self.kind.is_folder() {
                ui.checkbox(&mut self.all_files, "Show all files")
                    .on_hover_text(format!("Also list files that are not {what}"));
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                if ui.button("Cancel").on_hover_text("Esc").clicked() {
                    outcome = Some(Outcome::Cancel);
                }
                let verb = match (self.mode, self.overwrite.is_some()) {
                    (Mode::Open, _) => "Open",
                    (Mode::Save, true) => "Replace",
                    (Mode::Save, false) => "Save",
                };
                if ui
                    .button(RichText::new(verb).strong())
                    .on_hover_text("Enter")
                    .clicked()
                {
                    accept = true;
                }
            });
        });
        if outcome.is_none() && accept {
            outcome = self.accept();
            if outcome.is_none() {
                resp.request_focus();
            }
        }
        outcome
    }

    /// Shows `dir`, keeping the file name typed.
    fn go_to(&mut self, dir: &Path) {
        let name = match self.mode {
            Mode::Save => self.file_part().to_string(),
            Mode::Open => String::new(),
        };
        let mut text = dir.display().to_string();
        if !text.ends_with(std::path::MAIN_SEPARATOR) {
            text.push(std::path::MAIN_SEPARATOR);
        }
        text.push_str(&name);
        self.set_text(&text);
    }

    /// Enter: a folder named is entered; a file is opened or written (asking first before
    /// writing over one).
    pub fn accept(&mut self) -> Option<Outcome> {
        let raw = self.text.trim().to_string();
        if raw.is_empty() {
            self.error = Some("Type a path".into());
            return None;
        }
        let mut path = expand_home(&raw);
        if path.is_relative()
            && let Ok(abs) = std::path::absolute(&path)
        {
            path = abs;
        }
        let names_folder = raw.ends_with(std::path::MAIN_SEPARATOR);
        if path.is_dir() && (names_folder || !self.kind.is_folder()) {
            self.go_to(&path);
            return None;
        }
        match self.mode {
            Mode::Open => {
                if path.is_file() {
                    Some(Outcome::Accept(path))
                } else {
                    self.error = Some(format!("{}: no such file", path.display()));
                    None
                }
            }
            Mode::Save => {
                if !self.kind.is_folder()
                    && path.extension().is_none()
                    && let Some(ext) = self.kind.default_extension()
                {
                    path.set_extension(ext);
                }
                let parent = path.parent().map(Path::to_path_buf).unwrap_or_default();
                if !parent.as_os_str().is_empty() && !parent.is_dir() {
                    self.error = Some(format!("{}: no such folder", parent.display()));
                    return None;
                }
                let exists = if self.kind.is_folder() {
                    path.is_dir() && std::fs::read_dir(&path).is_ok_and(|mut r| r.next().is_some())
                } else {
                    path.exists()
                };
                if exists && self.overwrite.as_ref() != Some(&path) {
                    self.overwrite = Some(path);
                    return None;
                }
                Some(Outcome::Accept(path))
            }
        }
    }
}

/// `~/x` as the home folder's `x`.
fn expand_home(s: &str) -> PathBuf {
    if let Some(rest) = s.strip_prefix("~/")
        && let Some(home) = std::env::var_os("HOME")
    {
        return PathBuf::from(home).join(rest);
    }
    PathBuf::from(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_folder_and_name_are_split_at_the_last_separator() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("run7.csv"), "t,w,T\n").unwrap();
        std::fs::write(dir.path().join("run7-calibration.json"), "{}").unwrap();
        std::fs::create_dir(dir.path().join("runs")).unwrap();
        let d = FileDialog::new(Mode::Open, FileKind::Log, dir.path(), "ru", vec![]);
        assert_eq!(d.folder(), dir.path());
        assert_eq!(d.file_part(), "ru");
        // Folders and logs only; a folder completes with its separator.
        let sep = std::path::MAIN_SEPARATOR;
        assert_eq!(
            d.completions("ru"),
            vec![format!("runs{sep}"), "run7.csv".into()]
        );
    }

    #[test]
    fn saving_over_a_file_asks_first_and_a_bare_name_gets_its_extension() {
        let dir = tempfile::tempdir().unwrap();
        let mut d = FileDialog::new(
            Mode::Save,
            FileKind::Calibration,
            dir.path(),
            "gyro7",
            vec![],
        );
        assert_eq!(
            d.accept(),
            Some(Outcome::Accept(dir.path().join("gyro7.json")))
        );
        std::fs::write(dir.path().join("gyro7.json"), "{}").unwrap();
        assert_eq!(d.accept(), None, "asks before writing over it");
        assert_eq!(
            d.accept(),
            Some(Outcome::Accept(dir.path().join("gyro7.json"))),
            "a second Enter writes over it"
        );
        d.set_text(
            &dir.path()
                .join("nowhere")
                .join("x.json")
                .display()
                .to_string(),
        );
        assert_eq!(d.accept(), None);
        assert!(d.error.as_deref().unwrap().contains("no such folder"));
    }

    #[test]
    fn enter_on_a_folder_enters_it() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("logs")).unwrap();
        let mut d = FileDialog::new(Mode::Open, FileKind::Log, dir.path(), "logs", vec![]);
        assert_eq!(d.accept(), None);
        assert_eq!(d.folder(), dir.path().join("logs"));
        assert_eq!(d.file_part(), "");
    }
}
