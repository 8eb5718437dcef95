//! A texture's mip chain, made on the CPU: each level from the one above it as a linear
//! blit (`vkCmdBlitImage`, `VK_FILTER_LINEAR`) makes it, with sRGB colour averaged in
//! linear space. Made here rather than by blits on the device so that every device samples
//! the same levels (lavapipe's blits round upwards) and a start does not wait while
//! lavapipe compiles its blit shader (50 ms).

use rayon::prelude::*;

use super::procedural::builtin_key;
use super::{TexelFormat, TexelReader, TextureData, BUILTIN_PREFIX};
use crate::brdf::tonemap::srgb_eotf;
use crate::cache::{self, DiskCache};

/// Width or height of the level below one `side` texels across (as `Image::level_extent`).
fn half_side(side: u32) -> u32 {
    (side >> 1).max(1)
}

/// Width and height of every level of `texture`'s full chain, level 0 first, each half the
/// one above, down to 1×1.
fn chain_extents(texture: &TextureData) -> Vec<(u32, u32)> {
    let mut extents = vec![(texture.width, texture.height)];
    while let Some(&(width, height)) = extents.last().filter(|&&(w, h)| w > 1 || h > 1) {
        extents.push((half_side(width), half_side(height)));
    }
    extents
}

/// Levels 1 and below of `texture`'s full chain (level 0 is its own texels), each tightly
/// packed in its format.
pub fn mip_levels(texture: &TextureData) -> Vec<Vec<u8>> {
    let codec = Codec::new(texture.format);
    let extents = chain_extents(texture);
    let mut levels: Vec<Vec<u8>> = Vec::new();
    // Each level from the one above, whose extent downsample reads.
    for &(width, height) in &extents[..extents.len() - 1] {
        let above = levels.last().unwrap_or(&texture.pixels);
        levels.push(codec.downsample(above, width, height));
    }
    levels
}

/// [`mip_levels`] of `texture`, from `cache` where it is a builtin map, whose texels and so
/// whose levels follow from its key: made and stored by the first start, read by the next
/// (about 5 ms a 1024² normal map made, a fraction of one read).
pub fn cached_mip_levels(texture: &TextureData, cache: &DiskCache) -> Vec<Vec<u8>> {
    let Some(texels) = builtin_key(texture) else {
        return mip_levels(texture);
    };
    let key = cache::key(&[&texels.to_le_bytes(), include_str!("mips.rs").as_bytes()]);
    let entry = format!("mips-{}", texture.name.trim_start_matches(BUILTIN_PREFIX));
    let bytes_per_texel = texture.format.bytes_per_texel();
    let below = chain_extents(texture).into_iter().skip(1);
    let sizes: Vec<usize> = below.map(|(w, h)| w as usize * h as usize * bytes_per_texel).collect();
    let total: usize = sizes.iter().sum();
    let chain = cache.get_or_compute(&entry, key, |b| b.len() == total, || mip_levels(texture).concat());
    let mut rest = chain.as_slice();
    sizes
        .iter()
        .map(|&size| {
            let (level, below) = rest.split_at(size);
            rest = below;
            level.to_vec()
        })
        .collect()
}

/// Reads and writes texels of one format as linear RGBA.
struct Codec {
    reader: TexelReader,
    /// The linear values halfway between consecutive 8-bit sRGB codes: a value's code is
    /// how many of them it reaches, which rounding its encoding to 8 bits gives.
    srgb_midpoints: Vec<f64>,
}

impl Codec {
    fn new(format: TexelFormat) -> Codec {
        let srgb_midpoints = if format == TexelFormat::Rgba8Srgb {
            (0..255).map(|code| srgb_eotf((f64::from(code) + 0.5) / 255.0)).collect()
        } else {
            Vec::new()
        };
        Codec {
            reader: TexelReader::new(format),
            srgb_midpoints,
        }
    }

