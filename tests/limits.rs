//! Inputs too large to load are refused with a clear message and exit code 2, before they
//! are parsed or decoded (src/scene/limits.rs, the image loaders' header checks): scenes
//! with more lights or objects than argil draws, an oversized scene file, an OBJ of more
//! than 10⁷ triangles, and a 65536² environment map.

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::{argil, test_dir};

const SPHERE_OBJECT: &str = "[[objects]]\nmesh = \"builtin:sphere\"\n";
const LIGHT: &str = "[[lights]]\nkind = \"point\"\nposition = [0, 2, 2]\nintensity = [1, 1, 1]\n";


/// Renders `scene`: refused with exit code 2 and a message that mentions `mentions`, and
/// sooner than loading would take (a header or a count, not a decode).
fn assert_refused(scene: &Path, mentions: &[&str]) {
    let out = scene.with_extension("png");
    let began = Instant::now();
    let o = argil(&[
        "render",
        scene.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let took = began.elapsed();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{}: {err}", scene.display());
    for m in mentions {
        assert!(err.contains(m), "error does not mention {m:?}: {err}");
    }
    assert!(!out.exists(), "wrote {}", out.display());
    assert!(took < Duration::from_secs(60), "{}: took {took:?}", scene.display());
}

#[test]
fn too_many_lights_or_objects_are_refused() {
    let dir = test_dir("counts");
    let lights = dir.join("lights.toml");
    let count = argil::scene::limits::MAX_LIGHTS + 1;
    std::fs::write(&lights, format!("{}{SPHERE_OBJECT}", LIGHT.repeat(count))).expect("write");
    assert_refused(&lights, &["lights.toml", &format!("{count} point lights"), "at most"]);

    let objects = dir.join("objects.toml");
    let count = argil::scene::limits::MAX_OBJECTS + 1;
    std::fs::write(&objects, SPHERE_OBJECT.repeat(count)).expect("write");
    assert_refused(&objects, &["objects.toml", &format!("{count} objects"), "at most"]);

    // A million lights: the file alone is over the size limit, refused before parsing.
    let million = dir.join("million.toml");
    std::fs::write(&million, format!("{}{SPHERE_OBJECT}", LIGHT.repeat(1_000_000))).expect("write");
    assert_refused(&million, &["million.toml", "scene files are at most"]);
}

#[test]
fn an_obj_of_more_than_ten_million_triangles_is_refused() {
    let dir = test_dir("obj");
    let obj = dir.join("huge.obj");
    // One polygon of 10⁷ + 3 corners fans into 10⁷ + 1 triangles.
    let corners = argil::scene::limits::MAX_MESH_TRIANGLES + 3;
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    for i in 0..corners {
        text.push_str([" 1", " 2", " 3"][(i % 3) as usize]);
    }
    text.push('\n');
    std::fs::write(&obj, text).expect("write");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "[[objects]]\nmesh = \"huge.obj\"\n").expect("write");
    assert_refused(&scene, &["huge.obj", "10000001 triangles", "at most 10000000"]);
}

/// A scene in `dir` with the environment map `map`.
fn map_scene(dir: &Path, map: &str) -> PathBuf {
    let scene = dir.join("map.toml");
    let text = format!("{SPHERE_OBJECT}[environment]\nkind = \"map\"\npath = \"{map}\"\n");
    std::fs::write(&scene, text).expect("write");
    scene
}

/// As an environment map (as a texture: `huge_and_empty_headers_are_rejected_before_decoding`
/// in src/scene/texture.rs).
#[test]
fn a_65536_squared_image_is_refused_from_its_header() {
    let dir = test_dir("images");
    // A Radiance HDR header of 131072 × 65536 (2:1) and no scanlines.
    std::fs::write(
        dir.join("huge.hdr"),
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 65536 +X 131072\n",
    )
    .expect("write");
    assert_refused(&map_scene(&dir, "huge.hdr"), &["huge.hdr", "131072", "8192"]);
}

/// The fuzzer's first crasher: an EXR whose display window is 16 × 8 but whose data window
/// is 2²⁹ + 16 wide; decoding it asked for 25 GB and aborted.
#[test]
fn an_exr_with_a_huge_data_window_is_refused_from_its_header() {
    let crasher = common::project_dir().join("tests/fuzz/crashers/exr/data-window-2e29-wide.exr");
    let dir = test_dir("exr");
    std::fs::copy(&crasher, dir.join("sky.exr")).expect("copy");
    assert_refused(
        &map_scene(&dir, "sky.exr"),
        &["sky.exr", "data window 536870928 × 8", "at most 16384"],
    );
}
