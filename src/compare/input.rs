//! Reading the compared images: OpenEXR only, RGB(A) of the first layer that has RGB, and the
//! `argil.*` header attributes that say how a reference was made.

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use exr::meta::attribute::AttributeValue;
use exr::prelude::{ReadChannels, ReadLayers};

use super::metrics::Rgba32;
use crate::error::InputError;

/// The first four bytes of every OpenEXR file.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// Header attributes argil writes about itself (`argil.spp`, `argil.seed`, …) begin so.
const ATTRIBUTE_PREFIX: &str = "argil.";

/// An EXR's pixels and its `argil.*` attributes that are strings or numbers.
pub struct ExrImage {
    pub image: Rgba32,
    pub attributes: BTreeMap<String, serde_json::Value>,
}

/// Reads `path`. Alpha is 1 where the file has none. Every failure is an [`InputError`]
/// naming the file.
pub fn read_exr(path: &Path) -> Result<ExrImage, InputError> {
    let bytes = std::fs::read(path).map_err(|e| InputError::file(path, format_args!("cannot read: {e}")))?;
    if !bytes.starts_with(&EXR_MAGIC) {
        let problem = match image::guess_format(&bytes) {
            Ok(format) => format!(
                "a {} image, not an OpenEXR file",
                format.extensions_str()[0].to_ascii_uppercase()
            ),
            Err(_) => "not an OpenEXR file".to_owned(),
        };
        return Err(InputError::file(path, problem));
    }
    let exr = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size, _| (size.width(), vec![[0.0f32; 4]; size.area()]),
            |(width, pixels), at, (r, g, b, a): (f32, f32, f32, f32)| pixels[at.y() * *width + at.x()] = [r, g, b, a],
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| InputError::file(path, format_args!("unreadable OpenEXR file: {e}")))?;
    let layer = exr.layer_data;
    let attributes = exr
        .attributes
        .other
        .iter()
        .chain(&layer.attributes.other)
        .filter_map(|(name, value)| {
            let name = name.to_string();
            let value = match value {
                AttributeValue::Text(text) => serde_json::Value::from(text.to_string()),
                AttributeValue::I32(n) => serde_json::Value::from(*n),
                AttributeValue::F32(x) => serde_json::Value::from(*x),
                AttributeValue::F64(x) => serde_json::Value::from(*x),
                _ => return None,
            };
            name.starts_with(ATTRIBUTE_PREFIX).then_some((name, value))
        })
        .collect();
    Ok(ExrImage {
        image: Rgba32 {
            width: layer.size.width(),
            height: layer.size.height(),
            pixels: layer.channel_data.pixels.1,
        },
        attributes,
    })
}
