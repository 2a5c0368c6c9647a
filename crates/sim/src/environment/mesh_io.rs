//! Reading triangle-mesh files: Wavefront OBJ, STL (ASCII and binary) and PLY (ASCII and
//! binary, either byte order).
//!
//! Each reader returns a [`PolygonSoup`]: vertex positions in the file's own units and
//! polygons (triangles, quads or larger, as indices into the positions) with the line
//! or record each came from, so that later checks can point at the place in the file.
//! Readers check what only they can see: numbers that do not parse or are not finite,
//! indices out of range, polygons with fewer than three corners, truncated files.
//!
//! The parsers are written here rather than taken from `tobj`/`stl_io` so that every
//! error names its line, values stay in f64, and binary STL files whose 80-byte header
//! happens to begin with `solid` are recognised by their exact size (84 + 50·n bytes)
//! rather than by that word.

use std::path::{Path, PathBuf};

/// A problem with a mesh file: which file, where in it, what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {at}: {message}", file.display())]
pub struct MeshError {
    /// The file.
    pub file: PathBuf,
    /// Where: a line, facet, element record, or "mesh".
    pub at: String,
    /// What is wrong and what was expected.
    pub message: String,
}

impl MeshError {
    /// A new error.
    pub fn new(file: &Path, at: &str, message: String) -> Self {
        Self {
            file: file.to_path_buf(),
            at: at.to_string(),
            message,
        }
    }
}

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
    fn push_polygon(&mut self, polygon: Vec<u32>, at: String) -> Result<(), ParseError> {
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

/// Mesh file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// STL, ASCII or binary.
    Stl,
    /// Stanford PLY, ASCII or binary.
    Ply,
}

impl Format {
    /// The format named by a file's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "stl" => Some(Format::Stl),
            "ply" => Some(Format::Ply),
            _ => None,
        }
    }
}

/// Reads a mesh file in the format its extension names.
pub fn read(path: &Path) -> Result<PolygonSoup, MeshError> {
    let err = |at: &str, msg: String| MeshError::new(path, at, msg);
    let format = Format::from_path(path).ok_or_else(|| {
        err(
            "file name",
            "unknown mesh format: expected the extension .obj, .stl or .ply".into(),
        )
    })?;
    let bytes = std::fs::read(path).map_err(|e| err("file", format!("cannot read: {e}")))?;
    let soup = match format {
        Format::Obj => parse_obj(&bytes),
        Format::Stl => parse_stl(&bytes),
        Format::Ply => parse_ply(&bytes),
    }
    .map_err(|(at, msg)| err(&at, msg))?;
    if soup.polygons.is_empty() {
        return Err(err("file", "empty mesh: no faces".into()));
    }
    Ok(soup)
}

/// A parse error: (location, message).
pub type ParseError = (String, String);

fn finite(v: [f64; 3], at: &str) -> Result<[f64; 3], ParseError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(v)
    } else {
        Err((
            at.to_string(),
            format!("vertex {v:?} is not finite: expected three finite numbers"),
        ))
    }
}

fn number(token: Option<&str>, at: &str, what: &str) -> Result<f64, ParseError> {
    let t = token.ok_or_else(|| (at.to_string(), format!("missing {what}")))?;
    t.parse::<f64>()
        .map_err(|_| (at.to_string(), format!("{what} {t:?} is not a number")))
}

fn text(bytes: &[u8]) -> Result<&str, ParseError> {
    std::str::from_utf8(bytes).map_err(|e| {
        (
            "file".into(),
            format!("not text (invalid UTF-8 at byte {})", e.valid_up_to()),
        )
    })
}

