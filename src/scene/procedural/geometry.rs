//! Triangle-mesh building blocks shared by the procedural scenes: a [`MeshBuilder`] that
//! appends vertices and counter-clockwise triangles, and the shapes built from it (swept
//! tubes, surfaces of revolution, boxes, quads, rotated copies).
//!
//! Curved shapes are laid out as a grid of vertex rings: `u` runs around (or across) the shape
//! and `v` along it, and [`MeshBuilder::grid`] stitches `(nu + 1) x (nv + 1)` vertices into
//! quads whose front face is the side `dp/du x dp/dv` points to. Seams duplicate their
//! vertices so that texture coordinates stay continuous. Tubes use a parallel-transport frame
//! (the previous ring's normal projected onto the new ring's plane), which keeps them free of
//! twists and costs one projection per ring; ring normals are exact radial unit vectors.

use glam::{Mat3, Vec2, Vec3};

use crate::scene::{Mesh, Spin, Vertex};

/// Appends vertices and triangles for one mesh.
#[derive(Clone, Debug, Default)]
pub(crate) struct MeshBuilder {
    pub(crate) vertices: Vec<Vertex>,
    pub(crate) indices: Vec<u32>,
}

/// A surface-of-revolution profile point: radius and height.
pub(crate) type ProfilePoint = Vec2;

impl MeshBuilder {
    /// An empty builder with room for `vertices` vertices and `triangles` triangles.
    pub(crate) fn with_capacity(vertices: usize, triangles: usize) -> Self {
        Self {
            vertices: Vec::with_capacity(vertices),
            indices: Vec::with_capacity(triangles * 3),
        }
    }

    /// Index the next pushed vertex gets.
    fn next_index(&self) -> u32 {
        self.vertices.len() as u32
    }

    /// Appends one vertex and returns its index.
    pub(crate) fn vertex(&mut self, position: Vec3, normal: Vec3, uv: [f32; 2]) -> u32 {
        let index = self.next_index();
        self.vertices.push(Vertex::new(position, normal, uv));
        index
    }

    /// Appends a triangle (counter-clockwise seen from the front).
    pub(crate) fn triangle(&mut self, a: u32, b: u32, c: u32) {
        self.indices.extend_from_slice(&[a, b, c]);
    }

