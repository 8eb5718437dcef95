//! `argil compare` as a user meets it: the line, the JSON with the EXR attributes, the heat
//! map, and bad input (exit code 2, the file named, nothing written). No GPU involved.

mod common;

use std::process::Output;

use common::argil;
use exr::meta::attribute::{AttributeValue, Text};
use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};

const W: u32 = 48;
const H: u32 = 16;

/// A fresh folder for one test, removed when the test ends, and the paths in it as
/// arguments.
struct Scratch(argil::scratch::Scratch);

impl Scratch {
    fn new(name: &str) -> Self {
        Self(common::test_dir(name))
    }

    fn path(&self, name: &str) -> String {
        self.0.join(name).to_str().expect("utf-8 temp path").to_owned()
    }

    /// Another spelling of `path(name)`, through a subfolder and back.
    fn detour(&self, name: &str) -> String {
        std::fs::create_dir_all(self.0.join("sub")).expect("subfolder");
        self.0
            .join("sub")
            .join("..")
            .join(name)
            .to_str()
            .expect("utf-8 temp path")
            .to_owned()
    }

    fn files(&self) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(&*self.0)
            .expect("read scratch dir")
            .map(|e| e.expect("dir entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

/// The reference: a gradient covering all but the 8 rightmost columns.
fn reference_pixel(x: u32, y: u32) -> [f32; 4] {
    let covered = if x < W - 8 { 1.0 } else { 0.0 };
    [0.2 + x as f32 / W as f32, 0.3 + y as f32 / H as f32, 0.4, covered]
}

/// Writes an EXR as `argil render` does (the `image` crate, RGBA32F).
fn write_render(path: &str, width: u32, f: impl Fn(u32, u32) -> [f32; 4]) {
    image::Rgba32FImage::from_fn(width, H, |x, y| image::Rgba(f(x, y)))
        .save(path)
        .expect("write EXR");
}

/// Writes an EXR with header attributes, as a reference renderer would.
fn write_reference(path: &str, attributes: &[(&str, AttributeValue)]) {
    let channels = SpecificChannels::rgba(|Vec2(x, y)| {
        let [r, g, b, a] = reference_pixel(x as u32, y as u32);
        (r, g, b, a)
    });
    let mut image = Image::from_channels((W as usize, H as usize), channels);
    for (name, value) in attributes {
        image
            .layer_data
            .attributes
            .other
            .insert(Text::from(*name), value.clone());
    }
    image.write().to_file(path).expect("write EXR");
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn compare_prints_one_line_and_writes_the_json_and_the_heat_map() {
    let dir = Scratch::new("ok");
    let (a, b, out, json) = (
        dir.path("a.exr"),
        dir.path("b.exr"),
        dir.path("diff.png"),
        dir.path("r.json"),
    );
    // A is 10% brighter than B, with one NaN pixel in its covered part.
    write_render(&a, W, |x, y| {
        let p = reference_pixel(x, y);
        let nan = if (x, y) == (3, 4) { f32::NAN } else { 1.0 };
        [1.1 * p[0] * nan, 1.1 * p[1], 1.1 * p[2], 1.0]
    });
    write_reference(
        &b,
        &[
            ("argil.spp", AttributeValue::I32(64)),
            ("argil.transport", AttributeValue::Text(Text::from("path tracing"))),
            ("argil.noise", AttributeValue::F32(0.5)),
            ("studio.artist", AttributeValue::Text(Text::from("not argil"))),
        ],
    );

    let o = argil(&["compare", &a, &b, "--out", &out, "--json", &json]);
    assert!(o.status.success(), "argil compare failed: {}", stderr(&o));
    let covered = (W - 8) * H - 1;
    let line = String::from_utf8_lossy(&o.stdout);
    assert_eq!(line.lines().count(), 1, "{line}");
    assert!(line.starts_with("flip "), "{line}");
    for part in [
        "rel-mse 0.0100 ",
        "rel-err mean 0.100 p95 0.100 p99 0.100 ",
        "nan/inf 1/0 ",
        &format!("covered {covered} px"),
    ] {
        assert!(line.contains(part), "{part:?} not in {line}");
    }

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("JSON written")).expect("valid JSON");
    assert_eq!(report["covered_pixels"], covered);
    assert_eq!(
        (report["non_finite_a"].as_u64(), report["non_finite_b"].as_u64()),
        (Some(1), Some(0))
    );
    let figure = |path: &[&str]| path.iter().fold(&report, |v, k| &v[k]).as_f64().expect("a number");
    assert!((figure(&["rel_mse"]) - 0.01).abs() < 1e-6);
    assert!(figure(&["flip", "mean"]) > 0.0 && figure(&["flip", "p99"]) >= figure(&["flip", "p95"]));
    assert_eq!(figure(&["psnr_peak"]), 1.0);
    assert_eq!(report["a_attributes"], serde_json::json!({}));
    assert_eq!(
        report["b_attributes"],
        serde_json::json!({"argil.spp": 64, "argil.transport": "path tracing", "argil.noise": 0.5})
    );

    let heat_map = image::open(&out).expect("heat map is a PNG");
    assert_eq!((heat_map.width(), heat_map.height()), (W, H));
    assert_eq!(
        dir.files(),
        ["a.exr", "b.exr", "diff.png", "r.json"],
        "no temporary left"
    );
}

#[test]
fn compare_refuses_bad_input_with_exit_code_2_and_writes_nothing() {
    let dir = Scratch::new("bad");
    let (a, b, narrow, png, corrupt) = (
        dir.path("a.exr"),
        dir.path("b.exr"),
        dir.path("narrow.exr"),
        dir.path("render.png"),
        dir.path("corrupt.exr"),
    );
    write_render(&a, W, reference_pixel);
    write_reference(&b, &[]);
    write_render(&narrow, W - 1, reference_pixel);
    image::RgbaImage::new(W, H).save(&png).expect("write PNG");
    let bytes = std::fs::read(&a).expect("read EXR");
    std::fs::write(&corrupt, &bytes[..bytes.len() / 2]).expect("write corrupt EXR");
    let missing = dir.path("missing.exr");
    let (out, json) = (dir.path("diff.png"), dir.path("r.json"));
    let out_again = dir.detour("diff.png");
    let before = dir.files();

    let cases: [(&str, &str, &str, &str, &[&str]); 7] = [
        (
            &narrow,
            &b,
            &out,
            &json,
            &["narrow.exr", "47x16", "b.exr", "48x16", "same size"],
        ),
        (&a, &png, &out, &json, &["render.png", "PNG", "not an OpenEXR file"]),
        (&missing, &b, &out, &json, &["missing.exr", "cannot read"]),
        (&a, &corrupt, &out, &json, &["corrupt.exr", "unreadable OpenEXR file"]),
        // Outputs that would overwrite an input or each other.
        (&a, &b, &out, &b, &["b.exr", "would overwrite"]),
        (&a, &b, &a, &json, &["a.exr", ".png"]),
        (&a, &b, &out, &out_again, &["diff.png", "would overwrite"]),
    ];
    // With `--overwrite`, which lets none of them through; then one without it, whose
    // existing output is refused.
    let existing: (&str, &str, &str, &str, &[&str]) = (&a, &b, &out, &b, &["b.exr", "already exists", "--overwrite"]);
    let runs = cases.iter().map(|case| (case, true)).chain([(&existing, false)]);
    for (i, ((x, y, out, json, mentions), overwrite)) in runs.enumerate() {
        let mut args = vec!["compare", x, y, "--out", out, "--json", json];
        args.extend(overwrite.then_some("--overwrite"));
        let o = argil(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "case {i}: {err}");
        assert!(!err.contains("panicked"), "case {i}: {err}");
        for m in *mentions {
            assert!(err.contains(m), "case {i}: the error does not mention {m:?}: {err}");
        }
        assert!(
            o.stdout.is_empty(),
            "case {i}: printed {}",
            String::from_utf8_lossy(&o.stdout)
        );
        assert_eq!(dir.files(), before, "case {i}: a file was written");
    }
    assert_eq!(std::fs::read(&a).expect("read A"), bytes, "A was overwritten");
}

#[test]
fn compare_help_defines_every_figure() {
    let o = argil(&["--help"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("compare"));
    let o = argil(&["compare", "--help"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for word in [
        "alpha of B > 0",
        "rel-mse  Σ(a−b)² / Σb²",
        "peak 1",
        "floor = 0.01 × mean Y(b)",
        "ꟻLIP",
        "PBR Neutral",
        "nearest-rank",
        "Exit code 2",
        "--out",
        "--json",
    ] {
        assert!(text.contains(word), "compare --help lacks {word:?}: {text}");
    }
}

/// A file against itself, under two spellings of its path: no error, and no output may
/// overwrite it under either.
#[test]
fn compare_of_a_file_with_itself_is_exact() {
    let dir = Scratch::new("self");
    let b = dir.path("b.exr");
    write_reference(&b, &[]);
    let other_spelling = dir.detour("b.exr");
    let o = argil(&["compare", &b, &other_spelling]);
    assert!(o.status.success(), "{}", stderr(&o));
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(
        line.starts_with("flip 0 (p95 0, p99 0)  rel-mse 0  psnr inf dB"),
        "{line}"
    );
    let o = argil(&["compare", &b, &b, "--json", &other_spelling]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}
