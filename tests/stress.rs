//! Whole frames under numerically hostile conditions: every model at roughness 0 and 1, a
//! grazing camera, a mesh of zero-area and UV-degenerate triangles with zero-length
//! normals, lights inside and on objects. Each frame must have no NaN/Inf value (checked
//! by `common::render`) and produce no validation error.

mod common;

use argil::render::OffscreenFrame;
use common::{render, scene};

/// The fraction of pixels an object covers (alpha is coverage), so a test knows its frame
/// drew something.
fn coverage(frame: &OffscreenFrame) -> f64 {
    let covered = frame.hdr.chunks_exact(4).filter(|p| p[3] > 0.0).count();
    covered as f64 / (frame.width * frame.height) as f64
}

const DIFFUSE: [&str; 4] = ["lambert", "oren-nayar", "eon", "none"];
const SPECULAR: [&str; 4] = ["cook-torrance", "torrance-sparrow", "blinn-phong", "none"];

/// Materials `m0…` covering every diffuse × specular pair at the given roughness, with both
/// distributions and geometries, maximal diffuse roughness and the wrap term on.
fn all_materials(roughness: f64, f0: f64) -> (String, usize) {
    let mut text = String::new();
    let mut count = 0;
    for (i, diffuse) in DIFFUSE.iter().enumerate() {
        for (j, specular) in SPECULAR.iter().enumerate() {
            let distribution = if (i + j) % 2 == 0 { "ggx" } else { "beckmann" };
            let geometry = if i % 2 == 0 {
                "smith-correlated"
            } else {
                "smith-separable"
            };
            text += &format!(
                "[materials.m{count}]\nbase_color = [1.0, 1.0, 1.0]\ndiffuse = \"{diffuse}\"\nspecular = \"{specular}\"\n\
                 distribution = \"{distribution}\"\ngeometry = \"{geometry}\"\nroughness = {roughness}\nf0 = {f0}\n\
                 diffuse_roughness = 1.0\nwrap = 1.0\nwrap_width = 0.0001\nwrap_intensity = 1.0\n\n"
            );
            count += 1;
        }
    }
    (text, count)
}

/// A row of small spheres, one per material, lit by `lights` and seen from `camera`.
fn spheres(camera: &str, lights: &str, roughness: f64, f0: f64) -> String {
    let (materials, count) = all_materials(roughness, f0);
    let objects: String = (0..count)
        .map(|k| {
            let x = (k % 4) as f64 * 0.6 - 0.9;
            let y = (k / 4) as f64 * 0.6 - 0.9;
            format!("[[objects]]\nmesh = \"builtin:sphere\"\nposition = [{x}, {y}, 0.0]\nscale = 0.25\nmaterial = \"m{k}\"\n\n")
        })
        .collect();
    format!("{camera}\n{lights}\n[environment]\nkind = \"uniform\"\nradiance = [0.1, 0.1, 0.1]\n\n{objects}\n[[objects]]\nmesh = \"builtin:plane\"\nposition = [0.0, -1.25, 0.0]\nscale = 4.0\nmaterial = \"m5\"\n\n{materials}")
}

const FRONT_CAMERA: &str = "[camera]\nposition = [0.0, 0.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_degrees = 45.0\n";
const GRAZING_CAMERA: &str =
    "[camera]\nposition = [0.0, -1.2499, 4.0]\ntarget = [0.0, -1.25, 0.0]\nfov_y_degrees = 60.0\n";
const HEAD_ON_LIGHT: &str =
    "[[lights]]\nkind = \"point\"\nposition = [0.0, 0.0, 4.0]\nintensity = [50.0, 50.0, 50.0]\n";
/// Lights at a sphere's centre, exactly on a sphere's surface, and grazing the plane.
const HOSTILE_LIGHTS: &str =
    "[[lights]]\nkind = \"point\"\nposition = [-0.9, -0.9, 0.0]\nintensity = [1000.0, 1000.0, 1000.0]\n\n\
[[lights]]\nkind = \"point\"\nposition = [-0.3, -0.65, 0.0]\nintensity = [1000.0, 1000.0, 1000.0]\n\n\
[[lights]]\nkind = \"point\"\nposition = [3.0, -1.25, 0.0]\nintensity = [100.0, 100.0, 100.0]\n";

#[test]
fn every_model_at_roughness_zero_and_one_stays_finite() {
    for roughness in [0.0, 1.0] {
        for f0 in [0.0, 1.0] {
            for camera in [FRONT_CAMERA, GRAZING_CAMERA] {
                for lights in [HEAD_ON_LIGHT, HOSTILE_LIGHTS] {
                    let frame = render(&scene(&spheres(camera, lights, roughness, f0)), 96, 96);
                    assert!(coverage(&frame) > 0.1, "the spheres and the plane cover the frame");
                }
            }
        }
    }
}

/// Zero-area triangles, a triangle whose UVs are all equal, one whose UVs are collinear,
/// zero-length normals in the file, and a vertex repeated in one face.
const DEGENERATE_OBJ: &str = "\
v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\nv 0.5 0.5 0\nv 1 1 1e-30\n\
vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n\
vn 0 0 0\nvn 0 0 1\n\
f 1/1/1 2/2/1 3/3/1\n\
f 2/4/2 4/4/2 3/4/2\n\
f 1/1/2 5/2/2 2/2/2\n\
f 1/1/1 6/4/1 4/1/1\n\
f 4/1/2 4/2/2 4/3/2\n\
f 3/1/1 4/2/1 7/3/1\n";

#[test]
fn degenerate_mesh_renders_finite() {
    let dir = common::test_dir("stress");
    std::fs::write(dir.join("degenerate.obj"), DEGENERATE_OBJ).expect("write obj");
    let (materials, count) = all_materials(0.5, 0.04);
    for k in 0..count {
        let text = format!(
            "{FRONT_CAMERA}\n{HEAD_ON_LIGHT}\n[[objects]]\nmesh = \"degenerate.obj\"\nposition = [-0.5, -0.5, 0.0]\nmaterial = \"m{k}\"\n\n{materials}"
        );
        let scene = argil::scene::Scene::from_toml(&text, "degenerate scene", &dir).expect("scene loads");
        let frame = render(&scene, 64, 64);
        assert!(coverage(&frame) > 0.01, "the degenerate mesh is visible");
    }
}
