//! Material maps on the CPU, read as the GPU reads level 0 of them: texels decoded to
//! linear values (the sRGB EOTF for `Rgba8Srgb`, /255 or /65535 for UNORM), then
//! filtered bilinearly with repeat addressing. The rasteriser's mip levels and anisotropy
//! are an approximation of this: the reference's box filter averages the map over the
//! pixel's footprint itself.

use glam::DVec2;

use crate::scene::{TexelReader, TextureData};

pub struct Texture {
    width: usize,
    height: usize,
    /// Linear RGBA, row 0 at v = 0, as the GPU samples it (an image file's bottom row).
    texels: Vec<[f64; 4]>,
}

impl Texture {
    pub fn new(data: &TextureData) -> Self {
        let texels = TexelReader::new(data.format).read_all(&data.pixels);
        Self {
            width: data.width as usize,
            height: data.height as usize,
            texels,
        }
    }

    /// Bilinear filtering at uv with repeat addressing; texel (i, j) is centred at
    /// ((i + ½)/w, (j + ½)/h).
    pub fn sample(&self, uv: DVec2) -> [f64; 4] {
        let x = uv.x * self.width as f64 - 0.5;
        let y = uv.y * self.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |i: f64, n: usize| (i.rem_euclid(n as f64) as usize).min(n - 1);
        let (xa, xb) = (wrap(x0, self.width), wrap(x0 + 1.0, self.width));
        let (ya, yb) = (wrap(y0, self.height), wrap(y0 + 1.0, self.height));
        let at = |x: usize, y: usize| &self.texels[y * self.width + x];
        let (a, b, c, d) = (at(xa, ya), at(xb, ya), at(xa, yb), at(xb, yb));
        std::array::from_fn(|i| {
            let top = a[i] + (b[i] - a[i]) * fx;
            let bottom = c[i] + (d[i] - c[i]) * fx;
            top + (bottom - top) * fy
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::TexelFormat;

    fn texture(width: u32, height: u32, values: &[u8]) -> Texture {
        Texture::new(&TextureData {
            name: "test".into(),
            width,
            height,
            format: TexelFormat::Rgba8Unorm,
            pixels: values.iter().flat_map(|&v| [v, v, v, 255]).collect(),
        })
    }

    #[test]
    fn texel_centres_return_texels_and_edges_wrap() {
        let t = texture(2, 1, &[0, 255]);
        assert_eq!(t.sample(DVec2::new(0.25, 0.5))[0], 0.0);
        assert_eq!(t.sample(DVec2::new(0.75, 0.5))[0], 1.0);
        // Halfway between texel 1 and texel 0 of the next repeat.
        assert!((t.sample(DVec2::new(1.0, 0.5))[0] - 0.5).abs() < 1e-12);
        assert!((t.sample(DVec2::new(-0.5, 7.0))[0] - 0.5).abs() < 1e-12);
        assert!((t.sample(DVec2::new(0.5, 0.5))[0] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn srgb_texels_are_decoded_before_filtering() {
        let t = Texture::new(&TextureData {
            name: "srgb".into(),
            width: 1,
            height: 1,
            format: TexelFormat::Rgba8Srgb,
            pixels: vec![188, 188, 188, 255],
        });
        // sRGB 188/255 is linear 0.5029.
        assert!((t.sample(DVec2::new(0.3, 0.9))[0] - 0.502_886).abs() < 1e-6);
    }
}
