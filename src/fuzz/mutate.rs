//! Mutations of a seed: byte-level ones (bit flips, boundary values, deleted, repeated and
//! spliced ranges) and the tokens of each format (TOML keys and extreme numbers, OBJ
//! statements and indices, image sizes as 32-bit integers). A mutated PNG gets its chunk
//! CRCs recomputed, or the decoder would stop at the first chunk and nothing behind the
//! checksum would be reached.

use super::Target;
use crate::rng::Rng;

/// Numbers that break parsers and size checks: zero, one, the edges of signed and unsigned
/// integers, and 65536 (a side refused from the header).
const EDGE_U32: [u32; 9] = [
    0,
    1,
    0x7f,
    0xff,
    0xffff,
    0x1_0000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
];

const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "nan",
    "inf",
    "-inf",
    "1e39",
    "-1e39",
    "1e-45",
    "3.4e38",
    "4294967296",
    "9223372036854775807",
    "65536",
    "16385",
    "0.5",
    "1e9",
];

const SCENE_TOKENS: &[&str] = &[
    "[camera]\n",
    "[[lights]]\n",
    "[[objects]]\n",
    "[environment]\n",
    "[materials.m]\n",
    "[materials.m.normal_map]\n",
    "[materials.m.color_map]\n",
    "[materials.m.roughness_map]\n",
    "kind = \"point\"\n",
    "kind = \"map\"\n",
    "kind = \"studio\"\n",
    "kind = \"uniform\"\n",
    "mesh = \"mesh.obj\"\n",
    "mesh = \"builtin:sphere\"\n",
    "mesh = \"builtin:torus\"\n",
    "mesh = \"missing.obj\"\n",
    "material = \"m\"\n",
    "preset = \"plasticine\"\n",
    "texture = \"color.png\"\n",
    "texture = \"color.jpg\"\n",
    "texture = \"sky.hdr\"\n",
    "texture = \"builtin:noise\"\n",
    "path = \"sky.hdr\"\n",
    "path = \"sky.exr\"\n",
    "roughness = ",
    "base_color = ",
    "position = ",
    "target = ",
    "scale = ",
    "intensity = ",
    "fov_y_degrees = ",
    "uv_scale = ",
    "uv_rotation_degrees = ",
    "strength = ",
    "samples = ",
    "scatter_radius = ",
    "radiance = ",
    "rotation_degrees = ",
    "[0.0, 0.0, 0.0]",
    "[1, 2]",
    "[]",
    "\"\"",
    "=",
    "\n",
    "#",
    "'",
    "\"",
    "[",
    "]",
    "{",
    "}",
    ",",
    ".",
    "\\u0000",
];

const OBJ_TOKENS: &[&str] = &[
    "v ",
    "vt ",
    "vn ",
    "f ",
    "o x\n",
    "g x\n",
    "s 1\n",
    "l 1 2\n",
    "p 1\n",
    "mtllib x.mtl\n",
    "usemtl x\n",
    "/",
    "//",
    " ",
    "\n",
    "\\\n",
    "#",
    "-1",
    "-4",
    "0",
    "99999999",
    "f 1 2 3\n",
    "f 1/1/1 2/2/2 3/3/3\n",
    "f 1 2 3 4 5 6 7 8\n",
    "v 0 0 0\n",
    "v nan 0 0\n",
    "vt 0 0\n",
    "vn 0 0 0\n",
];

const HDR_TOKENS: &[&str] = &[
    "#?RADIANCE\n",
    "FORMAT=32-bit_rle_rgbe\n",
    "FORMAT=32-bit_rle_xyze\n",
    "EXPOSURE=0\n",
    "\n",
    "-Y ",
    " +X ",
    "+Y ",
    " -X ",
    "65536",
    "8",
    "16",
];

const EXR_TOKENS: &[&str] = &[
    "channels\0",
    "chlist\0",
    "compression\0",
    "dataWindow\0",
    "box2i\0",
    "displayWindow\0",
    "lineOrder\0",
    "pixelAspectRatio\0",
    "screenWindowCenter\0",
    "screenWindowWidth\0",
    "tiles\0",
    "tiledesc\0",
    "R\0",
    "G\0",
    "B\0",
    "A\0",
    "Y\0",
    "\0",
];

/// Mutates seeds; the random stream is fixed by the seed given, so a run can be repeated.
pub struct Mutator {
    rng: Rng,
}

impl Mutator {
    pub fn new(seed: u64) -> Self {
        Self { rng: Rng::new(seed) }
    }

