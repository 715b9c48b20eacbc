//! `aa-lab info` and `aa-lab techniques`: the adapter's capability report and the technique
//! registry with availability, as text or JSON.

use crate::aa::{self, ParamKind};
use crate::gpu::Gpu;

/// Prints the capability report.
pub fn info(json: bool) -> anyhow::Result<()> {
    let gpu = Gpu::headless()?;
    if json {
        println!("{}", serde_json::to_string_pretty(&gpu.caps)?);
    } else {
        print!("{}", gpu.caps.report());
    }
    Ok(())
}

fn kind_text(kind: &ParamKind) -> String {
    match kind {
        ParamKind::Bool => "on|off".to_owned(),
        ParamKind::Float { min, max } => format!("{min}..={max}"),
        ParamKind::Int { min, max } => format!("{min}..={max}"),
        ParamKind::Choice(options) => options.join("|"),
    }
}

/// Prints the registry with availability on this adapter.
pub fn techniques(json: bool, verbose: bool) -> anyhow::Result<()> {
    let gpu = Gpu::headless()?;
    let mut rows = Vec::new();
    for info in aa::registry() {
        let availability = (info.availability)(&gpu.caps);
        let params = match &availability {
            Ok(()) => {
                let technique = (info.create)(&gpu);
                let presets = technique.presets().to_vec();
                let params: Vec<serde_json::Value> = technique
                    .params()
                    .into_iter()
                    .map(|p| {
                        serde_json::json!({
                            "key": p.key, "label": p.label, "help": p.help,
                            "range": kind_text(&p.kind), "default": p.value.to_string(),
                        })
                    })
                    .collect();
                serde_json::json!({ "presets": presets, "params": params, "path": technique.path_note() })
            }
            Err(_) => serde_json::Value::Null,
        };
        rows.push(serde_json::json!({
            "id": info.id,
            "name": info.name,
            "available": availability.is_ok(),
            "reason": availability.err(),
            "summary": info.summary,
            "settings": params,
        }));
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    println!(
        "techniques on {} ({}):",
        gpu.caps.adapter_name, gpu.caps.backend
    );
    for row in &rows {
        let status = if row["available"] == true {
            "available".to_owned()
        } else {
            format!(
                "unavailable: {}",
                row["reason"].as_str().unwrap_or_default()
            )
        };
        println!(
            "  {:<10} {:<12} {status}",
            row["id"].as_str().unwrap_or_default(),
            row["name"].as_str().unwrap_or_default()
        );
        if verbose {
            println!("      {}", row["summary"].as_str().unwrap_or_default());
            if let Some(presets) = row["settings"]["presets"]
                .as_array()
                .filter(|p| !p.is_empty())
            {
                let names: Vec<&str> = presets.iter().filter_map(|p| p.as_str()).collect();
                println!("      presets: {}", names.join(", "));
            }
            for p in row["settings"]["params"].as_array().into_iter().flatten() {
                println!(
                    "      {}.{} = {} ({})\n          {}",
                    row["id"].as_str().unwrap_or_default(),
                    p["key"].as_str().unwrap_or_default(),
                    p["default"].as_str().unwrap_or_default(),
                    p["range"].as_str().unwrap_or_default(),
                    p["help"].as_str().unwrap_or_default()
                );
            }
        }
    }
    Ok(())
}
