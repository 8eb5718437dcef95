//! The scene as rays see it: every object's triangles in world space (f64) in one BVH, and
//! at a hit the surface as the forward pass's vertex and fragment shaders see it there:
//! interpolated normal, tangent, uvs and curvature, the material's maps applied.

use glam::{DVec2, DVec3, DVec4};

use super::bvh::{Bvh, Hit, Triangle};
use super::texture::Texture;
use crate::brdf::normal_mapping::{blend_rnm, blend_seed, blend_udn, blend_whiteout, decode_normal, tangent_to_world};
use crate::brdf::shading::{ShadingModels, ShadingParams};
use crate::scene::map_slots::MAP_COUNT;
use crate::scene::{DetailBlend, MapRef, MapSlot, Material, Scene};

/// Below this squared length an interpolated normal has no direction (`MIN_NORMAL_LENGTH2`
/// of shading.glsl).
const MIN_NORMAL_LENGTH2: f64 = 1e-12;

#[derive(Clone, Copy)]
struct WorldVertex {
    position: DVec3,
    normal: DVec3,
    uv: DVec2,
    tangent: DVec4,
    /// Divided by the object's scale, as forward.vert does.
    curvature: f64,
}

/// `map_factor` of material_maps.glsl: mix(1, the texel's channel, strength).
fn map_factor(map: &MapRef, texel: [f64; 4], channel: usize) -> f64 {
    1.0 + (texel[channel] - 1.0) * f64::from(map.strength)
}

pub struct WorldMaterial {
    pub models: ShadingModels,
    pub params: ShadingParams,
    pub seed_horizon: bool,
    /// Whether the specular lobe is energy-compensated, as the forward pass compensates it.
    pub energy_compensation: bool,
    /// The emitted radiance, before the emission map.
    emission: DVec3,
    /// By slot.
    maps: [Option<MapRef>; MAP_COUNT],
    detail_blend: DetailBlend,
}

impl WorldMaterial {
    fn new(material: &Material) -> Self {
        Self {
            models: material.shading_models(),
            params: material.shading_params(),
            seed_horizon: material.horizon == crate::scene::Horizon::Seed,
            energy_compensation: material.energy_compensation,
            emission: material.emission.as_dvec3(),
            maps: material.maps.0,
            detail_blend: material.detail_blend,
        }
    }
}

/// The clay as a homogeneous scattering medium, for `--subsurface volume`: per channel,
/// the extinction coefficient and the single-scattering albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    pub sigma_t: DVec3,
    pub albedo: DVec3,
}

/// Shortest mean free path, in scene units: a colour channel of `scatter_color` 0 would
/// make the medium infinitely dense.
const MIN_MEAN_FREE_PATH: f64 = 1e-6;

/// The single-scattering albedo α whose medium, with diffuse boundaries, reflects a
/// multiple-scattering albedo A (Christensen & Burley 2015, "Approximate Reflectance
/// Profiles for Efficient Subsurface Scattering", the van de Hulst inversion of their
/// eq. 4 fit): α = 1 − (4.09712 + 4.20863 A − √(9.59217 + 41.6808 A + 17.7126 A²))².
pub fn single_scattering_albedo(multiple: f64) -> f64 {
    let a = multiple.clamp(0.0, 1.0);
    let s = 4.09712 + 4.20863 * a - (9.59217 + 41.6808 * a + 17.7126 * a * a).sqrt();
    (1.0 - s * s).clamp(0.0, 1.0)
}

impl Medium {
    /// The medium of a surface's material, if it scatters (a subsurface model with a
    /// `scatter_radius` and a diffuse lobe): mean free path `scatter_radius` ·
    /// `scatter_color` per channel, albedo from the mapped `base_color` at the point (its
    /// dielectric part, `diffuse_color`).
    pub fn of(material: &WorldMaterial, params: &ShadingParams) -> Option<Medium> {
        let scatters = material.models.subsurface != crate::brdf::subsurface::Subsurface::None
            && material.models.diffuse != crate::brdf::shading::DiffuseModel::None
            && params.scatter_radius > 0.0;
        scatters.then(|| Medium {
            sigma_t: DVec3::from(
                params
                    .scatter_color
                    .map(|c| 1.0 / (params.scatter_radius * c).max(MIN_MEAN_FREE_PATH)),
            ),
            albedo: DVec3::from(params.diffuse_color().map(single_scattering_albedo)),
        })
    }
}

