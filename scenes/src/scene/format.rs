//! The scene file's format version: what lets a later change of the schema
//! tell an old file from a wrong one.

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serializer};

/// The scene format this version reads and writes (`format = 1` at the
/// top of a scene file). A change of the schema that an old file could
/// not be read under raises it; files of the old format are then read as
/// they were written, or refused naming what changed.
pub const SCENE_FORMAT: u32 = 1;

/// The note a run carries when its scene file has no `format` key.
pub fn missing_format_note() -> String {
    format!(
        "the scene has no `format` key: read as format {SCENE_FORMAT} \
         (add `format = {SCENE_FORMAT}` at its top to say so)"
    )
}

/// `format = 1` accepted; a newer format, or anything but a positive
/// integer, refused with the key and the value in the message.
pub(super) fn read<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u32>, D::Error> {
    let value = toml::Value::deserialize(d)?;
    match value {
        toml::Value::Integer(n) if n == i64::from(SCENE_FORMAT) => Ok(Some(SCENE_FORMAT)),
        toml::Value::Integer(n) if n > i64::from(SCENE_FORMAT) => Err(D::Error::custom(format!(
            "format = {n}: this version reads scene format {SCENE_FORMAT}; \
             the file was written for a newer one"
        ))),
        other => Err(D::Error::custom(format!(
            "format = {other}: expected the integer {SCENE_FORMAT} (the scene format version)"
        ))),
    }
}

/// Always the current format: a scene written out is a scene of this
/// version, whatever file it was read from.
pub(super) fn write<S: Serializer>(_: &Option<u32>, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_u32(SCENE_FORMAT)
}