    /// `values` into `out`, tightly packed. Unorm values round to nearest, as Vulkan's
    /// float-to-normalized conversion (v + ½ truncated: `round` is a library call).
    fn write_all(&self, values: &[[f64; 4]], out: &mut [u8]) {
        let unorm = |v: f64, max: f64| v.clamp(0.0, 1.0) * max + 0.5;
        let texels = out.chunks_exact_mut(self.reader.format().bytes_per_texel()).zip(values);
        match self.reader.format() {
            TexelFormat::Rgba8Srgb => {
                let colour = |v: f64| self.srgb_midpoints.partition_point(|&m| m <= v) as u8;
                for (t, v) in texels {
                    t.copy_from_slice(&[colour(v[0]), colour(v[1]), colour(v[2]), unorm(v[3], 255.0) as u8]);
                }
            }
            TexelFormat::Rgba8Unorm => {
                for (t, v) in texels {
                    t.copy_from_slice(&v.map(|c| unorm(c, 255.0) as u8));
                }
            }
            TexelFormat::Rgba16Unorm => {
                for (t, v) in texels {
                    t.copy_from_slice(bytemuck::cast_slice(&v.map(|c| unorm(c, 65535.0) as u16)));
                }
            }
            TexelFormat::Rgba32Float => {
                for (t, v) in texels {
                    t.copy_from_slice(bytemuck::cast_slice(&v.map(|c| c as f32)));
                }
            }
        }
    }

    /// The level below a `width` × `height` level `above`.
    fn downsample(&self, above: &[u8], width: u32, height: u32) -> Vec<u8> {
        let (to_width, to_height) = (half_side(width), half_side(height));
        let texel = self.reader.format().bytes_per_texel();
        let row_bytes = width as usize * texel;
        let (columns, rows) = (blit_taps(width, to_width), blit_taps(height, to_height));
        let mut level = vec![0; to_width as usize * to_height as usize * texel];
        let lerp = |a: [f64; 4], b: [f64; 4], t: f64| std::array::from_fn(|c| a[c] + (b[c] - a[c]) * t);
        level
            .par_chunks_mut(to_width as usize * texel)
            .zip(rows)
            .for_each(|(out, (y0, y1, ty))| {
                let row = |y: usize| self.reader.read_all(&above[y * row_bytes..(y + 1) * row_bytes]);
                let (top, bottom) = (row(y0), row(y1));
                let filtered: Vec<[f64; 4]> = columns
                    .iter()
                    .map(|&(x0, x1, tx)| lerp(lerp(top[x0], top[x1], tx), lerp(bottom[x0], bottom[x1], tx), ty))
                    .collect();
                self.write_all(&filtered, out);
            });
        level
    }
}

