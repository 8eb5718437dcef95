//! The light arriving at the camera along one ray, by Monte Carlo integration of the
//! rendering equation (Kajiya 1986; the report's eq. 2) with the material's own f64
//! `brdf_cos`. Point lights are sampled directly (they are deltas), a light with a radius
//! as a sphere of the same power by the solid angle it subtends; the environment both by
//! its luminance and by the material's lobes, the two combined by the power heuristic
//! (Veach 1997). `Direct` and `Shadows` stop after the first surface; `Full` follows the
//! path with Russian roulette. An emissive surface's light is added where a camera ray or
//! a path's bounce meets it: emissive surfaces are not sampled as lights, so in `full`
//! transport they light other surfaces only through the material's own samples (unbiased,
//! noisy for small bright emitters), and in `direct` and `shadows` not at all.

use std::f64::consts::PI;

use glam::DVec3;

use super::environment::EnvironmentLight;
use super::sampling::{power_heuristic, sample_sphere_light, Lobes};
use super::world::Medium;
use super::world::{Surface, World};
use super::{Sampling, Settings, SubsurfaceTransport, Transport};
use crate::brdf::energy::{specular_energy_compensation, SpecularAlbedoTable};
use crate::brdf::environment::{sample_cosine, sample_uniform_sphere, tangent_frame};
use crate::brdf::fresnel::f_schlick;
use crate::brdf::shading::{
    brdf_cos, brdf_cos_seed, subsurface_lights, view_facing_normal, DiffuseModel, ShadingModels, ShadingParams,
    SpecularModel,
};
use crate::brdf::subsurface::Subsurface;
use crate::brdf::MIN_N_DOT_V;
use crate::rng::Rng;
use crate::scene::{Camera, Scene};

/// `MIN_LIGHT_DISTANCE2` of shading.glsl: a light closer than 1e-4 would give unbounded
/// irradiance.
const MIN_LIGHT_DISTANCE2: f64 = 1e-8;
/// Ray origins leave a surface by this fraction of the scene's extent: far above f64's
/// rounding of a hit position (~1e-16 of it), far below anything visible.
const RAY_OFFSET: f64 = 1e-9;
/// Bounces before Russian roulette may end a path.
const ROULETTE_DEPTH: u32 = 3;
/// Scattering events after which a random walk is taken as absorbed: at an albedo of
/// 0.999 less than e⁻¹⁰ of the light is left, and a walk in white clay that has not found
/// the surface by then has crossed ~300 mean free paths.
const MAX_WALK_STEPS: u32 = 100_000;

/// Primary rays of a pinhole camera, as `Camera::view` and `Camera::projection` place them.
pub struct CameraRays {
    position: DVec3,
    forward: DVec3,
    /// Screen right and up, scaled to the image plane at unit distance along `forward`.
    right: DVec3,
    up: DVec3,
}

impl CameraRays {
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let position = camera.position.as_dvec3();
        let forward = (camera.target.as_dvec3() - position).normalize_or(DVec3::NEG_Z);
        let world_up = if forward.y.abs() > 0.9999 {
            DVec3::new(0.0, 0.0, forward.y.signum())
        } else {
            DVec3::Y
        };
        let right = forward.cross(world_up).normalize();
        let up = right.cross(forward);
        let tan_half = (f64::from(camera.fov_y_degrees).to_radians() * 0.5).tan();
        let aspect = f64::from(width) / f64::from(height);
        Self {
            position,
            forward,
            right: right * tan_half * aspect,
            up: up * tan_half,
        }
    }

    /// The ray through image point (x, y) in pixels from the top-left corner: its origin and
    /// a direction whose component along the view axis is 1, so that t is view depth and
    /// (NEAR, FAR) clips as the rasteriser does.
    pub fn ray(&self, x: f64, y: f64, width: u32, height: u32) -> (DVec3, DVec3) {
        let ndc_x = 2.0 * x / f64::from(width) - 1.0;
        let ndc_y = 2.0 * y / f64::from(height) - 1.0;
        (self.position, self.forward + ndc_x * self.right - ndc_y * self.up)
    }
}

