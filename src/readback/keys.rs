//! Surface keys' faces, shared by every reader that names surfaces (`bake report` targets,
//! `bake design`/`fit` rows, `bake plan --surface`): a key may end in a face, `[+x]`, `[-x]`,
//! `[+y]`, `[-y]`, `[+z]` or `[-z]` (glTF axes, +Y up), which keeps only the triangles whose
//! normal is within ~8° of that world axis (`desk_dark/top[+y]`: the desk top's upper face).

use super::model::Primitive;
use crate::probes::{FACE_NAMES, FACES};
use glam::DVec3;

/// The cosine a triangle's normal must reach with a face's axis to be on that face (~8.1°).
pub const FACE_COS: f64 = 0.99;

/// `name[+y]` → (`name`, Some(+Y)); `name` → (`name`, None); an unknown face is an error
/// message listing the six.
pub(crate) fn split_face(key: &str) -> Result<(&str, Option<DVec3>), String> {
    let Some(open) = key.strip_suffix(']').and_then(|k| k.rfind('[')) else {
        return Ok((key, None));
    };
    let face = &key[open + 1..key.len() - 1];
    let k = FACE_NAMES.iter().position(|&f| f == face).ok_or_else(|| {
        format!(
            "unknown face [{face}] (use one of {})",
            FACE_NAMES.join(" ")
        )
    })?;
    Ok((&key[..open], Some(FACES[k])))
}

/// Whether triangle `j` of `p` faces `d` (its normal within ~8° of it; no area: no).
pub(crate) fn faces(p: &Primitive, j: usize, d: DVec3) -> bool {
    let [a, b, c] = p.triangles[j].map(|v| p.positions[v as usize]);
    let cross = (b - a).cross(c - a);
    cross.length() > 0.0 && cross.normalize().dot(d.normalize()) >= FACE_COS
}

#[cfg(test)]
mod tests {
    use super::split_face;
    use glam::DVec3;

    #[test]
    fn faces_are_split_off_keys() {
        assert_eq!(
            split_face("desk/top[+y]").unwrap(),
            ("desk/top", Some(DVec3::Y))
        );
        assert_eq!(
            split_face("desk/top[-x]").unwrap(),
            ("desk/top", Some(DVec3::NEG_X))
        );
        assert_eq!(
            split_face("material:wall").unwrap(),
            ("material:wall", None)
        );
        assert!(
            split_face("desk[up]")
                .unwrap_err()
                .contains("+x -x +y -y +z -z")
        );
    }
}
