//! Shared luminaire fixtures: tiny valid IES LM-63 and EULUMDAT texts and a glTF scene that
//! places one luminaire of each kind.

use super::{Builder, base64_encode, triangle_builder};
use serde_json::{Value, json};

/// A small valid IES LM-63-2002 file (type C, rotationally symmetric, metres).
pub const IES: &str = "IESNA:LM-63-2002\r
[TEST] luxbake tiny downlight\r
[MANUFAC] luxbake tests\r
[LUMINAIRE] tiny downlight\r
[LAMP] LED\r
TILT=NONE\r
1 1000 1 3 1 1 2 0.6 0.6 0\r
1 1 10\r
0 45 90\r
0\r
300 200 0\r
";

/// A small valid EULUMDAT file (rotationally symmetric, 4 C planes, 3 γ angles).
pub const LDT: &str = "luxbake tests
1
1
4
90
3
45
report 1
tiny panel
LB-2
tiny.ldt
2026-01-01 luxbake
600
600
50
600
600
0
0
0
0
100
80
1
0
1
1
LED
1000
3000K
80
10
0.5
0.6
0.7
0.75
0.8
0.85
0.9
0.92
0.94
0.95
0
90
180
270
0
45
90
300
200
0
";

pub fn data_uri(mime: &str, text: &str) -> String {
    format!("data:{mime};base64,{}", base64_encode(text.as_bytes()))
}

pub fn ies_uri() -> String {
    data_uri("application/x-ies-lm-63", IES)
}

pub fn ldt_uri() -> String {
    data_uri("application/x-eulumdat", LDT)
}

/// Add `node` as a new root of the scene; returns its index.
pub fn root(b: &mut Builder, node: Value) -> usize {
    let i = b.node(node);
    b.json["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(i));
    i
}

/// The triangle scene (node 0) with one profile in each list (data URIs), an `EXT_lights_ies`
/// node (1), a `LUXBAKE_luminaire` node (2), and both extensions required.
pub fn base() -> Builder {
    let mut b = triangle_builder();
    b.json["extensions"] = json!({
        "EXT_lights_ies": {"lights": [{"uri": ies_uri(), "name": "down"}]},
        "LUXBAKE_luminaire": {"profiles": [{"uri": ldt_uri(), "name": "panel"}]},
    });
    b.json["extensionsUsed"] = json!(["EXT_lights_ies", "LUXBAKE_luminaire"]);
    b.json["extensionsRequired"] = json!(["EXT_lights_ies", "LUXBAKE_luminaire"]);
    root(
        &mut b,
        json!({"name": "Ies", "translation": [0, 3, 0],
            "extensions": {"EXT_lights_ies": {"light": 0}}}),
    );
    root(
        &mut b,
        json!({"name": "Ldt", "translation": [1, 3, 0],
            "extensions": {"LUXBAKE_luminaire": {"profile": 0}}}),
    );
    b
}
