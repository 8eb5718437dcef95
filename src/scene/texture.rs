//! Textures on the CPU: decoded image files, ready for upload.

use std::fs::File;
use std::io::{BufRead, BufReader, Cursor, ErrorKind, Seek, SeekFrom};
use std::path::Path;

use image::{ColorType, DynamicImage, ImageDecoder, ImageError, ImageFormat, ImageReader, Limits};

use super::SceneError;
use crate::brdf::tonemap::srgb_eotf;

/// Largest width or height accepted, in texels (Vulkan's guaranteed
/// `maxImageDimension2D` is 4096; 16384 is what desktop GPUs offer).
pub const MAX_TEXTURE_SIDE: u32 = 16384;

/// Largest decoded texture accepted, in bytes, checked from the header before
/// decoding so that a small file claiming a huge image cannot exhaust memory.
pub const MAX_TEXTURE_BYTES: u64 = 1 << 30;

/// How the texels of a [`TextureData`] are stored: RGBA, 8-bit, 16-bit or
/// 32-bit float channels. Multi-byte channels are native-endian, as the GPU
/// reads them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelFormat {
    /// sRGB-encoded colour, linear alpha (`R8G8B8A8_SRGB`).
    Rgba8Srgb,
    /// Linear data (`R8G8B8A8_UNORM`).
    Rgba8Unorm,
    /// Linear data (`R16G16B16A16_UNORM`).
    Rgba16Unorm,
    /// Linear values (`R32G32B32A32_SFLOAT`).
    Rgba32Float,
}

impl TexelFormat {
    pub fn bytes_per_texel(self) -> usize {
        match self {
            TexelFormat::Rgba8Srgb | TexelFormat::Rgba8Unorm => 4,
            TexelFormat::Rgba16Unorm => 8,
            TexelFormat::Rgba32Float => 16,
        }
    }
}

/// What a texture is used for, which decides how its file is decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureRole {
    /// Colour: sRGB-encoded when 8-bit, linear when float.
    BaseColor,
    /// Tangent-space normals: linear data, 8 or 16 bits.
    Normal,
    /// Linear data: noise and the property maps.
    Data,
}

/// Reads texels of one format as linear RGBA, sRGB colour decoded as the GPU decodes it.
pub struct TexelReader {
    format: TexelFormat,
    /// The linear value of each 8-bit sRGB code: a table, as a whole texture is read.
    srgb: Vec<f64>,
}

impl TexelReader {
    pub fn new(format: TexelFormat) -> TexelReader {
        let srgb = if format == TexelFormat::Rgba8Srgb {
            (0..256).map(|code| srgb_eotf(f64::from(code) / 255.0)).collect()
        } else {
            Vec::new()
        };
        TexelReader { format, srgb }
    }

    pub fn format(&self) -> TexelFormat {
        self.format
    }

    /// The texels of `pixels` (whole texels, tightly packed), in order.
    pub fn read_all(&self, pixels: &[u8]) -> Vec<[f64; 4]> {
        let texels = pixels.chunks_exact(self.format.bytes_per_texel());
        let unorm8 = |c: u8| f64::from(c) / 255.0;
        // One match a call, not a texel: the loops stay tight.
        match self.format {
            TexelFormat::Rgba8Srgb => {
                let colour = |c: u8| self.srgb[usize::from(c)];
                texels.map(|t| [colour(t[0]), colour(t[1]), colour(t[2]), unorm8(t[3])]).collect()
            }
            TexelFormat::Rgba8Unorm => texels.map(|t| std::array::from_fn(|c| unorm8(t[c]))).collect(),
            TexelFormat::Rgba16Unorm => texels
                .map(|t| std::array::from_fn(|c| f64::from(u16::from_ne_bytes([t[2 * c], t[2 * c + 1]])) / 65535.0))
                .collect(),
            TexelFormat::Rgba32Float => texels
                .map(|t| {
                    std::array::from_fn(|c| {
                        f64::from(f32::from_ne_bytes([t[4 * c], t[4 * c + 1], t[4 * c + 2], t[4 * c + 3]]))
                    })
                })
                .collect(),
        }
    }
}

