//! An environment's luminance as a piecewise-constant density over its equirectangular
//! (u, v), sampled by inverting the marginal CDF of rows and then the row's conditional CDF
//! (pbrt-v4's `PiecewiseConstant2D`). The reference renderer samples its environment by
//! it; the forward pass's sampled reflection reads its CDFs from a storage buffer, and
//! `sample_direction` and `pdf_direction` are the twins of environment.glsl's
//! `sample_env_luminance` and `pdf_env_luminance`.

use super::environment::{equirect_direction, equirect_uv, studio_radiance};
use super::tonemap::luminance;
use super::{Vec3, PI};
use crate::cache::{self, DiskCache};

/// Columns × rows of the studio's distribution: a cell subtends 0.7° × 0.7°, finer than
/// the studio's softest box edge.
pub const STUDIO_GRID: (usize, usize) = (512, 256);
/// The disk cache's entry of the studio's grid of luminances.
const STUDIO_ENTRY: &str = "studio-luminance";
/// Every cell keeps this fraction of the mean weight, so that a black map still has a
/// density and no direction has pdf 0.
const WEIGHT_FLOOR: f64 = 1e-3;

/// A cell is weighted by the solid angle its row subtends (sin θ) times the largest value
/// of itself and its eight neighbours: bilinear filtering reads a cell as a blend of those
/// nine, so the radiance over the pdf stays bounded where a bright texel lights its
/// neighbours' cells (a sun's disc, a studio box's edge) instead of firing once in
/// thousands of samples.
pub struct LuminanceDistribution {
    width: usize,
    height: usize,
    /// Per row, the running sum of its cells' weights (width + 1 entries, from 0).
    conditional: Vec<Vec<f64>>,
    /// The running sum of the rows' totals (height + 1 entries, from 0).
    marginal: Vec<f64>,
}

impl LuminanceDistribution {
    /// From the values of a grid of cells over [0, 1]², rows from v = 0 (+y).
    pub fn new(values: &[f64], width: usize, height: usize) -> Self {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let floor = (WEIGHT_FLOOR * mean).max(f64::MIN_POSITIVE);
        let value = |x: usize, y: usize| values[y * width + x].max(0.0);
        let weight = |i: usize| {
            let (x, y) = (i % width, i / width);
            let columns = [(x + width - 1) % width, x, (x + 1) % width];
            let rows = [y.saturating_sub(1), y, (y + 1).min(height - 1)];
            let bound = rows
                .iter()
                .flat_map(|&r| columns.iter().map(move |&c| value(c, r)))
                .fold(0.0, f64::max);
            let sin_theta = ((y as f64 + 0.5) / height as f64 * PI).sin();
            (bound + floor) * sin_theta
        };
        let running_sum = |weights: &mut dyn Iterator<Item = f64>| -> Vec<f64> {
            std::iter::once(0.0)
                .chain(weights.scan(0.0, |sum, w| {
                    *sum += w;
                    Some(*sum)
                }))
                .collect()
        };
        let conditional: Vec<Vec<f64>> = (0..height)
            .map(|y| running_sum(&mut (y * width..(y + 1) * width).map(weight)))
            .collect();
        let marginal = running_sum(&mut conditional.iter().map(|row| row[width]));
        Self {
            width,
            height,
            conditional,
            marginal,
        }
    }

    /// The studio's luminance at the centres of `STUDIO_GRID`'s cells, from the disk cache
    /// when a start before computed it.
    pub fn studio() -> Self {
        Self::studio_cached(&DiskCache::from_env())
    }

    /// [`Self::studio`] from `cache`, keyed by the code that computes its cells.
    fn studio_cached(cache: &DiskCache) -> Self {
        let (w, h) = STUDIO_GRID;
        let key = cache::key(&[
            include_str!("luminance_distribution.rs").as_bytes(),
            include_str!("environment.rs").as_bytes(),
            include_str!("tonemap.rs").as_bytes(),
        ]);
        let size = w * h * std::mem::size_of::<f64>();
        let bytes = cache.get_or_compute(STUDIO_ENTRY, key, |b| b.len() == size, || {
            bytemuck::cast_slice(&Self::studio_cells()).to_vec()
        });
        Self::new(&bytemuck::pod_collect_to_vec(&bytes), w, h)
    }

