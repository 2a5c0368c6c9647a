//! The PLY reader (Stanford polygon format, ASCII or binary in either byte order): the
//! `vertex` element's `x`, `y`, `z` and the `face` element's vertex-index lists. Every
//! count the file declares (element records, list lengths) is a claim checked against
//! what remains of the file before anything is allocated.

use super::soup::{ParseError, PolygonSoup, finite, number, text};

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
