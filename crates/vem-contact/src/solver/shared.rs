//! Factorisation work shared between solvers, per structure.
//!
//! Every sparse factorisation of the contact solvers is built on one ordering per stiffness
//! block: the block's fill-reducing order with its **interface unknowns** (those a normal or
//! tangential row touches) eliminated last. The condensed solver factorises each block `K_b`
//! in that order; the penalty and active-set solvers factorise `K + B'WB (+ shift)`, whose
//! contact terms couple only interface unknowns, in the order made of the blocks' interior
//! orders followed by all interface unknowns. So per structure ([`PatternId`]) there is
//!
//! - one ordering per block, shared by all solvers;
//! - one symbolic analysis per block (condensed) and one of the coupled pattern (penalty and
//!   active set), each shared by the solvers that need it;
//! - per stiffness values ([`ContactSystem::stiffness_version`]) one numeric factor per block,
//!   shared by condensed solvers (the coupled matrices change with every Newton step and are
//!   factorised by each solver).
//!
//! They are found through a process-wide registry of **weak** references keyed by the
//! structure, the block and the settings: a solver holds what it uses, and a second solver on
//! the same structure finds it while the first still holds it. Nothing is kept alive by the
//! registry itself, so it costs no memory.

use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex, OnceLock, Weak};

use vem_elastic::{CholeskyAnalysis, CholeskyFactor, Ordering};

use super::system::{ContactSystem, PatternId};

/// A stiffness block of a structure, with the ordering setting its order was made with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct BlockKey {
    pub pattern: PatternId,
    pub block: usize,
    pub has_friction: bool,
    pub ordering: Ordering,
}

impl BlockKey {
    pub(crate) fn of(system: &ContactSystem<'_>, block: usize, ordering: Ordering) -> Self {
        Self {
            pattern: system.pattern(),
            block,
            has_friction: system.friction().is_some(),
            ordering,
        }
    }
}

/// The numeric factor of a block for given stiffness values and Cholesky settings (their
/// `Debug` form: the pivot tolerance and the parallelism decide what is accepted and how it
/// is computed).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) struct FactorKey {
    pub block: BlockKey,
    pub stiffness_version: u64,
    pub settings: String,
}

/// The coupled pattern `K + B_N'B_N + B_T'B_T + I` of a structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct CoupledKey {
    pub pattern: PatternId,
    pub has_friction: bool,
    pub ordering: Ordering,
}

/// The elimination order of one stiffness block, in the block's own numbering: `order[k]` is
/// eliminated at step `k`; the last `interface.len()` entries are the interface unknowns.
#[derive(Debug)]
pub(crate) struct BlockOrder {
    pub order: Vec<usize>,
    /// The interface unknowns of the block (sorted), eliminated last in this order.
    pub interface: Vec<usize>,
}

/// The numeric factor of a block: of `K_b`, or of `K_b + s E_G` when `K_b` is singular (`s`
/// the shift of the interface unknowns), or none when that is singular too.
#[derive(Debug)]
pub(crate) struct BlockFactor {
    pub factor: Option<Arc<CholeskyFactor>>,
    pub shift: f64,
}

/// One map of weak references.
struct Weaks<K, V>(HashMap<K, Weak<V>>);

impl<K: Eq + Hash, V> Weaks<K, V> {
    fn get(&self, key: &K) -> Option<Arc<V>> {
        self.0.get(key).and_then(Weak::upgrade)
    }

    fn insert(&mut self, key: K, value: &Arc<V>) {
        self.0.retain(|_, w| w.strong_count() > 0);
        self.0.insert(key, Arc::downgrade(value));
    }
}

impl<K, V> Default for Weaks<K, V> {
    fn default() -> Self {
        Self(HashMap::new())
    }
}

#[derive(Default)]
struct Registry {
    orders: Weaks<BlockKey, BlockOrder>,
    analyses: Weaks<BlockKey, CholeskyAnalysis>,
    factors: Weaks<FactorKey, BlockFactor>,
    coupled: Weaks<CoupledKey, super::newton_matrix::CoupledPattern>,
}

