//! Every WGSL file under `shaders/` and in the technique folders under `src/aa/` parses and
//! validates with naga (no GPU needed), with all capabilities this engine may use, and every
//! file is listed in `gpu::shader::SHADERS` so that none escapes this test or the binary.

use std::path::{Path, PathBuf};

/// Every `.wgsl` file under `dir`, recursively.
fn wgsl_under(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok())
    {
        let path = entry.path();
        if path.is_dir() {
            wgsl_under(&path, files);
        } else if path.extension().is_some_and(|x| x == "wgsl") {
            files.push(path);
        }
    }
}

/// The shader files of the crate: `shaders/` and `src/aa/`.
fn shader_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    wgsl_under(&root.join("shaders"), &mut files);
    wgsl_under(&root.join("src/aa"), &mut files);
    files.sort();
    files
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[test]
fn every_shader_validates_with_naga() {
    let files = shader_files();
    assert!(!files.is_empty(), "no shaders found");
    let mut failures = Vec::new();
    for path in &files {
        let name = path.display();
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
    for path in shader_files() {
        let name = file_name(&path);
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
