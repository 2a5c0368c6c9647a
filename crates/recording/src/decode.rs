//! Reading a recording back with Rerun's own decoder: the chunks of its recording store
//! (the blueprint store is skipped), what each entity holds, and the values of the
//! archetypes the recordings use. The tests check recordings through this; it is also a
//! way to get numbers out of a `.rrd` without the viewer.

use super::SIM_TIME;
pub use rerun::log::Chunk;
use rerun::log::LogMsg;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// An `.rrd` that could not be read: the file and what the decoder said.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError {
    pub path: std::path::PathBuf,
    pub message: String,
}

impl std::fmt::Display for DecodeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for DecodeError {}

/// Where two recordings' contents first differ (chunk, entity, component).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference(pub String);

impl std::fmt::Display for Difference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Difference {}

/// The recording store's chunks of the `.rrd` at `path`, and its recording id.
pub fn read(path: &Path) -> Result<(String, Vec<Chunk>), DecodeError> {
    use rerun::external::re_log_encoding::DecoderApp;
    let fail = |e: &dyn std::fmt::Display| DecodeError {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(|e| fail(&e))?;
    let mut chunks = Vec::new();
    let mut id = String::new();
    for msg in DecoderApp::decode_eager(std::io::BufReader::new(file)).map_err(|e| fail(&e))? {
        match msg.map_err(|e| fail(&e))? {
            LogMsg::ArrowMsg(store, arrow) if store.kind() == rerun::StoreKind::Recording => {
                id = store.recording_id().to_string();
                chunks.push(Chunk::from_arrow_msg(&arrow).map_err(|e| fail(&e))?);
            }
            _ => {}
        }
    }
    Ok((id, chunks))
}

/// What one entity holds.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Entity {
    /// Its components, as `Archetype:field` (e.g. `Points3D:positions`).
    pub components: BTreeSet<String>,
    /// Rows with time, and rows without (static).
    pub rows: usize,
    pub static_rows: usize,
    /// The timelines of its temporal rows.
    pub timelines: BTreeSet<String>,
}

/// Every entity path (`/world/…`) with what it holds.
pub fn entities(chunks: &[Chunk]) -> BTreeMap<String, Entity> {
    let mut out: BTreeMap<String, Entity> = BTreeMap::new();
    for c in chunks {
        let e = out.entry(c.entity_path().to_string()).or_default();
        for id in c.components_identifiers() {
            e.components.insert(id.to_string());
        }
        if c.is_static() {
            e.static_rows += c.num_rows();
        } else {
            e.rows += c.num_rows();
            e.timelines
                .extend(c.timelines().keys().map(|t| t.as_str().to_string()));
        }
    }
    out
}

