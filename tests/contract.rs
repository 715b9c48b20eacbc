//! The contract every registered technique keeps, checked by walking the whole registry (so a
//! new technique is covered by adding its registry line): ids, names and labels are unique and
//! the id is the technique's own; every parameter value round-trips through the CLI's `--set`
//! parsing and through the record/sidecar JSON; every preset applies and unknown ones are
//! refused; every debug view has the output's size and disappears when debug views are off.
//! Renders are tiny (64x36) so the whole walk stays fast on a software adapter.

mod common;

use std::collections::BTreeSet;

use aa_lab::aa::{self, ParamKind, ParamValue, Technique, TechniqueInfo};
use aa_lab::cli::{Cli, Command, technique_specs};
use aa_lab::gpu::Gpu;
use aa_lab::spec::TechniqueSpec;
use clap::Parser;

const SIZE: (u32, u32) = (64, 36);

/// The registry entries this adapter can run, each with a fresh instance.
fn available(gpu: &Gpu) -> Vec<(TechniqueInfo, Box<dyn Technique>)> {
    aa::registry()
        .into_iter()
        .filter(|info| (info.availability)(&gpu.caps).is_ok())
        .map(|info| (info, common::technique(gpu, info.id, &[])))
        .collect()
}

/// The values a parameter is tried with: every choice, both states, the ends and middle of
/// a range.
fn values_to_try(kind: &ParamKind) -> Vec<ParamValue> {
    match kind {
        ParamKind::Bool => vec![ParamValue::Bool(false), ParamValue::Bool(true)],
        ParamKind::Float { min, max } => [*min, (min + max) / 2.0, *max]
            .into_iter()
            .map(ParamValue::Float)
            .collect(),
        ParamKind::Int { min, max } => [*min, (min + max) / 2, *max]
            .into_iter()
            .map(ParamValue::Int)
            .collect(),
        ParamKind::Choice(options) => options
            .iter()
            .map(|o| ParamValue::Choice((*o).to_owned()))
            .collect(),
    }
}

/// The technique's settings after the command line `--technique ID --set ID.KEY=TEXT`, as the
/// CLI resolves them into the render's record.
fn through_the_cli(gpu: &Gpu, id: &str, key: &str, text: &str) -> TechniqueSpec {
    let set = format!("{id}.{key}={text}");
    let cli = Cli::try_parse_from([
        "aa-lab",
        "render",
        "--technique",
        id,
        "--set",
        &set,
        "--out",
        "unused",
    ])
    .unwrap_or_else(|e| panic!("--set {set}: {e}"));
    let Some(Command::Render(args)) = cli.command else {
        panic!("`render` did not parse as the render command");
    };
    let mut specs =
        technique_specs(gpu, &args.techniques).unwrap_or_else(|e| panic!("--set {set}: {e}"));
    assert_eq!(specs.len(), 1);
    specs.remove(0)
}

#[test]
fn ids_names_and_labels_are_unique_and_the_id_is_the_techniques_own() {
    let gpu = common::gpu();
    let registry = aa::registry();
    let ids: BTreeSet<&str> = registry.iter().map(|i| i.id).collect();
    let names: BTreeSet<&str> = registry.iter().map(|i| i.name).collect();
    assert_eq!(ids.len(), registry.len(), "duplicate ids");
    assert_eq!(names.len(), registry.len(), "duplicate names");
    for info in &registry {
        assert!(!info.summary.is_empty(), "{} has no summary", info.id);
        assert!(
            info.id
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
            "{}: ids are typed on command lines",
            info.id
        );
    }
    let available = available(&gpu);
    assert!(!available.is_empty());
    let mut labels = BTreeSet::new();
    for (info, technique) in &available {
        assert_eq!(technique.id(), info.id);
        assert_eq!(aa::registry::display_name(info.id), info.name);
        assert!(
            labels.insert(technique.label()),
            "{}: label {} is taken",
            info.id,
            technique.label()
        );
        let keys: BTreeSet<&str> = technique.params().iter().map(|p| p.key).collect();
        assert_eq!(
            keys.len(),
            technique.params().len(),
            "{}: duplicate keys",
            info.id
        );
    }
}

#[test]
fn every_parameter_round_trips_through_the_cli_and_the_record() {
    let gpu = common::gpu();
    for (info, technique) in available(&gpu) {
        for param in technique.params() {
            for value in values_to_try(&param.kind) {
                let text = value.to_string();
                let what = format!("{}.{}={text}", info.id, param.key);
                // The command line: the record holds the value in its own form.
                let spec = through_the_cli(&gpu, info.id, param.key, &text);
                assert_eq!(spec.id, info.id);
                assert_eq!(spec.settings.get(param.key), Some(&value), "{what}");
                // The record/sidecar: JSON and back restores every setting exactly.
                let json = serde_json::to_string(&spec).expect("serialises");
                let back: TechniqueSpec =
                    serde_json::from_str(&json).unwrap_or_else(|e| panic!("{what}: {e} in {json}"));
                assert_eq!(back, spec, "{what}: {json}");
                let mut restored = common::technique(&gpu, info.id, &[]);
                aa::apply_param_map(restored.as_mut(), &back.settings)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(
                    aa::param_map(restored.as_ref()),
                    spec.settings,
                    "{what}: restoring the record"
                );
            }
        }
        // A key the technique does not have is refused with the keys it has.
        let mut t = common::technique(&gpu, info.id, &[]);
        let err = aa::set_param(t.as_mut(), "no_such_key", ParamValue::Int(1))
            .expect_err("unknown key refused")
            .to_string();
        assert!(err.contains(info.id), "{err}");
    }
}

