//! A small indexed raster for pictures of large meshes: polygons filled by scanlines, segments
//! drawn one pixel wide (in bands of rows, one thread each), and PNG encoding (zlib through
//! `miniz_oxide` in pieces on every thread, Adler-32 through `adler2`, CRC-32 here).
//!
//! A picture of 10^6 cells drawn as vectors is a file of 100 MB that no browser opens; the
//! same picture rasterised at the resolution it is shown at is a PNG whose size depends on the
//! number of pixels, not of cells. Its pixels are indices into a [`Palette`] of at most 256
//! colours (a PNG of colour type 3): a byte per pixel to draw, filter and deflate rather than
//! four.

/// The colours of a [`Raster`], at most 256: index 0 is transparent, then the ink segments
/// are drawn in over transparent, then the fills, then the ink over each fill.
pub(crate) struct Palette {
    /// Red, green, blue and alpha of every index.
    colours: Vec<[u8; 4]>,
    /// `under_ink[i]`: the index of the ink blended over colour `i`.
    under_ink: Vec<u8>,
    /// The number of fills.
    fills: usize,
}

impl Palette {
    /// The most fills a palette holds.
    pub(crate) const MAX_FILLS: usize = 127;

    /// The palette of the opaque colours `fills` (at most [`Palette::MAX_FILLS`]) and of
    /// segments drawn in `ink`, blended by its alpha. Ink over ink stays the ink's first
    /// blend (where segments cross, as at the vertices of a mesh's edges).
    pub(crate) fn new(fills: &[[u8; 3]], ink: [u8; 4]) -> Self {
        assert!(
            fills.len() <= Self::MAX_FILLS,
            "a palette of {} fills",
            fills.len()
        );
        let n = fills.len();
        let alpha = u32::from(ink[3]);
        let over = |fill: &[u8; 3]| {
            let [r, g, b] = [0, 1, 2].map(|c| {
                ((u32::from(ink[c]) * alpha + u32::from(fill[c]) * (255 - alpha)) / 255) as u8
            });
            [r, g, b, 255]
        };
        let mut colours = vec![[0; 4], ink];
        colours.extend(fills.iter().map(|&[r, g, b]| [r, g, b, 255]));
        colours.extend(fills.iter().map(over));
        let mut under_ink = vec![1u8, 1];
        under_ink.extend((0..n).map(|i| (2 + n + i) as u8));
        under_ink.extend((0..n).map(|i| (2 + n + i) as u8));
        Palette {
            colours,
            under_ink,
            fills: n,
        }
    }

    /// The index of fill `k` (of the fills the palette was made with).
    pub(crate) fn fill(&self, k: usize) -> u8 {
        assert!(k < self.fills, "fill {k} of {}", self.fills);
        (2 + k) as u8
    }
}

/// An image of palette indices, rows from the top, transparent (index 0) where nothing is
/// drawn.
pub(crate) struct Raster {
    width: usize,
    height: usize,
    palette: Palette,
    pixels: Vec<u8>,
}

/// One thing drawn into a [`Raster`] (see [`Raster::draw`]).
#[cfg(test)]
pub(crate) enum Shape {
    /// The polygon through the drawing's points `corners` (a range of their indices),
    /// filled with the palette's `colour`: every pixel whose centre lies inside (the even-odd
    /// rule).
    Polygon {
        corners: std::ops::Range<usize>,
        colour: u8,
    },
    /// The segment from `a` to `b`, one pixel wide, in the palette's ink.
    Segment { a: (f64, f64), b: (f64, f64) },
}

impl Raster {
    /// A transparent image of `width` x `height` pixels in the colours of `palette`.
    pub(crate) fn new(width: usize, height: usize, palette: Palette) -> Self {
        Raster {
            width,
            height,
            palette,
            pixels: vec![0; width * height],
        }
    }

    /// Draws `shapes` in order (the polygons' corners in `points`), in bands of rows, one
    /// thread each: every band draws every shape clipped to its rows, so the image is the one
    /// drawn on one thread, pixel for pixel.
    #[cfg(test)]
    pub(crate) fn draw(&mut self, points: &[(f64, f64)], shapes: &[Shape]) {
        self.draw_in_bands(points, shapes, pieces_for(self.pixels.len()));
    }

