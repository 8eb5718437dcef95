use super::input::read_exr;
use super::metrics::{compare, Rgba32};
use super::*;

// Wide enough that ꟻLIP's filters (about 17 pixels at 67 pixels per degree) leave the left
// edge untouched by the right half.
const W: usize = 96;
const H: usize = 8;

/// A smooth covered image: no pixel darker than the relative error's floor.
fn gradient() -> Rgba32 {
    let pixels = (0..W * H)
        .map(|i| {
            let (x, y) = ((i % W) as f32 / W as f32, (i / W) as f32 / H as f32);
            [0.2 + 0.6 * x, 0.3 + 0.4 * y, 0.5, 1.0]
        })
        .collect();
    Rgba32 {
        width: W,
        height: H,
        pixels,
    }
}

fn map(image: &Rgba32, f: impl Fn(usize, [f32; 4]) -> [f32; 4]) -> Rgba32 {
    Rgba32 {
        pixels: image.pixels.iter().enumerate().map(|(i, &p)| f(i, p)).collect(),
        ..image.clone()
    }
}

fn close(x: f64, expected: f64) -> bool {
    (x - expected).abs() <= 1e-6 * expected.abs().max(1.0)
}

#[test]
fn identical_images_have_no_error() {
    let b = gradient();
    let c = compare(&b, &b).expect("compare");
    let m = &c.metrics;
    assert_eq!(m.covered_pixels, W * H);
    assert_eq!((m.rel_mse, m.mse), (0.0, 0.0));
    assert_eq!(m.psnr_db, f64::INFINITY);
    assert_eq!((m.rel_err.mean, m.rel_err.p95, m.rel_err.p99), (0.0, 0.0, 0.0));
    assert_eq!((m.flip.mean, m.flip.p95, m.flip.p99), (0.0, 0.0, 0.0));
    assert!(
        c.heat_map.pixels().all(|p| p.0 == c.heat_map.get_pixel(0, 0).0),
        "a flat heat map"
    );
}

#[test]
fn a_scaled_reference_has_the_known_errors() {
    let b = gradient();
    for k in [0.5f32, 1.1, 2.0] {
        let a = map(&b, |_, [r, g, bl, al]| [k * r, k * g, k * bl, al]);
        let m = compare(&a, &b).expect("compare").metrics;
        let k = f64::from(k);
        // Σ(kb − b)² / Σb² = (k − 1)², and |Y(kb) − Y(b)| / Y(b) = |k − 1| at every pixel.
        assert!(close(m.rel_mse, (k - 1.0).powi(2)), "k {k}: rel-mse {}", m.rel_mse);
        for e in [m.rel_err.mean, m.rel_err.p95, m.rel_err.p99] {
            assert!(close(e, (k - 1.0).abs()), "k {k}: rel-err {e}");
        }
        let mse = b
            .pixels
            .iter()
            .flat_map(|p| p[..3].iter().map(|&v| ((k - 1.0) * f64::from(v)).powi(2)))
            .sum::<f64>()
            / (3 * W * H) as f64;
        assert!(close(m.psnr_db, -10.0 * mse.log10()), "k {k}: psnr {}", m.psnr_db);
        assert!(m.flip.mean > 0.05, "k {k}: ꟻLIP sees no difference: {}", m.flip.mean);
    }
}

#[test]
fn percentiles_are_nearest_rank() {
    // 100 pixels of relative error 0.01, 0.02, …, 1.00.
    let b = Rgba32 {
        width: 10,
        height: 10,
        pixels: vec![[0.5, 0.5, 0.5, 1.0]; 100],
    };
    let a = map(&b, |i, p| {
        let s = 1.0 + (i + 1) as f32 / 100.0;
        [p[0] * s, p[1] * s, p[2] * s, 1.0]
    });
    let e = compare(&a, &b).expect("compare").metrics.rel_err;
    assert!(
        close(e.mean, 0.505) && close(e.p95, 0.95) && close(e.p99, 0.99),
        "{e:?}"
    );
}

