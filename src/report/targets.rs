//! Design targets: a JSON object of average illuminances (lx) the report compares the bake with,
//! e.g. the seed paper's Table 1 for the office (`samples/office/targets.json`).
//!
//! Keys, in the file's order:
//! - `working_plane`: the working plane's average (an error when the bake has no working plane);
//! - `PATH` or `node:PATH`: the node whose names joined by `/` from its root are PATH
//!   (`desk_dark/top`); all nodes with that path together;
//! - `material:NAME`: every surface with that material;
//! - any surface key may end in a face, `[+x]`, `[-x]`, `[+y]`, `[-y]`, `[+z]` or `[-z]`: only
//!   the faces whose normal is within ~8° of that world axis (`desk_dark/top[+y]`: the desk's
//!   upper face).
//!
//! A key that names nothing in the bake, or whose faces have no area, is an error naming it.

use super::rows::{Filter, row};
use crate::readback::BakedOutput;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The targets, in the file's order.
#[derive(Debug, Clone, PartialEq)]
pub struct Targets {
    /// Where they came from (for messages).
    pub file: PathBuf,
    pub entries: Vec<(String, f64)>,
}

/// One target beside what the bake achieved.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TargetRow {
    /// The key, as in the targets file.
    pub name: String,
    /// lx.
    pub target: f64,
    /// Average illuminance achieved (lx); `None` for a working plane the bake did not measure.
    pub achieved: Option<f64>,
    /// achieved / target.
    pub ratio: Option<f64>,
    /// achieved ≥ target (EN 12464-1: the maintained illuminance is a floor, not a goal to
    /// approach from either side).
    pub pass: Option<bool>,
}

impl Targets {
    /// Parse the JSON text of `file`.
    pub fn parse(file: &Path, text: &str) -> Result<Self> {
        let err = |at: &str, m: String| Error::input(file, at, m);
        let value: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| err("", format!("targets are not valid JSON: {e}")))?;
        let object = value.as_object().ok_or_else(|| {
            err(
                "",
                "targets must be a JSON object of illuminances in lx, e.g. {\"working_plane\": 500}"
                    .into(),
            )
        })?;
        let mut entries = Vec::new();
        for (key, v) in object {
            match v.as_f64() {
                Some(lx) if lx.is_finite() && lx > 0.0 => entries.push((key.clone(), lx)),
                _ => {
                    return Err(err(
                        "",
                        format!("target '{key}' must be a positive illuminance in lx, got {v}"),
                    ));
                }
            }
        }
        Ok(Targets {
            file: file.to_path_buf(),
            entries,
        })
    }

    /// Read (through [`crate::import::files`]) and parse a targets file.
    pub fn read(file: &Path) -> Result<Self> {
        let text = crate::import::files::read_text(file)
            .map_err(|e| Error::input(file, "", format!("cannot read the targets: {e}")))?;
        Targets::parse(file, &text)
    }

    /// Each target beside the bake's figure.
    pub(crate) fn rows(
        &self,
        input: &BakedOutput,
        plane_avg: Option<f64>,
    ) -> Result<Vec<TargetRow>> {
        self.entries
            .iter()
            .map(|(key, target)| {
                let target = *target;
                let achieved = if key == "working_plane" {
                    Some(plane_avg.ok_or_else(|| self.no_working_plane())?)
                } else {
                    Some(self.surface_average(input, key)?)
                };
                Ok(TargetRow {
                    name: key.clone(),
                    target,
                    achieved,
                    ratio: achieved.map(|a| a / target),
                    pass: achieved.map(|a| a >= target),
                })
            })
            .collect()
    }

    /// Whether a target needs the bake's working plane.
    pub fn wants_working_plane(&self) -> bool {
        self.entries.iter().any(|(k, _)| k == "working_plane")
    }

    /// The error for a `working_plane` target when the bake has none.
    pub fn no_working_plane(&self) -> Error {
        Error::input(
            &self.file,
            "",
            "target 'working_plane': the bake has no working plane (bake with --working-plane \
             HEIGHT, e.g. --working-plane 0.75)",
        )
    }

    /// The average illuminance over the surfaces `key` names.
    fn surface_average(&self, input: &BakedOutput, key: &str) -> Result<f64> {
        self.surface_row(input, key).map(|r| r.e_avg)
    }

    /// The report row of the surfaces `key` names (a node path, `material:NAME`, either with a
    /// face); errors name the key and this file.
    pub fn surface_row(&self, input: &BakedOutput, key: &str) -> Result<super::Row> {
        let err = |m: String| Error::input(&self.file, "", format!("target '{key}': {m}"));
        let (name, filter) = split_face(key).map_err(&err)?;
        let prims: Vec<_> = match name.strip_prefix("material:") {
            Some(material) => input
                .primitives
                .iter()
                .filter(|p| input.material_name(p.material) == material)
                .collect(),
            None => {
                let path = name.strip_prefix("node:").unwrap_or(name);
                // Each node's path once (a path is as long as the node's depth).
                let mut is: std::collections::HashMap<usize, bool> = Default::default();
                input
                    .primitives
                    .iter()
                    .filter(|p| {
                        *is.entry(p.node)
                            .or_insert_with(|| input.node_path(p.node) == path)
                    })
                    .collect()
            }
        };
        if prims.is_empty() {
            return Err(err(
                "no baked node or material of that name (nodes are named by their path from the \
                 root, e.g. desk_dark/top; materials as material:NAME)"
                    .into(),
            ));
        }
        row(input, key, &prims, &filter).ok_or_else(|| err("no face of it faces that way".into()))
    }
}

/// `name[+y]` → (`name`, facing +Y); `name` → (`name`, all faces).
fn split_face(key: &str) -> std::result::Result<(&str, Filter), String> {
    let (name, face) = crate::readback::keys::split_face(key)?;
    Ok((name, face.map_or(Filter::All, Filter::Facing)))
}
