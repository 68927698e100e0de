//! Thin wrapper over `faer`'s sparse Cholesky (LLᴴ) for symmetric / Hermitian
//! positive definite systems stored as their **lower** triangle in CSC.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree, memory
//! layout) is computed once per sparsity pattern ([`SparseSpd::analyze`]);
//! every numeric factorization with the same pattern reuses it
//! ([`SparseSpd::factor`]), which is what the multilevel cross-field solver
//! relies on (one numeric factorization per diffusion level).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par, Side};

use super::CrossFieldError;

/// Sparsity pattern of the lower triangle of a square matrix, in CSC with
/// sorted row indices; the diagonal entry of every column is present.
#[derive(Clone, Debug)]
pub struct LowerPattern {
    /// Matrix size.
    pub n: usize,
    /// Column pointers (`n + 1` entries).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column, all `>=` the column.
    pub row_idx: Vec<usize>,
}

impl LowerPattern {
    /// Builds the pattern from, for each column `j`, the rows `> j` it couples
    /// to (any order, duplicates allowed); the diagonal is added.
    pub fn from_columns(n: usize, mut below: Vec<Vec<usize>>) -> LowerPattern {
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (j, rows) in below.iter_mut().enumerate() {
            rows.sort_unstable();
            rows.dedup();
            row_idx.push(j);
            row_idx.extend(rows.iter().copied().filter(|&r| r > j));
            col_ptr.push(row_idx.len());
        }
        LowerPattern { n, col_ptr, row_idx }
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Storage position of entry `(row, col)` with `row >= col`, if present.
    #[inline]
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let (s, e) = (self.col_ptr[col], self.col_ptr[col + 1]);
        let rows = &self.row_idx[s..e];
        if rows.len() <= 8 {
            rows.iter().position(|&r| r == row).map(|k| s + k)
        } else {
            rows.binary_search(&row).ok().map(|k| s + k)
        }
    }

    /// Storage position of the diagonal entry of column `j`.
    #[inline]
    pub fn diag(&self, j: usize) -> usize {
        self.col_ptr[j]
    }

    fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }
}

/// Fill-reducing ordering by geometric nested dissection: the unknowns
/// (points `coords`, graph `pattern`) are split at the median of their
/// longest bounding-box axis; the unknowns of the lower half adjacent to the
/// upper half form the separator, numbered last; both halves recurse.
/// Returns `order[k]` = the unknown eliminated k-th.
pub fn nested_dissection(pattern: &LowerPattern, coords: &[[f64; 3]]) -> Vec<usize> {
    let n = pattern.n;
    // symmetric adjacency (CSR) from the lower triangle
    let mut deg = vec![0usize; n + 1];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j] + 1..pattern.col_ptr[j + 1]] {
            deg[i] += 1;
            deg[j] += 1;
        }
    }
    let mut ptr = vec![0usize; n + 1];
    for v in 0..n {
        ptr[v + 1] = ptr[v] + deg[v];
    }
    let mut fill = ptr.clone();
    let mut adj = vec![0u32; ptr[n]];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j] + 1..pattern.col_ptr[j + 1]] {
            adj[fill[i]] = j as u32;
            fill[i] += 1;
            adj[fill[j]] = i as u32;
            fill[j] += 1;
        }
    }
    let mut mark = vec![0u32; n];
    let mut stamp = 0u32;
    let mut order = Vec::with_capacity(n);
    // explicit stack of tasks: Split(nodes) or Emit(nodes)
    enum Task {
        Split(Vec<u32>),
        Emit(Vec<u32>),
    }
    let mut stack = vec![Task::Split((0..n as u32).collect())];
    while let Some(task) = stack.pop() {
        let mut nodes = match task {
            Task::Emit(nodes) => {
                order.extend(nodes.iter().map(|&v| v as usize));
                continue;
            }
            Task::Split(nodes) => nodes,
        };
        if nodes.len() <= 64 {
            order.extend(nodes.iter().map(|&v| v as usize));
            continue;
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &v in &nodes {
            for k in 0..3 {
                lo[k] = lo[k].min(coords[v as usize][k]);
                hi[k] = hi[k].max(coords[v as usize][k]);
            }
        }
        let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
        let mid = nodes.len() / 2;
        nodes.select_nth_unstable_by(mid, |&a, &b| coords[a as usize][axis].total_cmp(&coords[b as usize][axis]).then(a.cmp(&b)));
        let right: Vec<u32> = nodes[mid..].to_vec();
        stamp += 1;
        for &v in &right {
            mark[v as usize] = stamp;
        }
        let (mut left, mut sep) = (Vec::with_capacity(mid), Vec::new());
        for &v in &nodes[..mid] {
            let touches = adj[ptr[v as usize]..ptr[v as usize + 1]].iter().any(|&w| mark[w as usize] == stamp);
            if touches {
                sep.push(v);
            } else {
                left.push(v);
            }
        }
        // processed in reverse push order: left, right, then separator
        stack.push(Task::Emit(sep));
        stack.push(Task::Split(right));
        stack.push(Task::Split(left));
    }
    order
}

