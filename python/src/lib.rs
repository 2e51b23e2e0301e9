//! `fissure._native`: the compiled part of the Python package `fissure` (python/fissure/).
//!
//! It owns the crossing between Python and the library: a case given as a Python dict is
//! written as case-file text ([`to_toml`]), overrides become the library's `--set`
//! overrides, a run goes through [`fissure::run::run_case_results`] with the interpreter
//! released, and its results come back as a [`Results`] whose fields are NumPy arrays.
//! Every library error becomes a Python exception carrying the file, line and key
//! (`CaseError`), and every Rust panic is caught and raised as `PanicError`: nothing here
//! aborts the interpreter. The Python-facing API (`fissure.run`, `Result`) is in
//! python/fissure/__init__.py.
//!
//! Entry points: [`run`], [`to_toml`], [`Results`].

use fissure::case::overrides::Override;
use fissure::io::vtu::UnstructuredGrid;
use fissure::run::{run_case_results, CaseInput, RunError, RunOptions, RunResults, StepFields};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use toml_edit::{Array, ArrayOfTables, DocumentMut, InlineTable, Item, Table, Value};

create_exception!(fissure, FissureError, PyException, "Any error of a fissure run.");
create_exception!(
    fissure,
    CaseError,
    FissureError,
    "The case (file, dict or override) is wrong: attributes `file`, `line` (None when unknown), `key`, `message`."
);
create_exception!(fissure, SolveError, FissureError, "The solve failed (the converged steps stay on disk).");
create_exception!(fissure, OutputError, FissureError, "The result files could not be written.");
create_exception!(
    fissure,
    PanicError,
    FissureError,
    "A defect in fissure (a Rust panic), caught before it could abort the interpreter."
);

/// A case error as a Python `CaseError` with its `file`, `line`, `key`, `message`.
fn case_error(py: Python<'_>, e: &fissure::case::CaseError) -> PyErr {
    let err = CaseError::new_err(e.to_string());
    let v = err.value(py);
    // Setting attributes on a fresh exception instance cannot fail but for memory.
    let _ = v.setattr("file", &e.file);
    let _ = v.setattr("line", e.line);
    let _ = v.setattr("key", &e.key);
    let _ = v.setattr("message", &e.message);
    err
}

fn run_error(py: Python<'_>, e: &RunError) -> PyErr {
    match e {
        RunError::Case(c) => case_error(py, c),
        // An under-constrained model is a modelling error but not a key's: SolveError.
        RunError::Solve(_) => SolveError::new_err(e.to_string()),
        RunError::Output(_) => OutputError::new_err(e.to_string()),
    }
}

/// A case error about a key of the Python dict (no line: it is not text yet).
fn dict_error(file: &str, key: &str, message: impl Into<String>) -> fissure::case::CaseError {
    fissure::case::CaseError { file: file.into(), line: None, key: key.into(), message: message.into() }
}

/// Runs `f`, turning a panic into `PanicError` with its message.
fn guarded<T>(f: impl FnOnce() -> T) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        let msg = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic payload".into());
        PanicError::new_err(format!("internal error (a defect in fissure, please report it): {msg}"))
    })
}

/// The key path of a dict entry as the case reader writes it (`cracks[0].contact`).
fn child(key: &str, seg: &str) -> String {
    if key.is_empty() {
        seg.to_string()
    } else {
        format!("{key}.{seg}")
    }
}

/// A Python scalar or list as a TOML value; `key` names it in errors.
fn to_value(obj: &Bound<'_, PyAny>, key: &str, file: &str) -> Result<Value, fissure::case::CaseError> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(Value::from(obj.extract::<bool>().unwrap_or(false)));
    }
    if obj.is_instance_of::<PyInt>() {
        return obj
            .extract::<i64>()
            .map(Value::from)
            .map_err(|_| dict_error(file, key, "the integer does not fit in 64 bits"));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(Value::from(obj.extract::<f64>().unwrap_or(f64::NAN)));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::from(s.to_string()));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut a = Array::new();
        for (i, item) in obj.try_iter().map_err(|e| dict_error(file, key, e.to_string()))?.enumerate() {
            let item = item.map_err(|e| dict_error(file, key, e.to_string()))?;
            a.push(to_value(&item, &format!("{key}[{i}]"), file)?);
        }
        return Ok(Value::Array(a));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut t = InlineTable::new();
        for (k, v) in d.iter() {
            let k = dict_key(&k, key, file)?;
            let sub = to_value(&v, &child(key, &k), file)?;
            t.insert(&k, sub);
        }
        return Ok(Value::InlineTable(t));
    }
    if obj.is_none() {
        return Err(dict_error(file, key, "None has no value in a case: leave the key out"));
    }
    // NumPy scalars and other numbers: through float (integers that are floats stay floats).
    if let Ok(i) = obj.call_method0("__index__").and_then(|v| v.extract::<i64>()) {
        return Ok(Value::from(i));
    }
    if let Ok(f) = obj.call_method0("__float__").and_then(|v| v.extract::<f64>()) {
        return Ok(Value::from(f));
    }
    let type_name = obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
    Err(dict_error(
        file,
        key,
        format!("a Python {type_name} has no value in a case (numbers, strings, booleans, lists and dicts)"),
    ))
}