pub struct Integrator<'a> {
    world: &'a World,
    environment: Option<&'a EnvironmentLight>,
    lights: Vec<Light>,
    transport: Transport,
    max_depth: u32,
    /// Whether the environment is sampled by its luminance, and by the material's lobes.
    light_sampling: bool,
    material_sampling: bool,
    /// Whether scattering materials are media (`--subsurface volume`).
    volume: bool,
}

/// A scene light: a point, or with a radius a sphere emitting I/(πr²) outwards from every
/// point of its surface, the power 4πI of the point. The sphere is not seen by rays that
/// meet it (the camera's, the material's samples), so its light is counted once, by
/// sampling it; a surface inside it receives none of its light.
struct Light {
    position: DVec3,
    intensity: DVec3,
    radius: f64,
}

/// What one camera ray brought back.
pub struct Sample {
    pub radiance: DVec3,
    /// Whether it hit an object (the pixel's coverage).
    pub hit: bool,
    pub rays: u64,
}

/// A surface point ready to shade, seen from v: the shading normal (turned towards v
/// unless the material keeps the report's horizon), its frame and the lobes to sample.
struct Shading<'s> {
    surface: &'s Surface,
    models: ShadingModels,
    params: ShadingParams,
    n: DVec3,
    v: DVec3,
    seed_horizon: bool,
    /// (t, b, n) of the shading normal.
    frame: [DVec3; 3],
    lobes: Lobes,
    /// The clay's medium, where `--subsurface volume` puts one under this surface.
    medium: Option<Medium>,
    /// The probability of sampling the transmission into the medium rather than `lobes`.
    enter: f64,
}

impl Shading<'_> {
    fn local(&self, d: DVec3) -> DVec3 {
        DVec3::new(d.dot(self.frame[0]), d.dot(self.frame[1]), d.dot(self.frame[2]))
    }

    fn world(&self, d: DVec3) -> DVec3 {
        self.frame[0] * d.x + self.frame[1] * d.y + self.frame[2] * d.z
    }

    /// The pdf of the material's sampling choosing unit world direction l outside.
    fn lobes_pdf(&self, l: DVec3) -> f64 {
        (1.0 - self.enter) * self.lobes.pdf(self.local(self.v), self.local(l))
    }
}

impl<'a> Integrator<'a> {
    pub fn new(
        scene: &Scene,
        world: &'a World,
        environment: Option<&'a EnvironmentLight>,
        settings: &Settings,
    ) -> Self {
        let worth = environment.is_some_and(EnvironmentLight::worth_sampling);
        Self {
            world,
            environment,
            lights: scene
                .lights
                .iter()
                .map(|l| Light {
                    position: l.position.as_dvec3(),
                    intensity: l.intensity.as_dvec3(),
                    radius: f64::from(l.radius),
                })
                .collect(),
            transport: settings.transport,
            max_depth: settings.max_depth,
            light_sampling: match settings.sampling {
                Sampling::Mis => worth,
                Sampling::Material => false,
                Sampling::Light => true,
            },
            material_sampling: settings.sampling != Sampling::Light,
            volume: settings.subsurface == SubsurfaceTransport::Volume,
        }
    }

    /// The weight of the material's sample l of pdf `pdf` in the environment's estimate.
    fn material_weight(&self, pdf: f64, l: DVec3) -> f64 {
        match (self.material_sampling, self.light_sampling, self.environment) {
            (false, _, _) | (_, _, None) => 0.0,
            (true, false, _) => 1.0,
            (true, true, Some(e)) => power_heuristic(pdf, e.pdf(l)),
        }
    }

