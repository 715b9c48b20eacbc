//! OBJ/MTL loading against the hand-written fixtures in `tests/fixtures/obj/` (CPU only).
//!
//! The well-formed fixtures check geometry counts, materials, texture coordinates, normals and
//! alpha masks; the malformed ones check that each problem is the right [`ObjError`] variant
//! (or a warning, for textures) and that the message names the file at fault.

use std::path::{Path, PathBuf};

use aa_lab::scene::obj::{ObjError, load_obj};
use aa_lab::scene::{AlphaMode, Mesh, Scene, Vertex};
use glam::Vec3;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/obj")
        .join(name)
}

fn load(name: &str) -> Scene {
    load_obj(&fixture(name)).unwrap_or_else(|e| panic!("{name} should load: {e}"))
}

/// Loads a fixture that must fail, with a message naming the fixture.
fn load_err(name: &str) -> ObjError {
    load_err_naming(name, name)
}

/// Loads a fixture that must fail, with a message naming `culprit`.
fn load_err_naming(name: &str, culprit: &str) -> ObjError {
    match load_obj(&fixture(name)) {
        Ok(_) => panic!("{name} should not load"),
        Err(e) => {
            assert!(
                e.to_string().contains(culprit),
                "message should name {culprit}: {e}"
            );
            e
        }
    }
}

fn mesh<'a>(scene: &'a Scene, name: &str) -> &'a Mesh {
    scene
        .meshes
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("no mesh {name}"))
}

fn vertex_at(mesh: &Mesh, position: [f32; 3]) -> Vertex {
    *mesh
        .vertices
        .iter()
        .find(|v| v.position == position)
        .unwrap_or_else(|| panic!("no vertex at {position:?}"))
}

fn assert_unit_normals(scene: &Scene) {
    for v in scene.meshes.iter().flat_map(|m| &m.vertices) {
        let length = Vec3::from(v.normal).length();
        assert!((length - 1.0).abs() < 1e-5, "normal {:?}", v.normal);
    }
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).length() < 1e-4, "{a} != {b}");
}

/// Checks the camera looks at the centre of the bounds and keeps every vertex in view.
fn assert_framed(scene: &Scene) {
    let (lo, hi) = scene.bounds().expect("bounds");
    let camera = &scene.camera;
    assert_close(camera.target, (lo + hi) * 0.5);
    let radius = scene
        .meshes
        .iter()
        .flat_map(|m| &m.vertices)
        .map(|v| Vec3::from(v.position).distance(camera.target))
        .fold(0.0, f32::max);
    let half_fov = (camera.fov_y_degrees.to_radians() * 0.5).sin();
    assert!(camera.distance * half_fov >= radius, "{camera:?}");
    assert!(camera.near > 0.0 && camera.near < camera.distance - radius);
    assert_eq!(camera.orbit_degrees_per_frame, 0.5);
    assert!(camera.pitch_degrees > 0.0 && camera.pitch_degrees < 45.0);
}

#[test]
fn closed_objects_are_framed_from_outside_and_interiors_seen_inside() {
    // An ordinary closed object: the orbit framing.
    let cube = load("cube.obj");
    assert!(!cube.interior);
    assert_framed(&cube);

    // A room with inward faces: the eye inside, looking level along its long (x) axis.
    let room = load("room.obj");
    assert!(room.interior);
    let pose = aa_lab::scene::camera::OrbitPose::at_frame(&room.camera, 0);
    let (lo, hi) = room.bounds().expect("bounds");
    let eye = pose.eye();
    assert!(eye.cmpgt(lo).all() && eye.cmplt(hi).all(), "{eye}");
    assert!((pose.target - eye).normalize().x > 0.99);
    assert_eq!(room.camera.orbit_degrees_per_frame, 0.0);

    // A box open at +x (the Cornell box's shape): looked into through the opening.
    let set = load("open_box.obj");
    assert!(set.interior);
    let pose = aa_lab::scene::camera::OrbitPose::at_frame(&set.camera, 0);
    let eye = pose.eye();
    assert!(
        eye.x > 2.0 && (eye.y - 2.0).abs() < 1e-4 && eye.z.abs() < 1e-4,
        "{eye}"
    );
    assert!((pose.target - eye).normalize().x < -0.99);
}

