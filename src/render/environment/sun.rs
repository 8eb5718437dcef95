//! A map's sun: a small source far brighter than the rest of the map, which split-sum
//! reflection lights with as a directional light of its own rather than through the
//! prefiltered cube. A prefiltered lobe is the lobe seen head-on (n = v = r) with the
//! lobe's mean Fresnel, so under a source 10³ times the sky it misplaces the highlight and
//! dims its tail, where Fresnel grows: on the bench's `sphere-sky`, 6% of the specular
//! light half-way to the limb. The map without its sun has nothing so bright left.

use super::equirect::Equirect;
use crate::brdf::environment::equirect_direction;
use crate::brdf::Vec3;

/// A map's brightest texel starts a sun when it is at least this many times the map's
/// mean luminance (the tests' soft box, 80 times its background, is 34 times its map's).
const SUN_CONTRAST: f64 = 100.0;
/// The widest sun, an angular radius: a wider bright region is the prefiltered cube's
/// to filter, and lit as one direction it would lose its shape.
pub const SUN_MAX_RADIUS_DEGREES: f64 = 5.0;

/// A sun lifted out of its map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Unit direction towards it, in the map's frame (before the map's rotation).
    pub direction: Vec3,
    /// The angular radius of a disc of its solid angle.
    pub angular_radius: f64,
    /// What it adds to the sky it hides, ∫ (L − L_sky) dω over its texels: its irradiance
    /// on a surface facing it, linear RGB, before the environment's intensity.
    pub irradiance: Vec3,
}

