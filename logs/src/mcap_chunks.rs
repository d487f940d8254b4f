//! The MCAP file's records, written here: the chunks are assembled in one
//! buffer and each message costs one record header and one copy.
//!
//! The `mcap` crate's writer takes messages one at a time through several
//! layers of `Write` (a counting CRC writer, a chunk sink, a cursor) and
//! keeps its per-channel message indexes and counts in ordered maps: on an
//! hour at 1 kHz (six messages a sample) that was about half of all the
//! instructions of an `--mcap` run, and its API has no way to hand it a
//! chunk built elsewhere. This writer lays the file out exactly as the
//! crate does with the options the simulation used (uncompressed chunks cut
//! at a target size, chunk and data-section CRCs left at 0 as MCAP allows,
//! the summary's CRC computed; schemas, channels, statistics, chunk and
//! metadata indexes, summary offsets): a test writes the same records
//! through both and compares the bytes, so every reader of the crate's
//! files reads these.
//!
//! Record layouts: the MCAP specification (mcap.dev/spec). Every integer is
//! little-endian; a string is a `u32` length and its bytes; a map is a
//! `u32` byte length and its entries.

use std::collections::BTreeMap;
use std::io::{self, Write};

/// The magic bytes at both ends of an MCAP file.
const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// Record opcodes.
mod op {
    pub const HEADER: u8 = 0x01;
    pub const FOOTER: u8 = 0x02;
    pub const SCHEMA: u8 = 0x03;
    pub const CHANNEL: u8 = 0x04;
    pub const MESSAGE: u8 = 0x05;
    pub const CHUNK: u8 = 0x06;
    pub const MESSAGE_INDEX: u8 = 0x07;
    pub const CHUNK_INDEX: u8 = 0x08;
    pub const STATISTICS: u8 = 0x0B;
    pub const METADATA: u8 = 0x0C;
    pub const METADATA_INDEX: u8 = 0x0D;
    pub const SUMMARY_OFFSET: u8 = 0x0E;
    pub const DATA_END: u8 = 0x0F;
}

fn put_u16(b: &mut Vec<u8>, v: u16) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_u32(b: &mut Vec<u8>, v: u32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_u64(b: &mut Vec<u8>, v: u64) {
    b.extend_from_slice(&v.to_le_bytes());
}

/// A length as the `u32` a string, byte array or map is prefixed with.
fn len32(n: usize) -> io::Result<u32> {
    u32::try_from(n)
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "an MCAP field over 4 GiB"))
}

fn put_str(b: &mut Vec<u8>, s: &[u8]) -> io::Result<()> {
    put_u32(b, len32(s.len())?);
    b.extend_from_slice(s);
    Ok(())
}

fn put_string_map(b: &mut Vec<u8>, m: &BTreeMap<String, String>) -> io::Result<()> {
    let bytes: usize = m.iter().map(|(k, v)| 8 + k.len() + v.len()).sum();
    put_u32(b, len32(bytes)?);
    for (k, v) in m {
        put_str(b, k.as_bytes())?;
        put_str(b, v.as_bytes())?;
    }
    Ok(())
}

/// A `u16 → u64` map (message counts, message index offsets): 10 bytes an
/// entry.
fn put_u16_u64_map(b: &mut Vec<u8>, m: &[(u16, u64)]) -> io::Result<()> {
    put_u32(b, len32(10 * m.len())?);
    for &(k, v) in m {
        put_u16(b, k);
        put_u64(b, v);
    }
    Ok(())
}

/// Appends a record: its opcode, its length, then what `body` appends.
fn record(
    b: &mut Vec<u8>,
    opcode: u8,
    body: impl FnOnce(&mut Vec<u8>) -> io::Result<()>,
) -> io::Result<()> {
    b.push(opcode);
    let at = b.len();
    put_u64(b, 0);
    body(b)?;
    let len = (b.len() - at - 8) as u64;
    b[at..at + 8].copy_from_slice(&len.to_le_bytes());
    Ok(())
}

struct Schema {
    id: u16,
    name: String,
    encoding: String,
    data: Vec<u8>,
}

struct Channel {
    id: u16,
    schema_id: u16,
    topic: String,
    encoding: String,
    metadata: BTreeMap<String, String>,
}

