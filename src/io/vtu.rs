//! VTK XML unstructured grids (`.vtu`), their parallel index (`.pvtu`) and collections
//! (`.pvd`).
//!
//! Entry points: [`UnstructuredGrid`], [`write_vtu`], [`write_pvtu`], [`write_pvd`].
//!
//! This module owns the in-memory grid handed to the writers ([`UnstructuredGrid`],
//! [`VtkCell`], [`DataArray`]), its validation ([`UnstructuredGrid::validate`], errors as
//! [`InvalidOutput`]), the selection of a piece of it ([`UnstructuredGrid::subset`]), the
//! `.vtu` writer (through `vtkio` 0.7.0-rc2: inline base64 binary, uncompressed or LZ4, see
//! [`Compression`]) and the hand-written `.pvtu` index ([`write_pvtu`]: the pieces of one
//! grid written by the ranks of an MPI run) and `.pvd` collection writer ([`PvdEntry`],
//! [`write_pvd`]).
//!
//! Layout of a written `.vtu`: `VTKFile` version 1.0, little endian, `header_type="UInt64"`;
//! points `Float64` × 3 (2D grids carry `z = 0`); `connectivity` and `offsets` `UInt64`,
//! `types` `UInt8`; every point and cell array `Float64` with its `NumberOfComponents`.
//!
//! Both writers validate their input first and return an [`std::io::Error`] of kind
//! [`std::io::ErrorKind::InvalidInput`] (wrapping an [`InvalidOutput`]) instead of panicking.
//! Files are written to a temporary sibling and renamed into place, so a reader polling the
//! output directory (ParaView reloading a `.pvd`) never sees a half-written file.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use vtkio::model;
use vtkio::xml::Compressor;

/// Linear VTK cell kinds written by fissure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VtkCell {
    Vertex,
    Line,
    Triangle,
    Quad,
    Tetra,
    Hexahedron,
}

impl VtkCell {
    /// The VTK type id (`vtkCellType.h`).
    pub fn vtk_id(self) -> u8 {
        match self {
            VtkCell::Vertex => 1,
            VtkCell::Line => 3,
            VtkCell::Triangle => 5,
            VtkCell::Quad => 9,
            VtkCell::Tetra => 10,
            VtkCell::Hexahedron => 12,
        }
    }

    /// Number of nodes of this cell kind (VTK node ordering).
    pub fn num_nodes(self) -> usize {
        match self {
            VtkCell::Vertex => 1,
            VtkCell::Line => 2,
            VtkCell::Triangle => 3,
            VtkCell::Quad => 4,
            VtkCell::Tetra => 4,
            VtkCell::Hexahedron => 8,
        }
    }

    fn to_vtkio(self) -> model::CellType {
        match self {
            VtkCell::Vertex => model::CellType::Vertex,
            VtkCell::Line => model::CellType::Line,
            VtkCell::Triangle => model::CellType::Triangle,
            VtkCell::Quad => model::CellType::Quad,
            VtkCell::Tetra => model::CellType::Tetra,
            VtkCell::Hexahedron => model::CellType::Hexahedron,
        }
    }
}

/// A named array of `components` values per point or per cell (row-major:
/// `values[i * components + c]`).
#[derive(Debug, Clone, PartialEq)]
pub struct DataArray {
    pub name: String,
    pub components: usize,
    pub values: Vec<f64>,
}

impl DataArray {
    /// An array named `name` with `components` values per entry.
    pub fn new(name: impl Into<String>, components: usize, values: Vec<f64>) -> Self {
        DataArray { name: name.into(), components, values }
    }
}

/// An unstructured grid to write: float64 points, cells with their kinds, point and
/// cell data. `connectivity` holds the node ids of every cell back to back;
/// `offsets[i]` is the end of cell `i` in `connectivity` (VTK's convention).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct UnstructuredGrid {
    pub points: Vec<[f64; 3]>,
    pub connectivity: Vec<u64>,
    pub offsets: Vec<u64>,
    pub kinds: Vec<VtkCell>,
    pub point_data: Vec<DataArray>,
    pub cell_data: Vec<DataArray>,
}

/// Compression of the binary arrays of a `.vtu` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compression {
    /// Plain base64 (largest file, fastest to write).
    #[default]
    None,
    /// LZ4 blocks (`vtkLZ4DataCompressor`): about as fast as `None`, much smaller files.
    Lz4,
}

