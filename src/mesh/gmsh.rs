//! Gmsh MSH 4.1 reader (ASCII and binary): nodes, linear elements and named physical
//! groups, into a validated [`Mesh`].
//!
//! Entry points: [`read_msh`] (a file) and [`parse_msh`] (bytes already in memory);
//! [`read_msh_elements`] gives the file's nodes and elements of every dimension as they
//! are, for meshes that are not finite-element meshes (crack curves and surfaces).
//!
//! What it owns: the MSH 4.1 file layout (`$MeshFormat`, `$PhysicalNames`, `$Entities`,
//! `$Nodes`, `$Elements`; other sections are skipped) and the mapping from Gmsh's
//! entities and physical groups to the mesh's groups:
//!
//! - the mesh dimension is the highest element dimension in the file (2 or 3);
//! - every element of that dimension is a cell, in file order, whether or not its entity
//!   is in a physical group; physical groups of that dimension are `cell_groups`;
//! - physical groups of dimension − 1 are `face_groups` (segments in 2D, triangles and
//!   quads in 3D), with Gmsh's node order; physical groups of dimension 0 (and of
//!   curves in a 3D mesh) are `node_groups`; lower-dimensional elements without a
//!   physical group are ignored;
//! - a group without a name in `$PhysicalNames` is named by its numeric tag (`"7"`);
//! - node tags (possibly non-contiguous or unordered) become 0-based indices in file
//!   order; nodes that no cell, face or node group references are dropped;
//! - in 2D the nodes must lie in one plane z = const (z is then set to 0).
//!
//! Supported element types: point (Gmsh type 15), line2 (1), tri3 (2), quad4 (3),
//! tet4 (4), hex8 (5); node orders are Gmsh's, which are those of [`crate::element`].
//! Any other type (second order, prisms, pyramids, …) is an error naming each such type and
//! how many elements of it the file holds (blocks of one type summed). The mesh is
//! checked with [`Mesh::validate`] before it is returned. The parser never panics on bad
//! input: every read is bounds-checked and every error is a [`MeshError::File`] naming
//! the file and, where it helps, the line (ASCII) or byte offset (binary).

use super::{Cell, Face, Mesh, MeshError};
use crate::element::{CellType, FaceType};
use std::collections::HashMap;
use std::path::Path;

/// Reads a Gmsh MSH 4.1 file (ASCII or binary) into a validated mesh.
pub fn read_msh(path: &Path) -> Result<Mesh, MeshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| MeshError::File(format!("{name}: cannot read the mesh file: {e}")))?;
    parse_msh(&bytes, &name)
}

/// Parses the bytes of a Gmsh MSH 4.1 file (ASCII or binary); `name` is used in error
/// messages (usually the file path).
pub fn parse_msh(bytes: &[u8], name: &str) -> Result<Mesh, MeshError> {
    let raw = Parser::new(bytes, name).parse()?;
    build(raw, name)
}

/// The elements of an MSH file as they are, whatever their dimension.
#[derive(Debug, Clone, Default)]
pub struct MshElements {
    /// Node coordinates in file order.
    pub nodes: Vec<[f64; 3]>,
    pub elements: Vec<MshElement>,
    /// Every physical group of the file as (dimension, name); unnamed groups by tag.
    pub groups: Vec<(usize, String)>,
}

/// One element: its dimension (0 point, 1 line, 2 triangle or quad, 3 volume), its node
/// positions in [`MshElements::nodes`] (Gmsh's order) and the physical groups of its entity.
#[derive(Debug, Clone)]
pub struct MshElement {
    pub dim: usize,
    pub nodes: Vec<usize>,
    pub groups: Vec<String>,
}

/// Reads a Gmsh MSH 4.1 file (ASCII or binary) without building a finite-element mesh:
/// the nodes and every element of the supported types with its physical groups.
pub fn read_msh_elements(path: &Path) -> Result<MshElements, MeshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| MeshError::File(format!("{name}: cannot read the mesh file: {e}")))?;
    let Raw { names, entity_physicals, coords, blocks, .. } = Parser::new(&bytes, &name).parse()?;
    let group_name = |d: i32, tag: i32| names.get(&(d, tag)).cloned().unwrap_or_else(|| tag.to_string());
    let mut out = MshElements { nodes: coords, ..Default::default() };
    let mut groups: Vec<(usize, String)> = entity_physicals
        .iter()
        .flat_map(|(&(d, _), tags)| tags.iter().map(move |&t| (d, t)))
        .map(|(d, t)| (d as usize, group_name(d, t)))
        .collect();
    groups.sort();
    groups.dedup();
    out.groups = groups;
    for b in &blocks {
        let phys: Vec<String> = entity_physicals
            .get(&(b.dim, b.entity))
            .map(|v| v.iter().map(|&p| group_name(b.dim, p)).collect())
            .unwrap_or_default();
        for e in b.conn.chunks_exact(b.n_per) {
            out.elements.push(MshElement {
                dim: b.dim as usize,
                nodes: e.iter().map(|&p| p as usize).collect(),
                groups: phys.clone(),
            });
        }
    }
    Ok(out)
}

/// Gmsh element type number → (dimension, node count), for the supported types.
fn element_info(gmsh_type: i32) -> Option<(i32, usize)> {
    match gmsh_type {
        15 => Some((0, 1)),
        1 => Some((1, 2)),
        2 => Some((2, 3)),
        3 => Some((2, 4)),
        4 => Some((3, 4)),
        5 => Some((3, 8)),
        _ => None,
    }
}

