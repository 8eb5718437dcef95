//! `argil verify` as `make test` runs it, on fewer random tuples: it passes on lavapipe with
//! the validation layer silent, its table names every model, term and shading function, and
//! `--json` writes the same rows. (The full run, 2²⁰ tuples per function, is `make test`'s last step.)

mod common;

use common::argil;

#[test]
fn verify_passes_and_reports_every_model() {
    let dir = common::test_dir("json");
    let json = dir.join("verify.json");
    let o = argil(&[
        "verify",
        "--samples",
        "65536",
        "--json",
        json.to_str().expect("utf-8 path"),
    ]);
    let (stdout, stderr) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "argil verify failed:\n{stdout}\n{stderr}");
    assert!(!stderr.contains("vulkan validation"), "validation messages: {stderr}");
    for name in [
        "lambert",
        "oren-nayar",
        "eon",
        "blinn-phong",
        "torrance-sparrow",
        "cook-torrance ggx smith-separable",
        "cook-torrance ggx smith-correlated",
        "cook-torrance beckmann smith-separable",
        "cook-torrance beckmann smith-correlated",
        "f_schlick",
        "d_ggx",
        "d_beckmann",
        "lambda_ggx",
        "lambda_beckmann",
        "g2_smith_correlated_ggx",
        "tonemap_pbr_neutral",
        "srgb_oetf",
        "wrap_seed",
        "wrap_energy_conserving",
        "shadow_terminator",
        "decode_normal",
        "blend_rnm",
        "blend_udn",
        "blend_whiteout",
        "blend_seed",
        "tangent_to_world",
        "view_facing_normal",
        "brdf_cos lambert + ct ggx correlated",
        "brdf_cos lambert + blinn-phong",
    ] {
        assert!(
            stdout.lines().any(|l| l.starts_with(&format!("{name} "))),
            "no row for {name}:\n{stdout}"
        );
    }
    assert!(
        stdout.contains("n/a: not a BRDF"),
        "the wrap terms' reciprocity rows are missing"
    );
    assert!(
        stdout.contains("gains energy: max albedo 1.07"),
        "Blinn-Phong's gain is not reported"
    );
    // Header, rule, rows, blank line, summary.
    let rows = stdout.lines().take_while(|l| !l.is_empty()).count() - 2;
    let written = std::fs::read_to_string(&json).expect("read the JSON table");
    assert_eq!(written.matches("\"status\": ").count(), rows, "{written}");
    assert!(written.contains("\"failures\": 0"), "{written}");
}

#[test]
fn verify_rejects_an_empty_sweep() {
    let o = argil(&["verify", "--samples", "0"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--samples"));
}