/// A pattern with its Cholesky symbolic analysis, ready for numeric factorizations.
pub struct SparseSpd {
    /// The lower-triangle pattern.
    pub pattern: LowerPattern,
    symbolic: SymbolicCholesky<usize>,
}

/// A numeric Cholesky factorization, reusable for any number of solves.
pub struct Factor<'a, T: ComplexField> {
    symbolic: &'a SymbolicCholesky<usize>,
    values: Vec<T>,
    scratch: std::cell::RefCell<MemBuffer>,
    n: usize,
}

impl SparseSpd {
    /// Symbolic analysis of `pattern` (ordering + elimination tree); done once.
    /// With `coords` (one point per unknown) the ordering is the geometric
    /// nested dissection of [`nested_dissection`], else faer's AMD.
    pub fn analyze(pattern: LowerPattern, coords: Option<&[[f64; 3]]>) -> Result<SparseSpd, CrossFieldError> {
        let err = |e| CrossFieldError::Solver(format!("symbolic Cholesky failed: {e:?}"));
        let symbolic = match coords {
            Some(c) if c.len() == pattern.n && pattern.n > 64 => {
                let fwd = nested_dissection(&pattern, c);
                let mut inv = vec![0usize; pattern.n];
                for (k, &v) in fwd.iter().enumerate() {
                    inv[v] = k;
                }
                let perm = PermRef::new_checked(&fwd, &inv, pattern.n);
                factorize_symbolic_cholesky(pattern.symbolic(), Side::Lower, SymmetricOrdering::Custom(perm), Default::default()).map_err(err)?
            }
            _ => factorize_symbolic_cholesky(pattern.symbolic(), Side::Lower, SymmetricOrdering::Amd, Default::default()).map_err(err)?,
        };
        Ok(SparseSpd { pattern, symbolic })
    }

    /// Number of stored entries of the Cholesky factor (a measure of fill).
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Numeric factorization of the matrix with this pattern and `values`
    /// (lower triangle, in pattern order). Fails when the matrix is not
    /// numerically positive definite.
    pub fn factor<T: ComplexField>(&self, values: &[T]) -> Result<Factor<'_, T>, CrossFieldError> {
        if values.len() != self.pattern.nnz() {
            return Err(CrossFieldError::Solver("value count does not match the pattern".into()));
        }
        let oom = |_| CrossFieldError::Solver("out of memory".into());
        let mat = SparseColMatRef::new(self.pattern.symbolic(), values);
        let mut l = Vec::new();
        l.try_reserve_exact(self.symbolic.len_val()).map_err(|_| CrossFieldError::Solver("out of memory".into()))?;
        l.resize(self.symbolic.len_val(), T::zero_impl());
        let mut buf = MemBuffer::try_new(self.symbolic.factorize_numeric_llt_scratch::<T>(Par::Seq, Default::default())).map_err(oom)?;
        self.symbolic
            .factorize_numeric_llt::<T>(&mut l, mat, Side::Lower, Default::default(), Par::Seq, MemStack::new(&mut buf), Default::default())
            .map_err(|e| CrossFieldError::Solver(format!("Cholesky factorization failed: {e:?}")))?;
        let scratch = MemBuffer::try_new(self.symbolic.solve_in_place_scratch::<T>(1, Par::Seq)).map_err(oom)?;
        Ok(Factor { symbolic: &self.symbolic, values: l, scratch: std::cell::RefCell::new(scratch), n: self.pattern.n })
    }
}

impl<T: ComplexField> Factor<'_, T> {
    /// Solves `A x = b` in place (`rhs` holds `b` on entry, `x` on exit).
    pub fn solve_in_place(&self, rhs: &mut [T]) {
        debug_assert_eq!(rhs.len(), self.n);
        let m = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        let mut buf = self.scratch.borrow_mut();
        LltRef::new(self.symbolic, &self.values).solve_in_place_with_conj(Conj::No, m, Par::Seq, MemStack::new(&mut buf));
    }
}