/// Node count of the Gmsh element types fissure does not read but recognises (second
/// order, prisms, pyramids), so that a file holding them can be read to its end and every
/// such block counted in the error.
fn unsupported_node_count(gmsh_type: i32) -> Option<usize> {
    match gmsh_type {
        6 => Some(6),
        7 => Some(5),
        8 => Some(3),
        9 => Some(6),
        10 => Some(9),
        11 => Some(10),
        12 => Some(27),
        13 => Some(18),
        14 => Some(14),
        16 => Some(8),
        17 => Some(20),
        18 => Some(15),
        19 => Some(13),
        _ => None,
    }
}

/// A readable name for a Gmsh element type number (for error messages).
fn element_name(gmsh_type: i32) -> &'static str {
    match gmsh_type {
        1 => "line2",
        2 => "tri3",
        3 => "quad4",
        4 => "tet4",
        5 => "hex8",
        6 => "prism6",
        7 => "pyramid5",
        8 => "line3 (second order)",
        9 => "tri6 (second order)",
        10 => "quad9 (second order)",
        11 => "tet10 (second order)",
        12 => "hex27 (second order)",
        13 => "prism18 (second order)",
        14 => "pyramid14 (second order)",
        15 => "point",
        16 => "quad8 (second order)",
        17 => "hex20 (second order)",
        18 => "prism15 (second order)",
        19 => "pyramid13 (second order)",
        20..=25 | 42..=46 | 52..=56 => "triangle of order 3 or more",
        26..=28 | 62..=66 => "line of order 3 or more",
        29..=33 | 71..=83 => "tetrahedron of order 3 or more",
        36..=41 | 47..=51 | 57..=61 => "quadrangle of order 3 or more",
        _ => "an element type fissure does not know",
    }
}

/// One block of elements of one type on one entity; `conn` holds file node positions.
struct Block {
    dim: i32,
    entity: i32,
    gmsh_type: i32,
    n_per: usize,
    conn: Vec<u32>,
}

/// The file's content before it becomes a mesh.
struct Raw {
    /// (dim, physical tag) → name.
    names: HashMap<(i32, i32), String>,
    /// (dim, entity tag) → physical tags.
    entity_physicals: HashMap<(i32, i32), Vec<i32>>,
    /// Node coordinates in file order.
    coords: Vec<[f64; 3]>,
    /// Node tags in file order (for error messages).
    tags: Vec<u64>,
    blocks: Vec<Block>,
}

/// Node tag → file position.
enum TagMap {
    Dense(Vec<u32>),
    Sparse(HashMap<u64, u32>),
}

impl TagMap {
    fn get(&self, tag: u64) -> Option<u32> {
        match self {
            TagMap::Dense(v) => usize::try_from(tag).ok().and_then(|t| v.get(t)).copied().filter(|&p| p != u32::MAX),
            TagMap::Sparse(m) => m.get(&tag).copied(),
        }
    }
}

struct Parser<'a> {
    buf: &'a [u8],
    pos: usize,
    name: &'a str,
    binary: bool,
    big_endian: bool,
    size_t: usize,
    raw: Raw,
    tag_map: Option<TagMap>,
}

fn parse_uint(tok: &[u8]) -> Option<u64> {
    if tok.is_empty() {
        return None;
    }
    let mut v: u64 = 0;
    for &b in tok {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        v = v.checked_mul(10)?.checked_add(u64::from(d))?;
    }
    Some(v)
}

fn parse_int(tok: &[u8]) -> Option<i64> {
    match tok.first() {
        Some(b'-') => parse_uint(&tok[1..]).and_then(|v| i64::try_from(v).ok()).map(|v| -v),
        Some(b'+') => parse_uint(&tok[1..]).and_then(|v| i64::try_from(v).ok()),
        _ => parse_uint(tok).and_then(|v| i64::try_from(v).ok()),
    }
}

fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(&tok[..tok.len().min(40)]).into_owned();
    if tok.len() > 40 {
        format!("{s}…")
    } else {
        s
    }
}

