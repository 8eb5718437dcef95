//! Completion of the panel's path field: the files and folders in the typed path's folder
//! whose names start with what follows its last `/`, listed under the field as it is
//! typed; a click completes the path (a folder, to go on into it). No native file dialog:
//! under Xvfb and in containers there is no portal to open one.

use std::path::Path;

use egui::Ui;

/// The files the field takes: images for maps and environments, OBJ meshes.
const EXTENSIONS: &[&str] = &["png", "jpg", "jpeg", "tga", "bmp", "tif", "tiff", "exr", "hdr", "obj"];
/// Completions listed at most.
pub const LIMIT: usize = 12;

/// The completions of `typed`, sorted: each the whole path, folders ending in `/`. Hidden
/// entries only when the name typed starts with a dot; nothing for a folder that cannot be
/// read.
pub fn completions(typed: &str) -> Vec<String> {
    let (folder, prefix) = match typed.rfind('/') {
        Some(i) => typed.split_at(i + 1),
        None => ("", typed),
    };
    let dir = if folder.is_empty() {
        Path::new(".")
    } else {
        Path::new(folder)
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<String> = entries
        .filter_map(|entry| {
            let entry = entry.ok()?;
            let name = entry.file_name().into_string().ok()?;
            if !name.starts_with(prefix) || name.starts_with('.') && !prefix.starts_with('.') {
                return None;
            }
            if entry.path().is_dir() {
                return Some(format!("{folder}{name}/"));
            }
            let extension = Path::new(&name).extension()?.to_str()?.to_ascii_lowercase();
            EXTENSIONS
                .contains(&extension.as_str())
                .then(|| format!("{folder}{name}"))
        })
        .filter(|c| c != typed)
        .collect();
    found.sort();
    found.truncate(LIMIT);
    found
}

/// Lists the completions of `path` under the field, and completes it on a click. The
/// folder is read again only when the path changes.
pub fn show(ui: &mut Ui, path: &mut String) {
    let id = ui.id().with("argil-path-completions");
    let cached = ui.data(|d| d.get_temp::<(String, Vec<String>)>(id));
    let list = match cached {
        Some((typed, list)) if typed == *path => list,
        _ => {
            let list = if path.trim().is_empty() {
                Vec::new()
            } else {
                completions(path.trim())
            };
            ui.data_mut(|d| d.insert_temp(id, (path.clone(), list.clone())));
            list
        }
    };
    for completion in list {
        if ui
            .add(egui::Button::new(egui::RichText::new(&completion).monospace()).small())
            .on_hover_text("Complete the path with this")
            .clicked()
        {
            *path = completion;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn completion_lists_matching_files_and_folders() {
        let dir = std::env::temp_dir().join(format!("argil-completion-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("clay-maps")).expect("dir");
        for name in ["clay.png", "clay.OBJ", "clay.txt", "studio.hdr", ".clay.png"] {
            std::fs::write(dir.join(name), b"").expect("file");
        }
        let root = format!("{}/", dir.display());
        assert_eq!(
            completions(&format!("{root}cl")),
            [
                format!("{root}clay-maps/"),
                format!("{root}clay.OBJ"),
                format!("{root}clay.png")
            ]
        );
        assert_eq!(completions(&format!("{root}s")), [format!("{root}studio.hdr")]);
        assert_eq!(completions(&format!("{root}.c")), [format!("{root}.clay.png")]);
        assert_eq!(
            completions(&root).len(),
            4,
            "every entry but the hidden one and the text file"
        );
        assert!(completions(&format!("{root}clay.png")).is_empty(), "a complete path");
        assert!(completions(&format!("{root}missing/x")).is_empty());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