    /// Appends the quad `a b c d` (counter-clockwise seen from the front) as two triangles.
    pub(crate) fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.indices.extend_from_slice(&[a, b, c, a, c, d]);
    }

    /// Appends a quad from four corners in order around its edge (either direction), with
    /// per-corner normals and texture coordinates, wound so that it faces `facing`.
    pub(crate) fn quad_facing(&mut self, corners: [(Vec3, Vec3, Vec2); 4], facing: Vec3) {
        let [a, b, c, d] = corners.map(|(p, n, uv)| self.vertex(p, n, uv.to_array()));
        let (p0, p1, p2) = (corners[0].0, corners[1].0, corners[2].0);
        // The larger triangle's normal decides (one of the two may be degenerate).
        let p3 = corners[3].0;
        let normal = (p1 - p0).cross(p2 - p0) + (p2 - p0).cross(p3 - p0);
        if normal.dot(facing) >= 0.0 {
            self.quad(a, b, c, d);
        } else {
            self.quad(a, d, c, b);
        }
    }

    /// Stitches the `(nu + 1) * (nv + 1)` vertices pushed last (row by row: `v` outer, `u`
    /// inner, starting at `base`) into quads facing where `dp/du x dp/dv` points.
    pub(crate) fn grid(&mut self, base: u32, nu: u32, nv: u32) {
        let row = nu + 1;
        for j in 0..nv {
            for i in 0..nu {
                let a = base + j * row + i;
                self.quad(a, a + 1, a + 1 + row, a + row);
            }
        }
    }

    /// A UV sphere about `center` with `around` segments around and half as many from pole
    /// to pole, facing outwards, with exact radial normals.
    pub(crate) fn uv_sphere(&mut self, center: Vec3, radius: f32, around: u32) {
        let base = self.next_index();
        let along = around / 2;
        for j in 0..=along {
            let latitude = (j as f32 / along as f32 - 0.5) * std::f32::consts::PI;
            for i in 0..=around {
                let longitude = i as f32 / around as f32 * std::f32::consts::TAU;
                let normal = Vec3::new(
                    latitude.cos() * longitude.sin(),
                    latitude.sin(),
                    latitude.cos() * longitude.cos(),
                );
                let uv = [i as f32 / around as f32, 1.0 - j as f32 / along as f32];
                self.vertex(center + normal * radius, normal, uv);
            }
        }
        self.grid(base, around, along);
    }

    /// A flat quad seen from its front as `origin` (bottom-left), `origin + right`,
    /// `origin + right + up`, `origin + up`; it faces `right x up`. Texture coordinates
    /// are planar in world units: one repeat per `texel_world`, u growing along `right` and
    /// v growing downwards, measured from the world origin so that adjacent quads continue
    /// the same texture.
    pub(crate) fn plane(&mut self, origin: Vec3, right: Vec3, up: Vec3, texel_world: f32) {
        let uv = |p: Vec3| {
            Vec2::new(
                p.dot(right.normalize()) / texel_world,
                -p.dot(up.normalize()) / texel_world,
            )
        };
        self.plane_uv(origin, right, up, uv(origin), uv(origin + right + up));
    }

    /// Like [`MeshBuilder::plane`] with explicit texture coordinates at the bottom-left and
    /// top-right corners (bilinear in between).
    pub(crate) fn plane_uv(
        &mut self,
        origin: Vec3,
        right: Vec3,
        up: Vec3,
        bottom_left: Vec2,
        top_right: Vec2,
    ) {
        let normal = right.cross(up).normalize();
        let corners = [
            (origin, bottom_left),
            (origin + right, Vec2::new(top_right.x, bottom_left.y)),
            (origin + right + up, top_right),
            (origin + up, Vec2::new(bottom_left.x, top_right.y)),
        ];
        let [a, b, c, d] = corners.map(|(p, uv)| self.vertex(p, normal, uv.to_array()));
        self.quad(a, b, c, d);
    }

    /// An axis-aligned box with outward faces and planar world-unit texture coordinates
    /// (see [`MeshBuilder::plane`]).
    pub(crate) fn cuboid(&mut self, min: Vec3, max: Vec3, texel_world: f32) {
        let s = max - min;
        // Each face: bottom-left corner seen from outside, right and up edges.
        let faces = [
            (Vec3::new(min.x, min.y, max.z), Vec3::X * s.x, Vec3::Y * s.y),
            (
                Vec3::new(max.x, min.y, min.z),
                Vec3::NEG_X * s.x,
                Vec3::Y * s.y,
            ),
            (
                Vec3::new(max.x, min.y, max.z),
                Vec3::NEG_Z * s.z,
                Vec3::Y * s.y,
            ),
            (Vec3::new(min.x, min.y, min.z), Vec3::Z * s.z, Vec3::Y * s.y),
            (
                Vec3::new(min.x, max.y, max.z),
                Vec3::X * s.x,
                Vec3::NEG_Z * s.z,
            ),
            (Vec3::new(min.x, min.y, min.z), Vec3::X * s.x, Vec3::Z * s.z),
        ];
        for (origin, right, up) in faces {
            self.plane(origin, right, up, texel_world);
        }
    }

    /// A tube of `sides` sides swept along `path` (at least two points), with `radius(i)` at
    /// point `i` (a zero radius closes the tube to a point). Texture u runs around the tube,
    /// v along it in units of `v_scale` per world unit. `closed` joins the last point to the
    /// first (the path must not repeat its first point).
    pub(crate) fn tube(
        &mut self,
        path: &[Vec3],
        sides: u32,
        closed: bool,
        v_scale: f32,
        radius: impl Fn(usize) -> f32,
    ) {
        let n = path.len();
        if n < 2 {
            return;
        }
        let tangent_at = |i: usize| -> Vec3 {
            let (prev, next) = if closed {
                (path[(i + n - 1) % n], path[(i + 1) % n])
            } else {
                (path[i.saturating_sub(1)], path[(i + 1).min(n - 1)])
            };
            (next - prev).normalize_or(Vec3::Y)
        };
        let base = self.next_index();
        let mut normal = tangent_at(0).any_orthonormal_vector();
        let mut along = 0.0;
        let rings = if closed { n + 1 } else { n };
        let step = std::f32::consts::TAU / sides as f32;
        for ring in 0..rings {
            let i = ring % n;
            let tangent = tangent_at(i);
            // Parallel transport: keep the previous normal, minus its component along the
            // new tangent.
            normal = (normal - tangent * normal.dot(tangent)).normalize_or(normal);
            let binormal = tangent.cross(normal);
            if ring > 0 {
                along += path[i].distance(path[(ring - 1) % n]);
            }
            let r = radius(i);
            for k in 0..=sides {
                let (sin, cos) = (k as f32 * step).sin_cos();
                let dir = normal * cos + binormal * sin;
                self.vertex(
                    path[i] + dir * r,
                    dir,
                    [k as f32 / sides as f32, along * v_scale],
                );
            }
        }
        self.grid(base, sides, rings as u32 - 1);
    }

    /// A surface of revolution about the vertical axis through `center`: the `profile`
    /// (radius, height above `center`) runs bottom to top; joints whose segments turn by more
    /// than 40 degrees become hard edges. Texture u runs around (one repeat per `u_repeats`),
    /// v along the profile in units of `v_scale` per world unit.
    pub(crate) fn lathe(
        &mut self,
        center: Vec3,
        profile: &[ProfilePoint],
        sides: u32,
        u_repeats: f32,
        v_scale: f32,
    ) {
        if profile.len() < 2 {
            return;
        }
        // Outward normal of each profile segment in the (radius, height) plane.
        let segment_normal = |s: usize| -> Vec2 {
            let d = profile[s + 1] - profile[s];
            Vec2::new(d.y, -d.x).normalize_or(Vec2::X)
        };
        let segments = profile.len() - 1;
        let mut along = 0.0;
        for s in 0..segments {
            let here = segment_normal(s);
            // Each segment gets its own two rings; a smooth joint shares the averaged normal.
            let joint = |other: Option<usize>| -> Vec2 {
                match other {
                    Some(o) if segment_normal(o).dot(here) > 40f32.to_radians().cos() => {
                        (segment_normal(o) + here).normalize_or(here)
                    }
                    _ => here,
                }
            };
            let ends = [
                (profile[s], joint(s.checked_sub(1))),
                (profile[s + 1], joint((s + 1 < segments).then_some(s + 1))),
            ];
            let length = profile[s].distance(profile[s + 1]);
            let base = self.next_index();
            for (e, (point, n2)) in ends.into_iter().enumerate() {
                let v = (along + length * e as f32) * v_scale;
                for k in 0..=sides {
                    let angle = k as f32 / sides as f32 * std::f32::consts::TAU;
                    let (sin, cos) = angle.sin_cos();
                    let radial = Vec3::new(sin, 0.0, cos);
                    self.vertex(
                        center + radial * point.x + Vec3::Y * point.y,
                        (radial * n2.x + Vec3::Y * n2.y).normalize_or(Vec3::Y),
                        [k as f32 / sides as f32 * u_repeats, -v],
                    );
                }
            }
            along += length;
            self.grid(base, sides, 1);
        }
    }

    /// Appends `copies - 1` copies of everything from vertex `first_vertex` and index
    /// `first_index` on, each rotated a further `360 / copies` degrees about the vertical axis
    /// through `center`.
    pub(crate) fn rotated_copies(
        &mut self,
        first_vertex: usize,
        first_index: usize,
        center: Vec3,
        copies: u32,
    ) {
        let vertex_end = self.vertices.len();
        let index_end = self.indices.len();
        for copy in 1..copies {
            let rotation =
                Mat3::from_rotation_y(copy as f32 * std::f32::consts::TAU / copies as f32);
            let offset = self.vertices.len() as u32 - first_vertex as u32;
            for v in first_vertex..vertex_end {
                let vertex = self.vertices[v];
                let p = rotation * (Vec3::from(vertex.position) - center) + center;
                let n = rotation * Vec3::from(vertex.normal);
                self.vertices.push(Vertex::new(p, n, vertex.uv));
            }
            for i in first_index..index_end {
                let index = self.indices[i];
                self.indices.push(index + offset);
            }
        }
    }

    /// Current vertex and index counts, to mark where a part starts (for `rotated_copies`).
    pub(crate) fn mark(&self) -> (usize, usize) {
        (self.vertices.len(), self.indices.len())
    }

    /// The finished mesh.
    pub(crate) fn build(self, name: &str, material: usize, spin: Option<Spin>) -> Mesh {
        Mesh {
            name: name.to_owned(),
            vertices: self.vertices,
            indices: self.indices,
            material,
            spin,
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Checks the invariants every generated mesh must keep: finite attributes, unit
    /// normals, indices in range, whole triangles.
    pub(crate) fn assert_mesh_valid(mesh: &Mesh) {
        assert_eq!(mesh.indices.len() % 3, 0, "{}: partial triangle", mesh.name);
        let count = mesh.vertices.len() as u32;
        assert!(
            mesh.indices.iter().all(|&i| i < count),
            "{}: index out of range",
            mesh.name
        );
        for v in &mesh.vertices {
            let finite = v.position.iter().chain(&v.normal).chain(&v.uv);
            assert!(
                finite.into_iter().all(|x| x.is_finite()),
                "{}: {v:?}",
                mesh.name
            );
            let length = Vec3::from(v.normal).length();
            assert!((length - 1.0).abs() < 1e-3, "{}: normal {v:?}", mesh.name);
        }
    }

    /// Sum over triangles of (face normal . vertex normals): positive when windings agree
    /// with the normals (counter-clockwise front faces).
    fn winding_agreement(mesh: &Mesh) -> f32 {
        mesh.indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.vertices[t[k] as usize]);
                let face = (Vec3::from(b.position) - Vec3::from(a.position))
                    .cross(Vec3::from(c.position) - Vec3::from(a.position));
                face.dot(Vec3::from(a.normal) + Vec3::from(b.normal) + Vec3::from(c.normal))
            })
            .sum()
    }

    #[test]
    fn tube_faces_outwards_with_radial_normals() {
        let mut b = MeshBuilder::default();
        let path: Vec<Vec3> = (0..10)
            .map(|i| Vec3::new((i as f32 * 0.3).sin(), i as f32 * 0.2, 0.0))
            .collect();
        b.tube(&path, 4, false, 1.0, |_| 0.05);
        let mesh = b.build("tube", 0, None);
        assert_mesh_valid(&mesh);
        assert_eq!(mesh.triangle_count(), 9 * 4 * 2);
        assert!(winding_agreement(&mesh) > 0.0);
        for (i, v) in mesh.vertices.iter().enumerate() {
            let centre = path[i / 5];
            let radial = (Vec3::from(v.position) - centre) / 0.05;
            assert!((radial - Vec3::from(v.normal)).length() < 1e-3);
        }
    }

    #[test]
    fn closed_tube_has_no_twist_at_the_seam() {
        let mut b = MeshBuilder::default();
        let path: Vec<Vec3> = (0..32)
            .map(|i| {
                let a = i as f32 / 32.0 * std::f32::consts::TAU;
                Vec3::new(a.cos(), 0.0, a.sin())
            })
            .collect();
        b.tube(&path, 6, true, 1.0, |_| 0.1);
        let mesh = b.build("ring", 0, None);
        assert_mesh_valid(&mesh);
        let first = &mesh.vertices[..7];
        let last = &mesh.vertices[mesh.vertices.len() - 7..];
        for (a, b) in first.iter().zip(last) {
            assert!((Vec3::from(a.position) - Vec3::from(b.position)).length() < 1e-4);
        }
    }

    #[test]
    fn lathe_and_cuboid_face_outwards() {
        let mut b = MeshBuilder::default();
        let profile = [
            Vec2::new(0.5, 0.0),
            Vec2::new(0.5, 1.0),
            Vec2::new(0.3, 1.2),
            Vec2::new(0.0, 1.2),
        ];
        b.lathe(Vec3::ZERO, &profile, 16, 1.0, 1.0);
        let lathe = b.build("lathe", 0, None);
        assert_mesh_valid(&lathe);
        assert!(winding_agreement(&lathe) > 0.0);
        let mut b = MeshBuilder::default();
        b.cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), 1.0);
        let cuboid = b.build("box", 0, None);
        assert_mesh_valid(&cuboid);
        for t in cuboid.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(cuboid.vertices[t[k] as usize].position));
            let outward = (a + b + c) / 3.0 - Vec3::new(0.5, 1.0, 1.5);
            assert!((b - a).cross(c - a).dot(outward) > 0.0);
        }
    }

    #[test]
    fn rotated_copies_repeat_the_part() {
        let mut b = MeshBuilder::default();
        b.plane(Vec3::new(1.0, 0.0, 0.0), Vec3::Z, Vec3::Y, 1.0);
        b.rotated_copies(0, 0, Vec3::ZERO, 4);
        let mesh = b.build("copies", 0, None);
        assert_mesh_valid(&mesh);
        assert_eq!(mesh.triangle_count(), 8);
        let p = Vec3::from(mesh.vertices[4].position);
        assert!((p - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5, "{p}");
    }
}
