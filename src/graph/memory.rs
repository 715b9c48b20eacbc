//! GPU memory accounting: every texture and buffer a technique owns or reads, with format,
//! size and bytes. Scene inputs shared by several techniques are listed with each of them but
//! counted once in the total, as the frame graph allocates them once. The report covers
//! everything the graph holds: the techniques that are on (running this frame or keeping an
//! earlier image), the scene inputs they read (the graph pools no others), and, apart, what
//! techniques switched off still own, so its total is what is allocated.

use crate::scene::renderer::SceneTargets;

use super::Slot;

/// One GPU resource.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct MemoryItem {
    /// What it is (`msaa4 color`, `taa history`...).
    pub label: String,
    /// Texture format, or `buffer`.
    pub format: String,
    /// Width in texels (buffer: bytes).
    pub width: u32,
    /// Height in texels (buffer: 1).
    pub height: u32,
    /// Samples per texel.
    pub samples: u32,
    /// Mip levels.
    pub mips: u32,
    /// Bytes.
    pub bytes: u64,
}

impl MemoryItem {
    /// Describes a texture.
    pub fn texture(label: impl Into<String>, texture: &wgpu::Texture) -> Self {
        Self {
            label: label.into(),
            format: format!("{:?}", texture.format()),
            width: texture.width(),
            height: texture.height(),
            samples: texture.sample_count(),
            mips: texture.mip_level_count(),
            bytes: crate::gpu::texture_bytes(texture),
        }
    }

    /// Describes a buffer.
    pub fn buffer(label: impl Into<String>, buffer: &wgpu::Buffer) -> Self {
        Self {
            label: label.into(),
            format: "buffer".to_owned(),
            width: u32::try_from(buffer.size()).unwrap_or(u32::MAX),
            height: 1,
            samples: 1,
            mips: 1,
            bytes: buffer.size(),
        }
    }

    /// The textures of a scene input labelled `label` (its size included when it is rendered
    /// at a render scale).
    fn of_targets(label: &str, targets: &SceneTargets) -> Vec<Self> {
        targets
            .textures()
            .into_iter()
            .map(|(name, t)| Self::texture(format!("{label} {name}"), t))
            .collect()
    }
}

/// Memory of one technique.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TechniqueMemory {
    /// Technique id.
    pub technique: String,
    /// The scene input it reads (label), if any.
    pub input: Option<String>,
    /// Techniques sharing that input (including this one).
    pub input_shared_with: Vec<String>,
    /// The input's targets.
    pub input_items: Vec<MemoryItem>,
    /// Resources the technique owns.
    pub private_items: Vec<MemoryItem>,
    /// Its output texture.
    pub output: Option<MemoryItem>,
}

impl TechniqueMemory {
    /// Bytes of the input targets.
    pub fn input_bytes(&self) -> u64 {
        self.input_items.iter().map(|i| i.bytes).sum()
    }

    /// Bytes the technique owns, its output included.
    pub fn own_bytes(&self) -> u64 {
        self.private_items.iter().map(|i| i.bytes).sum::<u64>()
            + self.output.as_ref().map_or(0, |o| o.bytes)
    }

    /// Everything this technique needs to run alone: input, private resources and output.
    pub fn standalone_bytes(&self) -> u64 {
        self.input_bytes() + self.own_bytes()
    }
}

/// Memory of a whole frame graph.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MemoryReport {
    /// Per technique.
    pub techniques: Vec<TechniqueMemory>,
    /// Techniques switched off that still own resources (their pipelines' targets and last
    /// output, kept for a quick switch back); they read no scene input.
    pub idle: Vec<TechniqueMemory>,
    /// The uploaded scene (geometry, textures with mips).
    pub scene_bytes: u64,
    /// Everything, shared inputs counted once, scene and idle techniques included.
    pub total_bytes: u64,
}

