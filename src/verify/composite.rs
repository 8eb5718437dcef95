//! `brdf_cos` of `shaders/lib/shading.glsl`, the material's lobes, wrap term and terminator
//! shadowing put together, for a few combinations of models; and the continuity of
//! `shadow_terminator` at g = 1.

use crate::brdf::shading::{
    brdf_cos, brdf_cos_seed, diffuse_lobe, shadow_terminator, specular_lobe, subsurface_reach, DiffuseModel, Horizon,
    ShadingModels, ShadingParams, SpecularModel,
};
use crate::brdf::specular::{Distribution, Geometry};
use crate::brdf::subsurface::{subsurface_transfer, Subsurface};
use crate::brdf::{dot, safe_half_vector, Vec3, MIN_N_DOT_V, PI};

use super::functions::{
    colour, direction, rgb, sample_alpha, sample_directions, vec4, Tuple, Values, DENORMAL, NORMAL,
};
use super::sweep::RELATIVE_FLOOR;
use super::{Row, Status};
use crate::rng::Rng;

/// `brdf_cos` for one combination of models. Tuples: a = (n_geometric, roughness),
/// b = (v, f0), c = (l, diffuse_roughness), d = (base_color, wrap_intensity),
/// e = (specular_color, wrap), f = (wrap_color, wrap_width), g = (scatter_color, curvature),
/// h = (metallic, 0, 0, 0); the shading normal is +z, where
/// n × h is exact in fp32 as for the models, and n_geometric leans away from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Composite {
    pub name: &'static str,
    models: ShadingModels,
    /// `Seed` evaluates `brdf_cos_seed`, the report's composition, which ignores n_geometric.
    horizon: Horizon,
}

/// The GLSL `FUNCTION` of the first combination; the models are encoded above it.
const FIRST_SHADING: u32 = 64;

/// |g − 1| within which `shadow_terminator`'s continuity at g = 1 is checked.
const TERMINATOR_WINDOW: f64 = 1e-3;
/// fp32 rounding of g and of g·(1 + g·(1 − g)) near 1: a few 2^-24.
const TERMINATOR_ROUNDING: f64 = 1.0 / (1u64 << 22) as f64;