    /// The weight of the environment's sample l of pdf `pdf`, for the material's lobes.
    fn light_weight(&self, s: &Shading, pdf: f64, l: DVec3) -> f64 {
        if self.material_sampling {
            power_heuristic(pdf, s.lobes_pdf(l))
        } else {
            1.0
        }
    }

    /// The surface as a path meets it: its material; or, with `--subsurface volume`, over
    /// a scattering medium, only the material's specular lobe above transmission into the
    /// clay; or, where a random walk leaves the clay (`exit`), a white Lambertian
    /// transmission outwards.
    fn shading<'s>(&self, surface: &'s Surface, v: DVec3, exit: bool) -> Shading<'s> {
        let m = self.world.material(surface.material);
        let (mut models, mut params) = (m.models, surface.params);
        let seed_horizon = m.seed_horizon && !exit;
        let n = if exit || seed_horizon {
            surface.mapped_normal
        } else {
            DVec3::from(view_facing_normal(surface.mapped_normal.to_array(), v.to_array()))
        };
        let medium = if self.volume && !exit {
            Medium::of(m, &params)
        } else {
            None
        };
        let mut enter = 0.0;
        if exit {
            models = ShadingModels {
                diffuse: DiffuseModel::Lambert,
                specular: SpecularModel::None,
                subsurface: Subsurface::None,
                ..models
            };
            params.base_color = [1.0; 3];
            params.metallic = 0.0;
        } else if medium.is_some() {
            models.diffuse = DiffuseModel::None;
            models.subsurface = Subsurface::None;
            enter = if models.specular == SpecularModel::None {
                1.0
            } else {
                0.5
            };
        }
        if m.energy_compensation && models.specular != SpecularModel::None {
            // As forward.frag: the tint scaled by the compensation at this n·v.
            let e = SpecularAlbedoTable::get().lookup(models, v.dot(n).max(MIN_N_DOT_V), params.roughness);
            let factor = specular_energy_compensation(e, params.specular_f0());
            params.specular_color = std::array::from_fn(|i| params.specular_color[i] * factor[i]);
        }
        let frame = tangent_frame(n.to_array()).map(DVec3::from);
        let lobes = Lobes::new(models, &params, v.dot(n), subsurface_lights(models, &params));
        Shading {
            surface,
            models,
            params,
            n,
            v,
            seed_horizon,
            frame,
            lobes,
            medium,
            enter,
        }
    }

    /// f(l) (n·l) of the material at the shading point, as the forward pass evaluates it.
    fn brdf_cos(&self, s: &Shading, l: DVec3) -> DVec3 {
        let (n, v, l) = (s.n.to_array(), s.v.to_array(), l.to_array());
        DVec3::from(if s.seed_horizon {
            brdf_cos_seed(s.models, &s.params, n, v, l, s.surface.curvature)
        } else {
            brdf_cos(
                s.models,
                &s.params,
                n,
                s.surface.normal.to_array(),
                v,
                l,
                s.surface.curvature,
            )
        })
    }

    /// A random walk through the clay from `entry` along `dir`, scattering isotropically
    /// until it reaches a surface: the point where it leaves, seen from outside; None if
    /// it is absorbed. Free flights in a homogeneous medium (Pharr, Jakob & Humphreys,
    /// PBR 4th ed., §14.1), chromatic: the distance is drawn from one colour channel chosen
    /// in proportion to the path's throughput in it, and weighted by the mixture of the
    /// channels' pdfs (Chiang, Kutz & Burley 2016, "Practical and Controllable Subsurface
    /// Scattering for Production Path Tracing"), which keeps the channels' throughputs from
    /// drifting apart over a long walk.
    fn random_walk(
        &self,
        entry: &Surface,
        mut dir: DVec3,
        medium: &Medium,
        rng: &mut Rng,
        throughput: &mut DVec3,
        rays: &mut u64,
    ) -> Option<Surface> {
        let mut origin = entry.position - entry.face_normal * (RAY_OFFSET * self.world.extent);
        let transmittance = |t: f64| DVec3::from((-medium.sigma_t * t).to_array().map(f64::exp));
        for _ in 0..MAX_WALK_STEPS {
            let total = throughput.element_sum();
            let p = if total > 0.0 {
                *throughput / total
            } else {
                DVec3::splat(1.0 / 3.0)
            };
            let u = rng.uniform();
            let channel = if u < p.x {
                0
            } else if u < p.x + p.y {
                1
            } else {
                2
            };
            let distance = -(1.0 - rng.uniform()).ln() / medium.sigma_t[channel];
            *rays += 1;
            if let Some(hit) = self.world.intersect(origin, dir, 0.0, distance, None) {
                // The probability of flying past hit.t is the channels' mixed transmittance.
                let t = transmittance(hit.t);
                *throughput *= t / p.dot(t);
                return Some(self.world.surface(&hit, -dir));
            }
            let t = transmittance(distance);
            *throughput *= medium.albedo * medium.sigma_t * t / p.dot(medium.sigma_t * t);
            let survive = throughput.max_element().clamp(0.05, 1.0);
            if rng.uniform() >= survive {
                return None;
            }
            *throughput /= survive;
            origin += dir * distance;
            dir = DVec3::from(sample_uniform_sphere([rng.uniform(), rng.uniform()]));
        }
        None
    }

    /// Where a ray towards l leaves the surface, and the object it must ignore: above the
    /// triangle's plane from the terminator-safe origin; below it (light the subsurface
    /// term gathers through the object, or a shading normal leaning past the plane)
    /// through the object itself.
    fn leave(&self, s: &Surface, l: DVec3) -> (DVec3, Option<usize>) {
        let offset = RAY_OFFSET * self.world.extent;
        if l.dot(s.face_normal) > 0.0 {
            (s.ray_origin + s.face_normal * offset, None)
        } else {
            (s.position, Some(s.object))
        }
    }

    fn visible(&self, s: &Surface, l: DVec3, distance: f64, rays: &mut u64) -> bool {
        if self.transport == Transport::Direct {
            return true;
        }
        *rays += 1;
        let (origin, skip) = self.leave(s, l);
        !self.world.occluded(origin, l, 0.0, distance, skip)
    }

    /// The light a camera ray (origin, direction not necessarily unit) brings back.
    pub fn trace(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64, rng: &mut Rng) -> Sample {
        let mut rays = 1;
        let Some(hit) = self.world.intersect(origin, dir, t_min, t_max, None) else {
            let background = self.environment.map_or(DVec3::ZERO, |e| e.radiance(dir.normalize()));
            return Sample {
                radiance: background,
                hit: false,
                rays,
            };
        };
        let mut surface = self.world.surface(&hit, dir);
        let mut v = -dir.normalize();
        let mut throughput = DVec3::ONE;
        let mut radiance = surface.emission;
        let mut exit = false;
        for depth in 0..self.max_depth {
            let s = self.shading(&surface, v, exit);
            // The occlusion map scales the environment's light at the first surface, as
            // the forward pass applies it. Not the point lights': the forward pass's
            // micro-shadowing stands for geometry finer than a texel, which the reference
            // does not have, so the ground truth leaves it out.
            let ambient = if depth == 0 { surface.occlusion } else { 1.0 };
            radiance += throughput * self.direct_light(&s, ambient, rng, &mut rays);

            if let Some(medium) = s.medium.filter(|_| rng.uniform() < s.enter) {
                // Into the clay, cosine-weighted about the triangle's inward normal (always
                // below its plane, unlike a bent shading normal's): what the specular lobe
                // leaves, 1 − F(n·v), goes in.
                let inward = tangent_frame((-surface.face_normal).to_array()).map(DVec3::from);
                let c = sample_cosine([rng.uniform(), rng.uniform()]);
                let l = (inward[0] * c[0] + inward[1] * c[1] + inward[2] * c[2]).normalize();
                let reflected = if s.models.specular == SpecularModel::None {
                    DVec3::ZERO
                } else {
                    DVec3::from(f_schlick(s.params.specular_f0(), v.dot(s.n).clamp(0.0, 1.0)))
                };
                throughput *= (DVec3::ONE - reflected) / s.enter;
                let Some(out) = self.random_walk(&surface, l, &medium, rng, &mut throughput, &mut rays) else {
                    break;
                };
                v = out.normal;
                surface = out;
                exit = true;
                continue;
            }

            // The material's own sample: the environment's light along it (MIS) and, for
            // the full transport, the next surface.
            let v_local = s.local(v);
            let Some(l_local) = s.lobes.sample(v_local, [rng.uniform(), rng.uniform(), rng.uniform()]) else {
                break;
            };
            let l = s.world(l_local).normalize();
            let pdf = (1.0 - s.enter) * s.lobes.pdf(v_local, l_local);
            let f = self.brdf_cos(&s, l);
            if pdf <= 0.0 || f == DVec3::ZERO || !f.is_finite() {
                break;
            }
            let weight = f / pdf;
            let escaped = |radiance: &mut DVec3| {
                if let Some(e) = self.environment {
                    *radiance += throughput * weight * e.radiance(l) * (ambient * self.material_weight(pdf, l));
                }
            };
            if self.transport == Transport::Direct {
                escaped(&mut radiance);
                break;
            }
            rays += 1;
            let (origin, skip) = self.leave(&surface, l);
            let next = self.world.intersect(origin, l, 0.0, f64::INFINITY, skip);
            let Some(next) = next else {
                escaped(&mut radiance);
                break;
            };
            if self.transport == Transport::Shadows {
                break;
            }
            throughput *= weight;
            if depth + 1 >= ROULETTE_DEPTH {
                let survive = throughput.max_element().clamp(0.05, 1.0);
                if rng.uniform() >= survive {
                    break;
                }
                throughput /= survive;
            }
            surface = self.world.surface(&next, l);
            // Counted where the bounce meets it, as the environment is where a ray escapes.
            radiance += throughput * surface.emission;
            v = -l;
            exit = false;
        }
        Sample {
            radiance,
            hit: true,
            rays,
        }
    }

    /// Light arriving straight from the point lights and, by light sampling weighted
    /// against the material's sampling, from the environment, that scaled by `ambient`.
    fn direct_light(&self, s: &Shading, ambient: f64, rng: &mut Rng, rays: &mut u64) -> DVec3 {
        let mut radiance = DVec3::ZERO;
        let p = s.surface.position;
        for light in &self.lights {
            if light.radius > 0.0 {
                let u = [rng.uniform(), rng.uniform()];
                if let Some((l, distance, pdf)) = sample_sphere_light(light.position, light.radius, p, u) {
                    let f = self.brdf_cos(s, l);
                    if f != DVec3::ZERO && self.visible(s.surface, l, distance, rays) {
                        let radiance_of_sphere = light.intensity / (PI * light.radius * light.radius);
                        radiance += f * radiance_of_sphere / pdf;
                    }
                }
                continue;
            }
            let to_light = light.position - p;
            let distance2 = to_light.length_squared().max(MIN_LIGHT_DISTANCE2);
            let l = to_light / distance2.sqrt();
            let f = self.brdf_cos(s, l);
            if f != DVec3::ZERO && self.visible(s.surface, to_light, 1.0, rays) {
                radiance += light.intensity / distance2 * f;
            }
        }
        if let Some(e) = self.environment.filter(|_| self.light_sampling) {
            let (l, pdf) = e.sample([rng.uniform(), rng.uniform()]);
            if pdf > 0.0 {
                let f = self.brdf_cos(s, l);
                if f != DVec3::ZERO && self.visible(s.surface, l, f64::INFINITY, rays) {
                    radiance += f * e.radiance(l) * (ambient * self.light_weight(s, pdf, l) / pdf);
                }
            }
        }
        radiance
    }
}