    /// The studio's luminance at the centres of `STUDIO_GRID`'s cells, computed.
    fn studio_cells() -> Vec<f64> {
        let (w, h) = STUDIO_GRID;
        (0..w * h)
            .map(|i| {
                let uv = [((i % w) as f64 + 0.5) / w as f64, ((i / w) as f64 + 0.5) / h as f64];
                luminance(studio_radiance(equirect_direction(uv)))
            })
            .collect()
    }

    /// An equirectangular map's texels (rows from the top), on a grid at most `max_width`
    /// cells wide: a cell takes the largest luminance of the texels whose centres it holds,
    /// so a sun smaller than a cell still bounds its cell.
    pub fn map(texels: &[Vec3], width: usize, height: usize, max_width: usize) -> Self {
        let columns = width.min(max_width).max(1);
        let rows = ((height * columns) as f64 / width as f64).round().max(1.0) as usize;
        let mut values = vec![0.0_f64; columns * rows];
        for (i, &t) in texels.iter().enumerate() {
            let (x, y) = (i % width, i / width);
            let cx = ((x as f64 + 0.5) / width as f64 * columns as f64) as usize;
            let cy = ((y as f64 + 0.5) / height as f64 * rows as f64) as usize;
            let cell = &mut values[cy.min(rows - 1) * columns + cx.min(columns - 1)];
            *cell = cell.max(luminance(t));
        }
        Self::new(&values, columns, rows)
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// The index i with cdf[i] ≤ x cdf[n] < cdf[i + 1] (cdf has n + 1 entries from 0) and
    /// where x falls inside that interval.
    fn invert(cdf: &[f64], x: f64) -> (usize, f64) {
        let n = cdf.len() - 1;
        let target = x * cdf[n];
        let i = cdf.partition_point(|&c| c <= target).clamp(1, n) - 1;
        let width = cdf[i + 1] - cdf[i];
        let t = if width > 0.0 { (target - cdf[i]) / width } else { 0.5 };
        (i, t.clamp(0.0, 1.0))
    }

    /// The density on [0, 1]² of cell (column, row): its probability times the cells' count.
    fn cell_density(&self, column: usize, row: usize) -> f64 {
        let cdf = &self.conditional[row];
        let p_row = (self.marginal[row + 1] - self.marginal[row]) / self.marginal[self.height];
        let p_column = (cdf[column + 1] - cdf[column]) / cdf[self.width];
        p_row * p_column * (self.width * self.height) as f64
    }

    /// A point of [0, 1]² and its density.
    pub fn sample(&self, u: [f64; 2]) -> ([f64; 2], f64) {
        let (row, tv) = Self::invert(&self.marginal, u[1]);
        let (column, tu) = Self::invert(&self.conditional[row], u[0]);
        let point = [
            (column as f64 + tu) / self.width as f64,
            (row as f64 + tv) / self.height as f64,
        ];
        (point, self.cell_density(column, row))
    }

    /// The density on [0, 1]² at p.
    pub fn pdf(&self, p: [f64; 2]) -> f64 {
        let column = ((p[0].rem_euclid(1.0) * self.width as f64) as usize).min(self.width - 1);
        let row = ((p[1] * self.height as f64) as usize).min(self.height - 1);
        self.cell_density(column, row)
    }

    /// A direction in the map's frame and its pdf per steradian: dω = 2π² sin θ du dv.
    pub fn sample_direction(&self, u: [f64; 2]) -> (Vec3, f64) {
        let (uv, pdf_uv) = self.sample(u);
        let sin_theta = (uv[1] * PI).sin();
        let pdf = if sin_theta > 0.0 {
            pdf_uv / (2.0 * PI * PI * sin_theta)
        } else {
            0.0
        };
        (equirect_direction(uv), pdf)
    }

    /// The pdf per steradian of `sample_direction` choosing unit direction m (map frame).
    pub fn pdf_direction(&self, m: Vec3) -> f64 {
        let sin_theta = (1.0 - m[1] * m[1]).max(0.0).sqrt();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.pdf(equirect_uv(m)) / (2.0 * PI * PI * sin_theta)
    }

    /// The storage buffer environment.glsl reads: the marginal running sums, then each
    /// row's, in f32. Rounding keeps them non-decreasing, and the shader takes a cell's
    /// probability from the same differences it samples by, so sampling and pdf agree.
    pub fn gpu_cdfs(&self) -> Vec<f32> {
        self.marginal
            .iter()
            .chain(self.conditional.iter().flatten())
            .map(|&c| c as f32)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bright texel inside one cell of a coarser grid sets that cell's value, and the
    /// density there exceeds the rest's by about the texel's luminance over theirs.
    #[test]
    fn coarse_map_cells_keep_their_brightest_texel() {
        let (width, height) = (64, 32);
        let mut texels = vec![[1.0; 3]; width * height];
        texels[13 * width + 37] = [500.0; 3];
        let distribution = LuminanceDistribution::map(&texels, width, height, 16);
        assert_eq!((distribution.width(), distribution.height()), (16, 8));
        let bright = distribution.pdf([37.5 / 64.0, 13.5 / 32.0]);
        let dim = distribution.pdf([5.5 / 64.0, 13.5 / 32.0]);
        assert!(bright / dim > 400.0, "bright cell {bright}, dim {dim}");
    }

    #[test]
    fn the_cached_studio_grid_is_the_computed_one() {
        let dir = std::env::temp_dir().join(format!("argil-luminance-cache-{}", std::process::id()));
        let cache = DiskCache::at(Some(&dir));
        let (w, h) = STUDIO_GRID;
        let computed = LuminanceDistribution::new(&LuminanceDistribution::studio_cells(), w, h);
        let (stored, read) = (
            LuminanceDistribution::studio_cached(&cache),
            LuminanceDistribution::studio_cached(&cache),
        );
        let entries = std::fs::read_dir(&dir).map(|d| d.count());
        std::fs::remove_dir_all(&dir).expect("remove the cache");
        assert_eq!(entries.expect("the cache's entries"), 1);
        for d in [&stored, &read] {
            assert!(d.conditional == computed.conditional && d.marginal == computed.marginal);
        }
    }

    /// Every direction's pdf is what sampling draws it with, and the f32 buffer's running
    /// sums give each row and each cell within its row the probability the f64 ones do, to
    /// the rounding of sums to f32: two sums and a total, each within 2⁻²⁴ of its value.
    #[test]
    fn sampled_directions_have_their_pdf_and_the_buffer_agrees() {
        let distribution = LuminanceDistribution::studio();
        for u in [[0.1, 0.2], [0.73, 0.41], [0.5, 0.999], [0.999, 0.001]] {
            let (d, pdf) = distribution.sample_direction(u);
            assert!((distribution.pdf_direction(d) / pdf - 1.0).abs() < 1e-6, "u = {u:?}");
        }
        let cdfs = distribution.gpu_cdfs();
        let (w, h) = (distribution.width(), distribution.height());
        assert_eq!(cdfs.len(), h + 1 + h * (w + 1));
        let probability = |cdf: &[f32], i: usize| f64::from(cdf[i + 1] - cdf[i]) / f64::from(cdf[cdf.len() - 1]);
        let exact = |cdf: &[f64], i: usize| (cdf[i + 1] - cdf[i]) / cdf[cdf.len() - 1];
        let tolerance = 3.0 * 2f64.powi(-24);
        for row in 0..h {
            let p_row = probability(&cdfs[..h + 1], row);
            assert!((p_row - exact(&distribution.marginal, row)).abs() < tolerance, "row {row}");
            let conditional = &cdfs[h + 1 + row * (w + 1)..][..w + 1];
            for column in 0..w {
                let p_column = probability(conditional, column);
                let expected = exact(&distribution.conditional[row], column);
                assert!((p_column - expected).abs() < tolerance, "cell ({column}, {row})");
            }
        }
    }
}