/// Where a linear blit from `from` texels to `to` samples each destination texel: the
/// source texels either side of its centre's image and the second's weight, clamped to the
/// edge. Halving an even side averages each pair.
fn blit_taps(from: u32, to: u32) -> Vec<(usize, usize, f64)> {
    let last = f64::from(from - 1);
    (0..to)
        .map(|i| {
            let u = ((f64::from(i) + 0.5) * f64::from(from) / f64::from(to) - 0.5).clamp(0.0, last);
            let below = u.floor();
            (below as usize, (below + 1.0).min(last) as usize, u - below)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::tonemap::srgb_oetf;

    fn texture(width: u32, height: u32, format: TexelFormat, pixels: Vec<u8>) -> TextureData {
        TextureData {
            name: "test".into(),
            width,
            height,
            format,
            pixels,
        }
    }

    /// A builtin map's levels are read from the cache once stored there, a stand-in's (whose
    /// texels its name does not fix) always made, and a corrupt entry is made again.
    #[test]
    fn builtin_maps_levels_are_cached_and_a_stand_ins_are_not() {
        let dir = std::env::temp_dir().join(format!("argil-mips-cache-{}", std::process::id()));
        let cache = DiskCache::at(Some(&dir));
        let map = crate::scene::builtin_texture("builtin:noise").expect("a builtin map");
        let made = mip_levels(&map);
        assert_eq!(cached_mip_levels(&map, &cache), made);
        let entries = || std::fs::read_dir(&dir).map_or(0, |d| d.filter(|e| e.is_ok()).count());
        assert_eq!(entries(), 1, "the first call stores the chain");
        assert_eq!(cached_mip_levels(&map, &cache), made);
        let entry = std::fs::read_dir(&dir).unwrap().next().unwrap().unwrap().path();
        let mut bytes = std::fs::read(&entry).unwrap();
        let last = bytes.len() - 1;
        bytes[last] ^= 0xff;
        std::fs::write(&entry, bytes).unwrap();
        assert_eq!(cached_mip_levels(&map, &cache), made, "a corrupt entry is made again");
        let stand_in = crate::scene::procedural::stand_in("builtin:noise").expect("a stand-in");
        assert_eq!(cached_mip_levels(&stand_in, &cache), mip_levels(&stand_in));
        assert_eq!(entries(), 1, "a stand-in stores nothing");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn levels_halve_down_to_one_texel() {
        let t = texture(8, 2, TexelFormat::Rgba8Unorm, vec![0; 8 * 2 * 4]);
        let sizes: Vec<usize> = mip_levels(&t).iter().map(Vec::len).collect();
        assert_eq!(sizes, [4 * 4, 2 * 4, 4]);
        assert!(mip_levels(&texture(1, 1, TexelFormat::Rgba8Unorm, vec![0; 4])).is_empty());
    }

    #[test]
    fn even_sides_average_each_square_of_four() {
        let values: Vec<f32> = (0..16).map(|i| i as f32).collect();
        let t = texture(2, 2, TexelFormat::Rgba32Float, bytemuck::cast_slice(&values).to_vec());
        let level: Vec<f32> = bytemuck::cast_slice(&mip_levels(&t)[0]).to_vec();
        // Channel c of texel i holds 4i + c, and the mean of i over 0..4 is 1.5.
        assert_eq!(level, [6.0, 7.0, 8.0, 9.0]);
    }

    #[test]
    fn odd_sides_sample_as_a_linear_blit() {
        // 3 → 1: the centre maps to the middle texel.
        let t = texture(3, 1, TexelFormat::Rgba8Unorm, [[10; 4], [200; 4], [30; 4]].concat());
        assert_eq!(mip_levels(&t)[0], [200; 4]);
        // 5 → 2: the centres map to texel coordinates 0.75 and 3.25.
        assert_eq!(blit_taps(5, 2), [(0, 1, 0.75), (3, 4, 0.25)]);
    }

    #[test]
    fn srgb_colour_is_averaged_in_linear_space_and_alpha_as_is() {
        let t = texture(2, 1, TexelFormat::Rgba8Srgb, vec![0, 0, 0, 0, 255, 255, 255, 255]);
        let level = &mip_levels(&t)[0];
        // Linear 0.5 encodes to 0.7354 × 255 = 187.5 → 188; alpha 127.5 → 128.
        let expected = (srgb_oetf(0.5) * 255.0).round() as u8;
        assert_eq!(expected, 188);
        assert_eq!(level, &[188, 188, 188, 128]);
    }

    #[test]
    fn srgb_codes_are_the_nearest_encoding_of_every_linear_value() {
        let codec = Codec::new(TexelFormat::Rgba8Srgb);
        for code in 0..=255u8 {
            let mut out = [0; 4];
            codec.write_all(&codec.reader.read_all(&[code, code, code, 255]), &mut out);
            assert_eq!(out[0], code, "code {code} does not survive decoding and encoding");
        }
        for i in 0..=1000 {
            let linear = i as f64 / 1000.0;
            let mut out = [0; 4];
            codec.write_all(&[[linear, 0.0, 0.0, 1.0]], &mut out);
            let nearest = (srgb_oetf(linear) * 255.0).round();
            assert_eq!(f64::from(out[0]), nearest, "linear {linear}");
        }
    }

    #[test]
    fn sixteen_bit_channels_round_to_nearest() {
        let texels: Vec<u16> = [[0u16; 4], [u16::MAX; 4]].concat();
        let t = texture(2, 1, TexelFormat::Rgba16Unorm, bytemuck::cast_slice(&texels).to_vec());
        let level: Vec<u16> = bytemuck::cast_slice(&mip_levels(&t)[0]).to_vec();
        assert_eq!(level, [32768; 4], "32767.5 rounds up");
    }
}
