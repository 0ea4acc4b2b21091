//! The Gmsh `.msh` file format, read as written: MSH 4.1 and 2.2, ASCII and binary.
//!
//! [`read_msh_bytes`] turns the bytes of a file into an [`MshFile`]: its nodes with their tags
//! (any order, gaps, several blocks), its elements with their tags, types, entities and node
//! tags, its entities with their physical tags, and its physical names. It knows nothing of
//! polygons; `read_gmsh` builds a [`crate::Mesh`] from it.
//!
//! Every malformed input is an [`MshError`] located by line (ASCII text) or byte offset (binary
//! data). Counts announced by a header never size an allocation beyond what the rest of the file
//! can hold, so a forged header cannot exhaust memory. Sections other than `$MeshFormat`,
//! `$PhysicalNames`, `$Entities`, `$Nodes` and `$Elements` are skipped up to their end marker,
//! as Gmsh does; partitioned meshes (`$PartitionedEntities`) are refused.

use std::collections::{BTreeMap, HashSet};
use std::fmt;
use std::str::FromStr;

/// The format version of a `.msh` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum MshVersion {
    /// MSH 2.2 (also accepted: 2.0 and 2.1, which share its layout).
    V2,
    /// MSH 4.1.
    V4_1,
}

/// A node: its tag and coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MshNode {
    /// The node's tag (its number in the file; tags may come in any order and have gaps).
    pub tag: u64,
    /// Its coordinates x, y, z.
    pub xyz: [f64; 3],
}

/// An element: its tag, Gmsh type number, entity and nodes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MshElement {
    /// The element's tag.
    pub tag: u64,
    /// Gmsh's element type number (1: 2-node line, 2: 3-node triangle, 3: 4-node quadrangle,
    /// 15: point, ...); see [`element_type_name`].
    pub element_type: i32,
    /// Dimension of the entity the element belongs to (the dimension of its type in MSH 2.2).
    pub entity_dim: i32,
    /// Tag of the entity the element belongs to (the elementary tag in MSH 2.2).
    pub entity_tag: i32,
    /// Tags of its nodes, in Gmsh's local order.
    pub nodes: Vec<u64>,
}

/// A geometric entity (point, curve, surface, volume) and the physical groups it belongs to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MshEntity {
    /// Its dimension, 0 to 3.
    pub dim: i32,
    /// Its tag.
    pub tag: i32,
    /// The physical groups (of the same dimension) it belongs to, as positive tags in
    /// increasing order.
    pub physical_tags: Vec<i32>,
}

/// The contents of a `.msh` file.
///
/// In MSH 2.2 files, which have no `$Entities` section, the entities are those the elements
/// name (dimension of the element type, elementary tag), and each carries the physical tags of
/// its elements, as Gmsh's own reader builds them.
#[derive(Debug, Clone, PartialEq)]
pub struct MshFile {
    /// The format version.
    pub version: MshVersion,
    /// Whether the file is binary.
    pub binary: bool,
    /// The nodes, in file order.
    pub nodes: Vec<MshNode>,
    /// The elements, in file order.
    pub elements: Vec<MshElement>,
    /// The entities, in increasing order of (dimension, tag).
    pub entities: Vec<MshEntity>,
    /// Physical names: (dimension, physical tag) -> name.
    pub physical_names: BTreeMap<(i32, i32), String>,
}

impl MshFile {
    /// The physical groups as (dimension, physical tag) -> tags of the entities in the group,
    /// each list in increasing order. Groups that only have a name (no entity) are not listed.
    pub fn physical_groups(&self) -> BTreeMap<(i32, i32), Vec<i32>> {
        let mut groups: BTreeMap<(i32, i32), Vec<i32>> = BTreeMap::new();
        for entity in &self.entities {
            for &physical in &entity.physical_tags {
                groups
                    .entry((entity.dim, physical))
                    .or_default()
                    .push(entity.tag);
            }
        }
        groups
    }
}

/// Where in a `.msh` file a problem is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MshLocation {
    /// A line of ASCII text, counted from 1.
    Line(usize),
    /// A byte offset into binary data, counted from 0.
    Byte(usize),
}

impl fmt::Display for MshLocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MshLocation::Line(line) => write!(f, "line {line}"),
            MshLocation::Byte(offset) => write!(f, "byte {offset}"),
        }
    }
}

/// A malformed or unsupported `.msh` file: where, in which section, and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{location}{}: {reason}", section_suffix(.section))]
pub struct MshError {
    /// Where the problem is.
    pub location: MshLocation,
    /// The section it is in (`$Nodes`, ...), empty outside any section.
    pub section: String,
    /// What is wrong.
    pub reason: String,
}

fn section_suffix(section: &str) -> String {
    if section.is_empty() {
        String::new()
    } else {
        format!(" (in {section})")
    }
}

/// Gmsh's name and number of nodes of element type `element_type`, `None` for a number that
/// is not a Gmsh element type this reader knows.
///
/// ```
/// assert_eq!(vem_mesh::io::element_type_name(9), Some(("Tri6", 6)));
/// assert_eq!(vem_mesh::io::element_type_name(1000), None);
/// ```
pub fn element_type_name(element_type: i32) -> Option<(&'static str, usize)> {
    element_type_info(element_type).map(|(name, nodes, _)| (name, nodes))
}

