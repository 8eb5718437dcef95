//! Checks 1, 2 and 4 on the GPU sweep of one function: GPU against the f64 twin on the same
//! f32 inputs, positivity and range (or unit length), reciprocity, what the function
//! promises besides, and the stress inputs.

use crate::brdf::{cross, dot, Vec3};

use super::functions::{Function, Output, Tolerance, Tuple, Values, MIN_RECIPROCAL_HALF_LEN, UNIT_TOLERANCE};
use super::{normals, Row, Status};

/// Values below this are compared absolutely: |a − b| / max(|b|, floor). The functions'
/// natural scale is 1 (a white Lambert is 1/π, masking and Fresnel are fractions, display
/// values reach 1), and 1e-3 of it times the 1e-4 tolerance is 1e-7, one fp32 ulp at 1.
/// Smaller absolute errors occur where a function crosses zero with a slope (Walter's Λ fit
/// where its numerator cancels, a wrap band's edge, Schlick's (1 − v·h)⁵ for F0 = 0): fp32
/// rounding of O(1) quantities, not defects, and 1/3000 of the darkest 8-bit sRGB step (3e-4).
pub const RELATIVE_FLOOR: f64 = 1e-3;

/// Check 2: the f64 twin is reciprocal to rounding; the GPU rounds v·h and l·h differently.
const RECIPROCITY_F64: f64 = 1e-12;
const RECIPROCITY_GPU: f64 = 1e-5;

/// Relative error of `a` against the reference `b`, with `RELATIVE_FLOOR`. NaN/Inf
/// disagreement is an infinite error.
pub fn relative_error(a: f64, b: f64) -> f64 {
    if a == b {
        return 0.0;
    }
    let error = (a - b).abs() / b.abs().max(RELATIVE_FLOOR);
    if error.is_nan() {
        f64::INFINITY
    } else {
        error
    }
}

/// Largest error over the function's channels of one tuple's value.
fn tuple_error(function: Function, a: &[f64; 4], b: &[f64; 4]) -> f64 {
    (0..function.channels())
        .map(|c| relative_error(a[c], b[c]))
        .fold(0.0, f64::max)
}

/// The channel of `tuple_error`.
fn worst_channel(function: Function, a: &[f64; 4], b: &[f64; 4]) -> usize {
    (0..function.channels())
        .max_by(|&i, &j| relative_error(a[i], b[i]).total_cmp(&relative_error(a[j], b[j])))
        .unwrap_or(0)
}

fn rgb(x: &[f64; 4]) -> Vec3 {
    [x[0], x[1], x[2]]
}

/// The angle between two vectors, accurate when small; NaN/Inf is π.
fn angle(a: Vec3, b: Vec3) -> f64 {
    let c = cross(a, b);
    let angle = dot(c, c).sqrt().atan2(dot(a, b));
    if angle.is_nan() {
        std::f64::consts::PI
    } else {
        angle
    }
}

fn widen(values: &Values<f32>) -> Values<f64> {
    values.map(|v| v.map(f64::from))
}

/// How many halves of a result hold values: models also have f(l, v).
fn halves(function: Function) -> usize {
    match function {
        Function::Model(_) => 2,
        _ => 1,
    }
}

/// How many values are bad: for capped functions channel values (both halves for models)
/// that are NaN, Inf, negative or above the cap; for unit vectors, vectors not finite or
/// not unit.
fn bad_values(function: Function, results: impl Iterator<Item = Values<f64>>) -> usize {
    match function.output() {
        Output::Capped(cap) => results
            .map(|r| {
                r[..halves(function)]
                    .iter()
                    .flat_map(|v| &v[..function.channels()])
                    .filter(|&&x| !(x.is_finite() && (0.0..=cap.value).contains(&x)))
                    .count()
            })
            .sum(),
        Output::Unit => results.filter(|r| !is_unit(&r[0])).count(),
    }
}

