//! Empty on purpose: this crate exists for its build script, whose link directives reach
//! every artifact that depends on it (argil's `build.rs`, which links shaderc).
