//! The CPU-side scene description every scene source produces and the renderer consumes.
//!
//! A [`Scene`] is plain data: triangle meshes with one material each, materials that point
//! into a texture list, a camera rig that fixes the deterministic camera path, one directional
//! light and a background colour. Procedural scenes (`scene::procedural`) and the OBJ/MTL loader
//! (`scene::obj`) both build this type; nothing here touches the GPU.

use glam::{Mat4, Quat, Vec3};

use super::camera::CameraRig;

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
    /// Alpha-blended (glTF `BLEND`): drawn after every opaque and masked surface, farthest
    /// object first, over what is behind it by its alpha, without writing depth or motion
    /// (`scene::renderer` says how and what that order cannot get right).
    Blend,
}

/// How a texture is filtered when magnified or minified.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    /// The nearest texel (or mip level).
    Nearest,
    /// Linear interpolation between texels (or mip levels).
    #[default]
    Linear,
}

/// What texture coordinates outside 0..1 read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// The texture tiles.
    #[default]
    Repeat,
    /// The texture tiles, every other copy mirrored.
    MirroredRepeat,
    /// The edge texels extend outwards.
    ClampToEdge,
}

/// How a material's texture is sampled (glTF samplers; OBJ/MTL and the built-in scenes use
/// the default: trilinear, repeating).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureSampler {
    /// Filter when a texel covers more than a pixel.
    pub mag_filter: Filter,
    /// Filter within a mip level when a texel covers less than a pixel.
    pub min_filter: Filter,
    /// Filter between mip levels; `None` samples the full-size image only.
    pub mipmap_filter: Option<Filter>,
    /// Wrapping of the horizontal coordinate.
    pub wrap_u: Wrap,
    /// Wrapping of the vertical coordinate.
    pub wrap_v: Wrap,
}

impl Default for TextureSampler {
    fn default() -> Self {
        Self {
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mipmap_filter: Some(Filter::Linear),
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
        }
    }
}

/// Linear base colour of a material that names none: a neutral mid grey (sRGB 118), dark
/// enough that lit faces of an untextured model stay distinguishable from white.
pub const DEFAULT_BASE_COLOR: f32 = 0.18;

/// Procedural high-frequency normal detail the scene shader evaluates per fragment, in place
/// of a tangent-space normal map: a surface with it needs neither tangents nor texture
/// coordinates (`shaders/scene.wgsl`, `detail_normal`, says how the normal is perturbed). It
/// bends the normal of the specular term only, like flakes under a clear coat over a smooth
/// base, so that what it adds to the image is specular aliasing alone.
///
/// The pattern lives in world space, so it suits static meshes only (a spinning mesh would
/// slide through it). Below a pixel per period it is the sub-pixel normal variation that makes
/// highlights sparkle and that geometric specular antialiasing widens the lobe for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalDetail {
    /// Pattern periods per world unit (ripples' wave number over 2 pi, flakes per unit).
    pub frequency: f32,
    /// Largest tangential tilt of the smooth ripples (sum of plane waves), as a slope.
    pub ripple: f32,
    /// Tangential tilt of the flakes (one random tilt per cubic cell), as a slope.
    pub flakes: f32,
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
    /// How the base-colour texture is sampled.
    pub sampler: TextureSampler,
    /// Alpha factor multiplied with the texture's alpha (glTF `baseColorFactor[3]`).
    pub opacity: f32,
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
    /// Procedural normal detail; `None` shades with the interpolated normal.
    pub normal_detail: Option<NormalDetail>,
    /// Emitted radiance in linear RGB, added to the shading (above 1 for lights and glowing
    /// edges in HDR scenes; an LDR render clamps the sum to 1).
    pub emissive: Vec3,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".to_owned(),
            base_color: Vec3::splat(DEFAULT_BASE_COLOR),
            base_color_texture: None,
            sampler: TextureSampler::default(),
            opacity: 1.0,
            specular: Vec3::splat(0.0),
            shininess: 32.0,
            alpha_mode: AlphaMode::Opaque,
            unlit: false,
            double_sided: true,
            normal_detail: None,
            emissive: Vec3::ZERO,
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

/// A named camera a scene file defines (a glTF camera node), offered as a view.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneView {
    /// The camera's name in the file (or `camera N`).
    pub name: String,
    /// The camera as a rig whose frame 0 is the file's camera.
    pub camera: CameraRig,
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
    /// Camera path (the default view).
    pub camera: CameraRig,
    /// The model encloses its bounds' centre and `camera` is an inside view
    /// ([`super::interior`]); the viewer opens it with the fly camera.
    pub interior: bool,
    /// Cameras the scene file defines, in file order; the first is `camera` when there is one.
    pub views: Vec<SceneView>,
    /// Light.
    pub light: DirectionalLight,
    /// Background colour, linear RGB.
    pub clear_color: Vec3,
    /// Problems found while building the scene that did not stop it (a missing texture
    /// replaced by a checker, say). Front ends must show these to the user.
    pub warnings: Vec<String>,
    /// Things worth knowing that are not problems (material statements a loader ignores,
    /// say); front ends show these too, and `--strict` does not count them.
    pub notes: Vec<String>,
}

impl Scene {
    /// Whether the scene emits radiance above the display's white (an emissive material
    /// brighter than 1), so that it is shown through a tonemapper by default (`graph::hdr`).
    pub fn is_hdr(&self) -> bool {
        self.materials
            .iter()
            .any(|m| m.emissive.max_element() > 1.0)
    }

    /// A scene with nothing in it (image mode draws no scene), called `name`.
    pub fn empty(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            meshes: Vec::new(),
            materials: Vec::new(),
            textures: Vec::new(),
            camera: CameraRig::default(),
            interior: false,
            light: DirectionalLight::default(),
            clear_color: Vec3::ZERO,
            views: Vec::new(),
            warnings: Vec::new(),
            notes: Vec::new(),
        }
    }

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
