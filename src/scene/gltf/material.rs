//! glTF materials as the forward renderer draws them: base colour factor and texture (with
//! its sampler), alpha mode and cutoff, double-sidedness, `KHR_materials_unlit` and the
//! emission (`emissiveFactor` with `KHR_materials_emissive_strength`); textures are decoded
//! once per image and a missing one draws the checker with a warning.

use super::*;

impl Loader<'_> {
    /// The scene material of a glTF material (converted on first use) and the texture
    /// coordinate set its base texture reads.
    pub(super) fn material(&mut self, material: &gltf::Material<'_>) -> (usize, u32) {
        let pbr = material.pbr_metallic_roughness();
        let info = pbr.base_color_texture();
        let tex_coord = info.as_ref().map_or(0, gltf::texture::Info::tex_coord);
        if let Some(&slot) = self.material_slots.get(&material.index()) {
            return (slot, tex_coord);
        }
        let Some(index) = material.index() else {
            let slot = self.materials.len();
            self.materials.push(Material::default());
            self.material_slots.insert(None, slot);
            return (slot, tex_coord);
        };
        let name = describe("material", index, material.name());
        let [r, g, b, a] = pbr.base_color_factor().map(|c| c.clamp(0.0, 1.0));
        let mut converted = Material {
            name: material.name().map_or_else(|| name.clone(), str::to_owned),
            base_color: Vec3::new(r, g, b),
            opacity: a,
            double_sided: material.double_sided(),
            unlit: material.unlit(),
            // The renderer's Blinn-Phong term: a dim, broad highlight for every glTF material.
            specular: Vec3::splat(0.04),
            shininess: 32.0,
            emissive: self.emission(material, &name),
            ..Material::default()
        };
        converted.alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: material.alpha_cutoff().unwrap_or(0.5).clamp(0.0, 1.0),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        if let Some(info) = info {
            let texture = info.texture();
            let (slot, failed) = self.texture(&texture.source(), &name);
            converted.base_color_texture = Some(slot);
            converted.sampler = sampler(&texture.sampler());
            if failed {
                // The checker must show at full strength whatever the material's colour.
                converted.base_color = Vec3::ONE;
                converted.alpha_mode = AlphaMode::Opaque;
            }
        }
        let slot = self.materials.len();
        self.materials.push(converted);
        self.material_slots.insert(Some(index), slot);
        (slot, tex_coord)
    }

    /// The radiance `material` emits: its emissive factor times its strength (linear RGB, no
    /// upper bound). The renderer samples no emissive map, and the factor alone would light a
    /// whole surface that its map lights in places, so a material with a map emits nothing
    /// and a warning says so.
    fn emission(&mut self, material: &gltf::Material<'_>, name: &str) -> Vec3 {
        let strength = material.emissive_strength().unwrap_or(1.0);
        let emission = Vec3::from(material.emissive_factor()) * strength;
        if emission == Vec3::ZERO {
            return Vec3::ZERO;
        }
        if material.emissive_texture().is_some() {
            self.warnings.push(format!(
                "{}: {name} emits through an emissive map, which is not drawn: it emits nothing",
                self.path.display()
            ));
            return Vec3::ZERO;
        }
        if emission.is_finite() {
            emission.max(Vec3::ZERO)
        } else {
            Vec3::ZERO
        }
    }

    /// The scene texture of a glTF image (decoded on first use) and whether it is the
    /// checker that stands in for an image that could not be loaded.
    fn texture(&mut self, image: &gltf::Image<'_>, usage: &str) -> (usize, bool) {
        if let Some(&slot) = self.texture_slots.get(&image.index()) {
            return slot;
        }
        let name = describe("image", image.index(), image.name());
        let decoded = match image.source() {
            gltf::image::Source::View { view, .. } => self
                .view_bytes(&view)
                .map(|bytes| (bytes.to_vec(), format!("buffer view {}", view.index())))
                .map_err(|e| e.to_string()),
            gltf::image::Source::Uri { uri, .. } => read_uri(self.base, uri, UriUse::Image),
        }
        .and_then(|(bytes, from)| {
            image::load_from_memory(&bytes)
                .map(|decoded| (decoded.to_rgba8(), from.clone()))
                .map_err(|e| format!("{from}: {e}"))
        });
        let (texture, failed) = match decoded {
            Ok((image, from)) => (
                TextureImage {
                    label: format!("{name} ({from})"),
                    image,
                },
                false,
            ),
            Err(reason) => {
                self.warnings.push(format!(
                    "{}: {name} (used by {usage}) could not be loaded: {reason}; a \
                     magenta/black checker is drawn instead",
                    self.path.display()
                ));
                (
                    TextureImage {
                        label: format!("{name} (missing)"),
                        image: checker_image(),
                    },
                    true,
                )
            }
        };
        let slot = (self.textures.len(), failed);
        self.textures.push(texture);
        self.texture_slots.insert(image.index(), slot);
        slot
    }
}

/// A glTF sampler as a [`TextureSampler`]; unspecified filters are linear.
fn sampler(sampler: &gltf::texture::Sampler<'_>) -> TextureSampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |mode: WrappingMode| match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    };
    let mag_filter = match sampler.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        Some(MagFilter::Linear) | None => Filter::Linear,
    };
    let (min_filter, mipmap_filter) = match sampler.min_filter() {
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, Some(Filter::Linear)),
    };
    TextureSampler {
        mag_filter,
        min_filter,
        mipmap_filter,
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
    }
}
