//! The run summary written out: into the output scene's `extras.luxbake`, and as the
//! `--summary-json` file (the summary, the run's paths, threads and timings).

use super::atomic::write_atomic;
use crate::Result;
use crate::summary::{RunRecord, RunSummary};
use serde_json::Value;
use std::path::Path;

/// The summary as the JSON object the output holds.
pub(crate) fn to_json(summary: &RunSummary) -> Value {
    serde_json::to_value(summary).expect("the run summary serialises")
}

/// `record` as the bytes of the summary file (pretty JSON, final newline).
pub fn bytes(record: &RunRecord) -> Vec<u8> {
    let mut bytes = serde_json::to_vec_pretty(record).expect("the run record serialises");
    bytes.push(b'\n');
    bytes
}

/// Write `record` to `path` as pretty JSON, atomically.
pub fn write(path: &Path, record: &RunRecord) -> Result<()> {
    write_atomic(path, &bytes(record))
}
