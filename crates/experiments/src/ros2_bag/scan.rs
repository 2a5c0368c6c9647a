//! Reading an MCAP file record by record, so that a damaged file is refused naming the
//! byte where it goes wrong: the framing (opcode, 8-byte length, body) is walked here, in
//! the file and in each chunk, each record parsed by the `mcap` crate; a chunk is
//! decompressed whole (its size bounded) and its CRC checked before any record in it is
//! read, so no damaged length reaches an allocation.

use mcap::records::Record;
use std::collections::BTreeMap;
use std::path::Path;
use whisker_scenario::{Error, Result};

/// MCAP's magic, at both ends of a file.
const MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// The largest chunk this reader decompresses (the writer's chunks are ~1 MB).
const MAX_CHUNK: u64 = 1 << 30;

/// A channel as the file declares it.
pub struct Channel {
    pub topic: String,
    pub metadata: BTreeMap<String, String>,
}

/// One message: its channel, sequence number, bytes, and the byte of the file where its
/// record (or the chunk holding it) starts.
pub struct Message {
    pub channel: u16,
    pub sequence: u32,
    pub data: Vec<u8>,
    pub offset: u64,
}

/// What a file holds, in file order.
#[derive(Default)]
pub struct Contents {
    pub channels: BTreeMap<u16, Channel>,
    pub messages: Vec<Message>,
    /// Attachments: (name, bytes).
    pub attachments: Vec<(String, Vec<u8>)>,
}

/// The records framed in `buf` from `at`: (offset, opcode, body) each, until `stop` says
/// a record ends the sequence or the buffer ends; an error names the offset.
fn frames(
    buf: &[u8],
    mut at: usize,
    mut each: impl FnMut(usize, u8, &[u8]) -> std::result::Result<bool, String>,
) -> std::result::Result<usize, (usize, String)> {
    while at < buf.len() {
        let Some(head) = buf.get(at..at + 9) else {
            return Err((
                at,
                format!("{} bytes left: a record header needs 9", buf.len() - at),
            ));
        };
        let op = head[0];
        let len = u64::from_le_bytes(head[1..9].try_into().expect("8 bytes"));
        let body_at = at + 9;
        let Some(body) = usize::try_from(len)
            .ok()
            .and_then(|n| buf.get(body_at..body_at.checked_add(n)?))
        else {
            return Err((
                at,
                format!(
                    "a record (opcode 0x{op:02x}) of {len} bytes runs past the end at byte {}: \
                     truncated",
                    buf.len()
                ),
            ));
        };
        let stop = each(at, op, body).map_err(|m| (at, m))?;
        at = body_at + body.len();
        if stop {
            return Ok(at);
        }
    }
    Ok(at)
}

/// Parses one record; a parser panic becomes an error.
fn parse(op: u8, body: &[u8]) -> std::result::Result<Record<'_>, String> {
    std::panic::catch_unwind(|| mcap::parse_record(op, body))
        .map_err(|_| format!("record (opcode 0x{op:02x}) cannot be parsed"))?
        .map_err(|e| format!("record (opcode 0x{op:02x}): {e}"))
}

/// A chunk's records, decompressed and CRC-checked first.
fn chunk(header: &mcap::records::ChunkHeader, data: &[u8]) -> std::result::Result<Vec<u8>, String> {
    if header.uncompressed_size > MAX_CHUNK {
        return Err(format!(
            "chunk of {} bytes uncompressed: larger than this reader's {MAX_CHUNK}",
            header.uncompressed_size
        ));
    }
    let plain = match header.compression.as_str() {
        "" => data.to_vec(),
        "zstd" => zstd::bulk::decompress(data, header.uncompressed_size as usize)
            .map_err(|e| format!("chunk: zstd: {e}"))?,
        other => {
            return Err(format!(
                "chunk compression {other:?}: this reader reads zstd"
            ));
        }
    };
    if plain.len() as u64 != header.uncompressed_size {
        return Err(format!(
            "chunk: {} bytes decompressed, its header says {}",
            plain.len(),
            header.uncompressed_size
        ));
    }
    let crc = crc32fast::hash(&plain);
    if header.uncompressed_crc != 0 && crc != header.uncompressed_crc {
        return Err(format!(
            "chunk: CRC {crc:08x}, its header says {:08x}",
            header.uncompressed_crc
        ));
    }
    Ok(plain)
}

/// Reads `path` whole; exit 2 naming the byte for a file that is not MCAP, is truncated
/// or corrupt.
pub fn read(path: &Path) -> Result<Contents> {
    let buf = std::fs::read(path)
        .map_err(|e| Error::Input(format!("{}: cannot read: {e}", path.display())))?;
    let bad = |offset: usize, m: String| {
        Error::Input(format!(
            "{}: byte {offset}: {m} (not a complete MCAP file written by `whisker export`?)",
            path.display()
        ))
    };
    if !buf.starts_with(MAGIC) {
        return Err(bad(0, "expected the MCAP magic \\x89MCAP0\\r\\n".into()));
    }
    let mut schemas: BTreeMap<u16, String> = BTreeMap::new();
    let mut out = Contents::default();
    // The summary section (after Data End) repeats what the data section holds: only its
    // framing is read.
    let mut summary = false;
    let mut footer = false;
    let end = frames(&buf, MAGIC.len(), |at, op, body| {
        match parse(op, body)? {
            Record::Footer(_) => {
                footer = true;
                return Ok(true);
            }
            Record::DataEnd(_) => summary = true,
            _ if summary => {}
            Record::Chunk { header, data } => {
                let plain = chunk(&header, &data)?;
                frames(&plain, 0, |_, op, body| {
                    take(parse(op, body)?, at as u64, &mut schemas, &mut out)?;
                    Ok(false)
                })
                .map_err(|(inner, m)| format!("chunk, its byte {inner}: {m}"))?;
            }
            other => take(other, at as u64, &mut schemas, &mut out)?,
        }
        Ok(false)
    })
    .map_err(|(at, m)| bad(at, m))?;
    if !footer {
        return Err(bad(
            end,
            format!(
                "the file ends ({} bytes) before its footer: truncated",
                buf.len()
            ),
        ));
    }
    if buf.get(end..) != Some(MAGIC) {
        return Err(bad(
            end,
            "expected the closing MCAP magic after the footer".into(),
        ));
    }
    Ok(out)
}

/// Keeps what the bag needs of one record.
fn take(
    record: Record,
    offset: u64,
    schemas: &mut BTreeMap<u16, String>,
    out: &mut Contents,
) -> std::result::Result<(), String> {
    match record {
        Record::Schema { header, .. } => {
            schemas.insert(header.id, header.name);
        }
        Record::Channel(c) => {
            if c.schema_id != 0 && !schemas.contains_key(&c.schema_id) {
                return Err(format!(
                    "channel {} names unknown schema {}",
                    c.topic, c.schema_id
                ));
            }
            out.channels.insert(
                c.id,
                Channel {
                    topic: c.topic,
                    metadata: c.metadata,
                },
            );
        }
        Record::Message { header, data } => {
            if !out.channels.contains_key(&header.channel_id) {
                return Err(format!(
                    "a message on channel {} before its channel record",
                    header.channel_id
                ));
            }
            out.messages.push(Message {
                channel: header.channel_id,
                sequence: header.sequence,
                data: data.into_owned(),
                offset,
            });
        }
        Record::Attachment { header, data, .. } => {
            out.attachments.push((header.name, data.into_owned()));
        }
        _ => {}
    }
    Ok(())
}
