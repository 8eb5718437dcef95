//! Subsurface scattering of the diffuse lobe: the models a material chooses from, and the
//! pre-integrated diffusion table (Penner & Borshukov 2011, "Pre-Integrated Skin Shading",
//! GPU Pro 2) with its f64 lookup, the twin of `shaders/lib/subsurface.glsl`.
//!
//! The energy-conserving wrap and the pre-integrated model replace the diffuse lobe's
//! cosine max(0, n·l) by a transfer K(n·l) per colour channel; `brdf_cos` adds
//! ρ/π · (K − max(0, n·l)), so light moves across the terminator rather than being added.

use std::sync::OnceLock;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::quadrature::gauss_legendre;
use super::wrap::wrap_energy_conserving;
use super::{Vec3, PI};
use crate::cache::{self, DiskCache};

/// The subsurface model of a material. `as u32` is the `SUBSURFACE` specialization constant
/// of forward.frag (`SUBSURFACE_*` in subsurface.glsl): never renumber.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Subsurface {
    /// None: the diffuse lobe ends at the terminator.
    None = 0,
    /// The report's wrap lighting (seed eq. 18): a coloured term added to the BRDF, which
    /// lights past the terminator; it adds energy (up to 1.6× Lambert's).
    #[default]
    Seed = 1,
    /// saturate((n·l + w)/(1 + w)²) per channel, w = wrap · scatter_color: the same
    /// reflected energy as Lambert under any light, spread past the terminator.
    EnergyConservingWrap = 2,
    /// Penner's ring integral of a Gaussian diffusion profile of standard deviation
    /// scatter_radius · scatter_color, over a surface of the mesh's curvature.
    PreIntegrated = 3,
}

impl Subsurface {
    /// Whether the model moves diffuse light across the terminator (through
    /// `subsurface_transfer`) rather than adding a term.
    pub fn redistributes(self) -> bool {
        matches!(self, Subsurface::EnergyConservingWrap | Subsurface::PreIntegrated)
    }
}

/// Columns of the pre-integrated table: n·l from −1 to 1, a texel centre on each end and
/// on n·l = 0, where max(0, n·l) kinks, so the t = 0 row interpolates it exactly.
pub const PREINTEGRATED_WIDTH: usize = 129;
/// Rows: s = t/(1 + t) from 0 (no scattering: max(0, n·l)) to 1 (t = ∞: 1/π everywhere).
pub const PREINTEGRATED_HEIGHT: usize = 65;
/// Largest t the lookup takes: t/(1 + t) rounds to 1 long before it, and ∞/∞ is NaN.
pub const MAX_PREINTEGRATED_T: f64 = 1e30;

/// Gauss-Legendre order per smooth piece of the ring integral.
const RING_ORDER: usize = 48;
/// The profile is integrated where exp(−2 sin²(x/2)/t²) ≥ e^(−`PROFILE_CUTOFF`) (1e-16):
/// the rest is below f64 resolution of the integral.
const PROFILE_CUTOFF: f64 = 36.8;
/// Gauss-Legendre order per piece of the kernels' θ integral.
const KERNEL_ORDER: usize = 32;

/// Penner's diffusion over a ring of radius r for a Gaussian profile of standard deviation
/// σ, t = σ/r = σκ: D(θ) = ∫ max(0, cos(θ + x)) R(x) dx / ∫ R(x) dx over x ∈ [−π, π], with
/// R(x) = exp(−d²/2σ²) at the chord d = 2r sin(x/2). D = max(0, n·l) at t = 0 and 1/π as
/// t → ∞. Exact to f64 rounding: the integrand is split where it kinks and where the
/// profile vanishes.
pub fn preintegrated_diffusion(n_dot_l: f64, t: f64) -> f64 {
    let mu = n_dot_l.clamp(-1.0, 1.0);
    if t <= 0.0 {
        return mu.max(0.0);
    }
    let theta = mu.acos();
    let reach = t * (PROFILE_CUTOFF / 2.0).sqrt();
    let half = if reach >= 1.0 { PI } else { 2.0 * reach.asin() };
    let mut edges = vec![-half, half];
    for kink in [PI / 2.0 - theta, -PI / 2.0 - theta, 1.5 * PI - theta] {
        if kink.abs() < half {
            edges.push(kink);
        }
    }
    edges.sort_by(f64::total_cmp);
    static RULE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let rule = RULE.get_or_init(|| gauss_legendre(RING_ORDER));
    let (mut lit, mut total) = (0.0, 0.0);
    for piece in edges.windows(2) {
        let (mid, radius) = (0.5 * (piece[0] + piece[1]), 0.5 * (piece[1] - piece[0]));
        for &(node, weight) in rule {
            let x = mid + radius * node;
            let chord = (0.5 * x).sin();
            let profile = weight * radius * (-2.0 * chord * chord / (t * t)).exp();
            lit += profile * (theta + x).cos().max(0.0);
            total += profile;
        }
    }
    lit / total
}

