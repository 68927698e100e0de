//! Thin wrapper over `faer`'s sparse Cholesky (LLᴴ) for symmetric / Hermitian
//! positive definite systems stored as their **lower** triangle in CSC.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree, memory
//! layout) is computed once per sparsity pattern ([`SparseSpd::analyze`]);
//! every numeric factorization with the same pattern reuses it
//! ([`SparseSpd::factor`], and [`SparseSpd::refactor`] into the buffers of a
//! previous factorization), which is what the multilevel cross-field solver
//! relies on (one numeric factorization per diffusion level). Solves use this
//! module's own triangular sweeps ([`Factor::solve_in_place`]): on a
//! supernodal factor about twice as fast as faer's for one right-hand side
//! on 2D meshes; on a simplicial one (small faces) faer's operations in
//! faer's order, bit-identical, with the diagonal's reciprocals taken once
//! per factorization.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::simplicial::SymbolicSimplicialCholesky;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
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
        LowerPattern {
            n,
            col_ptr,
            row_idx,
        }
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
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        let mid = nodes.len() / 2;
        nodes.select_nth_unstable_by(mid, |&a, &b| {
            coords[a as usize][axis]
                .total_cmp(&coords[b as usize][axis])
                .then(a.cmp(&b))
        });
        let right: Vec<u32> = nodes[mid..].to_vec();
        stamp += 1;
        for &v in &right {
            mark[v as usize] = stamp;
        }
        let (mut left, mut sep) = (Vec::with_capacity(mid), Vec::new());
        for &v in &nodes[..mid] {
            let touches = adj[ptr[v as usize]..ptr[v as usize + 1]]
                .iter()
                .any(|&w| mark[w as usize] == stamp);
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
    factor_scratch: MemBuffer,
    scratch: std::cell::RefCell<MemBuffer>,
    /// Permuted right-hand side + per-supernode gather/scatter buffer.
    work: std::cell::RefCell<Vec<T>>,
    /// `1 / L_jj` (supernodal factors).
    inv_diag: Vec<T::Real>,
    /// `1 / L_jj` as faer's simplicial solve computes it, the complex
    /// reciprocal of the stored diagonal (simplicial factors).
    inv_diag_simplicial: Vec<T>,
    n: usize,
}

impl SparseSpd {
    /// Symbolic analysis of `pattern` (ordering + elimination tree); done once.
    /// With `coords` (one point per unknown) the ordering is the geometric
    /// nested dissection of [`nested_dissection`], else faer's AMD.
    pub fn analyze(
        pattern: LowerPattern,
        coords: Option<&[[f64; 3]]>,
    ) -> Result<SparseSpd, CrossFieldError> {
        Self::analyze_with(pattern, coords, SupernodalThreshold::AUTO)
    }

