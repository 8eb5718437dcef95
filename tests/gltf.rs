//! glTF 2.0 models, written by the tests (JSON and a binary buffer, as .gltf with an
//! external or a `data:` buffer, or as .glb): their geometry in world space as OBJ files
//! give it, and bad files refused with exit code 2 and a message naming the file.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use argil::scene::{MapSlot, Mesh, Scene, Vertex};
use base64::Engine;
use glam::{Mat3, Mat4, Vec3, Vec4};
use serde_json::{json, Value};

use common::{argil, test_dir};


/// One primitive's vertex data, in argil's UV convention (v up; the file gets 1 - v).
#[derive(Clone)]
struct Primitive {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Vec<[f32; 2]>,
    tangents: Option<Vec<[f32; 4]>>,
    indices: Vec<u32>,
}

/// How the buffer is stored.
#[derive(Clone, Copy, Debug)]
enum Storage {
    /// `.gltf` beside `NAME.bin`.
    External,
    /// `.gltf` with the buffer in a `data:` URI.
    DataUri,
    /// `.glb`.
    Binary,
}

/// A model: its JSON (without `buffers`) and the one buffer's bytes.
struct Model {
    json: Value,
    bin: Vec<u8>,
}

/// The buffer being laid out, with its views and accessors.
#[derive(Default)]
struct Layout {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Layout {
    /// Appends `bytes` (4-byte aligned) as a view with one accessor; its index.
    fn push(&mut self, bytes: Vec<u8>, count: usize, component: u32, kind: &str) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let view = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        self.views.push(view);
        self.bin.extend(bytes);
        let accessor =
            json!({"bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": kind});
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn floats<const N: usize>(&mut self, values: &[[f32; N]], kind: &str) -> usize {
        let bytes = values.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        self.push(bytes, values.len(), 5126, kind)
    }
}

impl Model {
    /// One mesh per primitive (mesh i holds primitive i), and `nodes` as given with a
    /// scene of `roots`.
    fn new(primitives: &[Primitive], nodes: Value, roots: &[usize]) -> Model {
        let mut layout = Layout::default();
        let mut meshes = Vec::new();
        for p in primitives {
            let mut attributes = serde_json::Map::new();
            let position = layout.floats(&p.positions, "VEC3");
            // glTF requires the bounds of POSITION.
            let (min, max) = p.positions.iter().fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), q| {
                ([0, 1, 2].map(|i| lo[i].min(q[i])), [0, 1, 2].map(|i| hi[i].max(q[i])))
            });
            layout.accessors[position]["min"] = json!(min);
            layout.accessors[position]["max"] = json!(max);
            attributes.insert("POSITION".into(), json!(position));
            if let Some(normals) = &p.normals {
                attributes.insert("NORMAL".into(), json!(layout.floats(normals, "VEC3")));
            }
            let uvs: Vec<[f32; 2]> = p.uvs.iter().map(|&[u, v]| [u, 1.0 - v]).collect();
            attributes.insert("TEXCOORD_0".into(), json!(layout.floats(&uvs, "VEC2")));
            if let Some(tangents) = &p.tangents {
                attributes.insert("TANGENT".into(), json!(layout.floats(tangents, "VEC4")));
            }
            let indices = p.indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect();
            let indices = layout.push(indices, p.indices.len(), 5123, "SCALAR");
            meshes.push(json!({"primitives": [{"attributes": attributes, "indices": indices}]}));
        }
        let Layout { bin, views, accessors } = layout;
        let json = json!({
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": roots}],
            "nodes": nodes,
            "meshes": meshes,
            "accessors": accessors,
            "bufferViews": views,
        });
        Model { json, bin }
    }

    /// Writes the model as `dir/NAME.gltf` (or `.glb`) and returns its path.
    fn write(&self, dir: &Path, name: &str, storage: Storage) -> PathBuf {
        let mut json = self.json.clone();
        let length = self.bin.len();
        let path = match storage {
            Storage::External => {
                std::fs::write(dir.join(format!("{name} data.bin")), &self.bin).expect("write bin");
                // A space in the name, percent-encoded as URIs are.
                json["buffers"] = json!([{"uri": format!("{name}%20data.bin"), "byteLength": length}]);
                dir.join(format!("{name}.gltf"))
            }
            Storage::DataUri => {
                let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
                json["buffers"] =
                    json!([{"uri": format!("data:application/octet-stream;base64,{data}"), "byteLength": length}]);
                dir.join(format!("{name}.gltf"))
            }
            Storage::Binary => {
                json["buffers"] = json!([{"byteLength": length}]);
                let path = dir.join(format!("{name}.glb"));
                std::fs::write(&path, glb(&serde_json::to_vec(&json).expect("json"), &self.bin)).expect("write glb");
                return path;
            }
        };
        std::fs::write(&path, serde_json::to_vec_pretty(&json).expect("json")).expect("write gltf");
        path
    }
}

