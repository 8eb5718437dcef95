//! Normal mapping in f64: twins of `shaders/lib/normal_mapping.glsl`.

use super::{cross, dot, Vec3};

/// A tangent-space normal's z is kept at least this large (`MIN_TANGENT_Z` in GLSL).
pub const MIN_TANGENT_Z: f64 = 1e-3;
/// sin² of a tangent's angle to the normal below which it is degenerate
/// (`MIN_TANGENT_SIN2` in GLSL: there fp32 loses its direction).
pub const MIN_TANGENT_SIN2: f64 = 1e-4;

fn normalize(a: Vec3) -> Vec3 {
    let inv = 1.0 / dot(a, a).sqrt();
    [a[0] * inv, a[1] * inv, a[2] * inv]
}

/// A tangent-space unit normal from an RGB texel in [0, 1] (OpenGL convention; `green_down`
/// flips y for DirectX maps), its slope scaled by `strength`.
pub fn decode_normal(texel: Vec3, green_down: bool, strength: f64) -> Vec3 {
    let mut n = texel.map(|c| c * 2.0 - 1.0);
    if green_down {
        n[1] = -n[1];
    }
    n[0] *= strength;
    n[1] *= strength;
    n[2] = n[2].max(MIN_TANGENT_Z);
    normalize(n)
}

/// Reoriented Normal Mapping (Barré-Brisebois & Hill 2012): t·(t·u)/t.z − u,
/// t = base + (0, 0, 1), its z written as base·u as in GLSL.
pub fn blend_rnm(base: Vec3, detail: Vec3) -> Vec3 {
    let u = [-detail[0], -detail[1], detail[2]];
    let z = dot(base, u);
    let k = (z + u[2]) / (base[2] + 1.0);
    normalize([base[0] * k + detail[0], base[1] * k + detail[1], z])
}

/// UDN blending (Barré-Brisebois & Hill 2012).
pub fn blend_udn(base: Vec3, detail: Vec3) -> Vec3 {
    normalize([base[0] + detail[0], base[1] + detail[1], base[2]])
}

/// Whiteout blending (Barré-Brisebois & Hill 2012).
pub fn blend_whiteout(base: Vec3, detail: Vec3) -> Vec3 {
    normalize([base[0] + detail[0], base[1] + detail[1], base[2] * detail[2]])
}

/// The report's eq. 16, n = (v1 + v2)·(1, 1, 0.5), on decoded normals, normalised.
pub fn blend_seed(base: Vec3, detail: Vec3) -> Vec3 {
    normalize([base[0] + detail[0], base[1] + detail[1], 0.5 * (base[2] + detail[2])])
}

