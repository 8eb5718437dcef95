//! How large an input argil accepts, checked before the input is parsed or decoded, so
//! that an absurd file is refused with a message instead of exhausting memory. Images are
//! limited from their headers: textures in `texture.rs`, environment maps by
//! [`check_environment_map`], and OpenEXR files by [`check_exr_headers`] too.

use std::path::Path;

use exr::meta::BlockDescription;

use super::{SceneError, MAX_TEXTURE_BYTES, MAX_TEXTURE_SIDE};

/// Scene files: a scene of [`MAX_OBJECTS`] objects, each a few lines, is about 1 MiB.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;
/// Objects, each a draw call per frame.
pub const MAX_OBJECTS: usize = 10_000;
/// Point lights: the shader's fixed array (`MAX_POINT_LIGHTS` in scene_data.glsl).
pub const MAX_LIGHTS: usize = crate::render::gpu_scene::MAX_POINT_LIGHTS;
/// Spheres of `[occlusion] objects` the forward pass reads (`MAX_OCCLUDERS` in
/// shaders/lib/scene_data.glsl, 2 KiB of its uniforms); a scene with more keeps the largest.
pub const MAX_OCCLUDERS: usize = 64;
/// Triangles of one OBJ file (counted from its `f` lines before tobj parses it) or glTF
/// model (from its accessors' counts): a 391 MB OBJ of 9,999,392 triangles (a 2237² grid)
/// peaks at 2.1 GB of host memory in `argil render` (the text, tobj's arrays, then argil's
/// vertices with tangents and curvature).
pub const MAX_MESH_TRIANGLES: u64 = 10_000_000;
/// `subdivisions` of a `builtin:sphere` object, cells along each edge of its cube: 512 makes
/// 6 × 2 × 512² = 3.1 M triangles (82 MB of vertices), far finer than any frame resolves.
pub const SPHERE_SUBDIVISIONS_RANGE: std::ops::RangeInclusive<u32> = 1..=512;
/// `subdivisions` of a `builtin:torus` object, cells around its ring (3/8 as many around its
/// tube): 2048 makes 2 × 2048 × 768 = 3.1 M triangles, as the sphere's largest does.
pub const TORUS_SUBDIVISIONS_RANGE: std::ops::RangeInclusive<u32> = 3..=2048;
/// OBJ files, read whole before parsing: 10⁷ triangles and their vertices in text.
pub const MAX_OBJ_BYTES: u64 = 1 << 30;
/// glTF models (.gltf, .glb) and each of their buffer files, read whole: 10⁷ indexed
/// triangles with positions, normals, UVs and tangents are about 600 MB of binary.
pub const MAX_GLTF_BYTES: u64 = 1 << 30;

/// Refuses `path` when it is larger than `limit` bytes, before it is read.
pub fn check_file_size(path: &Path, limit: u64, what: &str) -> Result<(), SceneError> {
    let size = std::fs::metadata(path)
        .map_err(|error| SceneError::Io {
            path: path.to_path_buf(),
            error,
        })?
        .len();
    if size > limit {
        return Err(SceneError::TooLarge {
            path: path.to_path_buf(),
            problem: format!("the file is {size} bytes; {what} are at most {limit} bytes"),
        });
    }
    Ok(())
}

/// The triangles the `f` lines of an OBJ text make once fanned: a face of n corners makes
/// n − 2. Continuation lines (a `\` at the end) are not followed, so a face split over
/// lines counts as its first line's corners; tobj still parses it whole.
pub fn obj_triangles(text: &[u8]) -> u64 {
    text.split(|&b| b == b'\n')
        .filter_map(|line| line.trim_ascii_start().strip_prefix(b"f"))
        .filter(|rest| rest.first().is_some_and(u8::is_ascii_whitespace))
        .map(|rest| {
            let corners = rest.split(u8::is_ascii_whitespace).filter(|t| !t.is_empty()).count() as u64;
            corners.saturating_sub(2)
        })
        .sum()
}

