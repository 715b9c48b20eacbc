//! Every WGSL file of the repository (the shared ones under `shaders/`, each technique's in its
//! folder under `src/aa/`) parses and validates with naga (no GPU needed), with all
//! capabilities this engine may use, and every file is compiled into the binary: listed in
//! `gpu::shader::SHADERS` or in its technique's registry entry, so that none escapes this test
//! or the binary.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use aa_lab::aa::user::program;
use aa_lab::gpu::shader::{SHADERS, Shader};

/// Every `.wgsl` file under `dir`, recursively, as a path relative to the repository root
/// with `/` separators.
fn wgsl_files(root: &Path, dir: &Path, out: &mut Vec<String>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries.filter_map(|e| e.ok()) {
        let path = entry.path();
        if path.is_dir() {
            wgsl_files(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            let relative = path.strip_prefix(root).expect("under the root");
            let parts: Vec<String> = relative
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            out.push(parts.join("/"));
        }
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every WGSL file in the repository.
fn files_on_disk() -> Vec<String> {
    let root = root();
    let mut files = Vec::new();
    for dir in ["shaders", "src"] {
        wgsl_files(&root, &root.join(dir), &mut files);
    }
    files.sort();
    files
}

/// Every shader compiled into the binary, by path: the shared list and every technique's.
fn listed() -> BTreeMap<&'static str, Shader> {
    let mut listed = BTreeMap::new();
    let techniques = aa_lab::aa::registry();
    let all = SHADERS
        .iter()
        .chain(techniques.iter().flat_map(|t| t.shaders.iter()))
        .chain(aa_lab::aa::scaled::SHADERS);
    for shader in all.chain(USER_FRAGMENTS) {
        listed.insert(shader.path, *shader);
    }
    listed
}

/// The prelude and epilogue of user techniques: not shaders on their own, but validated around
/// every example user technique by
/// `every_example_user_technique_compiles_between_the_prelude_and_epilogue`.
const USER_FRAGMENTS: [&Shader; 2] = [&program::PRELUDE, &program::EPILOGUE];

/// The example user techniques under `assets/user_techniques/`.
fn example_user_techniques() -> Vec<PathBuf> {
    let dir = root().join("assets/user_techniques");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_shader_validates_with_naga() {
    let files = files_on_disk();
    assert!(
        files.iter().any(|f| f.starts_with("shaders/"))
            && files.iter().any(|f| f.starts_with("src/aa/")),
        "shaders missing: {files:?}"
    );
    let mut failures = Vec::new();
    let fragments: Vec<&str> = USER_FRAGMENTS.iter().map(|s| s.path).collect();
    let listed = listed();
    for name in files.iter().filter(|f| !fragments.contains(&f.as_str())) {
        let on_disk = std::fs::read_to_string(root().join(name)).expect("readable shader");
        // A file with a prelude is validated as the GPU compiles it: the prelude (after its own),
        // then the file.
        let source = match listed.get(name.as_str()).and_then(|s| s.prelude) {
            Some(prelude) => format!("{}\n{on_disk}", prelude.composed_source()),
            None => on_disk,
        };
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
fn every_shader_file_is_compiled_into_the_binary_and_every_listed_one_exists() {
    let listed = listed();
    let files = files_on_disk();
    for name in &files {
        let source = std::fs::read_to_string(root().join(name)).expect("readable shader");
        assert_eq!(
            listed.get(name.as_str()).map(|s| s.source),
            Some(source.as_str()),
            "{name} is in neither gpu::shader::SHADERS, aa::scaled::SHADERS nor its technique's \
             registry entry"
        );
    }
    for path in listed.keys() {
        assert!(
            files.iter().any(|f| f == path),
            "{path} is listed but no such file exists"
        );
    }
}

#[test]
fn shared_shaders_stay_in_shaders_and_technique_shaders_in_their_folders() {
    for shader in SHADERS {
        assert!(shader.path.starts_with("shaders/"), "{}", shader.path);
    }
    for shader in aa_lab::aa::scaled::SHADERS {
        assert!(shader.path.starts_with("src/aa/scaled/"), "{}", shader.path);
    }
    for technique in aa_lab::aa::registry() {
        for shader in technique.shaders {
            assert!(
                shader.path.starts_with("src/aa/"),
                "{}: {}",
                technique.id,
                shader.path
            );
        }
    }
    // Shared shaders are looked up by file name, so their names are unique.
    let mut names: Vec<&str> = SHADERS.iter().map(Shader::name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), SHADERS.len());
}

#[test]
fn every_example_user_technique_compiles_between_the_prelude_and_epilogue() {
    let examples = example_user_techniques();
    assert!(!examples.is_empty(), "no example in assets/user_techniques");
    for path in examples {
        let bytes = std::fs::read(&path).expect("readable example");
        if let Err(err) = program::compile(&path, &bytes) {
            panic!("{err}");
        }
    }
}