/// The map's sun, and the map with the sun's texels replaced by the mean of the texels
/// around them (the two together hold the map's light to rounding). A sun is the texels
/// connected to the brightest one (across the ±180° seam too) and brighter than the
/// geometric mean of it and the map's mean luminance, which takes in a disc's edge
/// texels it covers to about 2%; None when no texel is `SUN_CONTRAST` times the mean or
/// the region is wider than `SUN_MAX_RADIUS_DEGREES`.
pub fn extract(map: &Equirect) -> Option<(Sun, Equirect)> {
    let (width, height) = (map.width as usize, map.height as usize);
    let luminance = |t: [f32; 4]| 0.2126 * f64::from(t[0]) + 0.7152 * f64::from(t[1]) + 0.0722 * f64::from(t[2]);
    let row_solid_angle: Vec<f64> = (0..height)
        .map(|y| {
            let theta = std::f64::consts::PI * (y as f64 + 0.5) / height as f64;
            (std::f64::consts::TAU / width as f64) * (std::f64::consts::PI / height as f64) * theta.sin()
        })
        .collect();
    let solid_angle = |i: usize| row_solid_angle[i / width];
    let total: f64 = row_solid_angle.iter().sum::<f64>() * width as f64;
    let mean = (0..map.texels.len()).map(|i| luminance(map.texels[i]) * solid_angle(i)).sum::<f64>() / total;
    let (brightest, peak) = map
        .texels
        .iter()
        .map(|&t| luminance(t))
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (i, l)| if l > best.1 { (i, l) } else { best });
    if !(mean > 0.0 && peak >= SUN_CONTRAST * mean) {
        return None;
    }
    let threshold = (peak * mean).sqrt();
    let neighbours = |i: usize| {
        let (x, y) = ((i % width) as isize, (i / width) as isize);
        (-1..=1).flat_map(move |dy| (-1..=1).map(move |dx| (dx, dy))).filter_map(move |(dx, dy)| {
            let ny = y + dy;
            ((dx, dy) != (0, 0) && (0..height as isize).contains(&ny))
                .then(|| ny as usize * width + (x + dx).rem_euclid(width as isize) as usize)
        })
    };
    let mut in_sun = vec![false; map.texels.len()];
    let mut region = vec![brightest];
    in_sun[brightest] = true;
    let mut next = 0;
    while next < region.len() {
        for j in neighbours(region[next]) {
            if !in_sun[j] && luminance(map.texels[j]) > threshold {
                in_sun[j] = true;
                region.push(j);
            }
        }
        next += 1;
    }
    let region_solid_angle: f64 = region.iter().map(|&i| solid_angle(i)).sum();
    let widest = std::f64::consts::TAU * (1.0 - SUN_MAX_RADIUS_DEGREES.to_radians().cos());
    if region_solid_angle > widest {
        return None;
    }
    // The sky it hides: the texels that touch it.
    let mut ring = vec![false; map.texels.len()];
    let (mut sky, mut ring_solid_angle) = ([0.0; 3], 0.0);
    for j in region.iter().flat_map(|&i| neighbours(i)) {
        if !in_sun[j] && !ring[j] {
            ring[j] = true;
            ring_solid_angle += solid_angle(j);
            for (c, s) in sky.iter_mut().enumerate() {
                *s += f64::from(map.texels[j][c]) * solid_angle(j);
            }
        }
    }
    let sky = sky.map(|s| s / ring_solid_angle);
    let (mut irradiance, mut centre) = ([0.0; 3], [0.0; 3]);
    for &i in &region {
        let texel = map.texels[i];
        for (c, e) in irradiance.iter_mut().enumerate() {
            *e += (f64::from(texel[c]) - sky[c]) * solid_angle(i);
        }
        let (x, y) = (i % width, i / width);
        let d = equirect_direction([(x as f64 + 0.5) / width as f64, (y as f64 + 0.5) / height as f64]);
        let weight = luminance(texel) * solid_angle(i);
        for (c, d) in centre.iter_mut().zip(d) {
            *c += weight * d;
        }
    }
    let length = centre.iter().map(|c| c * c).sum::<f64>().sqrt();
    let sun = Sun {
        direction: centre.map(|c| c / length),
        angular_radius: (1.0 - region_solid_angle / std::f64::consts::TAU).acos(),
        irradiance: irradiance.map(|e| e.max(0.0)),
    };
    let mut texels = map.texels.clone();
    let fill = [sky[0] as f32, sky[1] as f32, sky[2] as f32, 1.0];
    for &i in &region {
        texels[i] = fill;
    }
    Some((
        sun,
        Equirect {
            width: map.width,
            height: map.height,
            texels,
        },
    ))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    const WIDTH: u32 = 512;

    fn map(radiance: impl Fn(Vec3) -> [f32; 3]) -> Equirect {
        let height = WIDTH / 2;
        let texels = (0..height)
            .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
            .map(|(x, y)| {
                let uv = [(f64::from(x) + 0.5) / f64::from(WIDTH), (f64::from(y) + 0.5) / f64::from(height)];
                let [r, g, b] = radiance(equirect_direction(uv));
                [r, g, b, 1.0]
            })
            .collect();
        Equirect {
            width: WIDTH,
            height,
            texels,
        }
    }

    /// ∫ L dω over the map, per channel.
    fn power(map: &Equirect) -> Vec3 {
        let mut sum = [0.0; 3];
        for (i, t) in map.texels.iter().enumerate() {
            let theta = std::f64::consts::PI * ((i / map.width as usize) as f64 + 0.5) / f64::from(map.height);
            let d_omega = std::f64::consts::TAU / f64::from(map.width) * std::f64::consts::PI
                / f64::from(map.height)
                * theta.sin();
            for c in 0..3 {
                sum[c] += f64::from(t[c]) * d_omega;
            }
        }
        sum
    }

    fn angle(a: Vec3, b: Vec3) -> f64 {
        DVec3::from(a).angle_between(DVec3::from(b))
    }

    /// A disc 1.5° in radius, 1,000 times a graded sky, across the map's ±180° seam: its
    /// direction, size and light come out, and what is left is sky.
    #[test]
    fn a_sun_is_lifted_out_with_its_light() {
        let towards = DVec3::new(0.01, 0.5, 1.0).normalize().to_array();
        let radius = 1.5_f64.to_radians();
        let sky = |d: Vec3| [0.3 + 0.2 * d[1].abs() as f32, 0.5, 0.9];
        let sun = [1500.0, 1400.0, 1250.0];
        let sunny = map(|d| if angle(d, towards) < radius { sun } else { sky(d) });
        let (found, sunless) = extract(&sunny).expect("a sun");
        // Within a fifth of a texel (0.7°) of the disc's centre, and its size to a tenth.
        assert!(angle(found.direction, towards) < 0.14_f64.to_radians(), "{found:?}");
        assert!((found.angular_radius / radius - 1.0).abs() < 0.1, "{found:?}");
        // Its light is the disc's over the sky it hid.
        let disc = std::f64::consts::TAU * (1.0 - radius.cos());
        for ((e, sun), sky) in found.irradiance.iter().zip(sun).zip(sky(towards)) {
            let expected = (f64::from(sun) - f64::from(sky)) * disc;
            assert!((e / expected - 1.0).abs() < 0.03, "{found:?}");
        }
        let (before, after) = (power(&sunny), power(&sunless));
        for c in 0..3 {
            assert!((after[c] + found.irradiance[c] - before[c]).abs() < 1e-6 * before[c]);
        }
        let brightest = sunless.texels.iter().map(|t| t[0]).fold(0.0, f32::max);
        assert!(brightest < 0.6, "{brightest}");
    }

    /// A soft box 80 times its background, a region too wide to be one direction, a
    /// uniform map and a black one have no sun.
    #[test]
    fn broad_or_dim_sources_stay_in_the_map() {
        let centre = DVec3::new(0.3, 0.4, 0.9).normalize().to_array();
        let soft_box = map(|d| {
            let t = ((angle(d, centre).to_degrees() - 10.0) / 10.0).clamp(0.0, 1.0);
            [(0.25 + 20.0 * (1.0 - t * t * (3.0 - 2.0 * t))) as f32; 3]
        });
        assert!(extract(&soft_box).is_none());
        let wide = map(|d| [if angle(d, centre) < 8_f64.to_radians() { 1e4 } else { 1.0 }; 3]);
        assert!(extract(&wide).is_none());
        assert!(extract(&map(|_| [2.0; 3])).is_none());
        assert!(extract(&map(|_| [0.0; 3])).is_none());
    }
}
