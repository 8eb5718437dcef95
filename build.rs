//! Compiles every GLSL stage in `shaders/` to SPIR-V in `OUT_DIR` (and the `VARIANTS`),
//! where `src/render/shaders.rs` embeds it. `#include "x.glsl"` resolves against the including file's folder, then
//! `shaders/lib/`, then `OUT_DIR`, where `material_struct.glsl` is written first: the
//! shaders' `struct Material` from `MaterialData` in src/render/material_data.rs, so the
//! two layouts are one declaration. A compile error fails the build, naming the file and line.
use std::path::{Path, PathBuf};

// Linked for its build script's link directives (see crates/shaderc-system-link).
#[cfg(feature = "system-shaderc")]
extern crate shaderc_system_link;

/// A stage compiled once more with macros defined: (source, output, [(macro, value)]).
/// `forward_shaded.frag` is forward.frag without its debug views, for the pipelines that
/// draw the shaded image; `forward_lean.frag` is that without the features of
/// shaders/lib/specialization.glsl too, for the pipelines that use none of them
/// (src/render/forward.rs, `FragmentBuild`).
type Variant = (&'static str, &'static str, &'static [(&'static str, &'static str)]);
const VARIANTS: &[Variant] = &[
    ("forward.frag", "forward_shaded.frag", &[("DEBUG_VIEWS", "0")]),
    (
        "forward.frag",
        "forward_lean.frag",
        &[("DEBUG_VIEWS", "0"), ("SAMPLED_REFLECTION", "0"), ("SEED_COMPOSITION", "0"), ("SUN_LOBE", "0")],
    ),
    ("forward.frag", "forward_gbuffer.frag", &[("DEBUG_VIEWS", "0"), ("GBUFFER", "1")]),
    ("forward.frag", "forward_deferred.frag", &[("DEBUG_VIEWS", "0"), ("DEFERRED", "1")]),
    (
        "forward.frag",
        "forward_deferred_lean.frag",
        &[
            ("DEBUG_VIEWS", "0"),
            ("DEFERRED", "1"),
            ("SAMPLED_REFLECTION", "0"),
            ("SEED_COMPOSITION", "0"),
            ("SUN_LOBE", "0"),
        ],
    ),
];

const STAGES: &[(&str, shaderc::ShaderKind)] = &[
    ("vert", shaderc::ShaderKind::Vertex),
    ("frag", shaderc::ShaderKind::Fragment),
    ("comp", shaderc::ShaderKind::Compute),
];

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let shader_dir = root.join("shaders");
    let lib_dir = shader_dir.join("lib");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed={}", shader_dir.display());
    println!("cargo:rerun-if-changed={}", lib_dir.display());
    for lib in sorted_files(&lib_dir) {
        println!("cargo:rerun-if-changed={}", lib.display());
    }

    let material_data = root.join("src/render/material_data.rs");
    println!("cargo:rerun-if-changed={}", material_data.display());
    let rust = std::fs::read_to_string(&material_data).unwrap_or_else(|e| panic!("cannot read {}: {e}", material_data.display()));
    let glsl = material_glsl(&rust).unwrap_or_else(|e| panic!("{}: {e}", material_data.display()));
    std::fs::write(out_dir.join("material_struct.glsl"), glsl).expect("cannot write material_struct.glsl to OUT_DIR");

    let compiler = shaderc::Compiler::new().expect("shaderc compiler could not be created");
    let mut failures = Vec::new();
    for source in sorted_files(&shader_dir) {
        let ext = source.extension().and_then(|e| e.to_str()).unwrap_or("");
        let Some(&(_, kind)) = STAGES.iter().find(|(e, _)| *e == ext) else {
            continue;
        };
        println!("cargo:rerun-if-changed={}", source.display());
        let text = std::fs::read_to_string(&source).unwrap_or_else(|e| panic!("cannot read {}: {e}", source.display()));
        let name = source.file_name().unwrap().to_string_lossy().into_owned();
        let variants = VARIANTS
            .iter()
            .filter(|v| v.0 == name)
            .map(|&(_, output, definitions)| (output, definitions));
        for (output, definitions) in std::iter::once((name.as_str(), &[][..])).chain(variants) {
            let mut options = compile_options(&lib_dir, &out_dir);
            for &(key, value) in definitions {
                options.add_macro_definition(key, Some(value));
            }
            match compiler.compile_into_spirv(&text, kind, &source.display().to_string(), "main", Some(&options)) {
                Ok(artifact) => {
                    std::fs::write(out_dir.join(format!("{output}.spv")), artifact.as_binary_u8())
                        .expect("cannot write SPIR-V to OUT_DIR");
                }
                Err(e) => failures.push(e.to_string()),
            }
        }
    }
    if !failures.is_empty() {
        for f in &failures {
            for line in f.lines() {
                println!("cargo:warning={line}");
            }
        }
        eprintln!("{}", failures.join("\n"));
        std::process::exit(1);
    }
}