impl Composite {
    /// Every diffuse model, every specular model, both distributions, both masking forms and
    /// every subsurface model but none at least once; and the report's composition.
    pub const ALL: [Composite; 8] = [
        Composite {
            name: "brdf_cos lambert + ct ggx correlated",
            models: ShadingModels {
                diffuse: DiffuseModel::Lambert,
                specular: SpecularModel::CookTorrance,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::Seed,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos oren-nayar + ct beckmann separable",
            models: ShadingModels {
                diffuse: DiffuseModel::OrenNayar,
                specular: SpecularModel::CookTorrance,
                distribution: Distribution::Beckmann,
                geometry: Geometry::SmithSeparable,
                subsurface: Subsurface::Seed,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos eon + torrance-sparrow",
            models: ShadingModels {
                diffuse: DiffuseModel::Eon,
                specular: SpecularModel::TorranceSparrow,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::Seed,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos lambert + blinn-phong",
            models: ShadingModels {
                diffuse: DiffuseModel::Lambert,
                specular: SpecularModel::BlinnPhong,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::Seed,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos lambert + ct ggx, energy-conserving wrap",
            models: ShadingModels {
                diffuse: DiffuseModel::Lambert,
                specular: SpecularModel::CookTorrance,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::EnergyConservingWrap,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos eon + ct ggx, pre-integrated",
            models: ShadingModels {
                diffuse: DiffuseModel::Eon,
                specular: SpecularModel::CookTorrance,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::PreIntegrated,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos oren-nayar + none, pre-integrated",
            models: ShadingModels {
                diffuse: DiffuseModel::OrenNayar,
                specular: SpecularModel::None,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::PreIntegrated,
            },
            horizon: Horizon::Smooth,
        },
        Composite {
            name: "brdf_cos_seed eon + ct ggx, pre-integrated",
            models: ShadingModels {
                diffuse: DiffuseModel::Eon,
                specular: SpecularModel::CookTorrance,
                distribution: Distribution::Ggx,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::PreIntegrated,
            },
            horizon: Horizon::Seed,
        },
    ];

    /// The harness's `FUNCTION`: FIRST_SHADING + 256 horizon + 64 subsurface + 16 diffuse +
    /// 4 specular + 2 distribution + geometry, as verify_brdf.comp decodes it.
    pub fn id(self) -> u32 {
        let m = self.models;
        FIRST_SHADING
            + 256 * self.horizon as u32
            + 64 * m.subsurface as u32
            + 16 * m.diffuse as u32
            + 4 * m.specular as u32
            + 2 * m.distribution as u32
            + m.geometry as u32
    }

    /// Whether the subsurface model moves light (and so may cancel against the lobes).
    pub fn redistributes(self) -> bool {
        self.models.subsurface.redistributes()
    }

    pub const SHADOWING_ROUNDING: &'static str = "rounding: n_g·l, a dot product of unit \
        vectors, is good to 3·2^-24 in fp32, and the terminator shadowing is proportional to it \
        below g = 1; bound 3·2^-24/n_g·l";

    /// The relative error fp32 rounding of n_g·l causes where the lobes are lit (n·l > 0):
    /// G ≈ g ∝ n_g·l for small g.
    pub fn shadowing_rounding(self, t: &Tuple) -> f64 {
        if t.c[2] <= 0.0 || self.horizon == Horizon::Seed {
            return 0.0;
        }
        3.0 * f64::from(f32::EPSILON) * 0.5 / dot(rgb(t.a), rgb(t.c)).abs()
    }

    pub const CANCELLATION_ROUNDING: &'static str = "rounding: a redistributing subsurface model \
        adds ρ/π (K − n·l) to the shadowed lobes, which may cancel; bound 16·2^-24 of the \
        summands' magnitude, relative to the value";

    /// The relative error fp32 rounding may cause where a redistributing subsurface model's
    /// ρ/π (K − max(0, n·l)) cancels against f·(n·l)·shadowing: each summand is good to a few
    /// 2^-24 of its own magnitude, not of the (smaller) sum.
    pub fn cancellation_rounding(self, t: &Tuple) -> f64 {
        let model = self.models.subsurface;
        if !model.redistributes() || self.models.diffuse == DiffuseModel::None {
            return 0.0;
        }
        let m = Self::params(t);
        let (n_geometric, v, l) = (rgb(t.a), rgb(t.b), rgb(t.c));
        let n_dot_l = l[2];
        let lit = n_dot_l.max(0.0);
        let lobes = if n_dot_l > 0.0 {
            let n_dot_v = v[2].max(MIN_N_DOT_V);
            let d = diffuse_lobe(self.models.diffuse, &m, NORMAL, v, l, n_dot_v, n_dot_l);
            let s = specular_lobe(self.models, &m, NORMAL, v, l, n_dot_v, n_dot_l);
            let shadowing = match self.horizon {
                Horizon::Smooth => shadow_terminator(dot(n_geometric, l), n_dot_l, n_geometric[2]),
                Horizon::Seed => 1.0,
            };
            std::array::from_fn(|c| (d[c] + s[c]).abs() * lit * shadowing)
        } else {
            [0.0; 3]
        };
        let transfer = subsurface_transfer(model, n_dot_l, subsurface_reach(model, &m, f64::from(t.g[3])));
        let value = self.eval(t);
        (0..3)
            .map(|c| {
                let magnitude = lobes[c] + m.base_color[c] / PI * (transfer[c] + lit);
                16.0 * f64::from(f32::EPSILON) * 0.5 * magnitude / value[c].abs().max(RELATIVE_FLOOR)
            })
            .fold(0.0, f64::max)
    }

    /// The material of a tuple, in f64.
    fn params(t: &Tuple) -> ShadingParams {
        ShadingParams {
            base_color: rgb(t.d),
            specular_color: rgb(t.e),
            wrap_color: rgb(t.f),
            wrap_intensity: f64::from(t.d[3]),
            roughness: f64::from(t.a[3]),
            f0: f64::from(t.b[3]),
            diffuse_roughness: f64::from(t.c[3]),
            wrap: f64::from(t.e[3]),
            wrap_width: f64::from(t.f[3]),
            scatter_color: rgb(t.g),
            scatter_radius: 1.0,
            metallic: f64::from(t.h[0]),
        }
    }

    /// The f64 twin on the tuple's (widened) f32 arguments.
    pub fn eval(self, t: &Tuple) -> Vec3 {
        let (m, curvature) = (Self::params(t), f64::from(t.g[3]));
        match self.horizon {
            Horizon::Smooth => brdf_cos(self.models, &m, NORMAL, rgb(t.a), rgb(t.b), rgb(t.c), curvature),
            Horizon::Seed => brdf_cos_seed(self.models, &m, NORMAL, rgb(t.b), rgb(t.c), curvature),
        }
    }

    /// v and l as for the models (about the lobe of α = roughness², grazing, mirrored,
    /// opposite); n_geometric equal to the shading normal, tilted up to 89°, or beyond 90°
    /// (n_g·n clamped); the material's parameters over their ranges, the wrap term on half
    /// the time.
    pub fn sample(self, rng: &mut Rng) -> Tuple {
        let alpha = sample_alpha(rng);
        let (v, l) = sample_directions(rng, alpha);
        let tilt = match rng.uniform() {
            u if u < 0.2 => 0.0,
            u if u < 0.8 => rng.range(0.0, 60f64.to_radians()),
            u if u < 0.95 => rng.range(60f64.to_radians(), 89f64.to_radians()),
            _ => rng.range(90f64.to_radians(), 180f64.to_radians()),
        };
        let n_geometric = direction(tilt.cos(), rng.azimuth());
        let mut fraction = || match rng.uniform() {
            u if u < 0.05 => 0.0,
            u if u < 0.1 => 1.0,
            _ => rng.uniform(),
        };
        let (f0, diffuse_roughness, wrap, metallic) = (fraction(), fraction(), fraction(), fraction());
        let wrap_intensity = if rng.uniform() < 0.5 {
            0.0
        } else {
            rng.log_uniform(1e-2, 10.0)
        };
        let wrap_width = rng.log_uniform(1e-3, 1.0);
        // σκ: flat or concave, then from far below to far above the profile's width.
        let curvature = match rng.uniform() {
            u if u < 0.1 => 0.0,
            u if u < 0.2 => -rng.log_uniform(1e-3, 10.0),
            _ => rng.log_uniform(1e-3, 100.0),
        };
        let with = |mut x: [f32; 4], w: f64| {
            x[3] = w as f32;
            x
        };
        Tuple {
            a: with(vec4(n_geometric), alpha.sqrt()),
            b: with(vec4(v), f0),
            c: with(vec4(l), diffuse_roughness),
            d: with(colour(rng), wrap_intensity),
            e: with(colour(rng), wrap),
            f: with(colour(rng), wrap_width),
            g: with(colour(rng), curvature),
            h: [metallic as f32, 0.0, 0.0, 0.0],
        }
    }

    /// n_geometric along, against and across the shading normal, and denormal; v along n,
    /// across it (n·v = 0), against it (v = −n), grazing and denormal; l along, against and
    /// across n, equal, opposite and mirrored to v; roughness 0, denormal and 1; a black
    /// material, a white one with the widest wrap and a huge curvature, and one with a
    /// denormal wrap width and curvature.
    pub fn stress(self) -> Vec<Tuple> {
        let z = [0.0, 0.0, 1.0, 0.0];
        let n_geometrics = [
            z,
            [0.0, 0.0, -1.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.6, 0.0, 0.8, 0.0],
            [DENORMAL, 0.0, 1.0, 0.0],
        ];
        let views = [
            z,
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, -1.0, 0.0],
            vec4(direction(1e-7, 0.0)),
            [DENORMAL, DENORMAL, 1.0, 0.0],
        ];
        // Materials: b.w = f0, c.w = diffuse_roughness, d, e, f and g as in every tuple.
        let material = |f0, diffuse_roughness, [d, e, f, g]: [[f32; 4]; 4]| Tuple {
            b: [0.0, 0.0, 0.0, f0],
            c: [0.0, 0.0, 0.0, diffuse_roughness],
            d,
            e,
            f,
            g,
            ..Tuple::default()
        };
        let clay = material(
            0.04,
            0.5,
            [
                [0.0, 0.5, 1.0, 10.0],
                [1.0, 1.0, 1.0, 0.5],
                [1.0, 0.5, 0.0, DENORMAL],
                [1.0, 0.5, 0.0, DENORMAL],
            ],
        );
        let materials = [
            material(0.0, 0.0, [[0.0; 4], [0.0; 4], [0.0, 0.0, 0.0, 1.0], [0.0; 4]]),
            material(1.0, 1.0, [[1.0; 4], [1.0; 4], [1.0; 4], [1.0, 1.0, 1.0, f32::MAX]]),
            clay,
            // The same as a metal.
            Tuple {
                h: [1.0, 0.0, 0.0, 0.0],
                ..clay
            },
        ];
        let mut out = Vec::new();
        for n_geometric in n_geometrics {
            for v in views {
                let lights = [
                    z,
                    [0.0, 0.0, -1.0, 0.0],
                    [0.0, 1.0, 0.0, 0.0],
                    v,
                    v.map(|x| -x),
                    [-v[0], -v[1], v[2], 0.0],
                    vec4(direction(1e-7, std::f64::consts::FRAC_PI_2)),
                ];
                for l in lights {
                    for roughness in [0.0, DENORMAL, 1.0] {
                        for m in materials {
                            let with = |mut x: [f32; 4], w: f32| {
                                x[3] = w;
                                x
                            };
                            out.push(Tuple {
                                a: with(n_geometric, roughness),
                                b: with(v, m.b[3]),
                                c: with(l, m.c[3]),
                                ..m
                            });
                        }
                    }
                }
            }
        }
        out
    }

    /// The tuple's arguments, named, for messages.
    pub fn describe(self, t: &Tuple) -> String {
        let (n_geometric, v, l) = (rgb(t.a), rgb(t.b), rgb(t.c));
        let h = safe_half_vector(v, l, NORMAL);
        format!(
            "roughness={:e}, n·v={:e}, n·l={:e}, n·h={:e}, n_g·n={:e}, n_g·l={:e}, f0={:e}, \
             diffuse_roughness={:e}, base=({:e}, {:e}, {:e}), wrap intensity {:e}, w {:e}, width {:e}, \
             scatter=({:e}, {:e}, {:e}), curvature {:e}, metallic {:e}",
            t.a[3],
            v[2],
            l[2],
            h[2],
            n_geometric[2],
            dot(n_geometric, l),
            t.b[3],
            t.c[3],
            t.d[0],
            t.d[1],
            t.d[2],
            t.d[3],
            t.e[3],
            t.f[3],
            t.g[0],
            t.g[1],
            t.g[2],
            t.g[3],
            t.h[0]
        )
    }
}

/// `shadow_terminator` is continuous and flat at g = 1: G = g + g² − g³ = 1 − 2δ² + δ³ at
/// g = 1 − δ, and 1 for g ≥ 1, so within `TERMINATOR_WINDOW` of g = 1, |G − 1| may exceed
/// 2δ₊² by rounding only. Checked on every tuple, random and stress, GPU and f64.
pub fn terminator_continuity(tuples: &[Tuple], gpu: &[Values<f32>], cpu: &[Values<f64>]) -> Row {
    let mut count = 0;
    let mut worst: (f64, f64, Option<&Tuple>) = (f64::NEG_INFINITY, 0.0, None);
    for ((t, g), c) in tuples.iter().zip(gpu).zip(cpu) {
        let [ng_l, ns_l, ng_ns, _] = t.a.map(f64::from);
        if ng_l <= 0.0 || ns_l <= 0.0 {
            continue;
        }
        let delta = 1.0 - ng_l / (ns_l * ng_ns.max(MIN_N_DOT_V));
        if delta.abs() > TERMINATOR_WINDOW {
            continue;
        }
        count += 1;
        for value in [f64::from(g[0][0]), c[0][0]] {
            let gap = (value - 1.0).abs();
            let excess = gap - 2.0 * delta.max(0.0).powi(2);
            // NaN is the worst.
            let excess = if excess.is_nan() { f64::INFINITY } else { excess };
            if excess >= worst.0 {
                worst = (excess, gap, Some(t));
            }
        }
    }
    let (excess, gap, at) = worst;
    Row {
        model: "shadow_terminator".to_owned(),
        check: "continuous and flat at g = 1".to_owned(),
        measured: format!("max |G − 1| − 2(1 − g)₊² {excess:.1e}"),
        tolerance: format!("<= {TERMINATOR_ROUNDING:.1e} (2^-22, rounding)"),
        status: if excess <= TERMINATOR_ROUNDING && count > 0 {
            Status::Pass
        } else {
            Status::Fail
        },
        note: format!(
            "{count} tuples with |g − 1| <= {TERMINATOR_WINDOW:e}, g = n_g·l/(n_s·l·n_g·n_s); \
             G = 1 − 2δ² + δ³ at g = 1 − δ{}",
            at.map_or_else(String::new, |t| format!(
                "; worst: n_g·l={:e}, n_s·l={:e}, n_g·n_s={:e}, |G − 1| {gap:.1e}",
                t.a[0], t.a[1], t.a[2]
            ))
        ),
    }
}