/// ||n| − 1|, NaN or Inf where n is not finite.
fn unit_gap(n: &[f64; 4]) -> f64 {
    let n = rgb(n);
    (dot(n, n).sqrt() - 1.0).abs()
}

fn is_unit(n: &[f64; 4]) -> bool {
    unit_gap(n) <= UNIT_TOLERANCE
}

/// The largest `unit_gap` (NaN counts as infinite).
fn max_unit_gap(results: impl Iterator<Item = Values<f64>>) -> f64 {
    results
        .map(|r| {
            let gap = unit_gap(&r[0]);
            if gap.is_nan() {
                f64::INFINITY
            } else {
                gap
            }
        })
        .fold(0.0, f64::max)
}

/// The range row of `gpu` and `cpu` results, random or (`stress`) stress ones: check,
/// measured ("k gpu + m f64 bad of N", and for unit vectors the largest ||n| − 1| of each),
/// tolerance, and whether it passes.
fn range_row(
    function: Function,
    gpu: &[Values<f32>],
    cpu: &[Values<f64>],
    stress: bool,
) -> (&'static str, String, String, bool) {
    let gpu_bad = bad_values(function, gpu.iter().map(widen));
    let cpu_bad = bad_values(function, cpu.iter().copied());
    let ok = gpu_bad + cpu_bad == 0;
    match function.output() {
        Output::Capped(cap) => {
            // Random tuples count channel values, stress inputs tuples.
            let (check, of, tolerance) = if stress {
                ("stress: finite, >= 0, capped", gpu.len(), format!("0; {}", cap.label))
            } else {
                (
                    "positive, finite, in range",
                    gpu.len() * function.channels() * halves(function),
                    format!("0; >= 0, {}", cap.label),
                )
            };
            (
                check,
                format!("{gpu_bad} gpu + {cpu_bad} f64 bad of {of}"),
                tolerance,
                ok,
            )
        }
        Output::Unit => (
            if stress {
                "stress: finite, unit length"
            } else {
                "finite, unit length"
            },
            format!(
                "{gpu_bad} gpu + {cpu_bad} f64 bad of {}; max ||n| − 1| gpu {}, f64 {}",
                gpu.len(),
                sci(max_unit_gap(gpu.iter().map(widen))),
                sci(max_unit_gap(cpu.iter().copied()))
            ),
            format!("0; ||n| − 1| <= {UNIT_TOLERANCE:e}"),
            ok,
        ),
    }
}

/// The p-quantile of `values` (reordered).
fn quantile(values: &mut [f64], p: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let k = ((values.len() - 1) as f64 * p).round() as usize;
    *values.select_nth_unstable_by(k, f64::total_cmp).1
}

fn sci(x: f64) -> String {
    format!("{x:.2e}")
}

