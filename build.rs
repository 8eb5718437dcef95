//! Compiles every GLSL stage in `shaders/` to SPIR-V in `OUT_DIR`, where `src/render/shaders.rs`
//! embeds it. `#include "x.glsl"` resolves against the including file's folder, then
//! `shaders/lib/`. A compile error fails the build, naming the file and line.
use std::path::{Path, PathBuf};

// Linked for its build script's link directives (see crates/shaderc-system-link).
#[cfg(feature = "system-shaderc")]
extern crate shaderc_system_link;

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

    let compiler = shaderc::Compiler::new().expect("shaderc compiler could not be created");
    let mut failures = Vec::new();
    for source in sorted_files(&shader_dir) {
        let ext = source.extension().and_then(|e| e.to_str()).unwrap_or("");
        let Some(&(_, kind)) = STAGES.iter().find(|(e, _)| *e == ext) else {
            continue;
        };
        println!("cargo:rerun-if-changed={}", source.display());
        let text = std::fs::read_to_string(&source).unwrap_or_else(|e| panic!("cannot read {}: {e}", source.display()));
        let mut options = shaderc::CompileOptions::new().unwrap();
        options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
        options.set_source_language(shaderc::SourceLanguage::GLSL);
        options.set_optimization_level(shaderc::OptimizationLevel::Performance);
        options.set_generate_debug_info();
        options.set_warnings_as_errors();
        let lib_dir = lib_dir.clone();
        options.set_include_callback(move |name, _ty, from, _depth| {
            let from_dir = Path::new(from).parent().unwrap_or(Path::new("."));
            let path = [from_dir.join(name), lib_dir.join(name)]
                .into_iter()
                .find(|p| p.is_file())
                .ok_or_else(|| format!("{from}: cannot find include \"{name}\""))?;
            let content = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(shaderc::ResolvedInclude {
                resolved_name: path.display().to_string(),
                content,
            })
        });
        let name = source.file_name().unwrap().to_string_lossy().into_owned();
        match compiler.compile_into_spirv(&text, kind, &source.display().to_string(), "main", Some(&options)) {
            Ok(artifact) => {
                std::fs::write(out_dir.join(format!("{name}.spv")), artifact.as_binary_u8())
                    .expect("cannot write SPIR-V to OUT_DIR");
            }
            Err(e) => failures.push(e.to_string()),
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