    /// [`SparseSpd::analyze`] with faer's choice between the simplicial and
    /// the supernodal factorization forced, or left to faer
    /// ([`SupernodalThreshold::AUTO`]).
    pub fn analyze_with(
        pattern: LowerPattern,
        coords: Option<&[[f64; 3]]>,
        threshold: SupernodalThreshold,
    ) -> Result<SparseSpd, CrossFieldError> {
        let err = |e| CrossFieldError::Solver(format!("symbolic Cholesky failed: {e:?}"));
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: threshold,
            ..Default::default()
        };
        let symbolic = match coords {
            Some(c) if c.len() == pattern.n && pattern.n > 64 => {
                let fwd = nested_dissection(&pattern, c);
                let mut inv = vec![0usize; pattern.n];
                for (k, &v) in fwd.iter().enumerate() {
                    inv[v] = k;
                }
                let perm = PermRef::new_checked(&fwd, &inv, pattern.n);
                factorize_symbolic_cholesky(
                    pattern.symbolic(),
                    Side::Lower,
                    SymmetricOrdering::Custom(perm),
                    params,
                )
                .map_err(err)?
            }
            _ => factorize_symbolic_cholesky(
                pattern.symbolic(),
                Side::Lower,
                SymmetricOrdering::Amd,
                params,
            )
            .map_err(err)?,
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
        let oom = |_| CrossFieldError::Solver("out of memory".into());
        let mut l = Vec::new();
        l.try_reserve_exact(self.symbolic.len_val())
            .map_err(|_| CrossFieldError::Solver("out of memory".into()))?;
        l.resize(self.symbolic.len_val(), T::zero_impl());
        let factor_scratch = MemBuffer::try_new(
            self.symbolic
                .factorize_numeric_llt_scratch::<T>(Par::Seq, Default::default()),
        )
        .map_err(oom)?;
        let scratch = MemBuffer::try_new(self.symbolic.solve_in_place_scratch::<T>(1, Par::Seq))
            .map_err(oom)?;
        let max_pattern = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sym) => {
                sym.nnz_per_super().iter().copied().max().unwrap_or(0)
            }
            SymbolicCholeskyRaw::Simplicial(_) => 0,
        };
        let mut f = Factor {
            symbolic: &self.symbolic,
            values: l,
            factor_scratch,
            scratch: std::cell::RefCell::new(scratch),
            work: std::cell::RefCell::new(vec![T::zero_impl(); self.pattern.n + max_pattern]),
            inv_diag: Vec::new(),
            inv_diag_simplicial: Vec::new(),
            n: self.pattern.n,
        };
        self.refactor(values, &mut f)?;
        Ok(f)
    }

    /// Numeric factorization of new `values` into an existing factorization
    /// of this pattern, reusing its buffers (the factor of a 100k-triangle
    /// face holds about 90 MB, whose allocation, zeroing and page faults
    /// cost up to a tenth of a factorization).
    pub fn refactor<T: ComplexField>(
        &self,
        values: &[T],
        f: &mut Factor<'_, T>,
    ) -> Result<(), CrossFieldError> {
        if values.len() != self.pattern.nnz() {
            return Err(CrossFieldError::Solver(
                "value count does not match the pattern".into(),
            ));
        }
        if !std::ptr::eq(f.symbolic, &self.symbolic) {
            return Err(CrossFieldError::Solver(
                "factorization of another pattern".into(),
            ));
        }
        if matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)) {
            f.values.fill(T::zero_impl());
        }
        let mat = SparseColMatRef::new(self.pattern.symbolic(), values);
        self.symbolic
            .factorize_numeric_llt::<T>(
                &mut f.values,
                mat,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut f.factor_scratch),
                Default::default(),
            )
            .map_err(|e| {
                CrossFieldError::Solver(format!("Cholesky factorization failed: {e:?}"))
            })?;
        if let SymbolicCholeskyRaw::Simplicial(sym) = self.symbolic.raw() {
            // the diagonal is the first stored entry of each column
            let l = sym.factor();
            f.inv_diag_simplicial.clear();
            f.inv_diag_simplicial.extend(
                (0..self.pattern.n).map(|j| T::recip_impl(&f.values[l.col_range(j).start])),
            );
        }
        if let SymbolicCholeskyRaw::Supernodal(sym) = self.symbolic.raw() {
            f.inv_diag.clear();
            for s in 0..sym.n_supernodes() {
                let (start, end) = (sym.supernode_begin()[s], sym.supernode_end()[s]);
                let nrows = end - start + sym.nnz_per_super()[s];
                let block = &f.values[sym.col_ptr_for_val()[s]..];
                for j in 0..end - start {
                    f.inv_diag
                        .push(<T::Real as ComplexField>::recip_impl(&T::real_part_impl(
                            &block[j * nrows + j],
                        )));
                }
            }
        }
        Ok(())
    }
}

