//! Turns `tobj`'s models and materials into the scene: vertices (UV `v` flipped to the
//! renderer's top-left origin, area-weighted normals where the model has none, smooth across
//! UV seams), one mesh per (object, material) pair, and the renderer's materials from MTL
//! colours, exponents and textures.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::mtl::{Textures, parse_texture_ref, srgb_color};
use crate::scene::{AlphaMode, CameraRig, DirectionalLight, Material, Mesh, Scene, Vertex};

/// Background colour of OBJ scenes: a neutral mid-dark grey (linear RGB).
const CLEAR_COLOR: Vec3 = Vec3::splat(0.1);

/// Turns `tobj`'s models and materials into the scene's meshes, materials and textures.
pub(super) struct SceneBuilder<'a> {
    pub(super) obj: &'a Path,
    /// Materials of all libraries, in `tobj`'s order.
    pub(super) library: &'a [tobj::Material],
    /// MTL file of each library material.
    pub(super) sources: &'a [PathBuf],
    pub(super) meshes: Vec<Mesh>,
    /// Mesh of each (object name, scene material).
    pub(super) mesh_slots: HashMap<(String, usize), usize>,
    /// Scene material of each library material (`None`: the default material).
    pub(super) material_slots: HashMap<Option<usize>, usize>,
    pub(super) materials: Vec<Material>,
    pub(super) textures: Textures,
    pub(super) warnings: Vec<String>,
}

impl SceneBuilder<'_> {
    pub(super) fn add_model(&mut self, model: &tobj::Model) {
        if model.mesh.indices.is_empty() {
            return;
        }
        let material = self.material_slot(model.mesh.material_id);
        let vertices = self.model_vertices(model);
        let slot = *self
            .mesh_slots
            .entry((model.name.clone(), material))
            .or_insert_with(|| {
                self.meshes.push(Mesh {
                    name: model.name.clone(),
                    vertices: Vec::new(),
                    indices: Vec::new(),
                    material,
                    spin: None,
                });
                self.meshes.len() - 1
            });
        let mesh = &mut self.meshes[slot];
        let base = mesh.vertices.len() as u32;
        mesh.indices
            .extend(model.mesh.indices.iter().map(|&i| base + i));
        mesh.vertices.extend(vertices);
    }

    /// Vertices of a `tobj` model: flipped UVs, normals from the file or generated.
    pub(super) fn model_vertices(&mut self, model: &tobj::Model) -> Vec<Vertex> {
        let mesh = &model.mesh;
        let positions: Vec<Vec3> = mesh
            .positions
            .chunks_exact(3)
            .map(Vec3::from_slice)
            .collect();
        let count = positions.len();
        let partial = |what: &str| {
            format!(
                "{}: object '{}' has {what} on only some face corners; ",
                self.obj.display(),
                model.name
            )
        };

        let texcoords = match mesh.texcoords.len() {
            n if n == 2 * count => Some(&mesh.texcoords),
            0 => None,
            _ => {
                self.warnings
                    .push(partial("texture coordinates") + "its texture coordinates are dropped");
                None
            }
        };
        let file_normals: Option<Vec<Option<Vec3>>> =
            (mesh.normals.len() == 3 * count).then(|| {
                mesh.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::from_slice(n).try_normalize())
                    .collect()
            });
        if file_normals.is_none() && !mesh.normals.is_empty() {
            self.warnings
                .push(partial("normals") + "smooth normals are generated instead");
        }
        let generated = || smooth_normals(&positions, &mesh.indices);
        let normals: Vec<Vec3> = match file_normals {
            None => generated(),
            Some(file) if file.iter().all(Option::is_some) => file.into_iter().flatten().collect(),
            // Zero-length normals in the file: generated ones stand in for them.
            Some(file) => file
                .into_iter()
                .zip(generated())
                .map(|(file, generated)| file.unwrap_or(generated))
                .collect(),
        };

        positions
            .iter()
            .zip(normals)
            .enumerate()
            .map(|(i, (&position, normal))| {
                let uv = texcoords.map_or([0.0, 0.0], |t| [t[2 * i], 1.0 - t[2 * i + 1]]);
                Vertex::new(position, normal, uv)
            })
            .collect()
    }

    /// Index in the scene's materials of a library material (`None`: the default material).
    pub(super) fn material_slot(&mut self, library_index: Option<usize>) -> usize {
        if let Some(&slot) = self.material_slots.get(&library_index) {
            return slot;
        }
        let material =
            match library_index.and_then(|i| Some((self.library.get(i)?, self.sources.get(i)?))) {
                Some((material, source)) => self.convert_material(material, source),
                None => Material::default(),
            };
        let slot = self.materials.len();
        self.materials.push(material);
        self.material_slots.insert(library_index, slot);
        slot
    }

    pub(super) fn convert_material(&mut self, mtl: &tobj::Material, source: &Path) -> Material {
        let dir = source.parent().unwrap_or(Path::new(""));
        let usage = format!("material '{}' in {}", mtl.name, source.display());
        let base_map = mtl
            .diffuse_texture
            .as_deref()
            .map(|s| parse_texture_ref(s, dir));
        let mask_map = mtl
            .dissolve_texture
            .as_deref()
            .map(|s| parse_texture_ref(s, dir));
        let has_map = base_map.is_some();
        let masked = mask_map.is_some();

        let defaults = Material::default();
        let mut material = Material {
            name: mtl.name.clone(),
            base_color: match mtl.diffuse {
                Some(kd) => srgb_color(kd),
                None if has_map => Vec3::ONE,
                None => defaults.base_color,
            },
            specular: mtl.specular.map_or(defaults.specular, srgb_color),
            shininess: mtl.shininess.map_or(defaults.shininess, |ns| ns.max(0.0)),
            ..defaults
        };

        if has_map || masked {
            let (texture, failed) =
                self.textures
                    .material_texture(base_map, mask_map, &usage, &mut self.warnings);
            material.base_color_texture = Some(texture);
            if failed {
                // The checker must show at full strength whatever the material's colour.
                material.base_color = Vec3::ONE;
            } else if masked {
                material.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
            }
        }

        let dissolve = mtl.dissolve.filter(|&d| d < 1.0).map(|d| format!("d {d}"));
        let transparency = mtl
            .unknown_param
            .get("Tr")
            .and_then(|tr| tr.split_whitespace().next()?.parse::<f32>().ok())
            .filter(|&tr| tr > 0.0)
            .map(|tr| format!("Tr {tr}"));
        if let Some(record) = dissolve.or(transparency) {
            self.warnings.push(format!(
                "{usage} asks for translucency ({record}), which is not supported; \
                 it is drawn opaque"
            ));
        }
        material
    }

    pub(super) fn finish(self) -> Scene {
        Scene {
            name: self
                .obj
                .file_stem()
                .map_or_else(|| "obj".to_owned(), |s| s.to_string_lossy().into_owned()),
            meshes: self.meshes,
            materials: self.materials,
            textures: self.textures.images,
            camera: CameraRig::default(),
            interior: false,
            light: DirectionalLight::default(),
            clear_color: CLEAR_COLOR,
            views: Vec::new(),
            notes: Vec::new(),
            warnings: self.warnings,
        }
    }
}

