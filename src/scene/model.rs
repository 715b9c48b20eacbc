//! The CPU-side scene description every scene source produces and the renderer consumes.
//!
//! A [`Scene`] is plain data: triangle meshes with one material each, materials that point
//! into a texture list, a camera rig that fixes the deterministic camera path, one directional
//! light and a background colour. Procedural scenes (`scene::procedural`) and the OBJ/MTL loader
//! (`scene::obj`) both build this type; nothing here touches the GPU.

use glam::{Mat4, Quat, Vec3};

/// One vertex as the scene shader reads it (32 bytes, tightly packed).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinate; (0, 0) is the top-left of the image.
    pub uv: [f32; 2],
}

impl Vertex {
    /// A vertex from its three attributes.
    pub fn new(position: Vec3, normal: Vec3, uv: [f32; 2]) -> Self {
        Self {
            position: position.to_array(),
            normal: normal.to_array(),
            uv,
        }
    }
}

/// An RGBA8 image whose colour channels hold sRGB-encoded values and whose alpha is linear.
#[derive(Clone, Debug)]
pub struct TextureImage {
    /// Where the image came from (file path or generator name), for labels and messages.
    pub label: String,
    /// The pixels.
    pub image: image::RgbaImage,
}

/// How a material treats its alpha channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored; the surface is solid.
    Opaque,
    /// Alpha-tested: fragments with alpha below `cutoff` are discarded (or, with
    /// alpha-to-coverage enabled, alpha becomes the fraction of covered samples).
    Mask {
        /// Alpha threshold in 0..1.
        cutoff: f32,
    },
}

/// A Blinn-Phong material.
#[derive(Clone, Debug)]
pub struct Material {
    /// Name from the MTL file or generator.
    pub name: String,
    /// Diffuse colour in linear RGB, multiplied with the texture when there is one.
    pub base_color: Vec3,
    /// Index into [`Scene::textures`] of the base-colour texture (alpha in its alpha channel).
    pub base_color_texture: Option<usize>,
    /// Specular colour in linear RGB.
    pub specular: Vec3,
    /// Blinn-Phong exponent (MTL `Ns`).
    pub shininess: f32,
    /// Alpha handling.
    pub alpha_mode: AlphaMode,
    /// Unlit materials output their base colour unshaded (test charts need exact values).
    pub unlit: bool,
    /// Whether back faces are drawn (foliage cards, fences and open meshes need it).
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".to_owned(),
            base_color: Vec3::splat(0.8),
            base_color_texture: None,
            specular: Vec3::splat(0.0),
            shininess: 32.0,
            alpha_mode: AlphaMode::Opaque,
            unlit: false,
            double_sided: true,
        }
    }
}

/// A rigid rotation applied to a mesh over time, so that scenes can have object motion
/// (motion vectors must carry it, not only camera motion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spin {
    /// Point the rotation is about.
    pub pivot: Vec3,
    /// Unit rotation axis.
    pub axis: Vec3,
    /// Rotation per frame, in radians.
    pub radians_per_frame: f32,
}

impl Spin {
    /// The object-to-world matrix at a (possibly fractional) frame number.
    pub fn transform_at(&self, frame: f32) -> Mat4 {
        Mat4::from_translation(self.pivot)
            * Mat4::from_quat(Quat::from_axis_angle(
                self.axis,
                self.radians_per_frame * frame,
            ))
            * Mat4::from_translation(-self.pivot)
    }
}

/// A triangle list with one material.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Name from the OBJ object/group or the generator.
    pub name: String,
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Triangle list indices into `vertices`, three per triangle, counter-clockwise front faces.
    pub indices: Vec<u32>,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Optional rigid animation; `None` means the mesh is static.
    pub spin: Option<Spin>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Object-to-world transform at a frame.
    pub fn transform_at(&self, frame: f32) -> Mat4 {
        self.spin
            .map_or(Mat4::IDENTITY, |spin| spin.transform_at(frame))
    }
}

/// The deterministic camera path of a scene: an orbit about the vertical axis through `target`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraRig {
    /// Point the camera looks at and orbits around.
    pub target: Vec3,
    /// Distance from the target.
    pub distance: f32,
    /// Azimuth at frame 0, in degrees (0 looks down -Z).
    pub yaw_degrees: f32,
    /// Elevation in degrees (positive looks down on the target).
    pub pitch_degrees: f32,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    /// Near clip distance.
    pub near: f32,
    /// Far clip distance.
    pub far: f32,
    /// Auto-rotation speed about the vertical axis, degrees per frame (0 for a still camera).
    pub orbit_degrees_per_frame: f32,
}

impl Default for CameraRig {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            distance: 5.0,
            yaw_degrees: 0.0,
            pitch_degrees: 15.0,
            fov_y_degrees: 45.0,
            near: 0.05,
            far: 100.0,
            orbit_degrees_per_frame: 0.5,
        }
    }
}

/// One directional light with an ambient term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels in (from the light towards the scene).
    pub direction: Vec3,
    /// Light colour times intensity, linear RGB.
    pub color: Vec3,
    /// Ambient light, linear RGB.
    pub ambient: Vec3,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        Self {
            direction: Vec3::new(-0.4, -1.0, -0.3).normalize(),
            color: Vec3::splat(1.0),
            ambient: Vec3::splat(0.15),
        }
    }
}

/// A complete scene, ready to be uploaded.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Scene name (`hairball`, `atrium`, `chart` or the OBJ file stem).
    pub name: String,
    /// Meshes.
    pub meshes: Vec<Mesh>,
    /// Materials referenced by the meshes.
    pub materials: Vec<Material>,
    /// Textures referenced by the materials.
    pub textures: Vec<TextureImage>,
    /// Camera path.
    pub camera: CameraRig,
    /// Light.
    pub light: DirectionalLight,
    /// Background colour, linear RGB.
    pub clear_color: Vec3,
    /// Problems found while building the scene that did not stop it (a missing texture
    /// replaced by a checker, say). Front ends must show these to the user.
    pub warnings: Vec<String>,
}

impl Scene {
    /// Total triangle count over all meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(Mesh::triangle_count).sum()
    }

    /// Total vertex count over all meshes.
    pub fn vertex_count(&self) -> usize {
        self.meshes.iter().map(|m| m.vertices.len()).sum()
    }

    /// Axis-aligned bounds of all vertices at frame 0, or `None` for a scene without vertices.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut points = self
            .meshes
            .iter()
            .flat_map(|m| m.vertices.iter().map(|v| Vec3::from(v.position)));
        let first = points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_is_32_bytes() {
        assert_eq!(std::mem::size_of::<Vertex>(), 32);
    }

    #[test]
    fn spin_rotates_about_pivot() {
        let spin = Spin {
            pivot: Vec3::new(1.0, 0.0, 0.0),
            axis: Vec3::Y,
            radians_per_frame: std::f32::consts::FRAC_PI_2,
        };
        let moved = spin
            .transform_at(1.0)
            .transform_point3(Vec3::new(2.0, 0.0, 0.0));
        assert!(
            (moved - Vec3::new(1.0, 0.0, -1.0)).length() < 1e-5,
            "{moved}"
        );
        let pivot = spin.transform_at(3.0).transform_point3(spin.pivot);
        assert!((pivot - spin.pivot).length() < 1e-6);
    }
}
