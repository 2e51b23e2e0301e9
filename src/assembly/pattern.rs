//! Sparsity patterns in compressed-column (CSC) form.
//!
//! Entry point: [`CscPattern`].

/// The sparsity pattern of a square matrix in compressed-column form: the row indices
/// of column `j` are `row_idx[col_ptr[j]..col_ptr[j + 1]]`, sorted ascending, unique.
/// Assembled matrices store both triangles (the pattern is structurally symmetric).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CscPattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

impl CscPattern {
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Position of entry `(row, col)` in the value array, if it is in the pattern.
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let (s, e) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[s..e].binary_search(&row).ok().map(|k| s + k)
    }

    /// Builds a pattern from (row, col) pairs (any order, duplicates allowed).
    pub fn from_entries(n: usize, entries: &[(usize, usize)]) -> CscPattern {
        let mut cols: Vec<Vec<usize>> = vec![vec![]; n];
        for &(r, c) in entries {
            cols[c].push(r);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = vec![];
        col_ptr.push(0);
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        CscPattern { n, col_ptr, row_idx }
    }

    /// `y = A x` for values `vals` on this pattern.
    pub fn mul_vec(&self, vals: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..self.n {
            let xj = x[j];
            if xj == 0.0 {
                continue;
            }
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row_idx[k]] += vals[k] * xj;
            }
        }
    }
}