impl<'a> Parser<'a> {
    fn new(buf: &'a [u8], name: &'a str) -> Parser<'a> {
        Parser {
            buf,
            pos: 0,
            name,
            binary: false,
            big_endian: false,
            size_t: 8,
            raw: Raw {
                names: HashMap::new(),
                entity_physicals: HashMap::new(),
                coords: Vec::new(),
                tags: Vec::new(),
                blocks: Vec::new(),
            },
            tag_map: None,
        }
    }

    /// An error at the current position.
    fn err(&self, msg: impl std::fmt::Display) -> MeshError {
        let at = self.pos.min(self.buf.len());
        let loc = if self.binary {
            format!("byte {at}")
        } else {
            format!("line {}", self.buf[..at].iter().filter(|&&b| b == b'\n').count() + 1)
        };
        MeshError::File(format!("{}: {msg} (at {loc})", self.name))
    }

    fn remaining(&self) -> usize {
        self.buf.len().saturating_sub(self.pos)
    }

    /// A capacity for `n` items of at least `min_bytes` each that the input can hold.
    fn capacity(&self, n: u64, min_bytes: usize) -> usize {
        let fit = self.remaining() / min_bytes.max(1);
        usize::try_from(n).map_or(fit, |n| n.min(fit))
    }

    fn skip_ws(&mut self) {
        while self.pos < self.buf.len() && self.buf[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip_ws();
        self.pos >= self.buf.len()
    }

    /// The next whitespace-delimited ASCII token.
    fn token(&mut self, what: &str) -> Result<&'a [u8], MeshError> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.buf.len() && !self.buf[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.err(format!("the file ends where {what} was expected (truncated file?)")));
        }
        Ok(&self.buf[start..self.pos])
    }

    fn expect(&mut self, tag: &str) -> Result<(), MeshError> {
        let t = self.token(tag)?;
        if t != tag.as_bytes() {
            self.pos -= t.len();
            return Err(self.err(format!("expected {tag}, found '{}'", show(t))));
        }
        Ok(())
    }

    fn ascii_uint(&mut self, what: &str) -> Result<u64, MeshError> {
        let t = self.token(what)?;
        parse_uint(t).ok_or_else(|| self.err(format!("expected {what} (a non-negative integer), found '{}'", show(t))))
    }

    fn ascii_int(&mut self, what: &str) -> Result<i32, MeshError> {
        let t = self.token(what)?;
        parse_int(t)
            .and_then(|v| i32::try_from(v).ok())
            .ok_or_else(|| self.err(format!("expected {what} (an integer), found '{}'", show(t))))
    }

    /// After a section header line in a binary file: the single newline before the data.
    fn end_header_line(&mut self) -> Result<(), MeshError> {
        if self.binary {
            if self.buf.get(self.pos) == Some(&b'\r') {
                self.pos += 1;
            }
            if self.buf.get(self.pos) != Some(&b'\n') {
                return Err(self.err("expected a newline after the section header"));
            }
            self.pos += 1;
        }
        Ok(())
    }

    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N], MeshError> {
        match self.buf.get(self.pos..self.pos.saturating_add(N)) {
            Some(s) => {
                self.pos += N;
                let mut a = [0u8; N];
                a.copy_from_slice(s);
                Ok(a)
            }
            None => Err(self.err(format!("the file ends where {what} was expected (truncated file?)"))),
        }
    }

    /// A `size_t` value (binary: 4 or 8 bytes; ASCII: a non-negative integer).
    fn size(&mut self, what: &str) -> Result<u64, MeshError> {
        if !self.binary {
            return self.ascii_uint(what);
        }
        if self.size_t == 4 {
            let b = self.take::<4>(what)?;
            Ok(u64::from(if self.big_endian { u32::from_be_bytes(b) } else { u32::from_le_bytes(b) }))
        } else {
            let b = self.take::<8>(what)?;
            Ok(if self.big_endian { u64::from_be_bytes(b) } else { u64::from_le_bytes(b) })
        }
    }

    /// A count (`size_t`) that must fit in memory.
    fn count(&mut self, what: &str) -> Result<usize, MeshError> {
        let v = self.size(what)?;
        usize::try_from(v).map_err(|_| self.err(format!("{what} {v} is too large")))
    }

    fn int(&mut self, what: &str) -> Result<i32, MeshError> {
        if !self.binary {
            return self.ascii_int(what);
        }
        let b = self.take::<4>(what)?;
        Ok(if self.big_endian { i32::from_be_bytes(b) } else { i32::from_le_bytes(b) })
    }

    fn double(&mut self, what: &str) -> Result<f64, MeshError> {
        if self.binary {
            let b = self.take::<8>(what)?;
            return Ok(if self.big_endian { f64::from_be_bytes(b) } else { f64::from_le_bytes(b) });
        }
        let t = self.token(what)?;
        std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| self.err(format!("expected {what} (a number), found '{}'", show(t))))
    }

    fn parse(mut self) -> Result<Raw, MeshError> {
        self.header()?;
        let mut seen_elements = false;
        while !self.at_end() {
            let t = self.token("a section header")?;
            let Some(section) = t.strip_prefix(b"$").filter(|s| !s.is_empty() && !s.starts_with(b"End")) else {
                self.pos -= t.len();
                return Err(self.err(format!("expected a section header ($Name), found '{}'", show(t))));
            };
            let section = String::from_utf8_lossy(section).into_owned();
            match section.as_str() {
                "PhysicalNames" => self.physical_names()?,
                "Entities" => {
                    self.end_header_line()?;
                    self.entities()?;
                }
                "Nodes" => {
                    if self.tag_map.is_some() {
                        return Err(self.err("a second $Nodes section; fissure reads files with one"));
                    }
                    self.end_header_line()?;
                    self.nodes()?;
                }
                "Elements" => {
                    if self.tag_map.is_none() {
                        return Err(self.err("$Elements comes before $Nodes"));
                    }
                    self.end_header_line()?;
                    self.elements()?;
                    seen_elements = true;
                }
                "PartitionedEntities" => {
                    return Err(self.err("partitioned meshes are not supported; save the mesh without partitions"))
                }
                _ => self.skip_section(&section)?,
            }
            self.expect(&format!("$End{section}"))?;
        }
        if !seen_elements {
            return Err(MeshError::File(format!("{}: no $Elements section; the file holds no mesh", self.name)));
        }
        Ok(self.raw)
    }

    fn header(&mut self) -> Result<(), MeshError> {
        self.skip_ws();
        if !self.buf[self.pos..].starts_with(b"$MeshFormat") {
            return Err(MeshError::File(format!(
                "{}: not a Gmsh mesh file (it does not start with $MeshFormat); fissure reads Gmsh MSH 4.1 files",
                self.name
            )));
        }
        self.expect("$MeshFormat")?;
        let v = self.token("the MSH version")?;
        let vs = String::from_utf8_lossy(v).into_owned();
        match vs.parse::<f64>() {
            Ok(x) if (x - 4.1).abs() < 1e-9 => {}
            Ok(_) => {
                return Err(MeshError::File(format!(
                    "{}: MSH version {vs} found; fissure reads MSH 4.1 (gmsh -format msh41)",
                    self.name
                )))
            }
            Err(_) => return Err(self.err(format!("unreadable MSH version '{}'", show(v)))),
        }
        let file_type = self.ascii_uint("the file type (0 ASCII, 1 binary)")?;
        let size_t = self.ascii_uint("the data size")?;
        match file_type {
            0 => {}
            1 => self.binary = true,
            _ => return Err(self.err(format!("file type {file_type} is neither 0 (ASCII) nor 1 (binary)"))),
        }
        self.size_t = match size_t {
            4 => 4,
            8 => 8,
            _ => return Err(self.err(format!("data size {size_t} is not supported (4 or 8)"))),
        };
        if self.binary {
            self.end_header_line()?;
            let b = self.take::<4>("the binary endianness marker")?;
            if i32::from_le_bytes(b) == 1 {
                self.big_endian = false;
            } else if i32::from_be_bytes(b) == 1 {
                self.big_endian = true;
            } else {
                self.pos -= 4;
                return Err(self.err("bad binary endianness marker (expected the integer 1)"));
            }
        }
        self.expect("$EndMeshFormat")
    }

    fn skip_section(&mut self, section: &str) -> Result<(), MeshError> {
        let end = format!("$End{section}");
        let hay = &self.buf[self.pos..];
        match hay.windows(end.len()).position(|w| w == end.as_bytes()) {
            Some(p) => {
                self.pos += p;
                Ok(())
            }
            None => Err(self.err(format!("section ${section} has no {end} (truncated file?)"))),
        }
    }

    /// `$PhysicalNames`: ASCII text even in binary files.
    fn physical_names(&mut self) -> Result<(), MeshError> {
        let n = self.ascii_uint("the number of physical names")?;
        for _ in 0..n {
            let dim = self.ascii_int("a physical group dimension")?;
            let tag = self.ascii_int("a physical group tag")?;
            self.skip_ws();
            if self.buf.get(self.pos) != Some(&b'"') {
                return Err(self.err("expected a quoted physical group name"));
            }
            let start = self.pos + 1;
            let Some(len) = self.buf[start..].iter().position(|&b| b == b'"' || b == b'\n') else {
                return Err(self.err("unterminated physical group name"));
            };
            if self.buf[start + len] != b'"' {
                return Err(self.err("unterminated physical group name"));
            }
            let name = String::from_utf8_lossy(&self.buf[start..start + len]).into_owned();
            self.pos = start + len + 1;
            self.raw.names.insert((dim, tag.abs()), name);
        }
        Ok(())
    }

    fn entities(&mut self) -> Result<(), MeshError> {
        let mut counts = [0usize; 4];
        for (d, c) in counts.iter_mut().enumerate() {
            *c = self.count(&format!("the number of entities of dimension {d}"))?;
        }
        for (dim, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                let tag = self.int("an entity tag")?;
                let n_coords = if dim == 0 { 3 } else { 6 };
                for _ in 0..n_coords {
                    self.double("an entity coordinate")?;
                }
                let np = self.count("the number of physical tags")?;
                let mut phys = Vec::with_capacity(self.capacity(np as u64, 2));
                for _ in 0..np {
                    phys.push(self.int("a physical tag")?.abs());
                }
                if dim > 0 {
                    let nb = self.count("the number of bounding entities")?;
                    for _ in 0..nb {
                        self.int("a bounding entity tag")?;
                    }
                }
                if !phys.is_empty() {
                    self.raw.entity_physicals.insert((dim as i32, tag), phys);
                }
            }
        }
        Ok(())
    }

    fn nodes(&mut self) -> Result<(), MeshError> {
        let n_blocks = self.count("the number of node blocks")?;
        let n_nodes = self.size("the number of nodes")?;
        let _min_tag = self.size("the smallest node tag")?;
        let _max_tag = self.size("the largest node tag")?;
        if n_nodes >= u64::from(u32::MAX) {
            return Err(self.err(format!("{n_nodes} nodes are more than fissure reads (2^32 − 1)")));
        }
        let cap = self.capacity(n_nodes, if self.binary { 32 } else { 8 });
        self.raw.coords.reserve(cap);
        self.raw.tags.reserve(cap);
        for _ in 0..n_blocks {
            let dim = self.int("a node block's entity dimension")?;
            let _entity = self.int("a node block's entity tag")?;
            let parametric = self.int("a node block's parametric flag")?;
            let n = self.count("the number of nodes in a block")?;
            let n_param = match parametric {
                0 => 0,
                1 => dim.clamp(0, 3) as usize,
                _ => return Err(self.err(format!("parametric flag {parametric} is neither 0 nor 1"))),
            };
            let first = self.raw.tags.len();
            for _ in 0..n {
                let t = self.size("a node tag")?;
                self.raw.tags.push(t);
            }
            for k in 0..n {
                let x = self.double("a node x coordinate")?;
                let y = self.double("a node y coordinate")?;
                let z = self.double("a node z coordinate")?;
                for _ in 0..n_param {
                    self.double("a node parametric coordinate")?;
                }
                if !(x.is_finite() && y.is_finite() && z.is_finite()) {
                    return Err(self.err(format!("node {} has a non-finite coordinate", self.raw.tags[first + k])));
                }
                self.raw.coords.push([x, y, z]);
            }
        }
        let n_read = self.raw.tags.len();
        if n_read as u64 != n_nodes {
            return Err(self.err(format!("$Nodes announces {n_nodes} nodes but its blocks hold {n_read}")));
        }
        self.tag_map = Some(self.build_tag_map()?);
        Ok(())
    }

    fn build_tag_map(&self) -> Result<TagMap, MeshError> {
        let n = self.raw.tags.len();
        let dup = |t: u64| MeshError::File(format!("{}: node tag {t} appears twice in $Nodes", self.name));
        let dense_limit = 2 * n as u64 + 1024;
        let true_max = self.raw.tags.iter().copied().max().unwrap_or(0);
        if true_max <= dense_limit {
            let mut v = vec![u32::MAX; true_max as usize + 1];
            for (p, &t) in self.raw.tags.iter().enumerate() {
                let slot = &mut v[t as usize];
                if *slot != u32::MAX {
                    return Err(dup(t));
                }
                *slot = p as u32;
            }
            Ok(TagMap::Dense(v))
        } else {
            let mut m = HashMap::with_capacity(n);
            for (p, &t) in self.raw.tags.iter().enumerate() {
                if m.insert(t, p as u32).is_some() {
                    return Err(dup(t));
                }
            }
            Ok(TagMap::Sparse(m))
        }
    }

    fn elements(&mut self) -> Result<(), MeshError> {
        let n_blocks = self.count("the number of element blocks")?;
        let _n_elements = self.size("the number of elements")?;
        let _min_tag = self.size("the smallest element tag")?;
        let _max_tag = self.size("the largest element tag")?;
        let Some(map) = self.tag_map.take() else {
            return Err(self.err("$Elements comes before $Nodes"));
        };
        let result = self.element_blocks(n_blocks, &map);
        self.tag_map = Some(map);
        result
    }

    fn element_blocks(&mut self, n_blocks: usize, map: &TagMap) -> Result<(), MeshError> {
        // Unsupported element types that can be skipped (known node count): (type, count),
        // reported together once every block is read.
        let mut unsupported: Vec<(i32, u64)> = vec![];
        for _ in 0..n_blocks {
            let dim = self.int("an element block's entity dimension")?;
            let entity = self.int("an element block's entity tag")?;
            let gmsh_type = self.int("an element type")?;
            let n = self.size("the number of elements in a block")?;
            let Some((type_dim, n_per)) = element_info(gmsh_type) else {
                let Some(n_per) = unsupported_node_count(gmsh_type) else {
                    return Err(self.err(format!(
                        "element type {} (Gmsh type {gmsh_type}): {n} element(s) on entity ({dim}, {entity}) are not \
                         supported; fissure reads linear elements: point, line2, tri3, quad4, tet4, hex8 (mesh with -order 1)",
                        element_name(gmsh_type)
                    )));
                };
                for _ in 0..n {
                    self.size("an element tag")?;
                    for _ in 0..n_per {
                        self.size("an element node tag")?;
                    }
                }
                match unsupported.iter_mut().find(|(t, _)| *t == gmsh_type) {
                    Some((_, count)) => *count += n,
                    None => unsupported.push((gmsh_type, n)),
                }
                continue;
            };
            if type_dim != dim {
                return Err(self.err(format!(
                    "element type {} has dimension {type_dim} but its block is on an entity of dimension {dim}",
                    element_name(gmsh_type)
                )));
            }
            let min_bytes = if self.binary { self.size_t * (n_per + 1) } else { 2 * (n_per + 1) };
            let mut conn = Vec::with_capacity(self.capacity(n, min_bytes).saturating_mul(n_per));
            for _ in 0..n {
                let etag = self.size("an element tag")?;
                for _ in 0..n_per {
                    let t = self.size("an element node tag")?;
                    match map.get(t) {
                        Some(p) => conn.push(p),
                        None => {
                            return Err(
                                self.err(format!("element {etag} references node {t}, which $Nodes does not have"))
                            )
                        }
                    }
                }
            }
            self.raw.blocks.push(Block { dim, entity, gmsh_type, n_per, conn });
        }
        if !unsupported.is_empty() {
            let list: Vec<String> =
                unsupported.iter().map(|&(t, n)| format!("{n} {} (Gmsh type {t})", element_name(t))).collect();
            return Err(self.err(format!(
                "the mesh has elements fissure does not support: {}; fissure reads linear elements: point, line2, \
                 tri3, quad4, tet4, hex8 (mesh with -order 1)",
                list.join(", ")
            )));
        }
        Ok(())
    }
}