/// Parses OBJ text: `v x y z [w]` vertices and `f a b c …` faces (corners `v`, `v/t`,
/// `v//n` or `v/t/n`, 1-based, negative = relative to the end); `o` and `g` count objects;
/// everything else (normals, texture coordinates, materials, lines) is ignored.
pub fn parse_obj(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let mut soup = PolygonSoup::default();
    let mut groups = 0;
    for (n, raw) in text(bytes)?.lines().enumerate() {
        let at = format!("line {}", n + 1);
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let mut v = [0.0; 3];
                for (c, name) in v.iter_mut().zip(["x", "y", "z"]) {
                    *c = number(tokens.next(), &at, &format!("vertex {name}"))?;
                }
                soup.positions.push(finite(v, &at)?);
            }
            Some("f") => {
                let count = soup.positions.len() as i64;
                let mut polygon = Vec::new();
                for corner in tokens {
                    let index = corner.split('/').next().unwrap_or("");
                    let i: i64 = index.parse().map_err(|_| {
                        (
                            at.clone(),
                            format!("face corner {corner:?} is not an index"),
                        )
                    })?;
                    let resolved = if i < 0 { count + i } else { i - 1 };
                    if i == 0 || resolved < 0 || resolved >= count {
                        return Err((
                            at,
                            format!(
                                "face index {i} is out of range: {count} vertices are defined \
                                 before this line"
                            ),
                        ));
                    }
                    polygon.push(resolved as u32);
                }
                soup.push_polygon(polygon, at)?;
            }
            Some("o") | Some("g") => groups += 1,
            _ => {}
        }
    }
    soup.objects = groups.max(1);
    Ok(soup)
}

/// Parses STL, binary when the file is exactly 84 + 50·n bytes long with n the count in
/// its header (whatever its first five bytes say), ASCII otherwise.
pub fn parse_stl(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * n {
            return parse_stl_binary(bytes, n);
        }
    }
    if bytes.trim_ascii_start().starts_with(b"solid") {
        return parse_stl_ascii(bytes);
    }
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        return Err((
            "header".into(),
            format!(
                "binary STL declares {n} triangles ({} bytes expected) but the file has {} \
                 bytes, and it is not ASCII STL (which starts with \"solid\")",
                84 + 50 * n,
                bytes.len()
            ),
        ));
    }
    Err((
        "file".into(),
        format!(
            "{} bytes: too short for binary STL (84-byte header) and not ASCII STL",
            bytes.len()
        ),
    ))
}

fn parse_stl_binary(bytes: &[u8], n: usize) -> Result<PolygonSoup, ParseError> {
    let mut soup = PolygonSoup {
        objects: 1,
        ..Default::default()
    };
    for t in 0..n {
        let at = format!("facet {}", t + 1);
        let record = &bytes[84 + 50 * t..84 + 50 * (t + 1)];
        let f = |k: usize| {
            let o = 12 + 4 * k;
            f32::from_le_bytes([record[o], record[o + 1], record[o + 2], record[o + 3]]) as f64
        };
        let base = soup.positions.len() as u32;
        for v in 0..3 {
            soup.positions
                .push(finite([f(3 * v), f(3 * v + 1), f(3 * v + 2)], &at)?);
        }
        soup.polygons.push(vec![base, base + 1, base + 2]);
        soup.origins.push(at);
    }
    Ok(soup)
}

fn parse_stl_ascii(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let mut soup = PolygonSoup::default();
    let mut corners: Vec<u32> = Vec::new();
    let mut facet_line = String::new();
    for (n, raw) in text(bytes)?.lines().enumerate() {
        let at = format!("line {}", n + 1);
        let mut tokens = raw.split_whitespace();
        match tokens.next() {
            Some("solid") => soup.objects += 1,
            Some("facet") => {
                corners.clear();
                facet_line = at;
            }
            Some("vertex") => {
                let mut v = [0.0; 3];
                for (c, name) in v.iter_mut().zip(["x", "y", "z"]) {
                    *c = number(tokens.next(), &at, &format!("vertex {name}"))?;
                }
                corners.push(soup.positions.len() as u32);
                soup.positions.push(finite(v, &at)?);
            }
            Some("endfacet") => {
                if corners.len() < 3 {
                    return Err((
                        facet_line.clone(),
                        format!("facet has {} vertices: expected 3 or more", corners.len()),
                    ));
                }
                soup.polygons.push(std::mem::take(&mut corners));
                soup.origins.push(facet_line.clone());
            }
            _ => {}
        }
    }
    soup.objects = soup.objects.max(1);
    Ok(soup)
}

