//! The checkpoint file: little-endian binary, every number with its exact bits, so a state
//! read back is the state written, bit for bit.
//!
//! ```text
//! magic "radiosity-ckpt\n\0"  format u32 (= 3)
//! fingerprint u64   method (length u64, UTF-8)   iterations u64   residual f64   links u64
//! radiosity (count u64, then r g b f64 each)     irradiance, unshot (the same)
//! matrix:    0u8 | 1u8, sources u64, rows u64, chunk rows u64, done u8 per chunk,
//!            then the f32 rows of every done chunk, in order; then for every row the
//!            count u64 of its opened pieces (0 in chunks not done) and the pieces, each
//!            first element u32, end u32, factor f32
//! hierarchy: 0u8 | 1u8, then the hierarchical solver's snapshot
//! ```
//!
//! Only the chunks of form-factor rows that are done are stored, so a checkpoint taken when the
//! form-factor stage is stopped early is as large as the work it saves. Lengths read from a
//! file are allocated fallibly: a damaged file is an error, never an abort.

use std::io::{self, Read, Write};

use super::{Checkpoint, Hierarchy, Iterate};
use crate::solve::matrix::{Matrix, Near, CHUNK_ROWS};
use crate::solve::opened_sources::Piece;
use crate::Rgb;

/// The first bytes of every checkpoint file.
const MAGIC: &[u8; 16] = b"radiosity-ckpt\n\0";

/// Version of the format.
const FORMAT: u32 = 3;

impl Checkpoint {
    /// Writes the checkpoint to `out` in the format of the module documentation.
    ///
    /// # Errors
    /// The first error of `out`.
    pub fn write(&self, out: &mut dyn Write) -> io::Result<()> {
        let mut e = Encoder(out);
        e.0.write_all(MAGIC)?;
        e.u32(FORMAT)?;
        e.u64(self.fingerprint)?;
        e.bytes(self.method.as_bytes())?;
        let state = &self.state;
        e.usize(state.iterations)?;
        e.f64(state.residual)?;
        e.u64(state.links)?;
        e.rgbs(&state.radiosity)?;
        e.rgbs(&state.irradiance)?;
        e.rgbs(&state.unshot)?;
        match &self.matrix {
            None => e.u8(0)?,
            Some(m) => {
                e.u8(1)?;
                write_matrix(&mut e, m)?;
            }
        }
        match &state.hierarchy {
            None => e.u8(0),
            Some(h) => {
                e.u8(1)?;
                h.encode(&mut e)
            }
        }
    }

    /// Reads a checkpoint written by [`Checkpoint::write`].
    ///
    /// # Errors
    /// A line saying why when `input` is not a whole checkpoint of this format version.
    pub fn read(input: &mut dyn Read) -> Result<Self, String> {
        let mut d = Decoder(input);
        let mut magic = [0; MAGIC.len()];
        d.exact(&mut magic)
            .map_err(|_| "not a checkpoint file".to_owned())?;
        if &magic != MAGIC {
            return Err("not a checkpoint file".to_owned());
        }
        let format = d.u32()?;
        if format != FORMAT {
            return Err(format!(
                "checkpoint format {format} is not supported (expected {FORMAT})"
            ));
        }
        let fingerprint = d.u64()?;
        let method = String::from_utf8(d.bytes()?).map_err(|_| "damaged checkpoint")?;
        let (iterations, residual, links) = (d.usize()?, d.f64()?, d.u64()?);
        let (radiosity, irradiance, unshot) = (d.rgbs()?, d.rgbs()?, d.rgbs()?);
        let matrix = match d.u8()? {
            0 => None,
            1 => Some(read_matrix(&mut d)?),
            _ => return Err("damaged checkpoint".to_owned()),
        };
        let hierarchy = match d.u8()? {
            0 => None,
            1 => Some(Hierarchy::decode(&mut d)?),
            _ => return Err("damaged checkpoint".to_owned()),
        };
        let mut rest = [0u8; 1];
        if d.0.read(&mut rest).map_err(|e| e.to_string())? != 0 {
            return Err("damaged checkpoint: bytes after its end".to_owned());
        }
        Ok(Self {
            fingerprint,
            method,
            matrix,
            state: Iterate {
                iterations,
                residual,
                links,
                radiosity,
                irradiance,
                unshot,
                hierarchy,
            },
        })
    }
}

fn write_matrix(e: &mut Encoder, m: &Matrix) -> io::Result<()> {
    let (rows, sources) = m.shape();
    e.usize(sources)?;
    e.usize(rows)?;
    e.usize(CHUNK_ROWS)?;
    for &done in m.chunks_done() {
        e.u8(u8::from(done))?;
    }
    let chunk = CHUNK_ROWS * sources;
    for (block, &done) in m.data().chunks(chunk.max(1)).zip(m.chunks_done()) {
        if done {
            e.f32s(block)?;
        }
    }
    let near = m.near();
    for row in 0..rows {
        let pieces = near.row(row);
        e.usize(pieces.len())?;
        for p in pieces {
            e.u32(p.elements.start)?;
            e.u32(p.elements.end)?;
            e.f32s(&[p.factor])?;
        }
    }
    Ok(())
}