impl MemoryReport {
    pub(super) fn build(
        slots: &[Slot],
        inputs: &[(String, Vec<&'static str>, &SceneTargets)],
        scene_bytes: u64,
    ) -> Self {
        let techniques: Vec<TechniqueMemory> = slots
            .iter()
            .filter(|s| s.held() && s.output.is_some())
            .map(|slot| {
                let id = slot.technique.id();
                let input = inputs.iter().find(|(_, users, _)| users.contains(&id));
                TechniqueMemory {
                    technique: id.to_owned(),
                    input: input.map(|(label, _, _)| label.clone()),
                    input_shared_with: input.map_or_else(Vec::new, |(_, users, _)| {
                        users.iter().map(|u| (*u).to_owned()).collect()
                    }),
                    input_items: input
                        .map_or_else(Vec::new, |(label, _, t)| MemoryItem::of_targets(label, t)),
                    private_items: (slot.technique.memory().into_iter())
                        .chain(
                            slot.hdr_output
                                .as_ref()
                                .map(|o| MemoryItem::texture(format!("{id} hdr output"), o)),
                        )
                        .collect(),
                    output: slot
                        .output
                        .as_ref()
                        .map(|o| MemoryItem::texture(format!("{id} output"), o)),
                }
            })
            .collect();
        let inputs_total: u64 = inputs
            .iter()
            .flat_map(|(label, _, t)| MemoryItem::of_targets(label, t))
            .map(|i| i.bytes)
            .sum();
        let idle: Vec<TechniqueMemory> = slots
            .iter()
            .filter(|s| !s.held())
            .map(|slot| {
                let id = slot.technique.id();
                TechniqueMemory {
                    technique: id.to_owned(),
                    input: None,
                    input_shared_with: Vec::new(),
                    input_items: Vec::new(),
                    private_items: slot.technique.memory(),
                    output: slot
                        .output
                        .as_ref()
                        .map(|o| MemoryItem::texture(format!("{id} output"), o)),
                }
            })
            .filter(|t| t.own_bytes() > 0)
            .collect();
        let own_total: u64 = techniques
            .iter()
            .chain(&idle)
            .map(TechniqueMemory::own_bytes)
            .sum();
        Self {
            total_bytes: inputs_total + own_total + scene_bytes,
            techniques,
            idle,
            scene_bytes,
        }
    }

    /// Bytes that switched-off techniques still own.
    pub fn idle_bytes(&self) -> u64 {
        self.idle.iter().map(TechniqueMemory::own_bytes).sum()
    }

    /// A plain-text table (what `aa-lab render --memory` prints).
    pub fn table(&self) -> String {
        let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
        let mut out = String::new();
        for t in &self.techniques {
            out += &format!(
                "{}: {:.2} MiB to run alone ({:.2} MiB own)\n",
                t.technique,
                mib(t.standalone_bytes()),
                mib(t.own_bytes())
            );
            if let Some(input) = &t.input {
                let shared = if t.input_shared_with.len() > 1 {
                    format!(", shared with {}", t.input_shared_with.join(", "))
                } else {
                    String::new()
                };
                out += &format!("  input {input}{shared}\n");
            }
            for item in t
                .input_items
                .iter()
                .chain(&t.private_items)
                .chain(t.output.iter())
            {
                out += &format!(
                    "    {:<28} {:<16} {:>5}x{:<5} {:>2} spp {:>2} mips {:>10} B ({:.2} MiB)\n",
                    item.label,
                    item.format,
                    item.width,
                    item.height,
                    item.samples,
                    item.mips,
                    item.bytes,
                    mib(item.bytes)
                );
            }
        }
        if !self.idle.is_empty() {
            let ids: Vec<&str> = self.idle.iter().map(|t| t.technique.as_str()).collect();
            out += &format!(
                "switched off, still allocated: {:.2} MiB ({})\n",
                mib(self.idle_bytes()),
                ids.join(", ")
            );
        }
        out += &format!(
            "scene geometry and textures: {:.2} MiB\ntotal (shared inputs once): {:.2} MiB\n",
            mib(self.scene_bytes),
            mib(self.total_bytes)
        );
        out
    }
}