/// A decoded 2D texture: tightly packed rows, RGBA; row 0 is sampled at v = 0, which for
/// an image file is its bottom row (the mesh UVs' v runs up the image).
#[derive(Clone, Debug, PartialEq)]
pub struct TextureData {
    /// The file's path, or the `builtin:` name.
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub format: TexelFormat,
    pub pixels: Vec<u8>,
}

/// Loads a PNG (8 or 16 bits), JPEG, Radiance HDR or OpenEXR file as a
/// texture for `role`.
///
/// * 8-bit PNG and JPEG: `Rgba8Srgb` for [`TextureRole::BaseColor`],
///   `Rgba8Unorm` otherwise.
/// * 16-bit PNG: `Rgba16Unorm`; for `BaseColor` (sRGB-encoded like 8-bit
///   files) its colour is decoded to linear `Rgba32Float`, which keeps the
///   16 bits of precision that an 8-bit sRGB format would drop.
/// * HDR and EXR: `Rgba32Float`, linear; every value must be finite and
///   >= 0. Not accepted for normal maps.
///
/// Grey and RGB images get alpha 1. The extension must be one of `.png`,
/// `.jpg`, `.jpeg`, `.hdr`, `.exr`; the data is decoded by its content.
/// Every error names the file.
pub fn load_texture(path: &Path, role: TextureRole) -> Result<TextureData, SceneError> {
    let fail = |problem: String| SceneError::Texture {
        path: path.to_path_buf(),
        problem,
    };
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if !["png", "jpg", "jpeg", "hdr", "exr"].contains(&extension.as_str()) {
        return Err(fail(format!(
            "unsupported texture file extension {:?}; expected .png, .jpg, .jpeg, .hdr or .exr",
            extension
        )));
    }
    let file = File::open(path).map_err(|error| SceneError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    decode(BufReader::new(file), path, role)
}

/// Decodes an image held in memory (one embedded in a glTF model) as [`load_texture`]
/// decodes a file, with its limits and errors, which name the texture `name`.
pub fn decode_texture(bytes: &[u8], name: &str, role: TextureRole) -> Result<TextureData, SceneError> {
    decode(Cursor::new(bytes), Path::new(name), role)
}

/// The decoding of [`load_texture`] and [`decode_texture`], by content; errors name `name`.
fn decode<R: BufRead + Seek>(mut data: R, name: &Path, role: TextureRole) -> Result<TextureData, SceneError> {
    let fail = |problem: String| SceneError::Texture {
        path: name.to_path_buf(),
        problem,
    };
    let io_error = |error| SceneError::Io {
        path: name.to_path_buf(),
        error,
    };
    let start = data.stream_position().map_err(io_error)?;
    let reader = ImageReader::new(&mut data).with_guessed_format().map_err(io_error)?;
    let format = match reader.format() {
        Some(format @ (ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::Hdr | ImageFormat::OpenExr)) => format,
        Some(other) => {
            return Err(fail(format!(
                "is a {other:?} image; textures must be PNG, JPEG, Radiance HDR or OpenEXR"
            )))
        }
        None => {
            return Err(fail(
                "not an image: the data is not PNG, JPEG, Radiance HDR or OpenEXR".to_owned(),
            ))
        }
    };
    if format == ImageFormat::OpenExr {
        super::limits::check_exr_headers_in(&mut data).map_err(fail)?;
    }
    data.seek(SeekFrom::Start(start)).map_err(io_error)?;
    let mut reader = ImageReader::with_format(data, format);
    let float = matches!(format, ImageFormat::Hdr | ImageFormat::OpenExr);
    if float && role == TextureRole::Normal {
        return Err(fail(format!(
            "a {} image cannot be a normal map (normal maps are 8- or 16-bit PNG or JPEG)",
            format_name(format)
        )));
    }
    // The decoder's own allocation limit backs up the header check below.
    let mut limits = Limits::default();
    limits.max_alloc = Some(MAX_TEXTURE_BYTES);
    reader.limits(limits);
    let decoder = reader.into_decoder().map_err(|e| fail(describe(format, e)))?;

    let (width, height) = decoder.dimensions();
    let color = decoder.color_type();
    if width == 0 || height == 0 {
        return Err(fail(format!("the image is empty ({width} × {height})")));
    }
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(fail(format!(
            "the image is too large ({width} × {height}); each side must be at most {MAX_TEXTURE_SIDE}"
        )));
    }
    let texel_format = texel_format(color, role).ok_or_else(|| {
        fail(format!(
            "unsupported pixel format {color:?} in a {} image",
            format_name(format)
        ))
    })?;
    let bytes = u64::from(width) * u64::from(height) * texel_format.bytes_per_texel() as u64;
    if bytes.max(decoder.total_bytes()) > MAX_TEXTURE_BYTES {
        return Err(fail(format!(
            "the image is too large ({width} × {height} {texel_format:?} is {} MiB); at most {} MiB",
            bytes >> 20,
            MAX_TEXTURE_BYTES >> 20
        )));
    }

    let image = DynamicImage::from_decoder(decoder).map_err(|e| fail(describe(format, e)))?;
    let mut pixels = match texel_format {
        TexelFormat::Rgba8Srgb | TexelFormat::Rgba8Unorm => image.into_rgba8().into_raw(),
        TexelFormat::Rgba16Unorm => bytemuck::cast_slice(&image.into_rgba16().into_raw()).to_vec(),
        // Float files; the other float textures are 16-bit sRGB colour.
        TexelFormat::Rgba32Float if float => {
            let texels = image.into_rgba32f().into_raw();
            if let Some(index) = texels.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
                let texel = (index / 4) as u64;
                return Err(fail(format!(
                    "texel ({}, {}) has channel {} = {}; every value must be finite and >= 0",
                    texel % u64::from(width),
                    texel / u64::from(width),
                    ["R", "G", "B", "A"][index % 4],
                    texels[index]
                )));
            }
            bytemuck::cast_slice(&texels).to_vec()
        }
        TexelFormat::Rgba32Float => srgb16_to_linear(&image.into_rgba16().into_raw()),
    };
    // Mesh UVs have v up the image (OBJ's, and glTF's after its loader's 1 − v) and the
    // samplers put row 0 at v = 0, so a file's rows are stored from its bottom row up.
    flip_rows(&mut pixels, width as usize * texel_format.bytes_per_texel());
    Ok(TextureData {
        name: name.display().to_string(),
        width,
        height,
        format: texel_format,
        pixels,
    })
}

