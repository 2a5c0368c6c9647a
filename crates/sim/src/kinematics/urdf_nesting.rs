//! The nesting depth of URDF text, checked before the XML reader sees it.
//!
//! `urdf-rs` reads through a recursive deserializer: tens of thousands of nested elements
//! (in a `<gazebo>` block, say) overflow the stack and abort the process, and deep input
//! takes time growing faster than its length. A URDF needs five levels (`robot`, `link`,
//! `collision`, `geometry`, `mesh`); plugins in `<gazebo>` blocks a few more. This scan
//! counts element depth once, linearly, and refuses more than [`MAX_DEPTH`].

/// The deepest element nesting accepted in a URDF file.
pub const MAX_DEPTH: usize = 64;

/// The first element nested deeper than [`MAX_DEPTH`]: (its line, its depth). Comments,
/// processing instructions, declarations, CDATA sections and quoted attribute values
/// (which may hold `>`) are skipped when they end; one that does not end hides nothing (its
/// `<` is passed over and the scan goes on), so malformed text errs towards counting more.
pub fn too_deep(text: &str) -> Option<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    // Terminators known to be absent from the rest of the text: a search that failed once
    // fails for every later start, and is not repeated (linear time on `<!--<!--<!--…`).
    let mut absent: Vec<&str> = Vec::new();
    while let Some(off) = bytes[i..].iter().position(|&b| b == b'<') {
        let start = i + off;
        let rest = &text[start..];
        let mut skip_to = |end: &'static str| {
            if absent.contains(&end) {
                return None;
            }
            let found = rest.find(end).map(|e| start + e + end.len());
            if found.is_none() {
                absent.push(end);
            }
            found
        };
        let next = if rest.starts_with("<!--") {
            skip_to("-->")
        } else if rest.starts_with("<![CDATA[") {
            skip_to("]]>")
        } else if rest.starts_with("<?") {
            skip_to("?>")
        } else if rest.starts_with("<!") || rest.starts_with("</") {
            if rest.starts_with("</") {
                depth = depth.saturating_sub(1);
            }
            skip_to(">")
        } else {
            let end = tag_end(&bytes[start..]).map(|e| start + e);
            if let Some(e) = end {
                if bytes[e - 1] != b'/' {
                    depth += 1;
                    if depth > MAX_DEPTH {
                        return Some((text[..start].matches('\n').count() + 1, depth));
                    }
                }
                Some(e + 1)
            } else {
                None
            }
        };
        // A construct that never ends is not trusted to hide what follows (an unclosed
        // `<?xml …?` hid 20,000 nested elements from this scan while the XML reader, more
        // lenient, went on and overflowed the stack): the scan goes on after its `<`.
        i = next.unwrap_or(start + 1);
    }
    None
}

/// The offset of the `>` that closes the tag starting at `tag[0] == b'<'`, outside quotes;
/// none before the next `<` (which XML allows in no tag, not even in a quoted value).
fn tag_end(tag: &[u8]) -> Option<usize> {
    let mut quote = None;
    for (k, &b) in tag.iter().enumerate().skip(1) {
        match (quote, b) {
            (_, b'<') => return None,
            (None, b'"' | b'\'') => quote = Some(b),
            (Some(q), _) if b == q => quote = None,
            (None, b'>') => return Some(k),
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nested(n: usize) -> String {
        format!(
            "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n<!-- <a><a><a> -->\n<gazebo>{}{}</gazebo>\n\
             <link name=\"a\"><visual><geometry><box size=\"1 1 1\"/></geometry></visual></link>\n\
             </robot>",
            "<a k='>'>".repeat(n),
            "</a>".repeat(n)
        )
    }

    #[test]
    fn depth_counts_elements_only() {
        // robot + gazebo + n: self-closing tags, comments, quoted '>' and the
        // declaration do not count.
        assert_eq!(too_deep(&nested(MAX_DEPTH - 2)), None);
        assert_eq!(too_deep(&nested(MAX_DEPTH - 1)), Some((4, MAX_DEPTH + 1)));
        assert_eq!(too_deep(&nested(100_000)), Some((4, MAX_DEPTH + 1)));
        // Closing tags bring the depth back: many siblings are not deep.
        let siblings = format!("<robot>{}</robot>", "<a><b/></a>".repeat(10_000));
        assert_eq!(too_deep(&siblings), None);
        // Unclosed constructs before deep nesting hide nothing (found by fuzzing #37).
        for opening in [
            "<?xml version=\"1.0\"? ",
            "<!-- ",
            "<![CDATA[ ",
            "<!DOCTYPE ",
            "<a b='",
        ] {
            let text = format!("{opening}{}", nested(100_000));
            assert!(too_deep(&text).is_some(), "{opening}");
        }
    }
}