/// The rows of one function: `tuples[..samples]` are random, the rest stress inputs;
/// `gpu` and `cpu` hold the harness's results for every tuple.
pub fn rows(
    function: Function,
    tuples: &[Tuple],
    samples: usize,
    gpu: &[Values<f32>],
    cpu: &[Values<f64>],
) -> Vec<Row> {
    let name = function.name();
    let row = |check: &str, measured: String, tolerance: String, status: Status, note: String| Row {
        model: name.to_owned(),
        check: check.to_owned(),
        measured,
        tolerance,
        status,
        note,
    };
    let pass = |ok: bool| if ok { Status::Pass } else { Status::Fail };
    let mut rows = Vec::new();
    let Tolerance {
        p99: p99_tolerance,
        max: max_tolerance,
    } = function.tolerance();

    // 1. GPU against f64 on the same inputs, where the harness's own fp32 derivation of the
    // arguments cannot spoil the tolerance; elsewhere against a bound that includes it.
    let error = |i: usize| tuple_error(function, &widen(&gpu[i])[0], &cpu[i][0]);
    let (exact, rounded): (Vec<usize>, Vec<usize>) =
        (0..samples).partition(|&i| function.argument_rounding(&tuples[i]) <= p99_tolerance);
    let mut errors: Vec<f64> = exact.iter().map(|&i| error(i)).collect();
    let worst = (0..exact.len()).max_by(|&i, &j| errors[i].total_cmp(&errors[j]));
    let max = worst.map_or(0.0, |i| errors[i]);
    let p99 = quantile(&mut errors, 0.99);
    let worst_note = |i: usize| {
        let c = worst_channel(function, &widen(&gpu[i])[0], &cpu[i][0]);
        let channel = if function.channels() > 1 {
            format!(" [{c}]")
        } else {
            String::new()
        };
        format!(
            "worst: {} gpu{channel} {:.7e} f64{channel} {:.7e}",
            function.describe(&tuples[i]),
            gpu[i][0][c],
            cpu[i][0][c]
        )
    };
    let domain = if rounded.is_empty() {
        format!("{samples} tuples")
    } else {
        format!(
            "{} of {samples} tuples, where argument rounding <= {p99_tolerance:e}",
            exact.len()
        )
    };
    rows.push(row(
        "gpu vs f64: p99 rel. error",
        sci(p99),
        format!("<= {p99_tolerance:e}"),
        pass(p99 <= p99_tolerance),
        format!("{domain}, floor {RELATIVE_FLOOR:e}"),
    ));
    rows.push(row(
        "gpu vs f64: max rel. error",
        sci(max),
        format!("<= {max_tolerance:e}"),
        pass(max <= max_tolerance),
        worst.map_or_else(String::new, |k| worst_note(exact[k])),
    ));
    if !rounded.is_empty() {
        let ratio = |i: usize| error(i) / (max_tolerance + function.argument_rounding(&tuples[i]));
        let worst = rounded.iter().copied().max_by(|&i, &j| ratio(i).total_cmp(&ratio(j)));
        let max_ratio = worst.map_or(0.0, ratio);
        let max_error = rounded.iter().map(|&i| error(i)).fold(0.0, f64::max);
        rows.push(row(
            "gpu vs f64, rest: error/bound",
            format!("{max_ratio:.2} (max error {})", sci(max_error)),
            format!("<= 1, bound {max_tolerance:e} + rounding"),
            pass(max_ratio <= 1.0),
            format!(
                "{} tuples; {}; {}",
                rounded.len(),
                function.argument_rounding_reason(),
                worst.map_or_else(String::new, worst_note)
            ),
        ));
    }

    if matches!(function.output(), Output::Unit) {
        let (max_angle, at) = (0..samples)
            .map(|i| (angle(rgb(&widen(&gpu[i])[0]), rgb(&cpu[i][0])), i))
            .fold(
                (0.0, None),
                |worst, (a, i)| {
                    if a > worst.0 {
                        (a, Some(i))
                    } else {
                        worst
                    }
                },
            );
        rows.push(row(
            "gpu vs f64: max angle (rad)",
            sci(max_angle),
            format!("<= {max_tolerance:e}, as the max rel. error allows"),
            pass(max_angle <= max_tolerance),
            at.map_or_else(String::new, |i| format!("worst: {}", function.describe(&tuples[i]))),
        ));
    }

    // 2. Positivity and range (or unit length) on the random tuples, on both sides.
    let (check, measured, tolerance, ok) = range_row(function, &gpu[..samples], &cpu[..samples], false);
    rows.push(row(check, measured, tolerance, pass(ok), function.equation()));

    // What the function promises besides, on every tuple.
    match function {
        Function::UnitVector(normal) => rows.extend(normals::rows(normal, tuples, gpu, cpu)),
        Function::Term(term) => rows.extend(term.spec().promise.map(|promise| promise(tuples, gpu, cpu))),
        _ => {}
    }

    // 2. Helmholtz reciprocity of the BRDFs, on their domain: v and l above the horizon.
    match function {
        Function::Model(model) => {
            let domain: Vec<usize> = (0..samples)
                .filter(|&i| model.in_reciprocity_domain(&tuples[i]))
                .collect();
            let asymmetry = |values: &dyn Fn(usize) -> Values<f64>| {
                domain
                    .iter()
                    .map(|&i| {
                        let [f, swapped] = values(i);
                        (tuple_error(function, &f, &swapped), i)
                    })
                    .fold(
                        (0.0, None),
                        |worst, (e, i)| if e > worst.0 { (e, Some(i)) } else { worst },
                    )
            };
            let at = |worst: Option<usize>| {
                worst.map_or_else(String::new, |i| format!("; worst: {}", function.describe(&tuples[i])))
            };
            let (cpu_gap, cpu_worst) = asymmetry(&|i| model.eval_unit_both_ways(&tuples[i]));
            let (gpu_gap, gpu_worst) = asymmetry(&|i| widen(&gpu[i]));
            rows.push(row(
                "reciprocity f(v,l)=f(l,v), f64, unit",
                sci(cpu_gap),
                format!("<= {RECIPROCITY_F64:e}"),
                pass(cpu_gap <= RECIPROCITY_F64),
                format!(
                    "{} tuples with n·v, n·l > 0, |v + l| >= {MIN_RECIPROCAL_HALF_LEN} (v·h is ill-conditioned as v → −l){}",
                    domain.len(),
                    at(cpu_worst)
                ),
            ));
            rows.push(row(
                "reciprocity f(v,l)=f(l,v), gpu",
                sci(gpu_gap),
                format!("<= {RECIPROCITY_GPU:e}"),
                pass(gpu_gap <= RECIPROCITY_GPU),
                format!("v·h and l·h round differently{}", at(gpu_worst)),
            ));
        }
        Function::Term(term) if term.spec().lighting_weight => {
            rows.push(row(
                "reciprocity",
                "n/a".to_owned(),
                "n/a".to_owned(),
                Status::NotApplicable,
                "n/a: not a BRDF (a weight of n·l alone, added to the diffuse lobe)".to_owned(),
            ));
        }
        _ => {}
    }

    // 4. Stress inputs: finite, non-negative, under the cap (or unit), on both sides.
    let first_bad = (samples..tuples.len())
        .find(|&i| bad_values(function, [widen(&gpu[i]), cpu[i]].into_iter()) > 0)
        .map_or_else(String::new, |i| {
            format!(
                "first bad: {} gpu {:?} f64 {:?}",
                function.describe(&tuples[i]),
                gpu[i],
                cpu[i]
            )
        });
    let (check, measured, tolerance, ok) = range_row(function, &gpu[samples..], &cpu[samples..], true);
    rows.push(row(check, measured, tolerance, pass(ok), first_bad));
    rows
}