#[test]
fn non_finite_pixels_are_counted_and_left_out() {
    let b = gradient();
    let a = map(&b, |i, p| if i == 5 { [f32::NAN, p[1], p[2], p[3]] } else { p });
    let b_bad = map(&b, |i, p| if i == 40 { [p[0], f32::INFINITY, p[2], p[3]] } else { p });
    let c = compare(&a, &b_bad).expect("compare");
    let m = &c.metrics;
    assert_eq!((m.non_finite_a, m.non_finite_b), (1, 1));
    assert_eq!(m.covered_pixels, W * H - 2);
    assert_eq!((m.rel_mse, m.rel_err.p99, m.flip.p99), (0.0, 0.0, 0.0));
    for i in [5, 40] {
        assert_eq!(c.heat_map.get_pixel((i % W) as u32, (i / W) as u32).0, [0, 255, 0]);
    }
}

#[test]
fn coverage_excludes_the_background() {
    // B covers the left half; A differs from B only on the right half.
    let b = map(&gradient(), |i, p| {
        [p[0], p[1], p[2], if i % W < W / 2 { 1.0 } else { 0.0 }]
    });
    let a = map(&b, |i, p| if i % W < W / 2 { p } else { [5.0, 0.0, 0.0, 1.0] });
    let c = compare(&a, &b).expect("compare");
    let m = &c.metrics;
    assert_eq!(m.covered_pixels, W * H / 2);
    assert_eq!((m.rel_mse, m.rel_err.p99), (0.0, 0.0));
    // ꟻLIP's filters see the background, so covered pixels near the border may differ; far
    // from it the error is 0, drawn as the uncovered pixels are.
    assert_eq!(c.heat_map.get_pixel(0, 0).0, c.heat_map.get_pixel(W as u32 - 1, 0).0);
    assert!(m.flip.mean < 0.5, "{:?}", m.flip);
}

#[test]
fn a_black_reference_has_undefined_relative_figures() {
    let b = map(&gradient(), |_, _| [0.0, 0.0, 0.0, 1.0]);
    let a = map(&b, |_, _| [0.1, 0.1, 0.1, 1.0]);
    let m = compare(&a, &b).expect("compare").metrics;
    assert!(m.rel_err.mean.is_nan() && m.rel_err_floor.is_nan());
    assert!(m.rel_mse.is_infinite() && close(m.mse, 0.01));
    let json = serde_json::to_value(&m).expect("json");
    assert!(json["rel_err"]["p95"].is_null() && json["rel_mse"].is_null(), "{json}");
}

#[test]
fn images_of_different_sizes_are_refused() {
    let b = gradient();
    let a = Rgba32 {
        width: W - 1,
        pixels: b.pixels[..(W - 1) * H].to_vec(),
        ..b.clone()
    };
    assert!(compare(&a, &b).is_err());
}

#[test]
fn figures_have_three_significant_digits() {
    let cases = [
        (0.041234, "0.0412"),
        (38.26, "38.3"),
        (0.5, "0.500"),
        (0.099999999, "0.100"),
        (0.0099999999, "0.0100"),
        (12345.6, "12346"),
        (3.1e-4, "3.10e-4"),
        (0.0, "0"),
        (f64::INFINITY, "inf"),
        (f64::NAN, "n/a"),
    ];
    for (x, text) in cases {
        assert_eq!(figure(x), text);
    }
}

#[test]
fn an_exr_without_alpha_is_fully_covered() {
    let dir = std::env::temp_dir().join(format!("argil-compare-unit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("rgb.exr");
    exr::prelude::write_rgb_file(&path, 3, 2, |x, y| (x as f32, y as f32, 0.5f32)).expect("write EXR");
    let read = read_exr(&path).expect("read EXR");
    assert_eq!((read.image.width, read.image.height), (3, 2));
    assert_eq!(read.image.pixels[5], [2.0, 1.0, 0.5, 1.0]);
    assert!(read.attributes.is_empty());
    let missing = read_exr(&dir.join("missing.exr")).err().expect("a missing file fails");
    assert!(missing.to_string().contains("missing.exr"), "{missing}");
    std::fs::remove_dir_all(&dir).expect("remove temp dir");
}
