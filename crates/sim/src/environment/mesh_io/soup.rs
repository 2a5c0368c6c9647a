//! The readers' common ground: the [`PolygonSoup`] every format is read into, and the
//! checks of one number, one vertex or a whole file as text that OBJ, STL and PLY share.

/// Vertices and polygons as read from a file, before any welding or checks of topology.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PolygonSoup {
    /// Vertex positions (file units).
    pub positions: Vec<[f64; 3]>,
    /// Polygons: corner indices into `positions`, counter-clockwise seen from outside
    /// by the formats' convention.
    pub polygons: Vec<Vec<u32>>,
    /// Where each polygon came from, e.g. "line 12" or "facet 7".
    pub origins: Vec<String>,
    /// Number of objects/groups the file declares (OBJ `o`/`g`; 1 otherwise).
    pub objects: usize,
}

impl PolygonSoup {
    /// Adds a polygon read at `at`, refusing one with fewer than three corners.
    pub(super) fn push_polygon(&mut self, polygon: Vec<u32>, at: String) -> Result<(), ParseError> {
        if polygon.len() < 3 {
            return Err((
                at,
                format!("face has {} corners: expected 3 or more", polygon.len()),
            ));
        }
        self.polygons.push(polygon);
        self.origins.push(at);
        Ok(())
    }
}

/// A parse error: (location, message).
pub type ParseError = (String, String);

pub(super) fn finite(v: [f64; 3], at: &str) -> Result<[f64; 3], ParseError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(v)
    } else {
        Err((
            at.to_string(),
            format!("vertex {v:?} is not finite: expected three finite numbers"),
        ))
    }
}

pub(super) fn number(token: Option<&str>, at: &str, what: &str) -> Result<f64, ParseError> {
    let t = token.ok_or_else(|| (at.to_string(), format!("missing {what}")))?;
    t.parse::<f64>()
        .map_err(|_| (at.to_string(), format!("{what} {t:?} is not a number")))
}

pub(super) fn text(bytes: &[u8]) -> Result<&str, ParseError> {
    std::str::from_utf8(bytes).map_err(|e| {
        (
            "file".into(),
            format!("not text (invalid UTF-8 at byte {})", e.valid_up_to()),
        )
    })
}