/// Why a grid or a collection was refused by [`write_vtu`] / [`write_pvd`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InvalidOutput {
    #[error("{offsets} cell offsets for {kinds} cell kinds")]
    CellCountMismatch { offsets: usize, kinds: usize },
    #[error("cell {cell} ({kind:?}): offsets go from {start} to {end}, a {kind:?} has {expected} nodes")]
    BadOffsets { cell: usize, kind: VtkCell, start: u64, end: u64, expected: usize },
    #[error("the last offset is {last} but connectivity holds {len} node ids")]
    ConnectivityLength { last: u64, len: usize },
    #[error("connectivity[{position}] = {node} is not a point index (grid has {points} points)")]
    NodeOutOfRange { position: usize, node: u64, points: usize },
    #[error("point {point} has a non-finite coordinate {coords:?}")]
    NonFinitePoint { point: usize, coords: [f64; 3] },
    #[error("{what} count {count} does not fit the 32-bit counts of the VTK XML header")]
    TooLarge { what: &'static str, count: usize },
    #[error("{location} array {index} has an empty name")]
    EmptyName { location: &'static str, index: usize },
    #[error("{what} {text:?} contains a control character (not representable in an XML attribute)")]
    ControlCharacter { what: &'static str, text: String },
    #[error("{location} array {name:?} appears twice")]
    DuplicateName { location: &'static str, name: String },
    #[error("{location} array {name:?} has {components} components (must be 1..={max})", max = u32::MAX)]
    BadComponents { location: &'static str, name: String, components: usize },
    #[error("{location} array {name:?} has {len} values, expected {count} × {components}")]
    ArrayLength { location: &'static str, name: String, len: usize, count: usize, components: usize },
    #[error("pvd entry {index}: time {time} is not finite")]
    NonFiniteTime { index: usize, time: f64 },
    #[error("pvd entry {index}: file {file:?} must be a non-empty relative path")]
    BadFile { index: usize, file: String },
    #[error("pvd entries {first} and {second} share time {time} and part {part}")]
    DuplicateEntry { first: usize, second: usize, time: f64, part: usize },
}

impl From<InvalidOutput> for io::Error {
    fn from(e: InvalidOutput) -> io::Error {
        io::Error::new(io::ErrorKind::InvalidInput, e)
    }
}

impl UnstructuredGrid {
    /// Number of points.
    pub fn num_points(&self) -> usize {
        self.points.len()
    }

    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.kinds.len()
    }

    /// Appends a point and returns its index.
    pub fn push_point(&mut self, p: [f64; 3]) -> u64 {
        self.points.push(p);
        (self.points.len() - 1) as u64
    }

    /// Appends a cell of `kind` with the given node ids (in VTK ordering) and returns its
    /// index. Nothing is checked here: [`UnstructuredGrid::validate`] (called by
    /// [`write_vtu`]) reports a wrong node count or an out-of-range id.
    pub fn push_cell(&mut self, kind: VtkCell, nodes: &[u64]) -> usize {
        self.connectivity.extend_from_slice(nodes);
        self.offsets.push(self.connectivity.len() as u64);
        self.kinds.push(kind);
        self.kinds.len() - 1
    }

    /// The cells `c` with `keep[c]` (a cell beyond `keep` is left out), the points they
    /// use (renumbered in their original order) and the point and cell data of those: one
    /// piece of the grid. Cell ids must be valid ([`UnstructuredGrid::validate`]).
    pub fn subset(&self, keep: &[bool]) -> UnstructuredGrid {
        let kept = |c: usize| keep.get(c).copied().unwrap_or(false);
        let mut used = vec![false; self.points.len()];
        let mut start = 0usize;
        for (c, &end) in self.offsets.iter().enumerate() {
            let end = end as usize;
            if kept(c) {
                for &n in &self.connectivity[start..end] {
                    used[n as usize] = true;
                }
            }
            start = end;
        }
        let mut new_id = vec![u64::MAX; self.points.len()];
        let mut points = Vec::new();
        for (p, _) in used.iter().enumerate().filter(|(_, &u)| u) {
            new_id[p] = points.len() as u64;
            points.push(self.points[p]);
        }
        let mut g = UnstructuredGrid { points, ..Default::default() };
        let mut start = 0usize;
        let mut cells = Vec::new();
        for (c, (&end, &kind)) in self.offsets.iter().zip(&self.kinds).enumerate() {
            let end = end as usize;
            if kept(c) {
                let ids: Vec<u64> = self.connectivity[start..end].iter().map(|&n| new_id[n as usize]).collect();
                g.push_cell(kind, &ids);
                cells.push(c);
            }
            start = end;
        }
        let pick = |a: &DataArray, rows: &mut dyn Iterator<Item = usize>| DataArray {
            name: a.name.clone(),
            components: a.components,
            values: rows.flat_map(|r| a.values[r * a.components..(r + 1) * a.components].iter().copied()).collect(),
        };
        g.point_data = self
            .point_data
            .iter()
            .map(|a| pick(a, &mut used.iter().enumerate().filter(|(_, &u)| u).map(|(p, _)| p)))
            .collect();
        g.cell_data = self.cell_data.iter().map(|a| pick(a, &mut cells.iter().copied())).collect();
        g
    }

    /// Checks everything a VTK reader relies on: one offset per cell kind; offsets
    /// increasing by exactly the node count of each cell and ending at the end of
    /// `connectivity`; node ids below the number of points; finite coordinates; point and
    /// cell arrays with non-empty unique names free of control characters, 1.. components and `count × components`
    /// values; counts within the 32-bit header fields vtkio writes.
    pub fn validate(&self) -> Result<(), InvalidOutput> {
        let n_points = self.points.len();
        let n_cells = self.kinds.len();
        if u32::try_from(n_points).is_err() {
            return Err(InvalidOutput::TooLarge { what: "point", count: n_points });
        }
        if u32::try_from(n_cells).is_err() {
            return Err(InvalidOutput::TooLarge { what: "cell", count: n_cells });
        }
        if self.offsets.len() != n_cells {
            return Err(InvalidOutput::CellCountMismatch { offsets: self.offsets.len(), kinds: n_cells });
        }
        let mut start = 0u64;
        for (cell, (&end, &kind)) in self.offsets.iter().zip(&self.kinds).enumerate() {
            let expected = kind.num_nodes();
            if end < start || end - start != expected as u64 {
                return Err(InvalidOutput::BadOffsets { cell, kind, start, end, expected });
            }
            start = end;
        }
        if start != self.connectivity.len() as u64 {
            return Err(InvalidOutput::ConnectivityLength { last: start, len: self.connectivity.len() });
        }
        if let Some((position, &node)) = self.connectivity.iter().enumerate().find(|(_, &n)| n >= n_points as u64) {
            return Err(InvalidOutput::NodeOutOfRange { position, node, points: n_points });
        }
        if let Some((point, &coords)) = self.points.iter().enumerate().find(|(_, p)| p.iter().any(|x| !x.is_finite())) {
            return Err(InvalidOutput::NonFinitePoint { point, coords });
        }
        check_arrays("point", &self.point_data, n_points)?;
        check_arrays("cell", &self.cell_data, n_cells)
    }
}

fn check_arrays(location: &'static str, arrays: &[DataArray], count: usize) -> Result<(), InvalidOutput> {
    let mut names = HashSet::new();
    for (index, a) in arrays.iter().enumerate() {
        if a.name.is_empty() {
            return Err(InvalidOutput::EmptyName { location, index });
        }
        if a.name.chars().any(char::is_control) {
            return Err(InvalidOutput::ControlCharacter { what: "array name", text: a.name.clone() });
        }
        if !names.insert(a.name.as_str()) {
            return Err(InvalidOutput::DuplicateName { location, name: a.name.clone() });
        }
        if a.components == 0 || u32::try_from(a.components).is_err() {
            return Err(InvalidOutput::BadComponents { location, name: a.name.clone(), components: a.components });
        }
        if count.checked_mul(a.components) != Some(a.values.len()) {
            return Err(InvalidOutput::ArrayLength {
                location,
                name: a.name.clone(),
                len: a.values.len(),
                count,
                components: a.components,
            });
        }
    }
    Ok(())
}

fn to_attributes(arrays: &[DataArray]) -> Vec<model::Attribute> {
    arrays
        .iter()
        .map(|a| {
            // Validated: components fits in u32.
            let num_comp = u32::try_from(a.components).unwrap_or(1);
            model::Attribute::DataArray(model::DataArray {
                name: a.name.clone(),
                elem: model::ElementType::Generic(num_comp),
                data: model::IOBuffer::F64(a.values.clone()),
            })
        })
        .collect()
}

/// Writes `grid` as a VTK XML unstructured grid (`.vtu`) at `path`.
///
/// The grid is validated first ([`UnstructuredGrid::validate`]); an invalid grid gives an
/// error of kind [`io::ErrorKind::InvalidInput`] and nothing is written. The file is
/// written next to `path` under a temporary name and renamed into place.
pub fn write_vtu(path: &Path, grid: &UnstructuredGrid, compression: Compression) -> io::Result<()> {
    grid.validate()?;
    let piece = model::UnstructuredGridPiece {
        points: model::IOBuffer::F64(grid.points.iter().flatten().copied().collect()),
        cells: model::Cells {
            cell_verts: model::VertexNumbers::XML {
                connectivity: grid.connectivity.clone(),
                offsets: grid.offsets.clone(),
            },
            types: grid.kinds.iter().map(|k| k.to_vtkio()).collect(),
        },
        data: model::Attributes { point: to_attributes(&grid.point_data), cell: to_attributes(&grid.cell_data) },
    };
    let vtk = model::Vtk {
        version: model::Version::new_xml(1, 0),
        title: String::new(),
        byte_order: model::ByteOrder::LittleEndian,
        data: model::DataSet::inline(piece),
        file_path: None,
    };
    // vtkio ignores the compressor when the level is 0; LZ4 ignores the level otherwise.
    let (compressor, level) = match compression {
        Compression::None => (Compressor::None, 0),
        Compression::Lz4 => (Compressor::LZ4, 1),
    };
    let xml = vtk.try_into_xml_format(compressor, level).map_err(vtkio_error)?;
    if !grid.points.is_empty() && !grid.kinds.is_empty() {
        return write_atomically(path, |w| xml.write(w).map_err(vtkio_error));
    }
    // vtkio leaves out zero `NumberOfPoints` / `NumberOfCells`, and VTK refuses a piece without
    // them ("Piece 0 is missing its NumberOfPoints attribute"): put them back. Such grids are
    // small, so patching the serialised text in memory costs nothing.
    let mut text = Vec::new();
    xml.write(&mut text).map_err(vtkio_error)?;
    let text = add_zero_counts(text);
    write_atomically(path, |w| w.write_all(&text))
}

/// Writes the parallel index (`.pvtu`) of a grid written in `pieces` (`.vtu` files,
/// relative to the directory of `path`, one per rank of an MPI run): the point and cell
/// arrays of `template` (any one piece, or the whole grid: only the names and component
/// counts are read) declared as `Float64`, as [`write_vtu`] writes them. ParaView opens the
/// `.pvtu` (or a `.pvd` naming it) as one grid, the union of the pieces. Refused (kind
/// [`io::ErrorKind::InvalidInput`]): no piece, an empty or absolute piece path, a control
/// character in a piece path or an array name.
pub fn write_pvtu(path: &Path, template: &UnstructuredGrid, pieces: &[String]) -> io::Result<()> {
    if pieces.is_empty() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "a .pvtu needs at least one piece"));
    }
    for (index, file) in pieces.iter().enumerate() {
        if file.is_empty() || Path::new(file).is_absolute() {
            return Err(InvalidOutput::BadFile { index, file: file.clone() }.into());
        }
    }
    let names = template.point_data.iter().chain(&template.cell_data).map(|a| ("array name", &a.name));
    for (what, text) in pieces.iter().map(|f| ("piece file", f)).chain(names) {
        if text.chars().any(char::is_control) {
            return Err(InvalidOutput::ControlCharacter { what, text: text.clone() }.into());
        }
    }
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n",
    );
    for (tag, arrays) in [("PPointData", &template.point_data), ("PCellData", &template.cell_data)] {
        let _ = writeln!(xml, "    <{tag}>");
        for a in arrays {
            let _ = writeln!(
                xml,
                "      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>",
                escape(&a.name),
                a.components
            );
        }
        let _ = writeln!(xml, "    </{tag}>");
    }
    xml.push_str("    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n");
    for file in pieces {
        let _ = writeln!(xml, "    <Piece Source=\"{}\"/>", escape(file));
    }
    xml.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    write_atomically(path, |w| w.write_all(xml.as_bytes()))
}