/// Vulkan 1.3 SPIR-V, optimised, with debug information; includes resolve against the
/// including file's folder, then `lib_dir`, then `generated`.
fn compile_options(lib_dir: &Path, generated: &Path) -> shaderc::CompileOptions<'static> {
    let mut options = shaderc::CompileOptions::new().unwrap();
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    options.set_generate_debug_info();
    options.set_warnings_as_errors();
    let (lib_dir, generated) = (lib_dir.to_path_buf(), generated.to_path_buf());
    options.set_include_callback(move |name, _ty, from, _depth| {
        let from_dir = Path::new(from).parent().unwrap_or(Path::new("."));
        let path = [from_dir.join(name), lib_dir.join(name), generated.join(name)]
            .into_iter()
            .find(|p| p.is_file())
            .ok_or_else(|| format!("{from}: cannot find include \"{name}\""))?;
        let content = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(shaderc::ResolvedInclude {
            resolved_name: path.display().to_string(),
            content,
        })
    });
    options
}

fn sorted_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// `struct Material` and `material_zero()` in GLSL, from the fields of `pub struct
/// MaterialData` in `rust` (one `pub name: type,` a line, `///` comments above).
fn material_glsl(rust: &str) -> Result<String, String> {
    let start = rust.find("pub struct MaterialData {").ok_or("no `pub struct MaterialData {`")?;
    let body = &rust[start..];
    let body = &body[..body.find("\n    }").ok_or("MaterialData does not end")?];
    let (mut members, mut zeros, mut comment) = (String::new(), String::new(), Vec::new());
    for line in body.lines().skip(1).map(str::trim) {
        if let Some(doc) = line.strip_prefix("///") {
            comment.push(doc.trim());
            continue;
        }
        let field = line.strip_prefix("pub ").and_then(|f| f.strip_suffix(','));
        let (name, ty) = field.and_then(|f| f.split_once(": ")).ok_or(format!("cannot read the field `{line}`"))?;
        // Padding std430 adds itself before a vec4 member.
        if ty == "[f32; MAP_STRENGTH_PAD]" {
            comment.clear();
            continue;
        }
        let (glsl, zero, array) = match ty {
            "f32" => ("float", "0.0", ""),
            "u32" => ("uint", "0u", ""),
            "[f32; 4]" => ("vec4", "vec4(0.0)", ""),
            "[u32; 4]" => ("uvec4", "uvec4(0u)", ""),
            "[f32; MAP_COUNT]" => ("float", "0.0", "[MAP_COUNT]"),
            "[[f32; 4]; MAP_COUNT]" => ("vec4", "vec4(0.0)", "[MAP_COUNT]"),
            "[[f32; 2]; MAP_COUNT]" => ("vec2", "vec2(0.0)", "[MAP_COUNT]"),
            other => return Err(format!("field `{name}`: no GLSL type for `{other}`")),
        };
        let note = if comment.is_empty() { String::new() } else { format!(" // {}", comment.join(" ")) };
        members.push_str(&format!("    {glsl} {name}{array};{note}\n"));
        zeros.push_str(&if array.is_empty() {
            format!("    m.{name} = {zero};\n")
        } else {
            format!("    for (int i = 0; i < MAP_COUNT; ++i) {{\n        m.{name}[i] = {zero};\n    }}\n")
        });
        comment.clear();
    }
    Ok(format!(
        "// Written by build.rs from MaterialData in src/render/material_data.rs: edit that.\n\
         struct Material {{\n{members}}};\n\n\
         // A material of zeros, to be filled member by member.\n\
         Material material_zero() {{\n    Material m;\n{zeros}    return m;\n}}\n"
    ))
}
