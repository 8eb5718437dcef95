//! The scene on the GPU: vertex and index buffers per mesh, and the per-frame data that
//! the forward pass reads (`shaders/lib/scene_data.glsl` declares the same layouts).

use std::sync::Arc;

use anyhow::{ensure, Result};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Mat4, Vec3};

use super::textures::{placeholder, GpuTexture};
use crate::scene::limits::MAX_OCCLUDERS;
use crate::scene::occluders::Occluder;
use crate::scene::{MapSlot, Mesh, MeshExtent, Object, Scene, TexelFormat, TextureData, TextureRole};
use crate::vk::{Buffer, DescriptorPool, DescriptorSetLayout, DescriptorWriter, Device, OneShot, Sampler};

/// `MAX_POINT_LIGHTS` in scene_data.glsl.
pub const MAX_POINT_LIGHTS: usize = 16;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct PointLightData {
    pub position: [f32; 4],
    pub intensity: [f32; 4],
}

/// `FrameData` (std140).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct FrameData {
    pub view_proj: [[f32; 4]; 4],
    pub camera_position: [f32; 4],
    pub counts: [u32; 4],
    pub lights: [PointLightData; MAX_POINT_LIGHTS],
    /// The ground (`Scene::ground`; shaders/lib/ground_light.glsl): xyz its centre, w its
    /// half side, 0 without a ground.
    pub ground: [f32; 4],
    /// rgb the ground's albedo, a 1 where it bounces the lights' light
    /// (shaders/lib/bounce.glsl), else 0.
    pub ground_albedo: [f32; 4],
    /// The spheres of `[occlusion] objects` (`counts[3]` of them, as `Scene::occluders`
    /// lists them): centre and radius, then albedo (w unused).
    pub occluders: [[[f32; 4]; 2]; MAX_OCCLUDERS],
}

impl FrameData {
    /// The frame's data for `scene`, whose occluding spheres are `spheres`
    /// (`Scene::occluders`), in a view of `aspect`.
    pub fn new(scene: &Scene, spheres: &[Occluder], aspect: f32) -> Result<Self> {
        ensure!(
            scene.lights.len() <= MAX_POINT_LIGHTS,
            "the scene has {} point lights; at most {MAX_POINT_LIGHTS} are supported",
            scene.lights.len()
        );
        let view_proj = scene.camera.view_projection(aspect);
        let mut lights = [PointLightData::zeroed(); MAX_POINT_LIGHTS];
        for (slot, light) in lights.iter_mut().zip(&scene.lights) {
            slot.position = light.position.extend(1.0).to_array();
            slot.intensity = light.intensity.extend(0.0).to_array();
        }
        let (ground, ground_albedo) = match scene.ground() {
            Some(object) => (
                object.position.extend(object.scale).to_array(),
                (scene.materials[object.material].base_color)
                    .extend(if scene.bounce { 1.0 } else { 0.0 })
                    .to_array(),
            ),
            None => ([0.0; 4], [0.0; 4]),
        };
        let mut occluders = [[[0.0; 4]; 2]; MAX_OCCLUDERS];
        for (slot, s) in occluders.iter_mut().zip(spheres) {
            *slot = [s.centre.extend(s.radius).to_array(), s.albedo.extend(0.0).to_array()];
        }
        Ok(Self {
            view_proj: view_proj.to_cols_array_2d(),
            camera_position: scene.camera.position.extend(1.0).to_array(),
            counts: [scene.lights.len() as u32, 0, 0, spheres.len() as u32],
            lights,
            ground,
            ground_albedo,
            occluders,
        })
    }
}

/// `ObjectPush`: the push constants of one draw.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ObjectPush {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 3],
    pub material_index: u32,
    /// The lights that may shadow it, bit i for light i (`Scene::shadowing_lights`): the
    /// shadow code runs for those alone.
    pub shadowing_lights: u32,
    /// The run of `FrameData::occluders` that stands for its own file object, which does
    /// not occlude it: first | count << 16.
    pub own_occluders: u32,
    /// Its first vertex's entry in what the draws read at their vertices (vertex_light.rs),
    /// where it reads there.
    pub vertex_light_first: u32,
}

/// Where a draw's occlusion by the other objects (`[occlusion] objects`) comes from:
/// shaders/lib/object_occlusion.glsl's OBJECTS_OCCLUSION_FROM_*, a specialization constant
/// of its pipeline (`ForwardConstants::objects_occlusion_from`).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObjectsOcclusionFrom {
    /// The spheres read at every pixel.
    Pixels = 0,
    /// The spheres read at its vertices and interpolated (`Scene::occlusion_at_vertices`).
    Vertices = 1,
    /// The ground's occlusion map (ground_maps.rs).
    GroundMap = 2,
}