/// The t of a table row.
fn row_t(row: usize) -> f64 {
    let s = row as f64 / (PREINTEGRATED_HEIGHT - 1) as f64;
    if row + 1 == PREINTEGRATED_HEIGHT {
        f64::INFINITY
    } else {
        s / (1.0 - s)
    }
}

/// Funk–Hecke coefficients 2π ∫ D(μ, t) P_l(μ) dμ (l = 0, 1, 2) of the pre-integrated
/// transfer, for the environment's SH convolution. Integrated over θ, split around the
/// terminator where D bends within a few t.
pub fn preintegrated_sh_kernel(t: f64) -> Vec3 {
    if t.is_infinite() {
        return [4.0, 0.0, 0.0];
    }
    let mut edges = vec![0.0, PI];
    for c in [0.0, 1.0, -1.0, 4.0, -4.0] {
        let edge = PI / 2.0 + c * t;
        if edge > 0.0 && edge < PI && !edges.contains(&edge) {
            edges.push(edge);
        }
    }
    edges.sort_by(f64::total_cmp);
    static RULE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let rule = RULE.get_or_init(|| gauss_legendre(KERNEL_ORDER));
    let mut k = [0.0; 3];
    for piece in edges.windows(2) {
        let (mid, radius) = (0.5 * (piece[0] + piece[1]), 0.5 * (piece[1] - piece[0]));
        for &(node, weight) in rule {
            let theta = mid + radius * node;
            let mu = theta.cos();
            let d = weight * radius * theta.sin() * preintegrated_diffusion(mu, t);
            k[0] += d;
            k[1] += d * mu;
            k[2] += d * 0.5 * (3.0 * mu * mu - 1.0);
        }
    }
    k.map(|x| 2.0 * PI * x)
}

/// Funk–Hecke coefficients of `wrap_energy_conserving`, (μ + w)/(1 + w)² on [−w, 1]:
/// (π, 2π(1/3 + w/2 − w³/6)/(1 + w)², π(1 − w)²/4); Lambert's at w = 0.
pub fn wrap_energy_conserving_sh_kernel(w: f64) -> Vec3 {
    let w = w.clamp(0.0, 1.0);
    let square = (1.0 + w) * (1.0 + w);
    [
        PI,
        2.0 * PI * (1.0 / 3.0 + w / 2.0 - w * w * w / 6.0) / square,
        PI * (1.0 - w) * (1.0 - w) / 4.0,
    ]
}

/// The table the GPU reads: per texel, r = D(n·l, t) and gba = its SH kernel at the row's
/// t (the same along a row), in f32, as uploaded.
pub struct PreintegratedTable {
    texels: Vec<[f32; 4]>,
    compute_time: Duration,
}