    /// [`Raster::draw`] in `bands` bands of rows.
    #[cfg(test)]
    fn draw_in_bands(&mut self, points: &[(f64, f64)], shapes: &[Shape], bands: usize) {
        self.draw_with_in_bands(
            |band| {
                for shape in shapes {
                    match shape {
                        Shape::Polygon { corners, colour } => {
                            band.fill_polygon(&points[corners.clone()], *colour);
                        }
                        Shape::Segment { a, b } => band.segment(*a, *b),
                    }
                }
            },
            bands,
        );
    }

    /// Draws the shapes `shapes` draws with the [`Band`] it is given, in bands of rows, one
    /// thread each: every band runs `shapes`, which draws every shape in the same order, each
    /// clipped to the band's rows, so the image is the one drawn on one thread, pixel for
    /// pixel. The shapes are made where they are drawn (a mesh's cells straight from the
    /// mesh): no list of them is gathered first.
    pub(crate) fn draw_with(&mut self, shapes: impl Fn(&mut Band) + Sync) {
        let bands = pieces_for(self.pixels.len());
        self.draw_with_in_bands(shapes, bands);
    }

    /// [`Raster::draw_with`] in `bands` bands of rows.
    fn draw_with_in_bands(&mut self, shapes: impl Fn(&mut Band) + Sync, bands: usize) {
        let stride = self.width;
        let bands = bands.clamp(1, self.height.max(1));
        let rows_per_band = self.height.div_ceil(bands).max(1);
        let width = self.width;
        let under_ink = &self.palette.under_ink;
        let draw_band = |first_row: usize, pixels: &mut [u8]| {
            let mut band = Band {
                first_row,
                width,
                pixels,
                under_ink,
                crossings: Vec::new(),
            };
            shapes(&mut band);
        };
        if bands == 1 || stride == 0 {
            draw_band(0, &mut self.pixels);
            return;
        }
        std::thread::scope(|scope| {
            for (k, pixels) in self.pixels.chunks_mut(rows_per_band * stride).enumerate() {
                let draw_band = &draw_band;
                scope.spawn(move || draw_band(k * rows_per_band, pixels));
            }
        });
    }

    /// Fills the polygon through `points` (pixel coordinates, y down; any orientation, the
    /// even-odd rule) with `colour`: every pixel whose centre lies inside.
    #[cfg(test)]
    pub(crate) fn fill_polygon(&mut self, points: &[(f64, f64)], colour: u8) {
        self.draw(
            points,
            &[Shape::Polygon {
                corners: 0..points.len(),
                colour,
            }],
        );
    }

    /// The image as a PNG file (8-bit palette indices with the palette's alphas, no
    /// interlacing). Every row but the first is filtered "Up" (its bytes minus the row
    /// above's, modulo 256): the differences of indices mean nothing as numbers, but a row
    /// of cells mostly repeats the row above, and its zeros deflate to half the size of the
    /// unfiltered rows (the whole-run picture at 10^5 unknowns: 400 -> 213 kB).
    pub(crate) fn to_png(&self) -> Vec<u8> {
        let stride = self.width;
        // Rows prefixed with their filter byte piece by piece on the threads that deflate
        // them (a piece's first row is filtered against the last row of the piece before).
        let bytes = (stride + 1) * self.height;
        let pieces = pieces_for(bytes).min(self.height.max(1));
        let rows_per_piece = self.height.div_ceil(pieces).max(1);
        let filtered_rows = |k: usize| {
            let rows = k * rows_per_piece..((k + 1) * rows_per_piece).min(self.height);
            let mut filtered = Vec::with_capacity((stride + 1) * rows.len());
            for row in rows {
                let line = &self.pixels[row * stride..(row + 1) * stride];
                if row == 0 {
                    filtered.push(PNG_FILTER_NONE);
                    filtered.extend_from_slice(line);
                } else {
                    let above = &self.pixels[(row - 1) * stride..row * stride];
                    filtered.push(PNG_FILTER_UP);
                    filtered.extend(line.iter().zip(above).map(|(x, b)| x.wrapping_sub(*b)));
                }
            }
            filtered
        };
        let idat = zlib_of_parts(
            self.height.div_ceil(rows_per_piece),
            filtered_rows,
            PNG_LEVEL,
        );
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut header = Vec::with_capacity(13);
        header.extend_from_slice(&(self.width as u32).to_be_bytes());
        header.extend_from_slice(&(self.height as u32).to_be_bytes());
        header.extend_from_slice(&[8, 3, 0, 0, 0]);
        chunk(&mut png, b"IHDR", &header);
        let colours = &self.palette.colours;
        let rgb: Vec<u8> = colours.iter().flat_map(|c| [c[0], c[1], c[2]]).collect();
        chunk(&mut png, b"PLTE", &rgb);
        // The alphas up to the last colour that is not opaque (the rest are).
        let translucent = colours
            .iter()
            .rposition(|c| c[3] != 255)
            .map_or(0, |i| i + 1);
        let alphas: Vec<u8> = colours[..translucent].iter().map(|c| c[3]).collect();
        chunk(&mut png, b"tRNS", &alphas);
        chunk(&mut png, b"IDAT", &idat);
        chunk(&mut png, b"IEND", &[]);
        png
    }
}