impl Schema {
    fn write(&self, b: &mut Vec<u8>) -> io::Result<()> {
        record(b, op::SCHEMA, |b| {
            put_u16(b, self.id);
            put_str(b, self.name.as_bytes())?;
            put_str(b, self.encoding.as_bytes())?;
            put_str(b, &self.data)
        })
    }
}

impl Channel {
    fn write(&self, b: &mut Vec<u8>) -> io::Result<()> {
        record(b, op::CHANNEL, |b| {
            put_u16(b, self.id);
            put_u16(b, self.schema_id);
            put_str(b, self.topic.as_bytes())?;
            put_str(b, self.encoding.as_bytes())?;
            put_string_map(b, &self.metadata)
        })
    }
}

/// What the summary says of one chunk.
struct ChunkIndex {
    bounds: (u64, u64),
    offset: u64,
    length: u64,
    message_index_offsets: Vec<(u16, u64)>,
    message_index_length: u64,
    size: u64,
}

/// The chunk being assembled.
#[derive(Default)]
struct OpenChunk {
    /// Where its record starts in the file.
    offset: u64,
    records: Vec<u8>,
    bounds: Option<(u64, u64)>,
    /// `(log time, offset in records)` of each message, by channel id.
    index: Vec<Vec<(u64, u64)>>,
}

fn widen(bounds: Option<(u64, u64)>, t: u64) -> Option<(u64, u64)> {
    Some(bounds.map_or((t, t), |(a, b)| (a.min(t), b.max(t))))
}

/// An MCAP file being written to `W`, which is only ever appended to (a
/// pipe works like a file).
pub(super) struct ChunkedMcap<W: Write> {
    out: W,
    /// Bytes written to `out` so far: the offset of the next record.
    pos: u64,
    /// A chunk is closed before a message once its records exceed this.
    target: usize,
    chunk: Option<OpenChunk>,
    /// The records' buffer of the last chunk closed, reused.
    spare: Vec<u8>,
    bounds: Option<(u64, u64)>,
    /// Messages by channel id.
    counts: Vec<u64>,
    schemas: Vec<Schema>,
    channels: Vec<Channel>,
    chunk_indexes: Vec<ChunkIndex>,
    /// `(offset, length, name)` of each metadata record.
    metadata: Vec<(u64, u64, String)>,
    scratch: Vec<u8>,
}

impl<W: Write> ChunkedMcap<W> {
    /// Writes the magic and the header (`library` names the writer).
    pub(super) fn create(out: W, library: &str, chunk_target: usize) -> io::Result<Self> {
        let mut w = Self {
            out,
            pos: 0,
            target: chunk_target,
            chunk: None,
            spare: Vec::new(),
            bounds: None,
            counts: Vec::new(),
            schemas: Vec::new(),
            channels: Vec::new(),
            chunk_indexes: Vec::new(),
            metadata: Vec::new(),
            scratch: Vec::new(),
        };
        let mut b = MAGIC.to_vec();
        record(&mut b, op::HEADER, |b| {
            put_str(b, b"")?;
            put_str(b, library.as_bytes())
        })?;
        w.emit(&b)?;
        Ok(w)
    }

    fn emit(&mut self, b: &[u8]) -> io::Result<()> {
        self.out.write_all(b)?;
        self.pos += b.len() as u64;
        Ok(())
    }

    fn open_chunk(&mut self) -> &mut OpenChunk {
        let (pos, spare) = (self.pos, &mut self.spare);
        self.chunk.get_or_insert_with(|| OpenChunk {
            offset: pos,
            records: std::mem::take(spare),
            ..Default::default()
        })
    }

    /// Adds a schema (in the open chunk, and in the summary), returning its
    /// id; the same content again gets the same id.
    pub(super) fn add_schema(
        &mut self,
        name: &str,
        encoding: &str,
        data: &[u8],
    ) -> io::Result<u16> {
        if let Some(s) = self
            .schemas
            .iter()
            .find(|s| s.name == name && s.encoding == encoding && s.data == data)
        {
            return Ok(s.id);
        }
        let s = Schema {
            id: u16::try_from(self.schemas.len() + 1).map_err(|_| too_many("schemas"))?,
            name: name.into(),
            encoding: encoding.into(),
            data: data.into(),
        };
        s.write(&mut self.open_chunk().records)?;
        let id = s.id;
        self.schemas.push(s);
        Ok(id)
    }

