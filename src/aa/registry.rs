//! The list of every technique aa-lab knows: each technique's folder provides its own entry
//! (a [`TechniqueInfo`], see [`super::info`]) and [`registry`] lists the entries, one line per
//! technique. Front ends look techniques up here by id and name them with [`display_name`];
//! techniques themselves never import this file (it imports them).

use super::info::TechniqueInfo;
use super::{cmaa2, fxaa, mlaa, msaa, none, smaa, ssaa, taa, taau};

/// Every technique, in the order front ends list them: each technique folder provides its
/// entries (`INFO`, or `INFOS` for a family of fixed variants), and adding a technique is one
/// line here.
pub fn registry() -> Vec<TechniqueInfo> {
    [
        &[none::INFO][..],
        &[ssaa::INFO],
        &msaa::INFOS,
        &[fxaa::INFO],
        &[mlaa::INFO],
        &smaa::INFOS,
        &[smaa::x4::INFO],
        &[taa::INFO],
        &[taau::INFO],
        &[cmaa2::INFO],
    ]
    .concat()
}

/// The registry entry of an id.
pub fn info(id: &str) -> Option<TechniqueInfo> {
    registry().into_iter().find(|t| t.id == id)
}

/// The display name of a registered technique, a user technique (`user:PATH`) or a
/// combination (`smaa@performance:easu`: "SMAA 1x @ 50% EASU"; any other id as it is): the
/// label of techniques whose settings do not change what they are.
pub fn display_name(id: &str) -> String {
    match info(id) {
        Some(info) => info.name.to_owned(),
        None if super::user::is_user_id(id) => super::user::display_name(id),
        None => match super::combo::Combo::parse(id) {
            Ok(combo) if !combo.is_plain() => {
                format!("{}{}", display_name(&combo.base), combo.label_suffix())
            }
            _ => id.to_owned(),
        },
    }
}