/// Adds `NumberOfPoints="0"` / `NumberOfCells="0"` to the first `<Piece` tag where missing.
fn add_zero_counts(text: Vec<u8>) -> Vec<u8> {
    let find = |hay: &[u8], needle: &[u8]| hay.windows(needle.len()).position(|w| w == needle);
    let Some(start) = find(&text, b"<Piece") else { return text };
    let after_name = start + b"<Piece".len();
    let end = find(&text[after_name..], b">").map_or(text.len(), |e| after_name + e);
    let tag = &text[after_name..end];
    let mut insert = String::new();
    for attr in ["NumberOfPoints", "NumberOfCells"] {
        if find(tag, format!(" {attr}=").as_bytes()).is_none() {
            insert.push_str(&format!(" {attr}=\"0\""));
        }
    }
    let mut out = Vec::with_capacity(text.len() + insert.len());
    out.extend_from_slice(&text[..after_name]);
    out.extend_from_slice(insert.as_bytes());
    out.extend_from_slice(&text[after_name..]);
    out
}

fn vtkio_error(e: vtkio::xml::Error) -> io::Error {
    match e {
        vtkio::xml::Error::IO(e) => e,
        e => io::Error::other(format!("vtkio: {e}")),
    }
}

/// One data set of a ParaView collection: the file holding part `part` at time `time`.
#[derive(Debug, Clone, PartialEq)]
pub struct PvdEntry {
    pub time: f64,
    pub part: usize,
    /// Path of the `.vtu`, relative to the directory of the `.pvd`.
    pub file: String,
    /// Block name shown by ParaView (`name` attribute); omitted when `None`.
    pub name: Option<String>,
}