impl<T: ComplexField> Factor<'_, T> {
    /// Solves `A x = b` in place (`rhs` holds `b` on entry, `x` on exit).
    pub fn solve_in_place(&self, rhs: &mut [T]) {
        debug_assert_eq!(rhs.len(), self.n);
        if let SymbolicCholeskyRaw::Supernodal(sym) = self.symbolic.raw() {
            self.supernodal_solve(sym, rhs);
            return;
        }
        if let SymbolicCholeskyRaw::Simplicial(sym) = self.symbolic.raw() {
            self.simplicial_solve(sym, rhs);
            return;
        }
        let m = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        let mut buf = self.scratch.borrow_mut();
        LltRef::new(self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            m,
            Par::Seq,
            MemStack::new(&mut buf),
        );
    }

    /// `L Lᴴ x = b` on the simplicial factor, one right-hand side: faer's
    /// simplicial solve (the same operations in the same order, so the
    /// result is bit-identical: `simplicial_solve_equals_faer_bit_for_bit`)
    /// without its per-column complex reciprocal of the diagonal, taken once
    /// per factorization instead ([`SparseSpd::refactor`]), and without its
    /// generic matrix views. Small faces get simplicial factors; their
    /// solves were a tenth of a small part's run (BENCHMARKS.md, session of
    /// 2026-12-07, ninth).
    fn simplicial_solve(&self, sym: &SymbolicSimplicialCholesky<usize>, rhs: &mut [T]) {
        let mut work = self.work.borrow_mut();
        let perm = self.symbolic.perm().map(|p| p.arrays());
        let x: &mut [T] = match perm {
            Some((fwd, _)) => {
                for (k, &i) in fwd.iter().enumerate() {
                    work[k] = rhs[i].clone();
                }
                &mut work[..self.n]
            }
            None => rhs,
        };
        let l = sym.factor();
        let rows = l.row_idx();
        let vals = &self.values[..];
        let inv = &self.inv_diag_simplicial[..];
        // forward: L y = b (faer: x_j ← x_j · (1 / L_jj); x_i −= L_ij · x_j)
        for j in 0..self.n {
            let r = l.col_range(j);
            let xj = &x[j] * &inv[j];
            for k in r.start + 1..r.end {
                let v = &vals[k] * &xj;
                x[rows[k]] -= v;
            }
            x[j] = xj;
        }
        // backward: Lᴴ x = y (faer: the column's products with conj(L_ij)
        // summed from its last entry back, then (x_j − sum) · conj(1 / L_jj))
        for j in (0..self.n).rev() {
            let r = l.col_range(j);
            let mut acc = T::zero_impl();
            for k in (r.start + 1..r.end).rev() {
                acc += &T::conj_impl(&vals[k]) * &x[rows[k]];
            }
            let xj = &x[j] - acc;
            x[j] = xj * T::conj_impl(&inv[j]);
        }
        if let Some((_, back)) = perm {
            for (i, &k) in back.iter().enumerate() {
                rhs[i] = work[k].clone();
            }
        }
    }

    /// `L Lᴴ x = b` on the supernodal factor, one right-hand side. faer's
    /// generic supernodal solve calls a dense triangular solve and a matrix
    /// product per supernode; a 2D mesh gives ~50k supernodes of ~3 columns
    /// each (100k-triangle face), where that costs 2.1–2.3× the plain loops
    /// below (26 vs 12.5 ms on the 100k disk). Each supernode's off-diagonal
    /// rows are gathered / scattered once and its columns processed four at
    /// a time; the inverse diagonal is precomputed by [`SparseSpd::refactor`];
    /// the backward sweep, which walks the factor from its end, prefetches
    /// explicitly (the hardware prefetchers follow decreasing addresses
    /// poorly: without it this sweep took 2–3× the forward one).
    fn supernodal_solve(&self, sym: &SymbolicSupernodalCholesky<usize>, rhs: &mut [T]) {
        let mut work = self.work.borrow_mut();
        let (x, tmp) = work.split_at_mut(self.n);
        let fwd = self.symbolic.perm().map(|p| p.arrays().0);
        match fwd {
            Some(fwd) => {
                for (k, &i) in fwd.iter().enumerate() {
                    x[k] = rhs[i].clone();
                }
            }
            None => x.clone_from_slice(rhs),
        }
        let begin = sym.supernode_begin();
        let end = sym.supernode_end();
        let rptr = sym.col_ptr_for_row_idx();
        let vptr = sym.col_ptr_for_val();
        let rows = sym.row_idx();
        let nps = sym.nnz_per_super();
        let l = &self.values[..];
        let ns = sym.n_supernodes();
        let inv_diag = &self.inv_diag[..];
        // forward: L y = b
        let elem = std::mem::size_of::<T>().max(1);
        let ahead = (8192 / elem).max(1);
        let step = (64 / elem).max(1);
        let mut prefetched = 0;
        for s in 0..ns {
            let (start, ncols) = (begin[s], end[s] - begin[s]);
            let pattern = &rows[rptr[s]..][..nps[s]];
            let np = pattern.len();
            let nrows = ncols + np;
            let target = (vptr[s] + nrows * ncols + ahead).min(l.len());
            while prefetched < target {
                prefetch(&l[prefetched]);
                prefetched += step;
            }
            let block = &l[vptr[s]..vptr[s] + nrows * ncols];
            // diagonal block
            let xs = &mut x[start..start + ncols];
            for j in 0..ncols {
                let col = &block[j * nrows..j * nrows + ncols];
                let xj = T::mul_real_impl(&xs[j], &inv_diag[start + j]);
                for (xi, li) in xs[j + 1..].iter_mut().zip(&col[j + 1..]) {
                    let v = li * &xj;
                    *xi -= v;
                }
                xs[j] = xj;
            }
            // off-diagonal rows: t = L_below · xs, four columns at a time, then scatter
            let t = &mut tmp[..np];
            for v in t.iter_mut() {
                *v = T::zero_impl();
            }
            let mut j = 0;
            while j + 4 <= ncols {
                let c0 = &block[j * nrows + ncols..(j + 1) * nrows];
                let c1 = &block[(j + 1) * nrows + ncols..(j + 2) * nrows];
                let c2 = &block[(j + 2) * nrows + ncols..(j + 3) * nrows];
                let c3 = &block[(j + 3) * nrows + ncols..(j + 4) * nrows];
                let (x0, x1, x2, x3) = (&xs[j], &xs[j + 1], &xs[j + 2], &xs[j + 3]);
                for p in 0..np {
                    let v = (&c0[p] * x0 + &c1[p] * x1) + (&c2[p] * x2 + &c3[p] * x3);
                    t[p] += v;
                }
                j += 4;
            }
            while j < ncols {
                let c = &block[j * nrows + ncols..(j + 1) * nrows];
                let xj = &xs[j];
                for (tp, lp) in t.iter_mut().zip(c) {
                    let v = lp * xj;
                    *tp += v;
                }
                j += 1;
            }
            for (tp, &r) in t.iter().zip(pattern) {
                x[r] -= tp;
            }
        }
        // backward: Lᴴ x = y
        let mut prefetched = l.len();
        for s in (0..ns).rev() {
            let (start, ncols) = (begin[s], end[s] - begin[s]);
            let pattern = &rows[rptr[s]..][..nps[s]];
            let np = pattern.len();
            let nrows = ncols + np;
            let target = vptr[s].saturating_sub(ahead);
            while prefetched > target + step {
                prefetched -= step;
                prefetch(&l[prefetched]);
            }
            let block = &l[vptr[s]..vptr[s] + nrows * ncols];
            let g = &mut tmp[..np];
            for (gp, &r) in g.iter_mut().zip(pattern) {
                *gp = x[r].clone();
            }
            // off-diagonal rows: independent dot products, four columns at a time
            let xs = &mut x[start..start + ncols];
            let mut j = 0;
            while j + 4 <= ncols {
                let c0 = &block[j * nrows + ncols..(j + 1) * nrows];
                let c1 = &block[(j + 1) * nrows + ncols..(j + 2) * nrows];
                let c2 = &block[(j + 2) * nrows + ncols..(j + 3) * nrows];
                let c3 = &block[(j + 3) * nrows + ncols..(j + 4) * nrows];
                let (mut a0, mut a1, mut a2, mut a3) = (
                    T::zero_impl(),
                    T::zero_impl(),
                    T::zero_impl(),
                    T::zero_impl(),
                );
                for p in 0..np {
                    let gp = &g[p];
                    a0 += T::conj_impl(&c0[p]) * gp;
                    a1 += T::conj_impl(&c1[p]) * gp;
                    a2 += T::conj_impl(&c2[p]) * gp;
                    a3 += T::conj_impl(&c3[p]) * gp;
                }
                xs[j] -= a0;
                xs[j + 1] -= a1;
                xs[j + 2] -= a2;
                xs[j + 3] -= a3;
                j += 4;
            }
            while j < ncols {
                let c = &block[j * nrows + ncols..(j + 1) * nrows];
                let (mut a0, mut a1) = (T::zero_impl(), T::zero_impl());
                let mut p = 0;
                while p + 2 <= np {
                    a0 += T::conj_impl(&c[p]) * &g[p];
                    a1 += T::conj_impl(&c[p + 1]) * &g[p + 1];
                    p += 2;
                }
                if p < np {
                    a0 += T::conj_impl(&c[p]) * &g[p];
                }
                xs[j] -= a0 + a1;
                j += 1;
            }
            // diagonal block
            for j in (0..ncols).rev() {
                let col = &block[j * nrows..j * nrows + ncols];
                let (c, below) = (&col[j + 1..], &xs[j + 1..]);
                let (mut a0, mut a1, mut a2, mut a3) = (
                    T::zero_impl(),
                    T::zero_impl(),
                    T::zero_impl(),
                    T::zero_impl(),
                );
                let m = c.len();
                let mut i = 0;
                while i + 4 <= m {
                    a0 += T::conj_impl(&c[i]) * &below[i];
                    a1 += T::conj_impl(&c[i + 1]) * &below[i + 1];
                    a2 += T::conj_impl(&c[i + 2]) * &below[i + 2];
                    a3 += T::conj_impl(&c[i + 3]) * &below[i + 3];
                    i += 4;
                }
                while i < m {
                    a0 += T::conj_impl(&c[i]) * &below[i];
                    i += 1;
                }
                let acc = xs[j].clone() - ((a0 + a1) + (a2 + a3));
                xs[j] = T::mul_real_impl(&acc, &inv_diag[start + j]);
            }
        }
        match fwd {
            Some(fwd) => {
                for (k, &i) in fwd.iter().enumerate() {
                    rhs[i] = x[k].clone();
                }
            }
            None => rhs.clone_from_slice(x),
        }
    }
}