/// Area-weighted smooth vertex normals of a triangle list.
///
/// Face normals weighted by area (the un-normalised cross product) are summed over all
/// vertices at the same position, so seams in the texture coordinates do not show in the
/// shading. A vertex whose sum vanishes (only degenerate faces, or faces that cancel) takes
/// the normal of its first non-degenerate face, or +Y.
pub(super) fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut groups: HashMap<[u32; 3], usize> = HashMap::new();
    let group_of: Vec<usize> = positions
        .iter()
        .map(|p| {
            // Adding zero turns -0.0 into 0.0, so both spellings of a position share a group.
            let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            let next = groups.len();
            *groups.entry(key).or_insert(next)
        })
        .collect();
    let mut sums = vec![Vec3::ZERO; groups.len()];
    let mut first_face: Vec<Option<Vec3>> = vec![None; groups.len()];
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let weighted = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        let unit = weighted.try_normalize();
        for v in [a, b, c] {
            let group = group_of[v];
            sums[group] += weighted;
            if first_face[group].is_none() {
                first_face[group] = unit;
            }
        }
    }
    group_of
        .iter()
        .map(|&g| sums[g].try_normalize().or(first_face[g]).unwrap_or(Vec3::Y))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normals_weight_by_area_and_survive_degenerate_faces() {
        // A big triangle facing +Z and a small one facing +X share vertex 0.
        let positions = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
            // A face of three collinear points, alone.
            Vec3::new(5.0, 5.0, 5.0),
            Vec3::new(6.0, 6.0, 6.0),
            Vec3::new(7.0, 7.0, 7.0),
        ];
        let indices = [0, 1, 2, 0, 3, 4, 5, 6, 7];
        let normals = smooth_normals(&positions, &indices);
        assert!(
            normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5),
            "{normals:?}"
        );
        assert!(normals[0].z > 0.9 && normals[0].x > 0.0, "{}", normals[0]);
        assert_eq!(normals[1], Vec3::Z);
        assert_eq!(normals[5], Vec3::Y);
    }

    #[test]
    fn smooth_normals_join_uv_seams() {
        // Two triangles of a bent strip meet at an edge duplicated for a UV seam.
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, 1.0, 1.0),
        ];
        let normals = smooth_normals(&positions, &[0, 1, 2, 3, 5, 4]);
        assert!((normals[1] - normals[3]).length() < 1e-6);
        assert!((normals[2] - normals[4]).length() < 1e-6);
    }
}
