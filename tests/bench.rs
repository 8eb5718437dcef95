//! `argil bench --quick` as `make test` runs it: every row has finite times and errors, the
//! references are cached, and bad input exits with code 2. No timing thresholds: times
//! depend on the machine.

mod common;

use std::path::Path;

use common::argil;
use serde_json::Value;

fn run(out: &Path, references: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "bench",
        "--quick",
        "--out",
        out.to_str().expect("utf-8 temp path"),
        "--references",
        references.to_str().expect("utf-8 temp path"),
    ];
    args.extend(extra);
    let output = argil(&args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "argil bench failed: {stderr}");
    assert!(!stderr.contains("vulkan validation"), "validation messages: {stderr}");
    stderr
}

fn finite(row: &Value, key: &str) -> f64 {
    let x = row[key].as_f64().unwrap_or(f64::NAN);
    assert!(
        x.is_finite(),
        "{key} of {} {} is {}",
        row["scene"],
        row["configuration"],
        row[key]
    );
    x
}

#[test]
fn quick_bench_rows_have_finite_times_and_errors_and_references_are_cached() {
    let dir = common::test_dir("quick");
    let (out, references) = (dir.join("results"), dir.join("references"));
    let first = run(&out, &references, &[]);
    assert_eq!(
        first.matches("rendering the").count(),
        2,
        "a full and a shadows reference: {first}"
    );

    let rows: Vec<Value> =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).expect("results.json")).expect("JSON rows");
    assert_eq!(rows.len(), 3, "floor, split-sum and report");
    for row in &rows {
        for key in [
            "gpu_ms_median",
            "gpu_ms_p95",
            "cpu_ms_median",
            "cpu_ms_p95",
            "forward_ratio_to_floor",
            "work_ms_median",
            "work_ratio_to_floor",
        ] {
            assert!(finite(row, key) > 0.0, "{key} is not positive");
        }
        for error in ["error_full", "error_shadows"] {
            for key in ["flip_mean", "rel_mse", "reference_noise"] {
                finite(&row[error], key);
            }
        }
        for pass in row["pass_ms_median"].as_array().expect("pass times") {
            assert!(pass.as_f64().is_some_and(f64::is_finite), "pass time {pass}");
        }
        assert!(row["commit"].as_str().is_some_and(|c| !c.is_empty()));
        // The rows' turns add up to --quick's 10 frames.
        assert_eq!(row["frames"], Value::from(10), "{}", row["configuration"]);
    }
    // The floor against itself: 1 within the noise of one frame to the next.
    assert!(rows.iter().any(|r| r["configuration"] == "floor"), "a floor row");
    let csv = std::fs::read_to_string(out.join("results.csv")).expect("results.csv");
    assert_eq!(csv.lines().count(), rows.len() + 1, "a header and a line per row");
    let table = std::fs::read_to_string(out.join("results.md")).expect("results.md");
    assert!(table.contains("| default | **report** |"), "{table}");

    let starts: Vec<Value> =
        serde_json::from_slice(&std::fs::read(out.join("startup.json")).expect("startup.json")).expect("JSON starts");
    assert_eq!(starts.len(), 3, "a cold start, one with argil's cache alone empty, and a warm one");
    for (start, kind) in starts.iter().zip(["cold", "argil cold", "warm"]) {
        assert_eq!(start["kind"], kind);
        let total = finite(start, "total_ms");
        let steps = start["steps"].as_array().expect("steps");
        assert!(steps.len() >= 8, "{steps:?}");
        let sum: f64 = steps.iter().map(|s| finite(s, "ms")).sum();
        assert!(sum <= total, "the steps ({sum} ms) fit in the whole ({total} ms)");
        // Every step but the write comes before the first frame is finished.
        let first_frame = finite(start, "first_frame_ms");
        let before: f64 = steps.iter().filter(|s| s["name"] != "write").map(|s| finite(s, "ms")).sum();
        assert!(before <= first_frame && first_frame <= total, "{before} ≤ {first_frame} ≤ {total} ms");
        // The builtin maps are made on other threads, beside the steps.
        let beside = start["beside"].as_array().expect("beside");
        assert!(beside.iter().any(|s| s["name"].as_str().is_some_and(|n| n.starts_with("builtin maps"))));
        assert!(beside.iter().all(|s| finite(s, "ms") <= first_frame), "{beside:?}");
    }

    // The second run finds both references in the cache; its one row replaces its
    // namesake and the others stay.
    let second = run(
        &out,
        &references,
        &["--frames", "1", "--warmup", "0", "--only", "default/report"],
    );
    assert!(!second.contains("rendering the"), "references rendered again: {second}");
    let merged: Vec<Value> =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).expect("results.json")).expect("JSON rows");
    assert_eq!(merged.len(), rows.len());
    let frames = |rows: &[Value], configuration: &str| {
        rows.iter()
            .find(|r| r["configuration"] == configuration)
            .map(|r| r["frames"].clone())
    };
    assert_eq!(frames(&merged, "report"), Some(Value::from(1)));
    assert_eq!(frames(&merged, "floor"), frames(&rows, "floor"));
}

/// Alone or beside a pattern that names rows, a pattern that names none is refused before
/// any row runs, with the scenes there are.
#[test]
fn bench_rejects_a_pattern_that_names_no_row() {
    for only in [&["no-such-scene"][..], &["default/report", "default/no-such-configuration"]] {
        let mut args = vec!["bench", "--quick", "--frames", "1", "--warmup", "0"];
        args.extend(only.iter().flat_map(|p| ["--only", *p]));
        let output = argil(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        let unmatched = only.last().expect("a pattern");
        assert!(stderr.contains(&format!("--only {unmatched}: names no row")), "{stderr}");
        assert!(stderr.contains("its scenes: default"), "{stderr}");
        assert!(!stderr.contains("vulkan validation"), "validation messages: {stderr}");
        assert!(!stderr.contains("default report"), "a row ran: {stderr}");
    }
}

/// Results that could not be written or merged fail the run before any row is timed,
/// not after: a results folder under a file, and with `--only` a `results.json` that is not
/// the bench's, which is left as it was.
#[test]
fn bench_checks_its_results_folder_before_the_rows() {
    let dir = common::test_dir("results-folder");
    let file = dir.join("a-file");
    std::fs::write(&file, "").expect("write");
    let malformed = dir.join("results");
    std::fs::create_dir_all(&malformed).expect("create");
    std::fs::write(malformed.join("results.json"), "not JSON").expect("write");
    for (out, only, mention) in [
        (file.join("results"), None, "cannot create"),
        (malformed.clone(), Some("default/report"), "not the bench's results"),
    ] {
        let out = out.to_str().expect("utf-8");
        let mut args = vec!["bench", "--quick", "--frames", "1", "--warmup", "0", "--out", out];
        args.extend(only.into_iter().flat_map(|p| ["--only", p]));
        let output = argil(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(mention), "{stderr}");
        assert!(!stderr.contains("vulkan validation"), "validation messages: {stderr}");
        assert!(!stderr.contains("default report"), "a row ran first: {stderr}");
    }
    assert_eq!(std::fs::read(malformed.join("results.json")).expect("read"), b"not JSON");
}

#[test]
fn bench_rejects_a_time_budget_that_is_not_positive() {
    let output = argil(&["bench", "--quick", "--max-seconds", "0"]);
    assert_eq!(
        output.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}
