//! Built-in procedural scenes, selectable by name: `hairball` (fine geometry under a strong
//! highlight), `atrium` (an arcaded courtyard in the spirit of Crytek Sponza), `chart` (a
//! flat resolution chart seen head-on, with an analytic layout for exact ground truth),
//! `sparkle` (shiny surfaces with sub-pixel normal detail: specular aliasing), `glass`
//! (alpha-blended panes and moving particles over a fine lattice: transparency) and `neon`
//! (thin emitters far brighter than white on dark surfaces: an HDR scene).
//!
//! Everything, meshes and textures alike, is generated in code from [`SceneOptions::seed`]
//! with the generators' own SplitMix64 (module `rng`), so a scene never changes with a crate
//! version and nothing is downloaded or read from disk. Together the scenes cover the
//! thesis' five zoom categories:
//! - shape preservation: the chart's Siemens star, discs and rings; the atrium's arches,
//!   columns and armillary rings;
//! - diagonals: the chart's slanted edges; the atrium's floor checker and lattices seen in
//!   perspective;
//! - textures: the chart's zone plate; the atrium's bricks, marble tiles, inscription and
//!   noticeboard print;
//! - multiple edges: the chart's grids; the atrium's balusters, chain-link and cables
//!   crossing;
//! - fine geometry: the hairball; the chart's line groups; the atrium's cables.
//!
//! Conventions: right-handed, +Y up, counter-clockwise front faces, texture (0, 0) at the
//! top-left, textures RGBA8 with sRGB-encoded colour and linear alpha, material colours in
//! linear RGB.

mod atrium;
mod chart;
mod geometry;
mod glass;
mod hairball;
mod neon;
mod rng;
mod sparkle;
mod texture;

pub use atrium::atrium;
pub use chart::{
    CHART_PIXELS_PER_UNIT_720P, ChartFeature, ChartLayout, ChartPolygon, ChartRegion, ZonePlate,
    chart, chart_layout,
};
pub use glass::glass;
pub use hairball::hairball;
pub use neon::neon;
pub use sparkle::sparkle;

use crate::scene::Scene;

/// Names [`builtin`] accepts.
pub const BUILTIN_SCENES: &[&str] = &["hairball", "atrium", "chart", "sparkle", "glass", "neon"];

/// Densities outside this range are clamped (with a warning in the scene): below it the
/// hairball has no curves left, above it (~10M triangles) it outgrows GPU buffers.
const DENSITY_RANGE: (f32, f32) = (0.001, 32.0);

/// Options that scale the built-in scenes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneOptions {
    /// Geometric density, 1.0 by default: the hairball's triangle count scales linearly with
    /// it (about 300k at 1, over 2M at 7). The atrium, the chart, sparkle and glass are fixed designs
    /// and ignore it. Values outside 0.001..=32 are clamped and non-finite values replaced by 1,
    /// with a warning in [`Scene::warnings`].
    pub density: f32,
    /// Seed of every random choice; the same seed always builds the same scene.
    pub seed: u64,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self {
            density: 1.0,
            seed: 1,
        }
    }
}

impl SceneOptions {
    /// The density to build with, and a warning when the requested one had to be changed.
    fn checked_density(&self) -> (f32, Vec<String>) {
        let (lo, hi) = DENSITY_RANGE;
        let used = if self.density.is_finite() {
            self.density.clamp(lo, hi)
        } else {
            1.0
        };
        let warnings = if used == self.density {
            Vec::new()
        } else {
            vec![format!(
                "scene density {} is outside {lo}..={hi}; using {used}",
                self.density
            )]
        };
        (used, warnings)
    }
}

/// The built-in scene called `name` (one of [`BUILTIN_SCENES`]), or `None` for an unknown name.
pub fn builtin(name: &str, options: &SceneOptions) -> Option<Scene> {
    match name {
        "hairball" => Some(hairball(options)),
        "atrium" => Some(atrium(options)),
        "chart" => Some(chart(options)),
        "sparkle" => Some(sparkle(options)),
        "glass" => Some(glass(options)),
        "neon" => Some(neon(options)),
        _ => None,
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::scene::procedural::geometry::tests::assert_mesh_valid;

    /// Checks what every scene must satisfy: valid meshes, material and texture references
    /// in range, a usable camera.
    pub(crate) fn assert_scene_valid(scene: &Scene) {
        assert!(!scene.meshes.is_empty());
        for mesh in &scene.meshes {
            assert_mesh_valid(mesh);
            assert!(mesh.material < scene.materials.len(), "{}", mesh.name);
        }
        for material in &scene.materials {
            if let Some(t) = material.base_color_texture {
                assert!(t < scene.textures.len(), "{}", material.name);
            }
            assert!(material.base_color.is_finite() && material.specular.is_finite());
        }
        let camera = &scene.camera;
        assert!(camera.distance > camera.near && camera.near > 0.0);
        assert!(camera.fov_y_degrees > 1.0 && camera.fov_y_degrees < 120.0);
        assert!((scene.light.direction.length() - 1.0).abs() < 1e-4);
    }

    #[test]
    fn every_name_builds_and_unknown_names_do_not() {
        let options = SceneOptions {
            density: 0.02,
            seed: 5,
        };
        for name in BUILTIN_SCENES {
            let scene = builtin(name, &options).expect("built-in name");
            assert_eq!(scene.name, *name);
        }
        assert!(builtin("sponza", &options).is_none());
        assert!(builtin("", &options).is_none());
    }

    #[test]
    fn same_seed_same_scene() {
        // The atrium's determinism is tested in its module (without rebuilding textures).
        let options = SceneOptions {
            density: 0.05,
            seed: 7,
        };
        for name in ["hairball", "chart"] {
            let (a, b) = (builtin(name, &options), builtin(name, &options));
            let (a, b) = (a.expect("built-in"), b.expect("built-in"));
            assert_eq!(a.meshes.len(), b.meshes.len());
            for (x, y) in a.meshes.iter().zip(&b.meshes) {
                assert_eq!(x.vertices, y.vertices, "{name}");
                assert_eq!(x.indices, y.indices, "{name}");
            }
            for (x, y) in a.textures.iter().zip(&b.textures) {
                assert_eq!(x.image, y.image, "{name}");
            }
        }
    }

    #[test]
    fn bad_densities_are_clamped_with_a_warning() {
        for (asked, used) in [
            (f32::NAN, 1.0),
            (-3.0, 0.001),
            (1e9, 32.0),
            (f32::INFINITY, 1.0),
        ] {
            let options = SceneOptions {
                density: asked,
                seed: 1,
            };
            let (density, warnings) = options.checked_density();
            assert_eq!(density, used);
            assert_eq!(warnings.len(), 1, "{warnings:?}");
        }
        assert!(SceneOptions::default().checked_density().1.is_empty());
    }
}