fn read_matrix(d: &mut Decoder) -> Result<Matrix, String> {
    let (sources, rows, chunk_rows) = (d.usize()?, d.usize()?, d.usize()?);
    if chunk_rows != CHUNK_ROWS {
        return Err("damaged checkpoint: another chunk size".to_owned());
    }
    let chunks = rows.div_ceil(CHUNK_ROWS);
    let mut done = allocate::<bool>(chunks)?;
    for _ in 0..chunks {
        done.push(match d.u8()? {
            0 => false,
            1 => true,
            _ => return Err("damaged checkpoint".to_owned()),
        });
    }
    let len = rows
        .checked_mul(sources)
        .ok_or("damaged checkpoint: matrix too large")?;
    let mut data = allocate::<f32>(len)?;
    data.resize(len, 0.0);
    let chunk = CHUNK_ROWS * sources;
    for (block, &is_done) in data.chunks_mut(chunk.max(1)).zip(&done) {
        if is_done {
            d.f32s(block)?;
        }
    }
    let mut rows_pieces = allocate::<Vec<Piece>>(rows)?;
    for _ in 0..rows {
        let count = d.usize()?;
        let mut pieces = allocate::<Piece>(count)?;
        for _ in 0..count {
            let (start, end) = (d.u32()?, d.u32()?);
            let mut factor = [0.0];
            d.f32s(&mut factor)?;
            if start > end {
                return Err("damaged checkpoint".to_owned());
            }
            pieces.push(Piece {
                elements: start..end,
                factor: factor[0],
            });
        }
        rows_pieces.push(pieces);
    }
    let near = Near::from_rows(rows_pieces);
    Matrix::from_parts(sources, data, near, done).ok_or_else(|| "damaged checkpoint".to_owned())
}

/// An empty vector with room for `n` items, or an error if memory refuses.
pub(crate) fn allocate<T>(n: usize) -> Result<Vec<T>, String> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| "damaged checkpoint: a length beyond memory".to_owned())?;
    Ok(v)
}

/// Writes numbers in the checkpoint's encoding.
pub(crate) struct Encoder<'a>(&'a mut dyn Write);

impl Encoder<'_> {
    pub fn u8(&mut self, x: u8) -> io::Result<()> {
        self.0.write_all(&[x])
    }

    pub fn u32(&mut self, x: u32) -> io::Result<()> {
        self.0.write_all(&x.to_le_bytes())
    }

    pub fn u64(&mut self, x: u64) -> io::Result<()> {
        self.0.write_all(&x.to_le_bytes())
    }

    pub fn usize(&mut self, x: usize) -> io::Result<()> {
        self.u64(x as u64)
    }

    pub fn f64(&mut self, x: f64) -> io::Result<()> {
        self.u64(x.to_bits())
    }

    /// A length, then the bytes.
    pub fn bytes(&mut self, x: &[u8]) -> io::Result<()> {
        self.usize(x.len())?;
        self.0.write_all(x)
    }

    pub fn rgb(&mut self, x: Rgb) -> io::Result<()> {
        x.to_array().into_iter().try_for_each(|c| self.f64(c))
    }

    /// A length, then the colours.
    pub fn rgbs(&mut self, x: &[Rgb]) -> io::Result<()> {
        self.usize(x.len())?;
        x.iter().try_for_each(|&c| self.rgb(c))
    }

    /// The numbers, without a length.
    pub fn f32s(&mut self, x: &[f32]) -> io::Result<()> {
        let bytes: Vec<u8> = x.iter().flat_map(|f| f.to_le_bytes()).collect();
        self.0.write_all(&bytes)
    }
}

/// Reads numbers in the checkpoint's encoding; an early end is "truncated".
pub(crate) struct Decoder<'a>(&'a mut dyn Read);

impl Decoder<'_> {
    fn exact(&mut self, buf: &mut [u8]) -> Result<(), String> {
        self.0.read_exact(buf).map_err(|e| match e.kind() {
            io::ErrorKind::UnexpectedEof => "truncated checkpoint".to_owned(),
            _ => e.to_string(),
        })
    }

    pub fn u8(&mut self) -> Result<u8, String> {
        let mut b = [0; 1];
        self.exact(&mut b)?;
        Ok(b[0])
    }

    pub fn u32(&mut self) -> Result<u32, String> {
        let mut b = [0; 4];
        self.exact(&mut b)?;
        Ok(u32::from_le_bytes(b))
    }

    pub fn u64(&mut self) -> Result<u64, String> {
        let mut b = [0; 8];
        self.exact(&mut b)?;
        Ok(u64::from_le_bytes(b))
    }

    pub fn usize(&mut self) -> Result<usize, String> {
        usize::try_from(self.u64()?).map_err(|_| "damaged checkpoint".to_owned())
    }

    pub fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }

    pub fn bytes(&mut self) -> Result<Vec<u8>, String> {
        let n = self.usize()?;
        let mut v = allocate(n)?;
        v.resize(n, 0);
        self.exact(&mut v)?;
        Ok(v)
    }

    pub fn rgb(&mut self) -> Result<Rgb, String> {
        Ok(Rgb::new(self.f64()?, self.f64()?, self.f64()?))
    }

    pub fn rgbs(&mut self) -> Result<Vec<Rgb>, String> {
        let n = self.usize()?;
        let mut v = allocate(n)?;
        for _ in 0..n {
            v.push(self.rgb()?);
        }
        Ok(v)
    }

    /// Fills `out` (no length is read).
    pub fn f32s(&mut self, out: &mut [f32]) -> Result<(), String> {
        let mut bytes = vec![0; out.len() * 4];
        self.exact(&mut bytes)?;
        for (x, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
            *x = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        }
        Ok(())
    }
}
