//! Every WGSL file under `shaders/` parses and validates with naga (no GPU needed), with all
//! capabilities this engine may use, and every file is listed in `gpu::shader::SHADERS` so that
//! none escapes this test or the binary.

use std::path::Path;

#[test]
fn every_shader_validates_with_naga() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".wgsl"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no shaders found in {}", dir.display());
    let mut failures = Vec::new();
    for name in &files {
        let source = std::fs::read_to_string(dir.join(name)).expect("readable shader");
        let module = match naga::front::wgsl::parse_str(&source) {
            Ok(module) => module,
            Err(err) => {
                failures.push(format!(
                    "{name}: parse error:\n{}",
                    err.emit_to_string(&source)
                ));
                continue;
            }
        };
        let mut validator = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        );
        if let Err(err) = validator.validate(&module) {
            failures.push(format!(
                "{name}: validation error:\n{}",
                err.emit_to_string(&source)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_shader_file_is_compiled_into_the_binary() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    for entry in std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .filter_map(|e| e.ok())
    {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.ends_with(".wgsl") {
            let listed = aa_lab::gpu::shader::SHADERS
                .iter()
                .find(|(file, _)| *file == name);
            let source = std::fs::read_to_string(entry.path()).expect("readable shader");
            assert_eq!(
                listed.map(|(_, s)| *s),
                Some(source.as_str()),
                "{name} is missing from gpu::shader::SHADERS"
            );
        }
    }
}