impl PreintegratedTable {
    /// The table, read from the disk cache or computed (tens of milliseconds) once per
    /// process.
    pub fn get() -> &'static PreintegratedTable {
        static TABLE: OnceLock<PreintegratedTable> = OnceLock::new();
        TABLE.get_or_init(|| Self::cached(&DiskCache::from_env()))
    }

    /// The table from `cache`, keyed by the code that computes it.
    fn cached(cache: &DiskCache) -> PreintegratedTable {
        let start = Instant::now();
        let key = cache::key(&[
            include_str!("subsurface.rs").as_bytes(),
            include_str!("quadrature.rs").as_bytes(),
            include_str!("wrap.rs").as_bytes(),
        ]);
        let size = PREINTEGRATED_WIDTH * PREINTEGRATED_HEIGHT * std::mem::size_of::<[f32; 4]>();
        let bytes = cache.get_or_compute(
            "preintegrated-subsurface",
            key,
            |b| b.len() == size,
            || bytemuck::cast_slice(&Self::compute().texels).to_vec(),
        );
        PreintegratedTable {
            texels: bytemuck::pod_collect_to_vec(&bytes),
            compute_time: start.elapsed(),
        }
    }

    /// Rows are independent: each thread computes an interleaved share of them.
    fn compute() -> PreintegratedTable {
        let start = Instant::now();
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(PREINTEGRATED_HEIGHT);
        let mut rows: Vec<(usize, Vec<[f32; 4]>)> = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|first| {
                    scope.spawn(move || {
                        (first..PREINTEGRATED_HEIGHT)
                            .step_by(threads)
                            .map(|row| (row, Self::row(row)))
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)))
                .collect()
        });
        rows.sort_by_key(|(row, _)| *row);
        PreintegratedTable {
            texels: rows.into_iter().flat_map(|(_, texels)| texels).collect(),
            compute_time: start.elapsed(),
        }
    }

    fn row(row: usize) -> Vec<[f32; 4]> {
        let t = row_t(row);
        let [k0, k1, k2] = preintegrated_sh_kernel(t).map(|k| k as f32);
        (0..PREINTEGRATED_WIDTH)
            .map(|column| {
                let d = if t.is_infinite() {
                    1.0 / PI
                } else {
                    preintegrated_diffusion(column_n_dot_l(column), t)
                };
                [d as f32, k0, k1, k2]
            })
            .collect()
    }

    /// How long reading or computing the table took (once per process).
    pub fn compute_time(&self) -> Duration {
        self.compute_time
    }

    /// Row-major texels, `PREINTEGRATED_WIDTH` per row.
    pub fn texels(&self) -> &[[f32; 4]] {
        &self.texels
    }

    fn texel(&self, column: usize, row: usize) -> [f64; 4] {
        self.texels[row * PREINTEGRATED_WIDTH + column].map(f64::from)
    }

    /// Bilinear between the four texels around (n·l, t/(1 + t)), weights computed as the
    /// shader computes them (it reads texels rather than trusting the sampler's few bits of
    /// filtering precision): the twin of `preintegrated_d` (r) and, at n·l = 0, of
    /// `preintegrated_kernel` (gba).
    pub fn lookup(&self, n_dot_l: f64, t: f64) -> [f64; 4] {
        let half_width = (PREINTEGRATED_WIDTH - 1) / 2;
        let s = n_dot_l.clamp(-1.0, 1.0) * half_width as f64;
        let column = s.floor().min((half_width - 1) as f64);
        let t = t.clamp(0.0, MAX_PREINTEGRATED_T);
        let y = t / (1.0 + t) * (PREINTEGRATED_HEIGHT - 1) as f64;
        let row = y.floor().min((PREINTEGRATED_HEIGHT - 2) as f64);
        let (i, j) = ((column as i64 + half_width as i64) as usize, row as usize);
        let (fx, fy) = (s - column, y - row);
        let lerp = |a: [f64; 4], b: [f64; 4], f: f64| std::array::from_fn(|c| a[c] + (b[c] - a[c]) * f);
        let below = lerp(self.texel(i, j), self.texel(i + 1, j), fx);
        let above = lerp(self.texel(i, j + 1), self.texel(i + 1, j + 1), fx);
        lerp(below, above, fy)
    }
}

/// The n·l of a table column.
fn column_n_dot_l(column: usize) -> f64 {
    2.0 * column as f64 / (PREINTEGRATED_WIDTH - 1) as f64 - 1.0
}