/// A surface point seen along a ray.
pub struct Surface {
    pub position: DVec3,
    /// The triangle's plane normal, on the side the ray came from.
    pub face_normal: DVec3,
    /// The interpolated vertex normal on the ray's side: the shaders' n_geometric.
    pub normal: DVec3,
    /// The normal after the normal and detail maps (not yet turned towards the viewer).
    pub mapped_normal: DVec3,
    pub curvature: f64,
    /// The material's parameters with its base colour and property maps applied.
    pub params: ShadingParams,
    /// The occlusion map's visibility of the environment's light (1 without one).
    pub occlusion: f64,
    /// The radiance the surface emits, its emission map applied, as mapped_emission does.
    pub emission: DVec3,
    pub material: usize,
    pub object: usize,
    /// The position moved onto the vertices' tangent planes, where rays leave from on the
    /// lit side (Hanika 2021, "Hacking the Shadow Terminator"): a smooth-shaded coarse mesh
    /// does not shadow itself at its terminator.
    pub ray_origin: DVec3,
}

pub struct World {
    bvh: Bvh,
    vertices: Vec<WorldVertex>,
    /// Per triangle: its three vertices and the object it belongs to.
    triangles: Vec<([u32; 3], u32)>,
    objects: Vec<usize>,
    materials: Vec<WorldMaterial>,
    textures: Vec<Texture>,
    /// The largest coordinate of any vertex (at least 1): ray offsets scale with it, as
    /// the rounding of positions does.
    pub extent: f64,
}

impl World {
    pub fn new(scene: &Scene) -> Self {
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        let mut geometry = Vec::new();
        for (index, object) in scene.objects.iter().enumerate() {
            let mesh = &scene.meshes[object.mesh];
            let base = vertices.len() as u32;
            let scale = f64::from(object.scale);
            let position = object.position.as_dvec3();
            vertices.extend(mesh.vertices.iter().map(|v| WorldVertex {
                position: position + scale * DVec3::from(v.position.map(f64::from)),
                normal: DVec3::from(v.normal.map(f64::from)),
                uv: DVec2::from(v.uv.map(f64::from)),
                tangent: DVec4::from(v.tangent.map(f64::from)),
                curvature: f64::from(v.curvature) / scale,
            }));
            for t in mesh.indices.chunks_exact(3) {
                let ids = [base + t[0], base + t[1], base + t[2]];
                let p = ids.map(|i| vertices[i as usize].position);
                geometry.push(Triangle::new(p[0], p[1], p[2]));
                triangles.push((ids, index as u32));
            }
        }
        let extent = vertices
            .iter()
            .map(|v| v.position.abs().max_element())
            .fold(1.0, f64::max);
        Self {
            bvh: Bvh::new(geometry),
            vertices,
            triangles,
            objects: scene.objects.iter().map(|o| o.material).collect(),
            materials: scene.materials.iter().map(WorldMaterial::new).collect(),
            textures: scene.textures.iter().map(Texture::new).collect(),
            extent,
        }
    }

    pub fn material(&self, index: usize) -> &WorldMaterial {
        &self.materials[index]
    }

    /// The object of a triangle.
    fn object_of(&self, triangle: usize) -> usize {
        self.triangles[triangle].1 as usize
    }

    /// The closest hit along the ray within (t_min, t_max), ignoring object `skip`.
    pub fn intersect(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64, skip: Option<usize>) -> Option<Hit> {
        self.bvh
            .intersect(origin, dir, t_min, t_max, |t| Some(self.object_of(t)) == skip)
    }

    /// Whether anything but object `skip` lies on the segment from `origin` along `dir`
    /// (not necessarily unit) within (t_min, t_max).
    pub fn occluded(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64, skip: Option<usize>) -> bool {
        self.bvh
            .occluded(origin, dir, t_min, t_max, |t| Some(self.object_of(t)) == skip)
    }

    /// The position and unit normal of each vertex of a hit's triangle, in the order of its
    /// barycentric weights (1 − b1 − b2, b1, b2): what the vertex shader computes at.
    pub fn hit_vertices(&self, hit: &Hit) -> [(DVec3, DVec3); 3] {
        self.triangles[hit.triangle]
            .0
            .map(|i| (self.vertices[i as usize].position, self.vertices[i as usize].normal.normalize_or_zero()))
    }