/// The chunks of `entity` holding `component`, each with its rows' times on `timeline`
/// (raw: ns for `sim_time`, the index for a sequence; static rows at `i64::MIN`) and the
/// component's identifier.
fn columns<'a>(
    chunks: &'a [Chunk],
    entity: &'a str,
    component: &'a str,
    timeline: &'a str,
) -> impl Iterator<Item = (&'a Chunk, Vec<i64>, rerun::ComponentIdentifier)> + 'a {
    chunks
        .iter()
        .filter(move |c| c.entity_path().to_string() == entity)
        .filter_map(move |c| {
            let id = c
                .components_identifiers()
                .find(|i| i.as_str() == component)?;
            let times = if c.is_static() {
                vec![i64::MIN; c.num_rows()]
            } else {
                c.timelines()
                    .iter()
                    .find(|(name, _)| name.as_str() == timeline)?
                    .1
                    .times_raw()
                    .to_vec()
            };
            Some((c, times, id))
        })
}

/// Each row of `component` at `entity` with its time on `timeline` ([`columns`]), sorted by
/// time; `rows_of` gives a chunk's rows.
fn gather<V>(
    chunks: &[Chunk],
    entity: &str,
    component: &str,
    timeline: &str,
    mut rows_of: impl FnMut(&Chunk, rerun::ComponentIdentifier) -> Vec<V>,
) -> Vec<(i64, V)> {
    let mut out = Vec::new();
    for (c, times, id) in columns(chunks, entity, component, timeline) {
        out.extend(times.into_iter().zip(rows_of(c, id)));
    }
    out.sort_by_key(|(t, _)| *t);
    out
}

/// The rows of `component` at `entity` with their time on `timeline` (see [`columns`]),
/// sorted by time, each row's values of native type `T` (`f64` for scalars, `[f32; 3]` for
/// 3-D points …).
pub fn rows<T>(
    chunks: &[Chunk],
    entity: &str,
    component: &str,
    timeline: &str,
) -> Vec<(i64, Vec<T>)>
where
    T: Clone
        + for<'a> rerun::external::re_chunk_store::external::re_chunk::ChunkComponentSlicer<
            Item<'a> = &'a [T],
        > + 'static,
{
    gather(chunks, entity, component, timeline, |c, id| {
        c.iter_slices::<T>(id).map(<[T]>::to_vec).collect()
    })
}

/// [`rows`] of a string component (labels, graph node ids).
pub fn strings(
    chunks: &[Chunk],
    entity: &str,
    component: &str,
    timeline: &str,
) -> Vec<(i64, Vec<String>)> {
    gather(chunks, entity, component, timeline, |c, id| {
        c.iter_slices::<String>(id)
            .map(|v| v.iter().map(|s| s.to_string()).collect())
            .collect()
    })
}

/// [`rows`] of a `LineStrips3D` at `entity`: each row's strips, each a list of points.
pub fn strips(chunks: &[Chunk], entity: &str, timeline: &str) -> Vec<(i64, Vec<Vec<[f32; 3]>>)> {
    gather(chunks, entity, "LineStrips3D:strips", timeline, |c, id| {
        c.iter_slices::<&[[f32; 3]]>(id)
            .map(|row| row.iter().map(|s| s.to_vec()).collect())
            .collect()
    })
}

/// [`rows`] of a binary component (an image's `Image:buffer`): each row's bytes.
pub fn blobs(
    chunks: &[Chunk],
    entity: &str,
    component: &str,
    timeline: &str,
) -> Vec<(i64, Vec<u8>)> {
    gather(chunks, entity, component, timeline, |c, id| {
        c.iter_slices::<&[u8]>(id)
            .map(|buffers| buffers.iter().flat_map(|b| b.iter().copied()).collect())
            .collect()
    })
}

/// The scalar rows of `entity` on `sim_time`: (time s, values).
pub fn scalars(chunks: &[Chunk], entity: &str) -> Vec<(f64, Vec<f64>)> {
    rows::<f64>(chunks, entity, "Scalars:scalars", SIM_TIME)
        .into_iter()
        .map(|(t, v)| (t as f64 * 1e-9, v))
        .collect()
}

/// The 3-D point rows of `entity` on `sim_time`: (time s, points).
pub fn points(chunks: &[Chunk], entity: &str) -> Vec<(f64, Vec<[f32; 3]>)> {
    rows::<[f32; 3]>(chunks, entity, "Points3D:positions", SIM_TIME)
        .into_iter()
        .map(|(t, v)| (t as f64 * 1e-9, v))
        .collect()
}

/// Whether two recordings hold the same content: the same chunks, entity by entity and
/// in order, with the same timelines, times and component values bit for bit (row and
/// chunk ids ignored; a NaN equals the same NaN, which Rerun's own `Chunk::ensure_similar`
/// does not allow). The recording's name (`/__properties`) is its identity, not content,
/// and is left out. Returns the first difference.
pub fn same_content(a: &[Chunk], b: &[Chunk]) -> Result<(), Difference> {
    use rerun::external::arrow::array::Array;
    // Chunks of one entity in the order of their timelines, first times and components:
    // a flush writes the chunks of different timeline or component sets in no fixed order.
    fn sorted(v: &[Chunk]) -> Vec<&Chunk> {
        let mut s: Vec<&Chunk> = v
            .iter()
            .filter(|c| c.entity_path().to_string() != "/__properties")
            .collect();
        s.sort_by_cached_key(|c| {
            let mut times: Vec<(String, i64)> = c
                .timelines()
                .iter()
                .map(|(name, t)| {
                    (
                        name.as_str().to_string(),
                        t.times_raw().first().copied().unwrap_or(0),
                    )
                })
                .collect();
            times.sort();
            let mut components: Vec<String> =
                c.components_identifiers().map(|i| i.to_string()).collect();
            components.sort();
            (
                c.entity_path().to_string(),
                c.is_static(),
                times,
                components,
            )
        });
        s
    }
    let (a, b) = (sorted(a), sorted(b));
    if a.len() != b.len() {
        return Err(Difference(format!(
            "{} chunks against {}",
            a.len(),
            b.len()
        )));
    }
    for (x, y) in a.iter().zip(&b) {
        let at = || format!("{} (static: {})", x.entity_path(), x.is_static());
        if x.entity_path() != y.entity_path() || x.is_static() != y.is_static() {
            return Err(Difference(format!("{} against {}", at(), y.entity_path())));
        }
        if x.num_rows() != y.num_rows() {
            return Err(Difference(format!(
                "{}: {} rows against {}",
                at(),
                x.num_rows(),
                y.num_rows()
            )));
        }
        let times = |c: &Chunk| -> BTreeMap<String, Vec<i64>> {
            c.timelines()
                .iter()
                .map(|(n, t)| (n.as_str().to_string(), t.times_raw().to_vec()))
                .collect()
        };
        if times(x) != times(y) {
            return Err(Difference(format!("{}: different times", at())));
        }
        for (id, column) in x.components().iter() {
            let Some(other) = y.components().get(*id) else {
                return Err(Difference(format!(
                    "{}: {id} missing from the second",
                    at()
                )));
            };
            if column.descriptor != other.descriptor
                || column.list_array.to_data() != other.list_array.to_data()
            {
                return Err(Difference(format!("{}: component {id} differs", at())));
            }
        }
        if x.components().len() != y.components().len() {
            return Err(Difference(format!("{}: different components", at())));
        }
    }
    Ok(())
}