fn dict_key(k: &Bound<'_, PyAny>, key: &str, file: &str) -> Result<String, fissure::case::CaseError> {
    k.cast::<PyString>()
        .map(|s| s.to_string())
        .map_err(|_| dict_error(file, key, format!("the keys of a case dict are strings, found {k}")))
}

/// A Python dict as a TOML table: sub-dicts become tables, lists of dicts arrays of
/// tables (`[[cracks]]`), everything else values.
fn to_table(d: &Bound<'_, PyDict>, key: &str, file: &str) -> Result<Table, fissure::case::CaseError> {
    let mut t = Table::new();
    for (k, v) in d.iter() {
        let k = dict_key(&k, key, file)?;
        let here = child(key, &k);
        let item = if let Ok(sub) = v.cast::<PyDict>() {
            Item::Table(to_table(sub, &here, file)?)
        } else if let Some(list) = dict_list(&v) {
            let mut a = ArrayOfTables::new();
            for (i, entry) in list.iter().enumerate() {
                a.push(to_table(entry, &format!("{here}[{i}]"), file)?);
            }
            Item::ArrayOfTables(a)
        } else {
            Item::Value(to_value(&v, &here, file)?)
        };
        t.insert(&k, item);
    }
    Ok(t)
}

/// The entries of a non-empty list (or tuple) made only of dicts.
fn dict_list<'py>(v: &Bound<'py, PyAny>) -> Option<Vec<Bound<'py, PyDict>>> {
    if !(v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>()) {
        return None;
    }
    let items: Vec<Bound<'py, PyAny>> = v.try_iter().ok()?.collect::<PyResult<_>>().ok()?;
    if items.is_empty() {
        return None;
    }
    items.into_iter().map(|i| i.cast_into::<PyDict>().ok()).collect()
}

/// The case-file (TOML) text of a case given as a Python dict. `file` names the case in
/// errors about values that have no TOML form.
#[pyfunction]
#[pyo3(signature = (case, file = "<dict>"))]
fn to_toml(py: Python<'_>, case: &Bound<'_, PyDict>, file: &str) -> PyResult<String> {
    let table = to_table(case, "", file).map_err(|e| case_error(py, &e))?;
    let mut doc = DocumentMut::new();
    *doc.as_table_mut() = table;
    Ok(doc.to_string())
}

/// Python overrides `{key: value}` as the library's `--set` overrides.
fn overrides(py: Python<'_>, given: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<Override>> {
    let mut out = vec![];
    for (k, v) in given.into_iter().flat_map(|d| d.iter()) {
        let key: String = k.extract().map_err(|_| {
            case_error(py, &dict_error("overrides", "", format!("the keys of overrides are strings, found {k}")))
        })?;
        let value = to_value(&v, &key, &format!("--set {key}")).map_err(|e| case_error(py, &e))?;
        out.push(Override::new(&key, value).map_err(|e| case_error(py, &e))?);
    }
    Ok(out)
}

/// Runs a case and keeps its results in memory. Either `path` (a case file) or `text`
/// (case-file text, named `path` in errors, relative paths from `base`).
#[pyfunction]
#[pyo3(signature = (path, out, text = None, base = None, overrides = None, verbose = false, newton = false))]
#[allow(clippy::too_many_arguments)]
fn run(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    text: Option<String>,
    base: Option<PathBuf>,
    overrides: Option<&Bound<'_, PyDict>>,
    verbose: bool,
    newton: bool,
) -> PyResult<Results> {
    let overrides = self::overrides(py, overrides)?;
    let input = match text {
        Some(text) => CaseInput::Text { text, path, base: base.unwrap_or_else(|| PathBuf::from(".")) },
        None => CaseInput::File(path),
    };
    let opts = RunOptions { verbose, overrides, newton_iterations: newton, ..Default::default() };
    let result = py.detach(|| guarded(|| run_case_results(&input, &out, &opts)))?;
    result.map(|r| Results { inner: r }).map_err(|e| run_error(py, &e))
}

/// Panics on purpose: the test of the panic guard (a Rust panic must come out as
/// `fissure.PanicError`, never abort the interpreter).
#[pyfunction]
fn _panic_for_test(py: Python<'_>, message: String) -> PyResult<()> {
    py.detach(|| guarded(|| panic!("{message}")))
}

