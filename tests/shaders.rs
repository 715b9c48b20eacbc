//! Every WGSL file under `shaders/` and in the technique folders `src/aa/<name>/` parses and
//! validates with naga (no GPU needed), with all capabilities this engine may use, and every
//! file is listed in `gpu::shader::SHADERS` so that none escapes this test or the binary.

use std::path::{Path, PathBuf};

/// Every `.wgsl` file of `shaders/` and of the folders under `src/aa/`, as (file name, path),
/// sorted by name.
fn wgsl_files() -> Vec<(String, PathBuf)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let technique_dirs = std::fs::read_dir(root.join("src/aa"))
        .expect("src/aa exists")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.is_dir());
    let mut files: Vec<(String, PathBuf)> = std::iter::once(root.join("shaders"))
        .chain(technique_dirs)
        .flat_map(|dir| {
            std::fs::read_dir(&dir)
                .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
                .filter_map(|e| e.ok())
        })
        .map(|e| (e.file_name().to_string_lossy().into_owned(), e.path()))
        .filter(|(name, _)| name.ends_with(".wgsl"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_shader_validates_with_naga() {
    let files = wgsl_files();
    assert!(!files.is_empty(), "no shaders found");
    let mut failures = Vec::new();
    for (name, path) in &files {
        let source = std::fs::read_to_string(path).expect("readable shader");
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
    let files = wgsl_files();
    assert!(
        files
            .iter()
            .any(|(_, p)| p.starts_with(Path::new(env!("CARGO_MANIFEST_DIR")).join("src"))),
        "no shader found in the technique folders"
    );
    for (name, path) in files {
        let listed = aa_lab::gpu::shader::SHADERS
            .iter()
            .find(|(file, _)| *file == name);
        let source = std::fs::read_to_string(&path).expect("readable shader");
        assert_eq!(
            listed.map(|(_, s)| *s),
            Some(source.as_str()),
            "{} is missing from gpu::shader::SHADERS",
            path.display()
        );
    }
}
