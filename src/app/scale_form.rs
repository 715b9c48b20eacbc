//! The techniques panel's "Render scale" section: a form that builds a combination of a
//! technique with a render scale, an upscaler and sharpening (`aa::combo`) and adds it to the
//! viewer as a technique of its own, compared at the output size beside the native ones and
//! kept in the settings (like a user technique). The form shows the combination's id, the
//! string the command line takes (`--technique smaa@performance:easu+rcas=0.2`), and the size
//! the technique renders at.
//!
//! The form's choices stay in egui's memory between frames (they are a draft, not a setting);
//! the base technique starts as the first compared one.

use egui::RichText;

use super::context::Context;
use super::style;
use crate::aa::combo::{
    Combo, DEFAULT_STRENGTH, MIN_SCALE, ScalePreset, Sharpen, Sharpening, Upscaler,
};
use crate::graph::params::Named;

/// The form's choices.
#[derive(Clone, Debug)]
struct Draft {
    /// The technique's own id.
    base: String,
    /// Render scale per axis.
    scale: f32,
    upscaler: Upscaler,
    sharpen: Option<Sharpen>,
    strength: f32,
}

impl Draft {
    /// Performance scale with the edge-adaptive upscaler, no sharpening, on `base`.
    fn new(base: &str) -> Self {
        Self {
            base: base.to_owned(),
            scale: ScalePreset::Performance.scale(),
            upscaler: Upscaler::Easu,
            sharpen: None,
            strength: DEFAULT_STRENGTH,
        }
    }

    /// The combination; `own_upscaling` for a base that reconstructs at the output size
    /// itself (it takes no upscaler).
    fn combo(&self, own_upscaling: bool) -> Combo {
        Combo {
            base: self.base.clone(),
            scale: self.scale,
            upscaler: (!own_upscaling).then_some(self.upscaler),
            sharpen: self.sharpen.map(|filter| Sharpening {
                filter,
                strength: self.strength,
            }),
        }
    }
}

/// The preset whose scale is `scale`, if one is.
fn preset_of(scale: f32) -> Option<ScalePreset> {
    ScalePreset::ALL
        .iter()
        .copied()
        .find(|p| (p.scale() - scale).abs() < 1e-4)
}

/// A preset's label: its name and its scale in percent.
fn preset_label(preset: ScalePreset) -> String {
    let name = match preset {
        ScalePreset::Native => "Native",
        ScalePreset::Quality => "Quality",
        ScalePreset::Balanced => "Balanced",
        ScalePreset::Performance => "Performance",
        ScalePreset::UltraPerformance => "Ultra performance",
    };
    format!("{name} ({:.0}%)", preset.scale() * 100.0)
}

/// The section (collapsed until opened).
pub(super) fn ui(ui: &mut egui::Ui, cx: &mut Context) {
    let Some(engine) = &cx.engine else { return };
    // The techniques a combination can start from: those of the registry this adapter runs.
    let bases: Vec<Base> = engine
        .entries()
        .iter()
        .filter(|e| e.available() && !e.removed && !super::engine::is_added(e.id))
        .map(|e| Base {
            id: e.id,
            name: e.name,
            own_upscaling: e.reconstructs_at_output(),
        })
        .collect();
    let Some(first) = bases.first().map(|b| b.id) else {
        return;
    };
    let start = cx
        .compared()
        .into_iter()
        .find(|id| bases.iter().any(|b| b.id == *id))
        .unwrap_or(first);
    let memory = egui::Id::unique("render scale draft");
    let mut draft = ui
        .data(|d| d.get_temp::<Draft>(memory))
        .filter(|d| bases.iter().any(|b| b.id == d.base))
        .unwrap_or_else(|| Draft::new(start));
    let output = cx.render_size;
    let mut add = None;
    egui::CollapsingHeader::new(RichText::new("Render scale").strong())
        .id_salt("render scale")
        .show(ui, |ui| {
            ui.label(
                RichText::new(
                    "Render a technique at a lower resolution, upscale it to the output and \
                     compare it with the native techniques.",
                )
                .small()
                .weak(),
            );
            egui::Grid::new("render scale form")
                .num_columns(2)
                .spacing([6.0, 4.0])
                .show(ui, |ui| {
                    form_rows(ui, &mut draft, &bases);
                });
            let own_upscaling = bases.iter().any(|b| b.id == draft.base && b.own_upscaling);
            let combo = draft.combo(own_upscaling);
            let id = combo.id();
            if output.0 > 0 {
                let (w, h) = combo.render_size(output);
                ui.label(
                    RichText::new(format!("renders {w}×{h} for {}×{}", output.0, output.1)).small(),
                );
            }
            ui.horizontal(|ui| {
                ui.label(RichText::new(&id).monospace().small())
                    .on_hover_text("The same id works on the command line: --technique ID");
            });
            let listed = engine.entry(&id).is_some_and(|e| !e.removed);
            // Keyed: the form's rows above it change with the draft.
            let add_button = egui::Id::unique("render scale form: add");
            let button = style::keyed(ui, add_button, |ui| {
                ui.add_enabled(
                    !combo.is_plain() && !listed,
                    egui::Button::new("Add and compare"),
                )
            })
            .on_disabled_hover_text(if listed {
                "Already in the list."
            } else {
                "At native scale without sharpening this is the technique itself."
            });
            if button.clicked() {
                add = Some(id);
            }
        });
    ui.data_mut(|d| d.insert_temp(memory, draft));
    if let Some(id) = add {
        cx.add_combination(&id);
    }
}