#[test]
fn textured_quad_flips_v_to_a_top_left_origin() {
    let scene = load("textured_quad.obj");
    assert_eq!(scene.name, "textured_quad");
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.triangle_count(), 2);
    assert_eq!(scene.vertex_count(), 4);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_framed(&scene);

    let quad = mesh(&scene, "quad");
    // The top-left corner has OBJ (0, 1), which is (0, 0) from the top-left.
    assert_eq!(vertex_at(quad, [-1.0, 1.0, 0.0]).uv, [0.0, 0.0]);
    assert_eq!(vertex_at(quad, [1.0, -1.0, 0.0]).uv, [1.0, 1.0]);
    assert_eq!(vertex_at(quad, [1.0, 1.0, 0.0]).normal, [0.0, 0.0, 1.0]);

    let material = &scene.materials[quad.material];
    assert_eq!(material.name, "quad");
    assert_eq!(material.alpha_mode, AlphaMode::Opaque);
    assert_close(material.base_color, Vec3::ONE);
    let texture = &scene.textures[material.base_color_texture.expect("texture")].image;
    assert_eq!(texture.dimensions(), (2, 2));
    // Row 0 of the image is its top: red, green.
    assert_eq!(texture.get_pixel(0, 0).0, [255, 0, 0, 255]);
    assert_eq!(texture.get_pixel(1, 0).0, [0, 255, 0, 255]);
    assert_eq!(texture.get_pixel(0, 1).0, [0, 0, 255, 255]);
}

#[test]
fn cube_keeps_its_normals_and_gets_the_default_material() {
    let scene = load("cube.obj");
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.triangle_count(), 12);
    assert_eq!(scene.vertex_count(), 24);
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].name, "default");
    assert!(scene.textures.is_empty());
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_framed(&scene);

    let cube = &scene.meshes[0];
    for triangle in cube.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|i| Vec3::from(cube.vertices[triangle[i] as usize].position));
        let face = (b - a).cross(c - a).normalize();
        for &i in triangle {
            let normal = Vec3::from(cube.vertices[i as usize].normal);
            // File normals are kept, and the winding is counter-clockwise seen from outside.
            assert_close(normal, face);
            assert!(normal.dot(a) > 0.0);
        }
    }
}

#[test]
fn polygons_are_triangulated_and_get_unit_normals() {
    let scene = load("ngons.obj");
    assert_eq!(scene.meshes.len(), 4);
    assert_eq!(mesh(&scene, "pentagon").triangle_count(), 3);
    assert_eq!(mesh(&scene, "hexagon").triangle_count(), 4);
    assert_eq!(mesh(&scene, "quad").triangle_count(), 2);
    assert_eq!(mesh(&scene, "sliver").triangle_count(), 1);
    assert_eq!(scene.triangle_count(), 10);
    assert_eq!(scene.materials.len(), 1);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);

    assert_unit_normals(&scene);
    for v in &mesh(&scene, "pentagon").vertices {
        assert_close(Vec3::from(v.normal), Vec3::Z);
    }
    for v in &mesh(&scene, "hexagon").vertices {
        assert_close(Vec3::from(v.normal), Vec3::Z);
    }
    for v in &mesh(&scene, "quad").vertices {
        assert_close(Vec3::from(v.normal), Vec3::X);
    }
    // Without texture coordinates every UV is zero.
    assert!(
        scene
            .meshes
            .iter()
            .flat_map(|m| &m.vertices)
            .all(|v| v.uv == [0.0, 0.0])
    );
}

