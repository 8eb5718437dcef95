//! Writing frames to files: PNG (tone-mapped sRGB, 8-bit) and EXR (linear radiance, fp32).

use std::path::Path;

use anyhow::{bail, Context, Result};

use super::renderer::OffscreenFrame;

/// Writes the frame in the format the extension names: `.png` or `.exr`.
pub fn write_frame(frame: &OffscreenFrame, path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => {
            let image = image::RgbaImage::from_raw(frame.width, frame.height, frame.display.clone())
                .context("display frame has the wrong size")?;
            image
                .save(path)
                .with_context(|| format!("cannot write {}", path.display()))
        }
        Some("exr") => {
            let image = image::Rgba32FImage::from_raw(frame.width, frame.height, frame.hdr.clone())
                .context("HDR frame has the wrong size")?;
            image
                .save(path)
                .with_context(|| format!("cannot write {}", path.display()))
        }
        _ => bail!(
            "{}: the output must end in .png (tone-mapped) or .exr (linear radiance)",
            path.display()
        ),
    }
}

/// How many values of the frame are NaN or infinite.
pub fn count_non_finite(values: &[f32]) -> usize {
    values.iter().filter(|v| !v.is_finite()).count()
}