/// A scalar type of a PLY property.
#[derive(Debug, Clone, Copy)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn decode(self, b: &[u8], big: bool) -> f64 {
        macro_rules! num {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                (if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }) as f64
            }};
        }
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => num!(i16, 2),
            Scalar::U16 => num!(u16, 2),
            Scalar::I32 => num!(i32, 4),
            Scalar::U32 => num!(u32, 4),
            Scalar::F32 => num!(f32, 4),
            Scalar::F64 => num!(f64, 8),
        }
    }
}

/// A PLY property: a scalar, or a list (count type, item type).
#[derive(Debug, Clone)]
struct Property {
    name: String,
    kind: Scalar,
    list_count: Option<Scalar>,
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Where a PLY body is read from: ASCII tokens or binary bytes.
enum Body<'a> {
    Ascii {
        tokens: Vec<&'a str>,
        pos: usize,
    },
    Binary {
        bytes: &'a [u8],
        pos: usize,
        big: bool,
    },
}

impl Body<'_> {
    fn value(&mut self, kind: Scalar, at: &str) -> Result<f64, ParseError> {
        match self {
            Body::Ascii { tokens, pos } => {
                let v = number(tokens.get(*pos).copied(), at, "value");
                *pos += 1;
                v
            }
            Body::Binary { bytes, pos, big } => {
                let end = *pos + kind.size();
                if end > bytes.len() {
                    return Err((at.into(), "file ends early (truncated binary PLY)".into()));
                }
                let v = kind.decode(&bytes[*pos..end], *big);
                *pos = end;
                Ok(v)
            }
        }
    }

    /// What is left to read: tokens (ASCII) or bytes (binary).
    fn remaining(&self) -> usize {
        match self {
            Body::Ascii { tokens, pos } => tokens.len().saturating_sub(*pos),
            Body::Binary { bytes, pos, .. } => bytes.len().saturating_sub(*pos),
        }
    }

    /// What one value of `kind` takes: a token or its size in bytes.
    fn cost(&self, kind: Scalar) -> usize {
        match self {
            Body::Ascii { .. } => 1,
            Body::Binary { .. } => kind.size(),
        }
    }

    /// What `unit` is counted in.
    fn unit(&self) -> &'static str {
        match self {
            Body::Ascii { .. } => "value(s)",
            Body::Binary { .. } => "byte(s)",
        }
    }

    /// Checks a count read from the file (a claim, not a size) against what is left: `count`
    /// items of at least `each` tokens or bytes must fit in the rest of the file.
    fn check_count(
        &self,
        count: usize,
        each: usize,
        at: &str,
        what: &str,
    ) -> Result<(), ParseError> {
        let remaining = self.remaining();
        if count.checked_mul(each).is_none_or(|need| need > remaining) {
            return Err((
                at.into(),
                format!(
                    "{what} declares {count} item(s) of at least {each} {unit} each, but only \
                     {remaining} {unit} remain in the file",
                    unit = self.unit()
                ),
            ));
        }
        Ok(())
    }
}

/// A list's length as read (any scalar type): a whole, non-negative number.
fn list_length(raw: f64, at: &str) -> Result<usize, ParseError> {
    if raw.fract() != 0.0 || !(0.0..=u32::MAX as f64).contains(&raw) {
        return Err((
            at.into(),
            format!("list length {raw:e} is not a count: expected a whole number from 0"),
        ));
    }
    Ok(raw as usize)
}