/// Hints the processor to fetch the cache line holding `v`.
#[inline(always)]
fn prefetch<T>(v: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is only a hint; `v` is a valid reference.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            v as *const T as *const i8,
        );
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = v;
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::c64;

    /// A Hermitian positive definite matrix on the edge graph of a disk
    /// (the cross-field operator `M + αK`), its pattern and values.
    fn disk_system(rings: usize) -> (LowerPattern, Vec<c64>, Vec<[f64; 3]>) {
        let mesh = crate::fixtures::crossfield_meshes::disk(rings);
        let topo = super::super::FaceTopology::build(&mesh).unwrap();
        let fixed = topo.feature.clone();
        let u = vec![[1.0, 0.0]; topo.edges.len()];
        let sys =
            super::super::assembly::assemble(&topo, &vec![true; topo.triangles.len()], &fixed, &u)
                .unwrap();
        let mut vals: Vec<c64> = sys.stiffness.iter().map(|k| k * 0.01).collect();
        for j in 0..sys.free.len() {
            vals[sys.spd.pattern.diag(j)] += c64::new(sys.mass[j], 0.0);
        }
        let coords = sys
            .free
            .iter()
            .map(|&e| {
                let [a, b] = topo.edges[e as usize];
                let (p, q) = (topo.positions[a as usize], topo.positions[b as usize]);
                [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, 0.0]
            })
            .collect();
        (sys.spd.pattern.clone(), vals, coords)
    }

    fn residual(p: &LowerPattern, vals: &[c64], x: &[c64], b: &[c64]) -> f64 {
        let mut r: Vec<c64> = b.to_vec();
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                let i = p.row_idx[k];
                r[i] -= vals[k] * x[j];
                if i != j {
                    r[j] -= vals[k].conj() * x[i];
                }
            }
        }
        let nr: f64 = r.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
        let nb: f64 = b.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
        nr / nb
    }

    #[test]
    fn simplicial_solve_equals_faer_bit_for_bit() {
        // faer's own solve on the same factor, the reference
        fn faer_solve<T: ComplexField>(f: &Factor<'_, T>, x: &mut [T]) {
            let n = x.len();
            let mut buf = f.scratch.borrow_mut();
            LltRef::new(f.symbolic, &f.values).solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(x, n, 1),
                Par::Seq,
                MemStack::new(&mut buf),
            );
        }
        let (p, vals, coords) = disk_system(12);
        let re: Vec<f64> = vals.iter().map(|v| v.re).collect();
        let mut checked = 0;
        for ordering in [Some(&coords[..]), None] {
            let spd =
                SparseSpd::analyze_with(p.clone(), ordering, SupernodalThreshold::FORCE_SIMPLICIAL)
                    .unwrap();
            assert!(matches!(spd.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)));
            // a complex system (its diagonal's reciprocal is faer's complex one)
            let f = spd.factor(&vals).unwrap();
            for seed in 0..3 {
                let b: Vec<c64> = (0..p.n)
                    .map(|i| c64::new((i as f64 * 0.37 + seed as f64).sin(), (i as f64 * 0.11).cos()))
                    .collect();
                let (mut ours, mut theirs) = (b.clone(), b.clone());
                f.solve_in_place(&mut ours);
                faer_solve(&f, &mut theirs);
                for (a, b) in ours.iter().zip(&theirs) {
                    assert_eq!((a.re.to_bits(), a.im.to_bits()), (b.re.to_bits(), b.im.to_bits()));
                }
                assert!(residual(&p, &vals, &ours, &b) < 1e-12);
                checked += 1;
            }
            // and a real one
            let f = spd.factor(&re).unwrap();
            let b: Vec<f64> = (0..p.n).map(|i| (i as f64 * 0.29).cos()).collect();
            let (mut ours, mut theirs) = (b.clone(), b.clone());
            f.solve_in_place(&mut ours);
            faer_solve(&f, &mut theirs);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&ours), bits(&theirs));
            checked += 1;
        }
        assert_eq!(checked, 8);
    }

    #[test]
    fn supernodal_and_simplicial_solves_agree() {
        let (p, vals, coords) = disk_system(30);
        let b: Vec<c64> = (0..p.n)
            .map(|i| c64::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()))
            .collect();
        let mut xs = Vec::new();
        for ordering in [Some(&coords[..]), None] {
            for threshold in [
                SupernodalThreshold::FORCE_SUPERNODAL,
                SupernodalThreshold::FORCE_SIMPLICIAL,
            ] {
                let spd = SparseSpd::analyze_with(p.clone(), ordering, threshold).unwrap();
                let f = spd.factor(&vals).unwrap();
                let mut x = b.clone();
                f.solve_in_place(&mut x);
                assert!(residual(&p, &vals, &x, &b) < 1e-12);
                xs.push(x);
            }
        }
        for x in &xs[1..] {
            let d = x
                .iter()
                .zip(&xs[0])
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max);
            assert!(d < 1e-10);
        }
        // real scalar systems take the same path
        let re: Vec<f64> = vals.iter().map(|v| v.re).collect();
        let spd = SparseSpd::analyze_with(
            p.clone(),
            Some(&coords),
            SupernodalThreshold::FORCE_SUPERNODAL,
        )
        .unwrap();
        let f = spd.factor(&re).unwrap();
        let mut x: Vec<f64> = b.iter().map(|v| v.re).collect();
        f.solve_in_place(&mut x);
        let xc: Vec<c64> = x.iter().map(|&v| c64::new(v, 0.0)).collect();
        let bc: Vec<c64> = b.iter().map(|v| c64::new(v.re, 0.0)).collect();
        let rc: Vec<c64> = re.iter().map(|&v| c64::new(v, 0.0)).collect();
        assert!(residual(&p, &rc, &xc, &bc) < 1e-12);
    }
}