/// A technique a combination can start from.
struct Base {
    id: &'static str,
    name: &'static str,
    /// It reconstructs at the output size itself (a temporal upscaler): no upscaler.
    own_upscaling: bool,
}

/// The form's rows: technique, scale, upscaler, sharpening.
fn form_rows(ui: &mut egui::Ui, draft: &mut Draft, bases: &[Base]) {
    ui.label("Technique");
    let base = bases.iter().find(|b| b.id == draft.base);
    egui::ComboBox::from_id_salt("render scale base")
        .selected_text(base.map_or(draft.base.as_str(), |b| b.name))
        .show_ui(ui, |ui| {
            for b in bases {
                ui.selectable_value(&mut draft.base, b.id.to_owned(), b.name);
            }
        });
    ui.end_row();
    let own_upscaling = base.is_some_and(|b| b.own_upscaling);

    ui.label("Scale");
    ui.horizontal(|ui| {
        let preset = preset_of(draft.scale);
        egui::ComboBox::from_id_salt("render scale preset")
            .selected_text(preset.map_or_else(|| "Custom".to_owned(), preset_label))
            .show_ui(ui, |ui| {
                for preset in ScalePreset::ALL {
                    ui.selectable_value(&mut draft.scale, preset.scale(), preset_label(*preset));
                }
            });
        ui.add(
            egui::DragValue::new(&mut draft.scale)
                .range(MIN_SCALE..=1.0)
                .speed(0.005)
                .fixed_decimals(3),
        )
        .on_hover_text("Render scale per axis, from 0.25 to 1.");
    });
    ui.end_row();

    ui.label("Upscaler");
    ui.add_enabled_ui(draft.scale < 1.0 && !own_upscaling, |ui| {
        let shown = match own_upscaling {
            true => "its own",
            false => draft.upscaler.name(),
        };
        egui::ComboBox::from_id_salt("render scale upscaler")
            .selected_text(shown)
            .show_ui(ui, |ui| {
                for upscaler in Upscaler::ALL {
                    ui.selectable_value(&mut draft.upscaler, *upscaler, upscaler.name())
                        .on_hover_text(upscaler.doc());
                }
            });
    });
    ui.end_row();

    ui.label("Sharpen");
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt("render scale sharpen")
            .selected_text(draft.sharpen.map_or("none", |s| s.name()))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut draft.sharpen, None, "none");
                for filter in Sharpen::ALL {
                    ui.selectable_value(&mut draft.sharpen, Some(*filter), filter.name())
                        .on_hover_text(filter.doc());
                }
            });
        if draft.sharpen.is_some() {
            ui.add(
                egui::DragValue::new(&mut draft.strength)
                    .range(0.0..=1.0)
                    .speed(0.01)
                    .fixed_decimals(2),
            )
            .on_hover_text("Sharpening strength: 0 leaves the image unchanged, 1 is strongest.");
        }
    });
    ui.end_row();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_draft_writes_the_canonical_id_the_command_line_takes() {
        let mut draft = Draft::new("smaa");
        assert_eq!(draft.combo(false).id(), "smaa@performance:easu");
        assert_eq!(draft.combo(true).id(), "smaa@performance");
        draft.sharpen = Some(Sharpen::Rcas);
        draft.strength = 0.2;
        draft.scale = ScalePreset::Quality.scale();
        draft.upscaler = Upscaler::Lanczos;
        let id = draft.combo(false).id();
        assert_eq!(Combo::parse(&id).unwrap(), draft.combo(false));
        assert!(id.starts_with("smaa@quality:lanczos+rcas"), "{id}");
        assert_eq!(preset_of(draft.scale), Some(ScalePreset::Quality));
        assert_eq!(preset_of(0.6), None);
    }
}
