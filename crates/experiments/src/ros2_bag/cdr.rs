//! ROS 2's wire encoding of a message: OMG CDR, little-endian (encapsulation `CDR_LE`, the
//! 4-byte header `00 01 00 00`), as the default RMW writes it — every primitive aligned to
//! its own size counted from the end of the header, a string as a `u32` length that counts
//! its terminating NUL then its bytes and the NUL, a sequence as a `u32` element count
//! then its elements, a fixed array as its elements alone.

/// The encapsulation header of little-endian plain CDR.
const CDR_LE: [u8; 4] = [0, 1, 0, 0];

/// Builds one message.
pub struct Encoder {
    buf: Vec<u8>,
}

impl Default for Encoder {
    fn default() -> Self {
        Self::new()
    }
}

impl Encoder {
    pub fn new() -> Self {
        Self {
            buf: CDR_LE.to_vec(),
        }
    }

    fn align(&mut self, n: usize) {
        while !(self.buf.len() - CDR_LE.len()).is_multiple_of(n) {
            self.buf.push(0);
        }
    }

    pub fn u32(&mut self, v: u32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn i32(&mut self, v: i32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn i64(&mut self, v: i64) {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn f64(&mut self, v: f64) {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn string(&mut self, s: &str) {
        self.u32(s.len() as u32 + 1);
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
    }

    /// A sequence's element count.
    pub fn count(&mut self, n: usize) {
        self.u32(n as u32);
    }

    /// `std_msgs/Header`: the stamp (`builtin_interfaces/Time`, from nanoseconds) and the
    /// frame.
    pub fn header(&mut self, stamp_ns: u64, frame: &str) {
        self.i32((stamp_ns / 1_000_000_000) as i32);
        self.u32((stamp_ns % 1_000_000_000) as u32);
        self.string(frame);
    }

    pub fn finish(self) -> Vec<u8> {
        self.buf
    }
}

/// Reads one message; every error says what did not fit at which byte of the message.
pub struct Decoder<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Decoder<'a> {
    /// A message's bytes, its encapsulation header checked.
    pub fn new(buf: &'a [u8]) -> Result<Self, String> {
        match buf.get(..4) {
            Some(h) if h == CDR_LE => Ok(Self { buf, pos: 4 }),
            Some(h) => Err(format!(
                "expected the CDR little-endian encapsulation 00 01 00 00, got {h:02x?}"
            )),
            None => Err(format!("{} bytes: shorter than the CDR header", buf.len())),
        }
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        while !(self.pos - CDR_LE.len()).is_multiple_of(n.clamp(1, 8)) {
            self.pos += 1;
        }
        let end = self.pos + n;
        let bytes = self.buf.get(self.pos..end).ok_or_else(|| {
            format!(
                "the message ends at byte {} where its {what} needs {n} bytes from byte {}",
                self.buf.len(),
                self.pos
            )
        })?;
        self.pos = end;
        Ok(bytes)
    }

    pub fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes(b.try_into().expect("4 bytes")))
    }

    pub fn i32(&mut self, what: &str) -> Result<i32, String> {
        let b = self.take(4, what)?;
        Ok(i32::from_le_bytes(b.try_into().expect("4 bytes")))
    }

    pub fn i64(&mut self, what: &str) -> Result<i64, String> {
        let b = self.take(8, what)?;
        Ok(i64::from_le_bytes(b.try_into().expect("8 bytes")))
    }

    pub fn f64(&mut self, what: &str) -> Result<f64, String> {
        let b = self.take(8, what)?;
        Ok(f64::from_le_bytes(b.try_into().expect("8 bytes")))
    }

    pub fn string(&mut self, what: &str) -> Result<String, String> {
        let n = self.u32(what)? as usize;
        if n == 0 {
            return Err(format!("{what}: a string of length 0 (the NUL is counted)"));
        }
        let start = self.pos;
        let bytes = self
            .buf
            .get(start..start + n)
            .ok_or_else(|| format!("{what}: a string of {n} bytes runs past the message's end"))?;
        self.pos += n;
        if bytes[n - 1] != 0 {
            return Err(format!("{what}: the string does not end with NUL"));
        }
        String::from_utf8(bytes[..n - 1].to_vec()).map_err(|_| format!("{what}: not UTF-8"))
    }

    /// A sequence's element count, bounded by what the message can still hold.
    pub fn count(&mut self, what: &str) -> Result<usize, String> {
        let n = self.u32(what)? as usize;
        if n > self.buf.len() {
            return Err(format!("{what}: {n} elements cannot fit in the message"));
        }
        Ok(n)
    }

    /// `std_msgs/Header`: (stamp in nanoseconds, frame).
    pub fn header(&mut self) -> Result<(u64, String), String> {
        let sec = self.i32("header.stamp.sec")?;
        let nanosec = self.u32("header.stamp.nanosec")?;
        let frame = self.string("header.frame_id")?;
        Ok((
            (sec.max(0) as u64) * 1_000_000_000 + u64::from(nanosec),
            frame,
        ))
    }

    /// Checks that nothing but alignment padding is left.
    pub fn end(&self) -> Result<(), String> {
        if self.buf.len() > self.pos + 7 {
            Err(format!(
                "{} bytes left over after the message's last field",
                self.buf.len() - self.pos
            ))
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `std_msgs/Header` with stamp 1.5 s and frame "world", then a float64: the layout
    /// worked out by hand from the CDR rules (the double is aligned to 8 from the payload).
    #[test]
    fn layout_matches_the_rules() {
        let mut e = Encoder::new();
        e.header(1_500_000_000, "world");
        e.f64(2.0);
        let b = e.finish();
        let mut want = vec![0, 1, 0, 0];
        want.extend_from_slice(&1i32.to_le_bytes());
        want.extend_from_slice(&500_000_000u32.to_le_bytes());
        want.extend_from_slice(&6u32.to_le_bytes());
        want.extend_from_slice(b"world\0");
        // payload offset now 18: pad to 24
        want.extend_from_slice(&[0; 6]);
        want.extend_from_slice(&2.0f64.to_le_bytes());
        assert_eq!(b, want);
        let mut d = Decoder::new(&b).unwrap();
        assert_eq!(d.header().unwrap(), (1_500_000_000, "world".into()));
        assert_eq!(d.f64("x").unwrap(), 2.0);
        d.end().unwrap();
        let mut short = Decoder::new(&b[..b.len() - 1]).unwrap();
        short.header().unwrap();
        assert!(short.f64("x").unwrap_err().contains("needs 8 bytes"));
    }
}