/// Reverses the order of the `row`-byte rows of `pixels` in place, a row swap at a time
/// (a copy byte by byte took 22 ms of a 2048² PNG's 55 ms load).
fn flip_rows(pixels: &mut [u8], row: usize) {
    let rows = pixels.len() / row;
    for top in 0..rows / 2 {
        let (above, below) = pixels.split_at_mut((rows - 1 - top) * row);
        above[top * row..(top + 1) * row].swap_with_slice(&mut below[..row]);
    }
}

/// The stored format for a decoded colour type, or `None` if unsupported.
fn texel_format(color: ColorType, role: TextureRole) -> Option<TexelFormat> {
    Some(match color {
        ColorType::L8 | ColorType::La8 | ColorType::Rgb8 | ColorType::Rgba8 => {
            if role == TextureRole::BaseColor {
                TexelFormat::Rgba8Srgb
            } else {
                TexelFormat::Rgba8Unorm
            }
        }
        ColorType::L16 | ColorType::La16 | ColorType::Rgb16 | ColorType::Rgba16 => {
            if role == TextureRole::BaseColor {
                TexelFormat::Rgba32Float
            } else {
                TexelFormat::Rgba16Unorm
            }
        }
        ColorType::Rgb32F | ColorType::Rgba32F => TexelFormat::Rgba32Float,
        _ => return None,
    })
}

