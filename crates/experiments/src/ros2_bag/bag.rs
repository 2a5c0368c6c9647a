//! The MCAP writer of an export: ROS 2 profile, zstd chunks (one compression thread, so
//! the same bytes on every machine), schemas and channels added once by name.

use super::schema::Schema;
use mcap::records::MessageHeader;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;
use whisker_scenario::{Error, Result};

pub struct Bag {
    writer: mcap::Writer<BufWriter<std::fs::File>>,
    schemas: BTreeMap<(String, String), u16>,
    names: BTreeMap<String, String>,
    channels: std::collections::BTreeSet<u16>,
    /// Messages written.
    pub messages: u64,
    /// Attachments written.
    pub attachments: usize,
}

fn failure(e: mcap::McapError) -> Error {
    Error::Output(format!("cannot write the MCAP file: {e}"))
}

impl Bag {
    /// A new bag at `path` (created).
    pub fn create(path: &Path) -> Result<Self> {
        let out = std::fs::File::create(path).map_err(|e| Error::output(path, e))?;
        let writer = mcap::WriteOptions::new()
            .profile("ros2")
            .library(format!("whisker {}", env!("CARGO_PKG_VERSION")))
            .compression(Some(mcap::Compression::Zstd))
            .compression_threads(0)
            .create(BufWriter::new(out))
            .map_err(failure)?;
        Ok(Self {
            writer,
            schemas: BTreeMap::new(),
            names: BTreeMap::new(),
            channels: Default::default(),
            messages: 0,
            attachments: 0,
        })
    }

    /// A channel on `topic` of `schema` with `meta`; a type name already used with another
    /// definition is numbered (`ExploreRow2`).
    pub fn channel(
        &mut self,
        topic: &str,
        s: &Schema,
        meta: BTreeMap<String, String>,
    ) -> Result<u16> {
        let mut name = s.name.clone();
        let mut k = 2;
        while self.names.get(&name).is_some_and(|t| *t != s.text) {
            name = format!("{}{k}", s.name);
            k += 1;
        }
        self.names.insert(name.clone(), s.text.clone());
        let key = (name.clone(), s.text.clone());
        let schema = match self.schemas.get(&key) {
            Some(&id) => id,
            None => {
                let id = self
                    .writer
                    .add_schema(&name, "ros2msg", s.text.as_bytes())
                    .map_err(failure)?;
                self.schemas.insert(key, id);
                id
            }
        };
        let id = self
            .writer
            .add_channel(schema, topic, "cdr", &meta)
            .map_err(failure)?;
        self.channels.insert(id);
        Ok(id)
    }

    /// Topics so far.
    pub fn topics(&self) -> usize {
        self.channels.len()
    }

    /// A message on `channel`, its log and publish time the stamp (ns).
    pub fn write(&mut self, channel: u16, sequence: usize, stamp: u64, data: &[u8]) -> Result {
        let header = MessageHeader {
            channel_id: channel,
            sequence: sequence as u32,
            log_time: stamp,
            publish_time: stamp,
        };
        self.messages += 1;
        self.writer
            .write_to_known_channel(&header, data)
            .map_err(failure)
    }

    /// A file as an attachment named by its path, its media type by its extension.
    pub fn attach(&mut self, name: &str, data: &[u8]) -> Result {
        let media_type = match name.rsplit('.').next() {
            Some("json") => "application/json",
            Some("toml") => "application/toml",
            Some("csv") => "text/csv",
            Some("svg") => "image/svg+xml",
            Some("png") => "image/png",
            Some("txt") => "text/plain",
            _ => "application/octet-stream",
        };
        self.attachments += 1;
        self.writer
            .attach(&mcap::Attachment {
                log_time: 0,
                create_time: 0,
                name: name.into(),
                media_type: media_type.into(),
                data: std::borrow::Cow::Borrowed(data),
            })
            .map_err(failure)
    }

    /// A metadata record.
    pub fn metadata(&mut self, name: &str, metadata: BTreeMap<String, String>) -> Result {
        self.writer
            .write_metadata(&mcap::records::Metadata {
                name: name.into(),
                metadata,
            })
            .map_err(failure)
    }

    /// Writes the summary and footer and syncs the file to disk.
    pub fn finish(mut self, path: &Path) -> Result {
        self.writer.finish().map_err(failure)?;
        let file = self
            .writer
            .into_inner()
            .into_inner()
            .map_err(|e| Error::output(path, e.into_error()))?;
        file.sync_all().map_err(|e| Error::output(path, e))
    }
}