fn registry() -> std::sync::MutexGuard<'static, Registry> {
    static REGISTRY: OnceLock<Mutex<Registry>> = OnceLock::new();
    REGISTRY
        .get_or_init(Mutex::default)
        .lock()
        // A panic while the lock was held left at most a stale weak reference.
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The shared value for `key`, or `make()` registered under it. Returns the value and
/// whether it was made here. The lock is not held while `make` runs (it may take minutes and
/// look up other entries); two solvers racing for the same key may both make it.
fn shared<K, V, E>(
    map: impl Fn(&mut Registry) -> &mut Weaks<K, V>,
    key: K,
    make: impl FnOnce() -> Result<Arc<V>, E>,
) -> Result<(Arc<V>, bool), E>
where
    K: Eq + Hash,
{
    if let Some(found) = map(&mut registry()).get(&key) {
        return Ok((found, false));
    }
    let made = make()?;
    map(&mut registry()).insert(key, &made);
    Ok((made, true))
}

/// The order of a block, shared.
fn block_order<E>(
    key: BlockKey,
    make: impl FnOnce() -> Result<BlockOrder, E>,
) -> Result<(Arc<BlockOrder>, bool), E> {
    shared(|r| &mut r.orders, key, || make().map(Arc::new))
}

/// The symbolic analysis of a block (on its shared order), shared.
pub(crate) fn block_analysis<E>(
    key: BlockKey,
    make: impl FnOnce() -> Result<Arc<CholeskyAnalysis>, E>,
) -> Result<(Arc<CholeskyAnalysis>, bool), E> {
    shared(|r| &mut r.analyses, key, make)
}

/// The numeric factor of a block for given values and settings, shared.
pub(crate) fn block_factor<E>(
    key: FactorKey,
    make: impl FnOnce() -> Result<BlockFactor, E>,
) -> Result<(Arc<BlockFactor>, bool), E> {
    shared(|r| &mut r.factors, key, || make().map(Arc::new))
}

/// The coupled pattern and its analysis, shared.
pub(crate) fn coupled_pattern<E>(
    key: CoupledKey,
    make: impl FnOnce() -> Result<super::newton_matrix::CoupledPattern, E>,
) -> Result<(Arc<super::newton_matrix::CoupledPattern>, bool), E> {
    shared(|r| &mut r.coupled, key, || make().map(Arc::new))
}

/// The interface unknowns of every stiffness block (local numbering, sorted): the unknowns a
/// normal or tangential row touches.
pub(crate) fn interfaces(system: &ContactSystem<'_>) -> Vec<Vec<usize>> {
    let blocks = system.stiffness_blocks();
    let mut block_of = vec![0usize; system.n_dofs()];
    for (b, block) in blocks.iter().enumerate() {
        let start = block.offset();
        block_of[start..start + block.matrix().ncols()].fill(b);
    }
    let mut touched = vec![false; system.n_dofs()];
    let mut mark = |rows: &super::ConstraintRows| {
        for r in 0..rows.nrows() {
            for &c in rows.row(r).0 {
                touched[c] = true;
            }
        }
    };
    mark(system.normal_rows());
    if let Some(friction) = system.friction() {
        mark(friction.tangential_rows());
    }
    let mut result = vec![Vec::new(); blocks.len()];
    for (c, &t) in touched.iter().enumerate() {
        if t {
            let b = block_of[c];
            result[b].push(c - blocks[b].offset());
        }
    }
    result
}

/// The order of block `block` with its interface last (shared; made with
/// [`vem_elastic::elimination_order`] if no solver holds it).
pub(crate) fn order_of_block(
    system: &ContactSystem<'_>,
    block: usize,
    interface: &[usize],
    ordering: Ordering,
) -> Result<Arc<BlockOrder>, vem_elastic::SolveError> {
    let key = BlockKey::of(system, block, ordering);
    let k = system.stiffness_blocks()[block].matrix();
    block_order(key, || {
        let (order, _) = vem_elastic::elimination_order(k.symbolic(), interface, ordering)?;
        Ok(BlockOrder {
            order,
            interface: interface.to_vec(),
        })
    })
    .map(|(order, _)| order)
}