/// 16-bit sRGB-encoded RGBA to linear f32 bytes; alpha is linear already.
fn srgb16_to_linear(texels: &[u16]) -> Vec<u8> {
    // A table is ~100× faster than powf per channel on a 16k × 16k image.
    let table: Vec<f32> = (0..=u16::MAX)
        .map(|code| srgb_eotf(f64::from(code) / f64::from(u16::MAX)) as f32)
        .collect();
    let linear: Vec<f32> = texels
        .chunks_exact(4)
        .flat_map(|t| {
            [
                table[usize::from(t[0])],
                table[usize::from(t[1])],
                table[usize::from(t[2])],
                f32::from(t[3]) / f32::from(u16::MAX),
            ]
        })
        .collect();
    bytemuck::cast_slice(&linear).to_vec()
}

fn format_name(format: ImageFormat) -> &'static str {
    match format {
        ImageFormat::Png => "PNG",
        ImageFormat::Jpeg => "JPEG",
        ImageFormat::Hdr => "Radiance HDR",
        ImageFormat::OpenExr => "OpenEXR",
        _ => "image",
    }
}

/// A decoder error as a sentence that says what is wrong with the file.
fn describe(format: ImageFormat, error: ImageError) -> String {
    let name = format_name(format);
    match error {
        ImageError::IoError(e) if e.kind() == ErrorKind::UnexpectedEof => {
            format!("truncated {name} data: {e}")
        }
        ImageError::IoError(e) => format!("cannot read {name} data: {e}"),
        ImageError::Decoding(e) => format!("corrupt or truncated {name} data: {e}"),
        ImageError::Limits(e) => format!("the image is too large to decode: {e}"),
        ImageError::Unsupported(e) => format!("unsupported {name} variant: {e}"),
        other => format!("cannot decode {name} data: {other}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::imageops::flip_vertical;
    use crate::scene::tests::TempDir;
    use image::{ImageBuffer, Rgb, Rgba};

    fn rgba8(width: u32, height: u32) -> ImageBuffer<Rgba<u8>, Vec<u8>> {
        ImageBuffer::from_fn(width, height, |x, y| {
            Rgba([(x * 40) as u8, (y * 60) as u8, 200, 255 - x as u8])
        })
    }

    fn message(path: &Path, role: TextureRole) -> String {
        let message = load_texture(path, role).unwrap_err().to_string();
        let prefix = format!("{}: ", path.display());
        assert!(message.starts_with(&prefix), "{message}");
        message[prefix.len()..].to_owned()
    }

    #[test]
    fn rows_are_reversed_in_place() {
        for rows in [1u8, 2, 3, 4] {
            let mut pixels: Vec<u8> = (0..rows).flat_map(|r| [r, r, 10 + r]).collect();
            flip_rows(&mut pixels, 3);
            let reversed: Vec<u8> = (0..rows).rev().flat_map(|r| [r, r, 10 + r]).collect();
            assert_eq!(pixels, reversed, "{rows} rows");
        }
    }

    #[test]
    fn png_8_bit_is_srgb_for_colour_and_unorm_for_data() {
        let dir = TempDir::new();
        let path = dir.0.join("colour.png");
        let image = rgba8(5, 3);
        image.save(&path).unwrap();
        let colour = load_texture(&path, TextureRole::BaseColor).unwrap();
        assert_eq!(
            (colour.width, colour.height, colour.format),
            (5, 3, TexelFormat::Rgba8Srgb)
        );
        // Stored from the bottom row up (v = 0 first).
        assert_eq!(colour.pixels, flip_vertical(&image).as_raw().as_slice());
        assert_eq!(colour.name, path.display().to_string());
        let normal = load_texture(&path, TextureRole::Normal).unwrap();
        assert_eq!(normal.format, TexelFormat::Rgba8Unorm);
        assert_eq!(normal.pixels, colour.pixels);

        // Grey without alpha gets alpha 1.
        let grey = dir.0.join("grey.png");
        ImageBuffer::from_pixel(2, 2, image::Luma([77u8])).save(&grey).unwrap();
        let noise = load_texture(&grey, TextureRole::Data).unwrap();
        assert_eq!(noise.pixels, [77, 77, 77, 255].repeat(4));
    }

    #[test]
    fn png_16_bit_keeps_its_precision() {
        let dir = TempDir::new();
        let path = dir.0.join("normal16.png");
        let image: ImageBuffer<Rgba<u16>, Vec<u16>> =
            ImageBuffer::from_fn(4, 2, |x, y| Rgba([x as u16 * 1000 + 1, 65535, y as u16, 32768]));
        image.save(&path).unwrap();
        let normal = load_texture(&path, TextureRole::Normal).unwrap();
        assert_eq!(normal.format, TexelFormat::Rgba16Unorm);
        let texels: Vec<u16> = bytemuck::pod_collect_to_vec(&normal.pixels);
        assert_eq!(texels, *flip_vertical(&image).as_raw());

        // Colour: sRGB decoded to linear float; alpha stays linear.
        let colour = load_texture(&path, TextureRole::BaseColor).unwrap();
        assert_eq!(colour.format, TexelFormat::Rgba32Float);
        let texels: Vec<f32> = bytemuck::pod_collect_to_vec(&colour.pixels);
        assert_eq!(texels.len(), 4 * 8);
        assert_eq!(texels[1], 1.0);
        assert!((texels[0] - 1.0 / 65535.0 / 12.92).abs() < 1e-9);
        let srgb = 3001.0f64 / 65535.0;
        let expected = ((srgb + 0.055) / 1.055).powf(2.4);
        assert!((f64::from(texels[12]) - expected).abs() < 1e-7, "{}", texels[12]);
        assert!((texels[3] - 32768.0 / 65535.0).abs() < 1e-7);
    }

    #[test]
    fn jpeg_is_decoded_as_8_bit() {
        let dir = TempDir::new();
        let path = dir.0.join("photo.JPG");
        let image: ImageBuffer<Rgb<u8>, Vec<u8>> = ImageBuffer::from_pixel(16, 8, Rgb([200, 100, 50]));
        image.save_with_format(&path, ImageFormat::Jpeg).unwrap();
        let texture = load_texture(&path, TextureRole::BaseColor).unwrap();
        assert_eq!(
            (texture.width, texture.height, texture.format),
            (16, 8, TexelFormat::Rgba8Srgb)
        );
        for texel in texture.pixels.chunks_exact(4) {
            let expected = [200, 100, 50, 255];
            assert!(
                texel.iter().zip(expected).all(|(&a, b)| a.abs_diff(b) <= 3),
                "{texel:?}"
            );
        }
    }

    #[test]
    fn hdr_and_exr_are_linear_float() {
        let dir = TempDir::new();
        let hdr = dir.0.join("sky.hdr");
        let rgb: ImageBuffer<Rgb<f32>, Vec<f32>> =
            ImageBuffer::from_fn(3, 2, |x, y| Rgb([x as f32 + 0.5, y as f32 * 4.0, 0.25]));
        rgb.save(&hdr).unwrap();
        let texture = load_texture(&hdr, TextureRole::BaseColor).unwrap();
        assert_eq!(
            (texture.width, texture.height, texture.format),
            (3, 2, TexelFormat::Rgba32Float)
        );
        let texels: Vec<f32> = bytemuck::pod_collect_to_vec(&texture.pixels);
        // RGBE keeps 8 bits of mantissa.
        for (texel, source) in texels.chunks_exact(4).zip(flip_vertical(&rgb).pixels()) {
            for (a, b) in texel.iter().zip(source.0) {
                assert!((a - b).abs() <= b * 0.01, "{texel:?} {source:?}");
            }
            assert_eq!(texel[3], 1.0);
        }

        let exr = dir.0.join("noise.exr");
        let rgba: ImageBuffer<Rgba<f32>, Vec<f32>> =
            ImageBuffer::from_fn(4, 4, |x, y| Rgba([x as f32, y as f32, 1e4, 0.5]));
        rgba.save(&exr).unwrap();
        let texture = load_texture(&exr, TextureRole::Data).unwrap();
        assert_eq!(texture.format, TexelFormat::Rgba32Float);
        let texels: Vec<f32> = bytemuck::pod_collect_to_vec(&texture.pixels);
        assert_eq!(texels, *flip_vertical(&rgba).as_raw());
        assert_eq!(
            message(&exr, TextureRole::Normal),
            "a OpenEXR image cannot be a normal map (normal maps are 8- or 16-bit PNG or JPEG)"
        );
    }

    #[test]
    fn float_images_must_be_finite_and_non_negative() {
        let dir = TempDir::new();
        for (value, shown) in [(f32::NAN, "NaN"), (f32::INFINITY, "inf"), (-1.0, "-1")] {
            let path = dir.0.join("bad.exr");
            let mut image: ImageBuffer<Rgba<f32>, Vec<f32>> = ImageBuffer::from_pixel(3, 3, Rgba([0.5; 4]));
            image.put_pixel(2, 1, Rgba([0.5, 0.5, value, 1.0]));
            image.save(&path).unwrap();
            assert_eq!(
                message(&path, TextureRole::BaseColor),
                format!("texel (2, 1) has channel B = {shown}; every value must be finite and >= 0")
            );
        }
    }

    #[test]
    fn missing_and_unsupported_files_are_named() {
        let dir = TempDir::new();
        let missing = dir.0.join("missing.png");
        assert!(message(&missing, TextureRole::BaseColor).starts_with("cannot read: "));
        let tga = dir.0.join("old.tga");
        std::fs::write(&tga, [0u8; 32]).unwrap();
        assert_eq!(
            message(&tga, TextureRole::BaseColor),
            "unsupported texture file extension \"tga\"; expected .png, .jpg, .jpeg, .hdr or .exr"
        );
        let text = dir.0.join("notes.png");
        std::fs::write(&text, "this is not an image").unwrap();
        assert_eq!(
            message(&text, TextureRole::BaseColor),
            "not an image: the data is not PNG, JPEG, Radiance HDR or OpenEXR"
        );
        let gif = dir.0.join("anim.png");
        std::fs::write(&gif, b"GIF89a\x01\x00\x01\x00\x00\x00\x00;").unwrap();
        assert_eq!(
            message(&gif, TextureRole::BaseColor),
            "is a Gif image; textures must be PNG, JPEG, Radiance HDR or OpenEXR"
        );
        let empty = dir.0.join("empty.jpg");
        std::fs::write(&empty, "").unwrap();
        assert!(message(&empty, TextureRole::Data).starts_with("not an image"));
    }

    #[test]
    fn huge_and_empty_headers_are_rejected_before_decoding() {
        let dir = TempDir::new();
        let hdr = |name: &str, width: u32, height: u32| {
            let path = dir.0.join(name);
            let header = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n");
            std::fs::write(&path, header).unwrap();
            path
        };
        assert_eq!(
            message(&hdr("wide.hdr", 100_000, 100_000), TextureRole::BaseColor),
            "the image is too large (100000 × 100000); each side must be at most 16384"
        );
        assert_eq!(
            message(&hdr("big.hdr", 16384, 16384), TextureRole::BaseColor),
            "the image is too large (16384 × 16384 Rgba32Float is 4096 MiB); at most 1024 MiB"
        );
        let png = dir.0.join("huge.png");
        std::fs::write(&png, png_header(16384, 16384, 16)).unwrap();
        assert_eq!(
            message(&png, TextureRole::Normal),
            "the image is too large (16384 × 16384 Rgba16Unorm is 2048 MiB); at most 1024 MiB"
        );
        let png = dir.0.join("65536.png");
        std::fs::write(&png, png_header(65536, 65536, 8)).unwrap();
        assert_eq!(
            message(&png, TextureRole::BaseColor),
            "the image is too large (65536 × 65536); each side must be at most 16384"
        );
        let png = dir.0.join("tall.png");
        std::fs::write(&png, png_header(1, 16385, 8)).unwrap();
        assert_eq!(
            message(&png, TextureRole::Normal),
            "the image is too large (1 × 16385); each side must be at most 16384"
        );
        let zero = dir.0.join("zero.png");
        std::fs::write(&zero, png_header(0, 7, 8)).unwrap();
        assert_eq!(
            message(&hdr("empty.hdr", 0, 4), TextureRole::BaseColor),
            "the image is empty (0 × 4)"
        );
        // The PNG decoder refuses zero sizes itself.
        assert_eq!(
            message(&zero, TextureRole::BaseColor),
            "corrupt or truncated PNG data: Format error decoding Png: Invalid image dimensions"
        );
    }

    /// A PNG signature, an RGBA IHDR chunk and an empty IDAT chunk: a
    /// header that promises an image without its data.
    fn png_header(width: u32, height: u32, bit_depth: u8) -> Vec<u8> {
        let mut ihdr = b"IHDR".to_vec();
        ihdr.extend(width.to_be_bytes());
        ihdr.extend(height.to_be_bytes());
        ihdr.extend([bit_depth, 6, 0, 0, 0]);
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        for chunk in [ihdr, b"IDAT".to_vec()] {
            png.extend((chunk.len() as u32 - 4).to_be_bytes());
            png.extend(&chunk);
            png.extend(crc32fast::hash(&chunk).to_be_bytes());
        }
        png
    }

    /// Truncations and corruptions of valid files of every format, and
    /// random bytes: each is an error naming the file or a valid texture,
    /// never a panic.
    #[test]
    fn broken_files_never_panic() {
        let dir = TempDir::new();
        let mut originals = Vec::new();
        for (name, format) in [
            ("a.png", ImageFormat::Png),
            ("a.jpg", ImageFormat::Jpeg),
            ("a.hdr", ImageFormat::Hdr),
            ("a.exr", ImageFormat::OpenExr),
        ] {
            let path = dir.0.join(name);
            let image = DynamicImage::ImageRgba8(rgba8(13, 9));
            let image = match format {
                ImageFormat::Jpeg => DynamicImage::ImageRgb8(image.to_rgb8()),
                ImageFormat::Hdr => DynamicImage::ImageRgb32F(image.to_rgb32f()),
                ImageFormat::OpenExr => DynamicImage::ImageRgba32F(image.to_rgba32f()),
                _ => image,
            };
            image.save_with_format(&path, format).unwrap();
            originals.push((name, std::fs::read(&path).unwrap()));
        }
        let png16 = dir.0.join("b.png");
        DynamicImage::ImageRgba8(rgba8(7, 5))
            .into_rgba16()
            .save(&png16)
            .unwrap();
        originals.push(("b.png", std::fs::read(&png16).unwrap()));

        // A fixed xorshift sequence, so failures reproduce.
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut broken = 0;
        for (name, bytes) in &originals {
            let path = dir.0.join(format!("broken-{name}"));
            // Every length through the headers, then a sample.
            let mut variants: Vec<Vec<u8>> = (0..bytes.len())
                .filter(|&n| n < 128 || n % 17 == 0)
                .map(|n| bytes[..n].to_vec())
                .collect();
            for _ in 0..200 {
                let mut corrupt = bytes.clone();
                for _ in 0..1 + next() % 4 {
                    let at = (next() % corrupt.len() as u64) as usize;
                    corrupt[at] = next() as u8;
                }
                variants.push(corrupt);
            }
            for length in [1, 16, 100, 4000] {
                variants.push((0..length).map(|_| next() as u8).collect());
            }
            let roles = [TextureRole::BaseColor, TextureRole::Normal, TextureRole::Data];
            for (variant, role) in variants.iter().zip(roles.iter().cycle()) {
                std::fs::write(&path, variant).unwrap();
                match load_texture(&path, *role) {
                    Ok(texture) => assert_eq!(
                        texture.pixels.len(),
                        (texture.width * texture.height) as usize * texture.format.bytes_per_texel()
                    ),
                    Err(error) => {
                        let message = error.to_string();
                        assert!(message.starts_with(&format!("{}: ", path.display())), "{message}");
                        broken += 1;
                    }
                }
            }
        }
        assert!(broken > 500, "{broken}");
    }
}