/// The rows `first_row..` of a raster `width` pixels wide, drawn into by one thread (see
/// [`Raster::draw_with`]).
pub(crate) struct Band<'a> {
    first_row: usize,
    width: usize,
    pixels: &'a mut [u8],
    /// The palette's [`Palette::under_ink`].
    under_ink: &'a [u8],
    /// The crossings of a row with a polygon's edges (kept from one polygon to the next).
    crossings: Vec<f64>,
}

impl Band<'_> {
    /// The rows of the band, in the image's numbering.
    fn rows(&self) -> std::ops::Range<usize> {
        self.first_row..self.first_row + self.pixels.len() / self.width.max(1)
    }

    /// Fills the polygon through `points` (pixel coordinates, y down; any orientation, the
    /// even-odd rule) with `colour`: every pixel of the band whose centre lies inside.
    pub(crate) fn fill_polygon(&mut self, points: &[(f64, f64)], colour: u8) {
        let m = points.len();
        if m < 3 {
            return;
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &(_, y) in points {
            lo = lo.min(y);
            hi = hi.max(y);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return;
        }
        let rows = self.rows();
        // Rows whose centre y + 1/2 lies in [lo, hi).
        let first = ((lo - 0.5).ceil().max(0.0) as usize).max(rows.start);
        let last = ((hi - 0.5).ceil().min(rows.end as f64)).max(0.0) as usize;
        let mut crossings = std::mem::take(&mut self.crossings);
        for row in first..last {
            let y = row as f64 + 0.5;
            crossings.clear();
            for k in 0..m {
                let (a, b) = (points[k], points[(k + 1) % m]);
                if (a.1 <= y) != (b.1 <= y) {
                    crossings.push(a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0));
                }
            }
            crossings.sort_by(f64::total_cmp);
            let line = (row - rows.start) * self.width;
            for pair in crossings.chunks_exact(2) {
                // Pixels whose centre x + 1/2 lies in [pair[0], pair[1]).
                let start = (pair[0] - 0.5).ceil().max(0.0) as usize;
                let end = ((pair[1] - 0.5).ceil().min(self.width as f64)).max(0.0) as usize;
                if start < end {
                    self.pixels[line + start..line + end].fill(colour);
                }
            }
        }
        self.crossings = crossings;
    }

    /// Draws the segment from `a` to `b` one pixel wide (a pixel per step along the longer
    /// axis) in the palette's ink over what is there; the band's pixels only.
    pub(crate) fn segment(&mut self, a: (f64, f64), b: (f64, f64)) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let steps = dx.abs().max(dy.abs()).ceil();
        if !steps.is_finite() || steps > 1e7 {
            return;
        }
        let rows = self.rows();
        // A step's y may round a little beyond the ends': a row of margin on either side.
        if a.1.max(b.1) < rows.start as f64 - 1.0 || a.1.min(b.1) >= rows.end as f64 + 1.0 {
            return;
        }
        let steps = steps.max(1.0) as usize;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y) = (a.0 + t * dx, a.1 + t * dy);
            if x >= 0.0 && y >= 0.0 && x < self.width as f64 && rows.contains(&(y as usize)) {
                let k = (y as usize - rows.start) * self.width + x as usize;
                self.pixels[k] = self.under_ink[usize::from(self.pixels[k])];
            }
        }
    }
}