/// Parses PLY: the `vertex` element's `x`, `y`, `z` and the `face` element's
/// `vertex_indices` (or `vertex_index`) list; other elements and properties are skipped.
pub fn parse_ply(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let header_end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| ("header".to_string(), "no end_header line".to_string()))?;
    let header = text(&bytes[..header_end])?;
    let mut lines = header.lines();
    if lines.next().map(str::trim) != Some("ply") {
        return Err(("line 1".into(), "expected \"ply\"".into()));
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in lines.enumerate() {
        let at = format!("header line {}", n + 2);
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.as_slice() {
            ["format", f, _] => format = Some(f.to_string()),
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| (at.clone(), format!("element count {count:?}")))?,
                properties: Vec::new(),
            }),
            ["property", "list", c, i, name] => {
                let (Some(c), Some(i)) = (Scalar::parse(c), Scalar::parse(i)) else {
                    return Err((at, format!("unknown list types in {line:?}")));
                };
                let e = elements
                    .last_mut()
                    .ok_or_else(|| (at.clone(), "property before any element".into()))?;
                e.properties.push(Property {
                    name: name.to_string(),
                    kind: i,
                    list_count: Some(c),
                });
            }
            ["property", kind, name] => {
                let kind = Scalar::parse(kind)
                    .ok_or_else(|| (at.clone(), format!("unknown property type {kind:?}")))?;
                let e = elements
                    .last_mut()
                    .ok_or_else(|| (at.clone(), "property before any element".into()))?;
                e.properties.push(Property {
                    name: name.to_string(),
                    kind,
                    list_count: None,
                });
            }
            _ => {}
        }
    }
    // The body starts after the newline that ends the end_header line.
    let mut start = header_end + 10;
    while start < bytes.len() && bytes[start] != b'\n' {
        start += 1;
    }
    let rest = bytes.get(start + 1..).unwrap_or(&[]);
    let mut body = match format.as_deref() {
        Some("ascii") => Body::Ascii {
            tokens: text(rest)?.split_whitespace().collect(),
            pos: 0,
        },
        Some("binary_little_endian") => Body::Binary {
            bytes: rest,
            pos: 0,
            big: false,
        },
        Some("binary_big_endian") => Body::Binary {
            bytes: rest,
            pos: 0,
            big: true,
        },
        other => {
            return Err((
                "header".into(),
                format!(
                    "format {other:?}: expected ascii, binary_little_endian or \
                     binary_big_endian"
                ),
            ));
        }
    };
    let mut soup = PolygonSoup {
        objects: 1,
        ..Default::default()
    };
    for e in &elements {
        let xyz = ["x", "y", "z"].map(|c| e.properties.iter().position(|p| p.name == c));
        if e.name == "vertex" && xyz.iter().any(Option::is_none) {
            return Err(("header".into(), "vertex element without x, y and z".into()));
        }
        if e.properties.is_empty() {
            // Records without properties hold no data, whatever their count.
            continue;
        }
        let record: usize = e
            .properties
            .iter()
            .map(|p| body.cost(p.list_count.unwrap_or(p.kind)))
            .sum();
        body.check_count(e.count, record, "header", &format!("element {:?}", e.name))?;
        for r in 0..e.count {
            let at = format!("{} {}", e.name, r);
            let mut v = [0.0; 3];
            let mut polygon = None;
            for (k, p) in e.properties.iter().enumerate() {
                match p.list_count {
                    Some(c) => {
                        let len = list_length(body.value(c, &at)?, &at)?;
                        body.check_count(
                            len,
                            body.cost(p.kind),
                            &at,
                            &format!("list {:?}", p.name),
                        )?;
                        let mut items = Vec::with_capacity(len);
                        for _ in 0..len {
                            items.push(body.value(p.kind, &at)?);
                        }
                        if e.name == "face"
                            && (p.name == "vertex_indices" || p.name == "vertex_index")
                        {
                            polygon = Some(items);
                        }
                    }
                    None => {
                        let x = body.value(p.kind, &at)?;
                        if let Some(c) = xyz.iter().position(|&i| i == Some(k)) {
                            v[c] = x;
                        }
                    }
                }
            }
            if e.name == "vertex" {
                soup.positions.push(finite(v, &at)?);
            }
            if let Some(items) = polygon {
                let count = soup.positions.len();
                let mut corners = Vec::with_capacity(items.len());
                for i in items {
                    if i < 0.0 || i as usize >= count || i.fract() != 0.0 {
                        return Err((
                            at,
                            format!("vertex index {i} is out of range: {count} vertices"),
                        ));
                    }
                    corners.push(i as u32);
                }
                soup.push_polygon(corners, at)?;
            }
        }
    }
    Ok(soup)
}

/// Writes a mesh as OBJ text (positions with 6 decimals, 1-based triangle faces), the
/// format of the generated assets.
pub fn obj_text(vertices: &[[f64; 3]], triangles: &[[u32; 3]], comment: &str) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for line in comment.lines() {
        let _ = writeln!(s, "# {line}");
    }
    for v in vertices {
        let _ = writeln!(s, "v {:.6} {:.6} {:.6}", v[0], v[1], v[2]);
    }
    for t in triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}