    /// Adds a channel (in the open chunk, and in the summary), returning
    /// its id; the same content again gets the same id.
    pub(super) fn add_channel(
        &mut self,
        schema_id: u16,
        topic: &str,
        encoding: &str,
        metadata: &BTreeMap<String, String>,
    ) -> io::Result<u16> {
        if let Some(c) = self.channels.iter().find(|c| {
            c.schema_id == schema_id
                && c.topic == topic
                && c.encoding == encoding
                && &c.metadata == metadata
        }) {
            return Ok(c.id);
        }
        if schema_id != 0 && usize::from(schema_id) > self.schemas.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("channel {topic}: no schema {schema_id}"),
            ));
        }
        let c = Channel {
            id: u16::try_from(self.channels.len() + 1).map_err(|_| too_many("channels"))?,
            schema_id,
            topic: topic.into(),
            encoding: encoding.into(),
            metadata: metadata.clone(),
        };
        c.write(&mut self.open_chunk().records)?;
        let id = c.id;
        self.channels.push(c);
        self.counts.push(0);
        Ok(id)
    }

    /// Writes a message on channel `channel` (an id [`Self::add_channel`]
    /// returned), logged and published at `time` ns.
    pub(super) fn message(
        &mut self,
        channel: u16,
        sequence: u32,
        time: u64,
        data: &[u8],
    ) -> io::Result<()> {
        let k = usize::from(channel).wrapping_sub(1);
        if k >= self.channels.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("no channel {channel}"),
            ));
        }
        if self
            .chunk
            .as_ref()
            .is_some_and(|c| c.records.len() > self.target)
        {
            self.close_chunk()?;
        }
        self.bounds = widen(self.bounds, time);
        self.counts[k] += 1;
        let c = self.open_chunk();
        c.bounds = widen(c.bounds, time);
        if c.index.len() <= k {
            c.index.resize_with(k + 1, Vec::new);
        }
        c.index[k].push((time, c.records.len() as u64));
        let r = &mut c.records;
        r.push(op::MESSAGE);
        put_u64(r, 2 + 4 + 8 + 8 + data.len() as u64);
        put_u16(r, channel);
        put_u32(r, sequence);
        put_u64(r, time);
        put_u64(r, time);
        r.extend_from_slice(data);
        Ok(())
    }

    /// Writes the open chunk, then its message indexes.
    fn close_chunk(&mut self) -> io::Result<()> {
        let Some(mut c) = self.chunk.take() else {
            return Ok(());
        };
        let size = c.records.len() as u64;
        let bounds = c.bounds.unwrap_or((0, 0));
        let mut h = std::mem::take(&mut self.scratch);
        h.clear();
        h.push(op::CHUNK);
        // Start and end times, sizes, CRC (0: not computed), compression
        // (none), then the records as a byte array.
        put_u64(&mut h, 8 + 8 + 8 + 4 + 4 + 8 + size);
        put_u64(&mut h, bounds.0);
        put_u64(&mut h, bounds.1);
        put_u64(&mut h, size);
        put_u32(&mut h, 0);
        put_str(&mut h, b"")?;
        put_u64(&mut h, size);
        let length = h.len() as u64 + size;
        self.emit(&h)?;
        self.emit(&c.records)?;
        let start = self.pos;
        let mut offsets = Vec::new();
        h.clear();
        for (k, entries) in c.index.iter().enumerate().filter(|(_, e)| !e.is_empty()) {
            let id = (k + 1) as u16;
            offsets.push((id, start + h.len() as u64));
            record(&mut h, op::MESSAGE_INDEX, |b| {
                put_u16(b, id);
                put_u32(b, len32(16 * entries.len())?);
                for &(t, o) in entries {
                    put_u64(b, t);
                    put_u64(b, o);
                }
                Ok(())
            })?;
        }
        self.emit(&h)?;
        self.chunk_indexes.push(ChunkIndex {
            bounds,
            offset: c.offset,
            length,
            message_index_offsets: offsets,
            message_index_length: h.len() as u64,
            size,
        });
        self.scratch = h;
        c.records.clear();
        self.spare = c.records;
        Ok(())
    }

    /// Closes the open chunk and writes a metadata record.
    pub(super) fn metadata(
        &mut self,
        name: &str,
        entries: &BTreeMap<String, String>,
    ) -> io::Result<()> {
        self.close_chunk()?;
        let mut b = Vec::new();
        record(&mut b, op::METADATA, |b| {
            put_str(b, name.as_bytes())?;
            put_string_map(b, entries)
        })?;
        self.metadata.push((self.pos, b.len() as u64, name.into()));
        self.emit(&b)
    }

    /// Closes the open chunk, writes the data section's end, the summary,
    /// the footer and the closing magic, flushes, and returns the output.
    pub(super) fn finish(mut self) -> io::Result<W> {
        self.close_chunk()?;
        let mut b = Vec::new();
        record(&mut b, op::DATA_END, |b| {
            put_u32(b, 0);
            Ok(())
        })?;
        self.emit(&b)?;
        let summary_start = self.pos;
        let (mut s, offsets_start) = self.summary()?;
        // The footer's CRC covers the summary and the footer's fields
        // before it.
        s.push(op::FOOTER);
        put_u64(&mut s, 8 + 8 + 4);
        put_u64(&mut s, if offsets_start > 0 { summary_start } else { 0 });
        put_u64(&mut s, summary_start + offsets_start);
        let crc = crc32fast::hash(&s);
        put_u32(&mut s, crc);
        s.extend_from_slice(MAGIC);
        self.emit(&s)?;
        self.out.flush()?;
        Ok(self.out)
    }

    /// The summary section's groups and their offsets, and where the
    /// offsets start within it.
    fn summary(&self) -> io::Result<(Vec<u8>, u64)> {
        let base = self.pos;
        let mut s = Vec::new();
        let mut groups: Vec<(u8, u64, u64)> = Vec::new();
        let mut group = |s: &mut Vec<u8>, opcode: u8, start: usize| {
            if s.len() > start {
                groups.push((opcode, base + start as u64, (s.len() - start) as u64));
            }
        };
        let at = s.len();
        for x in &self.schemas {
            x.write(&mut s)?;
        }
        group(&mut s, op::SCHEMA, at);
        let at = s.len();
        for x in &self.channels {
            x.write(&mut s)?;
        }
        group(&mut s, op::CHANNEL, at);
        let at = s.len();
        self.statistics(&mut s)?;
        group(&mut s, op::STATISTICS, at);
        let at = s.len();
        for c in &self.chunk_indexes {
            record(&mut s, op::CHUNK_INDEX, |b| {
                put_u64(b, c.bounds.0);
                put_u64(b, c.bounds.1);
                put_u64(b, c.offset);
                put_u64(b, c.length);
                put_u16_u64_map(b, &c.message_index_offsets)?;
                put_u64(b, c.message_index_length);
                put_str(b, b"")?;
                put_u64(b, c.size);
                put_u64(b, c.size);
                Ok(())
            })?;
        }
        group(&mut s, op::CHUNK_INDEX, at);
        let at = s.len();
        for (offset, length, name) in &self.metadata {
            record(&mut s, op::METADATA_INDEX, |b| {
                put_u64(b, *offset);
                put_u64(b, *length);
                put_str(b, name.as_bytes())
            })?;
        }
        group(&mut s, op::METADATA_INDEX, at);
        let offsets_start = s.len() as u64;
        for (opcode, start, length) in groups {
            record(&mut s, op::SUMMARY_OFFSET, |b| {
                b.push(opcode);
                put_u64(b, start);
                put_u64(b, length);
                Ok(())
            })?;
        }
        Ok((s, offsets_start))
    }

    fn statistics(&self, s: &mut Vec<u8>) -> io::Result<()> {
        let bounds = self.bounds.unwrap_or((0, 0));
        let counts: Vec<(u16, u64)> = (1u16..)
            .zip(&self.counts)
            .filter(|(_, n)| **n > 0)
            .map(|(id, n)| (id, *n))
            .collect();
        record(s, op::STATISTICS, |b| {
            put_u64(b, self.counts.iter().sum());
            put_u16(b, self.schemas.len() as u16);
            put_u32(b, self.channels.len() as u32);
            put_u32(b, 0); // attachments
            put_u32(b, self.metadata.len() as u32);
            put_u32(b, self.chunk_indexes.len() as u32);
            put_u64(b, bounds.0);
            put_u64(b, bounds.1);
            put_u16_u64_map(b, &counts)
        })
    }
}