#[test]
fn materials_carry_colour_and_specular_and_runs_merge() {
    let scene = load("two_materials.obj");
    assert_eq!(scene.meshes.len(), 4, "{:?}", scene.meshes);
    assert_eq!(scene.triangle_count(), 5);
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["red", "blue", "tinted", "default"]);

    let material_of = |object: &str, material: &str| {
        let found: Vec<&Mesh> = scene
            .meshes
            .iter()
            .filter(|m| m.name == object && scene.materials[m.material].name == material)
            .collect();
        assert_eq!(found.len(), 1, "{object} with {material}");
        found[0]
    };
    assert_eq!(material_of("left", "red").triangle_count(), 2);
    assert_eq!(material_of("left", "blue").triangle_count(), 1);
    assert_eq!(material_of("right", "tinted").triangle_count(), 1);
    assert_eq!(material_of("right", "default").triangle_count(), 1);

    // MTL colours are sRGB-encoded: 0.5 decodes to 0.214.
    let red = &scene.materials[0];
    assert_close(red.base_color, Vec3::new(0.214_041, 0.0, 0.0));
    assert_close(red.specular, Vec3::splat(0.214_041));
    assert_eq!(red.shininess, 10.0);
    assert_eq!(red.base_color_texture, None);
    let blue = &scene.materials[1];
    assert_close(blue.base_color, Vec3::Z);
    // A single Ks value stands for grey.
    assert_close(blue.specular, Vec3::splat(0.033_105));
    assert_eq!(blue.shininess, 200.0);
    assert!(
        scene
            .materials
            .iter()
            .all(|m| m.alpha_mode == AlphaMode::Opaque)
    );

    assert_eq!(scene.warnings.len(), 3, "{:?}", scene.warnings);
    let warned = |needle: &str| scene.warnings.iter().any(|w| w.contains(needle));
    assert!(warned("'blue'") && warned("d 0.5"), "{:?}", scene.warnings);
    assert!(
        warned("'tinted'") && warned("Tr 0.25"),
        "{:?}",
        scene.warnings
    );
    assert!(
        warned("nosuch") && warned("two_materials.obj"),
        "{:?}",
        scene.warnings
    );
    assert_unit_normals(&scene);
}

#[test]
fn alpha_maps_merge_into_the_base_texture() {
    let scene = load("alpha_card.obj");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.meshes.len(), 2);
    assert_eq!(scene.textures.len(), 2);
    for m in &scene.materials {
        assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.5 }, "{}", m.name);
    }

    // card: 4x4 green colour map, 2x2 TGA mask (left column clear) resampled to 4x4.
    let card = &scene.materials[mesh(&scene, "card").material];
    assert_close(card.base_color, Vec3::ONE);
    let image = &scene.textures[card.base_color_texture.expect("texture")].image;
    assert_eq!(image.dimensions(), (4, 4));
    for y in 0..4 {
        let row: Vec<[u8; 4]> = (0..4).map(|x| image.get_pixel(x, y).0).collect();
        assert!(row.iter().all(|p| p[..3] == [0, 200, 0]), "{row:?}");
        assert!(row[0][3] < 64 && row[3][3] > 191, "{row:?}");
        assert!(row.windows(2).all(|w| w[0][3] <= w[1][3]), "{row:?}");
    }

    // leaf: no colour map, so a white texture with the PNG's alpha (top row clear).
    let leaf = &scene.materials[mesh(&scene, "leaf").material];
    assert_close(leaf.base_color, srgb(Vec3::new(0.2, 0.6, 0.1)));
    let image = &scene.textures[leaf.base_color_texture.expect("texture")].image;
    assert_eq!(image.dimensions(), (2, 2));
    assert_eq!(image.get_pixel(0, 0).0, [255, 255, 255, 0]);
    assert_eq!(image.get_pixel(1, 1).0, [255, 255, 255, 255]);
}

fn srgb(c: Vec3) -> Vec3 {
    c.to_array().map(aa_lab::srgb::decode).into()
}

#[test]
fn textures_resolve_relative_to_the_mtl_with_backslashes_and_options() {
    let scene = load("subdir_texture.obj");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.textures.len(), 1);
    let texture = &scene.textures[0];
    assert!(texture.label.contains("wood.jpg"), "{}", texture.label);
    assert_eq!(texture.image.dimensions(), (8, 8));
    // JPEG is lossy: orange on top, dark brown below, within a few levels.
    let near = |p: [u8; 4], rgb: [u8; 3]| (0..3).all(|c| p[c].abs_diff(rgb[c]) <= 6);
    assert!(near(texture.image.get_pixel(1, 1).0, [230, 120, 30]));
    assert!(near(texture.image.get_pixel(6, 6).0, [80, 40, 10]));
}