/// A tangent-space normal in world space through the TBN frame (seed eqs. 13–15), T
/// re-orthogonalised against N, B = w·(N × T); a degenerate T (within `MIN_TANGENT_SIN2`
/// of N) leaves N.
pub fn tangent_to_world(n_tangent_space: Vec3, normal: Vec3, tangent: [f64; 4]) -> Vec3 {
    let tangent_xyz = [tangent[0], tangent[1], tangent[2]];
    let t_dot_n = dot(normal, tangent_xyz);
    let t = [
        tangent[0] - normal[0] * t_dot_n,
        tangent[1] - normal[1] * t_dot_n,
        tangent[2] - normal[2] * t_dot_n,
    ];
    let t2 = dot(t, t);
    if t2 <= MIN_TANGENT_SIN2 * dot(tangent_xyz, tangent_xyz) {
        return normal;
    }
    let t = normalize(t);
    let sign = if tangent[3] < 0.0 { -1.0 } else { 1.0 };
    let b = cross(normal, t).map(|c| c * sign);
    let [x, y, z] = n_tangent_space;
    normalize([
        t[0] * x + b[0] * y + normal[0] * z,
        t[1] * x + b[1] * y + normal[1] * z,
        t[2] * x + b[2] * y + normal[2] * z,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLAT: Vec3 = [0.0, 0.0, 1.0];

    #[test]
    fn a_flat_detail_leaves_the_base_unchanged_in_every_blend() {
        let base = decode_normal([0.7, 0.4, 0.9], false, 1.0);
        for blend in [blend_rnm, blend_udn, blend_whiteout] {
            let r = blend(base, FLAT);
            for c in 0..3 {
                assert!((r[c] - base[c]).abs() < 1e-12, "{r:?} vs {base:?}");
            }
        }
        // RNM is symmetric in this sense too: a flat base gives the detail.
        let detail = decode_normal([0.3, 0.6, 0.8], false, 1.0);
        let r = blend_rnm(FLAT, detail);
        for c in 0..3 {
            assert!((r[c] - detail[c]).abs() < 1e-12);
        }
    }

    #[test]
    fn rnm_rotates_the_detail_by_the_base() {
        // Base tilted 45° about y; a detail tilted 45° the same way adds up to 90°.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let r = blend_rnm([s, 0.0, s], [s, 0.0, s]);
        assert!((r[0] - 1.0).abs() < 1e-12 && r[2].abs() < 1e-12, "{r:?}");
    }

    #[test]
    fn decoding_honours_green_convention_and_strength() {
        let up = decode_normal([0.5, 0.75, 0.9], false, 1.0);
        let down = decode_normal([0.5, 0.75, 0.9], true, 1.0);
        assert!(up[1] > 0.0 && down[1] < 0.0 && (up[1] + down[1]).abs() < 1e-12);
        assert_eq!(decode_normal([0.9, 0.1, 0.5], false, 0.0), FLAT);
        // A texel below the surface still decodes above it.
        assert!(decode_normal([0.5, 0.5, 0.0], false, 1.0)[2] > 0.0);
    }

    #[test]
    fn rnm_is_the_rotation_that_takes_z_to_the_base() {
        let base = decode_normal([0.9, 0.2, 0.6], false, 2.0);
        let detail = decode_normal([0.3, 0.7, 0.8], false, 1.5);
        let [x, y, z] = base;
        let k = 1.0 / (1.0 + z);
        let rotation = [
            [1.0 - x * x * k, -x * y * k, x],
            [-x * y * k, 1.0 - y * y * k, y],
            [-x, -y, z],
        ];
        let r = blend_rnm(base, detail);
        for c in 0..3 {
            assert!((r[c] - dot(rotation[c], detail)).abs() < 1e-12, "{r:?}");
        }
    }

    #[test]
    fn a_tangent_is_degenerate_by_its_angle_to_the_normal_not_its_length() {
        let n = [0.0, 0.0, 1.0];
        let short = tangent_to_world([1.0, 0.0, 0.0], n, [1e-8, 0.0, 0.0, 1.0]);
        assert!((short[0] - 1.0).abs() < 1e-12, "{short:?}");
        let sin = 0.5 * MIN_TANGENT_SIN2.sqrt();
        let steep = [sin, 0.0, (1.0 - sin * sin).sqrt()];
        for length in [1e-3, 1.0, 1e3] {
            let [x, y, z] = steep.map(|c| c * length);
            assert_eq!(tangent_to_world([1.0, 0.0, 0.0], n, [x, y, z, 1.0]), n);
        }
    }

    #[test]
    fn tbn_follows_handedness() {
        let n = [0.0, 0.0, 1.0];
        let plus_v = tangent_to_world([0.0, 1.0, 0.0], n, [1.0, 0.0, 0.0, 1.0]);
        let mirrored = tangent_to_world([0.0, 1.0, 0.0], n, [1.0, 0.0, 0.0, -1.0]);
        assert!((plus_v[1] - 1.0).abs() < 1e-12 && (mirrored[1] + 1.0).abs() < 1e-12);
        // A tangent along the normal is degenerate: the normal is kept.
        assert_eq!(tangent_to_world([0.6, 0.0, 0.8], n, [0.0, 0.0, 1.0, 1.0]), n);
    }
}