#[cfg(test)]
mod tests {
    use super::super::functions::Model;
    use super::super::normals::UnitVector;
    use super::*;
    use crate::rng::Rng;

    /// The rows of a Cook-Torrance sweep whose "GPU" results are `perturb`ed f64 ones.
    fn statuses(perturb: impl Fn(usize, Values<f32>) -> Values<f32>) -> Vec<(String, Status)> {
        sweep_statuses(Function::Model(Model::CookTorranceGgxCorrelated), perturb)
    }

    /// The rows of a sweep of `function` whose "GPU" results are `perturb`ed f64 ones.
    fn sweep_statuses(
        function: Function,
        perturb: impl Fn(usize, Values<f32>) -> Values<f32>,
    ) -> Vec<(String, Status)> {
        let samples = 4000;
        let mut rng = Rng::new(3);
        let mut tuples: Vec<Tuple> = (0..samples).map(|_| function.sample(&mut rng)).collect();
        tuples.extend(function.stress());
        let cpu: Vec<Values<f64>> = tuples.iter().map(|t| function.eval(t)).collect();
        let gpu: Vec<Values<f32>> = cpu
            .iter()
            .enumerate()
            .map(|(i, v)| perturb(i, v.map(|half| half.map(|x| x as f32))))
            .collect();
        rows(function, &tuples, samples, &gpu, &cpu)
            .into_iter()
            .map(|r| (r.check, r.status))
            .collect()
    }

