//! Writing a scene back into the document it was read from, so that saving keeps what the
//! user wrote: comments, key order, formatting and `preset` lines stay; a key is rewritten
//! only when its value changed, and a material writes only the keys that differ from its
//! preset (or from the built-in defaults without one). `toml_edit` keeps the formatting.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use toml_edit::{ArrayOfTables, DocumentMut, Item, Table, TableLike, Value};

use super::file::{CameraDef, MaterialDef, ObjectDef, SceneFile};
use super::{Preset, Scene, SceneError};

/// The name of the built-in material that objects without `material` use.
const BUILTIN_MATERIAL: &str = "default";

/// `document` (a scene file's text) with `scene` written into it, paths relative to
/// `path`'s folder. Fails if `document` is not a scene file.
pub fn edit_document(scene: &Scene, document: &str, path: &Path) -> Result<String> {
    let origin = path.display().to_string();
    let old: SceneFile = toml::from_str(document).map_err(|error| SceneError::Toml {
        origin: origin.clone(),
        error,
    })?;
    let mut doc: DocumentMut = document.parse().with_context(|| format!("{origin}: not TOML"))?;
    let new = scene_file(scene, path, &old);
    let root = doc.as_table_mut();
    if old.camera != new.camera {
        merge(
            section(root, "camera")?,
            &table_of(&new.camera)?,
            Some(&table_of(&CameraDef::default())?),
        );
    }
    if old.environment != new.environment {
        merge(section(root, "environment")?, &table_of(&new.environment)?, None);
    }
    merge_list(root, "lights", &old.lights, &new.lights, None)?;
    if old.shadows != new.shadows {
        let shadows = new.shadows.clone().unwrap_or_default();
        merge(section(root, "shadows")?, &table_of(&shadows)?, None);
    }
    if old.antialiasing != new.antialiasing {
        let antialiasing = new.antialiasing.clone().unwrap_or_default();
        merge(section(root, "antialiasing")?, &table_of(&antialiasing)?, None);
    }
    if old.occlusion != new.occlusion {
        let occlusion = new.occlusion.clone().unwrap_or_default();
        merge(section(root, "occlusion")?, &table_of(&occlusion)?, None);
    }
    let object_base = table_of(&ObjectDef {
        mesh: String::new(),
        position: [0.0; 3],
        scale: 1.0,
        material: None,
        subdivisions: None,
    })?;
    merge_list(root, "objects", &old.objects, &new.objects, Some(&object_base))?;
    for (name, def) in &new.materials {
        if old.materials.get(name) == Some(def) {
            continue;
        }
        let mut base = table_of(&def.preset.map_or_else(MaterialDef::default, Preset::material))?;
        // The preset line is the user's choice, never redundant with the preset itself.
        base.remove("preset");
        let materials = section(root, "materials")?;
        let table = materials
            .entry(name)
            .or_insert_with(|| Item::Table(Table::new()))
            .as_table_like_mut()
            .with_context(|| format!("{origin}: materials.{name} is not a table"))?;
        merge(table, &table_of(def)?, Some(&base));
    }
    Ok(doc.to_string())
}

/// The scene as a file at `path`, with the built-in material left implicit where `old`
/// left it so.
fn scene_file(scene: &Scene, path: &Path, old: &SceneFile) -> SceneFile {
    let mut new = scene.to_file_at(path);
    let builtin_untouched = new.materials.get(BUILTIN_MATERIAL) == Some(&MaterialDef::default());
    if builtin_untouched && !old.materials.contains_key(BUILTIN_MATERIAL) {
        new.materials.remove(BUILTIN_MATERIAL);
        for (i, object) in new.objects.iter_mut().enumerate() {
            let implicit = old.objects.get(i).is_none_or(|o| o.material.is_none());
            if implicit && object.material.as_deref() == Some(BUILTIN_MATERIAL) {
                object.material = None;
            }
        }
    }
    new
}

/// A part of the scene file as a TOML table.
fn table_of<T: Serialize>(value: &T) -> Result<Table> {
    let text = toml::to_string(value).context("cannot write the scene as TOML")?;
    let doc: DocumentMut = text.parse().context("the scene's TOML does not parse back")?;
    Ok(doc.as_table().clone())
}

/// The table `key` of `root`, created (without a header of its own) if absent.
fn section<'a>(root: &'a mut Table, key: &str) -> Result<&'a mut dyn TableLike> {
    root.entry(key)
        .or_insert_with(|| {
            let mut table = Table::new();
            table.set_implicit(true);
            Item::Table(table)
        })
        .as_table_like_mut()
        .with_context(|| format!("`{key}` is not a table"))
}