#[test]
fn every_preset_applies_and_unknown_ones_are_refused() {
    let gpu = common::gpu();
    for (info, mut technique) in available(&gpu) {
        let presets = technique.presets();
        let unique: BTreeSet<&str> = presets.iter().copied().collect();
        assert_eq!(
            unique.len(),
            presets.len(),
            "{}: duplicate presets",
            info.id
        );
        for preset in presets {
            technique
                .apply_preset(preset)
                .unwrap_or_else(|e| panic!("{}={preset}: {e}", info.id));
            // A preset leaves valid settings: they restore on a fresh instance.
            let map = aa::param_map(technique.as_ref());
            let mut fresh = common::technique(&gpu, info.id, &[]);
            aa::apply_param_map(fresh.as_mut(), &map)
                .unwrap_or_else(|e| panic!("{}={preset}: {e}", info.id));
            assert_eq!(aa::param_map(fresh.as_ref()), map, "{}={preset}", info.id);
        }
        let err = technique
            .apply_preset("no-such-preset")
            .expect_err("unknown preset refused")
            .to_string();
        assert!(err.contains("no-such-preset"), "{err}");
    }
}

#[test]
fn debug_views_have_the_output_size_and_only_when_asked_for() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let techniques: Vec<Box<dyn Technique>> = available(&gpu)
        .into_iter()
        .map(|(_, mut t)| {
            t.set_debug_views(true);
            t
        })
        .collect();
    let mut graph = common::graph(&gpu, &scene, techniques);
    let outputs = common::render_frames(&mut graph, &scene, SIZE, 0..=1);
    let mut with_views = 0;
    for (slot, output) in graph.slots().iter().zip(&outputs) {
        let id = slot.technique.id();
        assert_eq!(output.dimensions(), SIZE, "{id}");
        let views = slot.technique.debug_views();
        let names: BTreeSet<&str> = views.iter().map(|v| v.name).collect();
        assert_eq!(names.len(), views.len(), "{id}: duplicate view names");
        for view in &views {
            assert_eq!(
                (view.texture.width(), view.texture.height()),
                SIZE,
                "{id}: debug view {}",
                view.name
            );
            assert!(!view.description.is_empty(), "{id}: {}", view.name);
        }
        with_views += usize::from(!views.is_empty());
    }
    assert!(
        with_views >= 3,
        "only {with_views} techniques showed debug views"
    );
    for slot in graph.slots_mut() {
        slot.technique.set_debug_views(false);
        assert!(
            slot.technique.debug_views().is_empty(),
            "{}: views while switched off",
            slot.technique.id()
        );
    }
}

/// The render-scale, upscaler and sharpening modifiers every technique is walked with.
const COMBINATIONS: [&str; 3] = ["@quality:bilinear", "@performance+rcas=0.2", "+cas=1"];

#[test]
fn every_technique_at_a_scale_with_sharpening_round_trips_and_keeps_the_contract() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut techniques: Vec<Box<dyn Technique>> = Vec::new();
    for (info, plain) in available(&gpu) {
        for suffix in COMBINATIONS {
            // A technique that reconstructs at the output size itself takes no upscaler.
            let reconstructs = plain.reconstructs_at_output();
            let suffix = match suffix.split_once(':') {
                Some((scale, _)) if reconstructs => scale,
                _ => suffix,
            };
            let id = format!("{}{suffix}", info.id);
            let mut technique = common::technique(&gpu, &id, &[]);
            // The id is the canonical string of the combination, and reads back to itself.
            let canonical = aa::combo::Combo::parse(&id)
                .and_then(|combo| combo.resolve(reconstructs))
                .expect("valid")
                .id();
            assert_eq!(technique.id(), canonical, "{id}");
            assert_eq!(common::technique(&gpu, &canonical, &[]).id(), canonical);
            assert!(technique.label().starts_with(&plain.label()), "{id}");
            assert_ne!(technique.label(), plain.label(), "{id}");
            // Parameters are the technique's own, and round-trip through the CLI and records.
            assert_eq!(
                aa::param_map(technique.as_ref()),
                aa::param_map(plain.as_ref())
            );
            for param in technique.params() {
                let value = values_to_try(&param.kind).pop().expect("a value");
                let spec = through_the_cli(&gpu, &id, param.key, &value.to_string());
                assert_eq!(spec.id, canonical, "{id}");
                assert_eq!(
                    spec.settings.get(param.key),
                    Some(&value),
                    "{id}.{}",
                    param.key
                );
                let json = serde_json::to_string(&spec).expect("serialises");
                let back: TechniqueSpec = serde_json::from_str(&json).expect("parses");
                let restored = back.create(&gpu).unwrap_or_else(|e| panic!("{id}: {e}"));
                assert_eq!(restored.id(), canonical);
                assert_eq!(aa::param_map(restored.as_ref()), spec.settings, "{id}");
            }
            technique.set_debug_views(true);
            techniques.push(technique);
        }
    }
    // Every combination renders at the output size, with its debug views at that size too.
    let mut graph = common::graph(&gpu, &scene, techniques);
    let outputs = common::render_frames(&mut graph, &scene, SIZE, 0..=1);
    for (slot, output) in graph.slots().iter().zip(&outputs) {
        let id = slot.technique.id();
        assert_eq!(output.dimensions(), SIZE, "{id}");
        for view in slot.technique.debug_views() {
            assert_eq!(
                (view.texture.width(), view.texture.height()),
                SIZE,
                "{id}: debug view {}",
                view.name
            );
        }
    }
}