fn too_many(what: &str) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("more than 65 535 {what}"),
    )
}

#[cfg(test)]
mod tests {
    //! The same records through this writer and through the `mcap` crate's
    //! (with the options the simulation used before this writer): the same
    //! bytes.

    use super::*;

    const LIB: &str = "test-library/1";

    enum Op {
        Schema(&'static str, Vec<u8>),
        Channel(u16, &'static str, BTreeMap<String, String>),
        Message(u16, u32, u64, Vec<u8>),
        Metadata(&'static str, BTreeMap<String, String>),
    }

    fn map(kv: &[(&str, &str)]) -> BTreeMap<String, String> {
        kv.iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    /// What a run asks of a writer, for both writers.
    trait Records {
        fn schema(&mut self, name: &str, data: &[u8]);
        fn channel(&mut self, schema: u16, topic: &str, meta: &BTreeMap<String, String>);
        fn message(&mut self, channel: u16, sequence: u32, t: u64, data: &[u8]);
        fn metadata(&mut self, name: &str, entries: &BTreeMap<String, String>);

        fn replay(&mut self, ops: &[Op]) {
            for op in ops {
                match op {
                    Op::Schema(name, data) => self.schema(name, data),
                    Op::Channel(schema, topic, meta) => self.channel(*schema, topic, meta),
                    Op::Message(channel, sequence, t, data) => {
                        self.message(*channel, *sequence, *t, data)
                    }
                    Op::Metadata(name, entries) => self.metadata(name, entries),
                }
            }
        }
    }

    type Crate = mcap::Writer<mcap::write::NoSeek<Vec<u8>>>;

    impl Records for Crate {
        fn schema(&mut self, name: &str, data: &[u8]) {
            self.add_schema(name, "protobuf", data).unwrap();
        }
        fn channel(&mut self, schema: u16, topic: &str, meta: &BTreeMap<String, String>) {
            self.add_channel(schema, topic, "protobuf", meta).unwrap();
        }
        fn message(&mut self, channel_id: u16, sequence: u32, t: u64, data: &[u8]) {
            let header = mcap::records::MessageHeader {
                channel_id,
                sequence,
                log_time: t,
                publish_time: t,
            };
            self.write_to_known_channel(&header, data).unwrap();
        }
        fn metadata(&mut self, name: &str, entries: &BTreeMap<String, String>) {
            let m = mcap::records::Metadata {
                name: name.to_string(),
                metadata: entries.clone(),
            };
            self.write_metadata(&m).unwrap();
        }
    }

    impl Records for ChunkedMcap<Vec<u8>> {
        fn schema(&mut self, name: &str, data: &[u8]) {
            self.add_schema(name, "protobuf", data).unwrap();
        }
        fn channel(&mut self, schema: u16, topic: &str, meta: &BTreeMap<String, String>) {
            self.add_channel(schema, topic, "protobuf", meta).unwrap();
        }
        fn message(&mut self, channel: u16, sequence: u32, t: u64, data: &[u8]) {
            ChunkedMcap::message(self, channel, sequence, t, data).unwrap();
        }
        fn metadata(&mut self, name: &str, entries: &BTreeMap<String, String>) {
            ChunkedMcap::metadata(self, name, entries).unwrap();
        }
    }

    fn theirs(ops: &[Op], target: usize) -> Vec<u8> {
        let mut w = mcap::WriteOptions::new()
            .compression(None)
            .chunk_size(Some(target as u64))
            .calculate_chunk_crcs(false)
            .calculate_data_section_crc(false)
            .profile("")
            .library(LIB)
            .disable_seeking(true)
            .create(mcap::write::NoSeek::new(Vec::new()))
            .unwrap();
        w.replay(ops);
        w.finish().unwrap();
        w.into_inner().into_inner()
    }

    fn ours(ops: &[Op], target: usize) -> Vec<u8> {
        let mut w = ChunkedMcap::create(Vec::new(), LIB, target).unwrap();
        w.replay(ops);
        w.finish().unwrap()
    }

    /// A run's shape: schemas and channels, messages of varied sizes on
    /// them (times not always increasing), a schema and channel added
    /// midway (the wind's), a schema added twice, metadata midway and at
    /// the end.
    fn run(messages: usize) -> Vec<Op> {
        let mut ops = vec![
            Op::Schema("a.Pose", vec![1, 2, 3]),
            Op::Schema("a.Errors", vec![4; 40]),
            Op::Channel(1, "/pose", BTreeMap::new()),
            Op::Channel(1, "/desired", map(&[("frame", "ned")])),
            Op::Channel(2, "/errors", BTreeMap::new()),
            Op::Schema("a.Pose", vec![1, 2, 3]),
        ];
        let mut seq = [0u32; 5];
        for k in 0..messages {
            if k == messages / 2 {
                ops.push(Op::Schema("a.Wind", vec![9; 7]));
                ops.push(Op::Channel(3, "/wind", BTreeMap::new()));
                ops.push(Op::Metadata("midway", map(&[("k", "v"), ("a", "")])));
            }
            let channels = if k >= messages / 2 { 4 } else { 3 };
            let c = (k * 7 % channels) as u16 + 1;
            seq[usize::from(c)] += 1;
            let t = 1_000_000 * k as u64 + if k % 13 == 5 { 0 } else { 3_000_000 };
            let len = 20 + (k * 37) % 150;
            ops.push(Op::Message(c, seq[usize::from(c)], t, vec![k as u8; len]));
        }
        ops.push(Op::Metadata("warnings", map(&[("warning 1", "text")])));
        ops.push(Op::Metadata(
            "stopped",
            map(&[("t", "1.5"), ("reason", "interrupted")]),
        ));
        ops
    }

    #[test]
    fn a_run_is_the_crate_s_bytes_whatever_the_chunk_size() {
        for (messages, target) in [(600, 1_000), (600, 64), (600, 1 << 20), (5, 0), (1, 1_000)] {
            let ops = run(messages);
            let (a, b) = (ours(&ops, target), theirs(&ops, target));
            assert_eq!(a.len(), b.len(), "{messages} messages, chunks of {target}");
            assert!(
                a == b,
                "{messages} messages, chunks of {target}: bytes differ"
            );
        }
    }

    #[test]
    fn a_file_without_messages_or_without_anything_is_the_crate_s_bytes() {
        let ops = vec![
            Op::Schema("a.Pose", vec![1, 2, 3]),
            Op::Channel(1, "/pose", BTreeMap::new()),
        ];
        assert_eq!(ours(&ops, 1_000), theirs(&ops, 1_000));
        assert_eq!(ours(&[], 1_000), theirs(&[], 1_000));
        let ops = vec![Op::Metadata("only", map(&[("k", "v")]))];
        assert_eq!(ours(&ops, 1_000), theirs(&ops, 1_000));
    }

    #[test]
    fn the_crate_s_reader_reads_every_message_through_the_summary() {
        let ops = run(600);
        let bytes = ours(&ops, 1_000);
        let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary");
        let stats = summary.stats.as_ref().unwrap();
        assert_eq!(stats.message_count, 600);
        assert_eq!(stats.channel_count, 4);
        assert_eq!(stats.metadata_count, 3);
        assert!(summary.chunk_indexes.len() > 10);
        // Through the chunk indexes and message indexes, as a seeking
        // reader (Foxglove) reads a file.
        let mut n = 0;
        for index in &summary.chunk_indexes {
            let by_channel = summary.read_message_indexes(&bytes, index).unwrap();
            for entries in by_channel.values() {
                for e in entries {
                    let m = summary.seek_message(&bytes, index, e).unwrap();
                    assert_eq!(m.log_time, e.log_time);
                    n += 1;
                }
            }
        }
        assert_eq!(n, 600);
        let linear = mcap::MessageStream::new(&bytes).unwrap().count();
        assert_eq!(linear, 600);
    }

    #[test]
    fn a_message_on_an_unknown_channel_is_an_error_not_a_record() {
        let mut w = ChunkedMcap::create(Vec::new(), LIB, 1_000).unwrap();
        assert!(w.message(1, 1, 0, b"x").is_err());
        let s = w.add_schema("s", "protobuf", b"").unwrap();
        assert!(
            w.add_channel(s + 1, "/t", "protobuf", &BTreeMap::new())
                .is_err()
        );
        let c = w
            .add_channel(s, "/t", "protobuf", &BTreeMap::new())
            .unwrap();
        assert!(w.message(c + 1, 1, 0, b"x").is_err());
        w.message(c, 1, 0, b"x").unwrap();
        let bytes = w.finish().unwrap();
        assert_eq!(mcap::MessageStream::new(&bytes).unwrap().count(), 1);
    }
}