/// The transfer K(n·l) per channel that replaces max(0, n·l) for the models that move
/// diffuse light across the terminator (0 for the others); `reach` is w (energy-conserving
/// wrap) or t = σκ (pre-integrated) per channel.
pub fn subsurface_transfer(model: Subsurface, n_dot_l: f64, reach: Vec3) -> Vec3 {
    match model {
        Subsurface::EnergyConservingWrap => reach.map(|w| wrap_energy_conserving(n_dot_l, w)),
        Subsurface::PreIntegrated => {
            let table = PreintegratedTable::get();
            reach.map(|t| table.lookup(n_dot_l, t)[0])
        }
        Subsurface::None | Subsurface::Seed => [0.0; 3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cached_table_is_the_computed_one() {
        let dir = std::env::temp_dir().join(format!("argil-subsurface-cache-{}", std::process::id()));
        let cache = DiskCache::at(Some(&dir));
        let computed = PreintegratedTable::compute().texels;
        let (stored, read) = (
            PreintegratedTable::cached(&cache).texels,
            PreintegratedTable::cached(&cache).texels,
        );
        let entries = std::fs::read_dir(&dir).unwrap().count();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(entries, 1);
        assert!(computed == stored && stored == read);
    }

    /// Plain midpoint rule on 200 000 panels: slow, simple, and accurate to ~1e-9 here.
    fn brute_force(mu: f64, t: f64) -> f64 {
        let theta = mu.acos();
        let n = 200_000;
        let (mut lit, mut total) = (0.0, 0.0);
        for i in 0..n {
            let x = -PI + (i as f64 + 0.5) * 2.0 * PI / n as f64;
            let r = (-2.0 * (0.5 * x).sin().powi(2) / (t * t)).exp();
            lit += r * (theta + x).cos().max(0.0);
            total += r;
        }
        lit / total
    }

    #[test]
    fn ring_integral_matches_brute_force() {
        for t in [0.01, 0.05, 0.2, 1.0, 5.0] {
            for mu in [-1.0, -0.6, -0.05, 0.0, 0.03, 0.5, 1.0] {
                let (fast, slow) = (preintegrated_diffusion(mu, t), brute_force(mu, t));
                assert!((fast - slow).abs() < 1e-8, "μ {mu}, t {t}: {fast} vs {slow}");
            }
        }
    }

    #[test]
    fn diffusion_limits_are_lambert_and_uniform() {
        for mu in [-1.0, -0.3, 0.0, 0.4, 1.0] {
            assert!((preintegrated_diffusion(mu, 1e-6) - f64::max(mu, 0.0)).abs() < 1e-6);
            assert!((preintegrated_diffusion(mu, 1e4) - 1.0 / PI).abs() < 1e-7);
        }
        // The ring integral keeps ∫ D dθ over the circle: 2 for every t.
        let rule = gauss_legendre(200);
        for t in [0.1, 0.5, 2.0] {
            let ring: f64 = rule
                .iter()
                .map(|&(x, w)| w * PI * preintegrated_diffusion((PI * x).cos(), t))
                .sum();
            assert!((ring - 2.0).abs() < 1e-6, "t {t}: {ring}");
        }
    }

    #[test]
    fn kernels_match_their_closed_forms_at_the_limits() {
        let lambert = [PI, 2.0 * PI / 3.0, PI / 4.0];
        for (a, b) in preintegrated_sh_kernel(0.0).iter().zip(lambert) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
        assert_eq!(wrap_energy_conserving_sh_kernel(0.0), lambert);
        // The closed form against quadrature of the wrap itself.
        let rule = gauss_legendre(64);
        for w in [0.1, 0.5, 1.0] {
            let (lo, hi) = (-w, 1.0);
            let mut k = [0.0; 3];
            for &(x, weight) in &rule {
                let mu = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
                let s = weight * 0.5 * (hi - lo) * wrap_energy_conserving(mu, w) * 2.0 * PI;
                k[0] += s;
                k[1] += s * mu;
                k[2] += s * 0.5 * (3.0 * mu * mu - 1.0);
            }
            let closed = wrap_energy_conserving_sh_kernel(w);
            for l in 0..3 {
                assert!(
                    (k[l] - closed[l]).abs() < 1e-12,
                    "w {w}, l {l}: {} vs {}",
                    k[l],
                    closed[l]
                );
            }
        }
    }

    /// ∫D dω/π grows with σκ from Lambert's 1 to the uniform 4/π (1.005 at 0.1, 1.114 at
    /// 0.5, 1.243 at 1); the higher bands fade to 0, never below.
    #[test]
    fn kernels_grow_from_lambert_to_uniform() {
        let mut last = preintegrated_sh_kernel(0.0);
        for t in [0.01, 0.1, 0.5, 1.0, 2.0, 10.0, 100.0] {
            let k = preintegrated_sh_kernel(t);
            assert!(k[0] > last[0] && k[0] < 4.0, "t {t}: {k:?}");
            assert!(
                k[1] < last[1] && k[2] < last[2] && k[1] >= 0.0 && k[2] >= 0.0,
                "t {t}: {k:?}"
            );
            last = k;
        }
        assert!((preintegrated_sh_kernel(0.5)[0] / PI - 1.113851).abs() < 1e-6);
        assert!((last[0] - 4.0).abs() < 1e-3);
    }

    /// The table's bilinear error against the exact integral, over a dense grid between its
    /// texels: bounds what the pre-integrated shading differs from Penner's model by.
    #[test]
    fn table_interpolates_the_integral_closely() {
        let table = PreintegratedTable::get();
        let mut worst = (0.0, 0.0, 0.0);
        for i in 0..=400 {
            let mu = -1.0 + 2.0 * f64::from(i) / 400.0;
            for t in [0.0, 0.003, 0.01, 0.02, 0.05, 0.1, 0.17, 0.3, 0.5, 1.0, 2.0, 10.0] {
                let error = (table.lookup(mu, t)[0] - preintegrated_diffusion(mu, t)).abs();
                if error > worst.0 {
                    worst = (error, mu, t);
                }
            }
        }
        // Measured 1.2e-3, at t = 0.01 next to the terminator: the first row above t = 0
        // is t = 0.016, and a bend that narrow spans about one column (Δμ = 1/64).
        assert!(
            worst.0 < 1.5e-3,
            "max error {:.2e} at μ {}, t {}",
            worst.0,
            worst.1,
            worst.2
        );
        // Exact on the t = 0 row (max(0, μ) is linear between texel centres), to f32.
        for i in 0..=1000 {
            let mu = -1.0 + 2.0 * f64::from(i) / 1000.0;
            assert!((table.lookup(mu, 0.0)[0] - mu.max(0.0)).abs() < 1e-7);
        }
    }
}
