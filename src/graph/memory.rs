//! GPU memory accounting: every texture and buffer a technique owns or reads, with format,
//! size and bytes. Scene inputs shared by several techniques are listed with each of them but
//! counted once in the total, as the frame graph allocates them once.

use super::SceneInput;
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

    fn of_targets(input: &SceneInput, targets: &SceneTargets) -> Vec<Self> {
        let label = input.label();
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
    /// The uploaded scene (geometry, textures with mips).
    pub scene_bytes: u64,
    /// Everything, shared inputs counted once, scene included.
    pub total_bytes: u64,
}

impl MemoryReport {
    pub(super) fn build(
        slots: &[Slot],
        inputs: &[(SceneInput, Vec<&'static str>, &SceneTargets)],
        scene_bytes: u64,
    ) -> Self {
        let techniques: Vec<TechniqueMemory> = slots
            .iter()
            .filter(|s| s.enabled && s.output.is_some())
            .map(|slot| {
                let id = slot.technique.id();
                let input = inputs.iter().find(|(_, users, _)| users.contains(&id));
                TechniqueMemory {
                    technique: id.to_owned(),
                    input: input.map(|(i, _, _)| i.label()),
                    input_shared_with: input.map_or_else(Vec::new, |(_, users, _)| {
                        users.iter().map(|u| (*u).to_owned()).collect()
                    }),
                    input_items: input
                        .map_or_else(Vec::new, |(i, _, t)| MemoryItem::of_targets(i, t)),
                    private_items: slot.technique.memory(),
                    output: slot
                        .output
                        .as_ref()
                        .map(|o| MemoryItem::texture(format!("{id} output"), o)),
                }
            })
            .collect();
        let inputs_total: u64 = inputs
            .iter()
            .flat_map(|(i, _, t)| MemoryItem::of_targets(i, t))
            .map(|i| i.bytes)
            .sum();
        let own_total: u64 = techniques.iter().map(TechniqueMemory::own_bytes).sum();
        Self {
            total_bytes: inputs_total + own_total + scene_bytes,
            techniques,
            scene_bytes,
        }
    }

    /// This report brought up to date by `newer`, the report of a frame in which only the
    /// techniques `ran` rendered (the others kept their images). Such a frame knows only the
    /// scene inputs it rendered, so the techniques that did not run keep their entries from
    /// this report (their inputs still exist); those that ran, and any this report lacks, take
    /// `newer`'s; techniques `newer` does not list (switched off) are dropped. Which
    /// techniques share each input and the total (each input once) are worked out anew.
    pub fn updated_by(&self, newer: MemoryReport, ran: &[&str]) -> MemoryReport {
        let mut techniques: Vec<TechniqueMemory> = newer
            .techniques
            .into_iter()
            .map(|entry| {
                let kept = self
                    .techniques
                    .iter()
                    .find(|t| t.technique == entry.technique);
                match kept {
                    Some(old) if !ran.contains(&entry.technique.as_str()) => old.clone(),
                    _ => entry,
                }
            })
            .collect();
        let readers: Vec<(Option<String>, String)> = techniques
            .iter()
            .map(|t| (t.input.clone(), t.technique.clone()))
            .collect();
        for t in &mut techniques {
            t.input_shared_with = readers
                .iter()
                .filter(|(input, _)| input.is_some() && *input == t.input)
                .map(|(_, id)| id.clone())
                .collect();
        }
        let mut inputs_total = 0;
        for (n, t) in techniques.iter().enumerate() {
            let first_reader = techniques[..n]
                .iter()
                .all(|earlier| earlier.input.is_none() || earlier.input != t.input);
            if first_reader {
                inputs_total += t.input_bytes();
            }
        }
        let own_total: u64 = techniques.iter().map(TechniqueMemory::own_bytes).sum();
        MemoryReport {
            total_bytes: inputs_total + own_total + newer.scene_bytes,
            techniques,
            scene_bytes: newer.scene_bytes,
        }
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
        out += &format!(
            "scene geometry and textures: {:.2} MiB\ntotal (shared inputs once): {:.2} MiB\n",
            mib(self.scene_bytes),
            mib(self.total_bytes)
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(label: &str, bytes: u64) -> MemoryItem {
        MemoryItem {
            label: label.to_owned(),
            format: "Rgba8Unorm".to_owned(),
            width: 1,
            height: 1,
            samples: 1,
            mips: 1,
            bytes,
        }
    }

    fn entry(id: &str, input: Option<(&str, u64)>, own: u64) -> TechniqueMemory {
        TechniqueMemory {
            technique: id.to_owned(),
            input: input.map(|(label, _)| label.to_owned()),
            input_shared_with: Vec::new(),
            input_items: input.map_or_else(Vec::new, |(label, bytes)| vec![item(label, bytes)]),
            private_items: Vec::new(),
            output: Some(item("output", own)),
        }
    }

    /// A report over a 1000-byte scene (its total is not read: the merge works it out anew).
    fn report(techniques: Vec<TechniqueMemory>) -> MemoryReport {
        MemoryReport {
            techniques,
            scene_bytes: 1000,
            total_bytes: 0,
        }
    }

    #[test]
    fn a_partial_frame_updates_what_ran_and_keeps_the_others_inputs() {
        let scene = Some(("scene 1x", 100));
        let complete = report(vec![
            entry("none", scene, 10),
            entry("fxaa", scene, 20),
            entry("msaa4", Some(("scene msaa4", 400)), 30),
        ]);
        // TAA switched on and MSAA 4x off on a still view: only TAA renders, and the frame
        // knows no input of the others.
        let partial = report(vec![
            entry("none", None, 10),
            entry("fxaa", None, 20),
            entry("taa", Some(("scene 1x jittered", 150)), 50),
        ]);
        let merged = complete.updated_by(partial, &["taa"]);
        let ids: Vec<&str> = merged
            .techniques
            .iter()
            .map(|t| t.technique.as_str())
            .collect();
        assert_eq!(ids, ["none", "fxaa", "taa"]);
        let none = &merged.techniques[0];
        assert_eq!(none.input.as_deref(), Some("scene 1x"));
        assert_eq!(none.input_shared_with, ["none", "fxaa"]);
        assert_eq!(none.standalone_bytes(), 110);
        assert_eq!(merged.techniques[2].input_shared_with, ["taa"]);
        assert_eq!(merged.total_bytes, 1000 + 100 + 150 + 10 + 20 + 50);
    }
}
