//! The scene on the GPU: vertex and index buffers per mesh, and the per-frame data that
//! the forward pass reads (`shaders/lib/scene_data.glsl` declares the same layouts).

use std::sync::Arc;

use anyhow::{ensure, Result};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Mat4};

use crate::scene::{Material, Mesh, Object, Scene};
use crate::vk::{Buffer, Device, OneShot};

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
}

impl FrameData {
    pub fn new(scene: &Scene, aspect: f32) -> Result<Self> {
        ensure!(
            scene.lights.len() <= MAX_POINT_LIGHTS,
            "the scene has {} point lights; at most {MAX_POINT_LIGHTS} are supported",
            scene.lights.len()
        );
        let view_proj = scene.camera.projection(aspect) * scene.camera.view();
        let mut lights = [PointLightData::zeroed(); MAX_POINT_LIGHTS];
        for (slot, light) in lights.iter_mut().zip(&scene.lights) {
            slot.position = light.position.extend(1.0).to_array();
            slot.intensity = light.intensity.extend(0.0).to_array();
        }
        Ok(Self {
            view_proj: view_proj.to_cols_array_2d(),
            camera_position: scene.camera.position.extend(1.0).to_array(),
            counts: [scene.lights.len() as u32, 0, 0, 0],
            lights,
        })
    }
}

/// `Material` (std430).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct MaterialData {
    pub base_color: [f32; 4],
    pub specular_color: [f32; 4],
    pub wrap_color: [f32; 4],
    pub roughness: f32,
    pub f0: f32,
    pub diffuse_roughness: f32,
    pub wrap: f32,
    pub wrap_width: f32,
    pub pad: [f32; 3],
}

impl From<&Material> for MaterialData {
    fn from(m: &Material) -> Self {
        Self {
            base_color: m.base_color.extend(1.0).to_array(),
            specular_color: m.specular_color.extend(1.0).to_array(),
            wrap_color: m.wrap_color.extend(m.wrap_intensity).to_array(),
            roughness: m.roughness,
            f0: m.f0,
            diffuse_roughness: m.diffuse_roughness,
            wrap: m.wrap,
            wrap_width: m.wrap_width,
            pad: [0.0; 3],
        }
    }
}

/// `ObjectPush`: the push constants of one draw.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ObjectPush {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 3],
    pub material_index: u32,
    pub pad: [u32; 3],
}

impl ObjectPush {
    pub fn new(object: &Object) -> Self {
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
            pad: [0; 3],
        }
    }
}

pub struct GpuMesh {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
}

impl GpuMesh {
    pub fn upload(device: &Arc<Device>, one_shot: &OneShot, mesh: &Mesh) -> Result<Self> {
        ensure!(!mesh.indices.is_empty(), "mesh '{}' has no triangles", mesh.name);
        Ok(Self {
            vertices: Buffer::with_data(device, one_shot, &mesh.vertices, vk::BufferUsageFlags::VERTEX_BUFFER, &mesh.name)?,
            indices: Buffer::with_data(device, one_shot, &mesh.indices, vk::BufferUsageFlags::INDEX_BUFFER, &mesh.name)?,
            index_count: mesh.indices.len() as u32,
        })
    }
}

/// The scene's meshes on the GPU, uploaded once.
pub struct GpuScene {
    pub meshes: Vec<GpuMesh>,
}

impl GpuScene {
    pub fn upload(device: &Arc<Device>, one_shot: &OneShot, scene: &Scene) -> Result<Self> {
        let meshes = scene.meshes.iter().map(|m| GpuMesh::upload(device, one_shot, m)).collect::<Result<_>>()?;
        Ok(Self { meshes })
    }
}