/// The results of a run held in memory (wrapped by `fissure.Result`).
#[pyclass(module = "fissure._native", frozen)]
struct Results {
    inner: RunResults,
}

impl Results {
    fn step(&self, pos: usize) -> PyResult<&StepFields> {
        self.inner.steps.get(pos).ok_or_else(|| {
            pyo3::exceptions::PyIndexError::new_err(format!(
                "step position {pos} out of range ({} recorded steps)",
                self.inner.steps.len()
            ))
        })
    }
}

/// `values` (`width` per row, `stride` stored) as an (n, width) array.
fn table<'py>(py: Python<'py>, values: Vec<f64>, width: usize) -> PyResult<Bound<'py, PyAny>> {
    let n = values.len() / width.max(1);
    Ok(PyArray1::from_vec(py, values).reshape([n, width])?.into_any())
}

#[pymethods]
impl Results {
    /// `summary.json` as JSON text.
    fn summary_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.inner.summary).map_err(|e| OutputError::new_err(e.to_string()))
    }

    /// 2 or 3.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim
    }

    /// The step `index` of each recorded step (as in `summary.json` `steps`).
    fn step_indices(&self) -> Vec<usize> {
        self.inner.steps.iter().map(|s| s.index).collect()
    }

    /// Mesh node coordinates, (nodes, dim).
    fn nodes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let d = self.inner.dim;
        let v: Vec<f64> = self.inner.nodes.iter().flat_map(|x| x[..d].to_vec()).collect();
        table(py, v, d)
    }

    /// Nodal displacements of the recorded step at position `pos`, (nodes, dim).
    fn displacement<'py>(&self, py: Python<'py>, pos: usize) -> PyResult<Bound<'py, PyAny>> {
        let s = self.step(pos)?;
        table(py, s.displacement.clone(), self.inner.dim)
    }

    /// The crack-lip fields of crack `crack` (case order) at the recorded step `pos`: a
    /// dict of arrays with one row per lip point (each facet vertex once on each lip):
    /// `x`, `lip` (+1 / −1), every point array of the lip grid and its cell arrays
    /// (`normal`, `status`) repeated on the cell's points; vectors as (n, dim).
    fn lip_fields<'py>(&self, py: Python<'py>, crack: usize, pos: usize) -> PyResult<Bound<'py, PyDict>> {
        let s = self.step(pos)?;
        let out = PyDict::new(py);
        let Some(g) = &s.lips else { return Ok(out) };
        let d = self.inner.dim;
        let points = lip_points(g, crack);
        // One row per lip point: point arrays at the point, cell arrays of its cell.
        let column = |name: &str, values: &[f64], comps: usize, by_cell: bool| -> PyResult<()> {
            let w = if comps == 3 { d } else { comps };
            let mut v = Vec::with_capacity(points.len() * w);
            for &(p, c) in &points {
                let at = if by_cell { c } else { p };
                v.extend_from_slice(&values[at * comps..at * comps + w]);
            }
            let a = if w == 1 { PyArray1::from_vec(py, v).into_any() } else { table(py, v, w)? };
            out.set_item(name, a)
        };
        let xs: Vec<f64> = g.points.iter().flat_map(|x| x.to_vec()).collect();
        column("x", &xs, 3, false)?;
        for a in &g.point_data {
            column(&a.name, &a.values, a.components, false)?;
        }
        for a in g.cell_data.iter().filter(|a| a.name != "crack") {
            column(&a.name, &a.values, a.components, true)?;
        }
        Ok(out)
    }
}

/// The (point, cell) pairs of the lip points of `crack`, in cell order.
fn lip_points(g: &UnstructuredGrid, crack: usize) -> Vec<(usize, usize)> {
    let Some(ids) = g.cell_data.iter().find(|a| a.name == "crack") else { return vec![] };
    let mut out = vec![];
    let mut start = 0usize;
    for (c, &end) in g.offsets.iter().enumerate() {
        let end = end as usize;
        if ids.values.get(c).is_some_and(|&k| k == crack as f64) {
            out.extend(g.connectivity[start..end].iter().map(|&p| (p as usize, c)));
        }
        start = end;
    }
    out
}

/// The module `fissure._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // The importing thread one of rayon's workers (`fissure::threads`; a pool built
    // before is kept).
    fissure::threads::init();
    let py = m.py();
    m.add("FissureError", py.get_type::<FissureError>())?;
    m.add("CaseError", py.get_type::<CaseError>())?;
    m.add("SolveError", py.get_type::<SolveError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    m.add("PanicError", py.get_type::<PanicError>())?;
    m.add("VERSION", fissure::VERSION)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add_class::<Results>()?;
    Ok(())
}