/// zlib's compression level of the pictures: at 1 (the fastest) the picture of the whole-run
/// bench at 10^5 unknowns (1800 x 2426 pixels, rows filtered "Up") is an SVG file of 0.42 MB
/// against 0.28 MB at 6, and the run's output takes 47 ms against 65-68.
const PNG_LEVEL: u8 = 1;

/// PNG's filter types of a row (the byte before it): none, and "Up" (minus the row above).
const PNG_FILTER_NONE: u8 = 0;
const PNG_FILTER_UP: u8 = 2;

/// Data of at least this many bytes is deflated in pieces, and an image of at least this many
/// bytes drawn in bands, one thread each.
const PIECE_MIN_BYTES: usize = 1 << 20;

/// The number of pieces `bytes` of data are deflated in, or of bands an image of `bytes` is
/// drawn in: one per thread from [`PIECE_MIN_BYTES`] on.
fn pieces_for(bytes: usize) -> usize {
    if bytes < PIECE_MIN_BYTES {
        1
    } else {
        std::thread::available_parallelism().map_or(1, |n| n.get().min(8))
    }
}

/// The zlib stream of `data` at `level`, its pieces deflated on one thread each (see
/// [`zlib_of_parts`]).
#[cfg(test)]
fn zlib_in_pieces(data: &[u8], level: u8) -> Vec<u8> {
    let size = data.len().div_ceil(pieces_for(data.len())).max(1);
    let chunks: Vec<&[u8]> = data.chunks(size).collect();
    zlib_of_parts(chunks.len(), |k| chunks[k].to_vec(), level)
}

/// The zlib stream at `level` of the concatenation of `count` parts, part `k` made by
/// `part(k)` and deflated on a thread of its own: every part but the last ends with a sync
/// flush (an empty stored block ending on a byte boundary), so that the raw deflate streams
/// join into one; then the zlib header and the Adler-32 of the whole, combined from the
/// parts'. Each part starts with an empty dictionary, which costs a few bytes per part.
fn zlib_of_parts(count: usize, part: impl Fn(usize) -> Vec<u8> + Sync, level: u8) -> Vec<u8> {
    let count = count.max(1);
    let last = count - 1;
    let deflate = |k: usize| {
        let data = part(k);
        (
            raw_deflate(&data, level, k == last),
            adler32(&data),
            data.len(),
        )
    };
    let deflated: Vec<(Vec<u8>, u32, usize)> = if count == 1 {
        vec![deflate(0)]
    } else {
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..count)
                .map(|k| {
                    let deflate = &deflate;
                    scope.spawn(move || deflate(k))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join()
                        .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
                })
                .collect()
        })
    };
    // CMF 0x78: deflate with a 32 KiB window; FLG 0x01: no dictionary, check bits.
    let mut out = vec![0x78, 0x01];
    let mut checksum = 1;
    for (stream, adler, len) in &deflated {
        out.extend_from_slice(stream);
        checksum = adler32_combine(checksum, *adler, *len);
    }
    out.extend_from_slice(&checksum.to_be_bytes());
    out
}

/// The Adler-32 of the concatenation of two byte strings from theirs and the length of the
/// second (zlib's `adler32_combine`).
fn adler32_combine(first: u32, second: u32, second_len: usize) -> u32 {
    const MOD: u64 = 65_521;
    let rem = second_len as u64 % MOD;
    let mut a = u64::from(first & 0xffff);
    let mut b = (rem * a) % MOD;
    a += u64::from(second & 0xffff) + MOD - 1;
    b += u64::from(first >> 16) + u64::from(second >> 16) + MOD - rem;
    if a >= MOD {
        a -= MOD;
    }
    if a >= MOD {
        a -= MOD;
    }
    if b >= MOD << 1 {
        b -= MOD << 1;
    }
    if b >= MOD {
        b -= MOD;
    }
    (a | (b << 16)) as u32
}