/// Writes a ParaView collection (`.pvd`) listing `entries` in the given order.
///
/// Entries sharing a time step and differing by `part` open in ParaView as one multiblock
/// data set per time step. Refused (kind [`io::ErrorKind::InvalidInput`]): a non-finite
/// time, an empty or absolute `file`, a control character in `file` or `name`, two entries
/// with the same time and part.
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> io::Result<()> {
    let mut seen = std::collections::HashMap::new();
    for (index, e) in entries.iter().enumerate() {
        if !e.time.is_finite() {
            return Err(InvalidOutput::NonFiniteTime { index, time: e.time }.into());
        }
        if e.file.is_empty() || Path::new(&e.file).is_absolute() {
            return Err(InvalidOutput::BadFile { index, file: e.file.clone() }.into());
        }
        for (what, text) in [("file", Some(&e.file)), ("block name", e.name.as_ref())] {
            if let Some(text) = text.filter(|t| t.chars().any(char::is_control)) {
                return Err(InvalidOutput::ControlCharacter { what, text: text.clone() }.into());
            }
        }
        // `+ 0.0` makes -0 and +0 the same key.
        if let Some(first) = seen.insert(((e.time + 0.0).to_bits(), e.part), index) {
            return Err(InvalidOutput::DuplicateEntry { first, second: index, time: e.time, part: e.part }.into());
        }
    }
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  \
         <Collection>\n",
    );
    for e in entries {
        // `{}` of an f64 is the shortest string that parses back to the same value.
        let _ = write!(
            xml,
            "    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"",
            e.time,
            e.part,
            escape(&e.file)
        );
        if let Some(name) = &e.name {
            let _ = write!(xml, " name=\"{}\"", escape(name));
        }
        xml.push_str("/>\n");
    }
    xml.push_str("  </Collection>\n</VTKFile>\n");
    write_atomically(path, |w| w.write_all(xml.as_bytes()))
}

