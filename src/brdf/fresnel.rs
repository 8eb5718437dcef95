//! Fresnel reflectance.

use super::Vec3;

/// Schlick 1994, seed eq. 9: F0 + (1 − F0)(1 − v·h)⁵, with F0 and v·h clamped to [0, 1].
pub fn f_schlick_scalar(f0: f64, v_dot_h: f64) -> f64 {
    let x = 1.0 - v_dot_h.clamp(0.0, 1.0);
    let x2 = x * x;
    let f0 = f0.clamp(0.0, 1.0);
    f0 + (1.0 - f0) * (x2 * x2 * x)
}

/// Schlick 1994, seed eq. 9, per channel.
pub fn f_schlick(f0: Vec3, v_dot_h: f64) -> Vec3 {
    f0.map(|c| f_schlick_scalar(c, v_dot_h))
}