/// The raw deflate stream of `data`, ended by a final block (`last`) or by a sync flush.
fn raw_deflate(data: &[u8], level: u8, last: bool) -> Vec<u8> {
    use miniz_oxide::deflate::core::{
        compress_to_output, create_comp_flags_from_zip_params, CompressorOxide, TDEFLFlush,
        TDEFLStatus,
    };
    // Negative window bits: no zlib header.
    let flags = create_comp_flags_from_zip_params(i32::from(level), -15, 0);
    let mut compressor = CompressorOxide::new(flags);
    let mut out = Vec::with_capacity(data.len() / 8 + 64);
    let flush = if last {
        TDEFLFlush::Finish
    } else {
        TDEFLFlush::Sync
    };
    let (status, _) = compress_to_output(&mut compressor, data, flush, |bytes| {
        out.extend_from_slice(bytes);
        true
    });
    debug_assert!(matches!(status, TDEFLStatus::Done | TDEFLStatus::Okay));
    out
}

/// The Adler-32 checksum of `data` (RFC 1950), by `adler2` (four sums at a time: a third of
/// the time of the byte-by-byte loop on a picture's rows).
fn adler32(data: &[u8]) -> u32 {
    adler2::adler32_slice(data)
}

/// Appends a PNG chunk: length, type, data, CRC-32 of type and data.
fn chunk(png: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    png.extend_from_slice(&(data.len() as u32).to_be_bytes());
    png.extend_from_slice(kind);
    png.extend_from_slice(data);
    let crc = crc32(kind.iter().chain(data));
    png.extend_from_slice(&crc.to_be_bytes());
}

/// CRC-32 (ISO 3309, as PNG uses it).
fn crc32<'a>(bytes: impl Iterator<Item = &'a u8>) -> u32 {
    let mut table = [0u32; 256];
    for (n, entry) in table.iter_mut().enumerate() {
        let mut c = n as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
        *entry = c;
    }
    let mut crc = u32::MAX;
    for &b in bytes {
        crc = table[((crc ^ u32::from(b)) & 0xff) as usize] ^ (crc >> 8);
    }
    crc ^ u32::MAX
}