/// Writes `full` (every key of a part of the scene) into `table`. A key already holding an
/// equal value stays as written; a value equal to `base`'s is left out (removed if written);
/// any other is set, keeping the comment after it. Keys of `table` that `full` lacks go.
fn merge(table: &mut dyn TableLike, full: &Table, base: Option<&Table>) {
    let gone: Vec<String> = table
        .iter()
        .map(|(k, _)| k.to_owned())
        .filter(|k| !full.contains_key(k))
        .collect();
    for key in gone {
        remove_key(table, &key);
    }
    for (key, item) in full.iter() {
        let base_item = base.and_then(|b| b.get(key));
        if let Some(sub) = item.as_table_like() {
            let sub_full = as_table(sub);
            let sub_base = base_item.and_then(Item::as_table_like).map(as_table);
            match table.get_mut(key).and_then(Item::as_table_like_mut) {
                Some(existing) => merge(existing, &sub_full, sub_base.as_ref()),
                None => {
                    let mut fresh = Table::new();
                    merge(&mut fresh, &sub_full, sub_base.as_ref());
                    if !fresh.is_empty() {
                        table.insert(key, Item::Table(fresh));
                    }
                }
            }
            continue;
        }
        let Some(value) = item.as_value() else { continue };
        let redundant = base_item.and_then(Item::as_value).is_some_and(|b| same(b, value));
        match table.get_mut(key) {
            Some(Item::Value(written)) if same(written, value) => {}
            Some(_) if redundant => remove_key(table, key),
            Some(Item::Value(written)) => {
                let decor = written.decor().clone();
                *written = value.clone();
                *written.decor_mut() = decor;
            }
            _ if redundant => {}
            _ => {
                let mut value = value.clone();
                value.decor_mut().clear();
                table.insert(key, Item::Value(value));
            }
        }
    }
}

/// Removes `key`; a comment written above it moves to the next key, so that it stays.
fn remove_key(table: &mut dyn TableLike, key: &str) {
    let comment = table
        .key(key)
        .and_then(|k| k.leaf_decor().prefix())
        .and_then(|p| p.as_str())
        .filter(|p| p.contains('#'))
        .map(str::to_owned);
    let next = table
        .iter()
        .skip_while(|(k, _)| *k != key)
        .nth(1)
        .filter(|(_, item)| item.is_value())
        .map(|(k, _)| k.to_owned());
    table.remove(key);
    if let (Some(comment), Some(next)) = (comment, next) {
        if let Some(mut k) = table.key_mut(&next) {
            let own = k
                .leaf_decor()
                .prefix()
                .and_then(|p| p.as_str())
                .unwrap_or("")
                .to_owned();
            k.leaf_decor_mut().set_prefix(format!("{comment}{own}"));
        }
    }
}

/// A table-like item (a `[table]`, an inline table or dotted keys) as a plain table.
fn as_table(table: &dyn TableLike) -> Table {
    let mut plain = Table::new();
    for (key, item) in table.iter() {
        plain.insert(key, item.clone());
    }
    plain
}

/// Writes the list `new` over `[[key]]`, entry by entry against `old` (what the file held).
fn merge_list<T: Serialize + PartialEq>(
    root: &mut Table,
    key: &str,
    old: &[T],
    new: &[T],
    base: Option<&Table>,
) -> Result<()> {
    if old == new {
        return Ok(());
    }
    let fulls = new.iter().map(table_of).collect::<Result<Vec<_>>>()?;
    let fresh = |full: &Table| {
        let mut table = Table::new();
        merge(&mut table, full, base);
        table
    };
    match root.get_mut(key) {
        Some(Item::ArrayOfTables(list)) => {
            while list.len() > new.len() {
                list.remove(list.len() - 1);
            }
            for (i, full) in fulls.iter().enumerate() {
                if old.get(i) == new.get(i) {
                    continue;
                }
                match list.get_mut(i) {
                    Some(table) => merge(table, full, base),
                    None => list.push(fresh(full)),
                }
            }
        }
        // Absent, or written as an inline array: written anew as [[key]] tables.
        _ => {
            let mut list = ArrayOfTables::new();
            for full in &fulls {
                list.push(fresh(full));
            }
            root.insert(key, Item::ArrayOfTables(list));
        }
    }
    Ok(())
}

/// Whether two TOML values mean the same to the scene, whose numbers are f32.
fn same(a: &Value, b: &Value) -> bool {
    let number = |v: &Value| match v {
        Value::Float(x) => Some(*x.value() as f32),
        Value::Integer(x) => Some(*x.value() as f32),
        _ => None,
    };
    match (a, b) {
        (Value::String(x), Value::String(y)) => x.value() == y.value(),
        (Value::Boolean(x), Value::Boolean(y)) => x.value() == y.value(),
        (Value::Integer(x), Value::Integer(y)) => x.value() == y.value(),
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y.iter()).all(|(a, b)| same(a, b)),
        (Value::InlineTable(x), Value::InlineTable(y)) => {
            x.len() == y.len() && x.iter().all(|(k, a)| y.get(k).is_some_and(|b| same(a, b)))
        }
        _ => matches!((number(a), number(b)), (Some(x), Some(y)) if x == y),
    }
}