    /// The surface at a hit of a ray with direction `dir`, as the fragment shader sees it.
    pub fn surface(&self, hit: &Hit, dir: DVec3) -> Surface {
        let (ids, object) = self.triangles[hit.triangle];
        let v = ids.map(|i| self.vertices[i as usize]);
        let b = [1.0 - hit.b1 - hit.b2, hit.b1, hit.b2];
        let interpolate = |f: &dyn Fn(&WorldVertex) -> DVec4| b[0] * f(&v[0]) + b[1] * f(&v[1]) + b[2] * f(&v[2]);
        // The same f64 arithmetic as the BVH's `Triangle`, from the vertices.
        let tri = Triangle::new(v[0].position, v[1].position, v[2].position);
        let position = tri.p0 + hit.b1 * tri.e1 + hit.b2 * tri.e2;
        // Front faces wind counter-clockwise seen from outside, where the normals point.
        let winding = tri.e1.cross(tri.e2);
        let front_facing = winding.dot(dir) < 0.0;
        let side = if front_facing { 1.0 } else { -1.0 };
        let face_normal = winding.normalize_or(DVec3::Z) * side;
        let interpolated = interpolate(&|w| w.normal.extend(0.0)).truncate();
        let normal = if interpolated.length_squared() > MIN_NORMAL_LENGTH2 {
            interpolated.normalize() * side
        } else {
            face_normal
        };
        let uv = interpolate(&|w| w.uv.extend(0.0).extend(0.0)).truncate().truncate();
        // The tangent frame follows the normal to the viewer's side, as in forward.frag.
        let mut tangent = interpolate(&|w| w.tangent);
        tangent.w *= side;
        let curvature = interpolate(&|w| DVec4::splat(w.curvature)).x;

        let material_index = self.objects[object as usize];
        let material = &self.materials[material_index];
        let mut params = material.params;
        let sample = |slot: MapSlot| {
            let map = material.maps[slot.index()].as_ref()?;
            Some((map, self.textures[map.texture].sample(map.uv(uv))))
        };
        // base_color · mix(1, map, strength), as mapped_base_color does, and the emission.
        let colour = |slot: MapSlot, value: [f64; 3]| {
            sample(slot).map_or(value, |(map, texel)| std::array::from_fn(|c| value[c] * map_factor(map, texel, c)))
        };
        params.base_color = colour(MapSlot::BaseColor, params.base_color);
        let emission = DVec3::from(colour(MapSlot::Emission, material.emission.to_array()));
        // The property maps, as mapped_properties and mapped_occlusion do.
        let factor = |slot: MapSlot| {
            sample(slot).map_or(1.0, |(map, texel)| {
                map_factor(map, texel, slot.info().channel.index().unwrap_or(0))
            })
        };
        params.roughness *= factor(MapSlot::Roughness);
        params.metallic *= factor(MapSlot::Metallic);
        let scatter = factor(MapSlot::Scatter);
        params.scatter_color = params.scatter_color.map(|c| c * scatter);
        params.wrap *= scatter;
        let occlusion = factor(MapSlot::Occlusion);
        let mapped_normal = self.mapped_normal(material, normal, tangent, uv);

        // Hanika's shift: onto each vertex's tangent plane where the point lies below it.
        let vertex_normals = v.map(|w| w.normal * side);
        let mut ray_origin = position;
        for i in 0..3 {
            let below = (position - v[i].position).dot(vertex_normals[i]).min(0.0);
            ray_origin -= b[i] * below * vertex_normals[i];
        }
        Surface {
            position,
            face_normal,
            normal,
            mapped_normal,
            curvature,
            params,
            occlusion,
            emission,
            material: material_index,
            object: object as usize,
            ray_origin,
        }
    }

    /// `mapped_normal` of material_maps.glsl, with level-0 bilinear texels.
    fn mapped_normal(&self, m: &WorldMaterial, normal: DVec3, tangent: DVec4, uv: DVec2) -> DVec3 {
        let decode = |map: &MapRef| {
            let t = self.textures[map.texture].sample(map.uv(uv));
            decode_normal([t[0], t[1], t[2]], map.green_down, f64::from(map.strength))
        };
        let base = m.maps[MapSlot::Normal.index()].as_ref().map(decode);
        let detail = m.maps[MapSlot::Detail.index()].as_ref().map(decode);
        let n = match (base, detail) {
            (Some(base), Some(detail)) => match m.detail_blend {
                DetailBlend::Rnm => blend_rnm(base, detail),
                DetailBlend::Udn => blend_udn(base, detail),
                DetailBlend::Whiteout => blend_whiteout(base, detail),
                DetailBlend::Seed => blend_seed(base, detail),
            },
            (Some(n), None) | (None, Some(n)) => n,
            (None, None) => return normal,
        };
        DVec3::from(tangent_to_world(n, normal.to_array(), tangent.to_array()))
    }
}
