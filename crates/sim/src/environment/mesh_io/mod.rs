//! Reading triangle-mesh files: Wavefront OBJ, STL (ASCII and binary) and PLY (ASCII and
//! binary, either byte order; in the `ply` submodule).
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

mod ply;
mod soup;

pub use ply::parse_ply;
pub use soup::{ParseError, PolygonSoup};
use soup::{finite, number, text};
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
    pub fn new(file: &Path, at: &str, message: impl std::fmt::Display) -> Self {
        Self {
            file: file.to_path_buf(),
            at: at.to_string(),
            message: message.to_string(),
        }
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