/// Turns the file's content into a mesh: cells, groups, compact node numbering.
fn build(raw: Raw, name: &str) -> Result<Mesh, MeshError> {
    let Raw { names, entity_physicals, coords, tags, blocks } = raw;
    let dim = blocks.iter().filter(|b| !b.conn.is_empty()).map(|b| b.dim).max();
    let dim = match dim {
        Some(d @ (2 | 3)) => d,
        Some(d) => {
            return Err(MeshError::File(format!(
                "{name}: the highest element dimension is {d}; fissure needs 2D (triangles, quads) or 3D (tets, hexes) elements"
            )))
        }
        None => return Err(MeshError::File(format!("{name}: the file has no elements"))),
    };
    let group_name = |d: i32, tag: i32| names.get(&(d, tag)).cloned().unwrap_or_else(|| tag.to_string());
    let physicals = |b: &Block| entity_physicals.get(&(b.dim, b.entity)).map(|v| v.as_slice()).unwrap_or(&[]);

    let mut mesh = Mesh { dim: dim as usize, ..Default::default() };
    for b in &blocks {
        let phys = physicals(b);
        if b.dim == dim {
            let kind = match b.gmsh_type {
                2 => CellType::Tri3,
                3 => CellType::Quad4,
                4 => CellType::Tet4,
                _ => CellType::Hex8,
            };
            let first = mesh.cells.len();
            let mut nodes = [0usize; 8];
            for e in b.conn.chunks_exact(b.n_per) {
                for (a, &p) in e.iter().enumerate() {
                    nodes[a] = p as usize;
                }
                mesh.cells.push(Cell::new(kind, &nodes[..b.n_per]));
            }
            for &p in phys {
                mesh.cell_groups.entry(group_name(b.dim, p)).or_default().extend(first..mesh.cells.len());
            }
        } else if b.dim == dim - 1 && !phys.is_empty() {
            let kind = match b.gmsh_type {
                1 => FaceType::Line2,
                2 => FaceType::Tri3,
                _ => FaceType::Quad4,
            };
            let mut nodes = [0usize; 4];
            let faces: Vec<Face> = b
                .conn
                .chunks_exact(b.n_per)
                .map(|e| {
                    for (a, &p) in e.iter().enumerate() {
                        nodes[a] = p as usize;
                    }
                    Face::new(kind, &nodes[..b.n_per])
                })
                .collect();
            for &p in phys {
                mesh.face_groups.entry(group_name(b.dim, p)).or_default().extend_from_slice(&faces);
            }
        } else if b.dim < dim - 1 {
            for &p in phys {
                mesh.node_groups.entry(group_name(b.dim, p)).or_default().extend(b.conn.iter().map(|&p| p as usize));
            }
        }
    }

    // Compact numbering of the referenced nodes, in file order.
    const UNUSED: usize = usize::MAX;
    let mut new_index = vec![UNUSED; coords.len()];
    let refs = mesh
        .cells
        .iter()
        .flat_map(|c| c.nodes().iter())
        .chain(mesh.face_groups.values().flatten().flat_map(|f| f.nodes().iter()))
        .chain(mesh.node_groups.values().flatten());
    for &p in refs {
        new_index[p] = 0;
    }
    let mut nodes = Vec::with_capacity(coords.len());
    for (p, slot) in new_index.iter_mut().enumerate() {
        if *slot != UNUSED {
            *slot = nodes.len();
            nodes.push(coords[p]);
        }
    }
    for c in &mut mesh.cells {
        let n = c.kind.n_nodes();
        for v in &mut c.nodes[..n] {
            *v = new_index[*v];
        }
    }
    for faces in mesh.face_groups.values_mut() {
        for f in faces {
            let n = f.kind.n_nodes();
            for v in &mut f.nodes[..n] {
                *v = new_index[*v];
            }
        }
    }
    for ns in mesh.node_groups.values_mut() {
        for v in ns.iter_mut() {
            *v = new_index[*v];
        }
        ns.sort_unstable();
        ns.dedup();
    }
    mesh.nodes = nodes;

    if dim == 2 {
        flatten_2d(&mut mesh, &tags, &new_index, name)?;
    }
    mesh.validate()?;
    Ok(mesh)
}

