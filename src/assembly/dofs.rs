//! The dof map: which unknowns exist, grouped in contiguous blocks by kind.
//!
//! Entry point: [`DofMap`].
//!
//! Standard displacement dofs come first, node by node (`node * dim + component`);
//! later blocks (enrichment, multipliers) are appended in order, so multipliers are
//! always numbered after every displacement unknown (the saddle-point solvers rely on it).

/// The kind of a block of dofs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DofKind {
    /// Nodal displacement components.
    Displacement,
    /// Heaviside-enriched displacement components (X-FEM).
    Heaviside,
    /// Crack-tip branch-function components (X-FEM).
    Tip,
    /// Lagrange multipliers enforcing Dirichlet conditions.
    DirichletMultiplier,
    /// Contact multipliers (λ) and friction semi-multipliers (Λ).
    ContactMultiplier,
}

impl DofKind {
    pub fn name(self) -> &'static str {
        match self {
            DofKind::Displacement => "standard",
            DofKind::Heaviside => "heaviside",
            DofKind::Tip => "tip",
            DofKind::DirichletMultiplier => "dirichlet_multipliers",
            DofKind::ContactMultiplier => "contact_multipliers",
        }
    }
    /// Multipliers are ordered after all displacement unknowns.
    pub fn is_multiplier(self) -> bool {
        matches!(self, DofKind::DirichletMultiplier | DofKind::ContactMultiplier)
    }
}

/// A contiguous range of dofs of one kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DofBlock {
    pub kind: DofKind,
    pub start: usize,
    pub len: usize,
}

/// All dofs of a model, in blocks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofMap {
    pub dim: usize,
    pub n_nodes: usize,
    pub blocks: Vec<DofBlock>,
}

impl DofMap {
    /// Standard displacement dofs only.
    pub fn standard(dim: usize, n_nodes: usize) -> DofMap {
        DofMap { dim, n_nodes, blocks: vec![DofBlock { kind: DofKind::Displacement, start: 0, len: dim * n_nodes }] }
    }

    /// Appends a block; returns its first dof. Displacement-like blocks may not follow
    /// a multiplier block.
    pub fn push_block(&mut self, kind: DofKind, len: usize) -> usize {
        let start = self.n_total();
        if let Some(last) = self.blocks.last() {
            assert!(
                kind.is_multiplier() || !last.kind.is_multiplier(),
                "displacement dofs must be numbered before multipliers"
            );
        }
        self.blocks.push(DofBlock { kind, start, len });
        start
    }

    pub fn n_total(&self) -> usize {
        self.blocks.last().map(|b| b.start + b.len).unwrap_or(0)
    }

    /// Number of dofs of one kind.
    pub fn count(&self, kind: DofKind) -> usize {
        self.blocks.iter().filter(|b| b.kind == kind).map(|b| b.len).sum()
    }

    /// Number of non-multiplier dofs (they come first).
    pub fn n_primal(&self) -> usize {
        self.blocks.iter().filter(|b| !b.kind.is_multiplier()).map(|b| b.len).sum()
    }

    /// Standard displacement dof of `node`, component `c`.
    #[inline]
    pub fn node_dof(&self, node: usize, c: usize) -> usize {
        node * self.dim + c
    }
}