/// The widest environment map accepted: 8K, whose RGB f32 decode (384 MiB) stays within
/// `image`'s default allocation limit.
pub const MAX_ENVIRONMENT_WIDTH: u32 = 8192;
/// The narrowest environment map accepted.
pub const MIN_ENVIRONMENT_WIDTH: u32 = 8;

/// The width and height of the equirectangular environment map at `path`, from its
/// headers: a Radiance HDR or OpenEXR image (by content, whatever the extension says),
/// twice as wide as tall, [`MIN_ENVIRONMENT_WIDTH`] to [`MAX_ENVIRONMENT_WIDTH`] wide. A
/// scene checks its map with it when it loads; the renderer again before it decodes one.
pub fn check_environment_map(path: &Path) -> Result<(u32, u32), String> {
    let reader = || {
        image::ImageReader::open(path)
            .map_err(|e| format!("cannot open: {e}"))?
            .with_guessed_format()
            .map_err(|e| format!("cannot read: {e}"))
    };
    match reader()?.format() {
        Some(image::ImageFormat::OpenExr) => check_exr_headers(path)?,
        Some(image::ImageFormat::Hdr) => {}
        Some(other) => return Err(format!("is a {other:?} image, not a Radiance HDR or OpenEXR one")),
        None => return Err("is not a Radiance HDR or OpenEXR image".to_owned()),
    }
    let (width, height) = reader()?
        .into_dimensions()
        .map_err(|e| format!("cannot read it as a Radiance HDR or OpenEXR image: {e}"))?;
    if !(MIN_ENVIRONMENT_WIDTH..=MAX_ENVIRONMENT_WIDTH).contains(&width) {
        return Err(format!(
            "is {width}x{height}; an environment map must be {MIN_ENVIRONMENT_WIDTH} to {MAX_ENVIRONMENT_WIDTH} \
             texels wide"
        ));
    }
    if width != 2 * height {
        return Err(format!("is {width}x{height}; an equirectangular map is twice as wide as tall"));
    }
    Ok((width, height))
}

/// Refuses an OpenEXR file whose headers describe more than a texture may hold, before it
/// is decoded: `image` checks the display window, but decodes the data window and each
/// block at the sizes the headers give, which a broken file sets to anything (one with a
/// data window 2²⁹ wide and 8 high made the decoder ask for 25 GB).
pub fn check_exr_headers(path: &Path) -> Result<(), String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    check_exr_headers_in(std::io::BufReader::new(file))
}

/// [`check_exr_headers`] of the OpenEXR data `read` holds.
pub fn check_exr_headers_in(read: impl std::io::Read) -> Result<(), String> {
    let meta =
        exr::meta::MetaData::read_from_buffered(read, false).map_err(|e| format!("not a valid OpenEXR file: {e}"))?;
    let max_side = MAX_TEXTURE_SIDE as usize;
    for header in &meta.headers {
        if header.deep {
            return Err("deep OpenEXR data is not supported".to_owned());
        }
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        let block = match header.blocks {
            BlockDescription::Tiles(tiles) => (tiles.tile_size.width(), tiles.tile_size.height()),
            BlockDescription::ScanLines => (width, header.compression.scan_lines_per_block()),
        };
        if width > max_side || height > max_side || block.0 > max_side || block.1 > max_side {
            return Err(format!(
                "the image is too large (data window {width} × {height}, blocks of {} × {}); each side must be at most {MAX_TEXTURE_SIDE}",
                block.0, block.1
            ));
        }
        let pixel = header.channels.bytes_per_pixel as u64;
        let bytes = (width as u64 * height as u64).max(block.0 as u64 * block.1 as u64) * pixel;
        if bytes > MAX_TEXTURE_BYTES {
            return Err(format!(
                "the image is too large ({width} × {height} of {} channels is {} MiB); at most {} MiB",
                header.channels.list.len(),
                bytes >> 20,
                MAX_TEXTURE_BYTES >> 20
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_the_triangles_of_fans() {
        let text = b"v 0 0 0\nf 1 2 3\n  f 1/1 2/2 3/3 4/4\nfoo 1 2 3\nf\tx y z w v\n# f 1 2 3\nf 1 2\n";
        assert_eq!(obj_triangles(text), 1 + 2 + 3);
    }
}
