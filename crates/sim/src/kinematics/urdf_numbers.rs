//! Locating malformed numbers in URDF text, for error messages.
//!
//! `urdf-rs` reports a bad number without saying where it is ("invalid float literal").
//! When parsing fails, this scanner walks the tags once more and finds the first numeric
//! attribute that does not hold the expected count of numbers, with the enclosing
//! `<link>` or `<joint>` and the line.

/// Attributes that hold numbers, with how many.
const NUMERIC: &[(&str, usize)] = &[
    ("xyz", 3),
    ("rpy", 3),
    ("size", 3),
    ("scale", 3),
    ("rgba", 4),
    ("lower", 1),
    ("upper", 1),
    ("effort", 1),
    ("velocity", 1),
    ("value", 1),
    ("radius", 1),
    ("length", 1),
    ("ixx", 1),
    ("ixy", 1),
    ("ixz", 1),
    ("iyy", 1),
    ("iyz", 1),
    ("izz", 1),
    ("damping", 1),
    ("friction", 1),
    ("multiplier", 1),
    ("offset", 1),
];

/// Attributes of one tag's text (after the tag name), as (key, value) pairs.
fn attributes(mut rest: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    while let Some(eq) = rest.find('=') {
        let key = rest[..eq].trim().trim_start_matches('/');
        let after = rest[eq + 1..].trim_start();
        let Some(quote) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            break;
        };
        let Some(end) = after[1..].find(quote) else {
            break;
        };
        out.push((key, &after[1..1 + end]));
        rest = &after[end + 2..];
    }
    out
}

/// The first malformed numeric attribute: (enclosing element, what is wrong).
pub fn find_bad_number(text: &str) -> Option<(String, String)> {
    let mut element = "<robot>".to_string();
    let mut offset = 0;
    for chunk in text.split('<') {
        let start = offset;
        offset += chunk.len() + 1;
        let tag_text = chunk.split('>').next().unwrap_or("");
        if tag_text.starts_with(['/', '!', '?']) {
            continue;
        }
        let name_end = tag_text.find(char::is_whitespace).unwrap_or(tag_text.len());
        let (tag, rest) = tag_text.split_at(name_end);
        let attrs = attributes(rest);
        if tag == "link" || tag == "joint" {
            if let Some((_, name)) = attrs.iter().find(|(k, _)| *k == "name") {
                element = format!("<{tag} name=\"{name}\">");
            }
            continue;
        }
        for (key, value) in attrs {
            let Some(&(_, count)) = NUMERIC.iter().find(|(k, _)| *k == key) else {
                continue;
            };
            let parsed: Vec<Option<f64>> =
                value.split_whitespace().map(|v| v.parse().ok()).collect();
            if parsed.len() != count || parsed.iter().any(Option::is_none) {
                let line = text[..start].matches('\n').count() + 1;
                let what = if count == 1 {
                    "a number".to_string()
                } else {
                    format!("{count} numbers")
                };
                return Some((
                    element,
                    format!("line {line}: <{tag} {key}=\"{value}\">: expected {what}"),
                ));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_element_and_line_of_a_bad_number() {
        let text = "<robot name=\"r\">\n<link name=\"a\"/>\n<joint name=\"j\" type=\"fixed\">\n  <origin xyz=\"0 0\" rpy='0 0 0'/>\n</joint></robot>";
        let (element, message) = find_bad_number(text).unwrap();
        assert_eq!(element, "<joint name=\"j\">");
        assert!(
            message.starts_with("line 4: <origin xyz=\"0 0\">: expected 3 numbers"),
            "{message}"
        );
        let ok = "<robot name=\"r\"><link name=\"a\"><inertial><mass value=\"1.5e-3\"/></inertial></link></robot>";
        assert_eq!(find_bad_number(ok), None);
        let bad =
            "<robot><link name=\"a\"><inertial><mass value=\"heavy\"/></inertial></link></robot>";
        assert!(
            find_bad_number(bad)
                .unwrap()
                .1
                .contains("expected a number")
        );
    }
}
