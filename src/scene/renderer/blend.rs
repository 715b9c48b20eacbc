//! The draw order of alpha-blended surfaces ([`AlphaMode::Blend`]).
//!
//! Blending is not commutative, so blended surfaces are drawn after every opaque and masked
//! one, farthest first ("painter's order" over the depth-tested opaque image). The granularity
//! is the mesh: every frame each blended mesh's centre (the middle of its object-space bounds,
//! moved by its [`Spin`] to the frame being drawn) is measured from the eye, and the meshes are
//! drawn by decreasing distance; the triangles inside one mesh keep their index order. What
//! that cannot get right, as in every engine that sorts by object: two blended meshes that
//! intersect or interleave (each partly in front of the other), a large mesh whose centre is
//! farther than a small one it covers although its near part is in front, and the triangles
//! of one mesh that overlap themselves on screen (build such a mesh single-sided and convex,
//! or split it). Equal distances keep the scene's mesh order.
//!
//! Blended surfaces test depth but do not write it, and leave the motion vectors alone: a
//! pixel's motion stays that of the opaque surface behind the glass, which is what TAA must
//! reproject the background with (the blended layer has no single motion; FSR 2's documents
//! make the same choice and let a reactive mask say where the pixel is not that surface's).

use glam::Vec3;

use super::Draw;
use crate::scene::{AlphaMode, Scene, Spin};

/// One blended mesh: its draw, its object-space centre and its motion.
struct BlendedMesh {
    draw: usize,
    centre: Vec3,
    spin: Option<Spin>,
}

/// The scene's blended meshes, sortable per frame.
pub(super) struct BlendOrder {
    meshes: Vec<BlendedMesh>,
}

impl BlendOrder {
    /// The draws of `draws` whose material blends.
    pub(super) fn new(scene: &Scene, draws: &[Draw]) -> Self {
        let meshes = draws
            .iter()
            .enumerate()
            .filter(|(_, d)| {
                scene
                    .materials
                    .get(d.material)
                    .is_some_and(|m| m.alpha_mode == AlphaMode::Blend)
            })
            .map(|(draw, d)| {
                let mesh = &scene.meshes[d.object];
                let mut points = mesh.vertices.iter().map(|v| Vec3::from(v.position));
                let first = points.next().unwrap_or(Vec3::ZERO);
                let (low, high) = points.fold((first, first), |(l, h), p| (l.min(p), h.max(p)));
                BlendedMesh {
                    draw,
                    centre: 0.5 * (low + high),
                    spin: mesh.spin,
                }
            })
            .collect();
        Self { meshes }
    }

    /// Whether draw `draw` blends.
    pub(super) fn contains(&self, draw: usize) -> bool {
        self.meshes.iter().any(|m| m.draw == draw)
    }

    /// The blended draws for an eye at `eye` and the (possibly fractional) frame `frame`,
    /// farthest first.
    pub(super) fn back_to_front(&self, eye: Vec3, frame: f32) -> Vec<usize> {
        let mut by_distance: Vec<(f32, usize)> = self
            .meshes
            .iter()
            .map(|m| {
                let centre = m.spin.map_or(m.centre, |s| {
                    s.transform_at(frame).transform_point3(m.centre)
                });
                (centre.distance_squared(eye), m.draw)
            })
            .collect();
        // Stable: equal distances keep the scene's order.
        by_distance.sort_by(|a, b| b.0.total_cmp(&a.0));
        by_distance.into_iter().map(|(_, draw)| draw).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Mesh, Vertex};

    fn quad_at(z: f32, material: usize) -> Mesh {
        let corner = |x: f32, y: f32| Vertex::new(Vec3::new(x, y, z), Vec3::Z, [0.0, 0.0]);
        Mesh {
            name: format!("quad {z}"),
            vertices: vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0)],
            indices: vec![0, 1, 2],
            material,
            spin: None,
        }
    }

    #[test]
    fn blended_meshes_come_farthest_first_and_opaque_ones_not_at_all() {
        let mut scene = Scene::empty("order");
        scene.materials = vec![
            Material::default(),
            Material {
                alpha_mode: AlphaMode::Blend,
                ..Material::default()
            },
        ];
        scene.meshes = vec![
            quad_at(1.0, 1),
            quad_at(-3.0, 1),
            quad_at(-5.0, 0),
            quad_at(0.0, 1),
        ];
        let draws: Vec<Draw> = (0..4)
            .map(|object| Draw {
                first_index: 0,
                index_count: 3,
                base_vertex: 0,
                material: scene.meshes[object].material,
                object,
            })
            .collect();
        let order = BlendOrder::new(&scene, &draws);
        assert!(!order.contains(2) && order.contains(0));
        // From +Z the quad at -3 is farthest; from -Z the one at 1.
        assert_eq!(
            order.back_to_front(Vec3::new(0.0, 0.0, 10.0), 0.0),
            [1, 3, 0]
        );
        assert_eq!(
            order.back_to_front(Vec3::new(0.0, 0.0, -10.0), 0.0),
            [0, 3, 1]
        );
    }
}
