//! A glTF primitive turned into a [`Mesh`]: its attributes read and transformed to world
//! space, strips and fans turned into triangle lists, indices checked against the vertex
//! count, and flat normals generated where the file has none, as the specification asks.

use super::*;

impl Loader<'_> {
    pub(super) fn add_primitive(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        world: Mat4,
    ) -> Result<(), GltfError> {
        use gltf::mesh::Mode;
        let name = format!(
            "{}, primitive {}",
            describe("mesh", mesh.index(), mesh.name()),
            primitive.index()
        );
        if !matches!(
            primitive.mode(),
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.skipped_modes.push(name);
            return Ok(());
        }
        let positions = primitive
            .get(&gltf::Semantic::Positions)
            .ok_or_else(|| self.invalid(format!("{name} has no POSITION attribute")))?;
        self.check_size(&name, positions.count(), 0)?;
        let positions = self.read(&positions, 3, &format!("{name} POSITION"))?;
        let vertex_count = positions.len() / 3;
        let positions: Vec<Vec3> = positions
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
            .collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(self.invalid(format!("{name}: POSITION {i} is not finite")));
        }

        let raw_indices: Vec<u32> = match primitive.indices() {
            Some(accessor) => {
                let what = format!("{name} indices");
                if matches!(
                    accessor.data_type(),
                    gltf::accessor::DataType::F32
                        | gltf::accessor::DataType::I8
                        | gltf::accessor::DataType::I16
                ) {
                    return Err(self.invalid(format!(
                        "{what}: component type {:?} is not an unsigned integer",
                        accessor.data_type()
                    )));
                }
                let values = self.read(&accessor, 1, &what)?;
                if let Some(bad) = values.iter().find(|&&v| v >= vertex_count as f64) {
                    return Err(self.invalid(format!(
                        "{what}: vertex index {bad} is out of range ({vertex_count} vertices)"
                    )));
                }
                values.into_iter().map(|v| v as u32).collect()
            }
            None => (0..u32::try_from(vertex_count).unwrap_or(u32::MAX)).collect(),
        };
        let mut indices = triangle_list(primitive.mode(), &raw_indices);

        let (material, tex_coord) = self.material(&primitive.material());
        let uvs = match primitive.get(&gltf::Semantic::TexCoords(tex_coord)) {
            Some(accessor) => {
                let uvs = self.read(&accessor, 2, &format!("{name} TEXCOORD_{tex_coord}"))?;
                if uvs.len() != vertex_count * 2 {
                    return Err(self.invalid(format!(
                        "{name}: TEXCOORD_{tex_coord} has {} elements, POSITION {vertex_count}",
                        uvs.len() / 2
                    )));
                }
                uvs.chunks_exact(2)
                    .map(|uv| [uv[0] as f32, uv[1] as f32])
                    .collect()
            }
            None => vec![[0.0; 2]; vertex_count],
        };
        let normals = match primitive.get(&gltf::Semantic::Normals) {
            Some(accessor) => {
                let normals = self.read(&accessor, 3, &format!("{name} NORMAL"))?;
                if normals.len() != vertex_count * 3 {
                    return Err(self.invalid(format!(
                        "{name}: NORMAL has {} elements, POSITION {vertex_count}",
                        normals.len() / 3
                    )));
                }
                Some(
                    normals
                        .chunks_exact(3)
                        .map(|n| Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32))
                        .collect::<Vec<_>>(),
                )
            }
            None => None,
        };

        // Bake the node transform; a mirroring one flips the winding.
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        if Mat3::from_mat4(world).determinant() < 0.0 {
            for triangle in indices.chunks_exact_mut(3) {
                triangle.swap(1, 2);
            }
        }
        let world_positions: Vec<Vec3> = positions
            .iter()
            .map(|&p| world.transform_point3(p))
            .collect();
        let (vertices, indices) = match normals {
            Some(normals) => {
                let vertices = world_positions
                    .iter()
                    .zip(&normals)
                    .zip(&uvs)
                    .map(|((&p, &n), &uv)| {
                        let n = (normal_matrix * n).try_normalize().unwrap_or(Vec3::Y);
                        Vertex::new(p, n, uv)
                    })
                    .collect();
                (vertices, indices)
            }
            None => flat_shaded(&world_positions, &uvs, &indices),
        };
        self.check_size(&name, vertices.len(), indices.len())?;
        self.scene_vertices += vertices.len();
        self.scene_indices += indices.len();
        self.meshes.push(Mesh {
            name,
            vertices,
            indices,
            material,
            spin: None,
        });
        Ok(())
    }
}

/// A triangle list from the indices of a triangle list, strip or fan (strips alternate
/// winding so every triangle keeps the first one's orientation).
fn triangle_list(mode: gltf::mesh::Mode, indices: &[u32]) -> Vec<u32> {
    use gltf::mesh::Mode;
    match mode {
        Mode::TriangleStrip => (2..indices.len())
            .flat_map(|i| {
                let (a, b, c) = (indices[i - 2], indices[i - 1], indices[i]);
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => (2..indices.len())
            .flat_map(|i| [indices[0], indices[i - 1], indices[i]])
            .collect(),
        _ => indices[..indices.len() - indices.len() % 3].to_vec(),
    }
}

/// Flat-shaded vertices (each triangle its own three, with the face normal), as the
/// specification asks when a primitive has no normals. Degenerate faces get +Y.
fn flat_shaded(positions: &[Vec3], uvs: &[[f32; 2]], indices: &[u32]) -> (Vec<Vertex>, Vec<u32>) {
    let mut vertices = Vec::with_capacity(indices.len());
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let normal = (positions[b] - positions[a])
            .cross(positions[c] - positions[a])
            .try_normalize()
            .unwrap_or(Vec3::Y);
        for i in [a, b, c] {
            vertices.push(Vertex::new(positions[i], normal, uvs[i]));
        }
    }
    let indices = (0..u32::try_from(vertices.len()).unwrap_or(u32::MAX)).collect();
    (vertices, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        use gltf::mesh::Mode;
        assert_eq!(
            triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3]),
            vec![0, 1, 2, 2, 1, 3]
        );
        assert_eq!(
            triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]),
            vec![0, 1, 2, 0, 2, 3]
        );
        assert_eq!(triangle_list(Mode::Triangles, &[0, 1, 2, 3]), vec![0, 1, 2]);
    }
}