/// Name, number of nodes and dimension of an element type.
fn element_type_info(element_type: i32) -> Option<(&'static str, usize, i32)> {
    Some(match element_type {
        1 => ("Lin2", 2, 1),
        2 => ("Tri3", 3, 2),
        3 => ("Qua4", 4, 2),
        4 => ("Tet4", 4, 3),
        5 => ("Hex8", 8, 3),
        6 => ("Pri6", 6, 3),
        7 => ("Pyr5", 5, 3),
        8 => ("Lin3", 3, 1),
        9 => ("Tri6", 6, 2),
        10 => ("Qua9", 9, 2),
        11 => ("Tet10", 10, 3),
        12 => ("Hex27", 27, 3),
        13 => ("Pri18", 18, 3),
        14 => ("Pyr14", 14, 3),
        15 => ("Pnt", 1, 0),
        16 => ("Qua8", 8, 2),
        17 => ("Hex20", 20, 3),
        18 => ("Pri15", 15, 3),
        19 => ("Pyr13", 13, 3),
        20 => ("Tri9", 9, 2),
        21 => ("Tri10", 10, 2),
        22 => ("Tri12", 12, 2),
        23 => ("Tri15", 15, 2),
        24 => ("Tri15i", 15, 2),
        25 => ("Tri21", 21, 2),
        26 => ("Lin4", 4, 1),
        27 => ("Lin5", 5, 1),
        28 => ("Lin6", 6, 1),
        29 => ("Tet20", 20, 3),
        30 => ("Tet35", 35, 3),
        31 => ("Tet56", 56, 3),
        36 => ("Qua16", 16, 2),
        37 => ("Qua25", 25, 2),
        38 => ("Qua36", 36, 2),
        _ => return None,
    })
}

/// Reads the contents of a `.msh` file (MSH 4.1 or 2.2, ASCII or binary).
///
/// ```
/// let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n\
///             $Nodes\n3\n7 0 0 0\n3 1 0 0\n5 0 1 0\n$EndNodes\n\
///             $Elements\n1\n1 2 2 0 1 7 3 5\n$EndElements\n";
/// let msh = vem_mesh::io::read_msh_bytes(text.as_bytes())?;
/// assert_eq!(msh.nodes.iter().map(|n| n.tag).collect::<Vec<_>>(), [7, 3, 5]);
/// assert_eq!(msh.elements[0].nodes, [7, 3, 5]);
/// # Ok::<(), vem_mesh::io::MshError>(())
/// ```
pub fn read_msh_bytes(bytes: &[u8]) -> Result<MshFile, MshError> {
    Parser::new(bytes).file()
}

/// Smallest number of bytes one item takes in ASCII text (a number and a separator).
const MIN_ASCII_ITEM: usize = 2;

/// A reading position in the file.
struct Parser<'a> {
    bytes: &'a [u8],
    pos: usize,
    section: &'static str,
    binary: bool,
    /// Whether binary numbers are stored in the other byte order than this machine's.
    swap: bool,
}

/// The value of one binary number.
trait Binary: Sized {
    const SIZE: usize;
    fn from_bytes(bytes: &[u8], swap: bool) -> Self;
}

macro_rules! binary {
    ($($t:ty),*) => {$(
        impl Binary for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            fn from_bytes(bytes: &[u8], swap: bool) -> Self {
                let mut raw = [0u8; std::mem::size_of::<$t>()];
                raw.copy_from_slice(bytes);
                if swap {
                    raw.reverse();
                }
                <$t>::from_ne_bytes(raw)
            }
        }
    )*};
}
binary!(i32, u64, f64);

/// A number read from the bytes of one token of ASCII text, accepting what `str::parse`
/// accepts; integers are read from the bytes directly, without a text conversion.
trait Ascii: Sized {
    fn parse_ascii(token: &[u8]) -> Option<Self>;
}

/// The digits of an unsigned decimal integer (an optional `+`, then at least one digit).
fn decimal_u64(token: &[u8]) -> Option<u64> {
    let digits = token.strip_prefix(b"+").unwrap_or(token);
    if digits.is_empty() {
        return None;
    }
    let mut value: u64 = 0;
    for &c in digits {
        let digit = c.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_add(u64::from(digit))?;
    }
    Some(value)
}

impl Ascii for u64 {
    fn parse_ascii(token: &[u8]) -> Option<Self> {
        decimal_u64(token)
    }
}

impl Ascii for i32 {
    fn parse_ascii(token: &[u8]) -> Option<Self> {
        match token.strip_prefix(b"-") {
            Some(digits) if !digits.starts_with(b"+") => {
                let magnitude = i64::try_from(decimal_u64(digits)?).ok()?;
                i32::try_from(-magnitude).ok()
            }
            Some(_) => None,
            None => i32::try_from(decimal_u64(token)?).ok(),
        }
    }
}

impl Ascii for f64 {
    fn parse_ascii(token: &[u8]) -> Option<Self> {
        f64::from_str(std::str::from_utf8(token).ok()?).ok()
    }
}

/// A set of tags (of nodes or elements): a bit per tag below a bound proportional to the
/// number of items (Gmsh numbers them densely), a hash set above it.
struct TagSet {
    bits: Vec<u64>,
    others: HashSet<u64>,
}

impl TagSet {
    /// A set for about `items` tags.
    fn with_capacity(items: usize) -> Self {
        TagSet {
            bits: vec![0; (items.saturating_mul(8).saturating_add(1024)) / 64 + 1],
            others: HashSet::new(),
        }
    }

    /// Adds `tag`; false when it was there already.
    fn insert(&mut self, tag: u64) -> bool {
        let (word, bit) = ((tag / 64) as usize, tag % 64);
        match self.bits.get_mut(word) {
            Some(w) => {
                let new = *w & (1 << bit) == 0;
                *w |= 1 << bit;
                new
            }
            None => self.others.insert(tag),
        }
    }
}