    /// A number in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.rng.next_u64() % n as u64) as usize
    }

    /// One to eight mutations of `input`, half the time one; `other` is a second corpus entry to splice from.
    pub fn mutate(&mut self, target: Target, input: &[u8], other: &[u8]) -> Vec<u8> {
        let mut out = input.to_vec();
        // Mostly one or two: every extra mutation of a text format is another chance to
        // break its syntax before the interesting check.
        let count = if self.below(2) == 0 { 1 } else { 2 + self.below(7) };
        for _ in 0..count {
            self.mutate_once(target, &mut out, other);
        }
        if target == Target::Png {
            fix_png_crcs(&mut out);
        }
        out
    }

    fn mutate_once(&mut self, target: Target, out: &mut Vec<u8>, other: &[u8]) {
        let len = out.len();
        match self.below(10) {
            0 if len > 0 => {
                let at = self.below(len);
                out[at] ^= 1 << self.below(8);
            }
            1 if len > 0 => {
                let at = self.below(len);
                out[at] = [0u8, 1, 0x7f, 0x80, 0xff, b'0', b'9', b'\n'][self.below(8)];
            }
            2 if len > 0 => {
                let at = self.below(len);
                let n = (1 + self.below(16)).min(len - at);
                out.drain(at..at + n);
            }
            3 if len > 0 => {
                // A range repeated elsewhere: duplicated statements, chunks and scanlines.
                let from = self.below(len);
                let n = (1 + self.below(64)).min(len - from);
                let chunk = out[from..from + n].to_vec();
                let at = self.below(len + 1);
                out.splice(at..at, chunk);
            }
            4 if len >= 4 => {
                let at = self.below(len - 3);
                let value = EDGE_U32[self.below(EDGE_U32.len())];
                let bytes = if self.below(2) == 0 {
                    value.to_be_bytes()
                } else {
                    value.to_le_bytes()
                };
                out[at..at + 4].copy_from_slice(&bytes);
            }
            5 if !other.is_empty() => {
                let cut = self.below(len + 1);
                let from = self.below(other.len());
                out.truncate(cut);
                out.extend_from_slice(&other[from..]);
            }
            6 if len > 0 => {
                out.truncate(self.below(len));
            }
            7 | 8 => {
                let token = self.token(target);
                let at = self.insertion_point(target, out);
                out.splice(at..at, token.bytes());
            }
            _ => {
                // A number replaced by an extreme one (text formats), or a random byte run.
                let token = NUMBERS[self.below(NUMBERS.len())];
                if let Some((start, end)) = self.number_span(out) {
                    out.splice(start..end, token.bytes());
                } else {
                    let at = self.below(len + 1);
                    out.splice(at..at, token.bytes());
                }
            }
        }
    }

    fn token(&mut self, target: Target) -> &'static str {
        let tokens = match target {
            Target::Scene => SCENE_TOKENS,
            Target::Obj => OBJ_TOKENS,
            Target::Hdr => HDR_TOKENS,
            Target::Exr => EXR_TOKENS,
            Target::Png | Target::Jpeg => NUMBERS,
        };
        if self.below(4) == 0 {
            NUMBERS[self.below(NUMBERS.len())]
        } else {
            tokens[self.below(tokens.len())]
        }
    }

    /// In text formats, tokens mostly go at the start of a line.
    fn insertion_point(&mut self, target: Target, out: &[u8]) -> usize {
        let at = self.below(out.len() + 1);
        if matches!(target, Target::Scene | Target::Obj) && self.below(2) == 0 {
            out[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)
        } else {
            at
        }
    }

    /// A run of digits (with sign, point and exponent) somewhere in `out`.
    fn number_span(&mut self, out: &[u8]) -> Option<(usize, usize)> {
        if out.is_empty() {
            return None;
        }
        let numeric = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e');
        let from = self.below(out.len());
        let start = from + out[from..].iter().position(|&b| b.is_ascii_digit())?;
        let start = out[..start].iter().rposition(|&b| !numeric(b)).map_or(0, |i| i + 1);
        let end = start
            + out[start..]
                .iter()
                .position(|&b| !numeric(b))
                .unwrap_or(out.len() - start);
        Some((start, end))
    }
}

/// Recomputes the CRC of every whole chunk after the PNG signature.
fn fix_png_crcs(png: &mut [u8]) {
    let mut at = 8;
    while at + 12 <= png.len() {
        let length = u32::from_be_bytes([png[at], png[at + 1], png[at + 2], png[at + 3]]) as usize;
        let Some(end) = (at + 8).checked_add(length).filter(|&end| end + 4 <= png.len()) else {
            return;
        };
        let crc = crc32fast::hash(&png[at + 4..end]);
        png[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_crcs_are_recomputed() {
        // IHDR of a 1×1 grey image, its CRC zeroed; the correct one is 0x3a7e9b55.
        let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x01\0\0\0\x01\x08\x00\0\0\0\0\0\0\0".to_vec();
        fix_png_crcs(&mut png);
        assert_eq!(&png[29..33], &0x3a7e_9b55u32.to_be_bytes());
    }

    #[test]
    fn mutations_are_repeatable_and_change_the_input() {
        let seed = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let run = |s| {
            let mut m = Mutator::new(s);
            (0..100)
                .map(|_| m.mutate(Target::Obj, seed, b"f 1 2 3\n"))
                .collect::<Vec<_>>()
        };
        let a = run(7);
        assert_eq!(a, run(7));
        assert!(a.iter().filter(|m| m.as_slice() != seed).count() > 90);
    }
}