/// Escapes the five XML special characters for use inside a double-quoted attribute.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Writes through `write` into a temporary sibling of `path`, then renames it onto `path`.
fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<std::fs::File>) -> io::Result<()>,
) -> io::Result<()> {
    let file_name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, format!("{} is not a file path", path.display())))?;
    // Unique per process and call, so that concurrent writers never share a temporary file.
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(file_name);
    tmp_name.push(format!(".{}-{n}.tmp", std::process::id()));
    let tmp: PathBuf = path.with_file_name(tmp_name);
    let result = (|| {
        let mut w = BufWriter::new(std::fs::File::create(&tmp)?);
        write(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch directory removed when dropped.
    struct TmpDir(PathBuf);

    impl TmpDir {
        fn join(&self, p: &str) -> PathBuf {
            self.0.join(p)
        }
    }

    impl Drop for TmpDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn tmp_dir(name: &str) -> TmpDir {
        let dir = std::env::temp_dir().join(format!("fissure-vtu-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TmpDir(dir)
    }

    /// A triangle and a quad sharing an edge (z = 0), with point and cell data.
    fn grid_2d() -> UnstructuredGrid {
        let mut g = UnstructuredGrid::default();
        for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.5, 0.0]] {
            g.push_point(p);
        }
        g.push_cell(VtkCell::Quad, &[0, 1, 2, 3]);
        g.push_cell(VtkCell::Triangle, &[1, 4, 2]);
        g.point_data.push(DataArray::new("displacement", 3, (0..15).map(f64::from).collect()));
        g.cell_data.push(DataArray::new("von_mises", 1, vec![1.5, -2.0]));
        g
    }

    /// A unit hex and a tet on its top face, with point and cell data.
    fn grid_3d() -> UnstructuredGrid {
        let mut g = UnstructuredGrid::default();
        for z in [0.0, 1.0] {
            for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                g.push_point([x, y, z]);
            }
        }
        let apex = g.push_point([0.5, 0.5, 2.0]);
        g.push_cell(VtkCell::Hexahedron, &[0, 1, 2, 3, 4, 5, 6, 7]);
        g.push_cell(VtkCell::Tetra, &[4, 5, 7, apex]);
        g.point_data.push(DataArray::new("displacement", 3, vec![0.25; 27]));
        g.cell_data.push(DataArray::new("von_mises", 1, vec![3.0, 4.0]));
        g.cell_data.push(DataArray::new("stress", 6, (0..12).map(f64::from).collect()));
        g
    }

    /// Checks that `text` is one well-formed XML document (balanced, properly nested tags,
    /// quoted attributes) and returns the start tags in document order.
    fn well_formed(text: &str) -> Vec<String> {
        let body = text.trim_start();
        let body = match body.strip_prefix("<?xml") {
            Some(rest) => &rest[rest.find("?>").expect("unterminated XML declaration") + 2..],
            None => body,
        };
        let mut stack: Vec<String> = Vec::new();
        let mut starts = Vec::new();
        let mut rest = body;
        let mut roots = 0;
        while let Some(open) = rest.find('<') {
            if stack.is_empty() {
                assert!(rest[..open].trim().is_empty(), "text outside the root element");
            }
            let close = rest[open..].find('>').expect("unterminated tag") + open;
            let tag = &rest[open + 1..close];
            assert!(!tag.contains('<'), "'<' inside a tag: {tag}");
            assert_eq!(tag.matches('"').count() % 2, 0, "unbalanced quotes in {tag}");
            if let Some(name) = tag.strip_prefix('/') {
                assert_eq!(stack.pop().as_deref(), Some(name.trim()), "mismatched end tag");
            } else {
                let name = tag.trim_end_matches('/').split_whitespace().next().expect("empty tag").to_string();
                if stack.is_empty() {
                    roots += 1;
                }
                starts.push(name.clone());
                if !tag.ends_with('/') {
                    stack.push(name);
                }
            }
            rest = &rest[close + 1..];
        }
        assert!(stack.is_empty(), "unclosed tags {stack:?}");
        assert!(rest.trim().is_empty(), "trailing text");
        assert_eq!(roots, 1, "exactly one root element");
        starts
    }

    fn attr<'a>(text: &'a str, tag_start: &str, name: &str) -> Vec<&'a str> {
        text.match_indices(tag_start)
            .filter_map(|(i, _)| {
                let tag = &text[i..i + text[i..].find('>')?];
                let key = format!(" {name}=\"");
                let at = tag.find(&key)? + key.len();
                Some(&tag[at..at + tag[at..].find('"')?])
            })
            .collect()
    }

    fn check_vtu(grid: &UnstructuredGrid, compression: Compression, tag: &str) -> String {
        let dir = tmp_dir(tag);
        let path = dir.join("grid.vtu");
        write_vtu(&path, grid, compression).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let starts = well_formed(&text);
        assert_eq!(starts[0], "VTKFile");
        assert!(starts.contains(&"UnstructuredGrid".to_string()));
        assert_eq!(attr(&text, "<VTKFile", "type"), ["UnstructuredGrid"]);
        assert_eq!(attr(&text, "<VTKFile", "byte_order"), ["LittleEndian"]);
        assert_eq!(attr(&text, "<Piece", "NumberOfPoints"), [grid.points.len().to_string()]);
        assert_eq!(attr(&text, "<Piece", "NumberOfCells"), [grid.kinds.len().to_string()]);
        let names = attr(&text, "<DataArray", "Name");
        for a in grid.point_data.iter().chain(&grid.cell_data) {
            assert!(names.contains(&escape(&a.name).as_str()), "{} missing from {names:?}", a.name);
        }
        assert!(attr(&text, "<DataArray", "type").iter().all(|t| ["Float64", "UInt64", "UInt8"].contains(t)));
        // NumberOfComponents is omitted for 1 component (VTK's default).
        let comps = attr(&text, "<DataArray", "NumberOfComponents");
        let expected: Vec<String> = grid
            .point_data
            .iter()
            .chain(&grid.cell_data)
            .map(|a| a.components)
            .chain([3])
            .filter(|&c| c != 1)
            .map(|c| c.to_string())
            .collect();
        assert_eq!(comps, expected);
        match compression {
            Compression::None => assert!(!text.contains("compressor=")),
            Compression::Lz4 => assert_eq!(attr(&text, "<VTKFile", "compressor"), ["vtkLZ4DataCompressor"]),
        }
        // No temporary file left behind.
        assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 1);
        text
    }

    #[test]
    fn mixed_2d_grid_writes_well_formed_xml() {
        let g = grid_2d();
        let text = check_vtu(&g, Compression::None, "2d");
        assert!(text.contains("Name=\"von_mises\""));
        check_vtu(&g, Compression::Lz4, "2d-lz4");
    }

    #[test]
    fn mixed_3d_grid_writes_well_formed_xml() {
        let g = grid_3d();
        let text = check_vtu(&g, Compression::None, "3d");
        assert!(text.contains("Name=\"stress\" NumberOfComponents=\"6\""));
        check_vtu(&g, Compression::Lz4, "3d-lz4");
    }

    #[test]
    fn written_vtu_reads_back_through_vtkio() {
        let g = grid_3d();
        for (c, tag) in [(Compression::None, "rb"), (Compression::Lz4, "rb-lz4")] {
            let dir = tmp_dir(tag);
            let path = dir.join("grid.vtu");
            write_vtu(&path, &g, c).unwrap();
            let vtk = vtkio::Vtk::import(&path).unwrap();
            let model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else { panic!("not a grid") };
            let model::Piece::Inline(p) = &pieces[0] else { panic!("not inline") };
            assert_eq!(p.points.cast_into::<f64>().unwrap(), g.points.iter().flatten().copied().collect::<Vec<_>>());
            assert_eq!(p.cells.types.len(), 2);
            let (conn, offs) = p.cells.cell_verts.clone().into_xml();
            assert_eq!((conn, offs), (g.connectivity.clone(), g.offsets.clone()));
            let model::Attribute::DataArray(stress) = &p.data.cell[1] else { panic!("no stress") };
            assert_eq!(stress.name, "stress");
            assert_eq!(stress.elem.num_comp(), 6);
            assert_eq!(stress.data.cast_into::<f64>().unwrap(), g.cell_data[1].values);
        }
    }

    #[test]
    fn array_names_are_escaped() {
        let mut g = grid_2d();
        g.cell_data[0].name = "a<b & \"c\"".into();
        let text = check_vtu(&g, Compression::None, "escape");
        assert!(text.contains("a&lt;b &amp; &quot;c&quot;"), "{}", &text[..text.len().min(2000)]);
    }

    #[test]
    fn empty_grids_keep_their_zero_counts() {
        let g = UnstructuredGrid::default();
        check_vtu(&g, Compression::None, "empty");
        check_vtu(&g, Compression::Lz4, "empty-lz4");
        // Points but no cells, with a point array.
        let g = UnstructuredGrid {
            points: vec![[0.0; 3], [1.0, 2.0, 3.0]],
            point_data: vec![DataArray::new("displacement", 3, vec![0.5; 6])],
            ..Default::default()
        };
        check_vtu(&g, Compression::None, "no-cells");
    }

    fn rejects(g: &UnstructuredGrid) -> InvalidOutput {
        let err = g.validate().unwrap_err();
        let dir = tmp_dir("bad");
        let io_err = write_vtu(&dir.join("bad.vtu"), g, Compression::None).unwrap_err();
        assert_eq!(io_err.kind(), io::ErrorKind::InvalidInput);
        let inner = io_err.get_ref().and_then(|e| e.downcast_ref::<InvalidOutput>()).expect("an InvalidOutput");
        assert_eq!(inner.to_string(), err.to_string());
        assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 0, "nothing must be written for an invalid grid");
        err
    }

    #[test]
    fn invalid_grids_are_rejected() {
        let good = grid_3d();
        good.validate().unwrap();

        let mut g = good.clone();
        g.connectivity[3] = 9;
        assert!(matches!(rejects(&g), InvalidOutput::NodeOutOfRange { position: 3, node: 9, points: 9 }));

        let mut g = good.clone();
        g.offsets = vec![8, 7];
        assert!(matches!(rejects(&g), InvalidOutput::BadOffsets { cell: 1, .. }));

        let mut g = good.clone();
        g.offsets = vec![4, 12];
        assert!(matches!(rejects(&g), InvalidOutput::BadOffsets { cell: 0, .. }));

        let mut g = good.clone();
        g.offsets.pop();
        assert!(matches!(rejects(&g), InvalidOutput::CellCountMismatch { offsets: 1, kinds: 2 }));

        let mut g = good.clone();
        g.connectivity.push(0);
        assert!(matches!(rejects(&g), InvalidOutput::ConnectivityLength { last: 12, len: 13 }));

        let mut g = good.clone();
        g.points[2][1] = f64::NAN;
        assert!(matches!(rejects(&g), InvalidOutput::NonFinitePoint { point: 2, .. }));

        let mut g = good.clone();
        g.point_data[0].values.pop();
        assert!(matches!(rejects(&g), InvalidOutput::ArrayLength { location: "point", len: 26, count: 9, .. }));

        let mut g = good.clone();
        g.cell_data[1].components = 3;
        assert!(matches!(rejects(&g), InvalidOutput::ArrayLength { location: "cell", .. }));

        let mut g = good.clone();
        g.cell_data[0].components = 0;
        assert!(matches!(rejects(&g), InvalidOutput::BadComponents { .. }));

        let mut g = good.clone();
        g.cell_data[1].name = "von_mises".into();
        assert!(matches!(rejects(&g), InvalidOutput::DuplicateName { location: "cell", .. }));

        let mut g = good.clone();
        g.point_data[0].name = "a\nb".into();
        assert!(matches!(rejects(&g), InvalidOutput::ControlCharacter { .. }));

        let mut g = good.clone();
        g.point_data[0].name.clear();
        assert!(matches!(rejects(&g), InvalidOutput::EmptyName { location: "point", index: 0 }));

        let mut g = good;
        g.push_cell(VtkCell::Triangle, &[0, 1]);
        assert!(matches!(rejects(&g), InvalidOutput::BadOffsets { cell: 2, expected: 3, .. }));
    }

    fn entry(time: f64, part: usize, file: &str, name: Option<&str>) -> PvdEntry {
        PvdEntry { time, part, file: file.into(), name: name.map(Into::into) }
    }

    #[test]
    fn pvd_is_well_formed() {
        let dir = tmp_dir("pvd");
        let path = dir.join("run.pvd");
        let entries: Vec<_> = (0..3)
            .flat_map(|s| {
                let t = 0.1 * f64::from(s);
                [
                    entry(t, 0, &format!("step{s}/bulk.vtu"), Some("bulk")),
                    entry(t, 1, &format!("step{s}/crack.vtu"), Some("crack & \"lips\"")),
                ]
            })
            .collect();
        write_pvd(&path, &entries).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            well_formed(&text),
            ["VTKFile", "Collection", "DataSet", "DataSet", "DataSet", "DataSet", "DataSet", "DataSet"]
        );
        assert_eq!(attr(&text, "<VTKFile", "type"), ["Collection"]);
        assert_eq!(attr(&text, "<DataSet", "timestep"), ["0", "0", "0.1", "0.1", "0.2", "0.2"]);
        assert_eq!(attr(&text, "<DataSet", "part"), ["0", "1", "0", "1", "0", "1"]);
        assert_eq!(attr(&text, "<DataSet", "file")[5], "step2/crack.vtu");
        assert_eq!(attr(&text, "<DataSet", "name")[1], "crack &amp; &quot;lips&quot;");
        // Round trip of the time values.
        for (e, t) in entries.iter().zip(attr(&text, "<DataSet", "timestep")) {
            assert_eq!(t.parse::<f64>().unwrap(), e.time);
        }
        write_pvd(&path, &[entry(1e-300, 0, "a.vtu", None)]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        well_formed(&text);
        assert!(!text.contains("name="));
        assert_eq!(attr(&text, "<DataSet", "timestep")[0].parse::<f64>().unwrap(), 1e-300);
    }

    #[test]
    fn invalid_pvd_entries_are_rejected() {
        let dir = tmp_dir("bad-pvd");
        let path = dir.join("run.pvd");
        let cases = [
            vec![entry(f64::NAN, 0, "a.vtu", None)],
            vec![entry(0.0, 0, "", None)],
            vec![entry(0.0, 0, "/abs/a.vtu", None)],
            vec![entry(0.0, 0, "a.vtu", None), entry(-0.0, 0, "b.vtu", None)],
            vec![entry(0.0, 0, "a.vtu", Some("x\u{0}y"))],
        ];
        for entries in &cases {
            let err = write_pvd(&path, entries).unwrap_err();
            assert_eq!(err.kind(), io::ErrorKind::InvalidInput, "{entries:?}");
        }
        assert!(!path.exists());
    }

    #[test]
    fn unwritable_path_is_an_error_not_a_panic() {
        let dir = tmp_dir("nodir");
        assert!(write_vtu(&dir.join("missing/grid.vtu"), &grid_2d(), Compression::None).is_err());
        assert!(write_vtu(Path::new("/"), &grid_2d(), Compression::None).is_err());
        assert!(write_pvd(&dir.join("missing/run.pvd"), &[]).is_err());
    }

    /// Two pieces of the 3D grid (the hex, the tet) hold its cells once each, the points
    /// they use renumbered, and the point and cell data of those; together they are the grid.
    #[test]
    fn subsets_split_the_grid_into_pieces_with_their_data() {
        let g = grid_3d();
        let hex = g.subset(&[true, false]);
        let tet = g.subset(&[false, true]);
        hex.validate().unwrap();
        tet.validate().unwrap();
        assert_eq!((hex.num_points(), hex.num_cells()), (8, 1));
        assert_eq!((tet.num_points(), tet.num_cells()), (4, 1));
        // The tet's nodes 4, 5, 7 and the apex 8 become 0..4 in order.
        assert_eq!(tet.connectivity, vec![0, 1, 2, 3]);
        assert_eq!(tet.points[3], [0.5, 0.5, 2.0]);
        assert_eq!(tet.cell_data[1].values, (6..12).map(f64::from).collect::<Vec<_>>());
        assert_eq!(hex.cell_data[0].values, vec![3.0]);
        assert_eq!(tet.point_data[0].values.len(), 12);
        // Beyond `keep`: left out; all kept: the grid itself.
        assert_eq!(g.subset(&[]).num_cells(), 0);
        assert_eq!(g.subset(&[true, true]), g);
    }

    /// The `.pvtu` index is well-formed XML declaring the template's arrays and one
    /// `Piece` per file; bad piece paths are refused.
    #[test]
    fn pvtu_index_declares_the_arrays_and_pieces() {
        let dir = tmp_dir("pvtu");
        let path = dir.join("run.pvtu");
        write_pvtu(&path, &grid_3d(), &["run_0.vtu".into(), "run_1.vtu".into()]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let tags = well_formed(&text);
        assert!(tags.iter().any(|t| t == "PUnstructuredGrid") && text.contains("type=\"PUnstructuredGrid\""), "{text}");
        assert_eq!(tags.iter().filter(|t| *t == "Piece").count(), 2, "{text}");
        for name in ["displacement", "von_mises", "stress"] {
            assert!(text.contains(&format!("Name=\"{name}\"")), "{text}");
        }
        for bad in [vec![], vec!["".to_string()], vec!["/abs.vtu".to_string()], vec!["a\u{1}.vtu".to_string()]] {
            let err = write_pvtu(&dir.join("bad.pvtu"), &grid_3d(), &bad).unwrap_err();
            assert_eq!(err.kind(), io::ErrorKind::InvalidInput, "{bad:?}");
        }
    }
}