impl<'a> Parser<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Parser {
            bytes,
            pos: 0,
            section: "",
            binary: false,
            swap: false,
        }
    }

    /// An error at byte `at`: located by line in text, by byte offset in binary data.
    fn error_at(&self, at: usize, binary: bool, reason: impl Into<String>) -> MshError {
        let at = at.min(self.bytes.len());
        let location = if binary {
            MshLocation::Byte(at)
        } else {
            MshLocation::Line(self.bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1)
        };
        MshError {
            location,
            section: self.section.to_string(),
            reason: reason.into(),
        }
    }

    /// An error at the current position, in text.
    fn error(&self, reason: impl Into<String>) -> MshError {
        self.error_at(self.pos, false, reason)
    }

    /// The position of the next item: in text, after any whitespace.
    fn mark(&mut self) -> usize {
        if !self.binary {
            self.skip_whitespace();
        }
        self.pos
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn skip_whitespace(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The next whitespace-separated token and its start, or an error at the end of the file.
    fn token(&mut self, what: &str) -> Result<(&'a str, usize), MshError> {
        let (token, start) = self.token_bytes(what)?;
        match std::str::from_utf8(token) {
            Ok(token) => Ok((token, start)),
            Err(_) => Err(self.not_text(start, what)),
        }
    }

    /// The bytes of the next whitespace-separated token and its start, or an error at the end
    /// of the file.
    fn token_bytes(&mut self, what: &str) -> Result<(&'a [u8], usize), MshError> {
        let bytes = self.bytes;
        let mut pos = self.pos;
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        self.pos = pos;
        if start == pos {
            return Err(self.error(format!("the file ends where {what} was expected")));
        }
        Ok((&bytes[start..pos], start))
    }

    /// The error for a token at `start` that is not text.
    fn not_text(&self, start: usize, what: &str) -> MshError {
        self.error_at(
            start,
            false,
            format!("expected {what}, found bytes that are not text"),
        )
    }

    /// The error for a token that is not the number expected.
    fn not_a_number(&self, token: &[u8], start: usize, what: &str) -> MshError {
        match std::str::from_utf8(token) {
            Ok(text) => self.error_at(
                start,
                false,
                format!("expected {what}, found '{}'", shorten(text)),
            ),
            Err(_) => self.not_text(start, what),
        }
    }

    /// The next token parsed as a number of type `T`.
    fn number<T: Ascii>(&mut self, what: &str) -> Result<T, MshError> {
        let (token, start) = self.token_bytes(what)?;
        T::parse_ascii(token).ok_or_else(|| self.not_a_number(token, start, what))
    }

    /// The next token as coordinate `k` (0, 1, 2: x, y, z) of node `tag`, which must be finite.
    fn coordinate(&mut self, tag: u64, k: usize) -> Result<f64, MshError> {
        let (token, start) = self.token_bytes("a node coordinate")?;
        match f64::parse_ascii(token) {
            Some(value) if value.is_finite() => Ok(value),
            _ => match std::str::from_utf8(token) {
                Ok(text) => Err(self.error_at(
                    start,
                    false,
                    format!(
                        "expected coordinate {} of node {tag} (a finite number), found '{}'",
                        ["x", "y", "z"][k],
                        shorten(text)
                    ),
                )),
                Err(_) => Err(self.not_text(start, "a node coordinate")),
            },
        }
    }

    /// A count of items announced by a header, checked against the bytes that remain.
    fn count(&mut self, what: &str, item_bytes: usize) -> Result<usize, MshError> {
        let (token, start) = self.token_bytes(what)?;
        let count = u64::parse_ascii(token).ok_or_else(|| self.not_a_number(token, start, what))?;
        self.check_count(count, start, false, what, item_bytes)
    }

    fn check_count(
        &self,
        count: u64,
        at: usize,
        binary: bool,
        what: &str,
        item_bytes: usize,
    ) -> Result<usize, MshError> {
        let fits = usize::try_from(count).ok().filter(|&c| {
            c.checked_mul(item_bytes)
                .is_some_and(|b| b <= self.remaining())
        });
        fits.ok_or_else(|| {
            self.error_at(
                at,
                binary,
                format!(
                    "{what} is {count}, more than the remaining {} bytes of the file can hold",
                    self.remaining()
                ),
            )
        })
    }

    /// The next number of type `T`: binary or text, as the file is.
    fn value<T: Binary + Ascii>(&mut self, what: &str) -> Result<T, MshError> {
        if self.binary {
            self.binary(what)
        } else {
            self.number(what)
        }
    }

    /// One binary number.
    fn binary<T: Binary>(&mut self, what: &str) -> Result<T, MshError> {
        if self.remaining() < T::SIZE {
            return Err(self.error_at(
                self.pos,
                true,
                format!("the file ends where {what} was expected"),
            ));
        }
        let value = T::from_bytes(&self.bytes[self.pos..self.pos + T::SIZE], self.swap);
        self.pos += T::SIZE;
        Ok(value)
    }

    /// A binary count of items of `item_bytes` bytes each, checked against the remaining bytes.
    fn binary_count(&mut self, what: &str, item_bytes: usize) -> Result<usize, MshError> {
        let at = self.mark();
        let count: u64 = self.binary(what)?;
        self.check_count(count, at, true, what, item_bytes)
    }

    /// A binary `int` tag of a 2.2 file, which must be positive.
    fn binary_tag_i32(&mut self, what: &str) -> Result<i32, MshError> {
        let at = self.mark();
        let value: i32 = self.binary(what)?;
        if value < 0 {
            return Err(self.error_at(at, true, format!("{what} is negative ({value})")));
        }
        Ok(value)
    }

    /// Binary coordinate `k` (0, 1, 2: x, y, z) of node `tag`, which must be finite.
    fn binary_coordinate(&mut self, tag: u64, k: usize) -> Result<f64, MshError> {
        let at = self.pos;
        let value: f64 = self.binary("a node coordinate")?;
        if !value.is_finite() {
            return Err(self.error_at(
                at,
                true,
                format!(
                    "coordinate {} of node {tag} is not finite ({value})",
                    ["x", "y", "z"][k]
                ),
            ));
        }
        Ok(value)
    }

    /// The rest of the current line (without its end), advancing past it.
    fn line(&mut self) -> &'a [u8] {
        let start = self.pos;
        let end = self.bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.bytes.len(), |i| start + i);
        self.pos = (end + 1).min(self.bytes.len());
        let line = &self.bytes[start..end];
        line.strip_suffix(b"\r").unwrap_or(line)
    }

    /// Expects the end marker `$End<name>` of the current section.
    fn end_marker(&mut self, name: &str) -> Result<(), MshError> {
        self.skip_whitespace();
        let start = self.pos;
        let line = self.line();
        let expected = format!("$End{name}");
        if trim(line) != expected.as_bytes() {
            return Err(self.error_at(
                start,
                false,
                format!(
                    "expected {expected}, found '{}'",
                    shorten(&String::from_utf8_lossy(trim(line)))
                ),
            ));
        }
        Ok(())
    }

    fn file(mut self) -> Result<MshFile, MshError> {
        let mut version = None;
        let mut nodes: Option<Vec<MshNode>> = None;
        let mut elements: Option<Vec<MshElement>> = None;
        let mut entities: Option<Vec<MshEntity>> = None;
        let mut physical_names = BTreeMap::new();
        // MSH 2.2: (dim, elementary tag) -> physical tags of its elements.
        let mut entities_v2: BTreeMap<(i32, i32), Vec<i32>> = BTreeMap::new();
        loop {
            self.section = "";
            self.skip_whitespace();
            if self.pos >= self.bytes.len() {
                break;
            }
            let start = self.pos;
            let line = trim(self.line());
            let Some(name) = line.strip_prefix(b"$") else {
                return Err(self.error_at(
                    start,
                    false,
                    format!(
                        "expected a section header such as $Nodes, found '{}'",
                        shorten(&String::from_utf8_lossy(line))
                    ),
                ));
            };
            let name = String::from_utf8_lossy(name).into_owned();
            if version.is_none() && name != "MeshFormat" {
                return Err(self.error_at(
                    start,
                    false,
                    format!(
                        "the file must begin with $MeshFormat, found '${}'",
                        shorten(&name)
                    ),
                ));
            }
            let repeated = |parser: &Self, already: bool, section: &'static str| {
                if already {
                    Err(parser.error_at(start, false, format!("a second {section} section")))
                } else {
                    Ok(())
                }
            };
            match name.as_str() {
                "MeshFormat" => {
                    self.section = "$MeshFormat";
                    repeated(&self, version.is_some(), "$MeshFormat")?;
                    version = Some(self.mesh_format()?);
                    self.end_marker("MeshFormat")?;
                }
                "PhysicalNames" => {
                    self.section = "$PhysicalNames";
                    self.physical_names(&mut physical_names)?;
                    self.end_marker("PhysicalNames")?;
                }
                "Entities" => {
                    self.section = "$Entities";
                    repeated(&self, entities.is_some(), "$Entities")?;
                    if version == Some(MshVersion::V2) {
                        return Err(self.error_at(
                            start,
                            false,
                            "an $Entities section in an MSH 2 file (it belongs to MSH 4.1)",
                        ));
                    }
                    entities = Some(self.entities()?);
                    self.end_marker("Entities")?;
                }
                "PartitionedEntities" => {
                    self.section = "$PartitionedEntities";
                    return Err(self.error_at(
                        start,
                        false,
                        "partitioned meshes are not supported; save the mesh without \
                         partitions (Mesh.PartitionSplitMeshFiles = 0, no -part)",
                    ));
                }
                "Nodes" => {
                    self.section = "$Nodes";
                    repeated(&self, nodes.is_some(), "$Nodes")?;
                    nodes = Some(match version {
                        Some(MshVersion::V4_1) => self.nodes_v4()?,
                        _ => self.nodes_v2()?,
                    });
                    self.end_marker("Nodes")?;
                }
                "Elements" => {
                    self.section = "$Elements";
                    repeated(&self, elements.is_some(), "$Elements")?;
                    elements = Some(match version {
                        Some(MshVersion::V4_1) => self.elements_v4()?,
                        _ => self.elements_v2(&mut entities_v2)?,
                    });
                    self.end_marker("Elements")?;
                }
                _ => self.skip_section(&name, start)?,
            }
        }
        let Some(version) = version else {
            return Err(self.error_at(0, false, "the file is empty (no $MeshFormat section)"));
        };
        let elements = elements.unwrap_or_default();
        let entities = match version {
            MshVersion::V4_1 => {
                let mut entities = entities.unwrap_or_default();
                entities.sort_by_key(|e| (e.dim, e.tag));
                entities
            }
            MshVersion::V2 => {
                for element in &elements {
                    entities_v2
                        .entry((element.entity_dim, element.entity_tag))
                        .or_default();
                }
                entities_v2
                    .into_iter()
                    .map(|((dim, tag), mut physical_tags)| {
                        physical_tags.sort_unstable();
                        physical_tags.dedup();
                        MshEntity {
                            dim,
                            tag,
                            physical_tags,
                        }
                    })
                    .collect()
            }
        };
        Ok(MshFile {
            version,
            binary: self.binary,
            nodes: nodes.unwrap_or_default(),
            elements,
            entities,
            physical_names,
        })
    }

    /// Skips an unknown section up to its end marker, as Gmsh does.
    fn skip_section(&mut self, name: &str, start: usize) -> Result<(), MshError> {
        let marker = format!("$End{name}");
        let mut at = self.pos;
        while at < self.bytes.len() {
            let rest = &self.bytes[at..];
            let line_end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            if trim(&rest[..line_end]) == marker.as_bytes() {
                self.pos = (at + line_end + 1).min(self.bytes.len());
                return Ok(());
            }
            at += line_end + 1;
        }
        Err(self.error_at(
            start,
            false,
            format!("section ${} has no end marker {marker}", shorten(name)),
        ))
    }

    fn mesh_format(&mut self) -> Result<MshVersion, MshError> {
        let (token, start) = self.token("the format version")?;
        let version = match token {
            "4.1" => MshVersion::V4_1,
            "2" | "2.0" | "2.1" | "2.2" => MshVersion::V2,
            other => {
                return Err(self.error_at(
                    start,
                    false,
                    format!(
                        "MSH format version '{}' is not supported (only 4.1 and 2.2); convert \
                         the file with `gmsh FILE -save -format msh41 -o NEW.msh`",
                        shorten(other)
                    ),
                ))
            }
        };
        let (file_type, start) = self.token("the file type (0: ASCII, 1: binary)")?;
        self.binary = match file_type {
            "0" => false,
            "1" => true,
            other => {
                return Err(self.error_at(
                    start,
                    false,
                    format!(
                        "expected the file type 0 (ASCII) or 1 (binary), found '{}'",
                        shorten(other)
                    ),
                ))
            }
        };
        let (data_size, start) = self.token("the data size")?;
        // Gmsh checks the data size (the size of `size_t`) only in binary files.
        if self.binary && data_size != "8" {
            return Err(self.error_at(
                start,
                false,
                format!(
                    "binary files with data size '{}' are not supported (only 8)",
                    shorten(data_size)
                ),
            ));
        }
        if !self.binary && data_size.parse::<u64>().is_err() {
            return Err(self.error_at(
                start,
                false,
                format!("expected the data size, found '{}'", shorten(data_size)),
            ));
        }
        if self.binary {
            // The integer 1, written in the byte order of the writer, after the line's end.
            self.line();
            let at = self.mark();
            let one: i32 = self.binary("the byte-order mark (the integer 1)")?;
            if one == 1 {
                self.swap = false;
            } else if one.swap_bytes() == 1 {
                self.swap = true;
            } else {
                return Err(self.error_at(
                    at,
                    true,
                    format!("the byte-order mark is {one}, not 1 in either byte order"),
                ));
            }
        }
        Ok(version)
    }

    fn physical_names(&mut self, names: &mut BTreeMap<(i32, i32), String>) -> Result<(), MshError> {
        let count = self.count("the number of physical names", 3 * MIN_ASCII_ITEM)?;
        // The count is followed by the end of its line.
        self.line();
        for _ in 0..count {
            self.skip_whitespace();
            let start = self.pos;
            let line = self.line();
            let entry = String::from_utf8_lossy(line);
            let (dim, tag, name) = parse_physical_name(&entry).ok_or_else(|| {
                self.error_at(
                    start,
                    false,
                    format!(
                        "expected 'dimension tag \"name\"', found '{}'",
                        shorten(entry.trim())
                    ),
                )
            })?;
            if !(0..=3).contains(&dim) || tag <= 0 {
                return Err(self.error_at(
                    start,
                    false,
                    format!("physical name '{name}' has dimension {dim} and tag {tag}; the dimension must be 0 to 3 and the tag positive"),
                ));
            }
            names.insert((dim, tag), name);
        }
        Ok(())
    }

    /// A physical tag list of an entity: count, then tags (made positive), sorted.
    fn physical_tag_list(&mut self, what: &str) -> Result<Vec<i32>, MshError> {
        let count = if self.binary {
            self.binary_count(&format!("the number of physical tags of {what}"), 4)?
        } else {
            self.count(
                &format!("the number of physical tags of {what}"),
                MIN_ASCII_ITEM,
            )?
        };
        let mut tags = Vec::with_capacity(count);
        for _ in 0..count {
            let tag: i32 = self.value("a physical tag")?;
            // Gmsh writes a negative tag for a group that uses the entity reversed.
            tags.push(tag.checked_abs().unwrap_or(i32::MAX));
        }
        tags.sort_unstable();
        tags.dedup();
        Ok(tags)
    }

    fn entities(&mut self) -> Result<Vec<MshEntity>, MshError> {
        let mut counts = [0usize; 4];
        for (dim, count) in counts.iter_mut().enumerate() {
            let what = format!("the number of entities of dimension {dim}");
            *count = if self.binary {
                self.binary_count(&what, 4 + 4 * 8)?
            } else {
                self.count(&what, 5 * MIN_ASCII_ITEM)?
            };
        }
        let mut entities = Vec::with_capacity(counts.iter().sum());
        let mut seen = HashSet::new();
        for (dim, &count) in counts.iter().enumerate() {
            let dim = dim as i32;
            for _ in 0..count {
                let at = self.mark();
                let tag: i32 = self.value("an entity tag")?;
                let what = format!("entity ({dim}, {tag})");
                // A point has its coordinates, other entities their bounding box.
                let n_reals = if dim == 0 { 3 } else { 6 };
                for _ in 0..n_reals {
                    self.value::<f64>("a coordinate of the entity")?;
                }
                let physical_tags = self.physical_tag_list(&what)?;
                if dim > 0 {
                    let n_bounding = if self.binary {
                        self.binary_count(&format!("the number of bounding entities of {what}"), 4)?
                    } else {
                        self.count(
                            &format!("the number of bounding entities of {what}"),
                            MIN_ASCII_ITEM,
                        )?
                    };
                    for _ in 0..n_bounding {
                        self.value::<i32>("a bounding entity tag")?;
                    }
                }
                if !seen.insert((dim, tag)) {
                    return Err(self.error_at(at, self.binary, format!("{what} is defined twice")));
                }
                entities.push(MshEntity {
                    dim,
                    tag,
                    physical_tags,
                });
            }
        }
        Ok(entities)
    }

    /// The header of a `$Nodes` or `$Elements` section of MSH 4.1 (`what` = "node" or
    /// "element"): the number of blocks and of items, each bounded by the bytes left at the
    /// least size of one (`block_bytes`, `item_bytes`), then the smallest and largest tags.
    fn section_header_v4(
        &mut self,
        what: &str,
        block_bytes: usize,
        item_bytes: usize,
    ) -> Result<(usize, usize), MshError> {
        let blocks = format!("the number of {what} blocks");
        let items = format!("the number of {what}s");
        let smallest = format!("the smallest {what} tag");
        let largest = format!("the largest {what} tag");
        let (n_blocks, n_items) = if self.binary {
            (
                self.binary_count(&blocks, block_bytes)?,
                self.binary_count(&items, item_bytes)?,
            )
        } else {
            (
                self.count(&blocks, block_bytes)?,
                self.count(&items, item_bytes)?,
            )
        };
        self.value::<u64>(&smallest)?;
        self.value::<u64>(&largest)?;
        Ok((n_blocks, n_items))
    }

    fn nodes_v4(&mut self) -> Result<Vec<MshNode>, MshError> {
        // Every node takes at least a tag and three coordinates.
        let node_bytes = if self.binary {
            8 + 3 * 8
        } else {
            4 * MIN_ASCII_ITEM
        };
        let block_bytes = if self.binary {
            3 * 4 + 8
        } else {
            4 * MIN_ASCII_ITEM
        };
        let (n_blocks, n_nodes) = self.section_header_v4("node", block_bytes, node_bytes)?;
        let mut nodes = Vec::with_capacity(n_nodes);
        let mut seen = TagSet::with_capacity(n_nodes);
        for _ in 0..n_blocks {
            let block_start = self.mark();
            let (dim, tag, parametric, count) = if self.binary {
                let dim: i32 = self.binary("the entity dimension of a node block")?;
                let tag: i32 = self.binary("the entity tag of a node block")?;
                let parametric: i32 = self.binary("the parametric flag of a node block")?;
                let count = self.binary_count("the number of nodes in the block", node_bytes)?;
                (dim, tag, parametric, count)
            } else {
                let dim: i32 = self.number("the entity dimension of a node block")?;
                let tag: i32 = self.number("the entity tag of a node block")?;
                let parametric: i32 =
                    self.number("the parametric flag of a node block (0 or 1)")?;
                let count = self.count("the number of nodes in the block", node_bytes)?;
                (dim, tag, parametric, count)
            };
            if !(0..=3).contains(&dim) || !(0..=1).contains(&parametric) {
                return Err(self.error_at(
                    block_start,
                    self.binary,
                    format!(
                        "node block of entity ({dim}, {tag}) has dimension {dim} and parametric \
                         flag {parametric}; expected a dimension 0 to 3 and a flag 0 or 1"
                    ),
                ));
            }
            if nodes.len() + count > n_nodes {
                return Err(self.error_at(
                    block_start,
                    self.binary,
                    format!(
                        "the node blocks hold more nodes than the {n_nodes} the section header \
                         announces"
                    ),
                ));
            }
            // Parametric coordinates follow x, y, z: u on curves, u and v on surfaces.
            let n_parametric = if parametric == 1 && (dim == 1 || dim == 2) {
                dim as usize
            } else {
                0
            };
            let first = nodes.len();
            for _ in 0..count {
                let at = self.mark();
                let tag: u64 = self.value("a node tag")?;
                if !seen.insert(tag) {
                    return Err(self.error_at(
                        at,
                        self.binary,
                        format!("node tag {tag} is defined twice"),
                    ));
                }
                nodes.push(MshNode { tag, xyz: [0.0; 3] });
            }
            for node in &mut nodes[first..] {
                for (k, value) in node.xyz.iter_mut().enumerate() {
                    *value = if self.binary {
                        self.binary_coordinate(node.tag, k)?
                    } else {
                        self.coordinate(node.tag, k)?
                    };
                }
                for _ in 0..n_parametric {
                    self.value::<f64>("a parametric coordinate")?;
                }
            }
        }
        if nodes.len() != n_nodes {
            return Err(self.error(format!(
                "the node blocks hold {} nodes, but the section header announces {n_nodes}",
                nodes.len()
            )));
        }
        Ok(nodes)
    }

    fn elements_v4(&mut self) -> Result<Vec<MshElement>, MshError> {
        // Every element takes at least a tag and one node tag.
        let element_bytes = if self.binary {
            2 * 8
        } else {
            2 * MIN_ASCII_ITEM
        };
        let block_bytes = if self.binary {
            3 * 4 + 8
        } else {
            4 * MIN_ASCII_ITEM
        };
        let (n_blocks, n_elements) =
            self.section_header_v4("element", block_bytes, element_bytes)?;
        let mut elements = Vec::with_capacity(n_elements);
        let mut seen = TagSet::with_capacity(n_elements);
        for _ in 0..n_blocks {
            let block_start = self.mark();
            let (dim, entity_tag, element_type) = if self.binary {
                let dim: i32 = self.binary("the entity dimension of an element block")?;
                let tag: i32 = self.binary("the entity tag of an element block")?;
                let element_type: i32 = self.binary("the element type of an element block")?;
                (dim, tag, element_type)
            } else {
                let dim: i32 = self.number("the entity dimension of an element block")?;
                let tag: i32 = self.number("the entity tag of an element block")?;
                let element_type: i32 = self.number("the element type of an element block")?;
                (dim, tag, element_type)
            };
            let (name, n_nodes, type_dim) = element_type_info(element_type).ok_or_else(|| {
                self.error_at(
                    block_start,
                    self.binary,
                    format!("element block of entity ({dim}, {entity_tag}) has element type {element_type}, which is not a known Gmsh element type"),
                )
            })?;
            if dim != type_dim {
                return Err(self.error_at(
                    block_start,
                    self.binary,
                    format!("element block of entity ({dim}, {entity_tag}) holds elements of type {element_type} ({name}), which have dimension {type_dim}"),
                ));
            }
            let element_bytes = if self.binary {
                8 * (1 + n_nodes)
            } else {
                MIN_ASCII_ITEM * (1 + n_nodes)
            };
            let count = if self.binary {
                self.binary_count("the number of elements in the block", element_bytes)?
            } else {
                self.count("the number of elements in the block", element_bytes)?
            };
            if elements.len() + count > n_elements {
                return Err(self.error_at(
                    block_start,
                    self.binary,
                    format!(
                        "the element blocks hold more elements than the {n_elements} the \
                         section header announces"
                    ),
                ));
            }
            for _ in 0..count {
                let at = self.mark();
                let tag: u64 = self.value("an element tag")?;
                if !seen.insert(tag) {
                    return Err(self.error_at(
                        at,
                        self.binary,
                        format!("element tag {tag} is defined twice"),
                    ));
                }
                let mut nodes = Vec::with_capacity(n_nodes);
                for _ in 0..n_nodes {
                    nodes.push(self.value("a node tag of an element")?);
                }
                elements.push(MshElement {
                    tag,
                    element_type,
                    entity_dim: dim,
                    entity_tag,
                    nodes,
                });
            }
        }
        if elements.len() != n_elements {
            return Err(self.error(format!(
                "the element blocks hold {} elements, but the section header announces \
                 {n_elements}",
                elements.len()
            )));
        }
        Ok(elements)
    }

    fn nodes_v2(&mut self) -> Result<Vec<MshNode>, MshError> {
        let node_bytes = if self.binary {
            4 + 3 * 8
        } else {
            4 * MIN_ASCII_ITEM
        };
        // The count is ASCII text even in binary files, on its own line.
        let n_nodes = self.count("the number of nodes", node_bytes)?;
        if self.binary {
            self.line();
        }
        let mut nodes = Vec::with_capacity(n_nodes);
        let mut seen = TagSet::with_capacity(n_nodes);
        for _ in 0..n_nodes {
            let at = self.mark();
            let tag: u64 = if self.binary {
                self.binary_tag_i32("a node tag")? as u64
            } else {
                self.number("a node tag")?
            };
            if !seen.insert(tag) {
                return Err(self.error_at(
                    at,
                    self.binary,
                    format!("node tag {tag} is defined twice"),
                ));
            }
            let mut xyz = [0.0; 3];
            for (k, value) in xyz.iter_mut().enumerate() {
                *value = if self.binary {
                    self.binary_coordinate(tag, k)?
                } else {
                    self.coordinate(tag, k)?
                };
            }
            nodes.push(MshNode { tag, xyz });
        }
        Ok(nodes)
    }

    fn elements_v2(
        &mut self,
        entities: &mut BTreeMap<(i32, i32), Vec<i32>>,
    ) -> Result<Vec<MshElement>, MshError> {
        // Every element takes at least a tag, a type, a tag count and one node.
        let element_bytes = if self.binary {
            2 * 4
        } else {
            4 * MIN_ASCII_ITEM
        };
        let n_elements = self.count("the number of elements", element_bytes)?;
        if self.binary {
            self.line();
        }
        let mut elements = Vec::with_capacity(n_elements);
        let mut seen = TagSet::with_capacity(n_elements);
        // Binary files group elements under headers (type, count, number of tags).
        let mut group: (i32, usize, usize) = (0, 0, 0);
        while elements.len() < n_elements {
            let (element_type, n_tags, tag, at) = if self.binary {
                if group.1 == 0 {
                    let at = self.mark();
                    let element_type: i32 = self.binary("the element type of a group")?;
                    let count = self.binary_tag_i32("the number of elements of a group")? as usize;
                    let n_tags = self.binary_tag_i32("the number of tags of a group")? as usize;
                    if count == 0 || elements.len() + count > n_elements {
                        return Err(self.error_at(
                            at,
                            true,
                            format!(
                                "an element group of {count} elements, where {} remain of the \
                                 {n_elements} announced",
                                n_elements - elements.len()
                            ),
                        ));
                    }
                    group = (element_type, count, n_tags);
                }
                group.1 -= 1;
                let at = self.mark();
                let tag = self.binary_tag_i32("an element tag")? as u64;
                (group.0, group.2, tag, at)
            } else {
                self.skip_whitespace();
                let at = self.mark();
                let tag: u64 = self.number("an element tag")?;
                let element_type: i32 = self.number("an element type")?;
                let n_tags = self.count("the number of tags of an element", MIN_ASCII_ITEM)?;
                (element_type, n_tags, tag, at)
            };
            let (name, n_nodes, dim) = element_type_info(element_type).ok_or_else(|| {
                self.error_at(
                    at,
                    self.binary,
                    format!("element {tag} has element type {element_type}, which is not a known Gmsh element type"),
                )
            })?;
            if self.binary {
                self.check_count(
                    (n_tags + n_nodes) as u64,
                    at,
                    true,
                    &format!("the number of tags and nodes of element {tag}"),
                    4,
                )?;
            }
            let mut tags = Vec::with_capacity(n_tags);
            for _ in 0..n_tags {
                tags.push(if self.binary {
                    self.binary::<i32>("an element's tag")?
                } else {
                    self.number::<i32>("an element's tag")?
                });
            }
            let mut nodes = Vec::with_capacity(n_nodes);
            for _ in 0..n_nodes {
                nodes.push(if self.binary {
                    self.binary_tag_i32("a node tag of an element")? as u64
                } else {
                    self.number("a node tag of an element")?
                });
            }
            if !seen.insert(tag) {
                return Err(self.error_at(
                    at,
                    self.binary,
                    format!("element tag {tag} ({name}) is defined twice"),
                ));
            }
            // Tags: physical group, elementary entity, then partitions (ignored).
            let physical = tags.first().copied().unwrap_or(0);
            let entity_tag = tags.get(1).copied().unwrap_or(0);
            let physicals = entities.entry((dim, entity_tag)).or_default();
            if physical != 0 {
                physicals.push(physical.checked_abs().unwrap_or(i32::MAX));
            }
            elements.push(MshElement {
                tag,
                element_type,
                entity_dim: dim,
                entity_tag,
                nodes,
            });
        }
        if self.binary && group.1 != 0 {
            return Err(self.error_at(
                self.pos,
                true,
                "an element group holds more elements than the section announces",
            ));
        }
        Ok(elements)
    }
}