/// How a draw reads its occlusion by the other objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjectOcclusion {
    /// Its own file object's run of the frame's occluders (`Scene::own_occluders`), which
    /// it skips.
    pub own: (usize, usize),
    pub from: ObjectsOcclusionFrom,
}

// `own_occluders` packs a first occluder and a count, each below 2¹⁶.
const _: () = assert!(MAX_OCCLUDERS < 1 << 16);

impl ObjectPush {
    /// The draw of `object`, which skips the occluders `occlusion.own`, may be shadowed by
    /// the lights `shadowing_lights` and reads its vertices' bounce and shadows from
    /// `vertex_light_first` on.
    pub fn new(object: &Object, occlusion: ObjectOcclusion, shadowing_lights: u32, vertex_light_first: u32) -> Self {
        let model: Mat4 = object.model_matrix();
        // Normals transform by the inverse transpose; with a degenerate matrix, which the
        // scene loader rejects, this would be non-finite.
        let normal = Mat3::from_mat4(model).inverse().transpose();
        Self {
            model: model.to_cols_array_2d(),
            normal_matrix: [
                normal.x_axis.extend(0.0).to_array(),
                normal.y_axis.extend(0.0).to_array(),
                normal.z_axis.extend(0.0).to_array(),
            ],
            material_index: object.material as u32,
            shadowing_lights,
            own_occluders: occlusion.own.0 as u32 | (occlusion.own.1 as u32) << 16,
            vertex_light_first,
        }
    }
}

pub struct GpuMesh {
    /// Read as vertices by the draws, and as a storage buffer by the computation of what
    /// they read at them (vertex_light.rs).
    pub vertices: Buffer,
    pub vertex_count: u32,
    pub indices: Buffer,
    pub index_count: u32,
    /// Where the mesh bounds a solid (`Mesh::bounds_solid`), its bounding sphere in object
    /// space: seen from outside it, its back faces are culled.
    pub solid: Option<(Vec3, f32)>,
    pub extent: MeshExtent,
}

impl GpuMesh {
    pub fn upload(device: &Arc<Device>, one_shot: &OneShot, mesh: &Mesh) -> Result<Self> {
        ensure!(!mesh.indices.is_empty(), "mesh '{}' has no triangles", mesh.name);
        Ok(Self {
            vertices: Buffer::with_data(
                device,
                one_shot,
                &mesh.vertices,
                vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
                &mesh.name,
            )?,
            vertex_count: mesh.vertices.len() as u32,
            indices: Buffer::with_data(
                device,
                one_shot,
                &mesh.indices,
                vk::BufferUsageFlags::INDEX_BUFFER,
                &mesh.name,
            )?,
            index_count: mesh.indices.len() as u32,
            solid: mesh.bounds_solid().then(|| mesh.bounding_sphere()),
            extent: mesh.extent(),
        })
    }
}

/// The scene on the GPU, uploaded once: meshes, and each material's maps as set 1 of the
/// forward pass (placeholders where a material has no map).
pub struct GpuScene {
    /// Which upload of its renderer this is: what the shadow maps were rendered from.
    pub id: u64,
    pub meshes: Vec<GpuMesh>,
    /// Set 1 for each material of the scene, in `Scene::materials` order.
    pub material_sets: Vec<vk::DescriptorSet>,
    /// Owns `material_sets`.
    _material_pool: DescriptorPool,
    /// Read by the material sets.
    textures: Vec<GpuTexture>,
    placeholders: Vec<GpuTexture>,
    sampler: Sampler,
}

/// The placeholder bound where a material has no map of a slot: white colour or data, a
/// flat normal. The shader never samples it (the slot's bit of `MAPS` is off).
fn placeholder_of(slot: MapSlot) -> TextureData {
    let info = slot.info();
    let (format, texel) = match info.role {
        TextureRole::BaseColor => (TexelFormat::Rgba8Srgb, [255; 4]),
        TextureRole::Normal => (TexelFormat::Rgba8Unorm, [128, 128, 255, 255]),
        TextureRole::Data => (TexelFormat::Rgba8Unorm, [255; 4]),
    };
    placeholder(&format!("no {}", info.label), format, texel)
}

impl GpuScene {
    pub fn upload(
        device: &Arc<Device>,
        one_shot: &OneShot,
        scene: &Scene,
        material_layout: &DescriptorSetLayout,
        id: u64,
    ) -> Result<Self> {
        let meshes = scene
            .meshes
            .iter()
            .map(|m| GpuMesh::upload(device, one_shot, m))
            .collect::<Result<_>>()?;
        let textures: Vec<GpuTexture> = scene
            .textures
            .iter()
            .map(|t| GpuTexture::upload(device, one_shot, t))
            .collect::<Result<_>>()?;
        let placeholders: Vec<GpuTexture> = MapSlot::ALL
            .iter()
            .map(|&slot| GpuTexture::upload(device, one_shot, &placeholder_of(slot)))
            .collect::<Result<_>>()?;
        let pool = DescriptorPool::for_layout(device, material_layout, scene.materials.len().max(1) as u32)?;
        let material_sets = (0..scene.materials.len())
            .map(|_| pool.allocate(material_layout))
            .collect::<Result<_>>()?;
        let gpu = Self {
            id,
            meshes,
            material_sets,
            _material_pool: pool,
            textures,
            placeholders,
            sampler: Sampler::material(device)?,
        };
        gpu.write_material_sets(device, scene);
        Ok(gpu)
    }