/// Standard base64 with padding (for a PNG embedded in an SVG as a data URI).
pub(crate) fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for group in bytes.chunks(3) {
        let b = [
            group[0],
            *group.get(1).unwrap_or(&0),
            *group.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= group.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_of_the_png_end_chunk_is_the_known_one() {
        // Every PNG ends with IEND and this CRC.
        assert_eq!(crc32(b"IEND".iter()), 0xAE42_6082);
        assert_eq!(crc32(b"123456789".iter()), 0xCBF4_3926);
    }

    #[test]
    fn base64_of_known_strings() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn a_filled_square_covers_the_pixels_whose_centres_are_inside() {
        let palette = Palette::new(&[[255, 0, 0], [0, 0, 255]], [48, 48, 48, 150]);
        let red = palette.fill(0);
        let mut r = Raster::new(10, 10, palette);
        r.fill_polygon(&[(2.0, 2.0), (6.0, 2.0), (6.0, 5.0), (2.0, 5.0)], red);
        let filled = r.pixels.iter().filter(|&&p| p == red).count();
        assert_eq!(filled, 4 * 3);
        assert_eq!(r.pixels.iter().filter(|&&p| p != 0).count(), 4 * 3);
        // A segment along row 3: the ink over red inside the square, over transparent outside.
        r.draw(
            &[],
            &[Shape::Segment {
                a: (0.5, 3.5),
                b: (9.5, 3.5),
            }],
        );
        let row: Vec<u8> = r.pixels[30..40].to_vec();
        assert_eq!(row, [1, 1, 4, 4, 4, 4, 1, 1, 1, 1]);
        // The PNG's chunks, each with its length and CRC, and its rows decoded back.
        let png = r.to_png();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let mut chunks = Vec::new();
        let mut at = 8;
        while at < png.len() {
            let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
            let kind = &png[at + 4..at + 8];
            let data = &png[at + 8..at + 8 + len];
            let crc = u32::from_be_bytes(png[at + 8 + len..at + 12 + len].try_into().unwrap());
            assert_eq!(crc, crc32(kind.iter().chain(data)));
            chunks.push((kind.to_vec(), data.to_vec()));
            at += 12 + len;
        }
        let kinds: Vec<&[u8]> = chunks.iter().map(|(k, _)| &k[..]).collect();
        assert_eq!(kinds, [b"IHDR", b"PLTE", b"tRNS", b"IDAT", b"IEND"]);
        // 10 x 10, 8 bits of colour type 3 (palette).
        assert_eq!(chunks[0].1, [0, 0, 0, 10, 0, 0, 0, 10, 8, 3, 0, 0, 0]);
        // Transparent, the ink, red, blue, then the ink over red and over blue (alpha 150:
        // 48 * 150 / 255 + 255 * 105 / 255 = 133).
        assert_eq!(
            chunks[1].1,
            [0, 0, 0, 48, 48, 48, 255, 0, 0, 0, 0, 255, 133, 28, 28, 28, 28, 133]
        );
        assert_eq!(chunks[2].1, [0, 150]);
        let raw = miniz_oxide::inflate::decompress_to_vec_zlib(&chunks[3].1).unwrap();
        assert_eq!(raw.len(), 10 * 11);
        // The first row unfiltered, the others "Up": undone by adding the row above.
        let mut above = [0u8; 10];
        for (row, line) in raw.chunks(11).enumerate() {
            assert_eq!(line[0], if row == 0 { 0 } else { 2 }, "filter of row {row}");
            let pixels: Vec<u8> = line[1..]
                .iter()
                .zip(above)
                .map(|(x, b)| x.wrapping_add(b))
                .collect();
            assert_eq!(pixels, &r.pixels[10 * row..10 * row + 10]);
            above.copy_from_slice(&pixels);
        }
    }

    #[test]
    fn an_image_drawn_in_bands_is_the_one_drawn_on_one_thread() {
        // Random polygons (some reaching outside the image) and segments over them, in order.
        let palette = || {
            let fills: Vec<[u8; 3]> = (0..Palette::MAX_FILLS)
                .map(|k| [(2 * k) as u8, (k % 13) as u8 * 19, 200])
                .collect();
            Palette::new(&fills, [48, 48, 48, 150])
        };
        let mut state = 11u32;
        let mut next = |scale: f64| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            f64::from(state >> 8) / f64::from(1u32 << 24) * scale - 0.1 * scale
        };
        let (mut points, mut shapes) = (Vec::new(), Vec::new());
        for k in 0..300 {
            let (cx, cy) = (next(60.0), next(45.0));
            let first = points.len();
            for _ in 0..3 + k % 4 {
                points.push((cx + 0.2 * next(40.0), cy + 0.2 * next(40.0)));
            }
            shapes.push(Shape::Polygon {
                corners: first..points.len(),
                colour: palette().fill(k % Palette::MAX_FILLS),
            });
            if k % 5 == 0 {
                shapes.push(Shape::Segment {
                    a: (next(60.0), next(45.0)),
                    b: (next(60.0), next(45.0)),
                });
            }
        }
        let drawn = |bands: usize| {
            let mut image = Raster::new(53, 41, palette());
            image.draw_in_bands(&points, &shapes, bands);
            image.pixels
        };
        let one = drawn(1);
        assert!(one.iter().filter(|&&p| p != 0).count() > 1000);
        // Without the segments, every pixel has the colour of the last polygon holding its
        // centre (the even-odd rule by a ray to the right), transparent outside all.
        let polygons_only: Vec<Shape> = shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Polygon { corners, colour } => Some(Shape::Polygon {
                    corners: corners.clone(),
                    colour: *colour,
                }),
                Shape::Segment { .. } => None,
            })
            .collect();
        let mut filled = Raster::new(53, 41, palette());
        filled.draw_in_bands(&points, &polygons_only, 3);
        for (k, &pixel) in filled.pixels.iter().enumerate() {
            let (x, y) = ((k % 53) as f64 + 0.5, (k / 53) as f64 + 0.5);
            let inside = |corners: &std::ops::Range<usize>| {
                let loop_ = &points[corners.clone()];
                let mut odd = false;
                for i in 0..loop_.len() {
                    let (a, b) = (loop_[i], loop_[(i + 1) % loop_.len()]);
                    if (a.1 <= y) != (b.1 <= y) && a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0) > x {
                        odd = !odd;
                    }
                }
                odd
            };
            let expected = polygons_only
                .iter()
                .rev()
                .find_map(|s| match s {
                    Shape::Polygon { corners, colour } if inside(corners) => Some(*colour),
                    _ => None,
                })
                .unwrap_or(0);
            assert_eq!(pixel, expected, "pixel {k}");
        }
        for bands in [2, 3, 7, 41, 100] {
            assert!(drawn(bands) == one, "{bands} bands");
        }
        // A segment whose last step rounds to y = 10 while its end is below 10: the band that
        // starts at row 10 draws that pixel too.
        let segment = [Shape::Segment {
            a: (3.0, 1.856_562_196_386_494),
            b: (9.0, 9.999_999_999_999_998),
        }];
        let mut one_band = Raster::new(12, 20, palette());
        one_band.draw_in_bands(&[], &segment, 1);
        let mut two_bands = Raster::new(12, 20, palette());
        two_bands.draw_in_bands(&[], &segment, 2);
        assert!(one_band.pixels[10 * 12 + 9] != 0);
        assert!(two_bands.pixels == one_band.pixels);
    }

    /// An image large enough to be deflated in pieces (one per thread): its rows, inflated
    /// and with the "Up" filter undone, are the pixels, also across the pieces' seams (a
    /// piece's first row is filtered against the last row of the piece before).
    #[test]
    fn a_png_in_pieces_decodes_to_the_pixels() {
        let (width, height) = (1200, 1000);
        assert!(width * height >= PIECE_MIN_BYTES);
        let palette = Palette::new(&[[200, 0, 0], [0, 0, 200]], [48, 48, 48, 150]);
        let mut image = Raster::new(width, height, palette);
        let mut state = 7u32;
        for (k, pixel) in image.pixels.iter_mut().enumerate() {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            // Bands of colour, with a noisy pixel now and then (wrapping differences).
            let (x, y) = (k % width, k / width);
            *pixel = if state >> 28 == 0 {
                (state >> 20) as u8
            } else {
                ((x / 37 + y / 23) % 5) as u8
            };
        }
        let png = image.to_png();
        let at = png.windows(4).position(|w| w == b"IDAT").unwrap();
        let len = u32::from_be_bytes(png[at - 4..at].try_into().unwrap()) as usize;
        let raw = miniz_oxide::inflate::decompress_to_vec_zlib(&png[at + 4..at + 4 + len]).unwrap();
        assert_eq!(raw.len(), (width + 1) * height);
        let mut above = vec![0u8; width];
        for (row, line) in raw.chunks(width + 1).enumerate() {
            let expected_filter = if row == 0 { 0 } else { 2 };
            assert_eq!(line[0], expected_filter, "filter of row {row}");
            for (a, &byte) in above.iter_mut().zip(&line[1..]) {
                *a = byte.wrapping_add(*a);
            }
            assert!(
                above[..] == image.pixels[row * width..(row + 1) * width],
                "row {row}"
            );
        }
    }

    #[test]
    fn pieces_deflated_apart_inflate_to_the_data() {
        // Large enough to be cut into pieces (on a machine with several threads), with runs
        // and noise; miniz_oxide's zlib decoder checks the Adler-32 too.
        let mut state = 7u32;
        let data: Vec<u8> = (0..3 * PIECE_MIN_BYTES + 12345)
            .map(|i| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                if (i / 4096) % 3 == 0 {
                    (state >> 24) as u8
                } else {
                    (i / 4096) as u8
                }
            })
            .collect();
        for level in [1, 6] {
            let stream = zlib_in_pieces(&data, level);
            let back = miniz_oxide::inflate::decompress_to_vec_zlib(&stream).unwrap();
            assert!(back == data, "level {level}");
            assert!(stream.len() < data.len() / 2);
        }
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
        let (x, y) = data.split_at(1_234_567);
        assert_eq!(
            adler32_combine(adler32(x), adler32(y), y.len()),
            adler32(&data)
        );
        assert_eq!(adler32_combine(1, adler32(b"Wiki"), 4), adler32(b"Wiki"));
        let small = zlib_in_pieces(b"abcabcabc", 1);
        assert_eq!(
            miniz_oxide::inflate::decompress_to_vec_zlib(&small).unwrap(),
            b"abcabcabc"
        );
    }
}