/// A .glb file: the header, the JSON chunk (padded with spaces) and the BIN chunk.
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |bytes: &[u8], with: u8| {
        let mut padded = bytes.to_vec();
        while padded.len() % 4 != 0 {
            padded.push(with);
        }
        padded
    };
    let (json, bin) = (pad(json, b' '), pad(bin, 0));
    let length = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(length);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((length as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// The same primitive in world space as an OBJ file: `world` applied as the loader
/// documents it (positions, inverse-transpose normals, winding reversed by a mirror).
fn write_obj(path: &Path, p: &Primitive, world: Mat4) {
    let linear = Mat3::from_mat4(world);
    let normal_matrix = linear.inverse().transpose();
    let mut text = String::new();
    for q in &p.positions {
        let q = world.transform_point3(Vec3::from(*q));
        text += &format!("v {} {} {}\n", q.x, q.y, q.z);
    }
    for n in p.normals.iter().flatten() {
        let n = normal_matrix * Vec3::from(*n);
        text += &format!("vn {} {} {}\n", n.x, n.y, n.z);
    }
    for [u, v] in &p.uvs {
        text += &format!("vt {u} {v}\n");
    }
    for t in p.indices.chunks_exact(3) {
        let mut t = [t[0] + 1, t[1] + 1, t[2] + 1];
        if linear.determinant() < 0.0 {
            t.swap(1, 2);
        }
        let corner = |i: u32| match p.normals {
            Some(_) => format!("{i}/{i}/{i}"),
            None => format!("{i}/{i}"),
        };
        text += &format!("f {} {} {}\n", corner(t[0]), corner(t[1]), corner(t[2]));
    }
    std::fs::write(path, text).expect("write obj");
}

/// A smooth-shaded octahedron (normals given) of radius 1.
fn octahedron() -> Primitive {
    // Numbered in the order the triangles first use them, as an OBJ file's loader numbers them.
    let positions = vec![
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        [0.0, -1.0, 0.0],
    ];
    let uvs = vec![
        [0.0, 0.5],
        [0.25, 1.0],
        [0.25, 0.5],
        [0.5, 0.5],
        [0.75, 0.5],
        [0.75, 0.0],
    ];
    let indices = vec![0, 1, 2, 2, 1, 3, 3, 1, 4, 4, 1, 0, 0, 2, 5, 2, 3, 5, 3, 4, 5, 4, 0, 5];
    Primitive {
        normals: Some(positions.clone()),
        positions,
        uvs,
        tangents: None,
        indices,
    }
}

/// A flat-shaded (no normals) tetrahedron whose corners are unshared, as glTF's flat
/// shading makes them.
fn tetrahedron() -> Primitive {
    let corners = [[1.0, 1.0, 1.0], [-1.0, -1.0, 1.0], [-1.0, 1.0, -1.0], [1.0, -1.0, -1.0]];
    let faces = [[0, 1, 3], [0, 2, 1], [0, 3, 2], [1, 2, 3]];
    let positions: Vec<[f32; 3]> = faces.iter().flatten().map(|&i| corners[i]).collect();
    let uvs = (0..12).map(|i| [(i % 3) as f32 * 0.5, (i / 3) as f32 * 0.25]).collect();
    Primitive {
        indices: (0..12).collect(),
        positions,
        normals: None,
        uvs,
        tangents: None,
    }
}

/// The test model's nodes, with transforms whose arithmetic is exact in f32 so that the
/// OBJ files can hold the same world-space numbers: the octahedron translated and scaled;
/// the tetrahedron under a parent turning it 90° about y (an exact `matrix`) and mirrored
/// (scale x -1) beneath it.
fn nodes() -> (Value, [Mat4; 2]) {
    let nodes = json!([
        {"mesh": 0, "translation": [-1.25, 0.0, 0.5], "scale": [0.75, 0.75, 0.75]},
        {"matrix": [0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.25, 0.0, 1.0], "children": [2]},
        {"mesh": 1, "scale": [-0.5, 0.5, 0.5]},
    ]);
    let octahedron = Mat4::from_translation(Vec3::new(-1.25, 0.0, 0.5)) * Mat4::from_scale(Vec3::splat(0.75));
    let parent = Mat4::from_cols_array(&[
        0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.25, 0.0, 1.0,
    ]);
    (
        nodes,
        [octahedron, parent * Mat4::from_scale(Vec3::new(-0.5, 0.5, 0.5))],
    )
}

fn scene_text(objects: &[&str]) -> String {
    let mut text = String::from(
        r#"
[camera]
position = [0.5, 1.5, 4.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 40.0

[[lights]]
kind = "point"
position = [2.0, 3.0, 3.0]
intensity = [20.0, 18.0, 16.0]

[environment]
kind = "uniform"
radiance = [0.2, 0.2, 0.25]

[materials.clay]
base_color = [0.7, 0.45, 0.3]
roughness = 0.5
"#,
    );
    for mesh in objects {
        text += &format!("\n[[objects]]\nmesh = {mesh:?}\nposition = [0.25, 0.0, 0.0]\nmaterial = \"clay\"\n");
    }
    text
}

/// Each primitive as `partN.obj` in `dir`, in world space.
fn write_parts(dir: &Path, primitives: &[Primitive], worlds: [Mat4; 2]) {
    for (i, (p, world)) in primitives.iter().zip(worlds).enumerate() {
        write_obj(&dir.join(format!("part{i}.obj")), p, world);
    }
}

/// The two parts as objects where the model's tests place it, with these materials.
fn parts_with(materials: [&str; 2]) -> String {
    materials
        .iter()
        .enumerate()
        .map(|(i, m)| format!("\n[[objects]]\nmesh = \"part{i}.obj\"\nposition = [0.25, 0.0, 0.0]\nmaterial = \"{m}\""))
        .collect()
}

/// The model's objects have the materials of the OBJ scene's, names aside.
fn assert_same_materials(scene: &Scene, obj: &Scene) {
    for (model_object, obj_object) in scene.objects.iter().zip(&obj.objects) {
        let (a, b) = (
            &scene.materials[model_object.material],
            &obj.materials[obj_object.material],
        );
        assert_eq!(
            argil::scene::Material {
                name: b.name.clone(),
                ..a.clone()
            },
            *b
        );
    }
}

fn load(dir: &Path, name: &str, text: &str) -> Scene {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write scene");
    Scene::load(&path).expect("scene loads")
}

/// Each primitive of the model's scene is a part in world space, with its node's transform
/// baked in: the frames of a .gltf with an external buffer, one with a `data:` buffer and a
/// .glb equal, bit for bit, the frame of the same geometry as two OBJ files. Corner for
/// corner the vertices are the OBJ files' but for the octahedron's tangents: those are
/// MikkTSpace's, as glTF asks (the frame has no normal map, which would show them), and
/// split its vertices where its UVs turn over, 6 into 14.
#[test]
fn a_model_renders_as_its_geometry_written_as_obj() {
    let dir = test_dir("geometry");
    let primitives = [octahedron(), tetrahedron()];
    let (nodes, worlds) = nodes();
    let model = Model::new(&primitives, nodes, &[0, 1]);
    write_parts(&dir, &primitives, worlds);
    let obj = load(&dir, "obj.toml", &scene_text(&["part0.obj", "part1.obj"]));
    assert!(obj.warnings.is_empty());
    let expected = common::render(&obj, 96, 64);
    for storage in [Storage::External, Storage::DataUri, Storage::Binary] {
        let path = model.write(&dir, "model", storage);
        let name = path.file_name().and_then(|n| n.to_str()).expect("name");
        let scene = load(&dir, "model.toml", &scene_text(&[name]));
        assert_eq!(scene.warnings, Vec::<String>::new(), "{storage:?}");
        assert_eq!((scene.meshes.len(), scene.objects.len()), (2, 2), "{storage:?}");
        let corners = |mesh: &Mesh| -> Vec<Vertex> {
            let corner = |i: &u32| Vertex {
                tangent: [0.0; 4],
                ..mesh.vertices[*i as usize]
            };
            mesh.indices.iter().map(corner).collect()
        };
        for (part, (mesh, obj_mesh)) in scene.meshes.iter().zip(&obj.meshes).enumerate() {
            assert_eq!(scene.objects[part].part, part);
            assert_eq!(corners(mesh), corners(obj_mesh), "{storage:?} part {part}");
        }
        let [octahedron, tetrahedron] = [0, 1].map(|part| (&scene.meshes[part], &obj.meshes[part]));
        assert_eq!((octahedron.0.vertices.len(), octahedron.1.vertices.len()), (14, 6));
        // Flat-shaded, the tetrahedron's tangents are argil's own, as the OBJ file's.
        assert_eq!(tetrahedron.0.indices, tetrahedron.1.indices, "{storage:?}");
        assert_eq!(tetrahedron.0.vertices, tetrahedron.1.vertices, "{storage:?}");
        let frame = common::render(&scene, 96, 64);
        assert!(
            frame.display == expected.display,
            "{storage:?}: the frame differs from the OBJ files'"
        );

        // Saved, the model is one object again.
        let saved = scene.to_file_at(&dir.join("saved.toml"));
        assert_eq!(saved.objects.len(), 1);
        assert_eq!(saved.objects[0].mesh, name);
    }
}

/// Tangents given by the file are kept (made orthogonal to the normal), turned with the
/// node and their handedness flipped by a mirror; without them they are MikkTSpace's.
#[test]
fn tangents_from_the_file_are_kept_and_mirrored() {
    let dir = test_dir("tangents");
    let mut quad = Primitive {
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
        uvs: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        // Deliberately not the UVs' direction (+x), and not orthogonal to the normal.
        tangents: Some(vec![[0.0, 2.0, 1.0, -1.0]; 4]),
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    let nodes = json!([{"mesh": 0}, {"mesh": 0, "scale": [-1.0, 1.0, 1.0]}]);
    let path = Model::new(&[quad.clone()], nodes, &[0, 1]).write(&dir, "quad", Storage::Binary);
    let scene = load(
        &dir,
        "quad.toml",
        &scene_text(&[path.file_name().and_then(|n| n.to_str()).expect("name")]),
    );
    let [plain, mirrored] = [0, 1].map(|i| &scene.meshes[scene.objects[i].mesh]);
    for v in &plain.vertices {
        assert_eq!(Vec4::from(v.tangent), Vec4::new(0.0, 1.0, 0.0, -1.0));
    }
    for v in &mirrored.vertices {
        assert_eq!(Vec4::from(v.tangent), Vec4::new(0.0, 1.0, 0.0, 1.0));
    }
    // The mirror reverses the winding, so the quad still faces its (unchanged) normal.
    assert_eq!(mirrored.indices, [0, 2, 1, 0, 3, 2]);

    quad.tangents = None;
    let computed = Model::new(&[quad], json!([{"mesh": 0}]), &[0]).write(&dir, "computed", Storage::Binary);
    let scene = load(&dir, "computed.toml", &scene_text(&["computed.glb"]));
    assert!(computed.exists());
    for v in &scene.meshes[0].vertices {
        assert_eq!(Vec4::from(v.tangent), Vec4::new(1.0, 0.0, 0.0, 1.0));
    }
}

/// Two unit quads side by side, the right one's UVs mirrored about their shared edge, with
/// normals and no tangents.
fn mirrored_strip() -> Primitive {
    // Vertex i at (i mod 3, i div 3); u runs 0, 1, 0 along each row.
    Primitive {
        positions: (0..6).map(|i| [(i % 3) as f32, (i / 3) as f32, 0.0]).collect(),
        normals: Some(vec![[0.0, 0.0, 1.0]; 6]),
        uvs: (0..6).map(|i| [(i % 3 % 2) as f32, (i / 3) as f32]).collect(),
        tangents: None,
        indices: vec![0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4],
    }
}

/// A primitive with normals and UVs but no tangents gets MikkTSpace's, as glTF asks: on a
/// strip whose right half mirrors its UVs, the tangent follows u (+x with w = +1 on the
/// left, -x with w = -1 on the right) and only the two vertices on the mirror seam are
/// split, 6 into 8. Under a plain and a mirroring node, the parts equal those of the same
/// strip with those 8 vertices and their tangents written in the file.
#[test]
fn missing_tangents_are_mikktspace_s() {
    let dir = test_dir("mikktspace");
    let strip = mirrored_strip();
    let nodes = json!([
        {"mesh": 0, "translation": [-2.5, 0.0, 0.0]},
        {"mesh": 0, "translation": [2.5, 0.0, 0.0], "scale": [-1.0, 1.0, 1.0]},
    ]);
    Model::new(std::slice::from_ref(&strip), nodes.clone(), &[0, 1]).write(&dir, "generated", Storage::Binary);
    let mut written = strip.clone();
    for seam in [1, 4] {
        written.positions.push(strip.positions[seam]);
        written.uvs.push(strip.uvs[seam]);
    }
    written.normals = Some(vec![[0.0, 0.0, 1.0]; 8]);
    let (left, right) = ([1.0, 0.0, 0.0, 1.0], [-1.0, 0.0, 0.0, -1.0]);
    written.tangents = Some(vec![left, left, right, left, left, right, right, right]);
    written.indices = vec![0, 1, 4, 0, 4, 3, 6, 2, 5, 6, 5, 7];
    Model::new(std::slice::from_ref(&written), nodes, &[0, 1]).write(&dir, "written", Storage::Binary);

    let generated = load(&dir, "generated.toml", &scene_text(&["generated.glb"]));
    let expected = load(&dir, "written.toml", &scene_text(&["written.glb"]));
    assert_eq!(generated.warnings, Vec::<String>::new());
    let plain = &generated.meshes[generated.objects[0].mesh];
    let tangents: Vec<[f32; 4]> = plain.vertices.iter().map(|v| v.tangent).collect();
    assert_eq!(Some(tangents), written.tangents);
    for (part, (mesh, file)) in generated.meshes.iter().zip(&expected.meshes).enumerate() {
        assert_eq!(mesh.indices, file.indices, "part {part}");
        assert_eq!(mesh.vertices, file.vertices, "part {part}");
    }
}

/// What argil does not draw is named in one warning each: primitives of another mode,
/// extensions it ignores, animations.
#[test]
fn unsupported_parts_are_named_in_warnings() {
    let dir = test_dir("warnings");
    let mut model = Model::new(
        &[octahedron(), tetrahedron()],
        json!([{"mesh": 0}, {"mesh": 1}]),
        &[0, 1],
    );
    model.json["meshes"][1]["primitives"][0]["mode"] = json!(1);
    model.json["meshes"][0]["primitives"]
        .as_array_mut()
        .expect("primitives")
        .push(json!({"attributes": {"POSITION": 0}, "mode": 0}));
    model.json["extensionsUsed"] = json!(["KHR_materials_clearcoat"]);
    let path = model.write(&dir, "mixed", Storage::Binary);
    let scene = load(&dir, "mixed.toml", &scene_text(&["mixed.glb"]));
    assert_eq!(scene.objects.len(), 1, "only the triangles are drawn");
    let shown = path.display().to_string();
    assert_eq!(
        scene.warnings,
        [
            format!("{shown}: the extension KHR_materials_clearcoat is not supported and is ignored"),
            format!("{shown}: primitives of mode LINES are not drawn"),
            format!("{shown}: primitives of mode POINTS are not drawn"),
        ]
    );
    let out = dir.join("x.png");
    let o = argil(&[
        "render",
        &dir.join("mixed.toml").display().to_string(),
        "--out",
        &out.display().to_string(),
        "--width",
        "32",
        "--height",
        "32",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert_eq!(err.matches("argil: warning: ").count(), 3, "{err}");
}

/// `argil render` of `scene` to `out`, 16 × 16.
fn render_16(scene: &Path, out: &Path) -> Output {
    argil(&[
        "render",
        &scene.display().to_string(),
        "--out",
        &out.display().to_string(),
        "--width",
        "16",
        "--height",
        "16",
    ])
}

fn assert_refused(o: &Output, out: &Path, mentions: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "exit code: {err}");
    assert!(!err.contains("panicked"), "argil panicked: {err}");
    for m in mentions {
        assert!(err.contains(m), "the error does not mention {m:?}: {err}");
    }
    assert!(!out.exists(), "{} was written", out.display());
}

/// A bad model is refused with exit code 2 and a message naming the file and the problem,
/// and nothing is written.
#[test]
fn bad_models_are_clear_errors() {
    let dir = test_dir("bad");
    let good = Model::new(&[octahedron()], json!([{"mesh": 0}]), &[0]);
    let glb_bytes = std::fs::read(good.write(&dir, "good", Storage::Binary)).expect("read");
    let out = dir.join("x.png");
    let render = |model: &str| {
        let scene = dir.join(format!("{model}.toml"));
        std::fs::write(&scene, scene_text(&[model])).expect("write scene");
        render_16(&scene, &out)
    };
    let mut cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        (
            "truncated.glb",
            glb_bytes[..glb_bytes.len() / 2].to_vec(),
            &["truncated.glb", "truncated"],
        ),
        ("header.glb", glb_bytes[..6].to_vec(), &["header.glb", "truncated"]),
        (
            "json.gltf",
            b"{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [".to_vec(),
            &["json.gltf", "invalid glTF"],
        ),
    ];
    let variant = |change: &dyn Fn(&mut Value)| {
        let mut json = good.json.clone();
        json["buffers"] = json!([{"byteLength": good.bin.len()}]);
        change(&mut json);
        glb(&serde_json::to_vec(&json).expect("json"), &good.bin)
    };
    cases.push((
        "missing.gltf",
        {
            let mut json = good.json.clone();
            json["buffers"] = json!([{"uri": "nowhere.bin", "byteLength": good.bin.len()}]);
            serde_json::to_vec(&json).expect("json")
        },
        &["missing.gltf", "buffer 0", "nowhere.bin"],
    ));
    cases.push((
        "index.glb",
        variant(&|json| json["meshes"][0]["primitives"][0]["indices"] = json!(99)),
        &["index.glb", "invalid glTF"],
    ));
    // Indices past the vertices: the accessor is valid, its values are not.
    let mut far = good.bin.clone();
    let view = good.json["bufferViews"][3]["byteOffset"].as_u64().expect("offset") as usize;
    far[view..view + 2].copy_from_slice(&77u16.to_le_bytes());
    cases.push((
        "vertex.glb",
        {
            let mut json = good.json.clone();
            json["buffers"] = json!([{"byteLength": far.len()}]);
            glb(&serde_json::to_vec(&json).expect("json"), &far)
        },
        &["vertex.glb", "index 77", "out of range"],
    ));
    cases.push((
        "overrun.glb",
        variant(&|json| json["accessors"][0]["count"] = json!(600)),
        &["overrun.glb", "POSITION", "do not fit"],
    ));
    cases.push((
        "required.glb",
        variant(&|json| {
            json["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
            json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
        }),
        &["required.glb", "KHR_draco_mesh_compression", "not support"],
    ));
    cases.push((
        "cycle.glb",
        variant(&|json| json["nodes"] = json!([{"mesh": 0, "children": [0]}])),
        &["cycle.glb", "node 0"],
    ));
    for (name, bytes, mentions) in cases {
        std::fs::write(dir.join(name), bytes).expect("write model");
        assert_refused(&render(name), &out, mentions);
    }
    // Opened alone, as a scene of its own.
    let model = dir.join("truncated.glb").display().to_string();
    let o = argil(&["render", &model, "--out", &out.display().to_string()]);
    assert_refused(&o, &out, &["truncated.glb", "truncated"]);

    // Over the size limit: a sparse file, so nothing is really written.
    let huge = dir.join("huge.glb");
    let file = std::fs::File::create(&huge).expect("create");
    file.set_len(argil::scene::limits::MAX_GLTF_BYTES + 1).expect("set_len");
    assert_refused(&render("huge.glb"), &out, &["huge.glb", "at most"]);
    std::fs::remove_file(&huge).expect("remove");
}

/// Writes three 8 × 8 images into `dir`, each varying across it, and makes them the model's
/// textures 0, 1 and 2: `albedo map.png`, `normals.png` and `orm.png` (occlusion in red,
/// roughness in green, metallic in blue, each varying on its own).
fn add_maps(model: &mut Model, dir: &Path) {
    let albedo = image::RgbaImage::from_fn(8, 8, |x, y| {
        image::Rgba([40 + 25 * x as u8, 200 - 20 * y as u8, 90, 255])
    });
    albedo.save(dir.join("albedo map.png")).expect("write albedo");
    let normals = image::RgbaImage::from_fn(8, 8, |x, y| {
        image::Rgba([128 + 12 * x as u8, 128 - 10 * y as u8, 230, 255])
    });
    normals.save(dir.join("normals.png")).expect("write normals");
    let orm = image::RgbaImage::from_fn(8, 8, |x, y| {
        image::Rgba([255 - 20 * y as u8, 60 + 24 * x as u8, 30 * ((x + y) % 8) as u8, 255])
    });
    orm.save(dir.join("orm.png")).expect("write orm");
    model.json["images"] = json!([{"uri": "albedo%20map.png"}, {"uri": "normals.png"}, {"uri": "orm.png"}]);
    model.json["textures"] = json!([{"source": 0}, {"source": 1}, {"source": 2}]);
}

/// A scene's inputs, the files the viewer watches, are every file its loading read: a
/// model's own file, its external buffer and the images its materials name; a model with
/// a `data:` buffer brings no file but its own.
#[test]
fn a_scene_lists_every_file_a_model_read() {
    let dir = test_dir("inputs");
    let (nodes, _) = nodes();
    let mut model = Model::new(&[octahedron(), tetrahedron()], nodes, &[0, 1]);
    add_maps(&mut model, &dir);
    model.json["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    model.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    model.write(&dir, "external", Storage::External);
    model.write(&dir, "inline", Storage::DataUri);
    let objects = ["external.gltf", "inline.gltf", "external.gltf"].map(|m| format!("\n[[objects]]\nmesh = {m:?}\n"));
    let scene = load(&dir, "inputs.toml", &(scene_text(&[]) + &objects.concat()));
    let albedo = std::path::absolute(dir.join("albedo map.png")).expect("absolute");
    assert_eq!(
        scene.inputs,
        [dir.join("external.gltf"), dir.join("external data.bin"), dir.join("inline.gltf"), albedo]
    );
}

/// A model's materials are argil materials: the base colour factor and texture, the
/// metallic and roughness factors (both glTF's roughness and argil's are perceptual, α =
/// roughness²) and their one texture as `roughness_map` and `metallic_map`, the normal
/// texture with its scale and the occlusion texture with its strength (clamped to argil's
/// range, and named in a warning). The model draws bit for bit as its geometry in OBJ
/// files with those materials written as tables; the normal map is on the flat-shaded
/// tetrahedron, whose tangents argil computes as an OBJ file's (the octahedron's are
/// MikkTSpace's).
#[test]
fn a_model_brings_its_materials() {
    let dir = test_dir("materials");
    let primitives = [octahedron(), tetrahedron()];
    let (nodes, worlds) = nodes();
    let mut model = Model::new(&primitives, nodes, &[0, 1]);
    add_maps(&mut model, &dir);
    model.json["materials"] = json!([
        {
            "name": "glaze",
            "pbrMetallicRoughness": {
                "baseColorFactor": [0.75, 0.5, 0.25, 1.0],
                "baseColorTexture": {"index": 0},
                "metallicFactor": 0.25,
                "roughnessFactor": 0.375,
                "metallicRoughnessTexture": {"index": 2},
            },
            "occlusionTexture": {"index": 2, "strength": 0.75},
        },
        {
            "pbrMetallicRoughness": {
                "metallicFactor": 1.0,
                "roughnessFactor": 0.625,
                "metallicRoughnessTexture": {"index": 2},
            },
            "normalTexture": {"index": 1, "scale": 0.5},
            "occlusionTexture": {"index": 2, "strength": 9.0},
        },
    ]);
    model.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    model.json["meshes"][1]["primitives"][0]["material"] = json!(1);
    model.write(&dir, "model", Storage::Binary);
    let path = dir.join("model.toml");
    std::fs::write(
        &path,
        scene_text(&[]) + "\n[[objects]]\nmesh = \"model.glb\"\nposition = [0.25, 0.0, 0.0]\n",
    )
    .expect("write scene");
    let scene = Scene::load(&path).expect("scene loads");
    let shown = dir.join("model.glb").display().to_string();
    assert_eq!(
        scene.warnings,
        [format!(
            "{shown}: an occlusion texture's strength outside argil's map strength range is clamped to it"
        )]
    );
    let names: Vec<&str> = scene
        .objects
        .iter()
        .map(|o| scene.materials[o.material].name.as_str())
        .collect();
    assert_eq!(names, [format!("{shown} #0 glaze"), format!("{shown} #1")]);
    assert!(scene.objects.iter().all(|o| o.material_from_model));

    write_parts(&dir, &primitives, worlds);
    let obj_text = scene_text(&[])
        + &parts_with(["glaze", "metal"])
        + r#"
[materials.glaze]
base_color = [0.75, 0.5, 0.25]
metallic = 0.25
roughness = 0.375
[materials.glaze.base_color_map]
texture = "albedo map.png"
[materials.glaze.roughness_map]
texture = "orm.png"
[materials.glaze.metallic_map]
texture = "orm.png"
[materials.glaze.occlusion_map]
texture = "orm.png"
strength = 0.75
[materials.metal]
base_color = [1.0, 1.0, 1.0]
metallic = 1.0
roughness = 0.625
[materials.metal.normal_map]
texture = "normals.png"
strength = 0.5
[materials.metal.roughness_map]
texture = "orm.png"
[materials.metal.metallic_map]
texture = "orm.png"
[materials.metal.occlusion_map]
texture = "orm.png"
strength = 8.0
"#;
    let obj = load(&dir, "obj.toml", &obj_text);
    assert_same_materials(&scene, &obj);
    let expected = common::render(&obj, 96, 64);
    let frame = common::render(&scene, 96, 64);
    assert!(
        frame.display == expected.display,
        "the frame differs from the OBJ files'"
    );

    // Saved, the object leaves its materials to the model.
    let saved = scene.to_file_at(&path);
    assert_eq!((saved.objects.len(), saved.objects[0].material.as_deref()), (1, None));
    assert!(
        saved.materials.keys().all(|name| name == "clay"),
        "{:?}",
        saved.materials.keys()
    );
    // An object that names a material gives it to every part.
    let named = load(&dir, "named.toml", &scene_text(&["model.glb"]));
    assert!(named
        .objects
        .iter()
        .all(|o| named.materials[o.material].name == "clay" && !o.material_from_model));
}

/// A texture reference with KHR_texture_transform's `offset` and `scale`.
fn transformed(index: usize, offset: [f32; 2], scale: [f32; 2]) -> Value {
    json!({"index": index, "extensions": {"KHR_texture_transform": {"offset": offset, "scale": scale}}})
}

/// KHR_texture_transform's offset and scale are a map's `uv_offset` and `uv_scale`, with v
/// turned up the image: glTF's v' = s v + o is v' = s v + (1 - s - o) in argil's UVs. On every
/// kind of texture (the `gltf` crate parses the extension on some, argil on the normal and
/// occlusion textures) the model draws bit for bit as its geometry in OBJ files with the
/// maps' transforms written in the scene; a texCoord of 0 in the transform overrides the
/// reference's 1. A rotation is `uv_rotation_degrees`, with the offset it moves.
#[test]
fn texture_transforms_are_uv_scale_offset_and_rotation() {
    let dir = test_dir("texture-transform");
    let primitives = [octahedron(), tetrahedron()];
    let (nodes, worlds) = nodes();
    let mut model = Model::new(&primitives, nodes, &[0, 1]);
    add_maps(&mut model, &dir);
    let mut emissive = transformed(0, [0.0, 0.25], [1.5, 0.5]);
    emissive["texCoord"] = json!(1);
    emissive["extensions"]["KHR_texture_transform"]["texCoord"] = json!(0);
    model.json["materials"] = json!([
        {
            "name": "colour",
            "pbrMetallicRoughness": {
                "baseColorTexture": transformed(0, [0.25, -0.5], [2.0, 3.0]),
                "metallicFactor": 0.0,
                "roughnessFactor": 0.5,
            },
            "occlusionTexture": transformed(2, [0.5, 0.125], [0.5, 4.0]),
        },
        {
            "name": "relief",
            "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.5},
            "normalTexture": transformed(1, [0.25, 0.75], [-1.0, 2.0]),
            "emissiveFactor": [0.5, 0.25, 0.125],
            "emissiveTexture": emissive,
        },
    ]);
    model.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    model.json["meshes"][1]["primitives"][0]["material"] = json!(1);
    model.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
    model.json["extensionsRequired"] = json!(["KHR_texture_transform"]);
    model.write(&dir, "model", Storage::Binary);
    let model_text = scene_text(&[]) + "\n[[objects]]\nmesh = \"model.glb\"\nposition = [0.25, 0.0, 0.0]\n";
    let scene = load(&dir, "model.toml", &model_text);
    assert_eq!(scene.warnings, Vec::<String>::new());

    write_parts(&dir, &primitives, worlds);
    // Named in the glTF's order, so that the scene loads their textures in the same order.
    let obj_text = scene_text(&[])
        + &parts_with(["colour", "relief"])
        + r#"
[materials.colour]
base_color = [1.0, 1.0, 1.0]
roughness = 0.5
[materials.colour.base_color_map]
texture = "albedo map.png"
uv_scale = [2.0, 3.0]
uv_offset = [0.25, -1.5]
[materials.colour.occlusion_map]
texture = "orm.png"
uv_scale = [0.5, 4.0]
uv_offset = [0.5, -3.125]
[materials.relief]
base_color = [1.0, 1.0, 1.0]
roughness = 0.5
emission = [0.5, 0.25, 0.125]
[materials.relief.normal_map]
texture = "normals.png"
uv_scale = [-1.0, 2.0]
uv_offset = [0.25, -1.75]
[materials.relief.emission_map]
texture = "albedo map.png"
uv_scale = [1.5, 0.5]
uv_offset = [0.0, 0.25]
"#;
    let obj = load(&dir, "obj.toml", &obj_text);
    assert_same_materials(&scene, &obj);
    let expected = common::render(&obj, 96, 64);
    assert!(
        common::render(&scene, 96, 64).display == expected.display,
        "the frame differs from the OBJ files'"
    );

    // A rotation turns the scaled UVs the same way in argil's UVs, and moves the offset:
    // glTF's o is (o_u + s_v sin θ, 1 - s_v cos θ - o_v) there.
    let rotate = |texture: &mut Value, angle: f32| texture["extensions"]["KHR_texture_transform"]["rotation"] = json!(angle);
    rotate(&mut model.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"], 0.5);
    rotate(&mut model.json["materials"][1]["normalTexture"], -1.0);
    model.write(&dir, "model", Storage::Binary);
    let rotated = load(&dir, "model.toml", &model_text);
    assert_eq!(rotated.warnings, Vec::<String>::new());
    let turned = |angle: f64, [ou, ov]: [f64; 2], sv: f64| {
        let offset = [ou + sv * angle.sin(), 1.0 - sv * angle.cos() - ov];
        format!("uv_offset = {offset:?}\nuv_rotation_degrees = {:?}", angle.to_degrees())
    };
    let obj_rotated = obj_text
        .replace("uv_offset = [0.25, -1.5]", &turned(0.5, [0.25, -0.5], 3.0))
        .replace("uv_offset = [0.25, -1.75]", &turned(-1.0, [0.25, 0.75], 2.0));
    let obj = load(&dir, "obj-rotated.toml", &obj_rotated);
    assert_same_materials(&rotated, &obj);
    assert!(
        common::render(&rotated, 96, 64).display == common::render(&obj, 96, 64).display,
        "the rotated frame differs from the OBJ files'"
    );
    assert!(
        common::render(&rotated, 96, 64).display != expected.display,
        "the rotation changes nothing"
    );
}

/// Maps on TEXCOORD_1 (by the texture reference's texCoord, or by its KHR_texture_transform's)
/// are left out, named in one warning per model: the parts draw without them.
#[test]
fn maps_on_texcoord_1_are_left_out() {
    let dir = test_dir("texcoord-1");
    let mut model = Model::new(&[octahedron()], json!([{"mesh": 0}]), &[0]);
    add_maps(&mut model, &dir);
    let mut occlusion = transformed(2, [0.0, 0.0], [1.0, 1.0]);
    occlusion["extensions"]["KHR_texture_transform"]["texCoord"] = json!(1);
    model.json["materials"] = json!([{
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}},
        "normalTexture": {"index": 1},
        "occlusionTexture": occlusion,
    }]);
    model.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    model.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] =
        model.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"].clone();
    model.write(&dir, "model", Storage::Binary);
    let scene = load(&dir, "model.toml", &(scene_text(&[]) + "\n[[objects]]\nmesh = \"model.glb\"\n"));
    let shown = dir.join("model.glb").display().to_string();
    assert_eq!(
        scene.warnings,
        [format!(
            "{shown}: textures on TEXCOORD_1 or above are not supported; those maps are left out"
        )]
    );
    let maps = &scene.materials[scene.objects[0].material].maps;
    let slots: Vec<MapSlot> = MapSlot::ALL.into_iter().filter(|&slot| maps[slot].is_some()).collect();
    assert_eq!(slots, [MapSlot::Normal]);
}

/// The octahedron and tetrahedron model with `scale` on a root node above both, and the
/// node `camera` (a perspective camera's node, as JSON) if given.
fn opened_model(dir: &Path, name: &str, scale: f32, camera: Option<Value>) -> PathBuf {
    let (mut nodes, _) = nodes();
    let list = nodes.as_array_mut().expect("nodes");
    list.push(json!({"scale": [scale, scale, scale], "children": [0, 1]}));
    let mut roots = vec![3];
    if let Some(camera) = camera {
        list.push(camera);
        roots.push(4);
    }
    let mut model = Model::new(&[octahedron(), tetrahedron()], nodes, &roots);
    model.json["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}]);
    model.write(dir, name, Storage::Binary)
}

/// A model opened alone gets the default scene's studio around it, framed from the default
/// camera's direction, its lights and clipping distances following its size: a model
/// 1000 times larger (far past the 200 units a scene file's camera sees) draws as the
/// small one does.
#[test]
fn a_model_opens_alone_framed_in_the_studio() {
    let dir = test_dir("open");
    let small = Scene::load(&opened_model(&dir, "small", 1.0, None)).expect("small model opens");
    let large = Scene::load(&opened_model(&dir, "large", 1000.0, None)).expect("large model opens");
    let default = Scene::default_scene();
    assert_eq!(small.environment, default.environment);
    assert_eq!(small.lights.len(), default.lights.len());
    assert_eq!(small.objects.len(), 2);
    for scene in [&small, &large] {
        // Every vertex lies between the clipping planes, in front of the camera.
        let forward = (scene.camera.target - scene.camera.position).normalize();
        for v in scene.meshes.iter().flat_map(|m| &m.vertices) {
            let depth = (Vec3::from(v.position) - scene.camera.position).dot(forward);
            assert!(
                depth > scene.camera.near && depth < scene.camera.far,
                "{depth} {:?}",
                scene.camera
            );
        }
    }
    assert!(large.camera.far > 5.0 * argil::scene::Camera::FAR, "{:?}", large.camera);
    let (a, b) = (common::render(&small, 96, 64), common::render(&large, 96, 64));
    let (rmse, max) = common::rgb_difference(&a.display, &b.display);
    // Coordinates 1000 times larger round differently: pixels on the silhouettes flip.
    let flipped = a.display.chunks_exact(4).zip(b.display.chunks_exact(4));
    let flipped = flipped.filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 8)).count();
    println!("small against large: RMSE {rmse:.3}, max {max}, {flipped} pixels differ by more than 8");
    assert!(
        rmse < 3.0 && flipped < 96 * 64 / 100,
        "RMSE {rmse} (max {max}), {flipped} pixels"
    );
    let background = common::rgb_difference(&a.display, &common::render(&default, 96, 64).display).0;
    assert!(
        background > 5.0,
        "the model is not in view: RMSE {background} from the default scene"
    );

    // The command line opens it too: render, reference and the viewer's loading.
    let model = dir.join("small.glb");
    for (command, out) in [("render", "small.png"), ("reference", "small.exr")] {
        let out = dir.join(out);
        let mut args = vec![
            command,
            model.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
        ];
        args.extend(["--width", "24", "--height", "16"]);
        if command == "reference" {
            args.extend(["--spp", "2"]);
        }
        let o = argil(&args);
        assert!(o.status.success(), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(out.exists());
    }
    let (viewed, _) = argil::viewer::load_document(&model).expect("the viewer opens it");
    assert_eq!(viewed.scene, small);
}

/// The model's first camera, when it has one, is the view: its node's position and -z
/// direction, and its vertical field of view.
#[test]
fn a_model_opens_through_its_camera() {
    let dir = test_dir("camera");
    let camera = json!({"camera": 0, "translation": [0.5, 0.25, 6.0]});
    let scene = Scene::load(&opened_model(&dir, "model", 1.0, Some(camera))).expect("opens");
    assert_eq!(scene.camera.position, Vec3::new(0.5, 0.25, 6.0));
    let forward = (scene.camera.target - scene.camera.position).normalize();
    assert!(forward.abs_diff_eq(Vec3::NEG_Z, 1e-6), "{forward}");
    assert!((scene.camera.fov_y_degrees - 0.5f32.to_degrees()).abs() < 1e-4);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// The octahedron and tetrahedron with one material whose base colour texture is image 0
/// and whose metallic-roughness and occlusion textures are image 1 (`images` as JSON).
fn textured_model(images: Value) -> Model {
    let (nodes, _) = nodes();
    let mut model = Model::new(&[octahedron(), tetrahedron()], nodes, &[0, 1]);
    model.json["images"] = images;
    model.json["textures"] = json!([{"source": 0}, {"source": 1}]);
    model.json["materials"] = json!([{
        "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0},
            "roughnessFactor": 0.5,
            "metallicFactor": 0.5,
            "metallicRoughnessTexture": {"index": 1},
        },
        "occlusionTexture": {"index": 1},
    }]);
    for mesh in 0..2 {
        model.json["meshes"][mesh]["primitives"][0]["material"] = json!(0);
    }
    model
}

/// Appends `bytes` to the model's buffer as a view of its own; the view's index.
fn push_view(model: &mut Model, bytes: &[u8]) -> usize {
    while model.bin.len() % 4 != 0 {
        model.bin.push(0);
    }
    let views = model.json["bufferViews"].as_array_mut().expect("views");
    views.push(json!({"buffer": 0, "byteOffset": model.bin.len(), "byteLength": bytes.len()}));
    model.bin.extend(bytes);
    views.len() - 1
}

fn png(image: &image::RgbaImage) -> Vec<u8> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, image::ImageFormat::Png).expect("encode png");
    bytes.into_inner()
}

/// Images embedded in the model, by a buffer view (a .glb's usual way) or a `data:` URI,
/// load as the same PNG files beside the model do: the frames are equal bit for bit, the
/// image serving three maps is one texture, and saving writes no texture path for them.
#[test]
fn embedded_images_draw_as_files_beside_the_model() {
    let dir = test_dir("embedded");
    let albedo = image::RgbaImage::from_fn(8, 8, |x, y| {
        image::Rgba([30 + 25 * x as u8, 220 - 25 * y as u8, 120, 255])
    });
    let orm = image::RgbaImage::from_fn(8, 8, |x, y| {
        image::Rgba([255 - 24 * x as u8, 40 + 26 * y as u8, 28 * ((x + 2 * y) % 8) as u8, 255])
    });
    let (albedo, orm) = (png(&albedo), png(&orm));
    std::fs::write(dir.join("albedo.png"), &albedo).expect("write albedo");
    std::fs::write(dir.join("orm.png"), &orm).expect("write orm");
    textured_model(json!([{"uri": "albedo.png"}, {"uri": "orm.png"}])).write(&dir, "files", Storage::Binary);
    let mut views = textured_model(json!([]));
    let images =
        [&albedo, &orm].map(|bytes| json!({"bufferView": push_view(&mut views, bytes), "mimeType": "image/png"}));
    views.json["images"] = json!(images);
    views.write(&dir, "views", Storage::Binary);
    let uri = |bytes: &[u8]| {
        let data = base64::engine::general_purpose::STANDARD.encode(bytes);
        json!({"uri": format!("data:image/png;base64,{data}")})
    };
    textured_model(json!([uri(&albedo), uri(&orm)])).write(&dir, "uris", Storage::External);

    let scene_of = |model: &str| {
        let text = scene_text(&[]) + &format!("\n[[objects]]\nmesh = {model:?}\nposition = [0.25, 0.0, 0.0]\n");
        load(&dir, &format!("{model}.toml"), &text)
    };
    let files = scene_of("files.glb");
    assert_eq!(files.warnings, Vec::<String>::new());
    // The colour map and the one ORM texture.
    assert_eq!(files.textures.len(), 2);
    let expected = common::render(&files, 96, 64);
    for model in ["views.glb", "uris.gltf"] {
        let scene = scene_of(model);
        assert_eq!(scene.warnings, Vec::<String>::new(), "{model}");
        assert_eq!(scene.textures.len(), 2, "{model}");
        let shown = dir.join(model).display().to_string();
        let names: Vec<&str> = scene.textures.iter().map(|t| t.name.as_str()).collect();
        assert_eq!(
            names,
            [format!("{shown}#image0"), format!("{shown}#image1")],
            "{model}"
        );
        for (a, b) in scene.textures.iter().zip(&files.textures) {
            assert_eq!(
                (a.width, a.height, a.format, &a.pixels),
                (b.width, b.height, b.format, &b.pixels)
            );
        }
        let frame = common::render(&scene, 96, 64);
        assert!(
            frame.display == expected.display,
            "{model}: the frame differs from the files'"
        );
        let saved = scene.to_file_at(&dir.join("saved.toml"));
        assert!(
            saved.materials.keys().all(|name| name == "clay"),
            "{:?}",
            saved.materials.keys()
        );
    }
}

/// An embedded image that does not decode, or whose buffer view is outside the buffer, is
/// refused with exit code 2 naming the model and the image, and nothing is written.
#[test]
fn bad_embedded_images_are_clear_errors() {
    let dir = test_dir("bad-embedded");
    let out = dir.join("x.png");
    let good = png(&image::RgbaImage::from_pixel(4, 4, image::Rgba([200, 100, 50, 255])));
    let mut corrupt = good.clone();
    corrupt.truncate(good.len() / 2);
    let mut model = textured_model(json!([]));
    let images =
        [&good, &corrupt].map(|bytes| json!({"bufferView": push_view(&mut model, bytes), "mimeType": "image/png"}));
    model.json["images"] = json!(images);
    model.write(&dir, "corrupt", Storage::Binary);
    let outside = model.json["bufferViews"].as_array().expect("views").len() - 1;
    model.json["bufferViews"][outside]["byteOffset"] = json!(model.bin.len() + 64);
    model.write(&dir, "outside", Storage::Binary);
    for (name, mentions) in [
        ("corrupt", vec!["corrupt.glb#image1", "PNG"]),
        ("outside", vec!["outside.glb", "image 1", "buffer view"]),
    ] {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(
            &scene,
            scene_text(&[]) + &format!("\n[[objects]]\nmesh = \"{name}.glb\"\n"),
        )
        .expect("write");
        assert_refused(&render_16(&scene, &out), &out, &mentions);
    }
}

/// glTF's emission is argil's: `emissiveFactor` (times `KHR_materials_emissive_strength`,
/// required or only used) is `emission` and `emissiveTexture` its `emission_map`, with no
/// warning; the frame equals, bit for bit, that of the same geometry as OBJ files with the
/// materials written in the scene.
#[test]
fn a_model_brings_its_emission() {
    let dir = test_dir("emission");
    let glow = image::RgbaImage::from_fn(8, 8, |x, y| image::Rgba([60 + 24 * x as u8, 200 - 20 * y as u8, 120, 255]));
    glow.save(dir.join("glow.png")).expect("write glow");
    let primitives = [octahedron(), tetrahedron()];
    let (nodes, worlds) = nodes();
    let mut model = Model::new(&primitives, nodes, &[0, 1]);
    model.json["images"] = json!([{"uri": "glow.png"}]);
    model.json["textures"] = json!([{"source": 0}]);
    let pbr = json!({"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5});
    model.json["materials"] = json!([
        {"name": "glow", "pbrMetallicRoughness": pbr, "emissiveFactor": [0.75, 0.5, 0.25], "emissiveTexture": {"index": 0}},
        {
            "name": "lamp",
            "pbrMetallicRoughness": pbr,
            "emissiveFactor": [1.0, 0.5, 0.25],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}},
        },
    ]);
    model.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    model.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    model.json["meshes"][1]["primitives"][0]["material"] = json!(1);
    write_parts(&dir, &primitives, worlds);
    let obj_text = scene_text(&[])
        + &parts_with(["glow", "lamp"])
        + r#"
[materials.glow]
base_color = [0.5, 0.5, 0.5]
roughness = 0.5
emission = [0.75, 0.5, 0.25]
[materials.glow.emission_map]
texture = "glow.png"
[materials.lamp]
base_color = [0.5, 0.5, 0.5]
roughness = 0.5
emission = [4.0, 2.0, 1.0]
"#;
    let obj = load(&dir, "obj.toml", &obj_text);
    let expected = common::render(&obj, 96, 64);
    let model_text = scene_text(&[]) + "\n[[objects]]\nmesh = \"model.glb\"\nposition = [0.25, 0.0, 0.0]\n";
    for required in [false, true] {
        if required {
            model.json["extensionsRequired"] = json!(["KHR_materials_emissive_strength"]);
        }
        model.write(&dir, "model", Storage::Binary);
        let scene = load(&dir, "model.toml", &model_text);
        assert_eq!(scene.warnings, Vec::<String>::new(), "required: {required}");
        assert_same_materials(&scene, &obj);
        let frame = common::render(&scene, 96, 64);
        assert!(
            frame.display == expected.display,
            "required: {required}: the frame differs from the OBJ files'"
        );
    }
}

/// Where Debian's package `assimp-testmodels` (installed by `scripts/setup.sh`) puts Khronos'
/// glTF sample models and the broken files of assimp's tests, with their licences in
/// /usr/share/doc/assimp-testmodels/copyright.
const SAMPLES: &str = "/usr/share/assimp/models/glTF2";

/// A file of `assimp-testmodels`, which must be installed: these tests never skip.
fn sample(path: &str) -> PathBuf {
    let file = Path::new(SAMPLES).join(path);
    assert!(
        file.exists(),
        "{} is missing: install Debian's package assimp-testmodels (`make setup` does)",
        file.display()
    );
    file
}

/// Pixels of `frame` whose colour leans towards one channel (0 red, 1 green, 2 blue) by more
/// than 30 code values over each of the others.
fn leaning_to(frame: &[u8], channel: usize) -> usize {
    frame
        .chunks_exact(4)
        .filter(|p| (0..3).all(|c| c == channel || i32::from(p[channel]) > i32::from(p[c]) + 30))
        .count()
}

/// Khronos' BoxTextured as a .gltf with its .bin and PNG beside it, as a .glb and as a .gltf
/// of `data:` URIs: the same 12 triangles, drawn bit for bit alike, and the Cesium logo on
/// them (its blue sky and green hills, which the box without its map has none of: 484 and
/// 315 of the 96 × 64 pixels against none).
#[test]
fn box_textured_draws_alike_from_every_storage() {
    let scenes = [
        "BoxTextured-glTF/BoxTextured.gltf",
        "BoxTextured-glTF-Binary/BoxTextured.glb",
        "BoxTextured-glTF-Embedded/BoxTextured.gltf",
    ]
    .map(|path| Scene::load(&sample(path)).unwrap_or_else(|e| panic!("{path}: {e}")));
    let frames = scenes.each_ref().map(|scene| {
        assert_eq!(scene.warnings, Vec::<String>::new());
        let triangles: usize = scene.meshes.iter().map(|m| m.indices.len() / 3).sum();
        let vertices: usize = scene.meshes.iter().map(|m| m.vertices.len()).sum();
        // MikkTSpace gives it tangents and splits none of its vertices: each face's UVs
        // keep one orientation.
        assert_eq!((triangles, vertices), (12, 24));
        common::render(scene, 96, 64)
    });
    assert!(frames[1].display == frames[0].display, "the .glb draws otherwise");
    assert!(frames[2].display == frames[0].display, "the data: URIs draw otherwise");

    let mut plain = scenes[0].clone();
    for material in &mut plain.materials {
        for slot in MapSlot::ALL {
            material.maps[slot] = None;
        }
    }
    let plain = common::render(&plain, 96, 64);
    let [blue, green] = [2, 1].map(|channel| leaning_to(&frames[0].display, channel));
    let [plain_blue, plain_green] = [2, 1].map(|channel| leaning_to(&plain.display, channel));
    println!("blue and green pixels: {blue} and {green} with the map, {plain_blue} and {plain_green} without");
    assert!(blue > 100 && green > 100, "{blue} blue and {green} green pixels");
    assert_eq!((plain_blue, plain_green), (0, 0));
}

/// What the samples have and argil does not draw is named in one warning each: the
/// specular-glossiness extension, a skin and its animation, morph targets and theirs.
#[test]
fn samples_name_what_is_not_drawn() {
    let cases: [(&str, &[&str]); 3] = [
        (
            "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf",
            &["the extension KHR_materials_pbrSpecularGlossiness is not supported and is ignored"],
        ),
        (
            "simple_skin/simple_skin.gltf",
            &[
                "1 animation(s) are not played",
                "1 skin(s) are ignored: meshes are drawn in their bind pose",
            ],
        ),
        (
            "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
            &[
                "1 animation(s) are not played",
                "1 primitive(s) have morph targets, which are ignored (the base shape is drawn)",
            ],
        ),
    ];
    for (path, expected) in cases {
        let file = sample(path);
        let scene = Scene::load(&file).unwrap_or_else(|e| panic!("{path}: {e}"));
        let expected: Vec<String> = expected.iter().map(|w| format!("{}: {w}", file.display())).collect();
        assert_eq!(scene.warnings, expected);
    }
}

/// assimp's broken files are refused with exit code 2, naming the file and the problem,
/// without writing anything.
#[test]
fn broken_samples_are_clear_errors() {
    let dir = test_dir("broken-samples");
    let out = dir.join("x.png");
    let cases: [(&str, &str); 16] = [
        ("MissingBin/BoxTextured.gltf", "BoxTextured0.bin: cannot read"),
        ("IndexOutOfRange/IndexOutOfRange.gltf", "index 255 (triangle 0) is out of range"),
        ("IndexOutOfRange/AllIndicesOutOfRange.gltf", "index 65535 (triangle 0) is out of range"),
        ("RecursiveNodes/RecursiveNodes.gltf", "node 0 is reached twice"),
        // Its normals are infinite, and its POSITION lacks the bounds glTF requires.
        ("BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "POSITION\"].min: Missing data"),
        ("SchemaFailures/sceneWrongType.gltf", "invalid type: string \"hello\""),
        ("wrongTypes/badArray.gltf", "expected a sequence"),
        ("wrongTypes/badExtension.gltf", "expected struct TextureTransform"),
        ("wrongTypes/badNumber.gltf", "expected f32"),
        ("wrongTypes/badObject.gltf", "invalid type: string \"not an object\""),
        ("wrongTypes/badString.gltf", "expected a string"),
        ("wrongTypes/badUint.gltf", "invalid type: integer `-1`"),
        ("TestNoRootNode/NoScene.gltf", "scene: Index out of bounds"),
        // glTF allows a scene without `nodes`, an empty one; the `gltf` crate does not.
        ("TestNoRootNode/SceneWithoutNodes.gltf", "missing field `nodes`"),
        // Its vertex and index counts are not whole triangles, its POSITIONs lack bounds.
        ("IncorrectVertexArrays/Cube.gltf", "POSITION\"].min: Missing data"),
        (
            "issue_3269/texcoord_crash.gltf",
            "material 4 has textures on TEXCOORD_0, which the primitive lacks",
        ),
    ];
    for (path, problem) in cases {
        let file = sample(path);
        let o = argil(&["render", file.to_str().expect("utf-8"), "--out", out.to_str().expect("utf-8")]);
        assert_refused(&o, &out, &[&format!("{}: ", file.display()), problem]);
    }
}

/// Khronos' KHR_texture_transform test: each of the three offset squares shows the quarter
/// of its texture the offset moves it to (green "U", blue "V", cyan "UV"; without the
/// offset all three would show the yellow top-left quarter), and the arrows of the rotated
/// squares point at their green markers: their heads, dark, cover the way to it, where the
/// way to the markers of an arrow unrotated (yellow) or turned the other way (red) is light;
/// the scaled square's arrow is shrunk towards its texture's corner.
#[test]
fn the_texture_transform_sample_shows_its_offsets_rotations_and_scale() {
    let file = sample("textureTransform/TextureTransformTest.gltf");
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_degrees = 40.0\n\
         [environment]\nkind = \"uniform\"\nradiance = [1.0, 1.0, 1.0]\n\
         [[objects]]\nmesh = {:?}\n",
        file.display().to_string()
    );
    let dir = test_dir("texture-transform-sample");
    let scene = load(&dir, "scene.toml", &text);
    assert_eq!(scene.warnings, Vec::<String>::new());
    let (width, height) = (384, 256);
    let frame = common::render(&scene, width, height);
    // The squares' nodes are at x = -1.1, 0, 1.1 and y = 0.55; their textures' background
    // fills each square's corners, away from the check mark.
    let half_height = 4.0 * 20f32.to_radians().tan();
    let pixel = |x: f32, y: f32| {
        let column = ((x / (half_height * width as f32 / height as f32) + 1.0) * 0.5 * width as f32) as usize;
        let row = ((1.0 - y / half_height) * 0.5 * height as f32) as usize;
        let at = 4 * (row * width as usize + column);
        [0, 1, 2].map(|c| i32::from(frame.display[at + c]))
    };
    let squares: [(f32, &str, &[usize]); 3] = [(-1.1, "U", &[1]), (0.0, "V", &[2]), (1.1, "UV", &[1, 2])];
    for (x, name, leans) in squares {
        let [r, g, b] = pixel(x - 0.35, 0.55 + 0.35);
        let channels = [r, g, b];
        let others: Vec<i32> = (0..3).filter(|c| !leans.contains(c)).map(|c| channels[c]).collect();
        assert!(
            leans.iter().all(|&c| others.iter().all(|&o| channels[c] > o + 60)),
            "offset {name}: the square's colour {channels:?} is not its quarter's"
        );
    }
    // How many of the pixels within 0.12 of the point 75% of the way from a square's centre
    // to a marker (the markers' nodes, relative to their square's) are dark.
    let dark_toward = |centre: [f32; 2], marker: [f32; 2]| {
        let [x, y] = [0, 1].map(|i| centre[i] + 0.75 * marker[i]);
        let offsets = (-15..=15).flat_map(|dx| (-15..=15).map(move |dy| (dx as f32 * 0.01, dy as f32 * 0.01)));
        offsets
            .filter(|(ox, oy)| ox * ox + oy * oy <= 0.12 * 0.12)
            .filter(|(ox, oy)| pixel(x + ox, y + oy).iter().sum::<i32>() < 150)
            .count()
    };
    let rotation = [-1.1, -0.55];
    let marks = [
        ("correct", [-0.079_048_22, -0.516_267_5]),
        ("not supported", [0.277_817_46, -0.277_817_46]),
        ("error", [0.516_267_5, 0.079_048_22]),
    ];
    let levels: Vec<(&str, usize)> = marks.iter().map(|&(name, at)| (name, dark_toward(rotation, at))).collect();
    assert!(
        levels[0].1 >= 10 && levels[1..].iter().all(|&(_, dark)| dark <= 2),
        "the rotated arrow's dark pixels on the way to each marker: {levels:?}"
    );
    // Offset, turned and scaled: its one marker is the correct one.
    let all = dark_toward([1.1, -0.55], [-0.07, -0.25]);
    assert!(all >= 10, "the transformed arrow's dark pixels on the way to its marker: {all}");
    // Scaled by 1.5 about the texture's corner, the arrow's head (about (0.6, 0.6) of the
    // texture) moves from (0.1, -0.1) of the square's centre to (-0.1, 0.1), and its tip to
    // the correct marker.
    let scaled = |at: [f32; 2]| dark_toward([0.0, -0.55], [at[0] / 0.75, at[1] / 0.75]);
    let (head, unscaled) = (scaled([-0.1, 0.1]), scaled([0.1, -0.1]));
    assert!(
        head >= 10 && unscaled <= 2,
        "the scaled arrow's dark pixels at its head {head}, where the head would be unscaled {unscaled}"
    );
}

/// Khronos' 2CylinderEngine: 34 primitives under 82 nodes of transforms, some meshes drawn
/// by several nodes, load as 115 parts and draw (every frame is checked for NaN and Inf).
#[test]
fn the_engine_sample_draws() {
    let scene = Scene::load(&sample("2CylinderEngine-glTF-Binary/2CylinderEngine.glb")).expect("loads");
    assert_eq!(scene.warnings, Vec::<String>::new());
    let triangles: usize = scene.meshes.iter().map(|m| m.indices.len() / 3).sum();
    assert_eq!((scene.meshes.len(), triangles), (115, 121_496));
    let frame = common::render(&scene, 96, 64);
    let background = common::render(&Scene::default_scene(), 96, 64);
    assert!(common::rgb_difference(&frame.display, &background.display).0 > 5.0, "the engine is not in view");
}