    /// Uploads textures `indices` of `scene` in place of the ones uploaded before, and
    /// points the material sets at them: `scene` is the one uploaded, those textures made
    /// since its stand-ins were (`PendingMaps`). No frame that reads the sets may be
    /// running.
    pub fn replace_textures(
        &mut self,
        device: &Arc<Device>,
        one_shot: &OneShot,
        scene: &Scene,
        indices: &[usize],
    ) -> Result<()> {
        ensure!(
            scene.textures.len() == self.textures.len() && scene.materials.len() == self.material_sets.len(),
            "the scene is not the one uploaded"
        );
        for &i in indices {
            self.textures[i] = GpuTexture::upload(device, one_shot, &scene.textures[i])?;
        }
        self.write_material_sets(device, scene);
        Ok(())
    }

    /// Points each material's set at its maps' textures, and at placeholders where it has
    /// none.
    fn write_material_sets(&self, device: &Arc<Device>, scene: &Scene) {
        for (material, &set) in scene.materials.iter().zip(&self.material_sets) {
            let writer = material.maps.iter().zip(&self.placeholders).fold(
                DescriptorWriter::default(),
                |writer, ((slot, map), placeholder)| {
                    let texture = map.as_ref().map_or(placeholder, |m| &self.textures[m.texture]);
                    writer.image(
                        slot.index() as u32,
                        vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                        texture.image.view,
                        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                        self.sampler.handle,
                    )
                },
            );
            writer.write(device, set);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    
    /// The shaders' limits are the Rust ones, and FrameData's occluders lie where std140
    /// puts them: after the ground's two vec4s, 32 bytes each.
    #[test]
    fn limits_and_occluders_match_scene_data_glsl() {
        let glsl = include_str!("../../shaders/lib/scene_data.glsl");
        assert!(glsl.contains(&format!("#define MAX_POINT_LIGHTS {MAX_POINT_LIGHTS}\n")));
        assert!(glsl.contains(&format!("#define MAX_OCCLUDERS {MAX_OCCLUDERS}\n")));
        assert!(glsl.contains(concat!(
            "    vec4 ground_albedo;  // rgb its albedo, a 1 where it bounces light (bounce.glsl), else 0\n",
            "    Occluder occluders[MAX_OCCLUDERS];\n} frame;"
        )));
        assert_eq!(
            std::mem::offset_of!(FrameData, occluders),
            std::mem::offset_of!(FrameData, ground_albedo) + 16
        );
        assert_eq!(std::mem::size_of::<FrameData>() - std::mem::offset_of!(FrameData, occluders), 32 * MAX_OCCLUDERS);
    }

    /// The push constants' fields sit where the shaders' block has them.
    #[test]
    fn object_push_is_the_shaders_block() {
        let glsl = include_str!("../../shaders/lib/scene_data.glsl");
        assert!(glsl.contains(concat!(
            "    mat4 model;\n",
            "    vec4 normal_matrix[3];  // columns of the inverse-transpose of model's 3x3\n",
            "    uint material_index;\n",
            "    uint shadowing_lights;  // bit i: point light i may shadow it (Scene::shadowing_lights)\n",
            "    uint own_occluders;  // the run of frame.occluders that is this object: first | count << 16\n",
            "    uint vertex_light_first;  // its first vertex in what the draws read there (vertex_light.rs)\n",
        )));
        assert_eq!(std::mem::offset_of!(ObjectPush, shadowing_lights), 116);
        assert_eq!(std::mem::offset_of!(ObjectPush, own_occluders), 120);
        assert_eq!(std::mem::offset_of!(ObjectPush, vertex_light_first), 124);
        assert_eq!(std::mem::size_of::<ObjectPush>(), 128, "Vulkan's least maxPushConstantsSize");
    }

    #[test]
    fn where_the_objects_occlusion_comes_from_is_the_shaders() {
        let glsl = include_str!("../../shaders/lib/object_occlusion.glsl");
        for (from, name) in [
            (ObjectsOcclusionFrom::Pixels, "PIXELS"),
            (ObjectsOcclusionFrom::Vertices, "VERTICES"),
            (ObjectsOcclusionFrom::GroundMap, "GROUND_MAP"),
        ] {
            let line = format!("const uint OBJECTS_OCCLUSION_FROM_{name} = {}u;", from as u32);
            assert!(glsl.contains(&line), "{line}");
        }
    }

}