    fn failing(rows: &[(String, Status)]) -> Vec<&str> {
        rows.iter()
            .filter(|(_, s)| *s == Status::Fail)
            .map(|(c, _)| c.as_str())
            .collect()
    }

    #[test]
    fn rounded_f64_results_pass() {
        assert_eq!(failing(&statuses(|_, v| v)), Vec::<&str>::new());
    }

    #[test]
    fn each_check_catches_its_defect() {
        let scaled = |k: f32| move |_, v: Values<f32>| v.map(|half| half.map(|x| x * k));
        // Scaled down, so that lobes clamped to FP16_MAX stay under it.
        assert_eq!(
            failing(&statuses(scaled(1.0 - 2e-5))),
            ["gpu vs f64: p99 rel. error"],
            "2e-5 everywhere is beyond p99 only"
        );
        // The tuples whose half vector is ill-conditioned have their own bound, which 2e-4
        // everywhere exceeds too where that conditioning is mild.
        assert_eq!(
            failing(&statuses(scaled(1.0 - 2e-4))),
            [
                "gpu vs f64: p99 rel. error",
                "gpu vs f64: max rel. error",
                "gpu vs f64, rest: error/bound"
            ]
        );
        assert!(failing(&statuses(scaled(1.001))).contains(&"stress: finite, >= 0, capped"));
        let negative = |i, mut v: Values<f32>| {
            if i == 7 {
                v[0][0] = -v[0][0] - 1.0;
            }
            v
        };
        assert!(failing(&statuses(negative)).contains(&"positive, finite, in range"));
        let asymmetric = |_, mut v: Values<f32>| {
            v[1] = v[1].map(|x| x * 0.999);
            v
        };
        assert_eq!(failing(&statuses(asymmetric)), ["reciprocity f(v,l)=f(l,v), gpu"]);
        let nan_under_stress = |i, mut v: Values<f32>| {
            if i == 4000 + 11 {
                v[1][2] = f32::NAN;
            }
            v
        };
        assert_eq!(failing(&statuses(nan_under_stress)), ["stress: finite, >= 0, capped"]);
    }

    #[test]
    fn unit_vector_checks_catch_their_defects() {
        let function = Function::UnitVector(UnitVector::BlendUdn);
        assert_eq!(failing(&sweep_statuses(function, |_, v| v)), Vec::<&str>::new());
        let long = |_, v: Values<f32>| v.map(|half| half.map(|x| x * (1.0 + 2e-5)));
        assert_eq!(
            failing(&sweep_statuses(function, long)),
            [
                "gpu vs f64: p99 rel. error",
                "finite, unit length",
                "stress: finite, unit length"
            ]
        );
        // Turned by 2e-4 rad about z, which moves no component by more than 2e-4 of 1.
        let (sin, cos) = 2e-4f64.sin_cos();
        let turned = |_, mut v: Values<f32>| {
            let [x, y] = [v[0][0], v[0][1]].map(f64::from);
            v[0][0] = (x * cos - y * sin) as f32;
            v[0][1] = (x * sin + y * cos) as f32;
            v
        };
        assert!(failing(&sweep_statuses(function, turned)).contains(&"gpu vs f64: max angle (rad)"));
    }

    #[test]
    fn relative_error_has_a_floor_and_sees_nan() {
        assert_eq!(relative_error(1.0, 1.0), 0.0);
        assert!((relative_error(1.001, 1.0) - 1e-3).abs() < 1e-12);
        // Below the floor the error is absolute, in units of the floor.
        assert!((relative_error(2e-7, 1e-7) - 1e-7 / RELATIVE_FLOOR).abs() < 1e-15);
        assert_eq!(relative_error(f64::NAN, 1.0), f64::INFINITY);
        assert_eq!(relative_error(f64::INFINITY, 1.0), f64::INFINITY);
    }
}