/// `line` without leading and trailing ASCII whitespace.
fn trim(line: &[u8]) -> &[u8] {
    let start = line
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(line.len());
    let end = line
        .iter()
        .rposition(|b| !b.is_ascii_whitespace())
        .map_or(start, |i| i + 1);
    &line[start..end]
}

/// At most 40 characters of `text`, for error messages.
fn shorten(text: &str) -> String {
    const MAX: usize = 40;
    if text.chars().count() <= MAX {
        text.to_string()
    } else {
        let head: String = text.chars().take(MAX).collect();
        format!("{head}...")
    }
}

/// Parses `dim tag "name"` (the name may contain spaces).
fn parse_physical_name(entry: &str) -> Option<(i32, i32, String)> {
    let entry = entry.trim();
    let mut fields = entry.splitn(3, char::is_whitespace);
    let dim = fields.next()?.parse().ok()?;
    let tag = fields.next()?.parse().ok()?;
    let name = fields.next()?.trim();
    let name = name.strip_prefix('"')?.strip_suffix('"')?;
    Some((dim, tag, name.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &[u8]) -> String {
        read_msh_bytes(text).unwrap_err().to_string()
    }

    #[test]
    fn physical_names_may_contain_spaces() {
        assert_eq!(
            parse_physical_name("1 7 \"contact zone\""),
            Some((1, 7, "contact zone".to_string()))
        );
        assert_eq!(parse_physical_name("1 7 contact"), None);
    }

    #[test]
    fn node_tags_keep_their_order_and_gaps() {
        let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n2 3 2 40\n\
                    2 1 0 2\n40\n2\n0 0 0\n1 0 0\n2 1 0 1\n9\n0 1 0\n$EndNodes\n";
        let msh = read_msh_bytes(text.as_bytes()).unwrap();
        let tags: Vec<u64> = msh.nodes.iter().map(|n| n.tag).collect();
        assert_eq!(tags, [40, 2, 9]);
        assert_eq!(msh.nodes[1].xyz, [1.0, 0.0, 0.0]);
    }

    #[test]
    fn duplicated_node_tags_are_an_error_with_their_line() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n4 0 0 0\n4 1 0 0\n$EndNodes\n";
        assert_eq!(
            error(text.as_bytes()),
            "line 7 (in $Nodes): node tag 4 is defined twice"
        );
    }

    #[test]
    fn a_huge_count_is_refused_before_any_allocation() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n18446744073709551615\n";
        assert!(error(text.as_bytes()).starts_with(
            "line 5 (in $Nodes): the number of nodes is 18446744073709551615, more than the \
             remaining"
        ));
        let mut binary = b"$MeshFormat\n4.1 1 8\n".to_vec();
        binary.extend(1i32.to_ne_bytes());
        binary.extend(b"\n$EndMeshFormat\n$Nodes\n");
        binary.extend(1u64.to_ne_bytes());
        binary.extend((1u64 << 60).to_ne_bytes());
        binary.extend([0u8; 200]);
        assert!(
            error(&binary).starts_with(
                "byte 55 (in $Nodes): the number of nodes is 1152921504606846976, more than"
            ),
            "{}",
            error(&binary)
        );
    }

    #[test]
    fn a_binary_data_size_other_than_8_is_refused() {
        let text = "$MeshFormat\n4.1 1 2147483648\n$EndMeshFormat\n";
        assert_eq!(
            error(text.as_bytes()),
            "line 2 (in $MeshFormat): binary files with data size '2147483648' are not \
             supported (only 8)"
        );
    }

    #[test]
    fn a_file_ending_inside_a_section_names_the_line() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n";
        assert_eq!(
            error(text.as_bytes()),
            "line 7 (in $Nodes): expected $EndNodes, found ''"
        );
    }

    #[test]
    fn unknown_sections_are_skipped_and_unclosed_ones_named() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nhello\n$EndComments\n";
        assert!(read_msh_bytes(text.as_bytes()).is_ok());
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nhello\n";
        assert_eq!(
            error(text.as_bytes()),
            "line 4: section $Comments has no end marker $EndComments"
        );
    }

    #[test]
    fn swapped_byte_order_is_read() {
        let mut binary = b"$MeshFormat\n2.2 1 8\n".to_vec();
        let swapped_i32 = |v: i32| {
            let mut b = v.to_ne_bytes();
            b.reverse();
            b
        };
        let swapped_f64 = |v: f64| {
            let mut b = v.to_ne_bytes();
            b.reverse();
            b
        };
        binary.extend(swapped_i32(1));
        binary.extend(b"\n$EndMeshFormat\n$Nodes\n1\n");
        binary.extend(swapped_i32(7));
        for v in [0.5, 2.0, 0.0] {
            binary.extend(swapped_f64(v));
        }
        binary.extend(b"\n$EndNodes\n");
        let msh = read_msh_bytes(&binary).unwrap();
        assert_eq!(
            msh.nodes,
            [MshNode {
                tag: 7,
                xyz: [0.5, 2.0, 0.0]
            }]
        );
    }
}