fn assert_checker_with_warning(name: &str, texture_file: &str) {
    let scene = load(name);
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    let warning = &scene.warnings[0];
    assert!(warning.contains(texture_file), "{warning}");
    assert!(warning.contains("checker"), "{warning}");
    let material = &scene.materials[0];
    assert_close(material.base_color, Vec3::ONE);
    let image = &scene.textures[material.base_color_texture.expect("checker")].image;
    let colours: std::collections::HashSet<[u8; 4]> = image.pixels().map(|p| p.0).collect();
    assert_eq!(
        colours,
        [[255, 0, 255, 255], [0, 0, 0, 255]].into_iter().collect()
    );
}

#[test]
fn missing_texture_becomes_a_checker_and_a_warning() {
    assert_checker_with_warning("missing_texture.obj", "not_here.png");
}

#[test]
fn corrupt_texture_becomes_a_checker_and_a_warning() {
    assert_checker_with_warning("corrupt_texture.obj", "corrupt.png");
}

#[test]
fn empty_and_faceless_files_are_errors() {
    assert!(matches!(load_err("empty.obj"), ObjError::NoFaces { .. }));
    assert!(matches!(load_err("no_faces.obj"), ObjError::NoFaces { .. }));
}

#[test]
fn binary_garbage_is_an_error() {
    assert!(matches!(load_err("garbage.obj"), ObjError::NotText { .. }));
}

#[test]
fn out_of_range_face_index_is_an_error() {
    let error = load_err("bad_index.obj");
    assert!(
        matches!(
            error,
            ObjError::IndexOutOfRange {
                line: 7,
                index: 7,
                count: 4,
                ..
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("line 7"), "{error}");
}

#[test]
fn nan_coordinate_is_an_error() {
    let error = load_err("nan_vertex.obj");
    assert!(
        matches!(
            error,
            ObjError::NonFinite {
                line: 4,
                index: 3,
                ..
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("vertex 3"), "{error}");
}

#[test]
fn missing_mtl_is_an_error_naming_the_library() {
    let error = load_err_naming("missing_mtl.obj", "does_not_exist.mtl");
    assert!(matches!(error, ObjError::MissingMtl { .. }), "{error:?}");
    assert!(error.to_string().contains("missing_mtl.obj"), "{error}");
}

#[test]
fn malformed_mtl_is_an_error_naming_the_library() {
    let error = load_err_naming("bad_mtl.obj", "bad_mtl.mtl");
    assert!(
        matches!(error, ObjError::Syntax { line: 2, .. }),
        "{error:?}"
    );
}

#[test]
fn unreadable_paths_are_io_errors() {
    let directory = fixture("");
    let error = load_obj(&directory).expect_err("a directory is not an OBJ file");
    assert!(
        matches!(
            error,
            ObjError::File(aa_lab::files::FileError::NotAFile { .. })
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("a directory"), "{error}");

    let error = load_obj(&fixture("nowhere.obj")).expect_err("missing file");
    assert!(matches!(error, ObjError::Io { .. }), "{error:?}");
    assert!(error.to_string().contains("nowhere.obj"), "{error}");
}

#[test]
fn records_tobj_would_mishandle_are_normalised() {
    let scene = load("awkward_records.obj");
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.meshes[0].name, "panel");
    assert_eq!(scene.triangle_count(), 2);
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].name, "paint");
    assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
    assert!(scene.warnings.iter().any(|w| w.contains("polyline")));
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("fewer than three"))
    );
}

#[test]
fn ignored_material_statements_are_listed_in_one_note() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl a\nKd 1 0 0\nNi 1.5\nbump n.png\nmap_bump n.png\nTf 1 1 1\nKe 0 0 0\nillum 2\n\
         newmtl b\nNi 1.2\n",
    )
    .expect("write mtl");
    let obj = dir.path().join("m.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    )
    .expect("write obj");
    let scene = load_obj(&obj).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.notes.len(), 1, "{:?}", scene.notes);
    let note = &scene.notes[0];
    for listed in [
        "Ni (2)",
        "bump (1)",
        "map_bump (1)",
        "Tf (1)",
        "Ke (1)",
        "illum (1)",
    ] {
        assert!(note.contains(listed), "`{listed}` missing from: {note}");
    }
    assert!(!note.contains("Kd"), "{note}");
}