/// A 2D mesh must lie in a plane z = const; its z is set to 0.
fn flatten_2d(mesh: &mut Mesh, tags: &[u64], new_index: &[usize], name: &str) -> Result<(), MeshError> {
    let (lo, hi) = mesh.bounding_box();
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if hi[2] - lo[2] > 1e-10 * size {
        // Name the node tags at the extremes.
        let tag_of = |k: usize| new_index.iter().position(|&i| i == k).map(|p| tags[p]).unwrap_or(0);
        let kmin = mesh.nodes.iter().position(|p| p[2] == lo[2]).unwrap_or(0);
        let kmax = mesh.nodes.iter().position(|p| p[2] == hi[2]).unwrap_or(0);
        return Err(MeshError::File(format!(
            "{name}: a 2D mesh must lie in a plane z = const, but z goes from {} (node {}) to {} (node {})",
            lo[2],
            tag_of(kmin),
            hi[2],
            tag_of(kmax)
        )));
    }
    for p in &mut mesh.nodes {
        p[2] = 0.0;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square as two triangles with non-contiguous, unordered node tags, a named
    /// and an unnamed edge group, a corner point group, and an orphan node (tag 99).
    const SQUARE: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
        $PhysicalNames\n2\n1 10 \"bottom\"\n2 20 \"domain face\"\n$EndPhysicalNames\n\
        $Entities\n1 2 1 0\n\
        1 0 0 0 1 30\n\
        1 0 0 0 1 0 0 1 10 2 1 -2\n\
        2 0 1 0 1 1 0 1 11 0\n\
        1 0 0 0 1 1 0 1 20 0\n\
        $EndEntities\n\
        $Nodes\n1 5 7 99\n2 1 0 5\n40\n7\n12\n30\n99\n1 0 0\n0 0 0\n0 1 0\n1 1 0\n5 5 0\n$EndNodes\n\
        $Elements\n4 5 1 5\n\
        0 1 15 1\n1 7\n\
        1 1 1 1\n2 7 40\n\
        1 2 1 1\n3 30 12\n\
        2 1 2 2\n4 7 40 12\n5 7 30 12\n\
        $EndElements\n";

    #[test]
    fn ascii_square_with_sparse_tags_and_groups() {
        let m = parse_msh(SQUARE.as_bytes(), "square.msh").unwrap();
        assert_eq!(m.dim, 2);
        assert_eq!(m.n_nodes(), 4, "the orphan node 99 is dropped");
        // File order: tags 40, 7, 12, 30 → indices 0, 1, 2, 3.
        assert_eq!(m.nodes[0], [1.0, 0.0, 0.0]);
        assert_eq!(m.nodes[1], [0.0, 0.0, 0.0]);
        assert_eq!(m.cells.len(), 2);
        assert_eq!(m.cells[0].nodes(), &[1, 0, 2]);
        assert_eq!(m.cells[1].nodes(), &[1, 3, 2]);
        assert_eq!(m.cell_groups["domain face"], vec![0, 1]);
        assert_eq!(m.face_groups["bottom"], vec![Face::new(FaceType::Line2, &[1, 0])]);
        assert_eq!(m.face_groups["11"], vec![Face::new(FaceType::Line2, &[3, 2])], "unnamed group → its tag");
        assert_eq!(m.node_groups["30"], vec![1]);
        let area: f64 = (0..2).map(|c| m.cell_measure(c)).sum();
        assert!((area - 1.0).abs() < 1e-14);
    }

    #[test]
    fn tet_without_cell_group_with_face_curve_and_point_groups() {
        let s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
            $PhysicalNames\n2\n0 3 \"tip\"\n2 2 \"base\"\n$EndPhysicalNames\n\
            $Entities\n1 1 1 1\n4 0 0 1 1 3\n1 0 0 0 1 0 0 1 7 0\n1 0 0 0 1 1 0 1 2 0\n1 0 0 0 1 1 1 0 0\n$EndEntities\n\
            $Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n\
            $Comments\nskipped $Nodes\n$EndComments\n\
            $Elements\n4 4 1 4\n0 4 15 1\n1 4\n1 1 1 1\n2 1 2\n2 1 2 1\n3 1 3 2\n3 1 4 1\n4 1 2 3 4\n$EndElements\n";
        let m = parse_msh(s.as_bytes(), "tet.msh").unwrap();
        assert_eq!((m.dim, m.n_nodes(), m.n_cells()), (3, 4, 1));
        assert_eq!(m.cells[0], Cell::new(CellType::Tet4, &[0, 1, 2, 3]));
        assert!(m.cell_groups.is_empty(), "the volume has no physical group but its cells are read");
        assert_eq!(m.face_groups["base"], vec![Face::new(FaceType::Tri3, &[0, 2, 1])]);
        assert_eq!(m.node_groups["tip"], vec![3]);
        assert_eq!(m.node_groups["7"], vec![0, 1], "a curve group of a 3D mesh is a node group");
        assert!((m.cell_measure(0) - 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn second_order_elements_are_rejected_by_name() {
        let s = SQUARE.replace("2 1 2 2\n4 7 40 12\n5 7 30 12", "2 1 9 1\n4 7 40 12 7 40 12");
        let e = parse_msh(s.as_bytes(), "q.msh").unwrap_err().to_string();
        assert!(e.contains("q.msh") && e.contains("tri6") && e.contains("type 9"), "{e}");
    }

    #[test]
    fn tilted_2d_mesh_is_rejected_and_a_plane_is_flattened() {
        let s = SQUARE.replace("0 1 0\n1 1 0\n5 5 0", "0 1 0.5\n1 1 0\n5 5 0");
        let e = parse_msh(s.as_bytes(), "t.msh").unwrap_err().to_string();
        assert!(e.contains("plane") && e.contains("node 12"), "{e}");
        let s = SQUARE.replace("1 0 0\n0 0 0\n0 1 0\n1 1 0", "1 0 3\n0 0 3\n0 1 3\n1 1 3");
        let m = parse_msh(s.as_bytes(), "p.msh").unwrap();
        assert!(m.nodes.iter().all(|p| p[2] == 0.0));
    }

    #[test]
    fn inverted_cell_is_reported_by_id() {
        let s = SQUARE.replace("5 7 30 12", "5 30 7 12");
        assert!(matches!(parse_msh(s.as_bytes(), "i.msh"), Err(MeshError::InvertedCell { cell: 1, .. })));
    }

    #[test]
    fn missing_node_and_duplicate_tag_are_errors() {
        let s = SQUARE.replace("5 7 30 12", "5 7 12 31");
        let e = parse_msh(s.as_bytes(), "m.msh").unwrap_err().to_string();
        assert!(e.contains("node 31") && e.contains("line"), "{e}");
        let s = SQUARE.replace("40\n7\n12\n30\n99", "40\n7\n12\n30\n7");
        let e = parse_msh(s.as_bytes(), "d.msh").unwrap_err().to_string();
        assert!(e.contains("node tag 7 appears twice"), "{e}");
    }

    #[test]
    fn versions_and_non_mesh_files() {
        let e = parse_msh(b"$MeshFormat\n4 0 8\n$EndMeshFormat\n", "old.msh").unwrap_err().to_string();
        assert!(e.contains("old.msh") && e.contains("version 4 found") && e.contains("msh41"), "{e}");
        let e = parse_msh(b"Point(1) = {0, 0, 0};\n", "a.geo").unwrap_err().to_string();
        assert!(e.contains("a.geo") && e.contains("not a Gmsh mesh file"), "{e}");
        let e = parse_msh(b"", "empty.msh").unwrap_err().to_string();
        assert!(e.contains("not a Gmsh mesh file"), "{e}");
    }

    /// Writes SQUARE in binary with the given endianness and size_t.
    fn square_binary(big: bool, size_t: usize) -> Vec<u8> {
        let mut b: Vec<u8> = Vec::new();
        let sz = |b: &mut Vec<u8>, v: u64| match (size_t, big) {
            (4, false) => b.extend((v as u32).to_le_bytes()),
            (4, true) => b.extend((v as u32).to_be_bytes()),
            (_, false) => b.extend(v.to_le_bytes()),
            (_, true) => b.extend(v.to_be_bytes()),
        };
        let int = |b: &mut Vec<u8>, v: i32| b.extend(if big { v.to_be_bytes() } else { v.to_le_bytes() });
        let dbl = |b: &mut Vec<u8>, v: f64| b.extend(if big { v.to_be_bytes() } else { v.to_le_bytes() });
        b.extend(format!("$MeshFormat\n4.1 1 {size_t}\n").as_bytes());
        int(&mut b, 1);
        b.extend(b"\n$EndMeshFormat\n$PhysicalNames\n2\n1 10 \"bottom\"\n2 20 \"domain face\"\n$EndPhysicalNames\n");
        b.extend(b"$Entities\n");
        for v in [1, 2, 1, 0] {
            sz(&mut b, v);
        }
        int(&mut b, 1);
        for v in [0.0; 3] {
            dbl(&mut b, v);
        }
        sz(&mut b, 1);
        int(&mut b, 30);
        for (tag, box_, phys, bound) in
            [(1, [0., 0., 0., 1., 0., 0.], 10, vec![1, -2]), (2, [0., 1., 0., 1., 1., 0.], 11, vec![])]
        {
            int(&mut b, tag);
            for v in box_ {
                dbl(&mut b, v);
            }
            sz(&mut b, 1);
            int(&mut b, phys);
            sz(&mut b, bound.len() as u64);
            for t in bound {
                int(&mut b, t);
            }
        }
        int(&mut b, 1);
        for v in [0., 0., 0., 1., 1., 0.] {
            dbl(&mut b, v);
        }
        sz(&mut b, 1);
        int(&mut b, 20);
        sz(&mut b, 0);
        b.extend(b"\n$EndEntities\n$Nodes\n");
        for v in [1, 5, 7, 99] {
            sz(&mut b, v);
        }
        int(&mut b, 2);
        int(&mut b, 1);
        int(&mut b, 0);
        sz(&mut b, 5);
        for t in [40, 7, 12, 30, 99] {
            sz(&mut b, t);
        }
        for v in [1., 0., 0., 0., 0., 0., 0., 1., 0., 1., 1., 0., 5., 5., 0.] {
            dbl(&mut b, v);
        }
        b.extend(b"\n$EndNodes\n$Elements\n");
        for v in [4, 5, 1, 5] {
            sz(&mut b, v);
        }
        let blocks: [(i32, i32, i32, &[&[u64]]); 4] = [
            (0, 1, 15, &[&[1, 7]]),
            (1, 1, 1, &[&[2, 7, 40]]),
            (1, 2, 1, &[&[3, 30, 12]]),
            (2, 1, 2, &[&[4, 7, 40, 12], &[5, 7, 30, 12]]),
        ];
        for (d, e, t, elems) in blocks {
            int(&mut b, d);
            int(&mut b, e);
            int(&mut b, t);
            sz(&mut b, elems.len() as u64);
            for el in elems {
                for &v in *el {
                    sz(&mut b, v);
                }
            }
        }
        b.extend(b"\n$EndElements\n");
        b
    }

    #[test]
    fn binary_little_and_big_endian_match_ascii() {
        let a = parse_msh(SQUARE.as_bytes(), "a.msh").unwrap();
        for (big, size_t) in [(false, 8), (true, 8), (false, 4), (true, 4)] {
            let bytes = square_binary(big, size_t);
            let m = parse_msh(&bytes, "b.msh").unwrap_or_else(|e| panic!("big {big} size_t {size_t}: {e}"));
            assert_eq!(m.nodes, a.nodes);
            assert_eq!(m.cells, a.cells);
            assert_eq!(m.cell_groups, a.cell_groups);
            assert_eq!(m.face_groups, a.face_groups);
            assert_eq!(m.node_groups, a.node_groups);
            // Every truncation is an error, never a panic.
            for cut in 0..bytes.len() - 1 {
                assert!(parse_msh(&bytes[..cut], "cut.msh").is_err(), "cut at {cut}");
            }
        }
    }

    #[test]
    fn every_ascii_truncation_is_an_error() {
        let b = SQUARE.as_bytes();
        // Any cut before the last byte (the final newline) loses part of the file.
        for cut in 0..b.len() - "\n".len() {
            assert!(parse_msh(&b[..cut], "cut.msh").is_err(), "cut at {cut}");
        }
    }
}
