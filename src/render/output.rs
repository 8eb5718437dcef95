//! Writing frames to files: PNG (tone-mapped sRGB, 8-bit) and EXR (linear radiance, fp32),
//! each written atomically.

use std::path::Path;

use anyhow::{bail, Context, Result};
use exr::prelude::{
    AttributeValue, Encoding, Image, Layer, LayerAttributes, LineOrder, SpecificChannels, Text, WritableImage,
};

use super::renderer::OffscreenFrame;
use crate::atomic::{write_atomically, Existing};
use crate::brdf::tonemap::display_srgb8;
use crate::error::InputError;

/// What a path's extension asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// Tone-mapped, 8-bit sRGB.
    Png,
    /// Linear radiance, RGBA32F.
    Exr,
}

impl OutputKind {
    pub fn of(path: &Path) -> Result<Self> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(OutputKind::Png),
            Some("exr") => Ok(OutputKind::Exr),
            _ => Err(InputError::file(
                path,
                "the output must end in .png (tone-mapped) or .exr (linear radiance)",
            )
            .into()),
        }
    }
}

/// Writes the frame in the format the extension names: `.png` or `.exr`, whose header
/// gives the frames its mean holds (`argil.frames`).
pub fn write_frame(frame: &OffscreenFrame, path: &Path, existing: Existing) -> Result<()> {
    match OutputKind::of(path)? {
        OutputKind::Png => write_png(path, existing, frame.width, frame.height, &frame.display),
        OutputKind::Exr => {
            let attributes = [("argil.frames", frame.frames.to_string())];
            write_exr(path, existing, frame.width, frame.height, &frame.hdr, &attributes)
        }
    }
}

/// Writes linear RGBA radiance as the extension asks: EXR as it is, with the header
/// attributes; PNG through the display transform of `tonemap.frag` (exposure, Khronos PBR
/// Neutral, sRGB), here in f64.
pub fn write_linear(
    path: &Path,
    existing: Existing,
    width: u32,
    height: u32,
    rgba: &[f32],
    exposure: f32,
    attributes: &[(&str, String)],
) -> Result<()> {
    match OutputKind::of(path)? {
        OutputKind::Exr => write_exr(path, existing, width, height, rgba, attributes),
        OutputKind::Png => {
            let display: Vec<u8> = rgba
                .chunks_exact(4)
                .flat_map(|p| {
                    let hdr = [0, 1, 2].map(|c| f64::from(p[c]) * f64::from(exposure));
                    let [r, g, b] = display_srgb8(hdr);
                    [r, g, b, 255]
                })
                .collect();
            write_png(path, existing, width, height, &display)
        }
    }
}

fn write_png(path: &Path, existing: Existing, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    let image =
        image::RgbaImage::from_raw(width, height, rgba8.to_vec()).context("display frame has the wrong size")?;
    write_atomically(path, existing, |sink| Ok(image.write_to(sink, image::ImageFormat::Png)?))
}

/// An RGBA32F EXR with string attributes in its header (`argil.spp`, …).
pub fn write_exr(
    path: &Path,
    existing: Existing,
    width: u32,
    height: u32,
    rgba: &[f32],
    attributes: &[(&str, String)],
) -> Result<()> {
    let (w, h) = (width as usize, height as usize);
    if rgba.len() != 4 * w * h {
        bail!("HDR frame has the wrong size");
    }
    let channels = SpecificChannels::rgba(|p: exr::math::Vec2<usize>| {
        let i = 4 * (p.y() * w + p.x());
        (rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3])
    });
    let mut layer_attributes = LayerAttributes::default();
    for (name, value) in attributes {
        layer_attributes
            .other
            .insert(Text::from(*name), AttributeValue::Text(Text::from(value.as_str())));
    }
    // Blocks compressed on every core, written in order so that a frame is the same file.
    let encoding = Encoding {
        line_order: LineOrder::Increasing,
        ..Encoding::FAST_LOSSLESS
    };
    let layer = Layer::new((w, h), layer_attributes, encoding, channels);
    let image = Image::from_layer(layer);
    write_atomically(path, existing, |sink| Ok(image.write().to_buffered(sink)?))
}

/// How many values of the frame are NaN or infinite.
pub fn count_non_finite(values: &[f32]) -> usize {
    values.iter().filter(|v| !v.is_finite()).count()
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("argil-output-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn exr_attributes_and_pixels_round_trip() {
        let dir = temp_dir("attributes");
        let path = dir.join("ref.exr");
        let rgba = [0.5, 0.25, 0.125, 1.0, 4.0, 0.0, 1e-3, 0.5];
        write_exr(&path, Existing::Replace, 2, 1, &rgba, &[("argil.spp", "64".into())]).unwrap();
        let image = exr::prelude::read_first_rgba_layer_from_file(
            &path,
            |resolution, _| vec![[0.0f32; 4]; resolution.width() * resolution.height()],
            |pixels: &mut Vec<[f32; 4]>, p, (r, g, b, a): (f32, f32, f32, f32)| pixels[p.x()] = [r, g, b, a],
        )
        .unwrap();
        assert_eq!(image.layer_data.channel_data.pixels.concat(), rgba);
        let spp = image.layer_data.attributes.other.get(&Text::from("argil.spp"));
        assert_eq!(spp, Some(&AttributeValue::Text(Text::from("64"))));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
